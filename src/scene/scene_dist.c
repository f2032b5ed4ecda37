/* scene_dist.c — the size distribution (`radius`) and the material mix (`material`)
 * that generators and insert entries of the particles list share (scene_parts.h;
 * docs/scene.md#particles-a-list-ids-follow-the-order-of-definition): a radius or
 * {uniform | uniform_diameter: [a, b]} | {values, fractions}; a material name or
 * {mix: {name: fraction}}. Errors name file:line:column. Units: m. */
#include <stdlib.h>

#include "scene/scene.h"
#include "scene/scene_parts.h"

int esf_scene_size(const esf_ynode *r, esf_size_dist *sd, double **buf, esf_error *err) {
  static const char *const keys[] = {"uniform", "uniform_diameter", "values", "fractions",
                                     NULL};
  if (r->kind == ESF_YN_SCALAR) {
    sd->kind = ESF_SIZE_FIXED;
    int rc = esf_ynode_double(r, &sd->a, err);
    if (!rc && !(sd->a > 0)) return esf_ynode_fail(r, err, "must be positive");
    return rc;
  }
  int rc = esf_ymap_check_keys(r, keys, err);
  if (rc) return rc;
  const esf_ynode *u = esf_ymap_get(r, "uniform"),
                  *ud = esf_ymap_get(r, "uniform_diameter"),
                  *v = esf_ymap_get(r, "values");
  if ((u != NULL) + (ud != NULL) + (v != NULL) != 1)
    return esf_ynode_fail(r, err,
                          "give one of uniform: [rmin, rmax], uniform_diameter: "
                          "[dmin, dmax], or values: [...] with fractions: [...]");
  if (u || ud) {
    double ab[2];
    rc = esf_ynode_doubles(u ? u : ud, ab, 2, err);
    if (rc) return rc;
    double s = ud ? 0.5 : 1.0;
    sd->kind = ESF_SIZE_UNIFORM;
    sd->a = s * ab[0];
    sd->b = s * ab[1];
    if (!(sd->a > 0 && sd->b >= sd->a))
      return esf_ynode_fail(u ? u : ud, err, "need 0 < min <= max");
    return ESF_OK;
  }
  rc = esf_ynode_require_seq(v, err);
  const esf_ynode *f = esf_ymap_get(r, "fractions");
  if (!rc && !f) return esf_ynode_fail(r, err, "values need fractions: [...]");
  if (!rc) rc = esf_ynode_require_seq(f, err);
  if (rc) return rc;
  if (f->n != v->n || v->n == 0)
    return esf_ynode_fail(f, err, "need as many fractions as values (%zu), got %zu", v->n,
                          f->n);
  *buf = malloc(2 * v->n * sizeof **buf);
  if (!*buf) return esf_fail(err, ESF_ENOMEM, "out of memory");
  for (size_t k = 0; k < v->n && !rc; k++) {
    rc = esf_ynode_double(v->items[k], &(*buf)[k], err);
    if (!rc && !((*buf)[k] > 0))
      return esf_ynode_fail(v->items[k], err, "must be positive");
    if (!rc) rc = esf_ynode_double(f->items[k], &(*buf)[v->n + k], err);
  }
  sd->kind = ESF_SIZE_DISCRETE;
  sd->nvalues = v->n;
  sd->values = *buf;
  sd->fractions = *buf + v->n;
  return rc;
}

int esf_scene_mix(const esf_ynode *mn, const esf_sim *s, esf_material_mix *mix,
                  int32_t **mats, double **fr, esf_error *err) {
  *mats = NULL;
  *fr = NULL;
  if (mn->kind == ESF_YN_SCALAR) {
    *mats = malloc(sizeof **mats);
    *fr = malloc(sizeof **fr);
    if (!*mats || !*fr) return esf_fail(err, ESF_ENOMEM, "out of memory");
    (*fr)[0] = 1.0;
    mix->n = 1;
    mix->material = *mats;
    mix->fraction = *fr;
    return esf_scene_material(mn, &s->mats, &(*mats)[0], err);
  }
  static const char *const keys[] = {"mix", NULL};
  int rc = esf_ymap_check_keys(mn, keys, err);
  const esf_ynode *m = esf_ymap_get(mn, "mix");
  if (!rc && !m)
    return esf_ynode_fail(mn, err,
                          "give a material name or {mix: {name: fraction, ...}}");
  if (!rc) rc = esf_ynode_require_map(m, err);
  if (rc) return rc;
  if (m->n == 0) return esf_ynode_fail(m, err, "the mix is empty");
  *mats = malloc(m->n * sizeof **mats);
  *fr = malloc(m->n * sizeof **fr);
  if (!*mats || !*fr) return esf_fail(err, ESF_ENOMEM, "out of memory");
  for (size_t k = 0; k < m->n && !rc; k++) {
    (*mats)[k] = esf_materials_find(&s->mats, m->keys[k]);
    if ((*mats)[k] < 0)
      return esf_ynode_fail(m->items[k], err, "unknown material '%s'", m->keys[k]);
    rc = esf_ynode_double(m->items[k], &(*fr)[k], err);
    if (!rc && !((*fr)[k] >= 0)) return esf_ynode_fail(m->items[k], err, "must be >= 0");
  }
  mix->n = m->n;
  mix->material = *mats;
  mix->fraction = *fr;
  return rc;
}
