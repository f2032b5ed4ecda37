/* porosity.h — the local void fraction of a packing on a coarse grid of cells, for the
 * fluid force (drag.c): each particle's volume is binned by its centre into the cell
 * holding it, over a grid spanning the particles' bounding box (surfaces included). */
#ifndef ESF_POROSITY_H
#define ESF_POROSITY_H

#include <stddef.h>

#include "bodies/particles.h"
#include "util/esf_error.h"

/* Void fractions are clamped to this range (Ergun's 1/eps diverges at 0). */
#define ESF_POROSITY_MIN 0.1
#define ESF_POROSITY_MAX 0.999

typedef struct esf_porosity_grid {
  double h;                /* requested cell size, m */
  double lo[3];            /* grid origin, m */
  double cell[3];          /* cell sizes (the box divided into whole cells), m */
  int nc[3];               /* cells per axis */
  double *eps;             /* void fraction per cell (clamped) */
  size_t cap;              /* cells allocated */
  double eps_min, eps_max; /* extremes of the last update before clamping */
  size_t ncell;            /* cells of the last update */
} esf_porosity_grid;

/* esf_porosity_update's parts, for an MPI run that takes them across its processes
 * (par.h): the surfaces' box of particles [i0, i1); the cells for the box [lo, hi]
 * (any: some particle), their solid volumes zeroed; the volumes of particles [i0, i1)
 * added, in order; the void fractions from the volumes. */
void esf_porosity_box(const esf_particles *p, const double *x, size_t i0, size_t i1,
                      double lo[3], double hi[3]);
int esf_porosity_cells(esf_porosity_grid *g, const double lo[3], const double hi[3],
                       int any, int dim, double thickness, esf_error *err);
void esf_porosity_add(esf_porosity_grid *g, const esf_particles *p, const double *x,
                      size_t i0, size_t i1, int dim, double thickness);
void esf_porosity_finish(esf_porosity_grid *g);

/* Rebuilds the grid for positions x (3n): the bounding box of the particles'
 * surfaces, split into round(extent/h) cells (at least 1) per axis; the solid volume
 * per cell (spheres 4/3 pi r^3; dim 2: disks pi r^2 thickness, y ignored, the cell's
 * depth being thickness). */
int esf_porosity_update(esf_porosity_grid *g, const esf_particles *p, const double *x,
                        int dim, double thickness, esf_error *err);

/* The void fraction of the cell holding point q (points outside: the nearest cell). */
double esf_porosity_at(const esf_porosity_grid *g, const double q[3]);

void esf_porosity_release(esf_porosity_grid *g);

#endif
