/* cells_grid.h — one uniform grid of linked cells over a subset of the particles, the
 * building block of the contact-candidate search (cells.c). Internal to the search.
 *
 * A grid covers the bounding box of its particles with cells of edge >= a given edge
 * (never more than a capped number of cells), threads each particle onto the linked list
 * of its cell (HEAD per cell, LIST per particle, shared by all grids since a particle
 * belongs to one grid), and answers two questions: the pairs within the grid (the
 * half-shell sweep) and the pairs between the grid and particles outside it (a box
 * query around each outside particle). */
#ifndef ESF_CELLS_GRID_H
#define ESF_CELLS_GRID_H

#include <stddef.h>
#include <stdint.h>

#include "search/pairbuf.h"
#include "util/esf_error.h"

#define ESF_CELL_EMPTY UINT32_MAX

typedef struct esf_grid {
  double lo[3];    /* lower corner of the bounding box (m) */
  double inv_h[3]; /* cells per metre along each axis (0 when one cell thick) (1/m) */
  int64_t nc[3];   /* cells along each axis */
  uint32_t *head;  /* HEAD: first particle of each cell, ESF_CELL_EMPTY if none */
  size_t head_cap; /* cells allocated */
} esf_grid;

void esf_grid_release(esf_grid *g);

/* Cell counts per axis of the grid esf_grid_build makes for m particles over a box of
 * extent ext (m): cell edges >= edge, at most max(64, 4 m) cells in all. inv_h[d] maps
 * a coordinate offset to a cell coordinate (0 when one cell thick). */
void esf_grid_dims(const double ext[3], double edge, size_t m, int64_t nc[3],
                   double inv_h[3]);

/* Builds the grid over the m particles idx[0..m) (ascending; idx NULL: particles 0..m-1)
 * whose bounding box is [lo, hi], cells of edge >= edge (> 0), at most max(64, 4 m)
 * cells. list[i] (indexed by particle) receives the next particle of i's cell; each
 * cell's list runs in ascending order. */
int esf_grid_build(esf_grid *g, size_t m, const uint32_t *idx, const double *x,
                   const double lo[3], const double hi[3], double edge, uint32_t *list,
                   esf_error *err);

/* Appends every pair within the grid closer than skin (surface to surface), once. */
int esf_grid_self_pairs(const esf_grid *g, const uint32_t *list, const double *x,
                        const double *radius, double skin, esf_pairbuf *out,
                        esf_error *err);

/* The same for the cells of layers z0 <= cz < z1 (with their half-shell neighbours,
 * which reach into layer z1): disjoint layer ranges give disjoint sets of pairs, so
 * threads can sweep a grid in slabs. */
int esf_grid_self_pairs_layers(const esf_grid *g, const uint32_t *list, const double *x,
                               const double *radius, double skin, int64_t z0, int64_t z1,
                               esf_pairbuf *out, esf_error *err);

/* Appends every pair (i, j), i one of the m particles idx[0..m) (none of them in the
 * grid), j in the grid, closer than skin. rgrid: the largest radius in the grid (m). */
int esf_grid_cross_pairs(const esf_grid *g, const uint32_t *list, double rgrid, size_t m,
                         const uint32_t *idx, const double *x, const double *radius,
                         double skin, esf_pairbuf *out, esf_error *err);

/* The pair criterion, the same expression for every search and the reference:
 * c = (r_i + r_j) + skin > 0 and d·d < c·c. */
static inline int esf_pair_near(const double *xi, const double *xj, double ri, double rj,
                                double skin) {
  double dx = xi[0] - xj[0], dy = xi[1] - xj[1], dz = xi[2] - xj[2];
  double c = (ri + rj) + skin;
  return c > 0 && dx * dx + dy * dy + dz * dz < c * c;
}

#endif
