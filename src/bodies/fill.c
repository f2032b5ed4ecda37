/* fill.c — drawing particles from a size distribution and a material mix, and the
 * placement grid (fill.h), as the random fill of 004 §3.3 needs them.
 * Drawing: radii uniform by number in [a, b], or discrete values by number fractions;
 * materials by number fractions; an index with probability w_k / sum w.
 * Grid: a uniform grid of cell edge h >= 2 r_max (grown when the region is huge against
 * the spheres so the grid has O(N) cells); a sphere is registered in every cell its
 * bounding box touches, so a query looks at the <= 2 cells per axis under the
 * candidate's bounding box: O(1) per query. Units: m. 2D: one cell along y. */
#include "bodies/fill.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Sum of weights, after checking they are finite, non-negative and not all zero. */
static int check_weights(const char *what, size_t n, const double *w, double *sum,
                         esf_error *err) {
  double s = 0.0;
  for (size_t k = 0; k < n; k++) {
    if (!isfinite(w[k]) || w[k] < 0.0)
      return esf_fail(err, ESF_EINPUT,
                      "%s fraction %zu must be a non-negative number, got %g", what,
                      k + 1, w[k]);
    s += w[k];
  }
  if (!(s > 0.0)) return esf_fail(err, ESF_EINPUT, "%s fractions are all zero", what);
  *sum = s;
  return ESF_OK;
}

int esf_size_check(const esf_size_dist *d, double *rmax, double *rmin, esf_error *err) {
  double r = 0.0, r0 = INFINITY, sum;
  switch (d->kind) {
  case ESF_SIZE_FIXED:
    if (!isfinite(d->a) || !(d->a > 0.0))
      return esf_fail(err, ESF_EINPUT, "radius must be positive, got %g", d->a);
    r = r0 = d->a;
    break;
  case ESF_SIZE_UNIFORM:
    if (!isfinite(d->a) || !isfinite(d->b) || !(d->a > 0.0) || !(d->a <= d->b))
      return esf_fail(err, ESF_EINPUT,
                      "uniform radius range [%g, %g] must have 0 < min <= max", d->a,
                      d->b);
    r = d->b;
    r0 = d->a;
    break;
  case ESF_SIZE_DISCRETE: {
    if (d->nvalues == 0 || !d->values || !d->fractions)
      return esf_fail(err, ESF_EINPUT, "discrete radius distribution has no values");
    int rc = check_weights("radius", d->nvalues, d->fractions, &sum, err);
    if (rc) return rc;
    for (size_t k = 0; k < d->nvalues; k++) {
      if (!isfinite(d->values[k]) || !(d->values[k] > 0.0))
        return esf_fail(err, ESF_EINPUT, "radius value %zu must be positive, got %g",
                        k + 1, d->values[k]);
      if (d->fractions[k] > 0.0 && d->values[k] > r) r = d->values[k];
      if (d->fractions[k] > 0.0 && d->values[k] < r0) r0 = d->values[k];
    }
    break;
  }
  default:
    return esf_fail(err, ESF_EINPUT, "unknown size distribution kind %d", d->kind);
  }
  *rmax = r;
  if (rmin) *rmin = r0;
  return ESF_OK;
}

int esf_mix_check(const esf_material_mix *m, esf_error *err) {
  double sum;
  if (m->n == 0 || !m->material || !m->fraction)
    return esf_fail(err, ESF_EINPUT, "the material mix is empty");
  int rc = check_weights("material", m->n, m->fraction, &sum, err);
  if (rc) return rc;
  for (size_t k = 0; k < m->n; k++)
    if (m->material[k] < 0)
      return esf_fail(err, ESF_EINPUT, "material %zu of the mix has invalid index %d",
                      k + 1, (int)m->material[k]);
  return ESF_OK;
}

double esf_size_weights(const esf_size_dist *d) {
  double s = 0.0;
  if (d->kind == ESF_SIZE_DISCRETE)
    for (size_t k = 0; k < d->nvalues; k++) s += d->fractions[k];
  return s;
}

double esf_mix_weights(const esf_material_mix *m) {
  double s = 0.0;
  for (size_t k = 0; k < m->n; k++) s += m->fraction[k];
  return s;
}

static int finite3(const double *v) {
  return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

int esf_fill_spec_check(const esf_fill_spec *s, double *rmax, esf_error *err) {
  if (s->dim != 2 && s->dim != 3)
    return esf_fail(err, ESF_EINPUT, "dimension must be 2 or 3, got %d", s->dim);
  static const char axis[3] = {'x', 'y', 'z'};
  for (int k = 0; k < 3; k++) {
    if (s->dim == 2 && k == 1) continue;
    if (!isfinite(s->min[k]) || !isfinite(s->max[k]) || !(s->min[k] < s->max[k]))
      return esf_fail(err, ESF_EINPUT,
                      "region: min %c (%g) must be less than max %c (%g)", axis[k],
                      s->min[k], axis[k], s->max[k]);
    if (!isfinite(s->max[k] - s->min[k]))
      return esf_fail(err, ESF_EINPUT,
                      "region: its extent in %c, max %g - min %g, is too large to "
                      "represent",
                      axis[k], s->max[k], s->min[k]);
  }
  double r = 0.0;
  int rc = esf_size_check(&s->size, &r, NULL, err);
  if (rc) return rc;
  for (int k = 0; k < 3; k++) {
    if (s->dim == 2 && k == 1) continue;
    if (s->max[k] - s->min[k] < 2.0 * r)
      return esf_fail(
          err, ESF_EINPUT,
          "region is too small for a particle of radius %g: its extent in %c is "
          "%g < %g",
          r, axis[k], s->max[k] - s->min[k], 2.0 * r);
  }
  rc = esf_mix_check(&s->mix, err);
  if (rc) return rc;
  if (!finite3(s->velocity))
    return esf_fail(err, ESF_EINPUT, "initial velocity must be finite");
  *rmax = r;
  return ESF_OK;
}

size_t esf_draw_index(esf_rng *rng, size_t n, const double *w, double sum) {
  double u = esf_rng_uniform(rng) * sum, c = 0.0;
  size_t last = 0;
  for (size_t k = 0; k < n; k++) {
    if (w[k] <= 0.0) continue;
    last = k;
    c += w[k];
    if (u < c) return k;
  }
  return last; /* rounding: u reached the (inexact) total */
}

double esf_draw_radius(const esf_size_dist *d, esf_rng *rng, double fsum) {
  switch (d->kind) {
  case ESF_SIZE_UNIFORM: {
    double r = d->a + (d->b - d->a) * esf_rng_uniform(rng);
    return r > d->b ? d->b : r;
  }
  case ESF_SIZE_DISCRETE:
    return d->values[esf_draw_index(rng, d->nvalues, d->fractions, fsum)];
  default:
    return d->a;
  }
}

void esf_fill_seed(uint64_t seed, esf_rng *rr, esf_rng *rm, esf_rng *rp) {
  esf_rng master;
  esf_rng_seed(&master, seed);
  esf_rng_seed(rr, esf_rng_next(&master));
  esf_rng_seed(rm, esf_rng_next(&master));
  esf_rng_seed(rp, esf_rng_next(&master));
}

void esf_fill_grid_release(esf_fill_grid *g) {
  free(g->head);
  free(g->next);
  free(g->who);
  free(g->sp);
  memset(g, 0, sizeof *g);
}

/* Builds an empty grid over the region for about `expect` spheres of radius <= rmax. */
int esf_fill_grid_init(esf_fill_grid *g, const double min[3], const double max[3],
                       int dim, double rmax, size_t expect, esf_error *err) {
  memset(g, 0, sizeof *g);
  double len[3], logvol = 0.0;
  const int axes = dim;
  for (int k = 0; k < 3; k++) {
    g->lo[k] = dim == 2 && k == 1 ? 0.0 : min[k];
    len[k] = dim == 2 && k == 1 ? 0.0 : max[k] - min[k];
    if (len[k] > 0.0) logvol += log(len[k]);
  }
  /* at most ~4 cells per expected sphere (and at least 2 r_max per cell); the volume
     in logarithms, as it may overflow */
  double target = 4.0 * (double)expect + 64.0;
  double h = 2.0 * rmax, hmin = exp((logvol - log(target)) / axes), total, c[3];
  if (h < hmin) h = hmin;
  for (;;) {
    total = 1.0;
    for (int k = 0; k < 3; k++) {
      c[k] = len[k] > 0.0 ? ceil(len[k] / h) : 1.0;
      if (c[k] < 1.0) c[k] = 1.0;
      total *= c[k];
    }
    if (total <= 2.0 * target) break;
    h *= 1.25; /* ceil() rounding can still leave too many cells on thin regions */
  }
  for (int k = 0; k < 3; k++) g->nc[k] = (size_t)c[k]; /* each <= total: exact */
  g->h = h;
  size_t ncell = (size_t)total;
  g->head = malloc(ncell * sizeof *g->head);
  if (!g->head)
    return esf_fail(err, ESF_ENOMEM, "out of memory for %zu grid cells", ncell);
  for (size_t c = 0; c < ncell; c++) g->head[c] = SIZE_MAX;
  return ESF_OK;
}

/* Cell range [lo, hi] along axis k covered by the interval [a, b] (clamped). */
static void cell_range(const esf_fill_grid *g, int k, double a, double b, size_t *lo,
                       size_t *hi) {
  double fa = floor((a - g->lo[k]) / g->h), fb = floor((b - g->lo[k]) / g->h);
  double top = (double)(g->nc[k] - 1);
  fa = fa < 0.0 ? 0.0 : fa > top ? top : fa;
  fb = fb < 0.0 ? 0.0 : fb > top ? top : fb;
  *lo = (size_t)fa;
  *hi = (size_t)fb;
}

int esf_fill_grid_add(esf_fill_grid *g, const esf_fill_sphere *sp, esf_error *err) {
  if (g->nsp == g->capsp) {
    size_t cap = g->capsp ? 2 * g->capsp : 256;
    esf_fill_sphere *p = realloc(g->sp, cap * sizeof *p);
    if (!p) return esf_fail(err, ESF_ENOMEM, "out of memory for %zu particles", cap);
    g->sp = p;
    g->capsp = cap;
  }
  size_t id = g->nsp++;
  g->sp[id] = *sp;
  size_t lo[3], hi[3];
  for (int k = 0; k < 3; k++)
    cell_range(g, k, sp->x[k] - sp->r, sp->x[k] + sp->r, &lo[k], &hi[k]);
  for (size_t iz = lo[2]; iz <= hi[2]; iz++)
    for (size_t iy = lo[1]; iy <= hi[1]; iy++)
      for (size_t ix = lo[0]; ix <= hi[0]; ix++) {
        if (g->nent == g->capent) {
          size_t cap = g->capent ? 2 * g->capent : 1024;
          size_t *nx = realloc(g->next, cap * sizeof *nx);
          if (!nx) return esf_fail(err, ESF_ENOMEM, "out of memory for the fill grid");
          g->next = nx;
          size_t *wh = realloc(g->who, cap * sizeof *wh);
          if (!wh) return esf_fail(err, ESF_ENOMEM, "out of memory for the fill grid");
          g->who = wh;
          g->capent = cap;
        }
        size_t c = (iz * g->nc[1] + iy) * g->nc[0] + ix;
        g->who[g->nent] = id;
        g->next[g->nent] = g->head[c];
        g->head[c] = g->nent++;
      }
  return ESF_OK;
}

int esf_fill_grid_overlaps(const esf_fill_grid *g, const esf_fill_sphere *sp) {
  size_t lo[3], hi[3];
  for (int k = 0; k < 3; k++)
    cell_range(g, k, sp->x[k] - sp->r, sp->x[k] + sp->r, &lo[k], &hi[k]);
  for (size_t iz = lo[2]; iz <= hi[2]; iz++)
    for (size_t iy = lo[1]; iy <= hi[1]; iy++)
      for (size_t ix = lo[0]; ix <= hi[0]; ix++)
        for (size_t e = g->head[(iz * g->nc[1] + iy) * g->nc[0] + ix]; e != SIZE_MAX;
             e = g->next[e]) {
          const esf_fill_sphere *o = &g->sp[g->who[e]];
          double dx = sp->x[0] - o->x[0], dy = sp->x[1] - o->x[1],
                 dz = sp->x[2] - o->x[2];
          double rr = sp->r + o->r;
          if (dx * dx + dy * dy + dz * dz < rr * rr) return 1;
        }
  return 0;
}
