/* cells_grid.c — one uniform grid of linked cells over a subset of the particles
 * (004 §3.5, Figs. 3.10–3.11; docs/physics.md#contact-search), the building block of
 * the contact-candidate search:
 *   build: the subset's bounding box cut into box cells of edge >= edge, each particle
 *     threaded onto the linked list of its cell (esf_grid_build), cost O(m + cells);
 *   pairs within the grid: every cell with itself and the 13 neighbours of its half
 *     shell (esf_grid_self_pairs), about 27/2 · m · (particles per cell) distance tests;
 *   pairs with outside particles: for each, the grid's cells within its reach, at most
 *     3, usually 2 per axis (esf_grid_cross_pairs).
 * Units: positions, radii, edges and skin in m. On entry: finite positions and radii
 * (cells.c checks them). On exit: pairs are appended to out as (min, max) index. */
#include "search/cells_grid.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CELL_EDGE_SLACK  1e-6 /* relative margin of the cell edge over the given edge */
#define CELL_REACH_SLACK 1e-6 /* relative margin of a query's reach */
#define CELL_MIN_CAP     64   /* the grid may always have this many cells */
#define CELL_PER_PART    4    /* ... or this many per particle */

void esf_grid_release(esf_grid *g) {
  if (!g) return;
  free(g->head);
  g->head = NULL;
  g->head_cap = 0;
}

void esf_grid_dims(const double ext[3], double edge, size_t m, int64_t nc[3],
                   double inv_h[3]) {
  size_t cap = CELL_PER_PART * m;
  if (cap < CELL_MIN_CAP) cap = CELL_MIN_CAP;
  double h = edge * (1 + CELL_EDGE_SLACK), f[3];
  for (;;) {
    double prod = 1;
    int k = 0; /* dimensions that still have more than one cell */
    for (int d = 0; d < 3; d++) {
      f[d] = ext[d] / h;
      if (f[d] > 1e15) f[d] = 1e15; /* the product stays finite; refined below */
      f[d] = floor(f[d]);
      if (f[d] < 1) f[d] = 1;
      if (f[d] > 1) k++;
      prod *= f[d];
    }
    if (prod <= (double)cap) break;
    double g = pow(prod / (double)cap, 1.0 / k); /* k >= 1 since prod > cap >= 1 */
    h *= g > 1.001 ? g : 1.001;
  }
  for (int d = 0; d < 3; d++) {
    nc[d] = (int64_t)f[d];
    inv_h[d] = nc[d] > 1 ? f[d] / ext[d] : 0; /* cell edge ext/nc >= h */
  }
}

/* Build: the subset's axis-aligned bounding box is cut into nx × ny × nz box cells whose
 * edges are all >= edge (times 1 + 1e-6, a margin that absorbs the rounding of the cell
 * coordinates). Each particle is threaded onto the linked list of its cell: HEAD[cell]
 * is the first particle, LIST[i] the next one (Fig. 3.10); the lists are built from the
 * last particle down, so each runs in increasing index order. When the box is huge
 * against the edge (a particle flew far away) the edge grows until the grid holds at
 * most max(64, 4 m) cells (esf_grid_dims), so memory and the sweep over cells stay
 * O(m). Cost O(m + cells). */
int esf_grid_build(esf_grid *g, size_t m, const uint32_t *idx, const double *x,
                   const double lo[3], const double hi[3], double edge, uint32_t *list,
                   esf_error *err) {
  double ext[3];
  for (int d = 0; d < 3; d++) {
    g->lo[d] = lo[d];
    ext[d] = hi[d] - lo[d];
    if (!isfinite(ext[d]))
      return esf_fail(err, ESF_ENUMERIC,
                      "the particles span a non-finite extent along axis %d (%g to %g m)",
                      d, lo[d], hi[d]);
  }
  esf_grid_dims(ext, edge, m, g->nc, g->inv_h);
  const int64_t nx = g->nc[0], ny = g->nc[1], nz = g->nc[2];
  const size_t ncell = (size_t)(nx * ny * nz);
  if (ncell > g->head_cap) {
    free(g->head);
    g->head = malloc(ncell * sizeof *g->head);
    g->head_cap = g->head ? ncell : 0;
    if (!g->head) return esf_fail(err, ESF_ENOMEM, "out of memory for %zu cells", ncell);
  }
  uint32_t *head = g->head;
  memset(head, 0xff, ncell * sizeof *head); /* all ESF_CELL_EMPTY */

  /* Thread the particles onto their cells' lists, last first (lists run ascending). */
  for (size_t k = m; k-- > 0;) {
    uint32_t i = idx ? idx[k] : (uint32_t)k;
    const double *p = x + 3 * (size_t)i;
    int64_t cx = (int64_t)((p[0] - lo[0]) * g->inv_h[0]);
    int64_t cy = (int64_t)((p[1] - lo[1]) * g->inv_h[1]);
    int64_t cz = (int64_t)((p[2] - lo[2]) * g->inv_h[2]);
    if (cx >= nx) cx = nx - 1; /* the particles on the box's upper faces */
    if (cy >= ny) cy = ny - 1;
    if (cz >= nz) cz = nz - 1;
    size_t cell = (size_t)((cz * ny + cy) * nx + cx);
    list[i] = head[cell];
    head[cell] = i;
  }
  return ESF_OK;
}

/* Pairs within the grid: every cell is paired with itself (each pair within it once)
 * and with the 13 neighbours of the half shell (Fig. 3.11: +x; the row y+1; the whole
 * layer z+1), so every pair of adjacent cells is visited once. The grid is not periodic;
 * neighbours outside it are skipped, which also covers a box flat in one or two
 * dimensions (a 2D scene is one cell thick). With edge >= 2 r_max + skin of the subset,
 * two of its particles closer than r_i + r_j + skin sit in the same or adjacent cells.
 * Cost: the distance tests, about 27/2 · m · (particles per cell). */
int esf_grid_self_pairs(const esf_grid *g, const uint32_t *list, const double *x,
                        const double *radius, double skin, esf_pairbuf *out,
                        esf_error *err) {
  return esf_grid_self_pairs_layers(g, list, x, radius, skin, 0, g->nc[2], out, err);
}

int esf_grid_self_pairs_layers(const esf_grid *g, const uint32_t *list, const double *x,
                               const double *radius, double skin, int64_t z0, int64_t z1,
                               esf_pairbuf *out, esf_error *err) {
  const int64_t nx = g->nc[0], ny = g->nc[1], nz = g->nc[2];
  const uint32_t *head = g->head;
  /* The half shell: 13 of the 26 neighbours, so each adjacent pair of cells once. */
  static const int8_t shell[13][3] = {
      {1, 0, 0},  {-1, 1, 0}, {0, 1, 0}, {1, 1, 0},  {-1, -1, 1}, {0, -1, 1}, {1, -1, 1},
      {-1, 0, 1}, {0, 0, 1},  {1, 0, 1}, {-1, 1, 1}, {0, 1, 1},   {1, 1, 1}};
  int64_t delta[13];
  for (int s = 0; s < 13; s++)
    delta[s] = ((int64_t)shell[s][2] * ny + shell[s][1]) * nx + shell[s][0];

  int rc;
  size_t cell = (size_t)(z0 * ny * nx);
  for (int64_t cz = z0; cz < z1; cz++)
    for (int64_t cy = 0; cy < ny; cy++)
      for (int64_t cx = 0; cx < nx; cx++, cell++) {
        uint32_t first = head[cell];
        if (first == ESF_CELL_EMPTY) continue;
        /* pairs within the cell, each once */
        for (uint32_t i = first; i != ESF_CELL_EMPTY; i = list[i]) {
          const double *xi = x + 3 * (size_t)i;
          const double ri = radius[i];
          for (uint32_t j = list[i]; j != ESF_CELL_EMPTY; j = list[j]) {
            rc = esf_pairbuf_push_if(
                out, i, j, esf_pair_near(xi, x + 3 * (size_t)j, ri, radius[j], skin),
                err);
            if (rc) return rc;
          }
        }
        /* pairs with the half-shell neighbours */
        for (int s = 0; s < 13; s++) {
          int64_t ox = cx + shell[s][0], oy = cy + shell[s][1], oz = cz + shell[s][2];
          if (ox < 0 || ox >= nx || oy < 0 || oy >= ny || oz >= nz) continue;
          uint32_t other = head[(size_t)((int64_t)cell + delta[s])];
          if (other == ESF_CELL_EMPTY) continue;
          for (uint32_t i = first; i != ESF_CELL_EMPTY; i = list[i]) {
            const double *xi = x + 3 * (size_t)i;
            const double ri = radius[i];
            for (uint32_t j = other; j != ESF_CELL_EMPTY; j = list[j]) {
              rc = esf_pairbuf_push_if(
                  out, i, j, esf_pair_near(xi, x + 3 * (size_t)j, ri, radius[j], skin),
                  err);
              if (rc) return rc;
            }
          }
        }
      }
  return ESF_OK;
}

/* The cells [*c0, *c1] along one axis that can hold a grid particle within q of
 * coordinate v; 0 when the range misses the grid. */
static int axis_range(const esf_grid *g, int d, double v, double q, int64_t *c0,
                      int64_t *c1) {
  const int64_t n = g->nc[d];
  if (n == 1) {
    *c0 = *c1 = 0;
    return 1;
  }
  double a = floor((v - q - g->lo[d]) * g->inv_h[d]);
  double b = floor((v + q - g->lo[d]) * g->inv_h[d]);
  /* a particle on the upper face may map to n (then stored in n - 1), never beyond */
  if (b < 0 || a > (double)n) return 0;
  *c0 = a > 0 ? (int64_t)a : 0;
  *c1 = b < (double)(n - 1) ? (int64_t)b : n - 1;
  if (*c0 > n - 1) *c0 = n - 1;
  return 1;
}

/* Pairs with outside particles: for each outside particle i the reach is
 * q = ((r_i + r_grid) + skin)(1 + 1e-6), r_grid the grid's largest radius; every grid
 * particle j with |x_i - x_j| < r_i + r_j + skin lies within q of x_i along each axis,
 * so within the cells from floor((x_i - q - lo) / h) to floor((x_i + q - lo) / h)
 * (clamped to the grid; skipped when wholly outside it). Cell coordinates are monotonic
 * in the position, so the range holds every such j. With q <= edge the range is at most
 * 3 cells per axis, usually 2. Cost: the distance tests, the grid particles in those
 * cells. */
int esf_grid_cross_pairs(const esf_grid *g, const uint32_t *list, double rgrid, size_t m,
                         const uint32_t *idx, const double *x, const double *radius,
                         double skin, esf_pairbuf *out, esf_error *err) {
  const int64_t nx = g->nc[0], ny = g->nc[1];
  const uint32_t *head = g->head;
  for (size_t k = 0; k < m; k++) {
    const uint32_t i = idx[k];
    const double *xi = x + 3 * (size_t)i;
    const double ri = radius[i];
    const double reach = (ri + rgrid) + skin;
    if (!(reach > 0)) continue; /* no grid particle can be near */
    const double q = reach * (1 + CELL_REACH_SLACK);
    int64_t lo[3], hi[3];
    if (!axis_range(g, 0, xi[0], q, &lo[0], &hi[0]) ||
        !axis_range(g, 1, xi[1], q, &lo[1], &hi[1]) ||
        !axis_range(g, 2, xi[2], q, &lo[2], &hi[2]))
      continue;
    for (int64_t cz = lo[2]; cz <= hi[2]; cz++)
      for (int64_t cy = lo[1]; cy <= hi[1]; cy++) {
        const size_t row = (size_t)((cz * ny + cy) * nx);
        for (int64_t cx = lo[0]; cx <= hi[0]; cx++)
          for (uint32_t j = head[row + (size_t)cx]; j != ESF_CELL_EMPTY; j = list[j]) {
            const int rc = esf_pairbuf_push_if(
                out, i, j, esf_pair_near(xi, x + 3 * (size_t)j, ri, radius[j], skin),
                err);
            if (rc) return rc;
          }
      }
  }
  return ESF_OK;
}
