/* pair_batch.c — the linear law of the fused step, ESF_BATCH pairs in vector lanes
 * (with ctx.hertz the Hertz-Mindlin law's springs and dashpots, contact_hertz.h).
 *
 * Physics: contact_linear.c's law (docs/physics.md#linear-springdashpot-law): normal
 * spring and dashpot without tension (004 2.9–2.12), the incremental tangential spring
 * xi carried into the new contact plane, rotated (000 3-17, 3-18: xi += (n_old x n) x
 * xi, then the twist of the mean spin about n) or projected and rescaled to its old
 * length, the tangential dashpot while sticking and the Mohr-Coulomb cap with radial
 * return (004 2.13–2.16). Lever arms la = ra - un/2, lb = rb - un/2; the relative
 * contact velocity vc = (vB - vA) - (la wA + lb wB) x n (000 3-21). Rolling resistance:
 * esf_law_rolling, +M on A, -M on B (as forces.c). Every lane runs the same
 * instructions, in two halves: gathers and geometry (geo_body), the law (batch_body).
 * Entry: the pairs overlapped at their last screening or step; their touch flag says
 * whether the history is live. Exit: a pair no longer overlapping (the screening's
 * test, |d|^2 < (ra + rb)^2, in the same order) has its touch flag cleared and nothing
 * else; for the others out holds force on A, torque on A, torque on B (N, N m), or
 * these were added, lane by lane, to A's and B's accumulators (B's force negated);
 * history committed. A trial (ctx.trial: the ODE methods' stages) writes nothing; with
 * ctx.vc0 a live contact's increment integrates (vc0 + vc)/2 (forces.c's
 * eval_contact) and a commit stores vc. Units: SI. */
#include "fused/pair_batch.h"

#include "util/vec4.h"

#include <math.h>
#include <stdatomic.h>
#include <stddef.h>
#include <string.h>

#if defined(__AVX__)
#include <immintrin.h>
#endif

/* The lanes: eight doubles (AVX-512 registers when the build targets them, two AVX or
 * four SSE2 halves otherwise). Rows of four doubles (a lane's x, v, w, history) are
 * loaded and stored as esf_v4 and transposed in two groups of four lanes; with AVX-512
 * the loads put lanes l and l + 4 in one register and transpose with eight-wide
 * shuffles (fewer of them: docs/performance.md#the-pair-batches). */
typedef double vd __attribute__((vector_size(ESF_BATCH * sizeof(double))));
typedef long long vm __attribute__((vector_size(ESF_BATCH * sizeof(double))));
typedef esf_v4 v4;
typedef esf_v4m v4m;

_Static_assert(ESF_BATCH == 8, "the gathers below are written for eight lanes");

/* The 48-byte history is read as two rows of four doubles inside the record: xi[0..2],
 * n[0] from HXI, and xi[2], n[0..2] from HX2 (its last two columns are n[1], n[2]);
 * written back: the first row whole, n[1] and n[2] alone (from HN1). */
#define HXI offsetof(esf_contact_hist, xi)
#define HX2 (HXI + 2 * sizeof(double))
#define HN1 (offsetof(esf_contact_hist, n) + sizeof(double))
_Static_assert(offsetof(esf_contact_hist, n) == HXI + 3 * sizeof(double) &&
                   HX2 + 4 * sizeof(double) == sizeof(esf_contact_hist),
               "xi, n contiguous, the record's last 32 bytes from xi[2]");

static inline __attribute__((always_inline)) vd sel(vm m, vd a, vd b) {
  return (vd)(((vm)a & m) | ((vm)b & ~m));
}

static inline __attribute__((always_inline)) vd vsqrt(vd x) {
#if defined(__AVX512F__)
  return (vd)_mm512_sqrt_pd((__m512d)x);
#elif defined(__AVX__)
  const v4 lo = __builtin_shufflevector(x, x, 0, 1, 2, 3),
           hi = __builtin_shufflevector(x, x, 4, 5, 6, 7);
  const v4 rl = (v4)_mm256_sqrt_pd((__m256d)lo), rh = (v4)_mm256_sqrt_pd((__m256d)hi);
  return __builtin_shufflevector(rl, rh, 0, 1, 2, 3, 4, 5, 6, 7);
#else
  vd r;
  for (int l = 0; l < ESF_BATCH; l++) r[l] = sqrt(x[l]);
  return r;
#endif
}

static inline __attribute__((always_inline)) int any(vm m) {
#if defined(__AVX512F__)
  return _mm512_test_epi64_mask((__m512i)m, (__m512i)m) != 0;
#else
  const v4m o = __builtin_shufflevector(m, m, 0, 1, 2, 3) |
                __builtin_shufflevector(m, m, 4, 5, 6, 7);
  return (o[0] | o[1] | o[2] | o[3]) != 0;
#endif
}

/* pow per lane (the constant Hertz dashpots only: libm's, the scalar copy's bits) */
static inline __attribute__((always_inline)) vd vpow(vd x, double y) {
  vd r;
  for (int l = 0; l < ESF_BATCH; l++) r[l] = pow(x[l], y);
  return r;
}

/* p[i[0]], ..., p[i[7]] */
static inline __attribute__((always_inline)) vd gat(const double *p, const size_t *i) {
  return (vd){p[i[0]], p[i[1]], p[i[2]], p[i[3]], p[i[4]], p[i[5]], p[i[6]], p[i[7]]};
}

static inline __attribute__((always_inline)) v4 ld(const char *p) { return v4_ld(p); }

/* Rows r[l] (lane l's four values) to columns c[j] (value j of the four lanes), and
 * back: the same operation. */
static inline __attribute__((always_inline)) void transpose(const v4 r[4], v4 c[4]) {
  const v4m lo = {0, 4, 2, 6}, hi = {1, 5, 3, 7}, first = {0, 1, 4, 5},
            last = {2, 3, 6, 7};
  const v4 t0 = __builtin_shuffle(r[0], r[1], lo), t1 = __builtin_shuffle(r[0], r[1], hi);
  const v4 t2 = __builtin_shuffle(r[2], r[3], lo), t3 = __builtin_shuffle(r[2], r[3], hi);
  c[0] = __builtin_shuffle(t0, t2, first);
  c[1] = __builtin_shuffle(t1, t3, first);
  c[2] = __builtin_shuffle(t0, t2, last);
  c[3] = __builtin_shuffle(t1, t3, last);
}

/* Columns c as the eight lanes' rows r[l], by two four-wide transposes. */
static inline __attribute__((always_inline)) void rows_by_transpose(const vd c[4],
                                                                    v4 r[ESF_BATCH]) {
  v4 lo[4], hi[4];
  for (int j = 0; j < 4; j++) {
    lo[j] = __builtin_shufflevector(c[j], c[j], 0, 1, 2, 3);
    hi[j] = __builtin_shufflevector(c[j], c[j], 4, 5, 6, 7);
  }
  transpose(lo, r);
  transpose(hi, r + 4);
}

/* Columns c to the lanes' rows at out[l] + off (by the transposes also with AVX-512:
 * the eight-wide network below, stored, was slower:
 * docs/performance.md#tried-and-not-kept). */
static inline __attribute__((always_inline)) void
store_rows(const vd c[4], double out[ESF_BATCH][ESF_BATCH_OUT], int off) {
  v4 r[ESF_BATCH];
  rows_by_transpose(c, r);
  for (int l = 0; l < ESF_BATCH; l++) v4_st(out[l] + off, r[l]);
}

/* Columns c as the eight lanes' rows r[l], in registers. */
static inline __attribute__((always_inline)) void rows_of(const vd c[4],
                                                          v4 r[ESF_BATCH]) {
#if defined(__AVX512F__)
  /* the load's network backwards (it is its own inverse): rows l and l + 4 side by
     side in z[l] (faster here than two four-wide transposes:
     docs/performance.md#tried-and-not-kept) */
  vd u[4], z[4];
  u[0] = __builtin_shufflevector(c[0], c[2], 0, 1, 8, 9, 4, 5, 12, 13);
  u[2] = __builtin_shufflevector(c[0], c[2], 2, 3, 10, 11, 6, 7, 14, 15);
  u[1] = __builtin_shufflevector(c[1], c[3], 0, 1, 8, 9, 4, 5, 12, 13);
  u[3] = __builtin_shufflevector(c[1], c[3], 2, 3, 10, 11, 6, 7, 14, 15);
  z[0] = __builtin_shufflevector(u[0], u[1], 0, 8, 2, 10, 4, 12, 6, 14);
  z[1] = __builtin_shufflevector(u[0], u[1], 1, 9, 3, 11, 5, 13, 7, 15);
  z[2] = __builtin_shufflevector(u[2], u[3], 0, 8, 2, 10, 4, 12, 6, 14);
  z[3] = __builtin_shufflevector(u[2], u[3], 1, 9, 3, 11, 5, 13, 7, 15);
  for (int l = 0; l < 4; l++) {
    r[l] = __builtin_shufflevector(z[l], z[l], 0, 1, 2, 3);
    r[l + 4] = __builtin_shufflevector(z[l], z[l], 4, 5, 6, 7);
  }
#else
  rows_by_transpose(c, r);
#endif
}

/* The four doubles at byte base + off[l] of each of the eight lanes, as columns (the
 * first nc of them). */
static inline __attribute__((always_inline)) void
load_cols_n(const void *base, const size_t *off, vd c[4], int nc) {
  const char *b = base;
#if defined(__AVX512F__)
  /* rows l and l + 4 side by side, then two rounds of eight-wide shuffles: 11 shuffles
     for three columns where two four-wide transposes take 20 */
  vd z[4], u[4];
  for (int j = 0; j < 4; j++) {
    const v4 lo = ld(b + off[j]), hi = ld(b + off[j + 4]);
    z[j] = __builtin_shufflevector(lo, hi, 0, 1, 2, 3, 4, 5, 6, 7);
  }
  u[0] = __builtin_shufflevector(z[0], z[1], 0, 8, 2, 10, 4, 12, 6, 14);
  u[1] = __builtin_shufflevector(z[0], z[1], 1, 9, 3, 11, 5, 13, 7, 15);
  u[2] = __builtin_shufflevector(z[2], z[3], 0, 8, 2, 10, 4, 12, 6, 14);
  u[3] = __builtin_shufflevector(z[2], z[3], 1, 9, 3, 11, 5, 13, 7, 15);
  c[0] = __builtin_shufflevector(u[0], u[2], 0, 1, 8, 9, 4, 5, 12, 13);
  if (nc > 1) c[1] = __builtin_shufflevector(u[1], u[3], 0, 1, 8, 9, 4, 5, 12, 13);
  if (nc > 2) c[2] = __builtin_shufflevector(u[0], u[2], 2, 3, 10, 11, 6, 7, 14, 15);
  if (nc > 3) c[3] = __builtin_shufflevector(u[1], u[3], 2, 3, 10, 11, 6, 7, 14, 15);
#else
  (void)nc;
  const v4 r0[4] = {ld(b + off[0]), ld(b + off[1]), ld(b + off[2]), ld(b + off[3])};
  const v4 r1[4] = {ld(b + off[4]), ld(b + off[5]), ld(b + off[6]), ld(b + off[7])};
  v4 lo[4], hi[4];
  transpose(r0, lo);
  transpose(r1, hi);
  for (int j = 0; j < 4; j++)
    c[j] = __builtin_shufflevector(lo[j], hi[j], 0, 1, 2, 3, 4, 5, 6, 7);
#endif
}

static inline __attribute__((always_inline)) void load_cols(const void *base,
                                                            const size_t *off, vd c[4]) {
  load_cols_n(base, off, c, 4);
}

/* The contact formulas (contact/law_body.h) over eight lanes: the same operations per
 * lane as the general path's scalar copy, so the same bits. */
#define LANE_R            vd
#define LANE_M            vm
#define LANE_SEL(m, a, b) sel(m, a, b)
#define LANE_SQRT(x)      vsqrt(x)
#define LANE_ANY(m)       any(m)
#define LANE_POW(x, y)    vpow(x, y)
#define LANE_FN(name)     name##_v
#define LANE_INLINE       static inline __attribute__((always_inline))
#include "contact/law_body.h"
#undef LANE_R
#undef LANE_M
#undef LANE_SEL
#undef LANE_SQRT
#undef LANE_ANY
#undef LANE_INLINE
#undef LANE_POW
#undef LANE_FN

static inline __attribute__((always_inline)) vd dot(const vd a[3], const vd b[3]) {
  return esf_law_dot_v(a, b);
}

/* ledger_rows' of a light step without the rows DT, MDT and rolling resistance: A's
 * [-fd n | slip] transposed into r, and B's (light_dn_b) its opposite with +0 in the
 * fourth lane (for -0: adding either to rows, which start at +0 and so are never -0,
 * gives the same bits; so does adding nothing for a contact that ended, whose rows
 * are -0). */
static inline __attribute__((always_inline)) void
light_dn_rows(vd fd, const vd n[3], vd slip, vm keep, v4 r[ESF_BATCH]) {
  const vd mz = {-0.0, -0.0, -0.0, -0.0, -0.0, -0.0, -0.0, -0.0};
  vd col[4];
  for (int q = 0; q < 3; q++) col[q] = sel(keep, -fd * n[q], mz);
  col[3] = sel(keep, slip, mz);
  rows_of(col, r);
}
static inline __attribute__((always_inline)) v4 light_dn_b(v4 a) {
  const v4m flip = {(long long)0x8000000000000000ULL, (long long)0x8000000000000000ULL,
                    (long long)0x8000000000000000ULL, 0},
            xyz = {-1, -1, -1, 0};
  return (v4)(((v4m)a ^ flip) & xyz);
}
/* The same for the rows DT and MDT (no bonds, no rolling resistance): A's
 * [fdt | -0], whose opposite is B's (light_dn_b), A's [lA n x fdt | w_st] (Hertz) and
 * B's [lB n x fdt | -0]. */
static inline __attribute__((always_inline)) void
light_dt_rows(const esf_pair_batch_ctx *c, const vd fdt[3], const vd n[3], vd la, vd lb,
              vd w_st, vm keep, v4 rdt[ESF_BATCH], v4 rma[ESF_BATCH], v4 rmb[ESF_BATCH]) {
  const vd mz = {-0.0, -0.0, -0.0, -0.0, -0.0, -0.0, -0.0, -0.0};
  vd md[3], c1[4], c2[4], c3[4];
  esf_law_cross_v(md, n, fdt);
  for (int q = 0; q < 3; q++) {
    c1[q] = sel(keep, fdt[q], mz);
    c2[q] = sel(keep, la * md[q], mz);
    c3[q] = sel(keep, lb * md[q], mz);
  }
  c1[3] = c3[3] = mz;
  c2[3] = c->hertz ? sel(keep, w_st, mz) : mz; /* as ledger_rows */
  rows_of(c1, rdt);
  rows_of(c2, rma);
  rows_of(c3, rmb);
}

static void light_dn(const esf_pair_batch_ctx *c, vd fd, const vd n[3], vd slip, vm keep,
                     const size_t *ia, const size_t *ib, int nl, unsigned skip,
                     double lout[ESF_BATCH][ESF_BATCH_LOUT]) {
  v4 r[ESF_BATCH];
  light_dn_rows(fd, n, slip, keep, r);
  for (int l = 0; l < nl; l++) {
    if (skip >> l & 1u) continue;
    const v4 rb4 = light_dn_b(r[l]);
    if (lout) {
      v4_st(lout[l], r[l]);
      v4_st(lout[l] + ESF_BATCH_LSIDE, rb4);
      continue;
    }
    double *ra = c->rows + c->lr * ia[l], *rb = c->rows + c->lr * ib[l];
    v4_st(ra, v4_ld(ra) + r[l]);
    v4_st(rb, v4_ld(rb) + rb4);
  }
}

/* The ledger's rows of the batch's lanes (esf_ledger_pair_rows's operations, per lane):
 * A's [-fd n | slip], [fdt | -0], [lA n x fdt | w_st], [-fel n | W], [ket | e_t],
 * [lA n x ket | -0] with ket = kt xi (core/ledger.h's order of a side), and B's the
 * opposite forces and its own torques (lB), each with -0 in its fourth lane (the one
 * value whose addition leaves every double as it was); a lane not in keep (the contact
 * ended) adds -0 everywhere but, when its bond broke, the bond's energy e_brk in A's
 * fourth lane of [fdt]. With c->light only the rows of the cumulative terms (the first
 * three, and rolling's first), with c->no_t not the second and third. Added to the rows
 * of the lanes not in skip, in lane order, or written to lout. */
static void ledger_rows(const esf_pair_batch_ctx *c, vd kt, vd fd, vd fel, vd e_n,
                        const vd n[3], vd la, vd lb, const esf_law_tout_v *T,
                        const esf_law_rout_v *R, vm keep, vm broke, vd e_brk,
                        const size_t *ia, const size_t *ib, int nl, unsigned skip,
                        double lout[ESF_BATCH][ESF_BATCH_LOUT]) {
  const vd mz = {-0.0, -0.0, -0.0, -0.0, -0.0, -0.0, -0.0, -0.0};
  const int light = c->light;
  if (light && c->no_t && !R) { /* DN alone (light_dn) */
    light_dn(c, fd, n, T->slip, keep, ia, ib, nl, skip, lout);
    return;
  }
  vd md[3];
  esf_law_cross_v(md, n, T->fdt);
  /* a side's rows j: A's column j, B's 6 + j; with rolling resistance
     (esf_ledger_roll_rows) A's [md | slip], [ms | e], B's [-md | -0], [-ms | -0] in
     the columns 12-15; their places in a particle's rows */
  const int ca[8] = {0, 1, 2, 3, 4, 5, 12, 13}, cb[8] = {6, 7, 8, 9, 10, 11, 14, 15};
  int js[8], pos[8], nj = 0; /* the side's rows written (ctx->light, ctx->no_t) */
  for (int j = 0; j < (R ? 8 : 6); j++)
    if ((j != 1 && j != 2) || !c->no_t)
      if (!light || j < 3 || j == 6) {
        pos[nj] = esf_ledger_side_pos(j);
        js[nj++] = j;
      }
  vd col[16][4];
  for (int q = 0; q < 3; q++) {
    col[0][q] = -fd * n[q];
    col[1][q] = T->fdt[q];
    col[2][q] = la * md[q];
    col[6][q] = -col[0][q];
    col[7][q] = -col[1][q];
    col[8][q] = lb * md[q];
  }
  col[0][3] = T->slip;
  col[1][3] = mz;
  col[2][3] = c->hertz ? (R ? T->w_st + R->w_k : T->w_st) : mz; /* as forces.c's */
  if (!light) {
    vd ket[3], me[3];
    for (int q = 0; q < 3; q++) ket[q] = kt * T->xi[q];
    esf_law_cross_v(me, n, ket);
    for (int q = 0; q < 3; q++) {
      col[3][q] = -fel * n[q];
      col[4][q] = ket[q];
      col[5][q] = la * me[q];
      col[9][q] = -col[3][q];
      col[10][q] = -col[4][q];
      col[11][q] = lb * me[q];
    }
    col[3][3] = e_n;
    col[4][3] = T->e_el;
    col[5][3] = mz;
  }
  if (R)
    for (int q = 0; q < 3; q++) {
      col[12][q] = R->md[q];
      col[13][q] = R->ms[q];
      col[14][q] = -R->md[q];
      col[15][q] = -R->ms[q];
    }
  if (R) {
    col[12][3] = R->slip;
    col[13][3] = R->e_el;
  }
  for (int u = 0; u < nj; u++) {
    const int j = js[u];
    col[cb[j]][3] = mz;
    for (int q = 0; q < 4; q++) { /* a contact that ended adds nothing... */
      col[ca[j]][q] = sel(keep, col[ca[j]][q], mz);
      col[cb[j]][q] = sel(keep, col[cb[j]][q], mz);
    }
  }
  col[1][3] = sel(broke, e_brk, mz); /* ...but the energy its bond held */
  v4 r[16][ESF_BATCH];
  for (int u = 0; u < nj; u++) {
    rows_of(col[ca[js[u]]], r[ca[js[u]]]);
    rows_of(col[cb[js[u]]], r[cb[js[u]]]);
  }
  for (int l = 0; l < nl; l++) {
    if (skip >> l & 1u) continue;
    if (lout) { /* a side's rows contiguous (A's, B's from ESF_BATCH_LSIDE) */
      for (int u = 0; u < nj; u++) {
        const int j = js[u];
        v4_st(lout[l] + 4 * j, r[ca[j]][l]);
        v4_st(lout[l] + ESF_BATCH_LSIDE + 4 * j, r[cb[j]][l]);
      }
      continue;
    }
    double *ra = c->rows + c->lr * ia[l], *rb = c->rows + c->lr * ib[l];
    for (int u = 0; u < nj; u++) {
      const int j = js[u];
      v4_st(ra + pos[u], v4_ld(ra + pos[u]) + r[ca[j]][l]);
      v4_st(rb + pos[u], v4_ld(rb + pos[u]) + r[cb[j]][l]);
    }
  }
}

/* The rolling resistance of the batch's lanes (esf_law_rolling_par, esf_law_rolling),
 * the operations of model/forces.c's per contact (kn: the linear law's, or a Hertz
 * pair's S_n at the overlap, esf_contact_rolling_kn; kn0 S_n at the last commit's
 * overlap, the ledger's stiffness change): the pairs' mu_r, mu_tw, eta_r and
 * stored states gathered, R* and the inertias, the torque M = md + ms added to ta (A's)
 * and subtracted from tb (B's); R receives the new states to commit. */
static void rolling(const esf_pair_batch_ctx *c, const esf_pair_params *const *pp,
                    const size_t *kk, const size_t *ia, const size_t *ib, vd kn, vd kn0,
                    vd ra, vd rb, vd fn, const vd n[3], const vd wa[3], const vd wb[3],
                    vm live, esf_law_rout_v *R, vd ta[4], vd tb[4]) {
  vd mur, mutw, etar, hm[3], ht;
  for (int l = 0; l < ESF_BATCH; l++) {
    mur[l] = pp[l]->mu_r;
    mutw[l] = pp[l]->mu_tw;
    etar[l] = pp[l]->eta_r;
    const esf_contact_roll *h = &c->roll[kk[l]];
    for (int q = 0; q < 3; q++) hm[q][l] = h->m[q];
    ht[l] = h->t;
  }
  vd rs, ir, itw, wrel[3];
  esf_law_rolling_pair_v(ra, rb, gat(c->mass, ia), gat(c->mass, ib), gat(c->inertia, ia),
                         gat(c->inertia, ib), &rs, &ir, &itw);
  esf_law_rpar_v P;
  esf_law_rolling_par_v(kn, mur, mutw, etar, rs, ir, itw, fn, c->roll_cdt, &P);
  if (c->hertz && c->rows) { /* the springs' stiffness change (esf_contact_rolling) */
    P.stiff = 1;
    P.kr0 = esf_law_rolling_stiffness_v(kn0, mur, rs);
    P.ktw0 = esf_law_rolling_stiffness_v(kn0, mutw, rs);
  }
  for (int q = 0; q < 3; q++) wrel[q] = wa[q] - wb[q];
  esf_law_rolling_v(&P, ((vd){0}) + c->dt, n, wrel, hm, ht, live, R);
  for (int q = 0; q < 3; q++) {
    const vd M = R->md[q] + R->ms[q];
    ta[q] = ta[q] + M;
    tb[q] = tb[q] - M;
  }
}

/* The columns of esf_pair_geo. */
enum {
  G_N = 0,
  G_VC = 3,
  G_UN = 6,
  G_LA,
  G_LB,
  G_VN,
  G_SPIN,
  G_RA,
  G_RB,
  G_IN,
  G_BAD,
  G_WA,
  G_WB = G_WA + 3
};
_Static_assert(G_WB + 3 == ESF_PAIR_GEO_COLS, "esf_pair_geo's columns");

static inline __attribute__((always_inline)) vd gcol(const esf_pair_geo *g, int j) {
  return *(const vd *)g->col[j];
}
static inline __attribute__((always_inline)) vm gmask(const esf_pair_geo *g, int j) {
  return (vm)gcol(g, j);
}
static inline __attribute__((always_inline)) void gput(esf_pair_geo *g, int j, vd v) {
  *(vd *)g->col[j] = v;
}

/* The first half of the batch (esf_pair_batch_geometry): the lanes' pairs and
 * particles, their positions (B's periodic image with gen), radii, velocities and
 * spins gathered, then the screening's overlap test in the same operations and order
 * (fused_lists.c), the geometry and contact velocity, vn and the mean spin about n. */
static inline __attribute__((always_inline)) void geo_body(const esf_pair_batch_ctx *c,
                                                           const uint32_t *k, int nl,
                                                           esf_pair_geo *g,
                                                           const int gen) {
  size_t *const kk = g->kk, *const ia = g->ia, *const ib = g->ib;
  size_t a3[ESF_BATCH], b3[ESF_BATCH];
  for (int l = 0; l < ESF_BATCH; l++) {
    kk[l] = k[l < nl ? l : 0];
    ia[l] = c->a[kk[l]];
    ib[l] = c->b[kk[l]];
    a3[l] = 3 * sizeof(double) * ia[l]; /* byte offsets of the 3-vectors */
    b3[l] = 3 * sizeof(double) * ib[l];
  }
  g->nl = nl;
  vd xa[4], xb[4], va[4], vb[4], wa[4], wb[4], d[3], n[3];
  load_cols_n(c->x, a3, xa, 3);
  load_cols_n(c->x, b3, xb, 3);
  if (gen && c->img) /* B's periodic image, esf_periodic_image's operations lane-wise */
    for (int q = 0; q < 3; q++)
      for (int l = 0; l < ESF_BATCH; l++)
        xb[q][l] = xb[q][l] + (double)c->img[3 * kk[l] + q] * c->plen[q];
  load_cols_n(c->v, a3, va, 3);
  load_cols_n(c->v, b3, vb, 3);
  if (gen && c->img &&
      c->le) /* Lees-Edwards: esf_periodic_le_image's and esf_candidates_vb's lane-wise */
    for (int l = 0; l < ESF_BATCH; l++) {
      const int8_t mg = c->img[3 * kk[l] + c->le_grad];
      xb[c->le_flow][l] += (double)mg * c->le_off;
      if (mg) vb[c->le_flow][l] += (double)mg * c->le_vel;
    }
  load_cols_n(c->w, a3, wa, 3);
  load_cols_n(c->w, b3, wb, 3);
  const vd ra = gat(c->radius, ia), rb = gat(c->radius, ib);
  vd d2, un, la, lb, vc[3];
  const vm in = esf_law_pair_overlap_v(xa, xb, ra, rb, d, &d2);
  esf_law_pair_kinematics_v(d, d2, ra, rb, va, vb, wa, wb, n, &un, &la, &lb, vc);
  const vm bad = un > c->max_overlap * sel(ra < rb, ra, rb);
  for (int q = 0; q < 3; q++) {
    gput(g, G_N + q, n[q]);
    gput(g, G_VC + q, vc[q]);
  }
  gput(g, G_UN, un);
  gput(g, G_LA, la);
  gput(g, G_LB, lb);
  gput(g, G_VN, dot(vc, n));
  gput(g, G_SPIN, 0.5 * (dot(wa, n) + dot(wb, n)));
  if (c->hertz || c->roll) { /* their springs read the radii again */
    gput(g, G_RA, ra);
    gput(g, G_RB, rb);
  }
  gput(g, G_IN, (vd)in);
  gput(g, G_BAD, (vd)bad);
  if (c->roll)
    for (int q = 0; q < 3; q++) {
      gput(g, G_WA + q, wa[q]);
      gput(g, G_WB + q, wb[q]);
    }
}

void esf_pair_batch_geometry(const esf_pair_batch_ctx *c, const uint32_t *k, int nl,
                             esf_pair_geo *g) {
  if (c->img)
    geo_body(c, k, nl, g, 1);
  else
    geo_body(c, k, nl, g, 0);
}

/* The batch's second half, from its first (g); its results to out (acc NULL) or added
 * to acc. In order: gather the lanes' history and pair parameters; compute the law
 * lane-wise with the same instructions for every lane (the Coulomb cap as a select, its
 * square root only when some lane slides); then transpose the outputs to one row per
 * lane (written to out, or kept in registers), commit the history of the lanes that
 * are in range and within the overlap limit and, for the accumulating entry point, add
 * those lanes' rows to their particles in lane order. Lanes past nl repeat lane 0's
 * pair and are neither written back nor reported. One out-of-line copy for both
 * outputs (two copies, each specialised for its output, were slower:
 * docs/performance.md#tried-and-not-kept). */
static inline __attribute__((always_inline)) unsigned
batch_body(const esf_pair_batch_ctx *c, const esf_pair_geo *g,
           double out[ESF_BATCH][ESF_BATCH_OUT], double lout[ESF_BATCH][ESF_BATCH_LOUT],
           double *acc, unsigned *apart, const int gen, const int ldn, const int lean) {
  /* lean: the linear law alone (no Hertz, bonds, rolling, cohesion) and no ledger but
     ldn's, known when compiling (fewer branches and registers held) */
  const int hertz = lean ? 0 : c->hertz, cohesion = lean ? 0 : c->cohesion;
  esf_contact_bond *const bond = lean ? NULL : c->bond;
  esf_contact_roll *const roll = lean ? NULL : c->roll;
  double *const lrows = lean && !ldn ? NULL : c->rows;
  const int nl = g->nl;
  const size_t *const kk = g->kk, *const ia = g->ia, *const ib = g->ib;
  size_t hk[ESF_BATCH]; /* byte offsets of the histories */
  vm tch;
  for (int l = 0; l < ESF_BATCH; l++) {
    hk[l] = kk[l] * sizeof(esf_contact_hist);
    tch[l] = -(long long)c->touch[kk[l]];
  }
  const vd zero = {0};
  vd kn, kt, mu, cnf, ctf, coh = zero, tl = zero;
  const esf_pair_params *pp[ESF_BATCH];
  if (c->one) { /* one material: the same parameters in every lane */
    for (int l = 0; l < ESF_BATCH; l++) pp[l] = c->one;
    kn = zero + c->one->kn;
    kt = zero + c->one->kt;
    mu = zero + c->one->mu;
    cnf = zero + c->one->cn_factor;
    ctf = zero + c->one->ct_factor;
    if (cohesion) coh += c->one->cohesion;
    if (bond) tl += c->one->tensile_limit;
  } else {
    const esf_materials *mt = c->mt;
    for (int l = 0; l < ESF_BATCH; l++)
      pp[l] = &mt->pair[c->material[ia[l]] * mt->n + c->material[ib[l]]];
    for (int l = 0; l < ESF_BATCH; l++) {
      kn[l] = pp[l]->kn;
      kt[l] = pp[l]->kt;
      mu[l] = pp[l]->mu;
      cnf[l] = pp[l]->cn_factor;
      ctf[l] = pp[l]->ct_factor;
      if (cohesion) coh[l] = pp[l]->cohesion;
      if (bond) tl[l] = pp[l]->tensile_limit;
    }
  }
  if (hertz) /* Hertz-Mindlin pairs (every pair: the laws never mix): hn, ht */
    for (int l = 0; l < ESF_BATCH; l++) {
      kn[l] = pp[l]->hn;
      kt[l] = pp[l]->ht;
    }
  vd cn = zero, ct = zero; /* the dashpots, N s/m (Hertz: below, at the overlap) */
  if (hertz) {
  } else if (c->beta > 0) {
    cn = c->beta * kn;
    ct = c->beta * kt;
  } else { /* c = factor sqrt(m*), sqrt(m*) per pair (computed at the list's build) */
    const vd sm = gat(c->sm, kk);
    cn = cnf * sm;
    ct = ctf * sm;
  }
  vd h0[4], h1[4], n[3], vc[3];
  load_cols((const char *)c->h + HXI, hk, h0); /* xi[0..2], n[0] */
  load_cols((const char *)c->h + HX2, hk, h1); /* xi[2], n[0..2] */
  const vd hx[3] = {h0[0], h0[1], h0[2]}, hn[3] = {h0[3], h1[2], h1[3]};
  for (int q = 0; q < 3; q++) {
    n[q] = gcol(g, G_N + q);
    vc[q] = gcol(g, G_VC + q);
  }
  const vd un = gcol(g, G_UN), la = gcol(g, G_LA), lb = gcol(g, G_LB);
  const vd vn = gcol(g, G_VN);
  const vd ra = hertz || roll ? gcol(g, G_RA) : zero, /* (written for these alone) */
      rb = hertz || roll ? gcol(g, G_RB) : zero;
  const vm in = gmask(g, G_IN), bad = gmask(g, G_BAD);
  vd st = zero, st0 = zero; /* Hertz: tangential stiffness now, at the last commit */
  vd sn = zero, sn0 = zero; /* Hertz: S_n now (rolling's kn), at the last commit */
  if (hertz) {              /* contact_hertz.h's operations, lane-wise */
    const vd rs = ra * rb / (ra + rb);
    vd ks, qa;
    esf_law_hertz_springs_v(kn, kt, rs, un, &ks, &sn, &st, &qa);
    const vd sm = gat(c->sm, kk);
    if (c->hertz_cst) {
      vd es;
      for (int l = 0; l < ESF_BATCH; l++) es[l] = pp[l]->estar;
      qa = esf_law_hertz_qref_v(es, sm, rs, pp[0]->v_imp);
    }
    esf_law_hertz_dashpots_v(c->beta, cnf, ctf, sm, qa, sn, st, &cn, &ct);
    if (lrows) st0 = esf_law_hertz_st_v(kt, rs, un + c->dt * vn);
    if (lrows && roll) sn0 = esf_law_hertz_sn_v(kn, rs, un + c->dt * vn);
    kn = ks;        /* the secant stiffness: fel = ks un */
    kt = zero + 1.; /* the record xi is the force */
  }
  vd fd, fel = kn * un, e_brk = zero;
  vd e_n = hertz ? esf_law_hertz_energy_v(kn, un) : 0.5 * kn * un * un;
  vd fn = esf_law_linear_normal_v(kn, cn, un, vn, &fd);
  /* Bonds (contact/contact_adhesive.c, 004 2.22-2.25): a bonded contact's normal spring
   * is the adhesive one at u = un + s, with the dashpot unclipped (it may pull); below
   * u_rupture the bond breaks: no force, the history restarts, the bond's energy is
   * booked. The same operations per lane as adhesive_eval's. */
  vm bonded = {0}, broke = {0};
  if (bond) {
    for (int l = 0; l < ESF_BATCH; l++)
      bonded[l] = -(long long)(bond[kk[l]].on && c->touch[kk[l]]);
    if (any(bonded)) {
      const vd fdv = -cn * vn;
      for (int l = 0; l < ESF_BATCH; l++) {
        if (!bonded[l]) continue;
        const esf_adhesion *A = &pp[l]->adh;
        const double u = un[l] + bond[kk[l]].s;
        if (u < A->u_rupture) {
          broke[l] = -1;
          e_brk[l] =
              esf_adhesion_energy(kn[l], A, u) +
              0.5 * kt[l] *
                  (hx[0][l] * hx[0][l] + hx[1][l] * hx[1][l] + hx[2][l] * hx[2][l]);
          continue;
        }
        fel[l] = esf_adhesion_force(kn[l], A, u);
        e_n[l] = esf_adhesion_energy(kn[l], A, u);
      }
      const vm pull = bonded & ~broke;
      fn = sel(pull, fel + fdv, fn);
      fd = sel(pull, fdv, fd);
    }
  }
  const vd spin = gcol(g, G_SPIN);
  esf_law_tpar_v P = {.kt = kt,
                      .ct = ct,
                      .mu = mu,
                      .coh = coh,
                      .tl = tl,
                      .rotate = c->rotate,
                      .tension = bond != NULL, /* only bonds pull */
                      .ledger = lrows != NULL,
                      .hertz = hertz,
                      .st = st,
                      .st0 = st0,
                      .vi = NULL};
  vd vim[3]; /* the ODE methods' carry (forces.c's eval_contact): (vc0 + vc)/2 live */
  if (gen && c->vc0) {
    vd c0[3];
    for (int l = 0; l < ESF_BATCH; l++)
      for (int q = 0; q < 3; q++) c0[q][l] = c->vc0[3 * kk[l] + q];
    for (int q = 0; q < 3; q++) vim[q] = sel(tch, 0.5 * (c0[q] + vc[q]), vc[q]);
    P.vi = vim;
  }
  esf_law_tout_v T;
  esf_law_tangential_v(&P, zero + c->dt, n, spin, vc, vn, fn, hx, hn, tch & ~broke, &T);
  vd m[3], f[3];
  esf_law_force_v(n, fn, T.ft, f, m);
  const vd *xi = T.xi;
  const vd f4[4] = {f[0], f[1], f[2], zero};
  vd ta[4] = {la * m[0], la * m[1], la * m[2], zero};
  vd tb[4] = {lb * m[0], lb * m[1], lb * m[2], zero};
  esf_law_rout_v R;
  if (roll) {
    vd wa[3], wb[3];
    for (int q = 0; q < 3; q++) {
      wa[q] = gcol(g, G_WA + q);
      wb[q] = gcol(g, G_WB + q);
    }
    rolling(c, pp, kk, ia, ib, hertz ? sn : kn, sn0, ra, rb, fn, n, wa, wb, tch & ~broke,
            &R, ta, tb);
  }
  const vm keep = (in | bonded) & ~broke; /* the contacts that go on */
  unsigned badmask = 0, gone = 0;         /* apart: the contact ended; past the limit */
  for (int l = 0; l < nl; l++)
    if (!keep[l])
      gone |= 1u << l;
    else if (bad[l])
      badmask |= 1u << l;
  /* the forces first, from registers (the history's commit below writes other memory,
     so the order changes no bit): the rows then need not outlive the commit loop */
  if (acc) {
    /* ldn (from esf_pair_batch_law alone): a light step's rows, without bonds or rolling
       resistance, go with the forces (light_dn_rows, light_dt_rows); a lane left out
       adds -0 there */
    v4 rf[ESF_BATCH], rta[ESF_BATCH], rtb[ESF_BATCH];
    rows_of(f4, rf);
    rows_of(ta, rta);
    rows_of(tb, rtb);
    v4 rdn[ESF_BATCH], rdt[ESF_BATCH], rma[ESF_BATCH], rmb[ESF_BATCH];
    const int ldt = ldn && !c->no_t;
    if (ldn) light_dn_rows(fd, n, T.slip, keep, rdn);
    if (ldt) light_dt_rows(c, T.fdt, n, la, lb, T.w_st, keep, rdt, rma, rmb);
    for (int l = 0; l < nl; l++) {
      if ((badmask | gone) >> l & 1u) continue;
      esf_pair_batch_acc_add(acc, ia[l], ib[l], rf[l], rta[l], rtb[l]);
      if (!ldn) continue;
      double *ra = lrows + c->lr * ia[l], *rb = lrows + c->lr * ib[l];
      v4_st(ra, v4_ld(ra) + rdn[l]);
      v4_st(rb, v4_ld(rb) + light_dn_b(rdn[l]));
      if (!ldt) continue;
      v4_st(ra + ESF_LR_DT, v4_ld(ra + ESF_LR_DT) + rdt[l]);
      v4_st(rb + ESF_LR_DT, v4_ld(rb + ESF_LR_DT) + light_dn_b(rdt[l]));
      v4_st(ra + ESF_LR_MDT, v4_ld(ra + ESF_LR_MDT) + rma[l]);
      v4_st(rb + ESF_LR_MDT, v4_ld(rb + ESF_LR_MDT) + rmb[l]);
    }
  } else {
    store_rows(f4, out, 0);
    store_rows(ta, out, 4);
    store_rows(tb, out, 8);
  }
  /* the history: xi and n[0] as one row, then n[1], n[2], the record's last 16 bytes */
  const vd c0[4] = {xi[0], xi[1], xi[2], n[0]};
  v4 hr[ESF_BATCH];
  rows_of(c0, hr);
  for (int l = 0; l < nl; l++) {
    if (gone >> l & 1u) {
      if (gen && c->trial) continue;
      c->touch[kk[l]] = 0;
      if (broke[l]) { /* as the linear law at un <= 0 commits: xi = 0, the normal */
        char *h = (char *)c->h + hk[l];
        const esf_contact_hist h0 = {{0, 0, 0}, {n[0][l], n[1][l], n[2][l]}};
        memcpy(h, &h0, sizeof h0);
        bond[kk[l]] = (esf_contact_bond){0};
        if (ia[l] >= c->own_lo && ia[l] < c->own_hi)
          atomic_fetch_add_explicit(c->broken, 1, memory_order_relaxed);
      }
      continue;
    }
    if (badmask >> l & 1u) continue;
    if (gen && c->trial) continue;
    if (gen && c->vc0)
      for (int q = 0; q < 3; q++) c->vc0[3 * kk[l] + q] = vc[q][l];
    char *h = (char *)c->h + hk[l];
    v4_st(h + HXI, hr[l]);
    const double n12[2] = {n[1][l], n[2][l]};
    memcpy(h + HN1, n12, sizeof n12);
    c->touch[kk[l]] = 1;
    if (roll)
      roll[kk[l]] = (esf_contact_roll){{R.hm[0][l], R.hm[1][l], R.hm[2][l]}, R.ht[l]};
  }
  if (lrows && !ldn)
    ledger_rows(c, kt, fd, fel, e_n, n, la, lb, &T, roll ? &R : NULL, keep, broke, e_brk,
                ia, ib, nl, badmask, acc ? NULL : lout);
  *apart = gone;
  return badmask;
}

/* The body three times: the leapfrog's batches without periodic images (gen 0: what
 * every other scene runs, with nothing of the images, the ODE methods' carry or their
 * trials in it; a test of each inside the batch made the S1 bed 5% slower,
 * docs/performance.md), the same for a light ledger step's rows added with the forces
 * (ldn: its test kept out of the others' copies), and the general one. */
__attribute__((noinline)) unsigned
esf_pair_batch_law(const esf_pair_batch_ctx *c, const esf_pair_geo *g,
                   double out[ESF_BATCH][ESF_BATCH_OUT],
                   double lout[ESF_BATCH][ESF_BATCH_LOUT], double *acc, unsigned *apart) {
  if (c->img || c->vc0 || c->trial)
    return batch_body(c, g, out, lout, acc, apart, 1, 0, 0);
  const int plain = !c->hertz && !c->bond && !c->roll && !c->cohesion;
  if (acc && c->rows && c->light && !c->roll && !c->bond)
    return plain ? batch_body(c, g, out, lout, acc, apart, 0, 1, 1)
                 : batch_body(c, g, out, lout, acc, apart, 0, 1, 0);
  if (plain && !c->rows) return batch_body(c, g, out, lout, acc, apart, 0, 0, 1);
  return batch_body(c, g, out, lout, acc, apart, 0, 0, 0);
}

unsigned esf_pair_batch_linear(const esf_pair_batch_ctx *c, const uint32_t *k, int nl,
                               double out[ESF_BATCH][ESF_BATCH_OUT],
                               double lout[ESF_BATCH][ESF_BATCH_LOUT], unsigned *apart) {
  esf_pair_geo g;
  esf_pair_batch_geometry(c, k, nl, &g);
  return esf_pair_batch_law(c, &g, out, lout, NULL, apart);
}
