/* damping.h — damping of particle motion (docs/physics.md#damping): the local
 * non-viscous forms (a strategy table) and the adaptive global damping of 001
 * (3.62–3.63). Global viscous damping lives in the integrators ((1 -+ alpha dt/2) form
 * in the leapfrog). */
#ifndef ESF_DAMPING_H
#define ESF_DAMPING_H

/* Cundall's local non-viscous damping: given the unbalanced force (or moment) f on a
 * particle and its velocity v, returns the damping force fd. */
typedef struct esf_local_damping {
  const char *name;
  void (*force)(double coef, const double f[3], const double v[3], double fd[3]);
} esf_local_damping;

/* 001 (3.50–3.51), the PFC convention: fd_k = -coef |f_k| sign(v_k) per component. */
extern const esf_local_damping esf_local_component;
/* 000 (3-11, 3-12): fd = -coef |f| v / |v|. */
extern const esf_local_damping esf_local_vector;

/* Adaptive (auto) global damping, 001 (3.62–3.63): each step the power the global
 * dampers dissipate, 2 alpha Ek, is compared with the rate of change of the kinetic
 * energy |dEk/dt|; when the ratio exceeds a_fac alpha is divided by a_mul, otherwise
 * multiplied by it; alpha stays within [alpha_min, alpha_max]. */
typedef struct esf_auto_damping {
  int on;
  double a_fac;     /* target ratio, ~1 (0.95 in 001) */
  double a_mul;     /* adjustment factor, ~1.1 */
  double alpha_min; /* 1/s */
  double alpha_max; /* 1/s */
} esf_auto_damping;

/* Returns the new alpha from the kinetic energy before and after a step of dt. */
double esf_auto_damping_update(const esf_auto_damping *a, double alpha, double ek_old,
                               double ek_new, double dt);

#endif
