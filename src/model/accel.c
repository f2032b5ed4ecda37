/* accel.c — accelerations from the forces with the damping forms as force terms, and
 * the stored energies of a state (model.h): what the ODE methods and velocity Verlet
 * integrate (the leapfrog applies global damping in its own (1 -+ alpha dt/2) form).
 * The accelerations run on the caller's threads when no power is asked for (each
 * particle's by one thread: the same bits on any count); the formula: accel.h. */
#include "model/model.h"

#include "model/accel.h"
#include "util/vec3.h"

#define ESF_ACCEL_PAR 4096 /* particles from which the accelerations are threaded */

void esf_sim_accel(const esf_sim *s, const double *v, const double *w, double *acc,
                   double *dw, double p_damp[2], int with_global, int threads) {
  const size_t n = s->p.n;
  const double ar = with_global ? s->alpha_r : 0.0, at = with_global ? s->alpha_t : 0.0;
  /* particle by particle, so threads change no bits; the powers' sums serially */
  const int nth = !p_damp && threads > 1 && n >= ESF_ACCEL_PAR ? threads : 1;
  if (nth > 1) {
#pragma omp parallel for num_threads(nth) schedule(static)
    for (size_t i = 0; i < n; i++)
      esf_accel_one(s, i, s->p.f + 3 * i, s->p.t + 3 * i, v, w, acc, dw, ar, at, NULL);
    return;
  }
  double pw[2] = {0, 0}; /* no parallel region (its start costs a tiny scene most) */
  for (size_t i = 0; i < n; i++)
    esf_accel_one(s, i, s->p.f + 3 * i, s->p.t + 3 * i, v, w, acc, dw, ar, at,
                  p_damp ? pw : NULL);
  if (p_damp) {
    p_damp[0] = pw[0];
    p_damp[1] = pw[1];
  }
}

void esf_sim_energies(const esf_sim *s, const double *x, const double *v, const double *w,
                      double *kin_t, double *kin_r, double *pot) {
  const esf_particles *p = &s->p;
  double kt = 0, kr = 0, pe = 0;
  for (size_t i = 0; i < p->n; i++) {
    kt += 0.5 * p->mass[i] * v3_norm2(v + 3 * i);
    kr += 0.5 * p->inertia[i] * v3_norm2(w + 3 * i);
    pe -= p->mass[i] * v3_dot(s->cfg.gravity, x + 3 * i);
  }
  *kin_t = kt;
  *kin_r = kr;
  *pot = pe;
}
