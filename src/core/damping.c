/* damping.c — local non-viscous damping forms and the adaptive global damping rule.
 * Local damping (Cundall 1982): 001 (3.50–3.51) component form; 000 (3-11, 3-12)
 * vector form. The velocity whose sign is taken is the caller's choice; the leapfrog
 * passes the half-step velocity v(t - dt/2), the latest one known when the force at t
 * is applied. Units: N (or N m), m/s (or rad/s). */
#include "core/damping.h"

#include <math.h>

static void local_component(double coef, const double f[3], const double v[3],
                            double fd[3]) {
  for (int k = 0; k < 3; k++) {
    double s = v[k] > 0 ? 1.0 : (v[k] < 0 ? -1.0 : 0.0);
    fd[k] = -coef * fabs(f[k]) * s;
  }
}

static void local_vector(double coef, const double f[3], const double v[3],
                         double fd[3]) {
  double vm = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  double fm = sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
  double s = vm > 0 ? -coef * fm / vm : 0.0;
  for (int k = 0; k < 3; k++) fd[k] = s * v[k];
}

const esf_local_damping esf_local_component = {"component", local_component};
const esf_local_damping esf_local_vector = {"vector", local_vector};

double esf_auto_damping_update(const esf_auto_damping *a, double alpha, double ek_old,
                               double ek_new, double dt) {
  double rate = fabs(ek_new - ek_old) / dt;             /* |dEk/dt|, W */
  double power = 2.0 * alpha * 0.5 * (ek_old + ek_new); /* 2 alpha Ek, W */
  /* ratio > a_fac (including rate = 0): the dampers absorb more than the motion
     changes, so damp less; otherwise damp more */
  if (power > a->a_fac * rate)
    alpha /= a->a_mul;
  else
    alpha *= a->a_mul;
  if (alpha < a->alpha_min) alpha = a->alpha_min;
  if (alpha > a->alpha_max) alpha = a->alpha_max;
  return alpha;
}
