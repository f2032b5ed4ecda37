/* reorder.c — particles renumbered along a grid of cells at list rebuilds (reorder.h).
 *
 * Why: the fused step (fused/fused.c) visits the pairs in ascending particle order and
 * adds each pair's force into its higher-numbered particle b. The particles between a
 * and b form a window whose data (positions, velocities, spins, accumulators, about
 * 150 bytes each) must stay in the core's L2 cache while the pass sweeps through it,
 * or every such access waits on L3 or memory. Numbering the particles along cells
 * bounds the window by one slab of cells, whatever order the scene gave them in (a
 * random order runs slower: docs/performance.md#the-fused-step).
 * Algorithm: a grid over the particles' bounding box with cells of 2 r_mean + skin
 * (coarsened if it would have more than 2n cells); the cell coordinates are ranked so
 * that the axis with the most cells varies slowest and the one with the fewest
 * fastest: the slab between a particle and its neighbours one cell further along the
 * slowest axis is then the grid's smallest cross-section. A stable counting sort by
 * cell gives the new order (ties keep the previous order, so the result depends only
 * on the state). When the order changes, the particle arrays are permuted, the lists
 * renumbered (esf_neighbor_remap: a build must follow, and the history follows its
 * pairs), and p.f, p.t synchronised first.
 * Entry: positions finite (the list check has run). Exit: particles in cell order,
 * lists renumbered and out of (a, b) order until the build. */
#include "core/reorder.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "util/xsum.h"

void esf_reorder_grid_make(esf_reorder_grid *g, const double lo[3], const double hi[3],
                           double h, size_t n) {
  for (;;) { /* at most 2n cells */
    double cells = 1.0;
    for (int q = 0; q < 3; q++) cells *= g->dims[q] = floor((hi[q] - lo[q]) / h) + 1.0;
    if (cells <= 2.0 * (double)n) break;
    h *= 1.25;
  }
  int *ax = g->ax; /* slowest .. fastest: most cells first, ties in x, y, z */
  ax[0] = 0;
  ax[1] = 1;
  ax[2] = 2;
  for (int i = 1; i < 3; i++)
    for (int j = i; j > 0 && g->dims[ax[j]] > g->dims[ax[j - 1]]; j--) {
      const int t = ax[j];
      ax[j] = ax[j - 1];
      ax[j - 1] = t;
    }
  for (int q = 0; q < 3; q++) g->lo[q] = lo[q];
  g->h = h;
  g->d1 = (size_t)g->dims[ax[1]];
  g->d2 = (size_t)g->dims[ax[2]];
  g->ncell = (size_t)g->dims[0] * (size_t)g->dims[1] * (size_t)g->dims[2];
}

int esf_reorder_particles(esf_sim *s, int *changed, esf_error *err) {
  esf_particles *p = &s->p;
  const size_t n = p->n;
  *changed = 0;
  if (n < 3) return ESF_OK;
  double lo[3], hi[3];
  esf_xsum rsum; /* exact: the cell size does not depend on the particles' order */
  esf_xsum_zero(&rsum);
  for (int q = 0; q < 3; q++) lo[q] = hi[q] = p->x[q];
  for (size_t i = 0; i < n; i++) {
    for (int q = 0; q < 3; q++) {
      const double v = p->x[3 * i + q];
      lo[q] = v < lo[q] ? v : lo[q];
      hi[q] = v > hi[q] ? v : hi[q];
    }
  }
  esf_xsum_add_n(&rsum, p->radius, n, 1);
  esf_reorder_grid g;
  esf_reorder_grid_make(&g, lo, hi, 2.0 * esf_xsum_value(&rsum) / (double)n + s->nb.skin,
                        n);
  const size_t ncell = g.ncell;
  uint32_t *key = malloc(n * sizeof *key);
  size_t *start = calloc(ncell + 1, sizeof *start);
  size_t *src = malloc(n * sizeof *src);
  size_t *remap = malloc(n * sizeof *remap);
  int rc = ESF_OK;
  if (!key || !start || !src || !remap) {
    rc = esf_fail(err, ESF_ENOMEM, "out of memory for reordering %zu particles", n);
    goto done;
  }
  const long nn = (long)n;
#pragma omp parallel for num_threads(esf_sim_threads_for(s, n))
  for (long ii = 0; ii < nn; ii++) {
    const size_t i = (size_t)ii;
    key[i] = esf_reorder_key(&g, p->x + 3 * i);
  }
  for (size_t i = 0; i < n; i++) start[key[i] + 1]++;
  for (size_t c = 0; c < ncell; c++) start[c + 1] += start[c];
  int same = 1;
  for (size_t i = 0; i < n; i++) { /* stable: ties keep the previous order */
    const size_t k = start[key[i]]++;
    src[k] = i;
    remap[i] = k;
    same &= k == i;
  }
  free(key); /* not held through the permutation (the peak memory) */
  free(start);
  key = NULL;
  start = NULL;
  if (same) goto done;
  rc = esf_sim_forces_sync(s, err);
  if (!rc) rc = esf_particles_permute(p, src, esf_sim_threads_for(s, n), err);
  if (rc) goto done;
  esf_neighbor_remap(&s->nb, remap, n);
  *changed = 1;
done:
  free(key);
  free(start);
  free(src);
  free(remap);
  return rc;
}
