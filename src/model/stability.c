/* stability.c — the live stability check (stability.h; docs/physics.md#live-stability-
 * check).
 *
 * The leapfrog's dashpots see v_{n-1/2} and its global damping is centred, so for the
 * linearised contact network x_{n+1} - 2 x_n + x_{n-1} + dt B (x_n - x_{n-1})
 * + dt^2 A x_n = 0 (mass-scaled, centred damping dropped). Its discrete energy
 * d^T (I - dt B/2 - dt^2 A/4) d + (dt^2/4) s^T A s (d = x_{n+1} - x_n, s = x_{n+1} +
 * x_n) never grows, and is positive definite exactly when lambda_max(dt^2 A + 2 dt B)
 * < 4: for a single mode this is dt < (2/omega)(sqrt(1 + xi^2) - xi) (001 3.66).
 * lambda_max comes from Lanczos on the operator applied contact by contact (no matrix):
 * a deterministic start vector, the tridiagonal's top Ritz value every 4 steps, stopped
 * when its residual bound is below 1e-3 of it. Springs are the linear law's kn and the
 * sticking kt (an adhesive pair's largest bonded tangent stiffness; the Hertz-Mindlin
 * law's tangent stiffnesses S_n = 2 E* a, S_t = 8 G* a at the current overlap,
 * a = sqrt(R* u)), dashpots as the law
 * has them, lever arms to the contact point, as in `esfera modes` (app/modes.c, which
 * assembles the same esf_stab_contact_apply densely); the turning normal's geometric
 * stiffness is neglected. Touching: overlap > 0, or bonded; a contact at its Coulomb
 * cap (or frictionless) has no tangential spring or dashpot. Rolling resistance (epsd):
 * its rotational springs and dashpots (esf_stab_roll_apply), elastic also at the limit.
 * Units: SI. Entry: a set-up sim with its candidate lists built; nothing is changed. */
#include "model/stability.h"

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_matrix.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bodies/wall_geom.h"
#include "contact/contact_rolling.h"
#include "contact/lane_scalar.h"
#include "model/forces.h"
#include "util/clock.h"
#include "util/vec3.h"

#define LZ_MAX   120  /* Lanczos steps at most */
#define LZ_EVERY 4    /* steps between tridiagonal solves */
#define LZ_TOL   1e-3 /* residual bound / Ritz value to stop */

void esf_stab_springs(const esf_pair_params *pp, double beta, double mstar, double rstar,
                      double un, double kc[4]) {
  if (pp->law == &esf_contact_hertz) { /* tangent stiffnesses at un (contact_hertz.h) */
    double ks, qa, sm = sqrt(mstar);
    esf_law_hertz_springs_s(pp->hn, pp->ht, rstar, fmax(un, 0.0), &ks, &kc[0], &kc[1],
                            &qa);
    if (pp->hertz_constant) qa = esf_law_hertz_qref_s(pp->estar, sm, rstar, pp->v_imp);
    esf_law_hertz_dashpots_s(beta, pp->cn_factor, pp->ct_factor, sm, qa, kc[0], kc[1],
                             &kc[2], &kc[3]);
    return;
  }
  double kn = pp->law->flags & ESF_LAW_TENSION ? pp->adh.k_max : pp->kn;
  kc[0] = kn;
  kc[1] = pp->kt;
  kc[2] = beta > 0 ? beta * pp->kn : pp->cn_factor * sqrt(mstar); /* as the laws */
  kc[3] = beta > 0 ? beta * pp->kt : pp->ct_factor * sqrt(mstar);
}

static int pair_geometry(const esf_sim *s, size_t k, double n[3], double *la,
                         double *lb) {
  const esf_particles *p = &s->p;
  const esf_candidates *c = &s->nb.pp;
  uint32_t a = c->a[k], b = c->b[k];
  double d[3], rs = p->radius[a] + p->radius[b], xb[3];
  v3_sub(d, esf_candidates_xb(c, k, p->x, xb), p->x + 3 * a);
  double d2 = v3_norm2(d);
  if (!(d2 < rs * rs) && !(c->touch[k] && esf_candidates_bonded(c, k))) return 0;
  double dist = sqrt(d2), un = rs - dist;
  if (!(dist > 0)) return 0;
  v3_scale(n, 1.0 / dist, d);
  *la = p->radius[a] - 0.5 * un;
  *lb = p->radius[b] - 0.5 * un;
  return 1;
}

/* The tangential terms of a linear-law contact (law_body.h): none when its cap
 * coh + mu fn is zero or less (frictionless); at the cap at its last commit (kt |xi|
 * there, with the elastic normal force kn u) sliding, the unit slip direction in *t
 * (xi brought into the current tangent plane). */
static void tangential(const esf_pair_params *pp, const esf_contact_hist *h, int live,
                       double un, const double n[3], esf_stab_contact *c) {
  c->slip = 0;
  if (pp->law->flags & ESF_LAW_TENSION) return;
  const int hz = pp->law == &esf_contact_hertz; /* fel (2/3) S_n u; xi the force */
  double tau = pp->cohesion + pp->mu * (hz ? c->kc[0] / 1.5 : pp->kn) * un;
  if (tau <= 0) {
    c->kc[1] = c->kc[3] = 0.0;
    return;
  }
  double xi = live ? v3_norm(h->xi) : 0.0;
  if (!((hz ? 1.0 : pp->kt) * xi >= (1 - 1e-9) * tau)) return;
  double s = v3_dot(h->xi, n), t[3], m;
  for (int q = 0; q < 3; q++) t[q] = h->xi[q] - s * n[q];
  m = v3_norm(t);
  if (!(m > 0)) return;
  v3_scale(c->t, 1.0 / m, t);
  c->slip = 1;
}

/* The rolling resistance's springs and dashpots of a contact (esf_law_rolling_par with
 * R* and the inertias of esf_law_rolling_pair; a wall, b < 0: rA, IA + mA rA^2, IA as
 * forces.c; kn at overlap un: esf_contact_rolling_kn), epsd only: cdt's constant
 * torque has no stiffness. */
static void roll_springs(const esf_sim *s, const esf_pair_params *par, size_t a, long b,
                         double un, esf_stab_contact *c) {
  const esf_particles *p = &s->p;
  c->roll = s->mats.any_rolling && s->mats.rolling_model == ESF_ROLL_EPSD;
  if (!c->roll) return;
  double rs, ir, itw, ra = p->radius[a], ia = p->inertia[a];
  if (b >= 0)
    esf_law_rolling_pair_s(ra, p->radius[b], p->mass[a], p->mass[b], ia, p->inertia[b],
                           &rs, &ir, &itw);
  else
    rs = ra, ir = ia + p->mass[a] * ra * ra, itw = ia;
  esf_law_rpar_s P;
  esf_law_rolling_par_s(esf_contact_rolling_kn(par, rs, un), par->mu_r, par->mu_tw,
                        par->eta_r, rs, ir, itw, 1.0, 0, &P);
  c->kr[0] = P.kr;
  c->kr[1] = P.ktw;
  c->kr[2] = P.cr;
  c->kr[3] = P.ctw;
}

size_t esf_stab_contacts(const esf_sim *s, esf_stab_visit fn, void *ctx) {
  const esf_particles *p = &s->p;
  const esf_materials *mt = &s->mats;
  const esf_candidates *pp = &s->nb.pp, *pw = &s->nb.pw;
  esf_stab_contact c;
  size_t cnt = 0;
  for (size_t k = 0; k < pp->n; k++) {
    if (!pair_geometry(s, k, c.n, &c.la, &c.lb)) continue;
    c.a = pp->a[k];
    c.b = pp->b[k];
    const esf_pair_params *par = &mt->pair[p->material[c.a] * mt->n + p->material[c.b]];
    const double ra = p->radius[c.a], rb = p->radius[c.b];
    const double u = ra - c.la + rb - c.lb;
    esf_stab_springs(par, s->beta,
                     p->mass[c.a] * p->mass[c.b] / (p->mass[c.a] + p->mass[c.b]),
                     ra * rb / (ra + rb), u, c.kc);
    tangential(par, &pp->h[k], pp->touch[k], u, c.n, &c);
    roll_springs(s, par, c.a, c.b, u, &c);
    fn(&c, ctx);
    cnt++;
  }
  /* the wall contacts of one particle at a time, those that carry force (forces.c's
     choice among hits on shared mesh edges and vertices) */
  enum { MAXH = 32 };
  esf_wall_hit hits[MAXH];
  double un[MAXH];
  uint32_t elem[MAXH];
  size_t kk[MAXH];
  unsigned char keep[MAXH];
  for (size_t k0 = 0, k1; k0 < pw->n; k0 = k1) {
    const uint32_t a = pw->a[k0];
    size_t m = 0;
    for (k1 = k0; k1 < pw->n && pw->a[k1] == a; k1++) {
      esf_wall_hit h;
      esf_wall_nearest(&s->walls.e[pw->b[k1]], p->x + 3 * (size_t)a, &h);
      if (!(h.dist < p->radius[a]) || m == MAXH) continue; /* beyond MAXH: ignored */
      hits[m] = h;
      un[m] = p->radius[a] - h.dist;
      elem[m] = pw->b[k1];
      kk[m++] = k1;
    }
    if (m == 0) continue;
    esf_forces_select_wall_hits(&s->walls, elem, hits, un, m, p->radius[a], keep);
    for (size_t j = 0; j < m; j++) {
      if (!keep[j]) continue;
      c.a = a;
      c.b = -1;
      v3_copy(c.n, hits[j].n);
      c.la = esf_wall_lever(s->cfg.wall_lever, p->radius[a], un[j], hits[j].dist);
      c.lb = 0.0;
      const esf_pair_params *par =
          &mt->pair[p->material[a] * mt->n + s->walls.e[elem[j]].material];
      esf_stab_springs(par, s->beta, p->mass[a], p->radius[a], un[j], c.kc);
      tangential(par, &pw->h[kk[j]], pw->touch[kk[j]], un[j], c.n, &c);
      roll_springs(s, par, a, -1, un[j], &c);
      fn(&c, ctx);
      cnt++;
    }
  }
  return cnt;
}

/* The operator: y += (sum over touching contacts G^T (ck S_K + cc S_C) G) x on 6
 * coordinates per particle, the contacts (esf_stab_contacts) recomputed from the state
 * at each application (no storage per contact). Lanczos runs on M^{-1} K' in the M
 * inner product (the spectrum of M^{-1/2} K' M^{-1/2}, without scaled copies); mass()
 * gives M's diagonal, 0 on frozen coordinates (2D: y and the rotations about x and z),
 * and minv() its inverse with the same zeros. */
typedef struct op {
  esf_sim *s;
  double ck, cc; /* weights of the springs and the dashpots */
  const double *x;
  double *y;
  size_t contacts;
} op;

static const int free2[6] = {1, 0, 1, 0, 1, 0};

static inline double minv(const esf_sim *s, size_t i, int j) {
  if (s->cfg.dim != 3 && !free2[j]) return 0.0;
  return j < 3 ? s->p.inv_mass[i] : s->p.inv_inertia[i];
}

static inline double mass(const esf_sim *s, size_t i, int j) {
  if (!(minv(s, i, j) > 0)) return 0.0;
  return j < 3 ? s->p.mass[i] : s->p.inertia[i];
}

static void apply_one(const esf_stab_contact *c, void *ctx) {
  op *o = ctx;
  const int wall = c->b < 0;
  esf_stab_contact_apply(c->n, c->slip ? c->t : NULL, c->la, c->lb,
                         o->ck * c->kc[0] + o->cc * c->kc[2],
                         o->ck * c->kc[1] + o->cc * c->kc[3], o->x + 6 * c->a,
                         wall ? NULL : o->x + 6 * (size_t)c->b, o->y + 6 * c->a,
                         wall ? NULL : o->y + 6 * (size_t)c->b);
  if (c->roll)
    esf_stab_roll_apply(c->n, o->ck * c->kr[0] + o->cc * c->kr[2],
                        o->ck * c->kr[1] + o->cc * c->kr[3], o->x + 6 * c->a,
                        wall ? NULL : o->x + 6 * (size_t)c->b, o->y + 6 * c->a,
                        wall ? NULL : o->y + 6 * (size_t)c->b);
}

static void op_apply(op *o, const double *x, double *y) {
  o->x = x;
  o->y = y;
  o->contacts = esf_stab_contacts(o->s, apply_one, o);
}

/* the M inner product */
static double dot(const op *o, const double *a, const double *b, size_t nd) {
  double r = 0;
  for (size_t j = 0; j < nd; j++) r += mass(o->s, j / 6, (int)(j % 6)) * a[j] * b[j];
  return r;
}

/* the deterministic start: a hash of the coordinate's index on the free coordinates */
static void start_vector(const op *o, double *v, size_t nd) {
  for (size_t j = 0; j < nd; j++) {
    uint64_t h = (uint64_t)j * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull;
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 29;
    v[j] = minv(o->s, j / 6, (int)(j % 6)) > 0 ? (double)(h >> 11) * 0x1p-53 - 0.5 : 0.0;
  }
  double nv = sqrt(dot(o, v, v, nd));
  for (size_t j = 0; j < nd; j++) v[j] = nv > 0 ? v[j] / nv : 0.0;
}

/* Top eigenpair of the m x m tridiagonal (al, be): its value, and s (m) */
static int tridiag_top(const double *al, const double *be, int m, double *theta,
                       double *s) {
  gsl_matrix *T = gsl_matrix_calloc((size_t)m, (size_t)m);
  gsl_matrix *V = gsl_matrix_alloc((size_t)m, (size_t)m);
  gsl_vector *e = gsl_vector_alloc((size_t)m);
  gsl_eigen_symmv_workspace *w = gsl_eigen_symmv_alloc((size_t)m);
  int ok = T && V && e && w;
  if (ok) {
    for (int j = 0; j < m; j++) {
      gsl_matrix_set(T, (size_t)j, (size_t)j, al[j]);
      if (j + 1 < m) {
        gsl_matrix_set(T, (size_t)j, (size_t)j + 1, be[j + 1]);
        gsl_matrix_set(T, (size_t)j + 1, (size_t)j, be[j + 1]);
      }
    }
    gsl_eigen_symmv(T, e, V, w);
    size_t top = gsl_vector_max_index(e);
    *theta = gsl_vector_get(e, top);
    for (int j = 0; j < m; j++) s[j] = gsl_matrix_get(V, (size_t)j, top);
  }
  if (w) gsl_eigen_symmv_free(w);
  gsl_vector_free(e);
  gsl_matrix_free(V);
  gsl_matrix_free(T);
  return ok ? ESF_OK : ESF_ENOMEM;
}

/* Lanczos with two vectors (Paige's form: u <- A v - beta u, alpha = u.v, u -= alpha
 * v, then the two swap roles): the recurrence from the start vector; when y is not
 * NULL, the second pass that sums the Ritz vector y = sum s_j v_j of the first pass's
 * m steps. */
static int lanczos(op *o, double *u, double *v, size_t nd, double *al, double *be, int *m,
                   double *theta, double *s, double *y) {
  int second = y != NULL, mm = second ? *m : LZ_MAX;
  memset(u, 0, nd * sizeof *u);
  start_vector(o, v, nd);
  if (y) memset(y, 0, nd * sizeof *y);
  if (!second) be[0] = 0;
  for (int j = 0; j < mm; j++) {
    if (y)
      for (size_t q = 0; q < nd; q++) y[q] += s[j] * v[q];
    if (second && j + 1 == mm) break;
    /* u = M^{-1} (K' v - beta_j M u): the contacts add into M times the old term */
    for (size_t q = 0; q < nd; q++) u[q] *= -be[j] * mass(o->s, q / 6, (int)(q % 6));
    op_apply(o, v, u);
    for (size_t q = 0; q < nd; q++) u[q] *= minv(o->s, q / 6, (int)(q % 6));
    if (!second) al[j] = dot(o, u, v, nd);
    for (size_t q = 0; q < nd; q++) u[q] -= al[j] * v[q];
    double b = second ? be[j + 1] : sqrt(dot(o, u, u, nd));
    if (!second) {
      be[j + 1] = b;
      int last = j + 1 == mm || !(b > 1e-14 * fabs(al[j]));
      if (last || (j + 1) % LZ_EVERY == 0) {
        int rc = tridiag_top(al, be, j + 1, theta, s);
        if (rc) return rc;
        *m = j + 1;
        if (last || b * fabs(s[j]) <= LZ_TOL * fabs(*theta)) return ESF_OK;
      }
    }
    if (!(b > 0)) break;
    for (size_t q = 0; q < nd; q++) { /* (u, v) <- (v, u / b) */
      double t = u[q] / b;
      u[q] = v[q];
      v[q] = t;
    }
  }
  return ESF_OK;
}

/* The energy y.G^T S G.y of each contact in the mode y; the largest names the mode. */
typedef struct share {
  const double *y;
  double best;
  size_t a;
  long b;
} share;

static void share_one(const esf_stab_contact *c, void *ctx) {
  share *h = ctx;
  const int wall = c->b < 0;
  double ya[6] = {0}, yb[6] = {0}, e = 0;
  const double *xa = h->y + 6 * c->a, *xb = wall ? NULL : h->y + 6 * (size_t)c->b;
  esf_stab_contact_apply(c->n, c->slip ? c->t : NULL, c->la, c->lb, c->kc[0], c->kc[1],
                         xa, xb, ya, wall ? NULL : yb);
  if (c->roll)
    esf_stab_roll_apply(c->n, c->kr[0], c->kr[1], xa, xb, ya, wall ? NULL : yb);
  for (int j = 0; j < 6; j++) e += xa[j] * ya[j] + (wall ? 0.0 : xb[j] * yb[j]);
  if (e > h->best) h->best = e, h->a = c->a, h->b = c->b;
}

/* The top mode of the Ritz vector y (unit in M): frequency, damping ratio, the step at
 * which it reaches 4 with the local damping factor fl, and the contact that stores most
 * of its energy; w is scratch. */
static void top_mode(op *o, const double *y, double *w, size_t nd, double fl,
                     esf_stability *out) {
  const esf_sim *s = o->s;
  o->ck = 1, o->cc = 0; /* a = y.K.y, b = y.C.y */
  memset(w, 0, nd * sizeof *w);
  op_apply(o, y, w);
  double a = 0, b = 0;
  for (size_t q = 0; q < nd; q++) a += y[q] * w[q];
  o->ck = 0, o->cc = 1;
  memset(w, 0, nd * sizeof *w);
  op_apply(o, y, w);
  for (size_t q = 0; q < nd; q++) b += y[q] * w[q];
  out->omega = a > 0 ? sqrt(a) : 0.0;
  out->xi = a > 0 ? b / (2 * out->omega) : 0.0;
  /* fl (dt^2 a + 2 dt b) = 4 */
  out->dt_limit = a > 0 ? (-b + sqrt(b * b + 4 * a / fl)) / a : INFINITY;
  share h = {.y = y, .best = -1};
  esf_stab_contacts(s, share_one, &h);
  if (h.best >= 0) {
    out->id = s->p.id[h.a];
    out->other = h.b >= 0 ? s->p.id[h.b] : -1;
  }
}

int esf_stability_estimate(esf_sim *s, double dt, int with_mode, esf_stability *out,
                           esf_error *err) {
  size_t nd = 6 * s->p.n;
  *out = (esf_stability){.id = -1, .other = -2, .dt_limit = INFINITY};
  if (nd == 0) return ESF_OK;
  /* two vectors, a third for the top mode's second pass (48 bytes a particle each) */
  double *buf = malloc((with_mode ? 3 : 2) * nd * sizeof *buf);
  double *al = malloc((2 * (LZ_MAX + 2) + LZ_MAX) * sizeof *al);
  if (!buf || !al) {
    free(buf), free(al);
    return esf_fail(err, ESF_ENOMEM, "stability check: out of memory for %zu particles",
                    s->p.n);
  }
  double *be = al + LZ_MAX + 2, *sv = be + LZ_MAX + 2, *u = buf, *v = buf + nd;
  const double fl = s->local ? 1.0 + s->cfg.local_coef : 1.0;
  op o = {.s = s, .ck = fl * dt * dt, .cc = fl * 2.0 * dt};
  int m = 0;
  double theta = 0;
  int rc = lanczos(&o, u, v, nd, al, be, &m, &theta, sv, NULL);
  out->lambda = theta > 0 ? theta : 0.0;
  out->iters = m;
  out->contacts = o.contacts;
  if (!rc && with_mode && o.contacts > 0 && m > 0) {
    double *y = buf + 2 * nd;
    rc = lanczos(&o, u, v, nd, al, be, &m, &theta, sv, y); /* regenerates the v_j */
    double ny = sqrt(dot(&o, y, y, nd));
    for (size_t q = 0; q < nd && ny > 0; q++) y[q] /= ny;
    if (!rc) top_mode(&o, y, u, nd, fl, out);
  }
  free(buf);
  free(al);
  return rc;
}

int esf_stability_limit(esf_sim *s, double *dt_limit, esf_stability *top,
                        esf_error *err) {
  double dt = s->dt > 0 ? s->dt : 1.0;
  *dt_limit = INFINITY;
  for (int it = 0; it < 30; it++) {
    int rc = esf_stability_estimate(s, dt, 1, top, err);
    if (rc) return rc;
    if (!isfinite(top->dt_limit)) return ESF_OK;
    double prev = dt;
    dt = top->dt_limit;
    if (fabs(dt - prev) <= 1e-6 * dt) break;
  }
  *dt_limit = dt;
  return ESF_OK;
}
