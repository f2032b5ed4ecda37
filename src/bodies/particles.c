/* particles.c — allocation, growth, compaction and renumbering of the structure-of-arrays
 * particle store (a renumbering array by array, through two scratch arrays).
 * Invariant on exit of every function: x, v, w point into the single block y of 9n
 * doubles, in that order, so the block is one contiguous ODE state vector. */
#include "bodies/particles.h"

#include <stdlib.h>
#include <string.h>

int esf_particle_defs_push(esf_particle_defs *defs, const esf_particle_def *def,
                           esf_error *err) {
  if (defs->n == defs->cap) {
    size_t cap = defs->cap ? 2 * defs->cap : 64;
    esf_particle_def *d = realloc(defs->d, cap * sizeof *d);
    if (!d) return esf_fail(err, ESF_ENOMEM, "out of memory for %zu particles", cap);
    defs->d = d;
    defs->cap = cap;
  }
  defs->d[defs->n++] = *def;
  return ESF_OK;
}

void esf_particle_defs_release(esf_particle_defs *defs) {
  free(defs->d);
  defs->d = NULL;
  defs->n = defs->cap = 0;
}

void esf_particles_release(esf_particles *p) {
  free(p->y);
  free(p->f);
  free(p->t);
  free(p->radius);
  free(p->mass);
  free(p->inv_mass);
  free(p->inertia);
  free(p->inv_inertia);
  free(p->material);
  free(p->id);
  free(p->img);
  memset(p, 0, sizeof *p);
}

/* The arrays for n particles, zeroed or (zero = 0, for a gather that writes them all)
 * not. */
static int alloc_arrays(esf_particles *p, size_t n, int zero, esf_error *err) {
  memset(p, 0, sizeof *p);
  const size_t m = n ? n : 1; /* never hand out NULL arrays */
#define ESF_PALLOC(k, size) (zero ? calloc((k), (size)) : malloc((k) * (size)))
  p->n = n;
  p->y = ESF_PALLOC(9 * m + 1, sizeof(double)); /* + 1: pair_batch.c's 4-wide loads */
  p->f = ESF_PALLOC(3 * m, sizeof(double));
  p->t = ESF_PALLOC(3 * m, sizeof(double));
  p->radius = ESF_PALLOC(m, sizeof(double));
  p->mass = ESF_PALLOC(m, sizeof(double));
  p->inv_mass = ESF_PALLOC(m, sizeof(double));
  p->inertia = ESF_PALLOC(m, sizeof(double));
  p->inv_inertia = ESF_PALLOC(m, sizeof(double));
  p->material = ESF_PALLOC(m, sizeof(int32_t));
  p->id = ESF_PALLOC(m, sizeof(int64_t));
#undef ESF_PALLOC
  if (!p->y || !p->f || !p->t || !p->radius || !p->mass || !p->inv_mass || !p->inertia ||
      !p->inv_inertia || !p->material || !p->id) {
    esf_particles_release(p);
    return esf_fail(err, ESF_ENOMEM, "out of memory for %zu particles", n);
  }
  p->y[9 * m] = 0.0; /* the spare double */
  p->x = p->y;
  p->v = p->y + 3 * n;
  p->w = p->y + 6 * n;
  return ESF_OK;
}

int esf_particles_images(esf_particles *p, esf_error *err) {
  if (p->img) return ESF_OK;
  p->img = calloc(3 * (p->n ? p->n : 1), sizeof *p->img);
  if (!p->img) return esf_fail(err, ESF_ENOMEM, "out of memory for %zu particles", p->n);
  return ESF_OK;
}

int esf_particles_alloc(esf_particles *p, size_t n, esf_error *err) {
  return alloc_arrays(p, n, 1, err);
}

/* p becomes the particles src[0 .. m) of p, in that order (threads > 1: the copy is
 * shared among that many threads). */
static int gather(esf_particles *p, const size_t *src, size_t m, int threads,
                  esf_error *err) {
  esf_particles q;
  int rc = alloc_arrays(&q, m, m == 0, err); /* every entry is written below */
  if (rc) return rc;
  if (p->img) {
    q.img = malloc(3 * (m ? m : 1) * sizeof *q.img);
    if (!q.img) {
      esf_particles_release(&q);
      return esf_fail(err, ESF_ENOMEM, "out of memory for %zu particles", m);
    }
  }
  const long mm = (long)m;
#pragma omp parallel for num_threads(threads > 1 ? threads : 1) schedule(static)
  for (long kk = 0; kk < mm; kk++) {
    const size_t k = (size_t)kk, i = src[k];
    memcpy(q.x + 3 * k, p->x + 3 * i, 3 * sizeof(double));
    memcpy(q.v + 3 * k, p->v + 3 * i, 3 * sizeof(double));
    memcpy(q.w + 3 * k, p->w + 3 * i, 3 * sizeof(double));
    memcpy(q.f + 3 * k, p->f + 3 * i, 3 * sizeof(double));
    memcpy(q.t + 3 * k, p->t + 3 * i, 3 * sizeof(double));
    q.radius[k] = p->radius[i];
    q.mass[k] = p->mass[i];
    q.inv_mass[k] = p->inv_mass[i];
    q.inertia[k] = p->inertia[i];
    q.inv_inertia[k] = p->inv_inertia[i];
    q.material[k] = p->material[i];
    q.id[k] = p->id[i];
    if (q.img) memcpy(q.img + 3 * k, p->img + 3 * i, 3 * sizeof(int32_t));
  }
  esf_particles_release(p);
  *p = q;
  return ESF_OK;
}

int esf_particles_compact(esf_particles *p, const unsigned char *keep, size_t *remap,
                          esf_error *err) {
  size_t n = p->n, m = 0;
  size_t *src = malloc((n ? n : 1) * sizeof *src);
  if (!src) return esf_fail(err, ESF_ENOMEM, "out of memory for %zu particles", n);
  for (size_t i = 0; i < n; i++) {
    if (remap) remap[i] = keep[i] ? m : SIZE_MAX;
    if (keep[i]) src[m++] = i;
  }
  int rc = gather(p, src, m, 1, err);
  free(src);
  return rc;
}

/* to[k] = from[src[k]] for k < n, entries of w doubles, on `threads` threads. */
static void gather_doubles(double *restrict to, const double *restrict from,
                           const size_t *src, size_t n, int w, int threads) {
  const long nn = (long)n;
#pragma omp parallel for num_threads(threads > 1 ? threads : 1) schedule(static)
  for (long kk = 0; kk < nn; kk++)
    for (int q = 0; q < w; q++) to[(size_t)w * (size_t)kk + q] = from[w * src[kk] + q];
}

/* The same for entries of `size` bytes (the integer arrays). */
static void gather_bytes(void *restrict to, const void *restrict from, const size_t *src,
                         size_t n, size_t size, int threads) {
  const long nn = (long)n;
#pragma omp parallel for num_threads(threads > 1 ? threads : 1) schedule(static)
  for (long kk = 0; kk < nn; kk++)
    memcpy((char *)to + size * (size_t)kk, (const char *)from + size * src[kk], size);
}

/* Array by array through two scratch arrays (3n and n doubles), not a second copy of
 * every array at once (the peak memory of a renumbering: 32 bytes a particle beside
 * the particles, not 172): x, v, w and material are gathered and copied back (x, v, w
 * stay in the one block y); f, t, the per-particle doubles and id are gathered into a
 * scratch array that then takes the old array's place. Same bits as a gather. */
int esf_particles_permute(esf_particles *p, const size_t *src, int threads,
                          esf_error *err) {
  const size_t n = p->n, m = n ? n : 1;
  double *s3 = malloc(3 * m * sizeof *s3), *s1 = malloc(m * sizeof *s1);
  if (!s3 || !s1) {
    free(s3);
    free(s1);
    return esf_fail(err, ESF_ENOMEM, "out of memory for reordering %zu particles", n);
  }
  double *vec[3] = {p->x, p->v, p->w};
  for (int a = 0; a < 3; a++) { /* in y: gathered, copied back */
    gather_doubles(s3, vec[a], src, n, 3, threads);
    memcpy(vec[a], s3, 3 * n * sizeof *s3);
  }
  double **own3[2] = {&p->f, &p->t};
  for (int a = 0; a < (p->f && p->t ? 2 : 0); a++) { /* the scratch takes their place */
    gather_doubles(s3, *own3[a], src, n, 3, threads);
    double *old = *own3[a];
    *own3[a] = s3;
    s3 = old;
  }
  double **own1[5] = {&p->radius, &p->mass, &p->inv_mass, &p->inertia, &p->inv_inertia};
  for (int a = 0; a < 5; a++) {
    gather_doubles(s1, *own1[a], src, n, 1, threads);
    double *old = *own1[a];
    *own1[a] = s1;
    s1 = old;
  }
  gather_bytes(s1, p->id, src, n, sizeof *p->id, threads); /* eight bytes, as s1's */
  int64_t *oid = p->id;
  p->id = (int64_t *)s1;
  s1 = (double *)oid;
  gather_bytes(s1, p->material, src, n, sizeof *p->material, threads);
  memcpy(p->material, s1, n * sizeof *p->material);
  if (p->img) { /* periodic image counters, 12 bytes a particle (s3 has 24) */
    gather_bytes(s3, p->img, src, n, 3 * sizeof *p->img, threads);
    memcpy(p->img, s3, 3 * n * sizeof *p->img);
  }
  free(s3);
  free(s1);
  return ESF_OK;
}

int esf_particles_append(esf_particles *p, size_t k, esf_error *err) {
  const size_t n = p->n;
  esf_particles q;
  int rc = alloc_arrays(&q, n + k, 1, err);
  if (rc) return rc;
  if (p->img) { /* periodic image counters: the newcomers' are zero */
    q.img = calloc(3 * (n + k) + 1, sizeof *q.img);
    if (!q.img) {
      esf_particles_release(&q);
      return esf_fail(err, ESF_ENOMEM, "out of memory for %zu particles", n + k);
    }
    memcpy(q.img, p->img, 3 * n * sizeof *q.img);
  }
  memcpy(q.x, p->x, 3 * n * sizeof(double));
  memcpy(q.v, p->v, 3 * n * sizeof(double));
  memcpy(q.w, p->w, 3 * n * sizeof(double));
  memcpy(q.f, p->f, 3 * n * sizeof(double));
  memcpy(q.t, p->t, 3 * n * sizeof(double));
  memcpy(q.radius, p->radius, n * sizeof(double));
  memcpy(q.mass, p->mass, n * sizeof(double));
  memcpy(q.inv_mass, p->inv_mass, n * sizeof(double));
  memcpy(q.inertia, p->inertia, n * sizeof(double));
  memcpy(q.inv_inertia, p->inv_inertia, n * sizeof(double));
  memcpy(q.material, p->material, n * sizeof(int32_t));
  memcpy(q.id, p->id, n * sizeof(int64_t));
  esf_particles_release(p);
  *p = q;
  return ESF_OK;
}
