/* scene_domain.c — the scene's `domain.periodic` (docs/scene.md#top-level-keys): the
 * list of periodic axes, each named once ("x", "y", "z"; a 2D scene moves in x-z, so
 * not "y"), set as the periodic box of search/periodic.h over domain.min .. max, and
 * the removal test's box (keep_lo, keep_hi: the domain, unbounded on periodic axes);
 * `domain.shear: {rate, flow, gradient}`, Lees-Edwards simple shear between two
 * distinct periodic axes (docs/physics.md#lees-edwards-shear).
 * Entry: c->domain_min < c->domain_max read, c->dim set. Exit: c->per, c->keep_lo,
 * c->keep_hi set, or a located ESF_EINPUT error. */
#include <math.h>
#include <string.h>

#include "scene/scene_parts.h"

/* An axis name: 0, 1, 2 for "x", "y", "z", else -1. */
static int axis_of(const char *name) {
  return !strcmp(name, "x") ? 0 : !strcmp(name, "y") ? 1 : !strcmp(name, "z") ? 2 : -1;
}

/* domain.shear: rate (1/s), flow and gradient axes, both periodic and distinct. */
static int read_shear(const esf_ynode *sh, esf_config *c, esf_error *err) {
  static const char *const keys[] = {"rate", "flow", "gradient", NULL};
  int rc = esf_ymap_check_keys(sh, keys, err);
  const char *name[2] = {NULL, NULL};
  const char *key[2] = {"flow", "gradient"};
  int ax[2] = {-1, -1};
  if (!rc) rc = esf_yget_double(sh, "rate", 1, &c->per.rate, err);
  if (!rc && !isfinite(c->per.rate))
    return esf_ynode_fail(esf_ymap_get(sh, "rate"), err, "must be a finite number");
  for (int k = 0; k < 2 && !rc; k++) {
    rc = esf_yget_string(sh, key[k], 1, &name[k], err);
    if (rc) break;
    ax[k] = axis_of(name[k]);
    if (ax[k] < 0 || !c->per.on[ax[k]])
      return esf_ynode_fail(esf_ymap_get(sh, key[k]), err,
                            "must name a periodic axis (domain.periodic), got '%s'",
                            name[k]);
  }
  if (!rc && ax[0] == ax[1])
    return esf_ynode_fail(sh, err, "flow and gradient must be different axes");
  if (rc) return rc;
  c->per.le = 1;
  c->per.flow = ax[0];
  c->per.grad = ax[1];
  return ESF_OK;
}

int esf_scene_periodic(const esf_ynode *dom, esf_config *c, esf_error *err) {
  memset(&c->per, 0, sizeof c->per);
  for (int q = 0; q < 3; q++) {
    c->keep_lo[q] = c->domain_min[q];
    c->keep_hi[q] = c->domain_max[q];
  }
  const esf_ynode *per = esf_ymap_get(dom, "periodic"), *sh = esf_ymap_get(dom, "shear");
  if (!per && sh)
    return esf_ynode_fail(sh, err,
                          "needs domain.periodic with its flow and gradient axes");
  if (!per) return ESF_OK;
  int rc = esf_ynode_require_seq(per, err);
  if (rc) return rc;
  for (size_t k = 0; k < per->n; k++) {
    const char *name = NULL;
    rc = esf_ynode_string(per->items[k], &name, err);
    if (rc) return rc;
    const int q = axis_of(name);
    if (q < 0)
      return esf_ynode_fail(per->items[k], err, "an axis is x, y or z, got '%s'", name);
    if (c->per.on[q])
      return esf_ynode_fail(per->items[k], err, "axis %s is listed twice", name);
    if (q == 1 && c->dim == 2)
      return esf_ynode_fail(per->items[k], err,
                            "a 2D scene moves in the x-z plane: y cannot be periodic");
    c->per.on[q] = 1;
    c->per.any = 1;
    c->per.lo[q] = c->domain_min[q];
    c->per.len[q] = c->domain_max[q] - c->domain_min[q];
    c->keep_lo[q] = -INFINITY;
    c->keep_hi[q] = INFINITY;
  }
  return sh ? read_shear(sh, c, err) : ESF_OK;
}
