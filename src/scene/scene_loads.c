/* scene_loads.c — scene keys for servo walls, events and the fluid force (docs/scene.md):
 *   walls[i].motion: {servo: {stress, direction, max_speed, gain | alpha, area}}
 *   events: [{at, delete: {cylinder: {center, axis, radius}} | {box: {min, max}}
 *             | remove_wall: NAME | add_wall: NAME}]; a wall's events alternate
 *             (remove, add, ...) in time; one whose first event adds it starts absent
 *   fluid: {start, porosity, viscosity, density, permeability,
 *           radial: {center, axis, well_radius, drainage_radius, pressure_drop} |
 *           uniform: {velocity, pressure_gradient}}
 * Every mapping is checked against its keys; errors name file, line and column. */
#include "scene/scene_loads.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "loads/drag.h"
#include "loads/events.h"
#include "util/vec3.h"

static int unit(const esf_ynode *m, const char *key, double u[3], esf_error *err) {
  int rc = esf_yget_doubles(m, key, 1, u, 3, err);
  if (rc) return rc;
  double len = v3_norm(u);
  if (!(len > 0) || !isfinite(len))
    return esf_ynode_fail(esf_ymap_get(m, key), err, "must be a non-zero vector");
  v3_scale(u, 1.0 / len, u);
  return ESF_OK;
}

static int pos(const esf_ynode *m, const char *key, int required, double *v,
               esf_error *err) {
  int rc = esf_yget_double(m, key, required, v, err);
  if (!rc && esf_ymap_get(m, key) && !(*v > 0))
    return esf_ynode_fail(esf_ymap_get(m, key), err, "must be positive, got %g", *v);
  return rc;
}

int esf_scene_servo(const esf_ynode *node, esf_wall_motion *m, esf_error *err) {
  static const char *const keys[] = {"stress", "direction", "max_speed", "gain",
                                     "alpha",  "area",      NULL};
  int rc = esf_ynode_require_map(node, err);
  if (!rc) rc = esf_ymap_check_keys(node, keys, err);
  if (rc) return rc;
  memset(m, 0, sizeof *m);
  m->kind = ESF_MOTION_SERVO;
  m->alpha = 0.5;
  rc = esf_yget_double(node, "stress", 1, &m->stress, err);
  if (!rc && !(m->stress >= 0))
    return esf_ynode_fail(esf_ymap_get(node, "stress"), err,
                          "must be a non-negative compressive stress (Pa), got %g",
                          m->stress);
  if (!rc) rc = unit(node, "direction", m->dir, err);
  if (!rc) rc = pos(node, "max_speed", 1, &m->vmax, err);
  if (!rc && esf_ymap_get(node, "gain") && esf_ymap_get(node, "alpha"))
    return esf_ynode_fail(esf_ymap_get(node, "alpha"), err,
                          "give gain (m/(s Pa)) or alpha (automatic gain), not both");
  if (!rc) rc = pos(node, "gain", 0, &m->gain, err);
  if (!rc) rc = pos(node, "alpha", 0, &m->alpha, err);
  if (!rc && !(m->alpha <= 1))
    return esf_ynode_fail(esf_ymap_get(node, "alpha"), err, "must be in (0, 1], got %g",
                          m->alpha);
  if (!rc) rc = pos(node, "area", 0, &m->area, err);
  return rc;
}

static int read_region(const esf_ynode *del, esf_region *r, esf_error *err) {
  static const char *const kinds[] = {"cylinder", "box", NULL};
  static const char *const ckeys[] = {"center", "axis", "radius", NULL};
  static const char *const bkeys[] = {"min", "max", NULL};
  int rc = esf_ynode_require_map(del, err);
  if (!rc) rc = esf_ymap_check_keys(del, kinds, err);
  if (rc) return rc;
  if (del->n != 1)
    return esf_ynode_fail(del, err, "delete: exactly one region, cylinder or box");
  const esf_ynode *c = esf_ymap_get(del, "cylinder"), *b = esf_ymap_get(del, "box");
  memset(r, 0, sizeof *r);
  if (c) {
    r->kind = ESF_REGION_CYLINDER;
    rc = esf_ynode_require_map(c, err);
    if (!rc) rc = esf_ymap_check_keys(c, ckeys, err);
    if (!rc) rc = esf_yget_doubles(c, "center", 1, r->center, 3, err);
    if (!rc) rc = unit(c, "axis", r->axis, err);
    if (!rc) rc = pos(c, "radius", 1, &r->radius, err);
    return rc;
  }
  r->kind = ESF_REGION_BOX;
  rc = esf_ynode_require_map(b, err);
  if (!rc) rc = esf_ymap_check_keys(b, bkeys, err);
  if (!rc) rc = esf_yget_doubles(b, "min", 1, r->min, 3, err);
  if (!rc) rc = esf_yget_doubles(b, "max", 1, r->max, 3, err);
  for (int k = 0; k < 3 && !rc; k++)
    if (!(r->min[k] <= r->max[k]))
      return esf_ynode_fail(b, err, "min must not exceed max in any direction");
  return rc;
}

/* remove_wall: NAME | add_wall: NAME into ev */
static int read_wall_event(const esf_ynode *e, const esf_sim *s, esf_event *ev,
                           esf_error *err) {
  const esf_ynode *rm = esf_ymap_get(e, "remove_wall"), *ad = esf_ymap_get(e, "add_wall");
  const char *name = NULL;
  ev->kind = rm ? ESF_EVENT_REMOVE_WALL : ESF_EVENT_ADD_WALL;
  int rc = esf_ynode_string(rm ? rm : ad, &name, err);
  if (rc) return rc;
  ev->group = esf_walls_find(&s->walls, name);
  if (ev->group < 0)
    return esf_ynode_fail(rm ? rm : ad, err,
                          "no wall is named '%s' (give the wall a `name: %s`)", name,
                          name);
  if (s->walls.g[ev->group].motion.kind == ESF_MOTION_SERVO)
    return esf_ynode_fail(rm ? rm : ad, err,
                          "wall '%s' is a servo: its feedback needs its contacts, so it "
                          "cannot be removed or added",
                          name);
  return ESF_OK;
}

/* a wall's events alternate in time: removed, added, removed... */
static int check_wall_order(const esf_ynode *seq, const esf_events *E, esf_error *err) {
  for (int k = 0; k < E->n; k++) {
    const esf_event *ev = &E->e[k];
    if (ev->kind == ESF_EVENT_DELETE) continue;
    int prev = -1; /* the same wall's event just before k */
    for (int j = 0; j < E->n; j++)
      if (j != k && E->e[j].kind != ESF_EVENT_DELETE && E->e[j].group == ev->group &&
          esf_event_before(E, j, k) && (prev < 0 || esf_event_before(E, prev, j)))
        prev = j;
    if (prev >= 0 && E->e[prev].kind == ev->kind)
      return esf_ynode_fail(seq->items[k], err,
                            "the wall is %s twice in a row (at %g s and %g s): its "
                            "events must alternate between remove_wall and add_wall",
                            ev->kind == ESF_EVENT_ADD_WALL ? "added" : "removed",
                            E->e[prev].at, ev->at);
  }
  return ESF_OK;
}

static int read_events(const esf_ynode *seq, esf_sim *s, esf_error *err) {
  static const char *const keys[] = {"at", "delete", "remove_wall", "add_wall", NULL};
  int rc = esf_ynode_require_seq(seq, err);
  if (rc || seq->n == 0) return rc;
  esf_events *E = calloc(1, sizeof *E);
  if (E) E->e = calloc(seq->n, sizeof *E->e);
  if (!E || !E->e) {
    free(E);
    return esf_fail(err, ESF_ENOMEM, "out of memory");
  }
  s->events = E;
  for (size_t k = 0; k < seq->n && !rc; k++) {
    const esf_ynode *e = seq->items[k];
    esf_event *ev = &E->e[E->n++];
    rc = esf_ynode_require_map(e, err);
    if (!rc) rc = esf_ymap_check_keys(e, keys, err);
    if (!rc) rc = esf_yget_double(e, "at", 1, &ev->at, err);
    if (!rc && !(ev->at >= 0))
      return esf_ynode_fail(esf_ymap_get(e, "at"), err, "must be a time >= 0 s");
    const esf_ynode *del = esf_ymap_get(e, "delete");
    const int nact = (del != NULL) + (esf_ymap_get(e, "remove_wall") != NULL) +
                     (esf_ymap_get(e, "add_wall") != NULL);
    if (!rc && nact != 1)
      return esf_ynode_fail(e, err,
                            "an event is exactly one of delete, remove_wall, add_wall");
    if (!rc)
      rc = del ? read_region(del, &ev->region, err) : read_wall_event(e, s, ev, err);
  }
  if (!rc) rc = check_wall_order(seq, E, err);
  if (!rc) esf_events_wall_state(s); /* walls added later start absent */
  return rc;
}

static int read_fluid(const esf_ynode *f, esf_sim *s, esf_error *err) {
  static const char *const keys[] = {"start",        "porosity", "viscosity", "density",
                                     "permeability", "radial",   "uniform",   NULL};
  static const char *const rkeys[] = {"center",          "axis",          "well_radius",
                                      "drainage_radius", "pressure_drop", NULL};
  static const char *const ukeys[] = {"velocity", "pressure_gradient", NULL};
  int rc = esf_ynode_require_map(f, err);
  if (!rc) rc = esf_ymap_check_keys(f, keys, err);
  if (rc) return rc;
  esf_drag *d = calloc(1, sizeof *d);
  if (!d) return esf_fail(err, ESF_ENOMEM, "out of memory");
  s->drag = d;
  rc = esf_yget_double(f, "start", 0, &d->start, err);
  const esf_ynode *po = esf_ymap_get(f, "porosity");
  if (!rc && !po) return esf_ynode_fail(f, err, "missing key 'porosity'");
  if (!rc && po->kind == ESF_YN_MAP) { /* {cell: h}: from a grid of cells */
    static const char *const pkeys[] = {"cell", NULL};
    d->grid = 1;
    rc = esf_ymap_check_keys(po, pkeys, err);
    if (!rc) rc = pos(po, "cell", 1, &d->pg.h, err);
  } else if (!rc) {
    rc = esf_ynode_double(po, &d->porosity, err);
    if (!rc && !(d->porosity > 0 && d->porosity < 1))
      return esf_ynode_fail(
          po, err, "must be a void fraction in (0, 1) or {cell: size in m}, got %g",
          d->porosity);
  }
  if (!rc) rc = pos(f, "viscosity", 1, &d->mu, err);
  if (!rc) rc = pos(f, "density", 1, &d->rho, err);
  const esf_ynode *r = esf_ymap_get(f, "radial"), *u = esf_ymap_get(f, "uniform");
  if (!rc && (r != NULL) == (u != NULL))
    return esf_ynode_fail(f, err, "give exactly one fluid field: radial or uniform");
  if (rc) return rc;
  if (r) {
    d->kind = ESF_DRAG_RADIAL;
    rc = pos(f, "permeability", 1, &d->perm, err);
    if (!rc) rc = esf_ynode_require_map(r, err);
    if (!rc) rc = esf_ymap_check_keys(r, rkeys, err);
    if (!rc) rc = esf_yget_doubles(r, "center", 1, d->center, 3, err);
    if (!rc) rc = unit(r, "axis", d->axis, err);
    if (!rc) rc = pos(r, "well_radius", 1, &d->rw, err);
    if (!rc) rc = pos(r, "drainage_radius", 1, &d->re, err);
    if (!rc && !(d->re > d->rw))
      return esf_ynode_fail(esf_ymap_get(r, "drainage_radius"), err,
                            "must exceed well_radius (%g m)", d->rw);
    if (!rc) rc = esf_yget_double(r, "pressure_drop", 1, &d->dp, err);
    return rc;
  }
  d->kind = ESF_DRAG_UNIFORM;
  if (esf_ymap_get(f, "permeability"))
    return esf_ynode_fail(esf_ymap_get(f, "permeability"), err,
                          "permeability belongs to the radial field (Darcy velocity); "
                          "a uniform field gives its velocity");
  rc = esf_ynode_require_map(u, err);
  if (!rc) rc = esf_ymap_check_keys(u, ukeys, err);
  if (!rc) rc = esf_yget_doubles(u, "velocity", 0, d->u, 3, err);
  if (!rc) rc = esf_yget_doubles(u, "pressure_gradient", 0, d->gradp, 3, err);
  return rc;
}

int esf_scene_loads(const esf_ynode *root, esf_sim *s, esf_error *err) {
  const esf_ynode *ev = esf_ymap_get(root, "events"), *fl = esf_ymap_get(root, "fluid");
  int rc = ESF_OK;
  if (ev && ev->kind != ESF_YN_NULL) rc = read_events(ev, s, err);
  if (!rc && fl) rc = read_fluid(fl, s, err);
  return rc;
}
