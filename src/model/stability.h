/* stability.h — the live stability check of the leapfrog (docs/physics.md#live-stability
 * check): the largest eigenvalue of dt^2 A + 2 dt B over the current contact network,
 * A = M^{-1/2} K M^{-1/2} (springs) and B = M^{-1/2} C M^{-1/2} (dashpots), which the
 * leapfrog keeps below 4 exactly when it is stable; and the one source of a contact's
 * stiffness G^T S G that `esfera modes` assembles densely. */
#ifndef ESF_STABILITY_H
#define ESF_STABILITY_H

#include <stddef.h>
#include <stdint.h>

#include "core/sim.h"
#include "util/vec3.h"
#include "util/esf_error.h"

/* y += G^T S G x for one contact with unit normal n (from A toward B or the wall), lever
 * arms la, lb from the centres to the contact point and S = kn n n^T + kt (I - n n^T
 * - t t^T) with t the unit slip direction of a sliding contact (radial return keeps the
 * spring across the slip, not along it), or S = kn n n^T + kt (I - n n^T) when t is
 * NULL. x and y hold a body's 6 local coordinates (translation, rotation); xb, yb NULL
 * for a wall (fixed). */
static inline void esf_stab_contact_apply(const double n[3], const double *t, double la,
                                          double lb, double kn, double kt,
                                          const double *xa, const double *xb, double *ya,
                                          double *yb) {
  /* the contact point's relative motion dc = dxB + lb n x dthB - dxA + la n x dthA */
  double dc[3], c[3];
  v3_cross(c, n, xa + 3);
  for (int q = 0; q < 3; q++) dc[q] = la * c[q] - xa[q];
  if (xb) {
    v3_cross(c, n, xb + 3);
    for (int q = 0; q < 3; q++) dc[q] += xb[q] + lb * c[q];
  }
  /* f = S dc, then G^T f: -f and la f x n on A, f and lb f x n on B */
  double dn = v3_dot(n, dc), dt = t ? v3_dot(t, dc) : 0.0, f[3];
  for (int q = 0; q < 3; q++)
    f[q] = kt * dc[q] + (kn - kt) * dn * n[q] - (t ? kt * dt * t[q] : 0.0);
  v3_cross(c, f, n);
  for (int q = 0; q < 3; q++) {
    ya[q] -= f[q];
    ya[3 + q] += la * c[q];
  }
  if (xb)
    for (int q = 0; q < 3; q++) {
      yb[q] += f[q];
      yb[3 + q] += lb * c[q];
    }
}

/* y += the rolling resistance's rotational stiffness for one contact:
 * S_r = kr (I - n n^T) + ktw n n^T on the relative rotation dth = dthA - dthB
 * (docs/physics.md#rolling-resistance): S_r dth on A's rotation, -S_r dth on B's (xb,
 * yb NULL for a wall). */
static inline void esf_stab_roll_apply(const double n[3], double kr, double ktw,
                                       const double *xa, const double *xb, double *ya,
                                       double *yb) {
  double d[3];
  for (int q = 0; q < 3; q++) d[q] = xa[3 + q] - (xb ? xb[3 + q] : 0.0);
  const double dn = v3_dot(n, d);
  for (int q = 0; q < 3; q++) {
    const double m = kr * d[q] + (ktw - kr) * dn * n[q];
    ya[3 + q] += m;
    if (yb) yb[3 + q] -= m;
  }
}

/* kn, kt, cn, ct of a contact of material pair pp with reduced mass mstar (the linear
 * law's dashpots, contact_linear.c; an adhesive pair's largest bonded tangent
 * stiffness; the Hertz-Mindlin law's tangent stiffnesses and dashpots at overlap un,
 * reduced radius rstar, contact_hertz.h); beta > 0: Rayleigh dashpots c = beta k. */
void esf_stab_springs(const esf_pair_params *pp, double beta, double mstar, double rstar,
                      double un, double kc[4]);

/* One touching contact as the check sees it: bodies a and b (b < 0: a wall), unit
 * normal n from a, lever arms, kc = kn, kt, cn, ct (esf_stab_springs; kt and ct zero
 * when frictionless) and, when slip, the unit slip direction t of a contact at its
 * Coulomb cap; with roll, the rolling and twisting springs and dashpots (the elastic
 * ones, also at the limit: an upper bound). */
typedef struct esf_stab_contact {
  size_t a;
  long b;
  double n[3], t[3], la, lb, kc[4];
  int slip;
  int roll;     /* 1: rolling resistance springs (epsd) in kr */
  double kr[4]; /* kr, ktw, cr, ctw (esf_law_rolling_par; roll only) */
} esf_stab_contact;

typedef void (*esf_stab_visit)(const esf_stab_contact *c, void *ctx);

/* Calls fn for every touching contact at the sim's state (pairs overlapping or bonded;
 * wall contacts that carry force, as forces.c chooses among hits on shared mesh edges
 * and vertices), pairs first in list order, then walls by particle; returns how many.
 * The one source of the network that the live check applies and `esfera modes`
 * assembles. */
size_t esf_stab_contacts(const esf_sim *s, esf_stab_visit fn, void *ctx);

/* One estimate at step dt. */
typedef struct esf_stability {
  double lambda;   /* largest eigenvalue of dt^2 A + 2 dt B (the leapfrog needs < 4) */
  double omega;    /* sqrt(phi.A.phi) of the top mode phi, rad/s (with_mode) */
  double xi;       /* its damping ratio phi.B.phi / (2 omega) (with_mode) */
  double dt_limit; /* the step at which that mode reaches 4, s (with_mode; an upper
                      bound of the limit, exact where phi does not change with dt) */
  size_t contacts; /* touching contacts in the network */
  int iters;       /* Lanczos steps */
  int64_t id;      /* id of the particle with the largest share of the mode (with_mode) */
  int64_t other;   /* id of its partner in the contact that stores most of the mode's
                      energy, -1 for a wall, -2 none (with_mode) */
} esf_stability;

/* Estimates lambda at step dt (Lanczos, matrix-free, on cfg.threads threads with the
 * same bits on any count; the state is not changed), with local damping of coefficient
 * alpha_c scaling the operator by (1 + alpha_c) (its force can add to the unbalanced one
 * in the unstable period-two mode); with_mode: also the top mode (a second Lanczos pass).
 * Errors: ESF_ENOMEM. */
int esf_stability_estimate(esf_sim *s, double dt, int with_mode, esf_stability *out,
                           esf_error *err);

/* The step at which lambda reaches 4 for the current network (fixed-point iterations of
 * esf_stability_estimate's dt_limit, to 1e-6), s; INFINITY without contacts. */
int esf_stability_limit(esf_sim *s, double *dt_limit, esf_stability *top, esf_error *err);

/* The leapfrog's guard, called before its steps: at every cfg.stability_every-th step
 * (and when final is 1) estimates lambda; above 4 stops the run (ESF_ENUMERIC, naming
 * the step, the mode's particles, dt, the limit and what to change) or, with
 * stability: warn, logs a warning once. Logs the first estimate. */
int esf_stability_guard(esf_sim *s, int final, esf_error *err);

/* A particle that travels more than this fraction of its radius in one step (or
 * turns as many radians) has run away: contacts would be skipped. */
#define ESF_RUNAWAY_TRAVEL 0.5

/* The runaway check, called by the leapfrog at every list rebuild (cheap: one pass over
 * the particles, serial): ESF_ENUMERIC naming the particle, its speed, dt and the
 * limits when one moves more than ESF_RUNAWAY_TRAVEL of its radius in a step. */
int esf_stability_runaway(const esf_sim *s, esf_error *err);

/* Steps the leapfrog may take before its next check (for its bursts), >= 1. */
long esf_stability_steps_left(const esf_sim *s);

#endif
