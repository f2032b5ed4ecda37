/* ode_vector.c — the ODE methods' state vector (dem_ode.h: esf_dem_ode_vector):
 * SUNDIALS' OpenMP vector, its thread count the run's, with the operations ARKODE and
 * CVODE spend their vector time in replaced by blocked ones.
 *
 * Algorithm: a linear combination z = sum c_i X_i (a Runge-Kutta stage, a step's
 * solution), a linear sum, a scaling (a copy) and a constant run block by block over
 * BLOCK entries, each block by SUNDIALS' own serial operation on views of the
 * vectors' entries there, so that every entry gets SUNDIALS' operations in SUNDIALS'
 * order (the same bits as the serial vector), while the several passes a serial
 * linear combination makes over z stay within a block in the cache; the blocks are
 * shared among the threads (each entry computed by one thread, whatever their number:
 * the same bits on any thread count). The weighted RMS norm is esfera's own, serial
 * (a sum whose order must not depend on the threads), scaled by the largest weight.
 * Entry: len entries, threads >= 1. Units: those of y (dem_ode.h). */
#include <math.h>
#include <nvector/nvector_openmp.h>
#include <nvector/nvector_serial.h>

#include "integrators/dem_ode.h"

#define BLOCK  2048 /* entries per block: 16 kB a vector, a 13-stage sum in L2 */
#define MAXV   32   /* vectors a blocked combination takes (more: SUNDIALS' own) */
#define SERIAL 8192 /* below this length, one thread */

/* A serial vector viewing n entries of data (the content and the generic record on
 * the caller's stack: SUNDIALS' serial operations read only the content). */
typedef struct view {
  struct _generic_N_Vector v;
  struct _N_VectorContent_Serial c;
} view;

static inline N_Vector view_of(view *w, realtype *data, sunindextype n) {
  w->c.length = n;
  w->c.own_data = SUNFALSE;
  w->c.data = data;
  w->v.content = &w->c;
  w->v.ops = NULL;
  w->v.sunctx = NULL;
  return &w->v;
}

static inline int threads_of(N_Vector z) { return NV_NUM_THREADS_OMP(z); }

/* The blocks of z's length: [b BLOCK, min((b + 1) BLOCK, n)). */
static inline sunindextype nblocks(N_Vector z) {
  return (NV_LENGTH_OMP(z) + BLOCK - 1) / BLOCK;
}

static inline sunindextype block_len(N_Vector z, sunindextype b) {
  const sunindextype n = NV_LENGTH_OMP(z), lo = b * BLOCK;
  return n - lo < BLOCK ? n - lo : BLOCK;
}

static int lincomb(int nvec, realtype *c, N_Vector *X, N_Vector z) {
  if (nvec < 1 || nvec > MAXV) return N_VLinearCombination_OpenMP(nvec, c, X, z);
  const sunindextype nb = nblocks(z);
#pragma omp parallel for num_threads(threads_of(z)) schedule(static)
  for (sunindextype b = 0; b < nb; b++) {
    const sunindextype lo = b * BLOCK, m = block_len(z, b);
    view vz, vx[MAXV];
    N_Vector Z = view_of(&vz, NV_DATA_OMP(z) + lo, m), V[MAXV];
    for (int i = 0; i < nvec; i++) /* X[i] == z stays z (SUNDIALS tests it) */
      V[i] = X[i] == z ? Z : view_of(vx + i, NV_DATA_OMP(X[i]) + lo, m);
    N_VLinearCombination_Serial(nvec, c, V, Z);
  }
  return 0;
}

static void linsum(realtype a, N_Vector x, realtype b, N_Vector y, N_Vector z) {
  const sunindextype nb = nblocks(z);
#pragma omp parallel for num_threads(threads_of(z)) schedule(static)
  for (sunindextype k = 0; k < nb; k++) {
    const sunindextype lo = k * BLOCK, m = block_len(z, k);
    view vx, vy, vz; /* aliases stay aliases (SUNDIALS tests them) */
    N_Vector Z = view_of(&vz, NV_DATA_OMP(z) + lo, m);
    N_VLinearSum_Serial(a, x == z ? Z : view_of(&vx, NV_DATA_OMP(x) + lo, m), b,
                        y == z ? Z : view_of(&vy, NV_DATA_OMP(y) + lo, m), Z);
  }
}

static void scale(realtype c, N_Vector x, N_Vector z) {
  const sunindextype nb = nblocks(z);
#pragma omp parallel for num_threads(threads_of(z)) schedule(static)
  for (sunindextype k = 0; k < nb; k++) {
    const sunindextype lo = k * BLOCK, m = block_len(z, k);
    view vx, vz;
    N_Vector Z = view_of(&vz, NV_DATA_OMP(z) + lo, m);
    N_VScale_Serial(c, x == z ? Z : view_of(&vx, NV_DATA_OMP(x) + lo, m), Z);
  }
}

static void constant(realtype c, N_Vector z) {
  const sunindextype nb = nblocks(z);
#pragma omp parallel for num_threads(threads_of(z)) schedule(static)
  for (sunindextype k = 0; k < nb; k++) {
    view vz;
    N_VConst_Serial(c, view_of(&vz, NV_DATA_OMP(z) + k * BLOCK, block_len(z, k)));
  }
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

N_Vector esf_dem_ode_vector(size_t len, int threads, SUNContext ctx) {
  /* short vectors on one thread: SUNDIALS' own OpenMP operations (those not replaced
     here) would otherwise open a team for a few thousand entries */
  const int t = threads > 1 && len >= SERIAL ? threads : 1;
  N_Vector v = N_VNew_OpenMP((sunindextype)len, t, ctx);
  if (!v) return NULL;
  N_VEnableFusedOps_OpenMP(v, SUNTRUE);
  v->ops->nvwrmsnorm = wrms_norm;
  v->ops->nvlinearcombination = lincomb;
  v->ops->nvlinearsum = linsum;
  v->ops->nvscale = scale;
  v->ops->nvconst = constant;
  return v;
}
