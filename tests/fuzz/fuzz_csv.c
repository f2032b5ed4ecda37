/* fuzz_csv.c — fuzzes the particle CSV reader (esf_particles_read_csv,
 * scene/particle_csv.c) with whole files.
 * How: the input is written to a scratch file and read twice, as a scene's
 * `{file: F, material: M}` entry does (a default material and a lookup that knows two
 * materials, so that a `material` column resolves) and as `{file: F}` without a
 * material does (no default), each into a list that already holds one definition.
 * What holds: the reader returns ESF_OK or an error with a message; on success it
 * appended only finite particles with positive radii and known materials, on failure
 * the list is back at its entry length; nothing leaks. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"
#include "scene/particle_source.h"

const char esf_fuzz_name[] = "csv";

static int lookup(void *ctx, const char *name, int32_t *index, esf_error *err) {
  (void)ctx;
  *index = !strcmp(name, "glass") ? 0 : !strcmp(name, "steel") ? 1 : -1;
  return *index < 0 ? esf_fail(err, ESF_EINPUT, "unknown material '%s'", name) : ESF_OK;
}

static int read_once(const char *path, int32_t mat, esf_error *err) {
  esf_particle_defs defs = {0};
  const esf_particle_def first = {.radius = 1.0, .material = 0};
  if (esf_particle_defs_push(&defs, &first, err)) abort();
  int rc = esf_particles_read_csv(path, mat, mat >= 0 ? lookup : NULL, NULL, &defs, err);
  if (rc && defs.n != 1) abort(); /* restored to its entry length */
  for (size_t i = 1; i < defs.n; i++) {
    const esf_particle_def *d = &defs.d[i];
    for (int k = 0; k < 3; k++)
      if (!isfinite(d->x[k]) || !isfinite(d->v[k]) || !isfinite(d->w[k])) abort();
    if (!(d->radius > 0) || !isfinite(d->radius) || d->material < 0 || d->material > 1)
      abort();
  }
  esf_particle_defs_release(&defs);
  return rc;
}

int esf_fuzz_one(const uint8_t *data, size_t size, esf_error *err) {
  const char *path = esf_fuzz_write("input.csv", data, size);
  esf_error other;
  esf_error_clear(&other);
  read_once(path, -1, &other);
  return read_once(path, 0, err);
}
