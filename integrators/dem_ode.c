/* dem_ode.c — the DEM right-hand side for ODE methods (see dem_ode.h for the layout and
 * the contact-history treatment). Units: SI; Q entries in J, their rates in W. */
#include "dem_ode.h"

#include <math.h>
#include <string.h>

#include "forces.h"
#include "integ_common.h"
#include "vec3.h"

void esf_dem_ode_init(esf_dem_ode *o, esf_sim *s, double *y0) {
  memset(o, 0, sizeof *o);
  o->s = s;
  o->n = s->p.n;
  o->len = 9 * o->n + ESF_ODE_NQ;
  o->t_commit = s->t;
  s->nb.carry =
      1; /* keep each contact's velocity at the commit (before the first build) */
  memcpy(y0, s->p.y, 9 * o->n * sizeof(double));
  memset(y0 + 9 * o->n, 0, ESF_ODE_NQ * sizeof(double));
  esf_error_clear(&o->err);
}

int esf_dem_ode_start(esf_dem_ode *o, const double *y, esf_error *err) {
  esf_sim *s = o->s;
  esf_ledger *L = &s->led;
  if (!L->on) return ESF_OK;
  size_t n = o->n;
  esf_force_tally ty;
  s->tally = &ty;
  int rc = esf_forces_eval(s, y, y + 3 * n, y + 6 * n, 0.0, ESF_FORCES_TRIAL, NULL, err);
  s->tally = NULL;
  if (rc) return rc;
  esf_integ_energies(s, y, y + 3 * n, y + 6 * n, &L->kin_t, &L->kin_r, &L->pot_g);
  L->el_n = ty.e_el_n;
  L->el_t = ty.e_el_t;
  L->e0 = esf_ledger_stored(L);
  L->started = 1;
  return ESF_OK;
}

double esf_dem_ode_qtol(const esf_dem_ode *o, double rtol) {
  const esf_ledger *L = &o->s->led;
  if (!L->on) return 1e300; /* no ledger: the quadratures are not needed */
  double scale = fabs(L->e0) + L->kin_t + L->kin_r + L->el_n + L->el_t;
  return scale > 0 ? rtol * scale : 1e300;
}

void esf_dem_ode_atol(const esf_dem_ode *o, double *a, double rtol, double atol) {
  for (size_t j = 0; j < 9 * o->n; j++) a[j] = atol;
  for (int q = 0; q < ESF_ODE_NQ; q++) a[9 * o->n + q] = esf_dem_ode_qtol(o, rtol);
}

void esf_sundials_silent(int code, const char *module, const char *function, char *msg,
                         void *data) {
  (void)code;
  (void)module;
  (void)function;
  (void)msg;
  (void)data;
}

int esf_dem_ode_check(const esf_sim *s, esf_error *err) {
  if (s->cfg.history == ESF_HIST_STATE)
    return esf_fail(err, ESF_EINPUT,
                    "integrator.history: state (contact history integrated as ODE state) "
                    "is not available in this version; use frozen");
  return ESF_OK;
}

int esf_dem_ode_rhs(esf_dem_ode *o, double t, const double *y, double *ydot) {
  esf_sim *s = o->s;
  size_t n = o->n;
  const double *x = y, *v = y + 3 * n, *w = y + 6 * n;
  esf_force_tally ty = {0};
  s->tally = s->led.on ? &ty : NULL; /* the quadratures only feed the ledger */
  int rc = esf_forces_eval(s, x, v, w, t - o->t_commit, ESF_FORCES_TRIAL, NULL, &o->err);
  s->tally = NULL;
  o->nrhs++;
  if (rc) {
    o->nfail++;
    return 1;
  }
  memcpy(ydot, v, 3 * n * sizeof(double));
  double pd[2] = {0, 0};
  esf_integ_accel(s, v, w, ydot + 3 * n, ydot + 6 * n, s->led.on ? pd : NULL, 1);
  /* orientations are not tracked: spheres need only w */
  for (size_t j = 3 * n; j < 9 * n; j++)
    if (!isfinite(ydot[j])) {
      size_t i = (j % (3 * n)) / 3;
      o->nfail++;
      esf_fail(&o->err, ESF_ENUMERIC,
               "t = %.6g s: particle id %lld has a non-finite acceleration", t,
               (long long)s->p.id[i]);
      return 1;
    }
  double *q = ydot + 9 * n;
  q[ESF_ODE_QN] = ty.p_normal;
  q[ESF_ODE_QT] = ty.p_tangential;
  q[ESF_ODE_QG] = pd[0];
  q[ESF_ODE_QL] = pd[1];
  q[ESF_ODE_QW] = ty.p_walls;
  return 0;
}

int esf_dem_ode_commit(esf_dem_ode *o, double t, const double *y, esf_error *err) {
  esf_sim *s = o->s;
  size_t n = o->n;
  memcpy(s->p.y, y, 9 * n * sizeof(double));
  esf_force_tally ty;
  s->tally = &ty;
  size_t touching = 0;
  int rc = esf_forces_eval(s, s->p.x, s->p.v, s->p.w, t - o->t_commit, ESF_FORCES_COMMIT,
                           &touching, err);
  s->tally = NULL;
  o->ncommit++;
  if (rc) return rc;
  o->t_commit = t;
  s->t = t;
  s->led_time = t;
  s->contacts_sum += (double)touching;
  esf_ledger *L = &s->led;
  if (L->on) {
    const double *q = y + 9 * n;
    esf_integ_energies(s, s->p.x, s->p.v, s->p.w, &L->kin_t, &L->kin_r, &L->pot_g);
    L->el_n = ty.e_el_n;
    L->el_t = ty.e_el_t;
    L->d_normal = q[ESF_ODE_QN];
    L->d_tangential = q[ESF_ODE_QT];
    L->d_global = q[ESF_ODE_QG];
    L->d_local = q[ESF_ODE_QL];
    L->w_walls = q[ESF_ODE_QW];
  }
  return ESF_OK;
}
