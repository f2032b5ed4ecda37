/* accel.h — one particle's accelerations from its force and torque with the damping
 * forms as force terms (model.h: esf_sim_accel), inline: written once for
 * esf_sim_accel (accel.c) and the fused evaluation's particle pass (fused_kick.c).
 *   a = (F + F_local(F, v) - alpha_r m v) / m,  dw = (M + M_local(M, w) - alpha_t I w) /
 * I with ar, at the global coefficients the caller applies (0: left out). SI. */
#ifndef ESF_MODEL_ACCEL_H
#define ESF_MODEL_ACCEL_H

#include "core/sim.h"
#include "util/vec3.h"

/* One entry of an acceleration: (f + fd) times the inverse mass (or inertia) im, less
 * the global damping ar v (fd: the local damping's term, +0 without it). The one
 * formula of esf_accel_one and of the fused kernels' vectorised loops (fused_kick.c). */
static inline double esf_accel_entry(double f, double fd, double im, double ar,
                                     double v) {
  return (f + fd) * im - ar * v;
}

/* Particle i's accelerations from force f and torque m (3 each) at velocities v, w (3n)
 * into acc, dw (3n); with pw, its damping powers added to pw[0] (global) and pw[1]
 * (local), W. */
static inline void esf_accel_one(const esf_sim *s, size_t i, const double *fi,
                                 const double *mi, const double *v, const double *w,
                                 double *acc, double *dw, double ar, double at,
                                 double *pw) {
  const esf_particles *p = &s->p;
  const esf_local_damping *loc = s->local;
  const double lc = s->cfg.local_coef;
  const double *vi = v + 3 * i, *wi = w + 3 * i;
  double f[3], m[3], fd[3] = {0, 0, 0}, md[3] = {0, 0, 0};
  v3_copy(f, fi);
  v3_copy(m, mi);
  if (loc) {
    loc->force(lc, f, vi, fd);
    loc->force(lc, m, wi, md);
  }
  double mass = p->mass[i], I = p->inertia[i];
  for (int q = 0; q < 3; q++) {
    acc[3 * i + q] = esf_accel_entry(f[q], fd[q], p->inv_mass[i], ar, vi[q]);
    dw[3 * i + q] = esf_accel_entry(m[q], md[q], p->inv_inertia[i], at, wi[q]);
  }
  if (pw) {
    pw[0] += s->alpha_r * mass * v3_norm2(vi) + s->alpha_t * I * v3_norm2(wi);
    pw[1] -= v3_dot(fd, vi) + v3_dot(md, wi);
  }
}

#endif
