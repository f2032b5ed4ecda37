/* forces.h — the DEM right-hand side: forces and torques on every particle for a given
 * state, shared by every integrator (the leapfrog commits contact history each step; a
 * Runge-Kutta stage evaluates with history frozen). */
#ifndef ESF_FORCES_H
#define ESF_FORCES_H

#include "sim.h"

enum {
  ESF_FORCES_TRIAL = 0, /* history read, not written */
  ESF_FORCES_COMMIT = 1 /* history, touching flags and ledger tallies written */
};

/* Evaluates gravity and all contact forces at state (x, v, w) — arrays of 3n — into
 * s->p.f and s->p.t (overwritten). dt is the time over which the tangential increment
 * integrates (the step). The candidate lists must be valid for x. Fails with
 * ESF_ENUMERIC when an overlap exceeds cfg.max_overlap of the smaller radius, naming
 * the step, particles, dt and the critical dt. Sets *touching to the touching count. */
int esf_forces_eval(esf_sim *s, const double *x, const double *v, const double *w,
                    double dt, int mode, size_t *touching, esf_error *err);

/* After a leapfrog kick (before the drift): accumulates the dashpot dissipation and the
 * work of walls over the step with the mid-step velocities vbar, wbar (the average of
 * the half steps), using the dashpot forces the last COMMIT evaluation stored, and
 * sets the elastic energies in the leapfrog's measure (forces.c). Requires the ledger;
 * s->p.v, s->p.w hold the new half-step velocities. */
void esf_forces_ledger_pass(esf_sim *s, const double *vbar, const double *wbar,
                            double dt);

#endif
