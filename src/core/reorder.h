/* reorder.h — particles renumbered along cells at list rebuilds (reorder.c), so that
 * a pair's particles lie close in memory whatever order the scene defined them in.
 * Only for schemes that keep no per-particle state of their own between steps (the
 * leapfrog: s->reorder); frames are written in id order all the same (frames.c). */
#ifndef ESF_REORDER_H
#define ESF_REORDER_H

#include <math.h>
#include <stdint.h>

#include "core/sim.h"

/* The renumbering's grid: cells of h (or coarser, at most 2n cells) over the box
 * [lo, hi], the axes ranked ax[0] (most cells, slowest) .. ax[2] (fastest); a cell's
 * key is (c0 d1 + c1) d2 + c2 in that ranking, its plane c0 = key / (d1 d2). */
typedef struct esf_reorder_grid {
  double lo[3], h, dims[3];
  int ax[3];
  size_t d1, d2, ncell;
} esf_reorder_grid;

void esf_reorder_grid_make(esf_reorder_grid *g, const double lo[3], const double hi[3],
                           double h, size_t n);

/* The key of the cell holding x (clamped into the grid). */
static inline uint32_t esf_reorder_key(const esf_reorder_grid *g, const double *x) {
  size_t c[3];
  for (int q = 0; q < 3; q++) {
    const double f = floor((x[g->ax[q]] - g->lo[g->ax[q]]) / g->h);
    const size_t m = (size_t)g->dims[g->ax[q]] - 1;
    c[q] = f > 0 ? ((size_t)f < m ? (size_t)f : m) : 0;
  }
  return (uint32_t)((c[0] * g->d1 + c[1]) * g->d2 + c[2]);
}

/* Renumbers the particles in cell order when that differs from the current order
 * (*changed = 1); the candidate lists are then renumbered and a build must follow
 * before they are used. Call it right before esf_neighbor_build. */
int esf_reorder_particles(esf_sim *s, int *changed, esf_error *err);

#endif
