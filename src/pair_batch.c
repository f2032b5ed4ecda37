/* pair_batch.c — the linear law of the fused step, ESF_BATCH pairs in vector lanes.
 *
 * Physics: contact_linear.c's law (PHYSICS.md §3.1–3.2), as the fused step needs it
 * (no ledger by-products): normal spring and dashpot without tension (004 2.9–2.12),
 * the incremental tangential spring xi carried into the new contact plane, rotated
 * (000 3-17, 3-18: xi += (n_old x n) x xi, then the twist of the mean spin about n) or
 * projected and rescaled to its old length, the tangential dashpot while sticking and
 * the Mohr-Coulomb cap with radial return (004 2.13–2.16). The contact point divides
 * the overlap equally: lever arms la = ra - un/2, lb = rb - un/2; the relative contact
 * velocity is vc = (vB - vA) - (la wA + lb wB) x n (000 3-21).
 *
 * Order per batch: gather the lanes' positions, radii, velocities, spins, history and
 * pair parameters; compute everything lane-wise with the same instructions for every
 * lane (the Coulomb cap as a select, its square root only when some lane slides); then
 * write the outputs component major and commit the history of the lanes that are in
 * range and within the overlap limit. Lanes past nl repeat lane 0's pair and are
 * neither written back nor reported.
 * Entry: the pairs overlap; their touch flag says whether the history is live.
 * Exit: out holds force on A, torque on A, torque on B (N, N m); history committed.
 * Units: SI. */
#include "pair_batch.h"

#include <math.h>

#if defined(__AVX__)
#include <immintrin.h>
#endif

/* The vector helpers below are static and inlined, so no vector crosses a call
 * boundary: GCC's note that AVX-sized vectors change the ABI of non-AVX builds does
 * not apply. */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

typedef double vd __attribute__((vector_size(ESF_BATCH * sizeof(double))));
typedef long long vm __attribute__((vector_size(ESF_BATCH * sizeof(double))));

_Static_assert(ESF_BATCH == 4, "the gathers below are written for four lanes");

static inline vd sel(vm m, vd a, vd b) { return (vd)(((vm)a & m) | ((vm)b & ~m)); }

static inline vd vsqrt(vd x) {
#if defined(__AVX__)
  return (vd)_mm256_sqrt_pd((__m256d)x);
#else
  return (vd){sqrt(x[0]), sqrt(x[1]), sqrt(x[2]), sqrt(x[3])};
#endif
}

static inline int any(vm m) { return (m[0] | m[1] | m[2] | m[3]) != 0; }

/* p[i[0]], ..., p[i[3]] */
static inline vd gat(const double *p, const size_t *i) {
  return (vd){p[i[0]], p[i[1]], p[i[2]], p[i[3]]};
}

static inline void cross(vd r[3], const vd a[3], const vd b[3]) {
  r[0] = a[1] * b[2] - a[2] * b[1];
  r[1] = a[2] * b[0] - a[0] * b[2];
  r[2] = a[0] * b[1] - a[1] * b[0];
}

static inline vd dot(const vd a[3], const vd b[3]) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

unsigned esf_pair_batch_linear(const esf_pair_batch_ctx *c, const uint32_t *k, int nl,
                               double out[ESF_BATCH_OUT][ESF_BATCH]) {
  size_t kk[ESF_BATCH], ia[ESF_BATCH], ib[ESF_BATCH], a3[ESF_BATCH], b3[ESF_BATCH];
  const esf_pair_params *pp[ESF_BATCH];
  const esf_materials *mt = c->mt;
  vm tch;
  for (int l = 0; l < ESF_BATCH; l++) {
    kk[l] = k[l < nl ? l : 0];
    ia[l] = c->a[kk[l]];
    ib[l] = c->b[kk[l]];
    a3[l] = 3 * ia[l];
    b3[l] = 3 * ib[l];
    pp[l] = &mt->pair[c->material[ia[l]] * mt->n + c->material[ib[l]]];
    tch[l] = c->touch[kk[l]] ? -1 : 0;
  }
  const vd kn = {pp[0]->kn, pp[1]->kn, pp[2]->kn, pp[3]->kn};
  const vd kt = {pp[0]->kt, pp[1]->kt, pp[2]->kt, pp[3]->kt};
  const vd mu = {pp[0]->mu, pp[1]->mu, pp[2]->mu, pp[3]->mu};
  const vd cn = gat(c->cn, kk), ct = gat(c->ct, kk);
  vd d[3], n[3], wa[3], wb[3], hx[3], hn[3];
  for (int q = 0; q < 3; q++) {
    d[q] = gat(c->x + q, b3) - gat(c->x + q, a3);
    wa[q] = gat(c->w + q, a3);
    wb[q] = gat(c->w + q, b3);
  }
  for (int l = 0; l < ESF_BATCH; l++) {
    const esf_contact_hist *h = c->h + kk[l];
    for (int q = 0; q < 3; q++) {
      hx[q][l] = h->xi[q];
      hn[q][l] = h->n[q];
    }
  }
  const vd ra = gat(c->radius, ia), rb = gat(c->radius, ib);
  const vd dist = vsqrt(dot(d, d));
  const vm pos = dist > 0;
  const vd inv = 1.0 / dist, zero = {0, 0, 0, 0}, one = {1, 1, 1, 1};
  n[0] = sel(pos, d[0] * inv, zero);
  n[1] = sel(pos, d[1] * inv, zero);
  n[2] = sel(pos, d[2] * inv, one);
  const vd un = ra + rb - dist;
  const vm bad = un > c->max_overlap * sel(ra < rb, ra, rb);
  const vd la = ra - 0.5 * un, lb = rb - 0.5 * un;
  /* vc = (vB - vA) - (la wA + lb wB) x n */
  vd sw[3], vc[3];
  for (int q = 0; q < 3; q++) sw[q] = la * wa[q] + lb * wb[q];
  cross(vc, sw, n);
  for (int q = 0; q < 3; q++) vc[q] = gat(c->v + q, b3) - gat(c->v + q, a3) - vc[q];
  const vd vn = dot(vc, n);
  vd fn = kn * un - cn * vn;
  fn = sel(fn < 0.0, zero, fn);

  vd xi[3];
  if (c->rotate) { /* 000 (3-17)-(3-18) */
    vd t1[3], t2[3], sp[3];
    cross(t1, hn, n);
    cross(t2, t1, hx);
    for (int q = 0; q < 3; q++) xi[q] = hx[q] + t2[q];
    const vd ang = 0.5 * (dot(wa, n) + dot(wb, n)) * c->dt;
    for (int q = 0; q < 3; q++) sp[q] = ang * n[q];
    cross(t2, sp, xi);
    for (int q = 0; q < 3; q++) xi[q] = xi[q] + t2[q];
  } else {
    const vd m0 = vsqrt(dot(hx, hx)), s = dot(hx, n);
    for (int q = 0; q < 3; q++) xi[q] = hx[q] - s * n[q];
    const vd m1 = vsqrt(dot(xi, xi));
    const vd r = m0 / m1;
    for (int q = 0; q < 3; q++) xi[q] = sel(m1 > 0, xi[q] * r, xi[q]);
  }
  vd vct[3], ft[3];
  for (int q = 0; q < 3; q++) {
    vct[q] = vc[q] - vn * n[q];
    xi[q] = sel(tch, xi[q], zero) + c->dt * vct[q];
    ft[q] = kt * xi[q] + ct * vct[q];
  }
  vd tau = mu * fn; /* fn >= 0 here (no tension): the tension cut-off never applies */
  if (c->cohesion)
    tau += (vd){pp[0]->cohesion, pp[1]->cohesion, pp[2]->cohesion, pp[3]->cohesion};
  const vd ftm2 = dot(ft, ft);
  const vm slide = ftm2 > tau * tau;
  if (any(slide)) { /* sliding: radial return, no dashpot (004 2.16) */
    const vd sc = tau / vsqrt(ftm2), ikt = sel(kt > 0, 1.0 / kt, zero);
    for (int q = 0; q < 3; q++) {
      ft[q] = sel(slide, ft[q] * sc, ft[q]);
      xi[q] = sel(slide, ikt * ft[q], xi[q]);
    }
  }
  vd m[3];
  cross(m, n, ft);
  for (int q = 0; q < 3; q++) {
    const vd fo = ft[q] - fn * n[q], ma = la * m[q], mb = lb * m[q];
    for (int l = 0; l < ESF_BATCH; l++) {
      out[q][l] = fo[l];
      out[3 + q][l] = ma[l];
      out[6 + q][l] = mb[l];
    }
  }
  unsigned badmask = 0;
  for (int l = 0; l < nl; l++) {
    if (bad[l]) {
      badmask |= 1u << l;
      continue;
    }
    esf_contact_hist *h = c->h + kk[l];
    for (int q = 0; q < 3; q++) {
      h->xi[q] = xi[q][l];
      h->n[q] = n[q][l];
    }
    c->touch[kk[l]] = 1;
  }
  return badmask;
}
