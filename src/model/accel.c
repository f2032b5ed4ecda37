/* accel.c — accelerations from the forces with the damping forms as force terms, and
 * the stored energies of a state (model.h): what the ODE methods and velocity Verlet
 * integrate (the leapfrog applies global damping in its own (1 -+ alpha dt/2) form).
 * The accelerations run on the caller's threads when no power is asked for (each
 * particle's by one thread: the same bits on any count). */
#include "model/model.h"

#include "util/vec3.h"

#define ESF_ACCEL_PAR 4096 /* particles from which the accelerations are threaded */

/* Particle i's accelerations into acc, dw; with pw, its damping powers added to pw[0]
 * (global) and pw[1] (local). */
static inline void accel_one(const esf_sim *s, size_t i, const double *v, const double *w,
                             double *acc, double *dw, double ar, double at, double *pw) {
  const esf_particles *p = &s->p;
  const esf_local_damping *loc = s->local;
  const double lc = s->cfg.local_coef;
  const double *vi = v + 3 * i, *wi = w + 3 * i;
  double f[3], m[3], fd[3] = {0, 0, 0}, md[3] = {0, 0, 0};
  v3_copy(f, p->f + 3 * i);
  v3_copy(m, p->t + 3 * i);
  if (loc) {
    loc->force(lc, f, vi, fd);
    loc->force(lc, m, wi, md);
  }
  double mass = p->mass[i], I = p->inertia[i];
  for (int q = 0; q < 3; q++) {
    acc[3 * i + q] = (f[q] + fd[q]) * p->inv_mass[i] - ar * vi[q];
    dw[3 * i + q] = (m[q] + md[q]) * p->inv_inertia[i] - at * wi[q];
  }
  if (pw) {
    pw[0] += s->alpha_r * mass * v3_norm2(vi) + s->alpha_t * I * v3_norm2(wi);
    pw[1] -= v3_dot(fd, vi) + v3_dot(md, wi);
  }
}

void esf_sim_accel(const esf_sim *s, const double *v, const double *w, double *acc,
                   double *dw, double p_damp[2], int with_global, int threads) {
  const size_t n = s->p.n;
  const double ar = with_global ? s->alpha_r : 0.0, at = with_global ? s->alpha_t : 0.0;
  /* particle by particle, so threads change no bits; the powers' sums serially */
  const int nth = !p_damp && threads > 1 && n >= ESF_ACCEL_PAR ? threads : 1;
  if (nth > 1) {
#pragma omp parallel for num_threads(nth) schedule(static)
    for (size_t i = 0; i < n; i++) accel_one(s, i, v, w, acc, dw, ar, at, NULL);
    return;
  }
  double pw[2] = {0, 0}; /* no parallel region (its start costs a tiny scene most) */
  for (size_t i = 0; i < n; i++)
    accel_one(s, i, v, w, acc, dw, ar, at, p_damp ? pw : NULL);
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
