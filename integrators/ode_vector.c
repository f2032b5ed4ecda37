/* ode_vector.c — the ODE methods' state vector (dem_ode.h: esf_dem_ode_vector):
 * SUNDIALS' OpenMP vector, its thread count the run's, with the operations ARKODE and
 * CVODE spend their vector time in replaced.
 *
 * Algorithm: a linear combination z = sum c_i X_i (a Runge-Kutta stage, a step's
 * solution), a linear sum, a scaling (a copy) and a constant run block by block over
 * BLOCK entries, every entry with the operations of SUNDIALS' serial vector in their
 * order, case by case (the same bits), written out here: the SUNDIALS 6.4.1 library
 * of the distribution is built without optimisation, and its combination makes one
 * pass over z per term, which here stays within a block in the cache. The blocks are
 * shared among the threads, each entry computed by one thread whatever their number:
 * the same bits on any thread count; the threads are those the force evaluation ran
 * on last (fewer while other programs keep them waiting: fused.c). The weighted RMS norm
 * is esfera's own, serial (a sum whose order must not depend on the threads), scaled by
 * the largest weight. esf_dem_ode_lincomb_nz (esfera's fixed-step Runge-Kutta driver,
 * erk.c): a combination without its zero terms, the entries that come out zero summed
 * again with all (the same bits). Entry: len entries, threads >= 1. Units: those of y. */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <nvector/nvector_openmp.h>

#include "integrators/dem_ode.h"

#define BLOCK  2048 /* entries per block: 16 kB a vector, a 13-stage sum in L2 */
#define SERIAL 8192 /* below this length, one thread */

/* The OpenMP vector's content, extended with the thread count the operations follow
 * (the evaluation path's: esf_eval_path.threads); its own num_threads stays 1, for
 * the operations of SUNDIALS' OpenMP vector not replaced here. Freed with free() by
 * N_VDestroy_OpenMP, as its own. */
typedef struct xcontent {
  struct _N_VectorContent_OpenMP c; /* first: SUNDIALS' macros read it */
  const int *threads;
} xcontent;

static inline int threads_of(N_Vector z) {
  const int t = *((const xcontent *)z->content)->threads;
  return t > 1 && NV_LENGTH_OMP(z) >= SERIAL ? t : 1;
}

/* Replaces v's content by an extended copy following *threads; NULL (v destroyed) when
 * out of memory. */
static N_Vector extend(N_Vector v, const int *threads) {
  if (!v) return NULL;
  xcontent *x = malloc(sizeof *x);
  if (!x) {
    N_VDestroy(v);
    return NULL;
  }
  memcpy(&x->c, v->content, sizeof x->c);
  x->c.num_threads = 1;
  x->threads = threads;
  free(v->content);
  v->content = x;
  return v;
}

static N_Vector clone(N_Vector w) {
  return extend(N_VClone_OpenMP(w), ((const xcontent *)w->content)->threads);
}

static N_Vector clone_empty(N_Vector w) {
  return extend(N_VCloneEmpty_OpenMP(w), ((const xcontent *)w->content)->threads);
}

/* The blocks of z's length: [b BLOCK, min((b + 1) BLOCK, n)). */
static inline sunindextype nblocks(N_Vector z) {
  return (NV_LENGTH_OMP(z) + BLOCK - 1) / BLOCK;
}

static inline sunindextype block_len(N_Vector z, sunindextype b) {
  const sunindextype n = NV_LENGTH_OMP(z), lo = b * BLOCK;
  return n - lo < BLOCK ? n - lo : BLOCK;
}

/* z = c x over m entries, as SUNDIALS' N_VScale: a copy for c = 1, else c x (for
 * c = -1 the same bits as its negation). z may be x. */
static inline void scale_m(double c, const double *x, double *z, sunindextype m) {
  if (c == 1.0) {
    if (z != x)
      for (sunindextype j = 0; j < m; j++) z[j] = x[j];
    return;
  }
  for (sunindextype j = 0; j < m; j++) z[j] = c * x[j];
}

/* z = a x + b y over m entries, as SUNDIALS' N_VLinearSum computes it, case by case
 * in its order (its special cases round differently from a x + b y only where
 * written out below: a (x + y) for a = b, a (x - y) for a = -b, a difference's sign of
 * zero). z may be x or y. */
static inline void linsum_m(double a, const double *x, double b, const double *y,
                            double *z, sunindextype m) {
  if ((b == 1.0 && z == y) || (a == 1.0 && z == x)) { /* y += a x, or x += b y */
    const double c = z == y && b == 1.0 ? a : b;
    const double *v = z == y && b == 1.0 ? x : y;
    if (c == 1.0)
      for (sunindextype j = 0; j < m; j++) z[j] = z[j] + v[j];
    else if (c == -1.0)
      for (sunindextype j = 0; j < m; j++) z[j] = z[j] - v[j];
    else
      for (sunindextype j = 0; j < m; j++) z[j] = z[j] + c * v[j];
    return;
  }
  if (a == 1.0 && b == 1.0) {
    for (sunindextype j = 0; j < m; j++) z[j] = x[j] + y[j];
    return;
  }
  if ((a == 1.0 && b == -1.0) || (a == -1.0 && b == 1.0)) { /* v2 - v1 */
    const double *v1 = a == 1.0 ? y : x, *v2 = a == 1.0 ? x : y;
    for (sunindextype j = 0; j < m; j++) z[j] = v2[j] - v1[j];
    return;
  }
  if (a == 1.0 || b == 1.0) { /* c v1 + v2 */
    const double c = a == 1.0 ? b : a;
    const double *v1 = a == 1.0 ? y : x, *v2 = a == 1.0 ? x : y;
    for (sunindextype j = 0; j < m; j++) z[j] = c * v1[j] + v2[j];
    return;
  }
  if (a == -1.0 || b == -1.0) { /* c v1 - v2 */
    const double c = a == -1.0 ? b : a;
    const double *v1 = a == -1.0 ? y : x, *v2 = a == -1.0 ? x : y;
    for (sunindextype j = 0; j < m; j++) z[j] = c * v1[j] - v2[j];
    return;
  }
  if (a == b) {
    for (sunindextype j = 0; j < m; j++) z[j] = a * (x[j] + y[j]);
    return;
  }
  if (a == -b) {
    for (sunindextype j = 0; j < m; j++) z[j] = a * (x[j] - y[j]);
    return;
  }
  for (sunindextype j = 0; j < m; j++) z[j] = a * x[j] + b * y[j];
}

/* lincomb_m's sum for N terms, entry by entry: the first term (c_0 x_0, or z, or c_0 z
 * when x_0 is z), then + c_i x_i in order, the partial sum in a register (the same
 * operations, so the same bits, as term by term; none of x_1 .. x_{N-1} may be z). */
static inline __attribute__((always_inline)) void lincomb_entries(int N, const double *c,
                                                                  const double *const *x,
                                                                  int first_z, double *zd,
                                                                  sunindextype m) {
  const double c0 = c[0];
  for (sunindextype j = 0; j < m; j++) {
    double s = !first_z ? c0 * x[0][j] : c0 != 1.0 ? zd[j] * c0 : zd[j];
    for (int i = 1; i < N; i++) s += c[i] * x[i][j];
    zd[j] = s;
  }
}

#define LINCOMB_FUSED 8 /* terms up to which lincomb_m sums entry by entry */

/* z = sum c_i X_i over m entries from offset lo, as SUNDIALS' N_VLinearCombination:
 * one or two vectors as a scaling or a linear sum; else z (or c_0 z, or c_0 X_0) then
 * z += c_i X_i term by term: entry by entry (lincomb_entries) up to LINCOMB_FUSED terms
 * when no later term is z, else each term a pass over the block (in the cache). */
static inline void lincomb_m(int nvec, const double *c, N_Vector *X, N_Vector z,
                             sunindextype lo, sunindextype m) {
  double *zd = NV_DATA_OMP(z) + lo;
  const double *x0 = NV_DATA_OMP(X[0]) + lo;
  if (nvec == 1) {
    scale_m(c[0], x0, zd, m);
    return;
  }
  if (nvec == 2) {
    linsum_m(c[0], x0, c[1], NV_DATA_OMP(X[1]) + lo, zd, m);
    return;
  }
  int later_z = 0;
  const double *x[LINCOMB_FUSED];
  for (int i = 0; i < nvec && i < LINCOMB_FUSED; i++) {
    x[i] = NV_DATA_OMP(X[i]) + lo;
    later_z |= i > 0 && X[i] == z;
  }
  const int first_z = X[0] == z;
  /* a constant N: the terms unrolled */
#define LINCOMB_N(N)                                                                     \
  if (nvec == N) {                                                                       \
    lincomb_entries(N, c, x, first_z, zd, m);                                            \
    return;                                                                              \
  }
  if (!later_z) {
    LINCOMB_N(3)
    LINCOMB_N(4)
    LINCOMB_N(5)
    LINCOMB_N(6)
    LINCOMB_N(7)
    LINCOMB_N(8)
  }
#undef LINCOMB_N
  if (X[0] != z)
    for (sunindextype j = 0; j < m; j++) zd[j] = c[0] * x0[j];
  else if (c[0] != 1.0)
    for (sunindextype j = 0; j < m; j++) zd[j] *= c[0];
  for (int i = 1; i < nvec; i++) {
    const double *xd = NV_DATA_OMP(X[i]) + lo, ci = c[i];
    for (sunindextype j = 0; j < m; j++) zd[j] += ci * xd[j];
  }
}

/* One operation's arguments, for its block function. */
typedef struct op_args {
  int nvec;
  const double *c;
  N_Vector *X;
  double a, b;
  N_Vector x, y, z;
} op_args;

/* fn(args, lo, m) over z's blocks, shared among the threads; on one thread, no
 * parallel region (its start costs more than a tiny scene's whole operation). */
static void each_block(void (*fn)(const op_args *, sunindextype, sunindextype),
                       const op_args *o) {
  const sunindextype nb = nblocks(o->z);
  const int nth = threads_of(o->z);
  if (nth > 1) {
#pragma omp parallel for num_threads(nth) schedule(static)
    for (sunindextype b = 0; b < nb; b++) fn(o, b * BLOCK, block_len(o->z, b));
    return;
  }
  for (sunindextype b = 0; b < nb; b++) fn(o, b * BLOCK, block_len(o->z, b));
}

static void lincomb_b(const op_args *o, sunindextype lo, sunindextype m) {
  lincomb_m(o->nvec, o->c, o->X, o->z, lo, m);
}

static int lincomb(int nvec, realtype *c, N_Vector *X, N_Vector z) {
  if (nvec < 1) return -1;
  const op_args o = {.nvec = nvec, .c = c, .X = X, .z = z};
  each_block(lincomb_b, &o);
  return 0;
}

static void linsum_b(const op_args *o, sunindextype lo, sunindextype m) {
  linsum_m(o->a, NV_DATA_OMP(o->x) + lo, o->b, NV_DATA_OMP(o->y) + lo,
           NV_DATA_OMP(o->z) + lo, m);
}

static void linsum(realtype a, N_Vector x, realtype b, N_Vector y, N_Vector z) {
  const op_args o = {.a = a, .b = b, .x = x, .y = y, .z = z};
  each_block(linsum_b, &o);
}

static void scale_b(const op_args *o, sunindextype lo, sunindextype m) {
  scale_m(o->a, NV_DATA_OMP(o->x) + lo, NV_DATA_OMP(o->z) + lo, m);
}

static void scale(realtype c, N_Vector x, N_Vector z) {
  const op_args o = {.a = c, .x = x, .z = z};
  each_block(scale_b, &o);
}

static void constant_b(const op_args *o, sunindextype lo, sunindextype m) {
  double *zd = NV_DATA_OMP(o->z) + lo;
  const double c = o->a;
  for (sunindextype j = 0; j < m; j++) zd[j] = c;
}

static void constant(realtype c, N_Vector z) {
  const op_args o = {.a = c, .z = z};
  each_block(constant_b, &o);
}

/* esf_dem_ode_lincomb_nz's block: the sum of the nonzero terms (o->nvec, o->c, o->X),
 * then the entries that came out zero again with all terms (o->b terms: o->cd, o->Xd),
 * one at a time (the same operations as over a block). full < 0: only that re-sum. */
typedef struct nz_args {
  op_args sparse;
  int full;
  const double *cd;
  N_Vector *Xd;
  long zeros;
} nz_args;

static void lincomb_nz_b(const op_args *o, sunindextype lo, sunindextype m) {
  nz_args *a = (nz_args *)o;
  if (a->full >= 0) lincomb_m(o->nvec, o->c, o->X, o->z, lo, m);
  const double *zd = NV_DATA_OMP(o->z);
  uint64_t any = 0; /* 1 when some |z_j| has all bits 0: integer operations, vectorised */
  for (sunindextype j = lo; j < lo + m; j++) {
    uint64_t u;
    memcpy(&u, zd + j, sizeof u);
    any |= ((u & 0x7fffffffffffffffULL) - 1) >> 63;
  }
  if (any) {
    long nz = 0;
    for (sunindextype j = lo; j < lo + m; j++)
      if (zd[j] == 0.0) {
        lincomb_m(a->full < 0 ? -a->full : a->full, a->cd, a->Xd, o->z, j, 1);
        nz++;
      }
#pragma omp atomic
    a->zeros += nz;
  }
}

long esf_dem_ode_lincomb_nz(int nvec, const double *c, N_Vector *X, N_Vector z,
                            int resum_only) {
  double cs[64];
  N_Vector xs[64];
  int n = 0;
  for (int i = 0; i < nvec; i++)
    if (c[i] != 0.0 && n < 64) {
      cs[n] = c[i];
      xs[n++] = X[i];
    }
  nz_args a = {.sparse = {.nvec = n, .c = cs, .X = xs, .z = z},
               .full = resum_only ? -nvec : nvec,
               .cd = c,
               .Xd = X};
  each_block(lincomb_nz_b, &a.sparse);
  return a.zeros;
}

/* sqrt(sum (x w)^2 / n) as W sqrt(sum (x w/W)^2 / n), W the largest weight: ARKODE
 * sets every weight to DBL_MIN in fixed-step runs, whose products with the state are
 * subnormal and cost a microcode assist each (SUNDIALS' own norm took a fifth of an rk4
 * run on S1); scaled, they are the state itself. Four interleaved partial sums, added
 * pairwise, so that the loop vectorises; serial, so that the sum's order does not
 * depend on the threads. */
static realtype wrms_norm(N_Vector x, N_Vector w) {
  const sunindextype n = NV_LENGTH_OMP(x);
  const realtype *a = NV_DATA_OMP(x), *b = NV_DATA_OMP(w);
  realtype big = 0;
  for (sunindextype i = 0; i < n; i++) big = fabs(b[i]) > big ? fabs(b[i]) : big;
  if (!(big > 0) || n == 0) return 0.0;
  const realtype inv = 1.0 / big;
  realtype s[4] = {0, 0, 0, 0};
  sunindextype i = 0;
  for (; i + 4 <= n; i += 4)
    for (int k = 0; k < 4; k++) {
      const realtype p = a[i + k] * (b[i + k] * inv);
      s[k] += p * p;
    }
  for (; i < n; i++) {
    const realtype p = a[i] * (b[i] * inv);
    s[0] += p * p;
  }
  return big * sqrt(((s[0] + s[1]) + (s[2] + s[3])) / (realtype)n);
}

N_Vector esf_dem_ode_vector(size_t len, const int *threads, SUNContext ctx) {
  N_Vector v = extend(N_VNew_OpenMP((sunindextype)len, 1, ctx), threads);
  if (!v) return NULL;
  N_VEnableFusedOps_OpenMP(v, SUNTRUE);
  v->ops->nvclone = clone;
  v->ops->nvcloneempty = clone_empty;
  v->ops->nvwrmsnorm = wrms_norm;
  v->ops->nvlinearcombination = lincomb;
  v->ops->nvlinearsum = linsum;
  v->ops->nvscale = scale;
  v->ops->nvconst = constant;
  return v;
}
