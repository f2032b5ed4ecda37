/* scene_walls.c — the `walls:` list of a scene
 * (docs/scene.md#walls-a-list-each-entry-is-one-wall): an infinite plane, a polygon
 * (triangle or quadrilateral) and the box helper (inward quadrilaterals less the open
 * faces). Each entry becomes one wall group; its material must be defined.
 * Prescribed motion (`motion:`, scene_motion.c): the whole wall (a box: all its faces)
 * moves rigidly (wall_motion.c). `name:` names a wall for the events that remove or add
 * it (scene_loads.c). Mesh walls (an STL file, a cylinder, a screw) are read in
 * scene_meshes.c. */
#include <stdio.h>
#include <string.h>

#include "scene/scene.h"
#include "scene/scene_parts.h"
#include "util/vec3.h"

static int wall_material(const esf_ynode *e, const esf_sim *s, int32_t *m,
                         esf_error *err) {
  const esf_ynode *mn = esf_ymap_get(e, "material");
  if (!mn) return esf_ynode_fail(e, err, "missing key 'material'");
  return esf_scene_material(mn, &s->mats, m, err);
}

static int read_box(const esf_ynode *e, esf_sim *s, int group, int32_t mat,
                    esf_error *err) {
  static const char *const bkeys[] = {"min", "max", NULL};
  static const char *const faces[] = {"xmin",   "xmax", "ymin", "ymax",
                                      "bottom", "top",  NULL};
  const esf_ynode *b = esf_ymap_get(e, "box");
  double lo[3], hi[3];
  int rc = esf_ynode_require_map(b, err);
  if (!rc) rc = esf_ymap_check_keys(b, bkeys, err);
  if (!rc) rc = esf_yget_doubles(b, "min", 1, lo, 3, err);
  if (!rc) rc = esf_yget_doubles(b, "max", 1, hi, 3, err);
  unsigned mask = 0;
  const esf_ynode *op = esf_ymap_get(e, "open");
  if (!rc && op) {
    rc = esf_ynode_require_seq(op, err);
    for (size_t k = 0; k < (op ? op->n : 0) && !rc; k++) {
      const char *f = NULL;
      rc = esf_ynode_string(op->items[k], &f, err);
      int hit = -1;
      for (int q = 0; faces[q] && !rc; q++)
        if (strcmp(faces[q], f) == 0) hit = q;
      if (!rc && hit < 0)
        return esf_ynode_fail(op->items[k], err,
                              "unknown face '%s' (expected one of: xmin, xmax, ymin, "
                              "ymax, bottom, top)",
                              f);
      if (!rc) mask |= 1u << hit;
    }
  }
  if (s->cfg.dim == 2) mask |= 4u | 8u; /* a 2D box has no y faces */
  if (rc) return rc;
  esf_wall_elem el[6];
  int count = 0;
  rc = esf_wall_box(lo, hi, mask, mat, group, el, &count, err);
  if (rc) return esf_scene_fail_at(b, err);
  for (int k = 0; k < count && !rc; k++) rc = esf_walls_add_elem(&s->walls, &el[k], err);
  return rc;
}

static int read_plane(const esf_ynode *e, esf_sim *s, int group, int32_t mat,
                      esf_error *err) {
  static const char *const pkeys[] = {"point", "normal", NULL};
  const esf_ynode *p = esf_ymap_get(e, "plane");
  double pt[3], nr[3];
  int rc = esf_ynode_require_map(p, err);
  if (!rc) rc = esf_ymap_check_keys(p, pkeys, err);
  if (!rc) rc = esf_yget_doubles(p, "point", 1, pt, 3, err);
  if (!rc) rc = esf_yget_doubles(p, "normal", 1, nr, 3, err);
  if (rc) return rc;
  esf_wall_elem el;
  rc = esf_wall_plane_init(&el, pt, nr, mat, group, err);
  if (rc) return esf_scene_fail_at(p, err);
  return esf_walls_add_elem(&s->walls, &el, err);
}

static int read_polygon(const esf_ynode *e, esf_sim *s, int group, int32_t mat,
                        esf_error *err) {
  const esf_ynode *p = esf_ymap_get(e, "polygon");
  int rc = esf_ynode_require_seq(p, err);
  if (rc) return rc;
  if (p->n < 3 || p->n > ESF_WALL_MAX_VERTS)
    return esf_ynode_fail(p, err, "a polygon has 3 or 4 vertices, got %zu", p->n);
  double v[ESF_WALL_MAX_VERTS][3];
  for (size_t k = 0; k < p->n && !rc; k++)
    rc = esf_ynode_doubles(p->items[k], v[k], 3, err);
  if (rc) return rc;
  esf_wall_elem el;
  rc = esf_wall_polygon_init(&el, (int)p->n, (const double(*)[3])v, mat, group, err);
  if (rc) return esf_scene_fail_at(p, err);
  return esf_walls_add_elem(&s->walls, &el, err);
}

/* name: a wall's unique name (the events' remove_wall, add_wall) into label */
static int wall_name(const esf_ynode *nm, const esf_walls *w, char *label, size_t len,
                     esf_error *err) {
  const char *name = NULL;
  int rc = esf_ynode_string(nm, &name, err);
  if (rc) return rc;
  if (!name[0] || strlen(name) >= len)
    return esf_ynode_fail(nm, err, "a wall name has 1 to %zu characters", len - 1);
  if (esf_walls_find(w, name) >= 0)
    return esf_ynode_fail(nm, err, "a wall named '%s' exists already", name);
  snprintf(label, len, "%s", name);
  return ESF_OK;
}

/* the mesh wall kinds (scene_meshes.c) */
static const char *const mesh_kinds[] = {"mesh", "cylinder", "screw", NULL};

int esf_scene_walls(const esf_ynode *seq, const char *dir, esf_sim *s, esf_error *err) {
  static const char *const keys[] = {"box",      "plane",  "polygon", "open",
                                     "material", "motion", "mesh",    "cylinder",
                                     "screw",    "name",   NULL};
  if (!seq || seq->kind == ESF_YN_NULL) return ESF_OK;
  int rc = esf_ynode_require_seq(seq, err);
  for (size_t k = 0; k < (seq ? seq->n : 0) && !rc; k++) {
    const esf_ynode *e = seq->items[k];
    rc = esf_ynode_require_map(e, err);
    if (!rc) rc = esf_ymap_check_keys(e, keys, err);
    if (rc) break;
    int nkind = (esf_ymap_get(e, "box") != NULL) + (esf_ymap_get(e, "plane") != NULL) +
                (esf_ymap_get(e, "polygon") != NULL);
    const char *mesh = NULL;
    for (int q = 0; mesh_kinds[q]; q++)
      if (esf_ymap_get(e, mesh_kinds[q])) nkind++, mesh = mesh_kinds[q];
    if (nkind != 1)
      return esf_ynode_fail(e, err,
                            "a wall is exactly one of box, plane, polygon, mesh, "
                            "cylinder or screw");
    if (esf_ymap_get(e, "open") && !esf_ymap_get(e, "box"))
      return esf_ynode_fail(esf_ymap_get(e, "open"), err, "only a box has open faces");
    int32_t mat = 0;
    rc = wall_material(e, s, &mat, err);
    if (rc) break;
    char label[32];
    const char *kind = esf_ymap_get(e, "box")     ? "box"
                       : esf_ymap_get(e, "plane") ? "plane"
                       : mesh                     ? mesh
                                                  : "polygon";
    snprintf(label, sizeof label, "%s %zu", kind, k);
    const esf_ynode *nm = esf_ymap_get(e, "name");
    if (nm) rc = wall_name(nm, &s->walls, label, sizeof label, err);
    int group = 0;
    if (!rc) rc = esf_walls_add_group(&s->walls, label, &group, err);
    if (rc) break;
    s->walls.g[group].named = nm != NULL;
    if (mesh && mesh[0] == 'm')
      rc = esf_scene_wall_stl(e, dir, s, group, mat, err);
    else if (mesh && mesh[0] == 'c')
      rc = esf_scene_wall_cylinder(e, s, group, mat, err);
    else if (mesh)
      rc = esf_scene_wall_screw(e, s, group, mat, err);
    else if (kind[0] == 'b')
      rc = read_box(e, s, group, mat, err);
    else if (kind[1] == 'l')
      rc = read_plane(e, s, group, mat, err);
    else
      rc = read_polygon(e, s, group, mat, err);
    const esf_ynode *mo = esf_ymap_get(e, "motion");
    if (!rc && mo) {
      rc = esf_scene_motion(mo, &s->walls, group, err);
      if (!rc && kind[1] == 'l' && s->walls.g[group].motion.kind == ESF_MOTION_ROTATE)
        return esf_ynode_fail(mo, err,
                              "an infinite plane cannot rotate; use a polygon or a box");
      if (!rc && kind[0] == 'b' && s->walls.g[group].motion.kind == ESF_MOTION_SERVO)
        return esf_ynode_fail(mo, err,
                              "a servo moves its whole wall, and a box's faces face each "
                              "other; make the servo-controlled face a polygon");
    }
  }
  return rc;
}
