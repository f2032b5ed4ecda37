/* wall_fast.h — the particle-wall contacts of one particle for the fused leapfrog step
 * (fused/fused.c): a pass specialised to static walls and the linear law (wall_fast.c),
 * and the general one (forces.c) behind the same signature, chosen once per step. */
#ifndef ESF_WALL_FAST_H
#define ESF_WALL_FAST_H

#include <stddef.h>

#include "core/sim.h"

/* The wall contacts of one particle, candidates [k0, k1) of s->nb.pw, at the state
 * s->p.x, v, w over step dt, history committed: adds the forces and torques to f and t
 * (3 each), the contacts carrying force to *nt and, when rows is not NULL, their ledger
 * rows to rows (the particle's, core/ledger.h). Returns nonzero when an overlap exceeds
 * cfg.max_overlap (esf_forces_wall_particle then gives the message). */
typedef int (*esf_wall_pass_fn)(esf_sim *s, size_t k0, size_t k1, double dt, size_t *nt,
                                double *f, double *t, double *rows);

/* The fast pass: the same bits as esf_forces_wall_particle(..., ESF_FORCES_COMMIT,
 * NULL, NULL, ...) when every wall is static, every material pair has the linear law
 * (or every one Hertz-Mindlin), no rolling resistance, and neither tally, servo walls
 * nor history as ODE state are on. */
int esf_wall_fast_particle(esf_sim *s, size_t k0, size_t k1, double dt, size_t *nt,
                           double *f, double *t, double *rows);

/* The same with moving walls (forces.c's: the group's velocity at the contact point in
 * the contact velocity, its spin about the normal, the ledger's wall rows). */
int esf_wall_fast_particle_moving(esf_sim *s, size_t k0, size_t k1, double dt, size_t *nt,
                                  double *f, double *t, double *rows);

/* The same with the ledger's rows of the cumulative terms only (the first ESF_LR_DISS
 * of core/ledger.h: a light step of the fused step) but W (static walls:
 * ESF_LEDGER_NO_W); _n without the rows DT and MDT either (ESF_LEDGER_NO_T: DN alone,
 * the first ESF_LR_DISS_N). */
int esf_wall_fast_particle_light(esf_sim *s, size_t k0, size_t k1, double dt, size_t *nt,
                                 double *f, double *t, double *rows);
int esf_wall_fast_particle_light_n(esf_sim *s, size_t k0, size_t k1, double dt,
                                   size_t *nt, double *f, double *t, double *rows);

/* esf_forces_wall_particle committing, without an error message. */
int esf_wall_general_particle(esf_sim *s, size_t k0, size_t k1, double dt, size_t *nt,
                              double *f, double *t, double *rows);

/* The fast pass (static or moving walls) when s qualifies (above), else the general
 * one. */
esf_wall_pass_fn esf_wall_pass_select(const esf_sim *s);

/* For esf_fused_forces: where the fast pass qualifies but for the ODE methods' carry
 * (the lists' vc0), the fast pass with the carry, committing or as a trial (writing no
 * history, touch flag or carry); else the general pass, committing or as a trial. */
esf_wall_pass_fn esf_wall_pass_eval(const esf_sim *s, int trial);

#endif
