/* scene_domain.c — the scene's `domain.periodic` (docs/scene.md#top-level-keys): the
 * list of periodic axes, each named once ("x", "y", "z"; a 2D scene moves in x-z, so
 * not "y"), set as the periodic box of search/periodic.h over domain.min .. max, and
 * the removal test's box (keep_lo, keep_hi: the domain, unbounded on periodic axes).
 * Entry: c->domain_min < c->domain_max read, c->dim set. Exit: c->per, c->keep_lo,
 * c->keep_hi set, or a located ESF_EINPUT error. */
#include <math.h>
#include <string.h>

#include "scene/scene_parts.h"

int esf_scene_periodic(const esf_ynode *dom, esf_config *c, esf_error *err) {
  memset(&c->per, 0, sizeof c->per);
  for (int q = 0; q < 3; q++) {
    c->keep_lo[q] = c->domain_min[q];
    c->keep_hi[q] = c->domain_max[q];
  }
  const esf_ynode *per = esf_ymap_get(dom, "periodic");
  if (!per) return ESF_OK;
  int rc = esf_ynode_require_seq(per, err);
  if (rc) return rc;
  for (size_t k = 0; k < per->n; k++) {
    const char *name = NULL;
    rc = esf_ynode_string(per->items[k], &name, err);
    if (rc) return rc;
    const int q = !strcmp(name, "x")   ? 0
                  : !strcmp(name, "y") ? 1
                  : !strcmp(name, "z") ? 2
                                       : -1;
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
  return ESF_OK;
}
