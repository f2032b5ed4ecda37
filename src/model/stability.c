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
 * sticking kt (an adhesive pair's largest bonded tangent stiffness), dashpots as the law
 * has them, lever arms to the contact point, as in `esfera modes` (app/modes.c, which
 * assembles the same esf_stab_contact_apply densely); the turning normal's geometric
 * stiffness is neglected. Touching: overlap > 0, or bonded; a contact at its Coulomb
 * cap (or frictionless) has no tangential spring or dashpot.
 * Units: SI. Entry: a set-up sim with its candidate lists built; nothing is changed. */
#include "model/stability.h"

#include <gsl/gsl_eigen.h>
#include <gsl/gsl_matrix.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bodies/wall_geom.h"
#include "util/clock.h"
#include "util/vec3.h"

#define LZ_MAX   120  /* Lanczos steps at most */
#define LZ_EVERY 4    /* steps between tridiagonal solves */
#define LZ_TOL   1e-3 /* residual bound / Ritz value to stop */

void esf_stab_contact_apply(const double n[3], double la, double lb, double kn, double kt,
                            const double *xa, const double *xb, double *ya, double *yb) {
  /* the contact point's relative motion dc = dxB + lb n x dthB - dxA + la n x dthA */
  double dc[3], c[3];
  v3_cross(c, n, xa + 3);
  for (int q = 0; q < 3; q++) dc[q] = la * c[q] - xa[q];
  if (xb) {
    v3_cross(c, n, xb + 3);
    for (int q = 0; q < 3; q++) dc[q] += xb[q] + lb * c[q];
  }
  /* f = S dc, then G^T f: -f and la f x n on A, f and lb f x n on B */
  double dn = v3_dot(n, dc), f[3];
  for (int q = 0; q < 3; q++) f[q] = kt * dc[q] + (kn - kt) * dn * n[q];
  v3_cross(c, f, n);
  for (int q = 0; q < 3; q++) {
    ya[q] -= f[q];
    ya[3 + q] += la * c[q];
  }
  if (xb)
    for (int q = 0; q < 3; q++) {
      yb[q] += f[q];
      yb[3 + q] += lb * c[q];
    }
}

void esf_stab_springs(const esf_pair_params *pp, double beta, double mstar,
                      double kc[4]) {
  double kn = pp->law->flags & ESF_LAW_TENSION ? pp->adh.k_max : pp->kn;
  kc[0] = kn;
  kc[1] = pp->kt;
  kc[2] = beta > 0 ? beta * kn : pp->cn_factor * sqrt(mstar);
  kc[3] = beta > 0 ? beta * pp->kt : pp->ct_factor * sqrt(mstar);
}

/* The network: each touching contact's bodies (b = NONE: a wall), unit normal, lever
 * arms, springs and dashpots (stability.h's kn, kt, cn, ct), gathered once per estimate
 * (ESF_STAB_REC doubles each). */
#define NONE          UINT32_MAX
#define ESF_STAB_REC  9
typedef struct net {
  size_t n;
  uint32_t *ab; /* 2 per contact */
  double *g;    /* n[3], la, lb, kn, kt, cn, ct */
} net;

static int pair_geometry(const esf_sim *s, size_t k, double n[3], double *la,
                         double *lb) {
  const esf_particles *p = &s->p;
  const esf_candidates *c = &s->nb.pp;
  uint32_t a = c->a[k], b = c->b[k];
  double d[3];
  v3_sub(d, p->x + 3 * b, p->x + 3 * a);
  double dist = v3_norm(d), un = p->radius[a] + p->radius[b] - dist;
  if (!(un > 0) && !esf_candidates_bonded(c, k)) return 0;
  if (!(dist > 0)) return 0;
  v3_scale(n, 1.0 / dist, d);
  *la = p->radius[a] - 0.5 * un;
  *lb = p->radius[b] - 0.5 * un;
  return 1;
}

static int wall_geometry(const esf_sim *s, size_t k, double n[3], double *la) {
  const esf_candidates *c = &s->nb.pw;
  uint32_t a = c->a[k];
  esf_wall_hit hit;
  esf_wall_nearest(&s->walls.e[c->b[k]], s->p.x + 3 * a, &hit);
  if (!(hit.dist < s->p.radius[a])) return 0;
  v3_copy(n, hit.n);
  *la = hit.dist;
  return 1;
}

/* A linear-law contact at its Coulomb cap (sliding at its last commit: kt |xi| at the
 * cap with the elastic normal force kn u, or a cap of zero) has no tangential spring or
 * dashpot (law_body.h); kc[1] and kc[3] are zeroed. */
static void sliding(const esf_pair_params *pp, const esf_contact_hist *h, int live,
                    double un, double kc[4]) {
  if (pp->law->flags & ESF_LAW_TENSION) return;
  double tau = pp->cohesion + pp->mu * pp->kn * un;
  double xi = live ? v3_norm(h->xi) : 0.0;
  if (tau <= 0 || pp->kt * xi >= (1 - 1e-9) * tau) kc[1] = kc[3] = 0.0;
}

static int net_gather(const esf_sim *s, net *N, esf_error *err) {
  const esf_particles *p = &s->p;
  const esf_materials *mt = &s->mats;
  const esf_candidates *pp = &s->nb.pp, *pw = &s->nb.pw;
  size_t cap = pp->n + pw->n;
  N->n = 0;
  N->ab = malloc((cap ? cap : 1) * 2 * sizeof *N->ab);
  N->g = malloc((cap ? cap : 1) * ESF_STAB_REC * sizeof *N->g);
  if (!N->ab || !N->g)
    return esf_fail(err, ESF_ENOMEM, "stability check: out of memory for %zu contacts",
                    cap);
  double n[3], la, lb;
  for (size_t k = 0; k < pp->n; k++) {
    if (!pair_geometry(s, k, n, &la, &lb)) continue;
    uint32_t a = pp->a[k], b = pp->b[k];
    double *g = N->g + ESF_STAB_REC * N->n;
    v3_copy(g, n);
    g[3] = la, g[4] = lb;
    const esf_pair_params *par = &mt->pair[p->material[a] * mt->n + p->material[b]];
    esf_stab_springs(par, s->beta, p->mass[a] * p->mass[b] / (p->mass[a] + p->mass[b]),
                     g + 5);
    sliding(par, &pp->h[k], pp->touch[k], p->radius[a] - la + p->radius[b] - lb, g + 5);
    N->ab[2 * N->n] = a, N->ab[2 * N->n + 1] = b;
    N->n++;
  }
  for (size_t k = 0; k < pw->n; k++) {
    if (!wall_geometry(s, k, n, &la)) continue;
    uint32_t a = pw->a[k];
    double *g = N->g + ESF_STAB_REC * N->n;
    v3_copy(g, n);
    g[3] = la, g[4] = 0.0;
    const esf_pair_params *par =
        &mt->pair[p->material[a] * mt->n + s->walls.e[pw->b[k]].material];
    esf_stab_springs(par, s->beta, p->mass[a], g + 5);
    sliding(par, &pw->h[k], pw->touch[k], p->radius[a] - la, g + 5);
    N->ab[2 * N->n] = a, N->ab[2 * N->n + 1] = NONE;
    N->n++;
  }
  return ESF_OK;
}

/* The operator y = D (sum over contacts G^T (ck S_K + cc S_C) G) D x, D = M^{-1/2},
 * on 6 coordinates per particle (2D: x, z and the rotation about y only). */
typedef struct op {
  const net *N;
  double ck, cc; /* weights of the springs and the dashpots */
  double *d;     /* 6 per particle: D's diagonal, 0 on frozen coordinates */
  double *z;     /* scratch, 6 per particle */
  size_t nd;
} op;

static void op_apply(op *o, const double *x, double *y) {
  const net *N = o->N;
  size_t nd = o->nd;
  for (size_t j = 0; j < nd; j++) o->z[j] = o->d[j] * x[j];
  memset(y, 0, nd * sizeof *y);
  for (size_t k = 0; k < N->n; k++) {
    const double *g = N->g + ESF_STAB_REC * k;
    uint32_t a = N->ab[2 * k], b = N->ab[2 * k + 1];
    int wall = b == NONE;
    esf_stab_contact_apply(g, g[3], g[4], o->ck * g[5] + o->cc * g[7],
                           o->ck * g[6] + o->cc * g[8], o->z + 6 * (size_t)a,
                           wall ? NULL : o->z + 6 * (size_t)b, y + 6 * (size_t)a,
                           wall ? NULL : y + 6 * (size_t)b);
  }
  for (size_t j = 0; j < nd; j++) y[j] *= o->d[j];
}

static double dot(const double *a, const double *b, size_t n) {
  double r = 0;
  for (size_t j = 0; j < n; j++) r += a[j] * b[j];
  return r;
}

/* the deterministic start: a hash of the coordinate's index on the free coordinates */
static void start_vector(const op *o, double *v, size_t nd) {
  for (size_t j = 0; j < nd; j++) {
    uint64_t h = (uint64_t)j * 0x9E3779B97F4A7C15ull + 0x632BE59BD9B4E019ull;
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 29;
    v[j] = o->d[j] != 0 ? (double)(h >> 11) * 0x1p-53 - 0.5 : 0.0;
  }
  double nv = sqrt(dot(v, v, nd));
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

/* Lanczos: the recurrence from v1; when y is not NULL, the second pass that sums the
 * Ritz vector y = sum s_j v_j of the first pass's m steps. */
static int lanczos(op *o, double *v0, double *v1, double *w, size_t nd, double *al,
                   double *be, int *m, double *theta, double *s, double *y) {
  int second = y != NULL, mm = second ? *m : LZ_MAX;
  double *vp = v0, *vc = v1;
  memset(vp, 0, nd * sizeof *vp);
  start_vector(o, vc, nd);
  if (second) memset(y, 0, nd * sizeof *y);
  if (!second) be[0] = 0;
  for (int j = 0; j < mm; j++) {
    if (second)
      for (size_t q = 0; q < nd; q++) y[q] += s[j] * vc[q];
    if (second && j + 1 == mm) break;
    op_apply(o, vc, w);
    if (!second) al[j] = dot(w, vc, nd);
    for (size_t q = 0; q < nd; q++) w[q] -= al[j] * vc[q] + be[j] * vp[q];
    double b = second ? be[j + 1] : sqrt(dot(w, w, nd));
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
    for (size_t q = 0; q < nd; q++) {
      double t = w[q] / b;
      vp[q] = vc[q];
      vc[q] = t;
    }
  }
  return ESF_OK;
}

int esf_stability_estimate(esf_sim *s, double dt, int with_mode, esf_stability *out,
                           esf_error *err) {
  const esf_particles *p = &s->p;
  size_t nd = 6 * p->n;
  *out = (esf_stability){.id = -1, .other = -2, .dt_limit = INFINITY};
  if (nd == 0) return ESF_OK;
  double *buf = malloc(5 * nd * sizeof *buf);
  double *al = malloc(2 * (LZ_MAX + 2) * sizeof *al), *sv = malloc(LZ_MAX * sizeof *sv);
  if (!buf || !al || !sv) {
    free(buf), free(al), free(sv);
    return esf_fail(err, ESF_ENOMEM, "stability check: out of memory for %zu particles",
                    p->n);
  }
  double *be = al + LZ_MAX + 2;
  net N = {0};
  int rc = net_gather(s, &N, err);
  op o = {.N = &N, .ck = dt * dt, .cc = 2.0 * dt, .d = buf, .z = buf + nd, .nd = nd};
  double *v0 = buf + 2 * nd, *v1 = buf + 3 * nd, *w = buf + 4 * nd;
  static const int free2[6] = {1, 0, 1, 0, 1, 0}; /* 2D: x, z and the rotation about y */
  for (size_t i = 0; i < p->n; i++)
    for (int j = 0; j < 6; j++) {
      double m = j < 3 ? p->inv_mass[i] : p->inv_inertia[i];
      buf[6 * i + (size_t)j] = (s->cfg.dim == 3 || free2[j]) && m > 0 ? sqrt(m) : 0.0;
    }
  int m = 0;
  double theta = 0;
  if (!rc) rc = lanczos(&o, v0, v1, w, nd, al, be, &m, &theta, sv, NULL);
  out->lambda = theta > 0 ? theta : 0.0;
  out->iters = m;
  out->contacts = N.n;
  if (!rc && with_mode && N.n > 0 && m > 0) {
    double *y = buf + 4 * nd; /* w is done with; the second pass needs its own */
    double *w2 = malloc(nd * sizeof *w2);
    if (!w2) rc = esf_fail(err, ESF_ENOMEM, "stability check: out of memory");
    if (!rc) {
      /* second pass: regenerate v_j into v0/v1 with w2 as the work vector */
      rc = lanczos(&o, v0, v1, w2, nd, al, be, &m, &theta, sv, y);
      double ny = sqrt(dot(y, y, nd));
      for (size_t q = 0; q < nd && ny > 0; q++) y[q] /= ny;
      /* a = y.A.y and b = y.B.y, and the particle with the largest share */
      o.ck = 1, o.cc = 0;
      op_apply(&o, y, w2);
      double a = dot(y, w2, nd);
      o.ck = 0, o.cc = 1;
      op_apply(&o, y, w2);
      double b = dot(y, w2, nd);
      out->omega = a > 0 ? sqrt(a) : 0.0;
      out->xi = a > 0 ? b / (2 * out->omega) : 0.0;
      out->dt_limit = a > 0 ? (-b + sqrt(b * b + 4 * a)) / a : INFINITY;
      size_t best = 0;
      double big = -1;
      for (size_t i = 0; i < p->n; i++) {
        double e = 0;
        for (int j = 0; j < 6; j++) e += y[6 * i + (size_t)j] * y[6 * i + (size_t)j];
        if (e > big) big = e, best = i;
      }
      out->id = p->id[best];
      /* its partner: the touching neighbour with the largest share */
      big = -1;
      double n[3], la, lb;
      const esf_candidates *c = &s->nb.pp;
      for (size_t k = 0; k < c->n; k++) {
        if ((c->a[k] != best && c->b[k] != best) || !pair_geometry(s, k, n, &la, &lb))
          continue;
        size_t q = c->a[k] == best ? c->b[k] : c->a[k];
        double e = 0;
        for (int j = 0; j < 6; j++) e += y[6 * q + (size_t)j] * y[6 * q + (size_t)j];
        if (e > big) big = e, out->other = p->id[q];
      }
      c = &s->nb.pw;
      for (size_t k = 0; k < c->n && big < 0; k++)
        if (c->a[k] == best && wall_geometry(s, k, n, &la)) out->other = -1;
    }
    free(w2);
  }
  free(N.ab);
  free(N.g);
  free(buf);
  free(al);
  free(sv);
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
