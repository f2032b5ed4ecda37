/* forces.h — the DEM right-hand side: forces and torques on every particle for a given
 * state, shared by every integrator (the leapfrog commits contact history each step; a
 * Runge-Kutta stage evaluates with history frozen). */
#ifndef ESF_FORCES_H
#define ESF_FORCES_H

#include "core/sim.h"

enum {
  ESF_FORCES_TRIAL = 0, /* history read, not written */
  ESF_FORCES_COMMIT = 1 /* history, touching flags and ledger tallies written */
};

/* Evaluates gravity and all contact forces at state (x, v, w) — arrays of 3n — into
 * s->p.f and s->p.t (overwritten). dt is the time over which the tangential increment
 * integrates (the step). The candidate lists must be valid for x. Fails with
 * ESF_ENUMERIC when an overlap exceeds cfg.max_overlap of the smaller radius, naming
 * the step, particles, dt and the critical dt. Sets *touching to the touching count.
 * When s->tally is not NULL it is overwritten with the evaluation's energy rates. */
int esf_forces_eval(esf_sim *s, const double *x, const double *v, const double *w,
                    double dt, int mode, size_t *touching, esf_error *err);

/* The error for an overlap beyond cfg.max_overlap of the smaller radius rmin: names the
 * step, the particles (ids; idb is the wall element when wall), the overlap, dt and the
 * critical dt, and what to change. Returns ESF_ENUMERIC. */
int esf_forces_overlap_failure(const esf_sim *s, long long ida, long long idb, int wall,
                               double un, double rmin, esf_error *err);

/* The wall contacts of one particle: candidates [k0, k1) of s->nb.pw, all of one
 * particle (the list is sorted by particle). Adds their forces and torques to f and t
 * (3 each), counts the contacts carrying force into *nt and, when rows is not NULL,
 * their ledger rows into rows (the particle's ESF_LR, ledger.h), when slip is not NULL,
 * their slip work into *slip. Touches only the
 * candidates' own entries (history, flags, the wall scratch of nb), so distinct
 * particles may run in parallel. */
int esf_forces_wall_particle(esf_sim *s, size_t k0, size_t k1, const double *x,
                             const double *v, const double *w, double dt, int commit,
                             double *rows, double *slip, size_t *nt, double *f, double *t,
                             esf_error *err);

/* Which of one particle's wall hits carry force (forces.c's rule: faces first, edges
 * and vertices unless on a touched face or already kept; shared points once): keep[k]
 * for hits[0..m) on elements elem[0..m) with overlaps un (entries with un <= 0 are
 * ignored and not read), particle radius r. For the fast wall pass (wall_fast.c). */
void esf_forces_select_wall_hits(const esf_walls *walls, const uint32_t *elem,
                                 const esf_wall_hit *hits, const double *un, size_t m,
                                 double r, unsigned char *keep);

/* One touching contact as esf_forces_probe reports it: particles a and b (a pair), or
 * particle a and wall element b of wall group `group` (the scene's walls index; -1 for a
 * pair); pc the contact point (m); f the force on a and ft its tangential part (N; the
 * law's output, valid during the call); ta the torque on a about its centre (N m: lever
 * arm x ft plus rolling and twisting resistance); fn the normal force's magnitude. */
typedef struct esf_probe_contact {
  uint32_t a, b;
  int group;
  double pc[3];
  const double *f, *ft;
  double ta[3];
  double fn;
} esf_probe_contact;

typedef struct esf_contact_probe {
  void (*fn)(void *ctx, const esf_probe_contact *c);
  void *ctx;
} esf_contact_probe;

/* For output: evaluates every touching pair (pairs != 0) and particle-wall contact
 * (walls != 0) at the current state (s->p.x, v, w) in trial mode, in list order (one
 * thread), and passes each to probe. The history's increment covers s->dt for the
 * leapfrog (the force its next step applies at this state) and nothing for the schemes
 * that commit at the state itself (Verlet, the ODE methods: the committed force). Writes
 * nothing to p.f, p.t, the histories, the touching flags or the ledger (only the lists'
 * wall scratch). */
int esf_forces_probe(esf_sim *s, int pairs, int walls, const esf_contact_probe *probe,
                     esf_error *err);

#endif
