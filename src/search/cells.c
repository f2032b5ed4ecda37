/* cells.c — contact-candidate search by linked cells (004 §3.5, Figs. 3.10–3.11), with
 * size classes for polydisperse sets (the idea of LAMMPS's `neighbor multi`;
 * docs/physics.md#contact-search).
 *
 * Criterion, shared bit-for-bit with the brute-force reference: with d the difference
 * of the two positions and c = (r_i + r_j) + skin, a pair is a candidate when c > 0 and
 * d·d < c·c (no square root). Pairs are stored as (min, max) index, each once, in an
 * order fixed by the sweep, so the output is deterministic.
 * One grid (the size ratio is small): a uniform grid of cells of edge >= 2 r_max + skin
 * over the bounding box, the half-shell sweep (cells_grid.c; esf_cells_pairs). Size
 * classes: each class of similar cutoffs 2 r + skin gets its own grid, and a pair
 * across two classes is found once, from the smaller side (the size-classes section);
 * the set found is the same as the single grid's and brute force's. ESF_CELLS_AUTO
 * chooses between the two by a cost estimate (classes_pay). Memory: struct esf_cells.
 * Units: positions, radii and skin in m. On entry: x holds 3n finite doubles, radius n
 * finite non-negative ones (checked: a non-finite position is ESF_ENUMERIC naming the
 * particle, a bad radius or skin ESF_EINPUT). On exit: out holds the candidate pairs
 * (cleared first, also on error); the grid storage in esf_cells is kept for reuse. */
#include "search/cells.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "search/cells_grid.h"

#define CELLS_FACTOR_DEFAULT 2.0 /* target ratio of s within one class */
#define CELLS_MIN_RATIO      2.0 /* below this S the classes never paid (bench_cells) */
#define CELLS_GAIN           0.8 /* classes when their estimate is below this share */
/* cost weights in units of one distance test, fitted to bench_cells
 * (docs/performance.md#contact-search-for-polydisperse-beds): */
#define COST_PART_ONE 78.0 /* per particle, one grid (scan, threading, sweep) */
#define COST_PART_CLASSES                                                                \
  38.0                  /* per particle, with classes (their cells counted apart) */
#define COST_CELL  65.0 /* per cell of a class grid */
#define COST_QCELL 6.6  /* per cell visited by a box query */

/* Memory, added per particle over the single grid: the class order (4 bytes) and the
 * class index (1 byte); each class grid is capped like the single grid (max(64, 4 n_k)
 * cells, 4 bytes a cell) and LIST (4 bytes) is shared. Storage is kept for reuse, so
 * a search that switches between the modes holds the single grid's cells as well:
 * esf_cells_bytes reports the total. */
struct esf_cells {
  uint32_t *list;        /* LIST: next particle in the same cell (shared by all grids) */
  uint32_t *ord;         /* the particles ordered by class, ascending within a class */
  uint8_t *cls;          /* the class of each particle */
  size_t cap, class_cap; /* particles allocated in list; in ord and cls */
  esf_grid grid[ESF_CELLS_MAX_CLASSES];
  esf_cells_mode mode; /* tuning (esf_cells_tune) */
  int threads;         /* threads of the one-grid sweep (esf_cells_threads) */
  esf_pairbuf tbuf[ESF_CELLS_MAX_THREADS]; /* their pair buffers (during a sweep) */
  int nclasses;                            /* grids used by the last search */
  double factor;
};

/* ---- input scan ---------------------------------------------------------------------
 */

/* Checks the input and finds the bounding box and the extreme radii. */
static int scan(size_t n, const double *x, const double *radius, double skin,
                double lo[3], double hi[3], double *rmin, double *rmax, esf_error *err) {
  if (!isfinite(skin))
    return esf_fail(err, ESF_EINPUT, "the neighbour-search skin is not finite (%g)",
                    skin);
  if (n >= (size_t)ESF_CELL_EMPTY)
    return esf_fail(err, ESF_EINPUT, "too many particles for the contact search (%zu)",
                    n);
  if (n && (!x || !radius))
    return esf_fail(err, ESF_EINTERNAL, "contact search: no position or radius array");
  double r = 0, rs = n ? INFINITY : 0;
  for (int d = 0; d < 3; d++) lo[d] = hi[d] = n ? x[d] : 0;
  for (size_t i = 0; i < n; i++) {
    const double *p = x + 3 * i;
    if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2]))
      return esf_fail(err, ESF_ENUMERIC,
                      "particle %zu has a non-finite position (%g, %g, %g)", i, p[0],
                      p[1], p[2]);
    if (!(radius[i] >= 0) || !isfinite(radius[i]))
      return esf_fail(err, ESF_EINPUT, "particle %zu has an invalid radius (%g m)", i,
                      radius[i]);
    for (int d = 0; d < 3; d++) {
      if (p[d] < lo[d]) lo[d] = p[d];
      if (p[d] > hi[d]) hi[d] = p[d];
    }
    if (radius[i] > r) r = radius[i];
    if (radius[i] < rs) rs = radius[i];
  }
  *rmin = rs;
  *rmax = r;
  return ESF_OK;
}

/* ---- storage ------------------------------------------------------------------------
 */

int esf_cells_create(esf_cells **out, esf_error *err) {
  *out = calloc(1, sizeof **out);
  if (!*out) return esf_fail(err, ESF_ENOMEM, "out of memory for the cell grid");
  (*out)->mode = ESF_CELLS_AUTO;
  (*out)->factor = CELLS_FACTOR_DEFAULT;
  return ESF_OK;
}

void esf_cells_trim(esf_cells *c) {
  free(c->list);
  free(c->ord);
  free(c->cls);
  c->list = c->ord = NULL;
  c->cls = NULL;
  c->cap = c->class_cap = 0;
  for (int k = 0; k < ESF_CELLS_MAX_CLASSES; k++) esf_grid_release(&c->grid[k]);
  for (int t = 0; t < ESF_CELLS_MAX_THREADS; t++) esf_pairbuf_release(&c->tbuf[t]);
}

void esf_cells_free(esf_cells **c) {
  if (!c || !*c) return;
  esf_cells_trim(*c);
  free(*c);
  *c = NULL;
}

int esf_cells_tune(esf_cells *c, esf_cells_mode mode, double factor, esf_error *err) {
  if (factor == 0) factor = CELLS_FACTOR_DEFAULT;
  if ((mode != ESF_CELLS_AUTO && mode != ESF_CELLS_ONE_GRID &&
       mode != ESF_CELLS_CLASSES) ||
      !(factor > 1) || !isfinite(factor))
    return esf_fail(err, ESF_EINPUT,
                    "contact search tuning: unknown mode %d or factor %g not finite > 1",
                    (int)mode, factor);
  c->mode = mode;
  c->factor = factor;
  return ESF_OK;
}

void esf_cells_threads(esf_cells *c, int threads) {
  c->threads = threads < 1                       ? 1
               : threads > ESF_CELLS_MAX_THREADS ? ESF_CELLS_MAX_THREADS
                                                 : threads;
}

int esf_cells_nclasses(const esf_cells *c) { return c->nclasses; }

size_t esf_cells_bytes(const esf_cells *c) {
  size_t b = sizeof *c + c->cap * sizeof *c->list +
             c->class_cap * (sizeof *c->ord + sizeof *c->cls);
  for (int k = 0; k < ESF_CELLS_MAX_CLASSES; k++)
    b += c->grid[k].head_cap * sizeof *c->grid[k].head;
  return b;
}

/* Grows *a to hold n elements of size sz (contents dropped); *cap tracks it. */
static int grow(void **a, size_t *cap, size_t n, size_t sz, esf_error *err) {
  if (n <= *cap) return ESF_OK;
  free(*a);
  *a = malloc(n * sz);
  *cap = *a ? n : 0;
  if (!*a)
    return esf_fail(err, ESF_ENOMEM, "out of memory for the cell lists of %zu particles",
                    n);
  return ESF_OK;
}

/* ---- size classes -------------------------------------------------------------------
 */

/* Size classes: let s_i = 2 r_i + skin, the cutoff a particle brings to a pair with its
 * twin, and S the ratio of the largest s to the smallest positive s. The particles are
 * cut into K = ceil(log S / log f) classes (f = 2 by default, at least 2, at most
 * ESF_CELLS_MAX_CLASSES) of equal ratio F = S^(1/K) in s: class 0 holds the largest,
 * s in (s_max / F, s_max], class k s in (s_max / F^(k+1), s_max / F^k], the last class
 * everything smaller (also s <= 0). Each class k gets its own grid over its own
 * bounding box with edge 2 R_k + skin, R_k its largest radius, and finds its own pairs
 * by the half-shell sweep. A pair between class k and a larger class m < k is found
 * once, from the smaller side: each particle i of class k queries the grid of class m
 * over the box of half-width r_i + R_m + skin around it (at most 3, usually 2 cells per
 * axis since that reach is <= class m's edge). Each pair is thus tested in exactly one
 * place, and the set found is the same as the single grid's and brute force's. Cost:
 * small particles are tested against small-cell neighbourhoods only, so a small-small
 * pair no longer costs the 27 large cells of the single grid; overhead: one pass to
 * classify, a counting sort, and per particle one box query per larger class. */

typedef struct class_info {
  size_t start, count; /* the class's slice of ord */
  double lo[3], hi[3]; /* its bounding box (m) */
  double rmax;         /* its largest radius (m) */
} class_info;

/* The class plan for a size ratio S: K classes of ratio F = S^(1/K) in s, and the
 * bounds. */
typedef struct class_plan {
  int K;
  double bound[ESF_CELLS_MAX_CLASSES]; /* s <= bound[k]: class k + 1 or smaller */
} class_plan;

static void plan_classes(class_plan *pl, double smax, double S, double factor) {
  int K = (int)ceil(log(S) / log(factor) - 1e-9);
  if (K < 2) K = 2;
  if (K > ESF_CELLS_MAX_CLASSES) K = ESF_CELLS_MAX_CLASSES;
  pl->K = K;
  double F = pow(S, 1.0 / K);
  double b = smax;
  for (int k = 0; k < K - 1; k++) pl->bound[k] = b /= F;
}

static inline int class_of(const class_plan *pl, double s) {
  int k = 0;
  while (k < pl->K - 1 && s <= pl->bound[k]) k++;
  return k;
}

/* Classifies the particles, fills ord (by class, ascending) and info. */
static void classify(esf_cells *c, size_t n, const double *x, const double *radius,
                     double skin, const class_plan *pl, class_info *info) {
  const int K = pl->K;
  for (int k = 0; k < K; k++) {
    info[k].count = 0;
    info[k].rmax = 0;
  }
  for (size_t i = 0; i < n; i++) {
    const int k = class_of(pl, 2 * radius[i] + skin);
    c->cls[i] = (uint8_t)k;
    class_info *ci = &info[k];
    const double *p = x + 3 * i;
    if (ci->count++ == 0)
      for (int d = 0; d < 3; d++) ci->lo[d] = ci->hi[d] = p[d];
    for (int d = 0; d < 3; d++) {
      if (p[d] < ci->lo[d]) ci->lo[d] = p[d];
      if (p[d] > ci->hi[d]) ci->hi[d] = p[d];
    }
    if (radius[i] > ci->rmax) ci->rmax = radius[i];
  }
  size_t fill[ESF_CELLS_MAX_CLASSES], at = 0;
  for (int k = 0; k < K; k++) {
    info[k].start = fill[k] = at;
    at += info[k].count;
  }
  for (size_t i = 0; i < n; i++) c->ord[fill[c->cls[i]]++] = (uint32_t)i;
}

/* ---- cost estimate ------------------------------------------------------------------
 */

/* The cells per axis (nc) of the grid esf_grid_build makes of edge h over extent ext
 * for n particles (esf_grid_dims); returns their count. */
static double est_cells(const double ext[3], double h, double n, double nc[3]) {
  int64_t k[3];
  double inv_h[3], C = 1;
  esf_grid_dims(ext, h, (size_t)n, k, inv_h);
  for (int d = 0; d < 3; d++) {
    nc[d] = (double)k[d];
    C *= nc[d];
  }
  return C;
}

/* The estimated distance tests of the half-shell sweep of n particles spread evenly
 * over C cells (nc per axis). */
static double est_tests(double n, double C, const double nc[3]) {
  double nb = 1; /* cells of the full stencil */
  for (int d = 0; d < 3; d++) nb *= fmin(3, nc[d]);
  return n * (n / C) * nb / 2;
}

/* Whether the classes of plan pl are estimated to cost less than one grid, all classes
 * spread evenly over the box of extent ext (the mixed bed the classes are made for).
 * Choice (ESF_CELLS_AUTO): one grid when S < 2 (CELLS_MIN_RATIO); otherwise a pass over
 * the radii counts the classes and both searches are estimated as if every class filled
 * the bounding box evenly: distance tests n (n / cells) (stencil cells) / 2 per grid
 * and n_k (n_m / cells_m) (query cells) per class pair, plus costs per particle, per
 * class-grid cell and per cell visited by a query, weighted as fitted to bench_cells
 * (COST_*). Classes are taken when their estimate is below 0.8 (CELLS_GAIN) of the
 * single grid's. They lose where a large cell holds only a few particles (the extra
 * passes cost more than the tests saved) and win where the small ones are numerous
 * (docs/performance.md#contact-search-for-polydisperse-beds). */
static int classes_pay(size_t n, const double *radius, double skin, double smax,
                       const double ext[3], const class_plan *pl) {
  double cnt[ESF_CELLS_MAX_CLASSES] = {0};
  for (size_t i = 0; i < n; i++) cnt[class_of(pl, 2 * radius[i] + skin)] += 1;
  double nc[ESF_CELLS_MAX_CLASSES][3], C[ESF_CELLS_MAX_CLASSES], h[ESF_CELLS_MAX_CLASSES];
  double one[3], N = (double)n;
  double single = est_tests(N, est_cells(ext, smax, N, one), one) + COST_PART_ONE * N;
  double multi = COST_PART_CLASSES * N;
  for (int k = 0; k < pl->K; k++) {
    h[k] = k ? pl->bound[k - 1] : smax; /* the largest s the class may hold */
    if (cnt[k] == 0) continue;
    C[k] = est_cells(ext, h[k], cnt[k], nc[k]);
    multi += est_tests(cnt[k], C[k], nc[k]) + COST_CELL * C[k];
    for (int m = 0; m < k; m++) {
      if (cnt[m] == 0) continue;
      double cells = 1; /* cells of class m's grid in one box query from class k */
      for (int d = 0; d < 3; d++)
        if (nc[m][d] > 1) cells *= fmin(nc[m][d], 1 + (h[k] + h[m]) * nc[m][d] / ext[d]);
      multi += cnt[k] * cells * (cnt[m] / C[m] + COST_QCELL);
    }
  }
  return multi < CELLS_GAIN * single;
}

static int pairs_by_class(esf_cells *c, size_t n, const double *x, const double *radius,
                          double skin, const class_plan *pl, esf_pairbuf *out,
                          esf_error *err) {
  const int K = pl->K;
  if (n > c->class_cap) { /* ord and cls, only when the classes are used */
    size_t cap = c->class_cap, cap2 = c->class_cap;
    int rc = grow((void **)&c->ord, &cap, n, sizeof *c->ord, err);
    if (!rc) rc = grow((void **)&c->cls, &cap2, n, sizeof *c->cls, err);
    c->class_cap = rc ? 0 : n;
    if (rc) return rc;
  }
  class_info info[ESF_CELLS_MAX_CLASSES];
  classify(c, n, x, radius, skin, pl, info);
  int built[ESF_CELLS_MAX_CLASSES] = {0};
  for (int k = 0; k < K; k++) {
    const class_info *ci = &info[k];
    double edge = 2 * ci->rmax + skin;
    if (ci->count == 0 || !(edge > 0)) continue; /* no pair with a twin of the class */
    int rc = esf_grid_build(&c->grid[k], ci->count, c->ord + ci->start, x, ci->lo, ci->hi,
                            edge, c->list, err);
    if (!rc) rc = esf_grid_self_pairs(&c->grid[k], c->list, x, radius, skin, out, err);
    if (rc) return rc;
    built[k] = 1;
  }
  /* cross pairs from the smaller side; a larger class without a grid has
     2 R_m + skin <= 0, so r_i + R_m + skin <= 0 for every smaller i: no pair */
  for (int k = 1; k < K; k++)
    for (int m = 0; m < k; m++) {
      if (!built[m] || info[k].count == 0) continue;
      int rc = esf_grid_cross_pairs(&c->grid[m], c->list, info[m].rmax, info[k].count,
                                    c->ord + info[k].start, x, radius, skin, out, err);
      if (rc) return rc;
    }
  return ESF_OK;
}

/* The one grid's pairs, swept in c->threads slabs of layers, each into its own
 * buffer, appended to out in slab order (the same pairs in the same order whatever the
 * thread count, as the slabs' sweeps are the serial sweep cut at layer boundaries). */
static int sweep_threaded(esf_cells *c, const esf_grid *g, const double *x,
                          const double *radius, double skin, esf_pairbuf *out,
                          esf_error *err) {
  const int T = c->threads > 1 && g->nc[2] > 1 ? c->threads : 1;
  if (T == 1) return esf_grid_self_pairs(g, c->list, x, radius, skin, out, err);
  int trc[ESF_CELLS_MAX_THREADS];
  esf_error terr[ESF_CELLS_MAX_THREADS];
#pragma omp parallel for num_threads(T) schedule(static, 1)
  for (int t = 0; t < T; t++) {
    const int64_t nz = g->nc[2], z0 = nz * t / T, z1 = nz * (t + 1) / T;
    esf_pairbuf b = c->tbuf[t]; /* a copy: the buffers' counts share cache lines, and a */
    b.n = 0;                    /* push into the array would bounce them between cores */
    trc[t] =
        esf_grid_self_pairs_layers(g, c->list, x, radius, skin, z0, z1, &b, &terr[t]);
    c->tbuf[t] = b;
  }
  for (int t = 0; t < T; t++) {
    if (trc[t]) {
      if (err) *err = terr[t];
      return trc[t];
    }
    const int rc = esf_pairbuf_append(out, &c->tbuf[t], err);
    esf_pairbuf_release(&c->tbuf[t]); /* the pairs held once, not twice, at the end */
    if (rc) return rc;
  }
  return ESF_OK;
}

/* One grid (the size ratio is small): a uniform grid of cells of edge >= 2 r_max + skin
 * over the bounding box, the half-shell sweep (cells_grid.c). Cost: with rho particles
 * per unit volume, about 27/2 · N · rho (2 r_max + skin)^3 distance tests. The classes
 * (above) when the mode asks for them, or in ESF_CELLS_AUTO when classes_pay. */
int esf_cells_pairs(esf_cells *c, size_t n, const double *x, const double *radius,
                    double skin, esf_pairbuf *out, esf_error *err) {
  out->n = 0;
  c->nclasses = 1;
  double lo[3], hi[3], rmin, rmax;
  int rc = scan(n, x, radius, skin, lo, hi, &rmin, &rmax, err);
  if (rc) return rc;
  double smax = 2 * rmax + skin, smin = 2 * rmin + skin;
  if (n < 2 || !(smax > 0)) return ESF_OK; /* r_i + r_j + skin <= smax: no pair */
  rc = grow((void **)&c->list, &c->cap, n, sizeof *c->list, err);
  if (rc) return rc;
  if (!(smin > 0)) { /* the smallest positive s: those with s <= 0 join the last class */
    smin = smax;
    for (size_t i = 0; i < n; i++) {
      double s = 2 * radius[i] + skin;
      if (s > 0 && s < smin) smin = s;
    }
  }
  double S = smax / smin;
  class_plan pl;
  int classes = c->mode == ESF_CELLS_CLASSES;
  if (c->mode == ESF_CELLS_AUTO && S >= CELLS_MIN_RATIO) {
    double ext[3];
    for (int d = 0; d < 3; d++) ext[d] = hi[d] - lo[d];
    plan_classes(&pl, smax, S, c->factor);
    classes = classes_pay(n, radius, skin, smax, ext, &pl);
  } else if (classes)
    plan_classes(&pl, smax, S, c->factor);
  if (classes) c->nclasses = pl.K;
  if (classes)
    rc = pairs_by_class(c, n, x, radius, skin, &pl, out, err);
  else {
    rc = esf_grid_build(&c->grid[0], n, NULL, x, lo, hi, smax, c->list, err);
    if (!rc) rc = sweep_threaded(c, &c->grid[0], x, radius, skin, out, err);
  }
  if (rc) out->n = 0;
  return rc;
}

int esf_pairs_brute(size_t n, const double *x, const double *radius, double skin,
                    esf_pairbuf *out, esf_error *err) {
  out->n = 0;
  double lo[3], hi[3], rmin, rmax;
  int rc = scan(n, x, radius, skin, lo, hi, &rmin, &rmax, err);
  if (rc) return rc;
  for (size_t i = 0; i < n; i++)
    for (size_t j = i + 1; j < n; j++)
      if (esf_pair_near(x + 3 * i, x + 3 * j, radius[i], radius[j], skin)) {
        rc = esf_pairbuf_push_ordered(out, (uint32_t)i, (uint32_t)j, err);
        if (rc) {
          out->n = 0;
          return rc;
        }
      }
  return ESF_OK;
}
