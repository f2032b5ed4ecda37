/* porosity.c — a coarse grid of local void fraction (docs/physics.md#fluid-force).
 *
 * Each update: the bounding box of the particle surfaces [min(x - r), max(x + r)] is
 * divided on each axis into n = max(1, round(extent/h)) equal cells (2D: x and z only;
 * the depth is the disk thickness). Every particle's volume goes whole into the cell
 * holding its centre (no splitting across cells: cells should be several diameters
 * wide, so that the binning noise is small). eps = 1 - V_solid / V_cell, clamped to
 * [ESF_POROSITY_MIN, ESF_POROSITY_MAX]. Cost O(n + cells) per update. Units: SI. */
#include "loads/porosity.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/vec3.h"

static int cell_index(const esf_porosity_grid *g, const double q[3], int k) {
  if (g->nc[k] == 1) return 0;
  int c = (int)floor((q[k] - g->lo[k]) / g->cell[k]);
  return c < 0 ? 0 : c >= g->nc[k] ? g->nc[k] - 1 : c;
}

static size_t flat(const esf_porosity_grid *g, const double q[3]) {
  return ((size_t)cell_index(g, q, 2) * (size_t)g->nc[1] + (size_t)cell_index(g, q, 1)) *
             (size_t)g->nc[0] +
         (size_t)cell_index(g, q, 0);
}

void esf_porosity_box(const esf_particles *p, const double *x, size_t i0, size_t i1,
                      double lo[3], double hi[3]) {
  for (int k = 0; k < 3; k++) {
    lo[k] = INFINITY;
    hi[k] = -INFINITY;
  }
  for (size_t i = i0; i < i1; i++)
    for (int k = 0; k < 3; k++) {
      lo[k] = fmin(lo[k], x[3 * i + k] - p->radius[i]);
      hi[k] = fmax(hi[k], x[3 * i + k] + p->radius[i]);
    }
}

int esf_porosity_update(esf_porosity_grid *g, const esf_particles *p, const double *x,
                        int dim, double thickness, esf_error *err) {
  double lo[3], hi[3];
  esf_porosity_box(p, x, 0, p->n, lo, hi);
  int rc = esf_porosity_cells(g, lo, hi, p->n > 0, dim, thickness, err);
  if (rc) return rc;
  esf_porosity_add(g, p, x, 0, p->n, dim, thickness);
  esf_porosity_finish(g);
  return ESF_OK;
}

int esf_porosity_cells(esf_porosity_grid *g, const double lo[3], const double hi[3],
                       int any, int dim, double thickness, esf_error *err) {
  size_t ncell = 1;
  for (int k = 0; k < 3; k++) {
    double ext = any ? hi[k] - lo[k] : 1.0;
    int n = (dim == 2 && k == 1) ? 1 : (int)fmax(1.0, floor(ext / g->h + 0.5));
    if (n > 100000) n = 100000; /* a stray particle far away: cap the grid */
    g->nc[k] = n;
    g->lo[k] = any ? lo[k] : 0.0;
    g->cell[k] = ext / n;
    ncell *= (size_t)n;
  }
  if (dim == 2) g->cell[1] = thickness;
  if (ncell > g->cap) {
    free(g->eps);
    g->eps = malloc(ncell * sizeof *g->eps);
    if (!g->eps) {
      g->cap = 0;
      return esf_fail(err, ESF_ENOMEM, "out of memory for %zu porosity cells", ncell);
    }
    g->cap = ncell;
  }
  memset(g->eps, 0, ncell * sizeof *g->eps);
  g->ncell = ncell;
  return ESF_OK;
}

void esf_porosity_add(esf_porosity_grid *g, const esf_particles *p, const double *x,
                      size_t i0, size_t i1, int dim, double thickness) {
  for (size_t i = i0; i < i1; i++) {
    double r = p->radius[i];
    double v = dim == 2 ? ESF_PI * r * r * thickness : 4.0 / 3.0 * ESF_PI * r * r * r;
    g->eps[flat(g, x + 3 * i)] += v;
  }
}

void esf_porosity_finish(esf_porosity_grid *g) {
  const size_t ncell = g->ncell;
  double vc = g->cell[0] * g->cell[1] * g->cell[2];
  g->eps_min = INFINITY;
  g->eps_max = -INFINITY;
  for (size_t c = 0; c < ncell; c++) {
    double e = 1.0 - g->eps[c] / vc;
    g->eps_min = fmin(g->eps_min, e);
    g->eps_max = fmax(g->eps_max, e);
    g->eps[c] = fmin(ESF_POROSITY_MAX, fmax(ESF_POROSITY_MIN, e));
  }
}

double esf_porosity_at(const esf_porosity_grid *g, const double q[3]) {
  return g->eps[flat(g, q)];
}

void esf_porosity_release(esf_porosity_grid *g) {
  free(g->eps);
  memset(g, 0, sizeof *g);
}
