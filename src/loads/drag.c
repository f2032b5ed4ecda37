/* drag.c — one-way coupled fluid force (docs/physics.md#fluid-force; seed 004 eqs.
 * 4.1–4.4, after Hoomans et al.).
 *
 * Field: radial, steady Darcy flow to a well (4.1, 4.4; esf_drag_field), or uniform
 * (u and grad p given). Force on a particle of volume V_p (3D 4/3 pi r^3; 2D pi r^2
 * thickness), diameter d_p = 2r and velocity v_p (4.2, with 1 - epsilon as in Hoomans
 * et al.; the seed prints 1 + epsilon):
 *   F = V_p beta/(1 - eps) (u - v_p) - V_p grad p
 * with beta (4.3) by Ergun for eps < 0.8 and Wen-Yu above (esf_drag_beta).
 * u is used as the seed uses it: the Darcy (superficial) velocity. The porosity is a
 * fixed scene value, or the local void fraction of a coarse grid of cells
 * (porosity.c) rebuilt at every evaluation while the force acts. The force starts at
 * `start` (production after drilling); the time is the step's (s->t), so an ODE method
 * switches it on at a step boundary. Ledger: the leapfrog's work is F_n . vbar dt per
 * step (the same identity as the other kick forces), other integrators integrate the
 * power F . v (tally p_fluid). Units: SI. */
#include "loads/drag.h"

#include <math.h>
#include <stdlib.h>

#include "loads/servo.h"
#include "util/vec3.h"

/* Radial field (steady Darcy flow to a well of radius r_w, drainage radius r_e, axis
 * through `center` along `axis`; r the distance from the axis; dp = p_e - p_w):
 *   p(r) - p_e = -dp ln(r_e/r) / ln(r_e/r_w)                        (4.1)
 *   grad p     = dp / (ln(r_e/r_w) r) e_r          (pointing away from the well)
 *   u          = -(k/mu) grad p                    (Darcy velocity, 4.4)
 * The field acts for r_w <= r <= r_e only (no porous medium inside the well).
 * Uniform field: u and grad p given. */
int esf_drag_field(const esf_drag *d, const double x[3], double *p, double gradp[3],
                   double u[3]) {
  if (d->kind == ESF_DRAG_UNIFORM) {
    v3_copy(gradp, d->gradp);
    v3_copy(u, d->u);
    *p = 0.0;
    return 1;
  }
  double r[3];
  v3_sub(r, x, d->center);
  v3_axpy(r, -v3_dot(r, d->axis), d->axis);
  double rr = v3_norm(r);
  v3_set(gradp, 0, 0, 0);
  v3_set(u, 0, 0, 0);
  *p = 0.0;
  if (!(rr >= d->rw) || rr > d->re) return 0;
  double L = log(d->re / d->rw);
  *p = -d->dp * log(d->re / rr) / L;
  v3_scale(gradp, d->dp / (L * rr * rr), r); /* dp/(L r) e_r */
  v3_scale(u, -d->perm / d->mu, gradp);
  return 1;
}

/* beta (4.3), Ergun for eps < 0.8:
 *   beta = 150 (1 - eps)^2/eps mu/d_p^2 + 1.75 (1 - eps) rho_f |u - v_p| / d_p
 * and Wen-Yu for eps >= 0.8 (the usual Gidaspow switch; the seed gives no rule):
 *   beta = 3/4 C_d eps (1 - eps) rho_f |u - v_p| / d_p eps^-2.65,
 *   C_d = 24/Re (1 + 0.15 Re^0.687) (Re < 1000), 0.44 above,
 *   Re = eps rho_f |u-v| d/mu. */
double esf_drag_beta(const esf_drag *d, double eps, double dp, double slip) {
  double e = eps, s = 1.0 - e;
  if (e < 0.8)
    return 150.0 * s * s / e * d->mu / (dp * dp) + 1.75 * s * d->rho * slip / dp;
  double re = e * d->rho * slip * dp / d->mu;
  /* C_d |u - v|, finite as the slip vanishes */
  double cds = re < 1000.0
                   ? 24.0 * d->mu / (e * d->rho * dp) * (1.0 + 0.15 * pow(re, 0.687))
                   : 0.44 * slip;
  return 0.75 * cds * e * s * d->rho / dp * pow(e, -2.65);
}

int esf_drag_setup(esf_sim *s, esf_error *err) {
  esf_drag *d = s->drag;
  if (!d) return ESF_OK;
  const esf_particles *p = &s->p;
  if (d->grid) {
    int rc = esf_porosity_update(&d->pg, p, p->x, s->cfg.dim, s->cfg.disk_thickness, err);
    if (rc) return rc;
  }
  double tau = INFINITY;
  for (size_t i = 0; i < p->n; i++) {
    double r = p->radius[i];
    double vol = s->cfg.dim == 2 ? ESF_PI * r * r * s->cfg.disk_thickness
                                 : 4.0 / 3.0 * ESF_PI * r * r * r;
    double e = d->grid ? esf_porosity_at(&d->pg, p->x + 3 * i) : d->porosity;
    double t = p->mass[i] * (1.0 - e) / (vol * esf_drag_beta(d, e, 2.0 * r, 0.0));
    if (t < tau) tau = t;
  }
  d->tau = tau;
  if (s->dt > tau && !s->cfg.allow_unstable)
    return esf_fail(
        err, ESF_EINPUT,
        "%s: dt = %.6g s exceeds the shortest drag relaxation time m (1 - eps) / "
        "(V beta) = %.6g s: the explicit drag would be inaccurate, and "
        "unstable above twice that. Lower dt, or check the fluid viscosity "
        "and porosity",
        esf_config_where(&s->cfg, "fluid"), s->dt, tau);
  return ESF_OK;
}

int esf_drag_prepare(esf_sim *s, const double *x, int *on_, esf_error *err) {
  esf_drag *d = s->drag;
  esf_particles *p = &s->p;
  if (d->cap < p->n) {
    free(d->f);
    d->f = malloc(3 * p->n * sizeof *d->f);
    if (!d->f) {
      d->cap = 0;
      return esf_fail(err, ESF_ENOMEM, "out of memory for fluid forces");
    }
    d->cap = p->n;
  }
  d->n = p->n;
  int on = s->t >= d->start;
  if (d->logged == 0 && s->step == 0 && s->log) {
    double tau = d->tau;
    esf_sim_log(
        s,
        "fluid: %s field from t = %.6g s, porosity %s%.4g%s, viscosity %.6g Pa s, "
        "density %.6g kg/m^3; shortest drag relaxation time %.6g s",
        d->kind == ESF_DRAG_RADIAL ? "radial" : "uniform", d->start,
        d->grid ? "from cells of about " : "", d->grid ? d->pg.h : d->porosity,
        d->grid ? " m" : "", d->mu, d->rho, tau);
    d->logged = 1;
  }
  if (on && d->logged < 2 && s->log) {
    esf_sim_log(s, "t = %.6g s (step %ld): fluid force on", s->t, s->step);
    if (s->walls.gforce) esf_servo_log_state(s);
    d->logged = 2;
  }
  if (on && d->grid) {
    int rc = d->update_porosity ? d->update_porosity(s, x, err)
                                : esf_porosity_update(&d->pg, p, x, s->cfg.dim,
                                                      s->cfg.disk_thickness, err);
    if (rc) return rc;
  }
  *on_ = on;
  return ESF_OK;
}

void esf_drag_particle(const esf_sim *s, int on, size_t i, const double x[3],
                       const double v[3], double F[3]) {
  const esf_drag *d = s->drag;
  v3_set(F, 0, 0, 0);
  double pr, gp[3], u[3];
  if (!on || !esf_drag_field(d, x, &pr, gp, u)) return;
  const double r = s->p.radius[i];
  const double vol = s->cfg.dim == 2 ? ESF_PI * r * r * s->cfg.disk_thickness
                                     : 4.0 / 3.0 * ESF_PI * r * r * r;
  double w[3];
  v3_sub(w, u, v);
  const double e = d->grid ? esf_porosity_at(&d->pg, x) : d->porosity;
  const double c = vol * esf_drag_beta(d, e, 2.0 * r, v3_norm(w)) / (1.0 - e);
  v3_scale(F, c, w);
  v3_axpy(F, -vol, gp);
}

int esf_drag_apply(esf_sim *s, const double *x, const double *v, esf_error *err) {
  int on;
  const int rc = esf_drag_prepare(s, x, &on, err);
  if (rc) return rc;
  esf_drag *d = s->drag;
  esf_particles *p = &s->p;
  double power = 0.0;
  for (size_t i = 0; i < p->n; i++) {
    double *F = d->f + 3 * i;
    esf_drag_particle(s, on, i, x + 3 * i, v + 3 * i, F);
    v3_add(p->f + 3 * i, p->f + 3 * i, F);
    power += v3_dot(F, v + 3 * i);
  }
  if (s->tally) s->tally->p_fluid += power;
  return ESF_OK;
}

void esf_drag_free(esf_drag **d) {
  if (!*d) return;
  free((*d)->f);
  esf_porosity_release(&(*d)->pg);
  free(*d);
  *d = NULL;
}
