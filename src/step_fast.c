/* step_fast.c — the fused, threaded leapfrog step (step_fast.h).
 *
 * Physics: exactly the leapfrog of integrators/leapfrog.c (000 3-6..3-8, 004 2.38–2.47,
 * 001 3.50–3.54) with the linear law of contact_linear.c (PHYSICS.md §3.1–3.2: normal
 * spring and dashpot without tension, incremental tangential spring carried into the
 * new contact plane, tangential dashpot while sticking, Mohr-Coulomb cap with radial
 * return), written out for the pair loop without the ledger's by-products.
 *
 * Order of operations in one call (state on entry: x_n, v_{n-1/2}, w_{n-1/2}, lists
 * valid for x_n, history at t_{n-1}):
 *   0. after a list rebuild: per-pair dashpot coefficients, the particles' ranges in
 *      the pair list as A (contiguous, the list is sorted by (a, b)), the ascending
 *      list of pairs each particle is B of, and the wall candidates' ranges;
 *   1. threads split the pairs in equal shares: each screens its share for
 *      overlapping spheres into a list without branches (a pair that stopped
 *      touching gets a zero slot), then computes the listed contacts: pair k's force
 *      on A and the torques on A and B go to slot k, history and flag committed;
 *   2. threads split the particles: particle i sums m_i g, then its slots as B (minus
 *      the force) and as A, both ascending in k, then its wall contacts
 *      (esf_forces_wall_particle, forces.c); in 2D drops the out-of-plane parts; local
 *      damping; kick with global damping (1 -+ alpha dt/2); drift x += v dt; the
 *      squared displacement since the last build.
 * Each particle's sums run in one fixed order whatever the threads, so the results
 * are the same bit for bit on any thread count. Failures (overlap beyond the limit)
 * are reported for the lowest pair or particle index, also independent of threads.
 * Units: SI. */
#include "step_fast.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "forces.h"
#include "vec3.h"

#define SLOT 9 /* force on A (3), torque on A (3), torque on B (3) */

struct esf_step_fast {
  long built;     /* nb.builds the indices below belong to (-1: none) */
  size_t np;      /* particles the indices were made for */
  size_t cap_k;   /* pair capacity */
  size_t cap_n;   /* particle capacity */
  double *slot;   /* SLOT per pair */
  double *cn;     /* normal dashpot coefficient per pair, N s/m */
  double *ct;     /* tangential dashpot coefficient per pair, N s/m */
  size_t *astart; /* n+1: pairs k in [astart[i], astart[i+1]) have a == i */
  size_t *bstart; /* n+1: bidx[bstart[i] .. bstart[i+1]) are the pairs with b == i */
  uint32_t *bidx; /* ascending within each particle */
  uint32_t *list; /* per pair: the overlapping pairs of each thread's share */
  size_t *wstart; /* n+1: wall candidates of particle i */
};

int esf_step_fast_create(esf_step_fast **out, esf_error *err) {
  *out = calloc(1, sizeof **out);
  if (!*out) return esf_fail(err, ESF_ENOMEM, "out of memory");
  (*out)->built = -1;
  return ESF_OK;
}

void esf_step_fast_free(esf_step_fast **f) {
  if (!f || !*f) return;
  esf_step_fast *q = *f;
  free(q->slot);
  free(q->cn);
  free(q->ct);
  free(q->astart);
  free(q->bstart);
  free(q->bidx);
  free(q->list);
  free(q->wstart);
  free(q);
  *f = NULL;
}

/* The features a scene may switch on, compiled in or (ESF_MINIMAL: meson -Dfeatures=
 * minimal) out of the fused step; a build without them sends the scenes that use them
 * to the general path. */
#ifdef ESF_MINIMAL
#define HAS_FEATURES 0
#else
#define HAS_FEATURES 1
#endif

static int minimal_ok(const esf_sim *s) {
  const esf_materials *mt = &s->mats;
  for (int k = 0; k < mt->n * mt->n; k++)
    if (mt->pair[k].cohesion != 0.0) return 0;
  return s->cfg.tframe == ESF_TFRAME_ROTATE && s->cfg.dim == 3 && !s->local &&
         s->alpha_r == 0.0 && s->alpha_t == 0.0 && !s->walls.moving;
}

int esf_step_fast_eligible(const esf_sim *s) {
  return s->cfg.fused && !s->led.on && !s->cfg.autod.on && !s->tally &&
         s->law == &esf_contact_linear && !s->nb.pp.vc0 && !s->nb.pp.xs && !s->nb.pw.xs &&
         (HAS_FEATURES || minimal_ok(s)) &&
         !s->walls.gforce && !s->drag; /* servo walls, fluid force: general path */
}

static int grow(void **p, size_t n, size_t size) {
  void *q = realloc(*p, (n ? n : 1) * size);
  if (!q) return 0;
  *p = q;
  return 1;
}

/* Step 0: indices and coefficients for the current lists. */
static int index_lists(esf_sim *s, esf_step_fast *f, esf_error *err) {
  const esf_particles *p = &s->p;
  const esf_contacts *c = &s->nb.pp, *cw = &s->nb.pw;
  size_t n = p->n, m = c->n;
  if (m > f->cap_k) {
    if (!grow((void **)&f->slot, m, SLOT * sizeof(double)) ||
        !grow((void **)&f->cn, m, sizeof(double)) ||
        !grow((void **)&f->ct, m, sizeof(double)) ||
        !grow((void **)&f->bidx, m, sizeof(uint32_t)) ||
        !grow((void **)&f->list, m, sizeof(uint32_t)))
      return esf_fail(err, ESF_ENOMEM, "out of memory for %zu contact slots", m);
    f->cap_k = m;
  }
  if (n + 1 > f->cap_n) {
    if (!grow((void **)&f->astart, n + 1, sizeof(size_t)) ||
        !grow((void **)&f->bstart, n + 1, sizeof(size_t)) ||
        !grow((void **)&f->wstart, n + 1, sizeof(size_t)))
      return esf_fail(err, ESF_ENOMEM, "out of memory for %zu particle ranges", n);
    f->cap_n = n + 1;
  }
  const esf_materials *mt = &s->mats;
  for (size_t k = 0; k < m; k++) {
    uint32_t a = c->a[k], b = c->b[k];
    const esf_pair_params *pp = &mt->pair[p->material[a] * mt->n + p->material[b]];
    if (s->beta > 0) {
      f->cn[k] = s->beta * pp->kn;
      f->ct[k] = s->beta * pp->kt;
    } else {
      double sm = sqrt(p->mass[a] * p->mass[b] / (p->mass[a] + p->mass[b]));
      f->cn[k] = pp->cn_factor * sm;
      f->ct[k] = pp->ct_factor * sm;
    }
    double *sl = f->slot + SLOT * k; /* invariant: a slot is zero unless touching */
    for (int q = 0; q < SLOT; q++) sl[q] = 0.0;
  }
  memset(f->astart, 0, (n + 1) * sizeof(size_t));
  memset(f->bstart, 0, (n + 1) * sizeof(size_t));
  memset(f->wstart, 0, (n + 1) * sizeof(size_t));
  for (size_t k = 0; k < m; k++) {
    f->astart[c->a[k] + 1]++;
    f->bstart[c->b[k] + 1]++;
  }
  for (size_t k = 0; k < cw->n; k++) f->wstart[cw->a[k] + 1]++;
  for (size_t i = 0; i < n; i++) {
    f->astart[i + 1] += f->astart[i];
    f->bstart[i + 1] += f->bstart[i];
    f->wstart[i + 1] += f->wstart[i];
  }
  /* the pairs of each particle as B, ascending k: one cursor per particle */
  size_t *cur = malloc((n ? n : 1) * sizeof *cur);
  if (!cur) return esf_fail(err, ESF_ENOMEM, "out of memory");
  memcpy(cur, f->bstart, n * sizeof *cur);
  for (size_t k = 0; k < m; k++) f->bidx[cur[c->b[k]]++] = (uint32_t)k;
  free(cur);
  f->built = s->nb.builds;
  f->np = n;
  return ESF_OK;
}

/* Step 1a for the pairs [k0, k1): the candidates whose spheres overlap go to
 * list[0 .. return value); pairs that stopped touching get a zero slot. Branch-free
 * for the common cases, so the contact pass below runs without the distance test. */
static size_t screen_pairs(esf_sim *s, esf_step_fast *f, size_t k0, size_t k1,
                           uint32_t *list) {
  const esf_particles *p = &s->p;
  esf_contacts *c = &s->nb.pp;
  const double *x = p->x, *r = p->radius;
  size_t cnt = 0;
  for (size_t k = k0; k < k1; k++) {
    const size_t a = c->a[k], b = c->b[k];
    const double dx = x[3 * b] - x[3 * a], dy = x[3 * b + 1] - x[3 * a + 1],
                 dz = x[3 * b + 2] - x[3 * a + 2], R = r[a] + r[b];
    const int in = dx * dx + dy * dy + dz * dz < R * R;
    list[cnt] = (uint32_t)k;
    cnt += (size_t)in;
    if ((in ^ 1) & c->touch[k]) { /* the contact ended (rare; no branch on `in`) */
      c->touch[k] = 0;
      double *sl = f->slot + SLOT * k;
      for (int q = 0; q < SLOT; q++) sl[q] = 0.0;
    }
  }
  return cnt;
}

/* Step 1b for an overlapping pair k. Returns 1 when the overlap exceeds the limit
 * (nothing written). */
static inline int pair_kernel(esf_sim *s, esf_step_fast *f, size_t k, int rotate,
                              double dt) {
  const esf_particles *p = &s->p;
  esf_contacts *c = &s->nb.pp;
  const uint32_t a = c->a[k], b = c->b[k];
  const double *xa = p->x + 3 * (size_t)a, *xb = p->x + 3 * (size_t)b;
  const double dx = xb[0] - xa[0], dy = xb[1] - xa[1], dz = xb[2] - xa[2];
  const double ra = p->radius[a], rb = p->radius[b], R = ra + rb;
  const double d2 = dx * dx + dy * dy + dz * dz;
  double *sl = f->slot + SLOT * k;
  const double dist = sqrt(d2);
  double n[3];
  if (dist > 0) {
    const double inv = 1.0 / dist;
    n[0] = dx * inv;
    n[1] = dy * inv;
    n[2] = dz * inv;
  } else {
    n[0] = 0, n[1] = 0, n[2] = 1;
  }
  const double un = R - dist;
  if (un > s->cfg.max_overlap * (ra < rb ? ra : rb)) return 1;
  const double la = ra - 0.5 * un, lb = rb - 0.5 * un;
  const double *va = p->v + 3 * (size_t)a, *vb = p->v + 3 * (size_t)b;
  const double *wa = p->w + 3 * (size_t)a, *wb = p->w + 3 * (size_t)b;
  /* vc = (vB - vA) - (la wA + lb wB) x n  (000 3-21) */
  double sw[3], vc[3];
  for (int q = 0; q < 3; q++) sw[q] = la * wa[q] + lb * wb[q];
  v3_cross(vc, sw, n);
  for (int q = 0; q < 3; q++) vc[q] = vb[q] - va[q] - vc[q];
  const esf_materials *mt = &s->mats;
  const esf_pair_params *pp = &mt->pair[p->material[a] * mt->n + p->material[b]];

  const double vn = v3_dot(vc, n);
  const double fel = pp->kn * un;
  double fn = fel - f->cn[k] * vn;
  if (fn < 0.0) fn = 0.0;

  esf_contact_hist *h = &c->h[k];
  double xi[3] = {0, 0, 0};
  if (c->touch[k]) {
    if (!HAS_FEATURES || rotate) { /* 000 (3-17)-(3-18) */
      double t1[3], t2[3];
      v3_cross(t1, h->n, n);
      v3_cross(t2, t1, h->xi);
      v3_add(xi, h->xi, t2);
      const double ang = 0.5 * (v3_dot(wa, n) + v3_dot(wb, n)) * dt;
      double sp[3] = {ang * n[0], ang * n[1], ang * n[2]};
      v3_cross(t2, sp, xi);
      v3_add(xi, xi, t2);
    } else {
      const double m0 = v3_norm(h->xi);
      v3_copy(xi, h->xi);
      v3_axpy(xi, -v3_dot(xi, n), n);
      const double m1 = v3_norm(xi);
      if (m1 > 0) v3_scale(xi, m0 / m1, xi);
    }
  }
  double vct[3];
  for (int q = 0; q < 3; q++) {
    vct[q] = vc[q] - vn * n[q];
    xi[q] += dt * vct[q];
  }
  double ft[3];
  const double ctk = f->ct[k];
  for (int q = 0; q < 3; q++) ft[q] = pp->kt * xi[q] + ctk * vct[q];
  /* fn >= 0 here (no tension), so the tension cut-off never applies */
  const double tau = HAS_FEATURES ? pp->cohesion + pp->mu * fn : pp->mu * fn;
  const double ftm2 = v3_norm2(ft);
  if (ftm2 > tau * tau) { /* sliding: radial return, no dashpot (004 2.16) */
    const double sc = tau / sqrt(ftm2);
    const double ikt = pp->kt > 0 ? 1.0 / pp->kt : 0.0;
    for (int q = 0; q < 3; q++) {
      ft[q] *= sc;
      xi[q] = ikt * ft[q];
    }
  }
  v3_copy(h->xi, xi);
  v3_copy(h->n, n);
  c->touch[k] = 1;
  double m[3];
  v3_cross(m, n, ft);
  for (int q = 0; q < 3; q++) {
    sl[q] = -fn * n[q] + ft[q];
    sl[3 + q] = la * m[q];
    sl[6 + q] = lb * m[q];
  }
  return 0;
}

int esf_step_fast_run(esf_sim *s, esf_step_fast *f, size_t *touching, esf_error *err) {
  esf_particles *p = &s->p;
  int rc;
  if (f->built != s->nb.builds || f->np != p->n) {
    rc = index_lists(s, f, err);
    if (rc) return rc;
  }
  const size_t m = s->nb.pp.n, n = p->n;
  const double dt = s->dt, h = 0.5 * dt;
  const int rotate = s->cfg.tframe == ESF_TFRAME_ROTATE, dim2 = s->cfg.dim == 2;
  const double cr0 = 1.0 - s->alpha_r * h, cr1 = 1.0 / (1.0 + s->alpha_r * h);
  const double ct0 = 1.0 - s->alpha_t * h, ct1 = 1.0 / (1.0 + s->alpha_t * h);
  const esf_local_damping *loc = s->local;
  const double lc = s->cfg.local_coef;
  const double *g = s->cfg.gravity;
  const double *xref = s->nb.xref;
  int threads = s->cfg.threads > 0 ? s->cfg.threads : 1;
  size_t nt_pp = 0, nt_pw = 0;
  size_t bad_pair = SIZE_MAX, bad_part = SIZE_MAX;
  double max2 = 0.0;
  int nonfinite = 0;
  (void)threads;

#pragma omp parallel num_threads(threads) reduction(+ : nt_pp, nt_pw) \
    reduction(min : bad_pair, bad_part) reduction(max : max2) reduction(| : nonfinite)
  {
    {
#ifdef _OPENMP
      const size_t nth = (size_t)omp_get_num_threads(), me = (size_t)omp_get_thread_num();
#else
      const size_t nth = 1, me = 0;
#endif
      const size_t k0 = m * me / nth, k1 = m * (me + 1) / nth;
      uint32_t *list = f->list + k0;
      const size_t cnt = screen_pairs(s, f, k0, k1, list);
      nt_pp += cnt;
      for (size_t j = 0; j < cnt; j++)
        if (pair_kernel(s, f, list[j], rotate, dt) && list[j] < bad_pair)
          bad_pair = list[j];
    }
#pragma omp barrier

#pragma omp for schedule(static)
    for (size_t i = 0; i < n; i++) {
      if (bad_pair != SIZE_MAX) continue; /* this thread saw a failure: stop early */
      const double mass = p->mass[i];
      double fi[3] = {mass * g[0], mass * g[1], mass * g[2]}, ti[3] = {0, 0, 0};
      for (size_t j = f->bstart[i]; j < f->bstart[i + 1]; j++) {
        const double *sl = f->slot + SLOT * (size_t)f->bidx[j];
        for (int q = 0; q < 3; q++) {
          fi[q] -= sl[q];
          ti[q] += sl[6 + q];
        }
      }
      for (size_t k = f->astart[i]; k < f->astart[i + 1]; k++) {
        const double *sl = f->slot + SLOT * k;
        for (int q = 0; q < 3; q++) {
          fi[q] += sl[q];
          ti[q] += sl[3 + q];
        }
      }
      if (f->wstart[i] < f->wstart[i + 1] &&
          esf_forces_wall_particle(s, f->wstart[i], f->wstart[i + 1], p->x, p->v, p->w,
                                   dt, ESF_FORCES_COMMIT, NULL, NULL, &nt_pw, fi, ti,
                                   NULL)) {
        if (i < bad_part) bad_part = i;
        continue;
      }
      if (HAS_FEATURES && dim2) {
        fi[1] = 0.0;
        ti[0] = 0.0;
        ti[2] = 0.0;
      }
      double *v = p->v + 3 * i, *w = p->w + 3 * i, *x = p->x + 3 * i;
      v3_copy(p->f + 3 * i, fi);
      v3_copy(p->t + 3 * i, ti);
      if (HAS_FEATURES && loc) {
        double fd[3], md[3];
        loc->force(lc, fi, v, fd);
        loc->force(lc, ti, w, md);
        v3_add(fi, fi, fd);
        v3_add(ti, ti, md);
      }
      const double im = p->inv_mass[i] * dt, ii = p->inv_inertia[i] * dt;
      double d2 = 0.0;
      for (int q = 0; q < 3; q++) {
        if (HAS_FEATURES) {
          v[q] = (cr0 * v[q] + fi[q] * im) * cr1;
          w[q] = (ct0 * w[q] + ti[q] * ii) * ct1;
        } else {
          v[q] += fi[q] * im;
          w[q] += ti[q] * ii;
        }
        x[q] += v[q] * dt;
        if (xref) {
          const double d = x[q] - xref[3 * i + q];
          d2 += d * d;
        }
      }
      if (!(d2 <= max2)) {
        if (d2 > max2)
          max2 = d2;
        else
          nonfinite = 1; /* NaN */
      }
    }
  }
  if (bad_pair != SIZE_MAX) {
    const esf_contacts *c = &s->nb.pp;
    uint32_t a = c->a[bad_pair], b = c->b[bad_pair];
    double d[3];
    v3_sub(d, p->x + 3 * (size_t)b, p->x + 3 * (size_t)a);
    double un = p->radius[a] + p->radius[b] - v3_norm(d);
    return esf_forces_overlap_failure(s, (long long)p->id[a], (long long)p->id[b], 0, un,
                                      fmin(p->radius[a], p->radius[b]), err);
  }
  if (bad_part != SIZE_MAX) { /* the same evaluation again, serially, for the message */
    size_t nt = 0;
    double fi[3] = {0, 0, 0}, ti[3] = {0, 0, 0};
    rc = esf_forces_wall_particle(s, f->wstart[bad_part], f->wstart[bad_part + 1], p->x,
                                  p->v, p->w, dt, ESF_FORCES_TRIAL, NULL, NULL, &nt, fi,
                                  ti, err);
    return rc ? rc : esf_fail(err, ESF_EINTERNAL, "wall contact failure not reproduced");
  }
  s->nb.max_disp2 = max2;
  s->nb.disp_valid = xref && !nonfinite;
  s->rhs_evals++;
  *touching = nt_pp + nt_pw;
  return ESF_OK;
}
