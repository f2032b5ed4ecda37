/* drag.h — one-way fluid forces on particles (docs/physics.md#fluid-force, seed 004
 * §4.4): a prescribed fluid field (steady radial Darcy flow toward a well, or uniform
 * flow) and the Ergun / Wen-Yu drag plus the pressure-gradient force on each particle.
 * The fluid is not affected by the particles. A scene without `fluid:` has s->drag NULL
 * and pays nothing. */
#ifndef ESF_DRAG_H
#define ESF_DRAG_H

#include "core/sim.h"
#include "loads/porosity.h"

enum { ESF_DRAG_RADIAL = 0, ESF_DRAG_UNIFORM = 1 };

typedef struct esf_drag {
  int kind;        /* ESF_DRAG_* */
  double start;    /* time the fluid force is switched on, s */
  double porosity; /* void fraction epsilon, fixed (grid off) */
  int grid;        /* 1: epsilon from a coarse grid of cells (porosity.h) */
  esf_porosity_grid pg;
  double mu;   /* fluid viscosity, Pa s */
  double rho;  /* fluid density, kg/m^3 */
  double perm; /* permeability k, m^2 (radial: Darcy velocity) */
  /* radial: the well's axis through center, radii and the pressure drop p_e - p_w */
  double center[3], axis[3]; /* m, unit */
  double rw, re;             /* well and drainage radii, m */
  double dp;                 /* p_e - p_w, Pa (positive: flow toward the well) */
  /* uniform */
  double u[3];     /* fluid (Darcy) velocity, m/s */
  double gradp[3]; /* pressure gradient, Pa/m */
  /* the last evaluation's force on each particle (ledger), N */
  size_t cap, n;
  double *f;
  int logged; /* set-up and switch-on written to the run's log: 1, 2 */
  /* the porosity's update, or NULL: esf_porosity_update over the particles (an MPI
     run's sums across its processes, par.c) */
  int (*update_porosity)(struct esf_sim *s, const double *x, esf_error *err);
  double tau; /* shortest drag relaxation time, s */
} esf_drag;

/* Fluid pressure relative to the far field, p - p_e (Pa), the pressure gradient (Pa/m)
 * and the Darcy velocity (m/s) at point x. Returns 0 where the field does not act (the
 * radial field inside the well, r < r_w, or beyond r_e), 1 otherwise. */
int esf_drag_field(const esf_drag *d, const double x[3], double *p, double gradp[3],
                   double u[3]);

/* The interphase momentum coefficient beta (kg/(m^3 s)) for void fraction eps,
 * particle diameter dp (m) and slip speed |u - v| (m/s): Ergun for eps < 0.8, Wen-Yu
 * above. */
double esf_drag_beta(const esf_drag *d, double eps, double dp, double slip);

/* At set-up (dt chosen): the shortest drag relaxation time of any particle,
 * tau = m (1 - eps) / (V beta_0), beta_0 the slip-free beta (the viscous Ergun or
 * Stokes-limit Wen-Yu term); an explicit step must stay below it (the drag is
 * integrated explicitly; dt > 2 tau diverges). Refused unless allow_unstable. */
int esf_drag_setup(esf_sim *s, esf_error *err);

/* Adds the fluid force to s->p.f at state (x, v) when t >= start, records it for the
 * ledger, and its power into s->tally (p_fluid) when set. */
int esf_drag_apply(esf_sim *s, const double *x, const double *v, esf_error *err);

/* esf_drag_apply in two parts, for a caller that adds the forces particle by particle
 * (the fused step): the evaluation's set-up at positions x (room for d->f, the log, the
 * porosity grid), *on whether the field acts now; then particle i's fluid force F at x,
 * v (zero when off or outside the field), which the caller stores in d->f. */
int esf_drag_prepare(esf_sim *s, const double *x, int *on, esf_error *err);
void esf_drag_particle(const esf_sim *s, int on, size_t i, const double x[3],
                       const double v[3], double F[3]);

void esf_drag_free(esf_drag **d);

#endif
