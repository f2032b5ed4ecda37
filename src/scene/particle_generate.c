/* particle_generate.c — particle generators (particle_source.h): a random
 * non-overlapping fill of a box and a simple cubic (square in 2D) lattice.
 *
 * The random fill is the pseudo-random generation of a primary set of 004 §3.3 (ranges
 * of coordinates, radii and materials); compaction is left to the simulation (let the
 * particles settle under gravity, or move the walls). Algorithm: random sequential
 * addition, largest first, overlaps found through a uniform grid, O(N) overall
 * (esf_generate_random).
 * Randomness: one esf_rng seeded with spec->seed seeds three independent streams, for
 * radii, materials and positions, so radii and materials do not depend on how many
 * placement attempts were needed and the lattice gets the same radii and materials as
 * the random fill for the same seed. Same spec -> identical output.
 * Units: lengths m, velocities m/s. In 2D (dim = 2) centres lie in the x-z plane at
 * y = 0 and the region's y bounds are ignored. Generated particles get
 * spec->velocity and zero angular velocity. Output order: the random fill appends in
 * placement order (largest first); the lattice in site order, x fastest, then y, then z.
 * On entry `out` holds any number of definitions (it may be the same list as
 * `existing`); on success the generated particles are appended; on failure `out` is
 * restored to its entry length. */
#include "scene/particle_source.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/rng.h"

enum { MAX_ATTEMPTS = 2000 }; /* placement attempts per particle */
static const double PI = 3.14159265358979323846;

/* ---- validation and drawing --------------------------------------------------- */

static int finite3(const double *v) {
  return isfinite(v[0]) && isfinite(v[1]) && isfinite(v[2]);
}

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

/* Validates everything but count; gives the largest radius that can be drawn. */
static int check_spec(const esf_fill_spec *s, double *rmax, esf_error *err) {
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
  const esf_size_dist *d = &s->size;
  double r = 0.0, sum;
  switch (d->kind) {
  case ESF_SIZE_FIXED:
    if (!isfinite(d->a) || !(d->a > 0.0))
      return esf_fail(err, ESF_EINPUT, "radius must be positive, got %g", d->a);
    r = d->a;
    break;
  case ESF_SIZE_UNIFORM:
    if (!isfinite(d->a) || !isfinite(d->b) || !(d->a > 0.0) || !(d->a <= d->b))
      return esf_fail(err, ESF_EINPUT,
                      "uniform radius range [%g, %g] must have 0 < min <= max", d->a,
                      d->b);
    r = d->b;
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
    }
    break;
  }
  default:
    return esf_fail(err, ESF_EINPUT, "unknown size distribution kind %d", d->kind);
  }
  for (int k = 0; k < 3; k++) {
    if (s->dim == 2 && k == 1) continue;
    if (s->max[k] - s->min[k] < 2.0 * r)
      return esf_fail(
          err, ESF_EINPUT,
          "region is too small for a particle of radius %g: its extent in %c is "
          "%g < %g",
          r, axis[k], s->max[k] - s->min[k], 2.0 * r);
  }
  const esf_material_mix *m = &s->mix;
  if (m->n == 0 || !m->material || !m->fraction)
    return esf_fail(err, ESF_EINPUT, "the material mix is empty");
  int rc = check_weights("material", m->n, m->fraction, &sum, err);
  if (rc) return rc;
  for (size_t k = 0; k < m->n; k++)
    if (m->material[k] < 0)
      return esf_fail(err, ESF_EINPUT, "material %zu of the mix has invalid index %d",
                      k + 1, (int)m->material[k]);
  if (!finite3(s->velocity))
    return esf_fail(err, ESF_EINPUT, "initial velocity must be finite");
  *rmax = r;
  return ESF_OK;
}

/* Index drawn with probability w[k] / sum (never a zero-weight index). */
static size_t draw_index(esf_rng *rng, size_t n, const double *w, double sum) {
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

static double draw_radius(const esf_size_dist *d, esf_rng *rng, double fsum) {
  switch (d->kind) {
  case ESF_SIZE_UNIFORM: {
    double r = d->a + (d->b - d->a) * esf_rng_uniform(rng);
    return r > d->b ? d->b : r;
  }
  case ESF_SIZE_DISCRETE:
    return d->values[draw_index(rng, d->nvalues, d->fractions, fsum)];
  default:
    return d->a;
  }
}

typedef struct drawn {
  double r;
  int32_t material;
  size_t order; /* draw order, the tie-break of the sort */
} drawn;

/* Draws n radii and materials from the spec's streams. */
static int draw_all(const esf_fill_spec *s, esf_rng *rr, esf_rng *rm, size_t n,
                    drawn **out, esf_error *err) {
  drawn *d = malloc((n ? n : 1) * sizeof *d);
  if (!d) return esf_fail(err, ESF_ENOMEM, "out of memory for %zu particles", n);
  double fsum = 0.0, msum = 0.0;
  if (s->size.kind == ESF_SIZE_DISCRETE)
    for (size_t k = 0; k < s->size.nvalues; k++) fsum += s->size.fractions[k];
  for (size_t k = 0; k < s->mix.n; k++) msum += s->mix.fraction[k];
  for (size_t i = 0; i < n; i++) {
    d[i].r = draw_radius(&s->size, rr, fsum);
    d[i].material = s->mix.material[draw_index(rm, s->mix.n, s->mix.fraction, msum)];
    d[i].order = i;
  }
  *out = d;
  return ESF_OK;
}

/* Seeds the radius, material and position streams from the spec's seed. */
static void seed_streams(uint64_t seed, esf_rng *rr, esf_rng *rm, esf_rng *rp) {
  esf_rng master;
  esf_rng_seed(&master, seed);
  esf_rng_seed(rr, esf_rng_next(&master));
  esf_rng_seed(rm, esf_rng_next(&master));
  esf_rng_seed(rp, esf_rng_next(&master));
}

static int by_radius_desc(const void *pa, const void *pb) {
  const drawn *a = pa, *b = pb;
  if (a->r != b->r) return a->r > b->r ? -1 : 1;
  return a->order < b->order ? -1 : a->order > b->order;
}

/* ---- the placement grid ---------------------------------------------------------- */

typedef struct sphere {
  double x[3], r;
} sphere;

typedef struct grid {
  double lo[3], h;    /* origin (region min) and cell edge */
  size_t nc[3];       /* cells per axis (1 along y in 2D) */
  size_t *head;       /* nc[0] nc[1] nc[2] heads, SIZE_MAX = empty */
  size_t *next, *who; /* entry lists: next entry, sphere index */
  size_t nent, capent;
  sphere *sp; /* registered spheres */
  size_t nsp, capsp;
} grid;

static void grid_release(grid *g) {
  free(g->head);
  free(g->next);
  free(g->who);
  free(g->sp);
  memset(g, 0, sizeof *g);
}

/* Builds an empty grid over the region for about `expect` spheres of radius <= rmax. */
static int grid_init(grid *g, const esf_fill_spec *s, double rmax, size_t expect,
                     esf_error *err) {
  memset(g, 0, sizeof *g);
  double len[3], logvol = 0.0;
  int axes = s->dim;
  for (int k = 0; k < 3; k++) {
    g->lo[k] = s->dim == 2 && k == 1 ? 0.0 : s->min[k];
    len[k] = s->dim == 2 && k == 1 ? 0.0 : s->max[k] - s->min[k];
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
static void cell_range(const grid *g, int k, double a, double b, size_t *lo, size_t *hi) {
  double fa = floor((a - g->lo[k]) / g->h), fb = floor((b - g->lo[k]) / g->h);
  double top = (double)(g->nc[k] - 1);
  fa = fa < 0.0 ? 0.0 : fa > top ? top : fa;
  fb = fb < 0.0 ? 0.0 : fb > top ? top : fb;
  *lo = (size_t)fa;
  *hi = (size_t)fb;
}

static int grid_add(grid *g, const sphere *sp, esf_error *err) {
  if (g->nsp == g->capsp) {
    size_t cap = g->capsp ? 2 * g->capsp : 256;
    sphere *p = realloc(g->sp, cap * sizeof *p);
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

/* 1 when the sphere overlaps a registered one (touching is allowed). */
static int grid_overlaps(const grid *g, const sphere *sp) {
  size_t lo[3], hi[3];
  for (int k = 0; k < 3; k++)
    cell_range(g, k, sp->x[k] - sp->r, sp->x[k] + sp->r, &lo[k], &hi[k]);
  for (size_t iz = lo[2]; iz <= hi[2]; iz++)
    for (size_t iy = lo[1]; iy <= hi[1]; iy++)
      for (size_t ix = lo[0]; ix <= hi[0]; ix++)
        for (size_t e = g->head[(iz * g->nc[1] + iy) * g->nc[0] + ix]; e != SIZE_MAX;
             e = g->next[e]) {
          const sphere *o = &g->sp[g->who[e]];
          double dx = sp->x[0] - o->x[0], dy = sp->x[1] - o->x[1],
                 dz = sp->x[2] - o->x[2];
          double rr = sp->r + o->r;
          if (dx * dx + dy * dy + dz * dz < rr * rr) return 1;
        }
  return 0;
}

/* ---- generators ------------------------------------------------------------------- */

static double solid_fraction(const esf_fill_spec *s, const drawn *d, size_t n) {
  double vol = 0.0, region = 1.0;
  for (size_t i = 0; i < n; i++)
    vol += s->dim == 3 ? 4.0 / 3.0 * PI * d[i].r * d[i].r * d[i].r : PI * d[i].r * d[i].r;
  for (int k = 0; k < 3; k++)
    if (s->dim == 3 || k != 1) region *= s->max[k] - s->min[k];
  return vol / region;
}

static void make_def(const esf_fill_spec *s, const double x[3], const drawn *d,
                     esf_particle_def *def) {
  memset(def, 0, sizeof *def);
  memcpy(def->x, x, sizeof def->x);
  memcpy(def->v, s->velocity, sizeof def->v);
  def->radius = d->r;
  def->material = d->material;
}

/* Random sequential addition: draw all N radii from the size distribution and N
 * materials from the mix, sort by radius descending (ties by draw order, so the order
 * is deterministic), then place each particle at a uniformly random centre for which
 * the sphere lies inside the region, rejecting positions that overlap a placed
 * particle or one of `existing`; after MAX_ATTEMPTS rejections the fill fails.
 * Overlaps are found through a uniform grid over the region of cell edge h >= 2 r_max
 * (grown when the region is huge against the particles so the grid has O(N) cells);
 * each particle is registered in every cell its bounding box touches, so a query looks
 * only at the <= 2 cells per axis under the candidate's bounding box: O(1) per attempt,
 * O(N) overall. Existing particles of any size are handled the same way (a big one
 * registers in many cells). Random sequential addition of equal spheres jams at a
 * solid fraction of 0.38 in 3D (0.55 for disks in 2D), well below random loose packing
 * (~0.55-0.6); with MAX_ATTEMPTS tries per particle this fill reaches about 0.29 in 3D
 * and 0.5 in 2D, which the error message says. */
int esf_generate_random(const esf_fill_spec *spec, const esf_particle_defs *existing,
                        esf_particle_defs *out, esf_error *err) {
  double rmax;
  int rc = check_spec(spec, &rmax, err);
  if (rc) return rc;
  size_t n = spec->count;
  if (n == 0) return esf_fail(err, ESF_EINPUT, "random fill: count must be positive");
  esf_rng rr, rm, rp;
  seed_streams(spec->seed, &rr, &rm, &rp);
  drawn *d = NULL;
  rc = draw_all(spec, &rr, &rm, n, &d, err);
  if (rc) return rc;
  qsort(d, n, sizeof *d, by_radius_desc);
  rmax = d[0].r; /* the largest radius actually drawn */

  size_t n0 = out->n, nexist = existing ? existing->n : 0; /* existing may be out */
  grid g;
  rc = grid_init(&g, spec, rmax, n + nexist, err);
  for (size_t j = 0; rc == ESF_OK && j < nexist; j++) {
    const esf_particle_def *e = &existing->d[j];
    int near = 1; /* register only those whose bounding box meets the region */
    for (int k = 0; k < 3; k++) {
      if (spec->dim == 2 && k == 1) continue;
      if (e->x[k] + e->radius <= spec->min[k] || e->x[k] - e->radius >= spec->max[k])
        near = 0;
    }
    if (!near) continue;
    sphere sp = {{e->x[0], e->x[1], e->x[2]}, e->radius};
    rc = grid_add(&g, &sp, err);
  }
  int axes[3] = {1, spec->dim == 3, 1};
  for (size_t i = 0; rc == ESF_OK && i < n; i++) {
    sphere sp = {{0.0, 0.0, 0.0}, d[i].r};
    int placed = 0;
    for (int a = 0; a < MAX_ATTEMPTS && !placed; a++) {
      for (int k = 0; k < 3; k++) {
        if (!axes[k]) continue;
        double lo = spec->min[k] + sp.r, hi = spec->max[k] - sp.r;
        double x = lo + (hi - lo) * esf_rng_uniform(&rp);
        sp.x[k] = x > hi ? hi : x;
      }
      placed = !grid_overlaps(&g, &sp);
    }
    if (!placed) {
      rc =
          esf_fail(err, ESF_EINPUT,
                   "could not place particle %zu of %zu after %d attempts: the region is "
                   "too full (asked solid fraction %.3g; random placement without "
                   "overlaps reaches only about %s for equal sizes: fill a larger "
                   "region and let the particles settle)",
                   i + 1, n, MAX_ATTEMPTS, solid_fraction(spec, d, n),
                   spec->dim == 3 ? "0.3 in 3D" : "0.5 in 2D");
      break;
    }
    rc = grid_add(&g, &sp, err);
    if (rc) break;
    esf_particle_def def;
    make_def(spec, sp.x, &d[i], &def);
    rc = esf_particle_defs_push(out, &def, err);
  }
  grid_release(&g);
  free(d);
  if (rc) out->n = n0;
  return rc;
}

int esf_generate_lattice(const esf_fill_spec *spec, esf_particle_defs *out,
                         esf_error *err) {
  double rmax;
  int rc = check_spec(spec, &rmax, err);
  if (rc) return rc;
  double s = spec->spacing;
  if (!isfinite(s) || s < 0.0)
    return esf_fail(err, ESF_EINPUT, "lattice spacing must be non-negative, got %g", s);
  if (s == 0.0) s = 2.0 * rmax;
  if (rmax > 0.5 * s)
    return esf_fail(err, ESF_EINPUT,
                    "lattice: radius %g exceeds half the spacing %g (particles would "
                    "overlap)",
                    rmax, s);
  /* sites per axis: centres at min + rmax + i s with the sphere inside the region (a
   * relative 1e-9 of slack absorbs rounding in (L - 2 rmax) / s) */
  size_t ns[3];
  double total = 1.0, q[3];
  for (int k = 0; k < 3; k++) {
    if (spec->dim == 2 && k == 1) {
      ns[k] = 1;
      continue;
    }
    q[k] = floor((spec->max[k] - spec->min[k] - 2.0 * rmax) / s + 1e-9) + 1.0;
    total *= q[k];
  }
  if (total > 1e9)
    return esf_fail(err, ESF_EINPUT, "lattice: %.3g sites is too many (spacing %g)",
                    total, s);
  for (int k = 0; k < 3; k++) /* each <= total: exact */
    if (!(spec->dim == 2 && k == 1)) ns[k] = (size_t)q[k];
  size_t nsites = (size_t)total;
  size_t n = spec->count ? spec->count : nsites;
  if (n > nsites)
    return esf_fail(
        err, ESF_EINPUT,
        "lattice: the region holds only %zu sites at spacing %g, fewer than the "
        "%zu particles asked",
        nsites, s, n);
  esf_rng rr, rm, rp;
  seed_streams(spec->seed, &rr, &rm, &rp);
  drawn *d = NULL;
  rc = draw_all(spec, &rr, &rm, n, &d, err);
  if (rc) return rc;
  size_t n0 = out->n;
  for (size_t i = 0; rc == ESF_OK && i < n; i++) {
    size_t idx[3] = {i % ns[0], i / ns[0] % ns[1], i / (ns[0] * ns[1])};
    double x[3] = {0.0, 0.0, 0.0};
    for (int k = 0; k < 3; k++) {
      if (spec->dim == 2 && k == 1) continue;
      double c = spec->min[k] + rmax + (double)idx[k] * s, top = spec->max[k] - rmax;
      x[k] = c > top ? top : c;
    }
    esf_particle_def def;
    make_def(spec, x, &d[i], &def);
    rc = esf_particle_defs_push(out, &def, err);
  }
  free(d);
  if (rc) out->n = n0;
  return rc;
}
