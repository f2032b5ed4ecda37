/* checkpoint.h — checkpoints of a run and resuming from them (`esfera run --resume`).
 *
 * A checkpoint is one file, OUT/checkpoint.esf, replaced atomically (atomic_file.h) at
 * every output.checkpoint_every seconds of simulated time and when the run is asked to
 * stop (SIGINT, SIGTERM). It holds the complete state between two steps:
 *   the scene's text, path and --set overrides (a resume rebuilds the sim from them and
 *   checks the materials and dt it derives against the saved ones);
 *   the particles (every SoA array, in their current order, any n); both candidate
 *   lists with a, b, history, touch and vc0, nb.xref and nb.builds; the materials and
 *   pair table; the walls' time and rebuild marks (their placement is a function of
 *   time); servo walls' displacement and velocity, the events applied and the fluid
 *   force's state (section SAND, loads_ckpt.h); damping state (alpha_r, alpha_t); the
 * rng; t, dt, step and the counters; the energy ledger; the integrator's own state
 * (integrator.h save/restore); the run loop's schedule (esf_ckpt_run). Format (native
 * byte order; the build's record layouts are stored and must match): "ESFCKPT\0", u32
 * byte-order mark 0x01020304, u32 format version, then sections [tag 8 bytes][u64
 * length][payload][u32 CRC-32 of payload], the last one "END". Loading verifies every
 * checksum, so a truncated, corrupted or foreign file is an ESF_EINPUT error naming the
 * file and what is wrong, never a crash. */
#ifndef ESF_CHECKPOINT_H
#define ESF_CHECKPOINT_H

#include <stdio.h>

#include "core/sim.h"
#include "integrators/integrator.h"

#define ESF_CKPT_NAME "checkpoint.esf"

/* Where the scene came from: stored in every checkpoint. */
typedef struct esf_ckpt_scene {
  const char *path;        /* the scene file as given */
  const char *text;        /* its contents */
  size_t len;              /* bytes of text */
  const char *const *sets; /* --set overrides in order */
  int nsets;
} esf_ckpt_scene;

/* The run loop's state between steps (run.c). */
typedef struct esf_ckpt_run {
  long n;         /* the loop counter of the next step */
  double next_e;  /* adaptive runs: next energy-row time, s */
  double next_f;  /* adaptive runs: next frame time, s */
  double next_c;  /* adaptive runs: next checkpoint time, s */
  double psum;    /* sum of particle counts over steps */
  long frames;    /* frames in frames.h5 */
  long erows;     /* rows of /energy in frames.h5 */
  long csv_bytes; /* bytes of energy.csv (-1: none) */
  long count;     /* checkpoints written so far, this one included */
} esf_ckpt_run;

typedef struct esf_ckpt esf_ckpt; /* a loaded and verified checkpoint */

/* Writes the checkpoint of the sim (between steps) to path, atomically. The
 * integrator's save runs first (it may restart the integrator, see integrator.h).
 * ESF_EINPUT when the integrator cannot checkpoint; ESF_EIO when writing fails (the
 * previous checkpoint stays intact). */
int esf_ckpt_write(const char *path, esf_sim *s, const esf_integrator_type *it, void *ist,
                   const esf_ckpt_scene *sc, const esf_ckpt_run *run, esf_error *err);

/* Reads and verifies the checkpoint at path (a directory: its checkpoint.esf). */
int esf_ckpt_load(const char *path, esf_ckpt **out, esf_error *err);
void esf_ckpt_free(esf_ckpt **c);

/* 1 when the file at path starts with the checkpoint signature. */
int esf_ckpt_is(const char *path);

/* The stored scene (pointers into the checkpoint). */
void esf_ckpt_scene_of(const esf_ckpt *c, esf_ckpt_scene *sc);

/* Loads the stored scene with its overrides and then `extra` ones (s zeroed), as
 * esf_scene_load does; esf_sim_setup comes next. */
int esf_ckpt_load_scene(const esf_ckpt *c, const char *const *extra, int nextra,
                        esf_sim *s, esf_error *err);

/* After esf_sim_setup on the stored scene and it->create: restores the sim's state,
 * then the integrator's, and returns the run loop's state in *run. ESF_EINPUT when the
 * checkpoint does not fit the scene (materials, dt, method, walls). */
int esf_ckpt_restore(const esf_ckpt *c, esf_sim *s, const esf_integrator_type *it,
                     void *ist, esf_ckpt_run *run, esf_error *err);

/* `esfera info` on a checkpoint: what it holds, one `key: value` per line, and the
 * command that resumes it. */
int esf_ckpt_describe(const char *path, FILE *out, esf_error *err);

#endif
