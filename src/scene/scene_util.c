/* scene_util.c — helpers shared by the scene's readers (scene_parts.h): a builder's
 * message re-raised at a node, unit vectors, material names. */
#include "scene/scene_parts.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

int esf_scene_fail_at(const esf_ynode *n, esf_error *err) {
  char msg[ESF_ERROR_MSG_MAX];
  snprintf(msg, sizeof msg, "%s", err->msg);
  return esf_ynode_fail(n, err, "%s", msg);
}

int esf_scene_unit_vector(const esf_ynode *m, const char *key, int required, double u[3],
                          esf_error *err) {
  int rc = esf_yget_doubles(m, key, required, u, 3, err);
  if (rc) return rc;
  double len = sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  if (!(len > 0) || !isfinite(len))
    return esf_ynode_fail(esf_ymap_get(m, key), err, "must be a non-zero vector");
  for (int q = 0; q < 3; q++) u[q] /= len;
  return ESF_OK;
}

int esf_scene_material(const esf_ynode *node, const esf_materials *m, int32_t *index,
                       esf_error *err) {
  const char *name = NULL;
  int rc = esf_ynode_string(node, &name, err);
  if (rc) return rc;
  *index = esf_materials_find(m, name);
  if (*index >= 0) return ESF_OK;
  char list[512] = "";
  for (int k = 0; k < m->n; k++) {
    size_t l = strlen(list);
    snprintf(list + l, sizeof list - l, "%s%s", k ? ", " : "", m->m[k].name);
  }
  return esf_ynode_fail(node, err, "unknown material '%s' (defined: %s)", name, list);
}
