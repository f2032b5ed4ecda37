/* scene_insert.c — a `particles:` entry {insert: {...}} (docs/scene.md#insert): particles
 * inserted during the run (loads/insert.h). Reads and checks region, rate or
 * mass_rate, radius (the generators' size distributions), material (a name or a mix),
 * velocity, seed, start, stop, count and every; every error names file:line:column. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "loads/insert.h"
#include "scene/scene_parts.h"

static int read_times(const esf_ynode *m, esf_insert *in, esf_error *err) {
  in->stop = INFINITY;
  int rc = esf_yget_double(m, "start", 0, &in->start, err);
  if (!rc) rc = esf_yget_double(m, "stop", 0, &in->stop, err);
  if (!rc) rc = esf_yget_double(m, "every", 0, &in->every, err);
  if (rc) return rc;
  if (!isfinite(in->start) || in->start < 0)
    return esf_ynode_fail(esf_ymap_get(m, "start"), err, "must be >= 0 (s), got %g",
                          in->start);
  if (!(in->stop > in->start))
    return esf_ynode_fail(esf_ymap_get(m, "stop"), err,
                          "must be after start (%g s), got %g", in->start, in->stop);
  if (!isfinite(in->every) || in->every < 0)
    return esf_ynode_fail(esf_ymap_get(m, "every"), err,
                          "must be >= 0 (s between batches; 0: 100 steps), got %g",
                          in->every);
  return ESF_OK;
}

static int read_rate(const esf_ynode *m, esf_insert *in, esf_error *err) {
  const esf_ynode *r = esf_ymap_get(m, "rate"), *mr = esf_ymap_get(m, "mass_rate");
  if ((r != NULL) == (mr != NULL))
    return esf_ynode_fail(m, err, "give one of rate (particles/s) or mass_rate (kg/s)");
  int rc = esf_yget_double(m, r ? "rate" : "mass_rate", 1, r ? &in->rate : &in->mass_rate,
                           err);
  const double v = r ? in->rate : in->mass_rate;
  if (!rc && (!isfinite(v) || !(v > 0)))
    return esf_ynode_fail(r ? r : mr, err, "must be positive, got %g", v);
  long count = 0;
  if (!rc) rc = esf_yget_long(m, "count", 0, &count, err);
  if (!rc && count < 0)
    return esf_ynode_fail(esf_ymap_get(m, "count"), err,
                          "must be >= 0 (0: no limit), got %ld", count);
  in->fill.count = (size_t)count;
  return rc;
}

int esf_scene_insert(const esf_ynode *e, esf_sim *s, esf_error *err) {
  static const char *const outer[] = {"insert", NULL};
  static const char *const keys[] = {"region",   "rate",     "mass_rate", "radius",
                                     "material", "velocity", "seed",      "start",
                                     "stop",     "count",    "every",     NULL};
  static const char *const rkeys[] = {"min", "max", NULL};
  int rc = esf_ymap_check_keys(e, outer, err);
  const esf_ynode *m = esf_ymap_get(e, "insert");
  if (!rc) rc = esf_ynode_require_map(m, err);
  if (!rc) rc = esf_ymap_check_keys(m, keys, err);
  if (rc) return rc;
  esf_insert in;
  memset(&in, 0, sizeof in);
  in.fill.dim = s->cfg.dim;
  esf_ynode_where(m, in.where, sizeof in.where);
  const esf_ynode *rg = esf_ymap_get(m, "region");
  if (!rg)
    return esf_ynode_fail(m, err, "missing key 'region' ({min: [...], max: [...]})");
  rc = esf_ymap_check_keys(rg, rkeys, err);
  if (!rc) rc = esf_yget_doubles(rg, "min", 1, in.fill.min, 3, err);
  if (!rc) rc = esf_yget_doubles(rg, "max", 1, in.fill.max, 3, err);
  if (!rc) rc = read_rate(m, &in, err);
  if (!rc) rc = read_times(m, &in, err);
  long seed = 1;
  if (!rc) rc = esf_yget_long(m, "seed", 0, &seed, err);
  in.fill.seed = (uint64_t)seed;
  if (!rc) rc = esf_yget_doubles(m, "velocity", 0, in.fill.velocity, 3, err);
  if (!rc && s->cfg.dim == 2 && in.fill.velocity[1] != 0.0)
    return esf_ynode_fail(esf_ymap_get(m, "velocity"), err,
                          "a 2D scene's disks move in the x-z plane: vy must be 0");
  const esf_ynode *rn = esf_ymap_get(m, "radius"), *mn = esf_ymap_get(m, "material");
  if (!rc && !rn) return esf_ynode_fail(m, err, "missing key 'radius'");
  if (!rc && !mn) return esf_ynode_fail(m, err, "missing key 'material'");
  if (rc) return rc;
  rc = esf_scene_size(rn, &in.fill.size, &in.sbuf, err);
  if (!rc) rc = esf_scene_mix(mn, s, &in.fill.mix, &in.mats, &in.fr, err);
  if (!rc) rc = esf_size_check(&in.fill.size, &in.rmax, &in.rmin, err);
  if (!rc) {
    double rmax;
    rc = esf_fill_spec_check(&in.fill, &rmax, err);
    if (rc) esf_error_prefix(err, "%s: insert: ", in.where);
  }
  if (!rc) rc = esf_inserts_add(&s->insert, &in, err);
  if (rc) {
    free(in.sbuf);
    free(in.mats);
    free(in.fr);
  }
  return rc;
}
