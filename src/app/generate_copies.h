/* generate_copies.h — `esfera generate`: model generation by successive copies
 * (004 §3.3, docs/physics.md#model-generation-by-successive-copies). A scene's
 * particles (the primary set) settle under gravity in a box open at the top; the
 * settled set is copied nx × ny × nz times to fill a box nx, ny times as wide and long;
 * the copies settle again (and, optionally, the side walls move inward to compact
 * them); the result is written as a packing CSV that `particles: [{file: ...}]` loads. */
#ifndef ESF_GENERATE_COPIES_H
#define ESF_GENERATE_COPIES_H

#include <stdio.h>

#include "util/esf_error.h"

/* How one settling stage ended. */
typedef struct esf_settle_report {
  size_t particles;
  long steps;
  double time;   /* simulated time of the stage, s */
  double ke;     /* kinetic energy at the end (translational + rotational), J */
  double e_ref;  /* the reference energy of the criterion, J */
  int settled;   /* 1: ke < ke_fraction e_ref; 0: stopped by max_time */
  double top;    /* highest particle top (z + r) at the end, m */
  double wall_s; /* wall time of the stage, s */
} esf_settle_report;

/* Runs the whole generation for the scene at `path` (with --set overrides) and writes
 * out_csv (x, y, z, radius, material, one row per particle in id order: copy c =
 * (k ny + j) nx + i holds ids c n0 .. c n0 + n0 - 1). One line per stage goes to `log`
 * (may be NULL). Errors: scene errors (ESF_EINPUT, with positions), numerical failure
 * (ESF_ENUMERIC), the file not writable (ESF_EIO; an earlier file is left intact). */
int esf_generate_copies(const char *path, const char *const *sets, int nsets,
                        const char *out_csv, FILE *log, esf_error *err);

#endif
