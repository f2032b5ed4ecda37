/* step_fast.h — the leapfrog step specialised and threaded for the common case.
 *
 * When a run needs nothing beyond the linear law with tangential history, walls, global
 * and local damping and gravity (no energy ledger, no adaptive damping, no per-
 * evaluation tallies), the leapfrog's force evaluation, kick and drift run here as one
 * threaded pass whose results do not depend on the thread count, bit for bit. The
 * particles are cut into one contiguous range per thread; each thread, for its range:
 *   1. computes the boundary pairs whose a is in it (b in a higher range) into
 *      per-pair slots (force on A, torques on A and B), commits their history and
 *      raises its flag;
 *   2. screens its interior pairs, waits for the lower ranges' flags, subtracts the
 *      incoming boundary slots, computes its interior pairs in batches of eight
 *      (pair_batch.h) and adds the outgoing slots between them, so every particle
 *      receives its pair forces in ascending pair order (the order the serial scatter
 *      of forces.c adds them in); then adds its wall contacts, and kicks and drifts
 *      its particles.
 * Every sum therefore has one fixed order. Anything else takes forces.c's general path
 * (esf_step_fast_eligible says which). */
#ifndef ESF_STEP_FAST_H
#define ESF_STEP_FAST_H

#include "core/sim.h"

typedef struct esf_step_fast esf_step_fast;

int esf_step_fast_create(esf_step_fast **out, esf_error *err);
void esf_step_fast_free(esf_step_fast **f);

/* 1 when the sim's current settings can use the fused step (checked every step: the
 * ledger or adaptive damping may be switched by the driver). */
int esf_step_fast_eligible(const esf_sim *s);

/* Up to nmax leapfrog steps from x_n, v_{n-1/2}, w_{n-1/2} (candidate lists valid),
 * each: forces at x_n committing the history, kick with global and local damping,
 * drift. Between two steps of one call the ranges check what the driver would (the
 * lists' displacement limit, particles leaving the domain, non-finite positions, the
 * balance of the ranges) and stop early when a rebuild or re-cut is due; more than one
 * step is taken only with static walls and no scene events, whose checks between steps
 * need more. On exit *taken steps were completed: s->step, s->t, s->contacts_sum and
 * s->rhs_evals advanced by them; x, v, w advanced, F_n and M_n of the last left in the
 * step's accumulators with s->ft_lazy pointing at them (esf_sim_forces_sync copies them
 * to p.f and p.t; not copied every step, as only frames and checkpoints read them), and
 * nb.max_disp2 the largest squared displacement since the last build. A failure
 * (overlap past the limit) is reported for the step it happened in, s->step naming it. */
int esf_step_fast_run(esf_sim *s, esf_step_fast *f, long nmax, long *taken,
                      esf_error *err);

#endif
