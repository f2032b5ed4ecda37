/* fill.h — drawing particles from a size distribution and a material mix, and the
 * placement grid that finds overlaps among spheres, shared by the scene's random fill
 * (scene/particle_generate.c) and run-time insertion (loads/insert.c). */
#ifndef ESF_FILL_H
#define ESF_FILL_H

#include <stddef.h>
#include <stdint.h>

#include "util/esf_error.h"
#include "util/rng.h"

enum {
  ESF_SIZE_FIXED = 0,   /* every radius = a */
  ESF_SIZE_UNIFORM = 1, /* radius uniform in [a, b] (by number) */
  ESF_SIZE_DISCRETE = 2 /* radius values[k] with number fractions[k] */
};

typedef struct esf_size_dist {
  int kind;
  double a, b; /* m */
  size_t nvalues;
  const double *values;    /* m */
  const double *fractions; /* sum to 1 (normalised by the generator if not) */
} esf_size_dist;

typedef struct esf_material_mix {
  size_t n; /* 1 for a single material */
  const int32_t *material;
  const double *fraction; /* number fractions, normalised if they do not sum to 1 */
} esf_material_mix;

typedef struct esf_fill_spec {
  double min[3], max[3]; /* region, m; particles lie entirely inside it */
  size_t count;          /* particles wanted (random: required; lattice: 0 = fill) */
  double spacing;        /* lattice: centre spacing, m (0: 2 r_max) */
  esf_size_dist size;
  esf_material_mix mix;
  uint64_t seed;
  int dim;            /* 3, or 2: centres in the x-z plane at y = 0 */
  double velocity[3]; /* initial velocity of every generated particle, m/s */
} esf_fill_spec;

/* Validates a spec but its count; gives the largest radius that can be drawn. */
int esf_fill_spec_check(const esf_fill_spec *s, double *rmax, esf_error *err);

/* Checks a size distribution; gives its largest and smallest radius that can be drawn. */
int esf_size_check(const esf_size_dist *d, double *rmax, double *rmin, esf_error *err);
/* Checks a material mix (non-empty, weights >= 0 not all 0, valid indices). */
int esf_mix_check(const esf_material_mix *m, esf_error *err);
/* The sum of a distribution's weights (discrete fractions; 0 for the others). */
double esf_size_weights(const esf_size_dist *d);
double esf_mix_weights(const esf_material_mix *m);
/* Index drawn with probability w[k] / sum (never a zero-weight index). */
size_t esf_draw_index(esf_rng *rng, size_t n, const double *w, double sum);
/* A radius from d (fsum = esf_size_weights(d)). */
double esf_draw_radius(const esf_size_dist *d, esf_rng *rng, double fsum);
/* Seeds the radius, material and position streams from one seed. */
void esf_fill_seed(uint64_t seed, esf_rng *rr, esf_rng *rm, esf_rng *rp);

/* A uniform grid of registered spheres over a box region (2D: one cell along y). */
typedef struct esf_fill_sphere {
  double x[3], r;
} esf_fill_sphere;

typedef struct esf_fill_grid {
  double lo[3], h;    /* origin (region min) and cell edge */
  size_t nc[3];       /* cells per axis (1 along y in 2D) */
  size_t *head;       /* nc[0] nc[1] nc[2] heads, SIZE_MAX = empty */
  size_t *next, *who; /* entry lists: next entry, sphere index */
  size_t nent, capent;
  esf_fill_sphere *sp; /* registered spheres */
  size_t nsp, capsp;
} esf_fill_grid;

/* An empty grid over [min, max] for about `expect` spheres of radius <= rmax. */
int esf_fill_grid_init(esf_fill_grid *g, const double min[3], const double max[3],
                       int dim, double rmax, size_t expect, esf_error *err);
int esf_fill_grid_add(esf_fill_grid *g, const esf_fill_sphere *sp, esf_error *err);
/* 1 when the sphere overlaps a registered one (touching is allowed). */
int esf_fill_grid_overlaps(const esf_fill_grid *g, const esf_fill_sphere *sp);
void esf_fill_grid_release(esf_fill_grid *g);

#endif
