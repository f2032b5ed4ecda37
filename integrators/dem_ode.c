/* dem_ode.c — the DEM right-hand side for ODE methods (see dem_ode.h for the layout and
 * the contact-history treatment). Units: SI; Q entries in J, their rates in W. */
#include "integrators/dem_ode.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "model/forces.h"
#include "model/model.h"
#include "util/vec3.h"

int esf_eval_forces(esf_eval_path *ep, esf_sim *s, const double *x, const double *v,
                    const double *w, double dt, int mode, size_t *touching,
                    const esf_eval_accel *ea, esf_error *err) {
  const char *why = esf_fused_eval_refusal(s, ep->ode);
  if (!why && !ep->fast) {
    int rc = esf_fused_create(&ep->fast, s->cfg.isa, err);
    if (rc) return rc;
  }
  if (!ep->logged || (why == NULL) != (ep->logged == 1)) { /* the path, when it changes */
    if (why)
      esf_sim_log(s,
                  "t = %.6g s: %s's force evaluations on the general path, one "
                  "thread (%s)",
                  s->t, ep->name, why);
    else
      esf_sim_log(s,
                  "t = %.6g s: %s's force evaluations on the fused step's kernels, "
                  "%s, %d threads",
                  s->t, ep->name, esf_fused_isa(ep->fast), s->cfg.threads);
    ep->logged = why ? 2 : 1;
  }
  ep->threads = 1;
  if (why) {
    const int rc = esf_forces_eval(s, x, v, w, dt, mode, touching, err);
    if (!rc && ea) esf_sim_accel(s, v, w, ea->acc, ea->dw, NULL, ea->with_global, 1);
    return rc;
  }
  const esf_fused_eval ev = {.x = x,
                             .v = v,
                             .w = w,
                             .dt = dt,
                             .trial = mode == ESF_FORCES_TRIAL,
                             .acc = ea ? ea->acc : NULL,
                             .dw = ea ? ea->dw : NULL,
                             .with_global = ea && ea->with_global,
                             .lazy = ea && ea->lazy};
  const int rc = esf_fused_forces(s, ep->fast, &ev, touching, err);
  ep->threads = esf_fused_threads(ep->fast);
  return rc;
}

void esf_eval_path_free(esf_eval_path *ep) { esf_fused_free(&ep->fast); }

void esf_dem_ode_free(esf_dem_ode *o) { esf_eval_path_free(&o->path); }

void esf_dem_ode_init(esf_dem_ode *o, esf_sim *s, const char *name) {
  memset(o, 0, sizeof *o);
  o->s = s;
  o->path.name = name;
  o->path.ode = 1;
  o->path.threads = 1;
  o->n = s->p.n;
  o->state = s->cfg.history == ESF_HIST_STATE;
  o->t_commit = s->t;
  /* frozen history keeps each contact's velocity at the commit (before the first
     build, so that the lists allocate it) */
  s->nb.carry = !o->state;
  o->nq = ESF_ODE_NQ + (s->mats.any_rolling ? 1 : 0); /* the rolling quadrature */
  esf_error_clear(&o->err);
  esf_dem_ode_layout(o);
}

size_t esf_dem_ode_layout(esf_dem_ode *o) {
  const esf_neighbor *nb = &o->s->nb;
  o->n = o->s->p.n; /* the refresh before the first build may have removed some */
  o->nxi = o->state ? 3 * (nb->pp.n + nb->pw.n) : 0;
  o->len = 9 * o->n + o->nq + o->nxi;
  return o->len;
}

static void pack_xi(const esf_candidates *c, double *xi) {
  for (size_t k = 0; k < c->n; k++)
    for (int q = 0; q < 3; q++) xi[3 * k + q] = c->touch[k] ? c->h[k].xi[q] : 0.0;
}

void esf_dem_ode_pack(const esf_dem_ode *o, const double *q, double *y) {
  const esf_sim *s = o->s;
  size_t n9 = 9 * o->n;
  memcpy(y, s->p.y, n9 * sizeof(double));
  for (size_t j = 0; j < o->nq; j++) y[n9 + j] = q ? q[j] : 0.0;
  if (!o->state) return;
  double *xi = y + n9 + o->nq;
  pack_xi(&s->nb.pp, xi);
  pack_xi(&s->nb.pw, xi + 3 * s->nb.pp.n);
}

/* Points the contact lists at the XI block of y (and of ydot, may be NULL). */
static void attach_xi(esf_dem_ode *o, const double *y, double *ydot) {
  esf_neighbor *nb = &o->s->nb;
  if (!o->state) return;
  size_t off = 9 * o->n + o->nq, npp = 3 * nb->pp.n;
  nb->pp.xs = y + off;
  nb->pw.xs = y + off + npp;
  nb->pp.xsdot = ydot ? ydot + off : NULL;
  nb->pw.xsdot = ydot ? ydot + off + npp : NULL;
  if (ydot) memset(ydot + off, 0, o->nxi * sizeof(double));
}

static void detach_xi(esf_dem_ode *o) {
  esf_neighbor *nb = &o->s->nb;
  nb->pp.xs = nb->pw.xs = NULL;
  nb->pp.xsdot = nb->pw.xsdot = NULL;
}

int esf_dem_ode_start(esf_dem_ode *o, const double *y, esf_error *err) {
  esf_sim *s = o->s;
  esf_ledger *L = &s->led;
  if (!L->on) return ESF_OK;
  size_t n = o->n;
  esf_force_tally ty = {0};
  s->tally = &ty;
  attach_xi(o, y, NULL);
  esf_walls_set_time(&s->walls, s->t);
  int rc = esf_forces_eval(s, y, y + 3 * n, y + 6 * n, 0.0, ESF_FORCES_TRIAL, NULL, err);
  detach_xi(o);
  s->tally = NULL;
  if (rc) return rc;
  esf_sim_energies(s, y, y + 3 * n, y + 6 * n, &L->kin_t, &L->kin_r, &L->pot_g);
  L->el_n = ty.e_el_n;
  L->el_t = ty.e_el_t;
  L->el_r = ty.e_el_r;
  o->el_t0 = ty.e_el_t;
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
  for (size_t q = 0; q < o->nq; q++) a[9 * o->n + q] = esf_dem_ode_qtol(o, rtol);
  for (size_t j = 0; j < o->nxi; j++) a[9 * o->n + o->nq + j] = atol; /* m */
}

void esf_sundials_silent(int code, const char *module, const char *function, char *msg,
                         void *data) {
  (void)code;
  (void)module;
  (void)function;
  (void)msg;
  (void)data;
}

int esf_dem_ode_periodic(const esf_sim *s, const char *name, esf_error *err) {
  if (s->cfg.per.any)
    return esf_fail(err, ESF_EINPUT,
                    "%s: domain.periodic: the ODE methods (%s) do not follow periodic "
                    "boundaries (the wrap into the box would jump the ODE state); use "
                    "the leapfrog or Verlet",
                    esf_config_where(&s->cfg, "domain"), name);
  return ESF_OK;
}

int esf_dem_ode_check(const esf_sim *s, const char *name, int state_ok, int roots_ok,
                      esf_error *err) {
  if (s->cfg.history == ESF_HIST_STATE && !state_ok)
    return esf_fail(err, ESF_EINPUT,
                    "%s: integrator.history: state (contact history as ODE state) is "
                    "available with the erk: methods only, not %s (CVODE cannot follow "
                    "a state whose length changes at every list rebuild; the leapfrog "
                    "and Verlet commit history every step)",
                    esf_config_where(&s->cfg, "integrator.history"), name);
  if (s->cfg.history == ESF_HIST_STATE && s->mats.any_rolling)
    return esf_fail(err, ESF_EINPUT,
                    "%s: integrator.history: state does not carry the rolling "
                    "resistance's springs; use history: frozen (the default) with "
                    "rolling_friction or twisting_friction",
                    esf_config_where(&s->cfg, "integrator.history"));
  if (s->cfg.roots && !roots_ok)
    return esf_fail(err, ESF_EINPUT,
                    "%s: integrator.roots: rootfinding at contact onset and separation "
                    "is available with the adaptive erk: methods only (rtol > 0), not %s",
                    esf_config_where(&s->cfg, "integrator.roots"), name);
  return ESF_OK;
}

/* The rest of f(t, y) after the forces: the velocities, the accelerations with the
 * ledger (pd its damping powers), the non-finite test and the quadratures from ty. */
static int rhs_finish(esf_dem_ode *o, double t, const double *y, double *ydot,
                      const esf_force_tally *tyc);

int esf_dem_ode_rhs(esf_dem_ode *o, double t, const double *y, double *ydot) {
  esf_sim *s = o->s;
  size_t n = o->n;
  const double *x = y, *v = y + 3 * n, *w = y + 6 * n;
  esf_force_tally ty = {0};
  s->tally = s->led.on ? &ty : NULL; /* the quadratures only feed the ledger */
  attach_xi(o, y, ydot);
  esf_walls_set_time(&s->walls, t);
  /* the accelerations with the forces (without the ledger: its powers are below) */
  const esf_eval_accel ea = {ydot + 3 * n, ydot + 6 * n, 1, 0};
  int rc = esf_eval_forces(&o->path, s, x, v, w, t - o->t_commit, ESF_FORCES_TRIAL, NULL,
                           s->led.on ? NULL : &ea, &o->err);
  detach_xi(o);
  s->tally = NULL;
  o->nrhs++;
  if (rc) {
    o->nfail++;
    return 1;
  }
  return rhs_finish(o, t, y, ydot, &ty);
}

/* A commit's bookkeeping at t (both commits: esf_dem_ode_commit, the merged one). */
static void commit_book(esf_dem_ode *o, double t, size_t touching) {
  esf_sim *s = o->s;
  o->t_commit = t;
  s->t = t;
  s->led_time = t;
  s->contacts_sum += (double)touching;
}

int esf_dem_ode_rhs_commit(esf_dem_ode *o, double t, const double *y, double *ydot) {
  esf_sim *s = o->s;
  const size_t n = o->n;
  if (!esf_dem_ode_can_merge(o)) return -1;
  memcpy(s->p.y, y, 9 * n * sizeof(double));
  size_t touching = 0;
  esf_walls_set_time(&s->walls, t);
  const esf_eval_accel ea = {ydot + 3 * n, ydot + 6 * n, 1, 0};
  int rc = esf_eval_forces(&o->path, s, s->p.x, s->p.v, s->p.w, t - o->t_commit,
                           ESF_FORCES_COMMIT, &touching, &ea, &o->err);
  o->nrhs++;
  if (rc) {
    o->nfail++;
    return 1;
  }
  const esf_force_tally ty = {0};
  rc = rhs_finish(o, t, y, ydot, &ty);
  if (!rc) commit_book(o, t, touching); /* (no ledger to book) */
  return rc;
}

int esf_dem_ode_can_merge(const esf_dem_ode *o) { return !o->state && !o->s->led.on; }

static int rhs_finish(esf_dem_ode *o, double t, const double *y, double *ydot,
                      const esf_force_tally *tyc) {
  esf_sim *s = o->s;
  const size_t n = o->n;
  const double *v = y + 3 * n, *w = y + 6 * n;
  const esf_force_tally ty = *tyc;
  memcpy(ydot, v, 3 * n * sizeof(double));
  double pd[2] = {0, 0};
  if (s->led.on)
    esf_sim_accel(s, v, w, ydot + 3 * n, ydot + 6 * n, pd, 1, o->path.threads);
  /* orientations are not tracked: spheres need only w. Non-finite: all exponent bits
     set; one vectorised pass tests them, the search runs only when one is */
  const uint64_t expo = 0x7ff0000000000000u;
  int bad = 0;
  for (size_t j = 3 * n; j < 9 * n; j++) {
    uint64_t u;
    memcpy(&u, ydot + j, sizeof u);
    bad |= (u & expo) == expo;
  }
  for (size_t j = 3 * n; j < 9 * n && bad; j++)
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
  q[ESF_ODE_QF] = ty.p_spring_t;
  q[ESF_ODE_QFL] = ty.p_fluid;
  q[ESF_ODE_QS] = ty.p_stiff;
  if (o->nq > ESF_ODE_NQ) q[ESF_ODE_QR] = ty.p_rolling;
  return 0;
}

int esf_dem_ode_commit(esf_dem_ode *o, double t, const double *y, esf_error *err) {
  esf_sim *s = o->s;
  size_t n = o->n;
  memcpy(s->p.y, y, 9 * n * sizeof(double));
  esf_force_tally ty = {0};
  s->tally = s->led.on ? &ty : NULL; /* read by the ledger only (none: the fast walls) */
  size_t touching = 0;
  attach_xi(o, y, NULL);
  esf_walls_set_time(&s->walls, t);
  int rc = esf_eval_forces(&o->path, s, s->p.x, s->p.v, s->p.w, t - o->t_commit,
                           ESF_FORCES_COMMIT, &touching, NULL, err);
  detach_xi(o);
  s->tally = NULL;
  o->ncommit++;
  if (rc) return rc;
  commit_book(o, t, touching);
  esf_ledger *L = &s->led;
  if (L->on) {
    const double *q = y + 9 * n;
    esf_sim_energies(s, s->p.x, s->p.v, s->p.w, &L->kin_t, &L->kin_r, &L->pot_g);
    L->el_n = ty.e_el_n;
    L->el_t = ty.e_el_t;
    L->d_normal = q[ESF_ODE_QN];
    L->d_tangential = q[ESF_ODE_QT];
    L->d_global = q[ESF_ODE_QG];
    L->d_local = q[ESF_ODE_QL];
    L->w_walls = q[ESF_ODE_QW];
    L->w_fluid = q[ESF_ODE_QFL];
    if (o->nq > ESF_ODE_NQ) { /* rolling: dashpots and torques, plus plastic work */
      o->slip_r += ty.slip_r;
      L->el_r = ty.e_el_r;
      L->d_rolling = q[ESF_ODE_QR] + o->slip_r;
    }
    if (o->state) { /* work into the springs less what they hold (the returns
                       included), and the Hertz springs' stiffness changes; frozen
                       history: the commits book them (forces.c) */
      L->w_stiff = q[ESF_ODE_QS];
      L->d_friction = q[ESF_ODE_QF] + q[ESF_ODE_QS] - (L->el_t - o->el_t0);
    }
  }
  return ESF_OK;
}
