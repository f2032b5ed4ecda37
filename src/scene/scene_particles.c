/* scene_particles.c — the `particles:` list of a scene: explicit particles, CSV files
 * and generators (docs/scene.md#particles-a-list-ids-follow-the-order-of-definition);
 * insert entries go to scene_insert.c.
 * Entries are read in order; ids follow that order. Explicit particles that overlap
 * each other are an error (naming both entries) unless contact.allow_initial_overlap
 * is true; packings from files and generators are taken as they are (a settled packing
 * has contacts). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/particle_source.h"
#include "scene/scene.h"
#include "scene/scene_parts.h"
#include "search/cells.h"

typedef struct lookup_ctx {
  const esf_materials *m;
} lookup_ctx;

static int lookup(void *ctx, const char *name, int32_t *index, esf_error *err) {
  const lookup_ctx *c = ctx;
  *index = esf_materials_find(c->m, name);
  if (*index < 0) return esf_fail(err, ESF_EINPUT, "unknown material '%s'", name);
  return ESF_OK;
}

static int read_explicit(const esf_ynode *e, esf_sim *s, esf_particle_defs *defs,
                         esf_error *err) {
  static const char *const keys[] = {"material", "radius",           "position",
                                     "velocity", "angular_velocity", NULL};
  int rc = esf_ymap_check_keys(e, keys, err);
  if (rc) return rc;
  esf_particle_def d;
  memset(&d, 0, sizeof d);
  const esf_ynode *mn = esf_ymap_get(e, "material");
  if (!mn) return esf_ynode_fail(e, err, "missing key 'material'");
  rc = esf_scene_material(mn, &s->mats, &d.material, err);
  if (!rc) rc = esf_yget_double(e, "radius", 1, &d.radius, err);
  if (!rc && !(d.radius > 0))
    return esf_ynode_fail(esf_ymap_get(e, "radius"), err, "must be positive, got %g",
                          d.radius);
  if (!rc) rc = esf_yget_doubles(e, "position", 1, d.x, 3, err);
  if (!rc) rc = esf_yget_doubles(e, "velocity", 0, d.v, 3, err);
  if (!rc) rc = esf_yget_doubles(e, "angular_velocity", 0, d.w, 3, err);
  if (!rc) rc = esf_particle_defs_push(defs, &d, err);
  return rc;
}

static int read_file(const esf_ynode *e, const char *dir, esf_sim *s,
                     esf_particle_defs *defs, esf_error *err) {
  static const char *const keys[] = {"file", "material", NULL};
  int rc = esf_ymap_check_keys(e, keys, err);
  const char *file = NULL;
  if (!rc) rc = esf_yget_string(e, "file", 1, &file, err);
  int32_t mat = -1;
  const esf_ynode *mn = esf_ymap_get(e, "material");
  if (!rc && mn) rc = esf_scene_material(mn, &s->mats, &mat, err);
  if (rc) return rc;
  char path[2048];
  if (file[0] == '/' || !dir || !dir[0])
    snprintf(path, sizeof path, "%s", file);
  else
    snprintf(path, sizeof path, "%s/%s", dir, file);
  lookup_ctx ctx = {&s->mats};
  rc = esf_particles_read_csv(path, mat, lookup, &ctx, defs, err);
  if (rc) {
    char where[512];
    esf_ynode_where(esf_ymap_get(e, "file"), where, sizeof where);
    esf_error_prefix(err, "%s: particles from file: ", where);
  }
  return rc;
}

static int read_generate(const esf_ynode *e, esf_sim *s, esf_particle_defs *defs,
                         esf_error *err) {
  static const char *const keys[] = {"generate", "region",   "count",
                                     "spacing",  "radius",   "material",
                                     "seed",     "velocity", NULL};
  static const char *const kinds[] = {"random", "lattice", NULL};
  int rc = esf_ymap_check_keys(e, keys, err);
  int kind = 0;
  if (!rc) rc = esf_yget_choice(e, "generate", 1, kinds, &kind, err);
  esf_fill_spec sp;
  memset(&sp, 0, sizeof sp);
  sp.dim = s->cfg.dim;
  const esf_ynode *rg = esf_ymap_get(e, "region");
  if (!rc && !rg)
    return esf_ynode_fail(e, err, "missing key 'region' ({min: [...], max: [...]})");
  static const char *const rkeys[] = {"min", "max", NULL};
  if (!rc) rc = esf_ymap_check_keys(rg, rkeys, err);
  if (!rc) rc = esf_yget_doubles(rg, "min", 1, sp.min, 3, err);
  if (!rc) rc = esf_yget_doubles(rg, "max", 1, sp.max, 3, err);
  long count = 0, seed = 1;
  if (!rc) rc = esf_yget_long(e, "count", kind == 0, &count, err);
  if (!rc && count < 0)
    return esf_ynode_fail(esf_ymap_get(e, "count"), err, "must be >= 0");
  if (!rc) rc = esf_yget_double(e, "spacing", 0, &sp.spacing, err);
  if (!rc) rc = esf_yget_long(e, "seed", 0, &seed, err);
  if (!rc) rc = esf_yget_doubles(e, "velocity", 0, sp.velocity, 3, err);
  sp.count = (size_t)count;
  sp.seed = (uint64_t)seed;
  const esf_ynode *rn = esf_ymap_get(e, "radius"), *mn = esf_ymap_get(e, "material");
  if (!rc && !rn) return esf_ynode_fail(e, err, "missing key 'radius'");
  if (!rc && !mn) return esf_ynode_fail(e, err, "missing key 'material'");
  if (rc) return rc;
  double *sbuf = NULL, *fr = NULL;
  int32_t *mats = NULL;
  rc = esf_scene_size(rn, &sp.size, &sbuf, err);
  if (!rc) rc = esf_scene_mix(mn, s, &sp.mix, &mats, &fr, err);
  if (!rc) {
    rc = kind == 0 ? esf_generate_random(&sp, defs, defs, err)
                   : esf_generate_lattice(&sp, defs, err);
    if (rc) {
      char where[512];
      esf_ynode_where(e, where, sizeof where);
      esf_error_prefix(err, "%s: generate: ", where);
    }
  }
  free(sbuf);
  free(mats);
  free(fr);
  return rc;
}

static int check_explicit_overlap(const esf_particle_defs *defs, const size_t *first,
                                  const esf_ynode *const *src, size_t nexp,
                                  esf_error *err) {
  if (nexp < 2) return ESF_OK;
  double *x = malloc(nexp * 3 * sizeof *x), *r = malloc(nexp * sizeof *r);
  esf_pairbuf pb = {0};
  int rc = (!x || !r) ? esf_fail(err, ESF_ENOMEM, "out of memory") : ESF_OK;
  for (size_t k = 0; k < nexp && !rc; k++) {
    const esf_particle_def *d = &defs->d[first[k]];
    memcpy(x + 3 * k, d->x, sizeof d->x);
    r[k] = d->radius;
  }
  if (!rc) rc = esf_pairs_brute(nexp, x, r, 0.0, &pb, err);
  if (!rc && pb.n) {
    char wa[512], wb[512];
    esf_ynode_where(src[pb.i[0]], wa, sizeof wa);
    esf_ynode_where(src[pb.j[0]], wb, sizeof wb);
    rc = esf_fail(err, ESF_EINPUT,
                  "%s: this particle overlaps the one at %s (%zu overlapping pairs in "
                  "all); move them apart or set contact.allow_initial_overlap: true",
                  wb, wa, pb.n);
  }
  esf_pairbuf_release(&pb);
  free(x);
  free(r);
  return rc;
}

int esf_scene_particles(const esf_ynode *seq, const char *dir, esf_sim *s,
                        uint32_t **entry, esf_error *err) {
  *entry = NULL;
  int rc = esf_ynode_require_seq(seq, err);
  if (rc) return rc;
  esf_particle_defs defs = {0};
  size_t *first = calloc(seq->n + 1, sizeof *first);
  size_t *end = calloc(seq->n + 1, sizeof *end); /* defs.n after entry k */
  const esf_ynode **src = calloc(seq->n + 1, sizeof *src);
  size_t nexp = 0;
  if (!first || !end || !src) rc = esf_fail(err, ESF_ENOMEM, "out of memory");
  for (size_t k = 0; k < seq->n && !rc; end[k++] = defs.n) {
    const esf_ynode *e = seq->items[k];
    rc = esf_ynode_require_map(e, err);
    if (rc) break;
    if (esf_ymap_get(e, "insert")) {
      rc = esf_scene_insert(e, s, err); /* during the run (scene_insert.c) */
    } else if (esf_ymap_get(e, "generate")) {
      rc = read_generate(e, s, &defs, err);
    } else if (esf_ymap_get(e, "file")) {
      rc = read_file(e, dir, s, &defs, err);
    } else {
      first[nexp] = defs.n;
      src[nexp++] = e;
      rc = read_explicit(e, s, &defs, err);
    }
  }
  if (!rc && !s->cfg.allow_initial_overlap)
    rc = check_explicit_overlap(&defs, first, src, nexp, err);
  if (!rc && defs.n == 0 && !s->insert)
    rc = esf_ynode_fail(seq, err, "the scene defines no particles");
  if (!rc) rc = esf_particles_alloc(&s->p, defs.n, err);
  if (!rc && !(*entry = malloc((defs.n ? defs.n : 1) * sizeof **entry)))
    rc = esf_fail(err, ESF_ENOMEM, "out of memory");
  for (size_t i = 0, k = 0; i < defs.n && !rc; i++) {
    while (end[k] <= i) k++;
    (*entry)[i] = (uint32_t)k;
    const esf_particle_def *d = &defs.d[i];
    memcpy(s->p.x + 3 * i, d->x, sizeof d->x);
    memcpy(s->p.v + 3 * i, d->v, sizeof d->v);
    memcpy(s->p.w + 3 * i, d->w, sizeof d->w);
    s->p.radius[i] = d->radius;
    s->p.material[i] = d->material;
    s->p.id[i] = (int64_t)i;
  }
  free(first);
  free(end);
  free(src);
  esf_particle_defs_release(&defs);
  return rc;
}
