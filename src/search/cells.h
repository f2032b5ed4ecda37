/* cells.h — contact-candidate search by linked cells (004 §3.5, Figs. 3.10–3.11).
 *
 * Finds every pair of particles whose surfaces are closer than `skin`,
 * |x_i - x_j| < r_i + r_j + skin, each pair exactly once, using a uniform grid of cells
 * of edge >= 2 r_max + skin over the particles' bounding box, HEAD/LIST linked lists and
 * the half-shell stencil (the own cell plus 13 of the 26 neighbours in 3D). In a 2D
 * scene (all y equal) the grid is one cell thick and the same stencil applies. A
 * polydisperse set is cut into size classes, each with its own grid sized for its own
 * radius; pairs across classes are found by querying the larger class's grid around
 * each smaller particle (cells.c).
 * Brute force O(N^2) is provided as the reference for tests. */
#ifndef ESF_CELLS_H
#define ESF_CELLS_H

#include <stddef.h>
#include <stdint.h>

#include "search/pairbuf.h"
#include "util/esf_error.h"

typedef struct esf_cells esf_cells; /* reusable grid storage (HEAD, LIST, cell index) */

#define ESF_CELLS_MAX_CLASSES 8 /* size classes of the polydisperse search, at most */

int esf_cells_create(esf_cells **out, esf_error *err);
void esf_cells_free(esf_cells **c);

/* Clears out and fills it with the pairs closer than skin (surface to surface).
 * x: 3n positions (m), radius: n radii (m). Non-finite positions are an ESF_ENUMERIC
 * error naming the particle. The grid never exceeds a few cells per particle: when the
 * bounding box is very large against the cell edge (a particle flew far) the edge grows.
 */
int esf_cells_pairs(esf_cells *c, size_t n, const double *x, const double *radius,
                    double skin, esf_pairbuf *out, esf_error *err);

/* How the search is organised; the pairs found never depend on it. */
typedef enum esf_cells_mode {
  ESF_CELLS_AUTO = 0,     /* size classes when a cost estimate says they pay (default) */
  ESF_CELLS_ONE_GRID = 1, /* always one grid sized for the largest particle */
  ESF_CELLS_CLASSES = 2   /* always size classes (at least two, maybe empty) */
} esf_cells_mode;

/* Tuning, for benchmarks and tests: the mode, and factor (> 1; 0: the default 2), the
 * target ratio of the largest to the smallest 2 r + skin within one size class. */
int esf_cells_tune(esf_cells *c, esf_cells_mode mode, double factor, esf_error *err);

#define ESF_CELLS_MAX_THREADS 64 /* threads of the one-grid sweep, at most */

/* Sweeps the one grid (the usual search) in `threads` slabs of cell layers at once
 * (clamped to 1 .. ESF_CELLS_MAX_THREADS; 1 until set). The pairs and their order do
 * not depend on it. */
void esf_cells_threads(esf_cells *c, int threads);

/* The number of grids the last search used: 1 (one grid, or no search needed) or the
 * number of size classes. */
int esf_cells_nclasses(const esf_cells *c);

/* Releases the storage kept for reuse (lists, class order, cells, the threads' pair
 * buffers): a caller that searches rarely (the candidate lists' builds) does not hold
 * it between searches. */
void esf_cells_trim(esf_cells *c);

/* The bytes of storage the search holds (lists, class order, cells of all grids). */
size_t esf_cells_bytes(const esf_cells *c);

/* The reference: all pairs by brute force, same criterion. */
int esf_pairs_brute(size_t n, const double *x, const double *radius, double skin,
                    esf_pairbuf *out, esf_error *err);

#endif
