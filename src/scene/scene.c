/* scene.c — the scene schema: top level, materials, mixing, integrator, damping,
 * contact, search, run and output sections (docs/scene.md). Particles and walls are read
 * in scene_particles.c and scene_walls.c. Defaults are set by esf_config_default and
 * documented in docs/scene.md; nothing misspelt is ever silently defaulted, because
 * every mapping is checked against its list of keys first. */
#include "scene/scene.h"
#include "scene/scene_parts.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_loads.h"
#include "util/vec3.h"

static int positive(const esf_ynode *map, const char *key, double v, int strict,
                    esf_error *err) {
  if (strict ? v > 0 : v >= 0) return ESF_OK;
  return esf_ynode_fail(esf_ymap_get(map, key), err, "must be %s, got %g",
                        strict ? "positive" : "non-negative", v);
}

/* adhesion: {force: F, epsilon: eps} (docs/physics.md#adhesive-normal-law-and-bonds),
 * checked by deriving the law with the material's own kn. */
static int read_adhesion(const esf_ynode *m, esf_material *mat, esf_error *err) {
  static const char *const keys[] = {"force", "epsilon", "bond_gap", NULL};
  const esf_ynode *ad = esf_ymap_get(m, "adhesion");
  if (!ad) return ESF_OK;
  int rc = esf_ynode_require_map(ad, err);
  if (!rc) rc = esf_ymap_check_keys(ad, keys, err);
  if (!rc) rc = esf_yget_double(ad, "force", 1, &mat->adhesion_force, err);
  if (!rc) rc = esf_yget_double(ad, "epsilon", 1, &mat->adhesion_epsilon, err);
  if (!rc) rc = esf_yget_double(ad, "bond_gap", 0, &mat->adhesion_gap, err);
  if (!rc) rc = positive(ad, "bond_gap", mat->adhesion_gap, 0, err);
  if (rc) return rc;
  esf_adhesion a;
  esf_error e2;
  esf_error_clear(&e2);
  if (!(mat->adhesion_force >= 0))
    return esf_ynode_fail(esf_ymap_get(ad, "force"), err,
                          "must be a non-negative force in N (the largest tension), "
                          "got %g",
                          mat->adhesion_force);
  if (mat->youngs_modulus > 0) return ESF_OK; /* refused by read_stiffness */
  if (esf_adhesion_derive(mat->adhesion_force, mat->adhesion_epsilon, mat->kn, &a, &e2))
    return esf_ynode_fail(esf_ymap_get(ad, "epsilon"), err, "%s", e2.msg);
  return ESF_OK;
}

/* rolling_friction mu_r, rolling_damping eta_r (a damping ratio, 0 to 1) and
 * twisting_friction mu_tw (docs/physics.md#rolling-resistance): all >= 0, default 0. */
static int read_rolling(const esf_ynode *m, esf_material *mat, esf_error *err) {
  int rc = esf_yget_double(m, "rolling_friction", 0, &mat->rolling_friction, err);
  if (!rc) rc = positive(m, "rolling_friction", mat->rolling_friction, 0, err);
  if (!rc) rc = esf_yget_double(m, "rolling_damping", 0, &mat->rolling_damping, err);
  if (!rc && !(mat->rolling_damping >= 0 && mat->rolling_damping <= 1))
    return esf_ynode_fail(esf_ymap_get(m, "rolling_damping"), err,
                          "must be a damping ratio in [0, 1], got %g",
                          mat->rolling_damping);
  if (!rc) rc = esf_yget_double(m, "twisting_friction", 0, &mat->twisting_friction, err);
  if (!rc) rc = positive(m, "twisting_friction", mat->twisting_friction, 0, err);
  return rc;
}

/* kn (and kt) for the linear law, or youngs_modulus and poisson_ratio for the
 * Hertz-Mindlin law (docs/scene.md#materials), never both. */
static int read_stiffness(const esf_ynode *m, esf_material *mat, esf_error *err) {
  const esf_ynode *E = esf_ymap_get(m, "youngs_modulus"),
                  *nu = esf_ymap_get(m, "poisson_ratio");
  const esf_ynode *kn = esf_ymap_get(m, "kn"), *kt = esf_ymap_get(m, "kt");
  if (!E && !nu) {
    int rc = esf_yget_double(m, "kn", 1, &mat->kn, err);
    if (!rc) rc = positive(m, "kn", mat->kn, 1, err);
    mat->kt = mat->kn;
    if (!rc) rc = esf_yget_double(m, "kt", 0, &mat->kt, err);
    if (!rc) rc = positive(m, "kt", mat->kt, 0, err);
    return rc;
  }
  if (kn || kt)
    return esf_ynode_fail(kn ? kn : kt, err,
                          "give kn (the linear law) or youngs_modulus and poisson_ratio "
                          "(Hertz-Mindlin), not both");
  if (!E || !nu)
    return esf_ynode_fail(m, err,
                          "the Hertz-Mindlin law needs both youngs_modulus and "
                          "poisson_ratio");
  int rc = esf_ynode_double(E, &mat->youngs_modulus, err);
  if (!rc && !(mat->youngs_modulus > 0))
    return esf_ynode_fail(E, err, "must be a positive modulus in Pa, got %g",
                          mat->youngs_modulus);
  if (!rc) rc = esf_ynode_double(nu, &mat->poisson_ratio, err);
  if (!rc && !(mat->poisson_ratio >= 0 && mat->poisson_ratio < 0.5))
    return esf_ynode_fail(nu, err, "must be in [0, 0.5), got %g", mat->poisson_ratio);
  if (!rc && esf_ymap_get(m, "adhesion"))
    return esf_ynode_fail(
        esf_ymap_get(m, "adhesion"), err,
        "adhesion (the adhesive law) is not defined for a Hertz-Mindlin "
        "material (youngs_modulus)");
  return rc;
}

static int read_material(const esf_ynode *name_key_map, size_t k, esf_sim *s,
                         esf_error *err) {
  static const char *const keys[] = {"density",
                                     "kn",
                                     "kt",
                                     "restitution",
                                     "tangential_restitution",
                                     "friction",
                                     "friction_angle",
                                     "cohesion",
                                     "tensile_limit",
                                     "adhesion",       /* bond: the adhesive law */
                                     "youngs_modulus", /* the Hertz-Mindlin law */
                                     "poisson_ratio",
                                     "rolling_friction",
                                     "rolling_damping",
                                     "twisting_friction",
                                     NULL};
  const esf_ynode *m = name_key_map->items[k];
  const char *name = name_key_map->keys[k];
  int rc = esf_ynode_require_map(m, err);
  if (!rc) rc = esf_ymap_check_keys(m, keys, err);
  if (rc) return rc;
  esf_material mat;
  memset(&mat, 0, sizeof mat);
  if (strlen(name) >= sizeof mat.name)
    return esf_ynode_fail(m, err, "material name longer than %d characters",
                          ESF_NAME_MAX - 1);
  snprintf(mat.name, sizeof mat.name, "%s", name);
  mat.density = 0;
  mat.restitution = 1.0;
  mat.friction = 0.0;
  mat.tensile_limit = -1;
  rc = esf_yget_double(m, "density", 0, &mat.density, err);
  if (!rc) rc = read_stiffness(m, &mat, err);
  if (!rc) rc = esf_yget_double(m, "restitution", 0, &mat.restitution, err);
  if (!rc && !(mat.restitution > 0 && mat.restitution <= 1))
    return esf_ynode_fail(esf_ymap_get(m, "restitution"), err,
                          "must be in (0, 1], got %g", mat.restitution);
  mat.tangential_restitution = mat.restitution;
  if (!rc)
    rc =
        esf_yget_double(m, "tangential_restitution", 0, &mat.tangential_restitution, err);
  if (!rc && !(mat.tangential_restitution > 0 && mat.tangential_restitution <= 1))
    return esf_ynode_fail(esf_ymap_get(m, "tangential_restitution"), err,
                          "must be in (0, 1], got %g", mat.tangential_restitution);
  if (rc) return rc;
  const esf_ynode *fr = esf_ymap_get(m, "friction"),
                  *fa = esf_ymap_get(m, "friction_angle");
  if (fr && fa)
    return esf_ynode_fail(fa, err, "give friction or friction_angle, not both");
  if (fr) rc = esf_ynode_double(fr, &mat.friction, err);
  if (fa) {
    double deg = 0;
    rc = esf_ynode_double(fa, &deg, err);
    if (!rc && !(deg >= 0 && deg < 90))
      return esf_ynode_fail(fa, err, "must be in [0, 90) degrees, got %g", deg);
    mat.friction = tan(deg * ESF_PI / 180.0);
  }
  if (!rc) rc = positive(m, "friction", mat.friction, 0, err);
  if (!rc) rc = esf_yget_double(m, "cohesion", 0, &mat.cohesion, err);
  if (!rc) rc = positive(m, "cohesion", mat.cohesion, 0, err);
  if (!rc && esf_ymap_get(m, "tensile_limit")) {
    rc = esf_yget_double(m, "tensile_limit", 1, &mat.tensile_limit, err);
    if (!rc) rc = positive(m, "tensile_limit", mat.tensile_limit, 0, err);
  }
  if (!rc && mat.density < 0)
    return esf_ynode_fail(esf_ymap_get(m, "density"), err, "must be positive");
  if (!rc) rc = read_adhesion(m, &mat, err);
  if (!rc) rc = read_rolling(m, &mat, err);
  if (rc) return rc;
  return esf_materials_add(&s->mats, &mat, NULL, err);
}

static int read_materials(const esf_ynode *root, esf_sim *s, esf_error *err) {
  const esf_ynode *ms = esf_ymap_get(root, "materials");
  if (!ms) return esf_ynode_fail(root, err, "missing key 'materials'");
  int rc = esf_ynode_require_map(ms, err);
  if (rc) return rc;
  if (ms->n == 0) return esf_ynode_fail(ms, err, "define at least one material");
  for (size_t k = 0; k < ms->n && !rc; k++) rc = read_material(ms, k, s, err);
  for (size_t k = 1; k < ms->n && !rc; k++) /* the laws never mix (material.c) */
    if ((s->mats.m[k].youngs_modulus > 0) != (s->mats.m[0].youngs_modulus > 0))
      return esf_ynode_fail(ms->items[k], err,
                            "material '%s' uses the %s law, material '%s' the %s law: a "
                            "Hertz-Mindlin material cannot meet a linear one (no mixing "
                            "rule); give every material youngs_modulus or every one kn",
                            s->mats.m[k].name,
                            s->mats.m[k].youngs_modulus > 0 ? "Hertz-Mindlin" : "linear",
                            s->mats.m[0].name,
                            s->mats.m[0].youngs_modulus > 0 ? "Hertz-Mindlin" : "linear");
  if (rc) return rc;
  esf_mixing_default(&s->mats.mixing);
  const esf_ynode *mx = esf_ymap_get(root, "mixing");
  static const char *const mkeys[] = {"kn",
                                      "kt",
                                      "restitution",
                                      "tangential_restitution",
                                      "friction",
                                      "cohesion",
                                      "tensile_limit",
                                      "adhesion_force",
                                      "adhesion_epsilon",
                                      "adhesion_bond_gap",
                                      "rolling_friction",
                                      "rolling_damping",
                                      "twisting_friction",
                                      NULL};
  if (!mx) return ESF_OK;
  rc = esf_ymap_check_keys(mx, mkeys, err);
  esf_mixing *r = &s->mats.mixing;
  int *slots[] = {&r->kn,
                  &r->kt,
                  &r->restitution,
                  &r->tangential_restitution,
                  &r->friction,
                  &r->cohesion,
                  &r->tensile_limit,
                  &r->adhesion_force,
                  &r->adhesion_epsilon,
                  &r->adhesion_gap,
                  &r->rolling_friction,
                  &r->rolling_damping,
                  &r->twisting_friction};
  for (int k = 0; mkeys[k] && !rc; k++)
    rc = esf_yget_choice(mx, mkeys[k], 0, esf_mix_names, slots[k], err);
  return rc;
}

static int read_integrator(const esf_ynode *root, esf_config *c, esf_error *err) {
  static const char *const keys[] = {
      "method",          "dt",    "dt_rule",      "frac",
      "allow_unstable",  "rtol",  "atol",         "history",
      "max_steps",       "roots", "fused",        "stability",
      "stability_every", "table", "impact_speed", NULL};
  const esf_ynode *in = esf_ymap_get(root, "integrator");
  if (!in) return ESF_OK;
  int rc = esf_ynode_require_map(in, err);
  if (!rc) rc = esf_ymap_check_keys(in, keys, err);
  const char *method = NULL;
  if (!rc) rc = esf_yget_string(in, "method", 0, &method, err);
  if (!rc && method) snprintf(c->method, sizeof c->method, "%s", method);
  const esf_ynode *dt = esf_ymap_get(in, "dt");
  if (!rc && dt) {
    if (dt->kind == ESF_YN_SCALAR && !dt->quoted && strcmp(dt->text, "auto") == 0) {
      c->dt_auto = 1;
    } else {
      rc = esf_ynode_double(dt, &c->dt, err);
      if (!rc && !(c->dt > 0))
        return esf_ynode_fail(dt, err, "must be a positive number of seconds or auto");
      c->dt_auto = 0;
    }
  }
  if (!rc) rc = esf_yget_choice(in, "dt_rule", 0, esf_dt_rule_names, &c->dt_rule, err);
  if (!rc) rc = esf_yget_double(in, "frac", 0, &c->frac, err);
  if (!rc && !(c->frac > 0))
    return esf_ynode_fail(esf_ymap_get(in, "frac"), err, "must be positive");
  if (!rc) rc = esf_yget_bool(in, "allow_unstable", 0, &c->allow_unstable, err);
  if (!rc) rc = esf_yget_double(in, "rtol", 0, &c->rtol, err);
  if (!rc) rc = positive(in, "rtol", c->rtol, 0, err);
  if (!rc) rc = esf_yget_double(in, "atol", 0, &c->atol, err);
  if (!rc) rc = positive(in, "atol", c->atol, 1, err);
  if (!rc) rc = esf_yget_choice(in, "history", 0, esf_history_names, &c->history, err);
  if (!rc) rc = esf_yget_long(in, "max_steps", 0, &c->max_steps, err);
  if (!rc && c->max_steps <= 0)
    return esf_ynode_fail(esf_ymap_get(in, "max_steps"), err, "must be positive");
  if (!rc) rc = esf_yget_bool(in, "roots", 0, &c->roots, err);
  if (!rc) rc = esf_yget_bool(in, "fused", 0, &c->fused, err);
  if (!rc) rc = esf_yget_choice(in, "stability", 0, esf_stab_names, &c->stability, err);
  if (!rc) rc = esf_yget_long(in, "stability_every", 0, &c->stability_every, err);
  if (!rc) rc = esf_yget_double(in, "impact_speed", 0, &c->impact_speed, err);
  if (!rc) rc = positive(in, "impact_speed", c->impact_speed, 1, err);
  if (!rc && c->stability_every <= 0)
    return esf_ynode_fail(esf_ymap_get(in, "stability_every"), err,
                          "must be a positive number of steps");
  if (!rc) rc = esf_scene_butcher(in, c, err); /* integrator.table (method erk) */
  return rc;
}

static int read_damping(const esf_ynode *root, esf_config *c, esf_error *err) {
  static const char *const keys[] = {"global", "local", "rayleigh", NULL};
  static const char *const gkeys[] = {"translation", "rotation", "auto", NULL};
  static const char *const akeys[] = {"a_fac", "a_mul", "min", "max", NULL};
  static const char *const lkeys[] = {"coefficient", "form", NULL};
  static const char *const rkeys[] = {"zeta", "frequency", NULL};
  static const char *const forms[] = {"off", "component", "vector", NULL};
  const esf_ynode *d = esf_ymap_get(root, "damping");
  if (!d) return ESF_OK;
  int rc = esf_ynode_require_map(d, err);
  if (!rc) rc = esf_ymap_check_keys(d, keys, err);
  const esf_ynode *g = esf_ymap_get(d, "global");
  if (!rc && g) {
    rc = esf_ymap_check_keys(g, gkeys, err);
    if (!rc) rc = esf_yget_double(g, "translation", 0, &c->alpha_r, err);
    if (!rc) rc = positive(g, "translation", c->alpha_r, 0, err);
    c->alpha_t = c->alpha_r;
    if (!rc) rc = esf_yget_double(g, "rotation", 0, &c->alpha_t, err);
    if (!rc) rc = positive(g, "rotation", c->alpha_t, 0, err);
    const esf_ynode *a = esf_ymap_get(g, "auto");
    if (!rc && a) {
      if (a->kind == ESF_YN_SCALAR) {
        rc = esf_ynode_bool(a, &c->autod.on, err);
      } else {
        c->autod.on = 1;
        rc = esf_ymap_check_keys(a, akeys, err);
        if (!rc) rc = esf_yget_double(a, "a_fac", 0, &c->autod.a_fac, err);
        if (!rc) rc = esf_yget_double(a, "a_mul", 0, &c->autod.a_mul, err);
        if (!rc && !(c->autod.a_mul > 1))
          return esf_ynode_fail(esf_ymap_get(a, "a_mul"), err, "must be > 1");
        if (!rc) rc = esf_yget_double(a, "min", 0, &c->autod.alpha_min, err);
        if (!rc) rc = esf_yget_double(a, "max", 0, &c->autod.alpha_max, err);
      }
    }
  }
  const esf_ynode *l = esf_ymap_get(d, "local");
  if (!rc && l) {
    rc = esf_ymap_check_keys(l, lkeys, err);
    if (!rc) rc = esf_yget_double(l, "coefficient", 0, &c->local_coef, err);
    if (!rc && !(c->local_coef >= 0 && c->local_coef < 1))
      return esf_ynode_fail(esf_ymap_get(l, "coefficient"), err, "must be in [0, 1)");
    int form = ESF_LOCAL_COMPONENT;
    if (!rc) rc = esf_yget_choice(l, "form", 0, forms, &form, err);
    c->local_form = c->local_coef > 0 ? form : ESF_LOCAL_OFF;
  }
  const esf_ynode *r = esf_ymap_get(d, "rayleigh");
  if (!rc && r) {
    if (g && (esf_ymap_get(g, "translation") || esf_ymap_get(g, "rotation")))
      return esf_ynode_fail(r, err,
                            "Rayleigh damping sets the global damping "
                            "(alpha = 2 omega zeta); remove damping.global");
    rc = esf_ymap_check_keys(r, rkeys, err);
    if (!rc) rc = esf_yget_double(r, "zeta", 1, &c->rayleigh_zeta, err);
    if (!rc) rc = esf_yget_double(r, "frequency", 1, &c->rayleigh_freq, err);
    if (!rc) rc = positive(r, "zeta", c->rayleigh_zeta, 0, err);
    if (!rc) rc = positive(r, "frequency", c->rayleigh_freq, 1, err);
    c->rayleigh = 1;
  }
  return rc;
}

static int read_misc(const esf_ynode *root, esf_config *c, esf_error *err) {
  static const char *const ckeys[] = {
      "tangential_frame", "hertz_damping", "max_overlap", "allow_initial_overlap",
      "wall_lever",       "rolling",       NULL};
  static const char *const frames[] = {"rotate", "project", NULL};
  static const char *const hdamp[] = {"tsuji", "constant", NULL};
  static const char *const levers[] = {"seed", "surface", NULL}; /* ESF_WALL_LEVER_* */
  static const char *const skeys[] = {"skin", "reorder", NULL};
  static const char *const rkeys[] = {"duration", "steps", NULL};
  static const char *const okeys[] = {"every",    "energy_every",     "dir",
                                      "contacts", "checkpoint_every", "walls",
                                      "stress",   "stress_every",     NULL};
  int rc = ESF_OK;
  const esf_ynode *ct = esf_ymap_get(root, "contact");
  if (ct) {
    rc = esf_ymap_check_keys(ct, ckeys, err);
    if (!rc) rc = esf_yget_choice(ct, "tangential_frame", 0, frames, &c->tframe, err);
    if (!rc) rc = esf_yget_choice(ct, "hertz_damping", 0, hdamp, &c->hertz_damping, err);
    if (!rc) rc = esf_yget_choice(ct, "wall_lever", 0, levers, &c->wall_lever, err);
    if (!rc) rc = esf_yget_choice(ct, "rolling", 0, esf_roll_names, &c->rolling, err);
    if (!rc) rc = esf_yget_double(ct, "max_overlap", 0, &c->max_overlap, err);
    if (!rc) rc = positive(ct, "max_overlap", c->max_overlap, 1, err);
    if (!rc)
      rc = esf_yget_bool(ct, "allow_initial_overlap", 0, &c->allow_initial_overlap, err);
  }
  const esf_ynode *se = esf_ymap_get(root, "search");
  if (!rc && se) {
    rc = esf_ymap_check_keys(se, skeys, err);
    if (!rc && esf_ymap_get(se, "skin")) {
      rc = esf_yget_double(se, "skin", 1, &c->skin, err);
      if (!rc) rc = positive(se, "skin", c->skin, 1, err);
    }
    if (!rc) rc = esf_yget_bool(se, "reorder", 0, &c->reorder, err);
  }
  const esf_ynode *ru = esf_ymap_get(root, "run");
  if (!rc && !ru && !esf_ymap_get(root, "generate")) /* esfera generate: no run */
    return esf_ynode_fail(root, err, "missing key 'run' (duration or steps)");
  if (!rc && ru) rc = esf_ymap_check_keys(ru, rkeys, err);
  if (rc) return rc;
  const esf_ynode *du = ru ? esf_ymap_get(ru, "duration") : NULL,
                  *st = ru ? esf_ymap_get(ru, "steps") : NULL;
  if (ru && (du != NULL) == (st != NULL))
    return esf_ynode_fail(ru, err, "give exactly one of duration (s) or steps");
  if (du) {
    rc = esf_ynode_double(du, &c->duration, err);
    if (!rc && !(c->duration > 0)) return esf_ynode_fail(du, err, "must be positive");
  } else if (st) {
    rc = esf_ynode_long(st, &c->steps, err);
    if (!rc && c->steps <= 0) return esf_ynode_fail(st, err, "must be positive");
  }
  const esf_ynode *ou = esf_ymap_get(root, "output");
  c->energy_every = -1;
  if (!rc && ou) {
    rc = esf_ymap_check_keys(ou, okeys, err);
    if (!rc) rc = esf_yget_double(ou, "every", 0, &c->out_every, err);
    if (!rc) rc = positive(ou, "every", c->out_every, 0, err);
    if (!rc) rc = esf_yget_double(ou, "energy_every", 0, &c->energy_every, err);
    if (!rc && esf_ymap_get(ou, "energy_every"))
      rc = positive(ou, "energy_every", c->energy_every, 0, err);
    const char *dir = NULL;
    if (!rc) rc = esf_yget_string(ou, "dir", 0, &dir, err);
    if (!rc && dir) snprintf(c->out_dir, sizeof c->out_dir, "%s", dir);
    if (!rc) rc = esf_yget_bool(ou, "contacts", 0, &c->out_contacts, err);
    /* checkpoints (checkpoint.h) */
    if (!rc) rc = esf_yget_double(ou, "checkpoint_every", 0, &c->ckpt_every, err);
    if (!rc) rc = positive(ou, "checkpoint_every", c->ckpt_every, 0, err);
    if (!rc) rc = esf_scene_outputs(ou, c, err); /* walls, stress (scene_outputs.c) */
  }
  return rc;
}

static int read_top(const esf_ynode *root, esf_config *c, esf_error *err) {
  /* one block per feature, so that parallel additions merge */
  /* clang-format off */
  static const char *const keys[] = {
      "name",   "dimension", "disk_thickness", "gravity",    "domain",  "materials",
      "mixing", "particles", "walls",          "integrator", "damping", "contact",
      "search", "run",       "output",         "generate",
      "events", "fluid", /* sand production (scene_loads.c) */
      NULL};
  /* clang-format on */
  int rc = esf_ynode_require_map(root, err);
  if (!rc) rc = esf_ymap_check_keys(root, keys, err);
  const char *name = NULL;
  if (!rc) rc = esf_yget_string(root, "name", 0, &name, err);
  if (!rc && name) snprintf(c->name, sizeof c->name, "%s", name);
  long dim = 3;
  if (!rc) rc = esf_yget_long(root, "dimension", 0, &dim, err);
  if (!rc && dim != 2 && dim != 3)
    return esf_ynode_fail(esf_ymap_get(root, "dimension"), err, "must be 2 or 3, got %ld",
                          dim);
  c->dim = (int)dim;
  if (!rc) rc = esf_yget_double(root, "disk_thickness", 0, &c->disk_thickness, err);
  if (!rc) rc = positive(root, "disk_thickness", c->disk_thickness, 1, err);
  if (!rc) rc = esf_yget_doubles(root, "gravity", 0, c->gravity, 3, err);
  const esf_ynode *dom = esf_ymap_get(root, "domain");
  if (!rc && dom) {
    static const char *const dkeys[] = {"min", "max", "periodic", "shear", NULL};
    rc = esf_ymap_check_keys(dom, dkeys, err);
    if (!rc) rc = esf_yget_doubles(dom, "min", 1, c->domain_min, 3, err);
    if (!rc) rc = esf_yget_doubles(dom, "max", 1, c->domain_max, 3, err);
    for (int k = 0; k < 3 && !rc; k++)
      if (!(c->domain_min[k] < c->domain_max[k]))
        return esf_ynode_fail(dom, err, "min must be below max in every direction");
    if (!rc) rc = esf_scene_periodic(dom, c, err);
    c->has_domain = 1;
  }
  if (!rc && c->dim == 2 && c->gravity[1] != 0)
    return esf_ynode_fail(esf_ymap_get(root, "gravity"), err,
                          "a 2D scene moves in the x-z plane: gravity's y must be 0");
  return rc;
}

/* Every material a particle is made of needs a density (walls' materials do not). */
static int check_densities(const esf_ynode *root, const esf_sim *s, esf_error *err) {
  for (size_t i = 0; i < s->p.n; i++) {
    const esf_material *m = &s->mats.m[s->p.material[i]];
    if (m->density > 0) continue;
    const esf_ynode *mn = esf_ymap_get(esf_ymap_get(root, "materials"), m->name);
    const esf_ynode *dn = esf_ymap_get(mn, "density");
    return esf_ynode_fail(dn ? dn : mn, err,
                          "material '%s' is used by particle id %lld and needs a "
                          "positive density (kg/m^3)%s",
                          m->name, (long long)s->p.id[i], dn ? "" : ": add density");
  }
  return ESF_OK;
}

/* The places of the keys checked after reading (esf_config_where). */
static void record_places(const esf_ynode *root, esf_config *c) {
  /* clang-format off */
  static const char *const keys[] = {
      "", "materials", "particles", "walls", "events", "fluid", "damping", "integrator",
      "integrator.method", "integrator.dt", "integrator.frac", "integrator.history",
      "integrator.roots", "integrator.rtol", "integrator.table", "run", "run.duration", "run.steps",
      "output", "output.every", "output.energy_every", "output.checkpoint_every",
      "output.stress_every",
      "search", "search.skin", "domain", NULL};
  /* clang-format on */
  char buf[sizeof c->where[0].place], path[64];
  for (int k = 0; keys[k]; k++) {
    const esf_ynode *n = root;
    snprintf(path, sizeof path, "%s", keys[k]);
    for (char *tok = path; n && *tok;) {
      char *dot = strchr(tok, '.');
      if (dot) *dot = '\0';
      n = esf_ymap_get(n, tok);
      tok = dot ? dot + 1 : tok + strlen(tok);
    }
    if (n) esf_config_set_where(c, keys[k], esf_ynode_where(n, buf, sizeof buf));
  }
}

int esf_scene_read(esf_ydoc *doc, esf_sim *s, esf_error *err) {
  esf_ynode *root = esf_ydoc_root(doc);
  esf_config *c = &s->cfg;
  record_places(root, c);
  int rc = read_top(root, c, err);
  if (!rc) rc = read_materials(root, s, err);
  if (!rc) rc = read_integrator(root, c, err);
  if (!rc) rc = read_damping(root, c, err);
  if (!rc) rc = read_misc(root, c, err);
  if (!rc) rc = esf_scene_walls(esf_ymap_get(root, "walls"), esf_ydoc_dir(doc), s, err);
  if (!rc) rc = esf_scene_loads(root, s, err); /* events, fluid (scene_loads.c) */
  if (!rc) {
    const esf_ynode *ps = esf_ymap_get(root, "particles");
    if (!ps) return esf_ynode_fail(root, err, "missing key 'particles'");
    uint32_t *entry = NULL;
    rc = esf_scene_particles(ps, esf_ydoc_dir(doc), s, &entry, err);
    if (!rc) rc = check_densities(root, s, err);
    if (!rc)
      rc = esf_scene_check_overlaps(ps, esf_ymap_get(root, "walls"), s, entry, err);
    free(entry);
  }
  if (rc) return rc;
  if (c->energy_every < 0) { /* not given: about 1000 rows over the run */
    double span = c->duration > 0 ? c->duration : 0.0;
    c->energy_every = span > 0 ? span / 1000.0 : 1e-300; /* steps: every step */
  }
  if (!c->out_dir[0]) snprintf(c->out_dir, sizeof c->out_dir, "out/%s", c->name);
  return ESF_OK;
}

int esf_scene_load(const char *path, const char *const *overrides, int noverrides,
                   esf_sim *s, esf_error *err) {
  esf_ydoc *doc = NULL;
  int rc = esf_ydoc_load(path, &doc, err);
  for (int k = 0; k < noverrides && !rc; k++)
    rc = esf_ydoc_override(doc, overrides[k], err);
  esf_config_default(&s->cfg);
  snprintf(s->cfg.source, sizeof s->cfg.source, "%s", path);
  if (!rc) rc = esf_scene_read(doc, s, err);
  esf_ydoc_free(&doc);
  return rc;
}
