/* run.h — the run driver: time loop, output schedule, failure checks, summary. */
#ifndef ESF_RUN_H
#define ESF_RUN_H

#include <signal.h>

#include "ckpt/checkpoint.h"
#include "core/sim.h"
#include "integrators/integrator.h"

typedef struct esf_run_opts {
  const char *out_dir; /* where energy.csv, log.txt, frames.h5 go */
  int quiet;           /* no progress */
  int progress;        /* show progress (stdout is a terminal) */
  /* checkpoints (checkpoint.h): every cfg.ckpt_every seconds and on *stop */
  const esf_ckpt_scene *scene; /* the scene they store; NULL: no checkpoints */
  const esf_ckpt *resume;      /* continue from it (the sim set up from its scene) */
  volatile sig_atomic_t *stop; /* set (by a signal handler): finish the step (the fused
                                  leapfrog's steps in hand, 32 at most), write a
                                  checkpoint (when the scheme can) and return with
                                  stats.interrupted */
  int overwrite; /* a new run may replace another run's results in out_dir */
} esf_run_opts;

typedef struct esf_run_stats {
  long steps;             /* the step count at the end (since the run's start) */
  double wall_s;          /* wall time of this invocation's time-stepping loop, s */
  double particles_mean;  /* mean particle count */
  double contacts_mean;   /* mean touching contacts */
  double rate;            /* particle-steps per second of this invocation's loop */
  double energy_error;    /* final total_error, J (0 without ledger) */
  double dissipated;      /* final dissipated energy, J */
  esf_integ_stats integ;  /* the integrator's cost accounting */
  int interrupted;        /* stopped on *stop */
  int stop_checkpoint;    /* ... and wrote a checkpoint there (else the scheme cannot) */
  int stepping;           /* the time loop began (output so far is worth a look) */
  long checkpoints;       /* checkpoints written by this invocation */
  long checkpoints_total; /* checkpoints since the run's start (a resumed run: those
                             before the resume included) */
  long resumed_step;      /* the step this invocation resumed at (0: not resumed); wall_s
                             and rate cover the steps from there on */
} esf_run_stats;

/* Creates out_dir (and parents), writes log.txt, energy.csv and frames.h5 while
 * integrating the set-up sim to its end. On a numerical failure the files written so
 * far are closed intact and the error says what happened and what to change. */
int esf_run(esf_sim *s, const esf_run_opts *o, esf_run_stats *st, esf_error *err);

/* Creates a directory and its parents (like mkdir -p). */
int esf_mkdirs(const char *path, esf_error *err);

#endif
