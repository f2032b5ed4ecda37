/* scene_meshes.c — the mesh walls of a scene's `walls:` list (docs/scene.md): an STL
 * file (`mesh:`), a faceted cylinder (`cylinder:`) and a screw (`screw:`), each one wall
 * group of polygons (wall_gen.h, stl.h) that moves as a whole.
 * STL vertices x (file units) are placed at R (scale x) + translate, R the rotation by
 * `degrees` about `axis` through the origin; a relative path is relative to the scene
 * file. Errors name the scene key's place and, for the file's contents, the file and
 * line or triangle (stl.h); exit status 2. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bodies/wall_gen.h"
#include "formats/stl.h"
#include "scene/scene.h"
#include "scene/scene_parts.h"
#include "util/vec3.h"

/* `caps: [bottom, top]` (either, both or none) */
static int read_caps(const esf_ynode *m, int *bottom, int *top, esf_error *err) {
  const esf_ynode *c = esf_ymap_get(m, "caps");
  if (!c) return ESF_OK;
  *bottom = *top = 0;
  int rc = esf_ynode_require_seq(c, err);
  for (size_t k = 0; k < (c ? c->n : 0) && !rc; k++) {
    const char *s = NULL;
    rc = esf_ynode_string(c->items[k], &s, err);
    if (rc) break;
    if (strcmp(s, "bottom") == 0)
      *bottom = 1;
    else if (strcmp(s, "top") == 0)
      *top = 1;
    else
      return esf_ynode_fail(c->items[k], err, "unknown end '%s' (expected bottom, top)",
                            s);
  }
  return rc;
}

/* `axis` (default z), normalised */
static int read_axis(const esf_ynode *m, double a[3], esf_error *err) {
  v3_set(a, 0, 0, 1);
  return esf_scene_unit_vector(m, "axis", 0, a, err);
}

static int read_count(const esf_ynode *m, const char *key, int lo, int *out,
                      esf_error *err) {
  long v = *out;
  int rc = esf_yget_long(m, key, 0, &v, err);
  if (!rc && (v < lo || v > 100000))
    return esf_ynode_fail(esf_ymap_get(m, key), err, "must be between %d and 100000", lo);
  *out = (int)v;
  return rc;
}

static int read_elements(const esf_ynode *m, int *quads, esf_error *err) {
  static const char *const names[] = {"triangles", "quads", NULL};
  int k = *quads;
  int rc = esf_yget_choice(m, "elements", 0, names, &k, err);
  *quads = k;
  return rc;
}

int esf_scene_wall_cylinder(const esf_ynode *e, esf_sim *s, int group, int32_t mat,
                            esf_error *err) {
  static const char *const keys[] = {"base", "axis",   "radius",   "height", "segments",
                                     "caps", "facing", "elements", NULL};
  static const char *const facings[] = {"outward", "inward", NULL};
  const esf_ynode *c = esf_ymap_get(e, "cylinder");
  esf_cylinder_spec sp = {.segments = 32, .inward = 1, .quads = 1};
  int rc = esf_ynode_require_map(c, err);
  if (!rc) rc = esf_ymap_check_keys(c, keys, err);
  if (!rc) rc = esf_yget_doubles(c, "base", 1, sp.base, 3, err);
  if (!rc) rc = read_axis(c, sp.axis, err);
  if (!rc) rc = esf_yget_double(c, "radius", 1, &sp.radius, err);
  if (!rc) rc = esf_yget_double(c, "height", 1, &sp.height, err);
  if (!rc) rc = read_count(c, "segments", 3, &sp.segments, err);
  if (!rc) rc = read_caps(c, &sp.cap_bottom, &sp.cap_top, err);
  if (!rc) rc = esf_yget_choice(c, "facing", 0, facings, &sp.inward, err);
  if (!rc) rc = read_elements(c, &sp.quads, err);
  if (rc) return rc;
  rc = esf_wall_gen_cylinder(&sp, mat, group, &s->walls, err);
  return rc ? esf_scene_fail_at(c, err) : ESF_OK;
}

int esf_scene_wall_screw(const esf_ynode *e, esf_sim *s, int group, int32_t mat,
                         esf_error *err) {
  static const char *const keys[] = {
      "base",   "axis",     "shaft_radius", "radius",   "pitch", "turns", "start",
      "length", "segments", "radial",       "elements", "caps",  NULL};
  const esf_ynode *c = esf_ymap_get(e, "screw");
  esf_screw_spec sp = {
      .segments = 36, .radial = 1, .quads = 1, .cap_bottom = 1, .cap_top = 1};
  int rc = esf_ynode_require_map(c, err);
  if (!rc) rc = esf_ymap_check_keys(c, keys, err);
  if (!rc) rc = esf_yget_doubles(c, "base", 1, sp.base, 3, err);
  if (!rc) rc = read_axis(c, sp.axis, err);
  if (!rc) rc = esf_yget_double(c, "shaft_radius", 1, &sp.shaft_radius, err);
  if (!rc) rc = esf_yget_double(c, "radius", 1, &sp.radius, err);
  if (!rc) rc = esf_yget_double(c, "pitch", 1, &sp.pitch, err);
  if (!rc) rc = esf_yget_double(c, "turns", 1, &sp.turns, err);
  if (!rc) rc = esf_yget_double(c, "start", 0, &sp.start, err);
  sp.length = sp.start + sp.turns * fabs(sp.pitch);
  if (!rc) rc = esf_yget_double(c, "length", 0, &sp.length, err);
  if (!rc) rc = read_count(c, "segments", 3, &sp.segments, err);
  if (!rc) rc = read_count(c, "radial", 1, &sp.radial, err);
  if (!rc) rc = read_elements(c, &sp.quads, err);
  if (!rc) rc = read_caps(c, &sp.cap_bottom, &sp.cap_top, err);
  if (rc) return rc;
  rc = esf_wall_gen_screw(&sp, mat, group, &s->walls, err);
  return rc ? esf_scene_fail_at(c, err) : ESF_OK;
}

int esf_scene_wall_stl(const esf_ynode *e, const char *dir, esf_sim *s, int group,
                       int32_t mat, esf_error *err) {
  static const char *const keys[] = {"file", "scale", "rotate", "translate", NULL};
  static const char *const rkeys[] = {"axis", "degrees", NULL};
  const esf_ynode *m = esf_ymap_get(e, "mesh");
  const char *file = NULL;
  double scale = 1, tr[3] = {0, 0, 0}, axis[3] = {0, 0, 1}, deg = 0;
  int rc = esf_ynode_require_map(m, err);
  if (!rc) rc = esf_ymap_check_keys(m, keys, err);
  if (!rc) rc = esf_yget_string(m, "file", 1, &file, err);
  if (!rc) rc = esf_yget_double(m, "scale", 0, &scale, err);
  if (!rc && !(scale > 0))
    return esf_ynode_fail(esf_ymap_get(m, "scale"), err, "must be positive");
  if (!rc) rc = esf_yget_doubles(m, "translate", 0, tr, 3, err);
  const esf_ynode *ro = esf_ymap_get(m, "rotate");
  if (!rc && ro) {
    rc = esf_ynode_require_map(ro, err);
    if (!rc) rc = esf_ymap_check_keys(ro, rkeys, err);
    if (!rc) rc = read_axis(ro, axis, err);
    if (!rc) rc = esf_yget_double(ro, "degrees", 1, &deg, err);
  }
  if (rc) return rc;
  char path[2048], where[256];
  if (file[0] == '/' || !dir || !dir[0])
    snprintf(path, sizeof path, "%s", file);
  else
    snprintf(path, sizeof path, "%s/%s", dir, file);
  esf_ynode_where(esf_ymap_get(m, "file"), where, sizeof where);
  esf_stl stl;
  rc = esf_stl_read(path, &stl, err);
  if (rc) return esf_error_prefix(err, "%s: wall mesh: ", where);
  double ang = deg * ESF_PI / 180;
  for (size_t t = 0; t < stl.n && !rc; t++) {
    double v[3][3];
    for (int k = 0; k < 3; k++) {
      double sv[3];
      v3_scale(sv, scale, stl.v[t][k]);
      v3_rotate(v[k], sv, axis, ang);
      v3_add(v[k], v[k], tr);
    }
    esf_wall_elem el;
    rc = esf_wall_polygon_init(&el, 3, (const double(*)[3])v, mat, group, err);
    if (rc) {
      if (stl.binary)
        esf_error_prefix(err, "%s: wall mesh: %s: triangle %zu: ", where, path, t + 1);
      else
        esf_error_prefix(err, "%s: wall mesh: %s:%ld: ", where, path, stl.line[t]);
    }
    if (!rc) rc = esf_walls_add_elem(&s->walls, &el, err);
  }
  esf_stl_release(&stl);
  return rc;
}
