/* cells.c — contact-candidate search by linked cells (004 §3.5, Figs. 3.10–3.11).
 *
 * Algorithm: the particles' axis-aligned bounding box is cut into nx × ny × nz box cells
 * whose edges are all >= 2 r_max + skin (times 1 + 1e-6, a margin that absorbs the
 * rounding of the cell coordinates), so two particles closer than r_i + r_j + skin sit
 * in the same or in adjacent cells. Each particle is threaded onto the linked list of
 * its cell: HEAD[cell] is the first particle, LIST[i] the next one (Fig. 3.10); the
 * lists are built from the last particle down, so each runs in increasing index order.
 * Every cell is then paired with itself (each pair within it once) and with the 13
 * neighbours of the half shell (Fig. 3.11: +x; the row y+1; the whole layer z+1), so
 * every pair of adjacent cells is visited exactly once. The grid is not periodic;
 * neighbours outside it are skipped, which also covers a box flat in one or two
 * dimensions (a 2D scene is one cell thick). When the box is huge against the cell edge
 * (a particle flew far away) the edge grows until the grid holds at most max(64, 4n)
 * cells, so memory and the sweep over cells stay O(n).
 *
 * Criterion, shared bit-for-bit with the brute-force reference: with d the difference
 * of the two positions and c = (r_i + r_j) + skin, a pair is a candidate when c > 0 and
 * d·d < c·c (no square root). Pairs are stored as (min, max) index, each once, in an
 * order fixed by the grid sweep, so the output is deterministic.
 *
 * Units: positions, radii and skin in m. On entry: x holds 3n finite doubles, radius n
 * finite non-negative ones (checked: a non-finite position is ESF_ENUMERIC naming the
 * particle, a bad radius or skin ESF_EINPUT). On exit: out holds the candidate pairs
 * (cleared first, also on error); the grid storage in esf_cells is kept for reuse. */
#include "cells.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define CELL_EMPTY      UINT32_MAX
#define CELL_EDGE_SLACK 1e-6 /* relative margin of the cell edge over 2 r_max + skin */
#define CELL_MIN_CAP    64   /* the grid may always have this many cells */
#define CELL_PER_PART   4    /* ... or this many per particle */

struct esf_cells {
  uint32_t *head; /* HEAD: first particle of each cell, CELL_EMPTY if none */
  size_t head_cap;
  uint32_t *list; /* LIST: next particle in the same cell, CELL_EMPTY at the end */
  size_t list_cap;
};

/* ---- pair buffer ------------------------------------------------------------------ */

static int pairbuf_grow(esf_pairbuf *b, esf_error *err) {
  size_t cap = b->cap ? 2 * b->cap : 1024;
  if (cap <= b->cap || cap > SIZE_MAX / sizeof(uint32_t))
    return esf_fail(err, ESF_ENOMEM, "too many contact-candidate pairs (%zu)", b->cap);
  uint32_t *i = realloc(b->i, cap * sizeof *i);
  if (!i) return esf_fail(err, ESF_ENOMEM, "out of memory for %zu candidate pairs", cap);
  b->i = i;
  uint32_t *j = realloc(b->j, cap * sizeof *j);
  if (!j) return esf_fail(err, ESF_ENOMEM, "out of memory for %zu candidate pairs", cap);
  b->j = j;
  b->cap = cap;
  return ESF_OK;
}

int esf_pairbuf_push(esf_pairbuf *b, uint32_t i, uint32_t j, esf_error *err) {
  if (b->n == b->cap) {
    int rc = pairbuf_grow(b, err);
    if (rc) return rc;
  }
  b->i[b->n] = i;
  b->j[b->n] = j;
  b->n++;
  return ESF_OK;
}

void esf_pairbuf_release(esf_pairbuf *b) {
  if (!b) return;
  free(b->i);
  free(b->j);
  memset(b, 0, sizeof *b);
}

/* Stores the pair as (min, max); the fast path is a bounds check and two stores. */
static inline int push_pair(esf_pairbuf *b, uint32_t i, uint32_t j, esf_error *err) {
  if (b->n == b->cap) {
    int rc = pairbuf_grow(b, err);
    if (rc) return rc;
  }
  b->i[b->n] = i < j ? i : j;
  b->j[b->n] = i < j ? j : i;
  b->n++;
  return ESF_OK;
}

/* The pair criterion, the same expression for the cell search and the reference. */
static inline int is_near(const double *xi, const double *xj, double ri, double rj,
                          double skin) {
  double dx = xi[0] - xj[0], dy = xi[1] - xj[1], dz = xi[2] - xj[2];
  double c = (ri + rj) + skin;
  return c > 0 && dx * dx + dy * dy + dz * dz < c * c;
}

/* ---- input scan ---------------------------------------------------------------------
 */

/* Checks the input and finds the bounding box and the largest radius. */
static int scan(size_t n, const double *x, const double *radius, double skin,
                double lo[3], double hi[3], double *rmax, esf_error *err) {
  if (!isfinite(skin))
    return esf_fail(err, ESF_EINPUT, "the neighbour-search skin is not finite (%g)",
                    skin);
  if (n >= (size_t)CELL_EMPTY)
    return esf_fail(err, ESF_EINPUT, "too many particles for the contact search (%zu)",
                    n);
  if (n && (!x || !radius))
    return esf_fail(err, ESF_EINTERNAL, "contact search: no position or radius array");
  double r = 0;
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
  }
  *rmax = r;
  return ESF_OK;
}

/* ---- grid ---------------------------------------------------------------------------
 */

int esf_cells_create(esf_cells **out, esf_error *err) {
  *out = calloc(1, sizeof **out);
  if (!*out) return esf_fail(err, ESF_ENOMEM, "out of memory for the cell grid");
  return ESF_OK;
}

void esf_cells_free(esf_cells **c) {
  if (!c || !*c) return;
  free((*c)->head);
  free((*c)->list);
  free(*c);
  *c = NULL;
}

/* Cell counts per dimension for a box of extent ext: cell edges >= edge, at most cap
 * cells in all. inv_h[d] maps a coordinate offset to a cell coordinate. */
static void grid_dims(const double ext[3], double edge, size_t cap, int64_t nc[3],
                      double inv_h[3]) {
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

int esf_cells_pairs(esf_cells *c, size_t n, const double *x, const double *radius,
                    double skin, esf_pairbuf *out, esf_error *err) {
  out->n = 0;
  double lo[3], hi[3], rmax;
  int rc = scan(n, x, radius, skin, lo, hi, &rmax, err);
  if (rc) return rc;
  double edge = 2 * rmax + skin;
  if (n < 2 || !(edge > 0)) return ESF_OK; /* r_i + r_j + skin <= edge: no pair */

  double ext[3];
  for (int d = 0; d < 3; d++) {
    ext[d] = hi[d] - lo[d];
    if (!isfinite(ext[d]))
      return esf_fail(err, ESF_ENUMERIC,
                      "the particles span a non-finite extent along axis %d (%g to %g m)",
                      d, lo[d], hi[d]);
  }
  size_t cap = CELL_PER_PART * n;
  if (cap < CELL_MIN_CAP) cap = CELL_MIN_CAP;
  int64_t nc[3];
  double inv_h[3];
  grid_dims(ext, edge, cap, nc, inv_h);
  const int64_t nx = nc[0], ny = nc[1], nz = nc[2];
  const size_t ncell = (size_t)(nx * ny * nz);

  if (ncell > c->head_cap) {
    free(c->head);
    c->head = malloc(ncell * sizeof *c->head);
    c->head_cap = c->head ? ncell : 0;
    if (!c->head) return esf_fail(err, ESF_ENOMEM, "out of memory for %zu cells", ncell);
  }
  if (n > c->list_cap) {
    free(c->list);
    c->list = malloc(n * sizeof *c->list);
    c->list_cap = c->list ? n : 0;
    if (!c->list)
      return esf_fail(err, ESF_ENOMEM,
                      "out of memory for the cell lists of %zu particles", n);
  }
  uint32_t *head = c->head, *list = c->list;
  memset(head, 0xff, ncell * sizeof *head); /* all CELL_EMPTY */

  /* Thread the particles onto their cells' lists, last first (lists run ascending). */
  for (size_t i = n; i-- > 0;) {
    const double *p = x + 3 * i;
    int64_t cx = (int64_t)((p[0] - lo[0]) * inv_h[0]);
    int64_t cy = (int64_t)((p[1] - lo[1]) * inv_h[1]);
    int64_t cz = (int64_t)((p[2] - lo[2]) * inv_h[2]);
    if (cx >= nx) cx = nx - 1; /* the particles on the box's upper faces */
    if (cy >= ny) cy = ny - 1;
    if (cz >= nz) cz = nz - 1;
    size_t cell = (size_t)((cz * ny + cy) * nx + cx);
    list[i] = head[cell];
    head[cell] = (uint32_t)i;
  }

  /* The half shell: 13 of the 26 neighbours, so each adjacent pair of cells once. */
  static const int8_t shell[13][3] = {
      {1, 0, 0},  {-1, 1, 0}, {0, 1, 0}, {1, 1, 0},  {-1, -1, 1}, {0, -1, 1}, {1, -1, 1},
      {-1, 0, 1}, {0, 0, 1},  {1, 0, 1}, {-1, 1, 1}, {0, 1, 1},   {1, 1, 1}};
  int64_t delta[13];
  for (int s = 0; s < 13; s++)
    delta[s] = ((int64_t)shell[s][2] * ny + shell[s][1]) * nx + shell[s][0];

  size_t cell = 0;
  for (int64_t cz = 0; cz < nz; cz++)
    for (int64_t cy = 0; cy < ny; cy++)
      for (int64_t cx = 0; cx < nx; cx++, cell++) {
        uint32_t first = head[cell];
        if (first == CELL_EMPTY) continue;
        /* pairs within the cell, each once */
        for (uint32_t i = first; i != CELL_EMPTY; i = list[i]) {
          const double *xi = x + 3 * (size_t)i;
          const double ri = radius[i];
          for (uint32_t j = list[i]; j != CELL_EMPTY; j = list[j])
            if (is_near(xi, x + 3 * (size_t)j, ri, radius[j], skin)) {
              rc = push_pair(out, i, j, err);
              if (rc) goto fail;
            }
        }
        /* pairs with the half-shell neighbours */
        for (int s = 0; s < 13; s++) {
          int64_t ox = cx + shell[s][0], oy = cy + shell[s][1], oz = cz + shell[s][2];
          if (ox < 0 || ox >= nx || oy < 0 || oy >= ny || oz >= nz) continue;
          uint32_t other = head[(size_t)((int64_t)cell + delta[s])];
          if (other == CELL_EMPTY) continue;
          for (uint32_t i = first; i != CELL_EMPTY; i = list[i]) {
            const double *xi = x + 3 * (size_t)i;
            const double ri = radius[i];
            for (uint32_t j = other; j != CELL_EMPTY; j = list[j])
              if (is_near(xi, x + 3 * (size_t)j, ri, radius[j], skin)) {
                rc = push_pair(out, i, j, err);
                if (rc) goto fail;
              }
          }
        }
      }
  return ESF_OK;
fail:
  out->n = 0;
  return rc;
}

int esf_pairs_brute(size_t n, const double *x, const double *radius, double skin,
                    esf_pairbuf *out, esf_error *err) {
  out->n = 0;
  double lo[3], hi[3], rmax;
  int rc = scan(n, x, radius, skin, lo, hi, &rmax, err);
  if (rc) return rc;
  for (size_t i = 0; i < n; i++)
    for (size_t j = i + 1; j < n; j++)
      if (is_near(x + 3 * i, x + 3 * j, radius[i], radius[j], skin)) {
        rc = push_pair(out, (uint32_t)i, (uint32_t)j, err);
        if (rc) {
          out->n = 0;
          return rc;
        }
      }
  return ESF_OK;
}
