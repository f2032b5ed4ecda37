/* integrator.h — the time-integration strategy table.
 *
 * Every scheme (the production leapfrog here; velocity Verlet and the SUNDIALS methods
 * of the testbed) is a const descriptor with its capabilities, so that the run driver
 * treats them alike and all of them call the same physics (model/forces.h).
 *
 * Contract of step(): on entry the sim holds a consistent state at time s->t; on exit
 * it holds the state one step later (fixed-step schemes advance by s->dt; adaptive ones
 * by the step they chose, never past t_stop), s->t and s->step advanced, and, when the
 * energy ledger is on, the ledger updated through that step with s->led_time set to the
 * time its stored energies refer to. */
#ifndef ESF_INTEGRATOR_H
#define ESF_INTEGRATOR_H

#include "core/sim.h"
#include "util/blob.h"
#include "util/esf_error.h"

enum {
  ESF_INTEG_FIXED_STEP = 1u << 0,          /* uses s->dt */
  ESF_INTEG_ADAPTIVE = 1u << 1,            /* chooses its own steps */
  ESF_INTEG_HALF_STEP_V = 1u << 2,         /* velocities in the state are at half steps */
  ESF_INTEG_HISTORY_INCREMENTAL = 1u << 3, /* contact history committed once per step */
  ESF_INTEG_STABILITY_CHECK = 1u << 4 /* checks its stability live (model/stability.h);
                                         the driver asks once more at the run's end */
};

/* Cost accounting of a run (every scheme fills what applies; the rest stays 0). */
typedef struct esf_integ_stats {
  long steps;        /* accepted steps */
  long attempts;     /* step attempts (accepted + rejected) */
  long rejected;     /* error-test failures */
  long rhs_evals;    /* right-hand-side (force) evaluations, commits included */
  long acc_limited;  /* adaptive: steps limited by accuracy */
  long stab_limited; /* adaptive: steps limited by the stability bound */
  long events;       /* contact onsets and separations located (integrator.roots) */
  long restarts;     /* restarts on a changed state (history as ODE state) */
  long merged;       /* fixed-step erk: steps whose last stage's evaluation was their
                        commit (one evaluation fewer each; since the run's or resume's
                        start) */
  double h_last;     /* last step size, s */
  double h_stab;     /* adaptive ERK: the stability bound given to ARKODE, s (0: none) */
} esf_integ_stats;

typedef struct esf_integrator_type {
  const char *name;
  const char *summary; /* one line for --help and the log */
  int order;           /* nominal order of accuracy */
  unsigned flags;
  int (*create)(esf_sim *s, void **state, esf_error *err);
  int (*step)(esf_sim *s, void *state, double t_stop, esf_error *err);
  void (*destroy)(void **state);
  /* Optional: cost accounting so far. */
  void (*stats)(const esf_sim *s, void *state, esf_integ_stats *out);
  /* Optional: checkpoints (checkpoint.h); a scheme without them cannot checkpoint.
   * save appends the scheme's state between steps to out. A scheme whose library keeps
   * state it does not expose (ARKODE's step-size controller history) restarts itself
   * here from exactly what it saved, so the run that wrote the checkpoint and a run
   * resumed from it continue identically. restore is called on a state fresh from
   * create on the same scene, after the sim's own state (particles, lists, walls,
   * ledger, counters) was restored, and sets the scheme's state from what save wrote
   * (ESF_EINPUT when it does not fit). */
  int (*save)(esf_sim *s, void *state, esf_blob *out, esf_error *err);
  int (*restore)(esf_sim *s, void *state, esf_blob_in *in, esf_error *err);
  /* Optional: releases the storage the scheme makes again at its next step (the fused
   * step's indices and accumulators), changing no result. The run driver calls it
   * before a frame and before the final stability check, whose scratch then does not
   * add to it (docs/performance.md#memory). */
  void (*trim)(esf_sim *s, void *state);
} esf_integrator_type;

extern const esf_integrator_type esf_integrator_leapfrog;
extern const esf_integrator_type esf_integrator_verlet;
extern const esf_integrator_type esf_integrator_erk;   /* erk:<TABLE> and rk4 */
extern const esf_integrator_type esf_integrator_cvode; /* cvode-adams */

/* The scheme of a given name (integrator.method), or NULL. */
const esf_integrator_type *esf_integrator_find(const char *name);

/* Names of all schemes, NULL-terminated, for messages. */
extern const esf_integrator_type *const esf_integrators[];

#endif
