/* scene_motion.c — a wall's `motion:`
 * (docs/scene.md#walls-a-list-each-entry-is-one-wall): one motion (a mapping) or a
 * sequence of them (a list; their displacements and angles add, wall_motion.c). A motion
 * is exactly one of translate {velocity}, rotate {axis, center, rpm | omega}, oscillate
 * {direction, frequency, amplitude | acceleration, phase}, table {time, displacement |
 * velocity} (docs/physics.md#walls-and-prescribed- motion), each with an optional window
 * `start`, `stop` (s), or servo (alone; scene_loads.c). A table's values are 3-vectors,
 * one a row, or per axis {x, y, z} (lists, absent axes zero); a velocity table (piecewise
 * constant, v_i on [t_i, t_i+1), the last one on) is turned into displacements d_0 = 0,
 * d_i+1 = d_i + v_i (t_i+1 - t_i) here. The rotations of a sequence share one axis
 * and centre and the first of them becomes the group's first term. Errors name file,
 * line and column. Units: SI. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_loads.h"
#include "scene/scene_parts.h"
#include "util/vec3.h"

/* a table's values: n 3-vectors as a list of rows or as per-axis lists {x, y, z} */
static int table_values(const esf_ynode *v, size_t n, double *out, esf_error *err) {
  static const char *const axes[] = {"x", "y", "z", NULL};
  memset(out, 0, 3 * n * sizeof *out);
  if (v->kind == ESF_YN_MAP) {
    int rc = esf_ymap_check_keys(v, axes, err);
    for (int q = 0; q < 3 && !rc; q++) {
      const esf_ynode *l = esf_ymap_get(v, axes[q]);
      if (!l) continue;
      rc = esf_ynode_require_seq(l, err);
      if (!rc && l->n != n)
        return esf_ynode_fail(l, err, "%zu values for %zu times", l->n, n);
      for (size_t i = 0; i < n && !rc; i++)
        rc = esf_ynode_double(l->items[i], &out[3 * i + q], err);
    }
    return rc;
  }
  int rc = esf_ynode_require_seq(v, err);
  if (!rc && v->n != n) return esf_ynode_fail(v, err, "%zu rows for %zu times", v->n, n);
  for (size_t i = 0; i < n && !rc; i++)
    rc = esf_ynode_doubles(v->items[i], out + 3 * i, 3, err);
  return rc;
}

/* table: {time: [...], displacement: V | velocity: V} */
static int read_table(const esf_ynode *t, esf_wall_motion *m, esf_walls *w,
                      esf_error *err) {
  const esf_ynode *tm = esf_ymap_get(t, "time"), *dn = esf_ymap_get(t, "displacement"),
                  *vn = esf_ymap_get(t, "velocity");
  if (!tm) return esf_ynode_fail(t, err, "missing key 'time'");
  if ((dn != NULL) == (vn != NULL))
    return esf_ynode_fail(t, err,
                          "give exactly one of displacement (m) or velocity (m/s)");
  int rc = esf_ynode_require_seq(tm, err);
  if (rc) return rc;
  if (tm->n < 1) return esf_ynode_fail(tm, err, "a table needs at least one row");
  const size_t n = tm->n;
  double *T = malloc(n * sizeof *T), *D = malloc(3 * n * sizeof *D);
  if (!T || !D) {
    free(T);
    free(D);
    return esf_fail(err, ESF_ENOMEM, "out of memory for a motion table");
  }
  rc = esf_walls_own(w, T, err);
  if (rc) {
    free(D);
    return rc;
  }
  rc = esf_walls_own(w, D, err);
  for (size_t i = 0; i < n && !rc; i++) {
    rc = esf_ynode_double(tm->items[i], &T[i], err);
    if (!rc && !(T[i] >= 0))
      return esf_ynode_fail(tm->items[i], err, "must be a time >= 0 s, got %g", T[i]);
    if (!rc && i > 0 && !(T[i] > T[i - 1]))
      return esf_ynode_fail(tm->items[i], err,
                            "table times must increase: %g s after %g s", T[i], T[i - 1]);
  }
  if (!rc) rc = table_values(dn ? dn : vn, n, D, err);
  if (rc) return rc;
  m->kind = ESF_MOTION_TABLE;
  m->nrow = (int)n;
  m->row_t = T;
  m->row_d = D;
  if (vn) { /* velocities v_i on [t_i, t_i+1): displacements, the last one on */
    double v[3];
    v3_copy(m->tail, D + 3 * (n - 1));
    v3_copy(v, D);
    v3_set(D, 0, 0, 0);
    for (size_t i = 1; i < n; i++) {
      double vi[3];
      v3_copy(vi, D + 3 * i);
      for (int q = 0; q < 3; q++)
        D[3 * i + q] = D[3 * (i - 1) + q] + v[q] * (T[i] - T[i - 1]);
      v3_copy(v, vi);
    }
  }
  return ESF_OK;
}

/* the window `start`, `stop` of a prescribed motion's mapping k */
static int read_window(const esf_ynode *k, esf_wall_motion *m, esf_error *err) {
  const esf_ynode *a = esf_ymap_get(k, "start"), *b = esf_ymap_get(k, "stop");
  if (!a && !b) return ESF_OK;
  m->timed = 1;
  m->start = 0;
  m->stop = INFINITY;
  int rc = esf_yget_double(k, "start", 0, &m->start, err);
  if (!rc && !(m->start >= 0))
    return esf_ynode_fail(a, err, "must be a time >= 0 s, got %g", m->start);
  if (!rc) rc = esf_yget_double(k, "stop", 0, &m->stop, err);
  if (!rc && !(m->stop > m->start))
    return esf_ynode_fail(b, err, "stop (%g s) must come after start (%g s)", m->stop,
                          m->start);
  return rc;
}

/* one motion: {translate | rotate | oscillate | table: {... start, stop}} | {servo} */
static int read_one(const esf_ynode *mo, esf_wall_motion *m, esf_walls *w, int alone,
                    esf_error *err) {
  static const char *const kinds[] = {"translate", "rotate", "oscillate",
                                      "table",     "servo", /* scene_loads.c */
                                      NULL};
  static const char *const tkeys[] = {"velocity", "start", "stop", NULL};
  static const char *const rkeys[] = {"axis",  "center", "rpm", "omega",
                                      "start", "stop",   NULL};
  static const char *const okeys[] = {"direction",    "frequency", "amplitude",
                                      "acceleration", "phase",     "start",
                                      "stop",         NULL};
  static const char *const xkeys[] = {"time",  "displacement", "velocity",
                                      "start", "stop",         NULL};
  int rc = esf_ynode_require_map(mo, err);
  if (!rc) rc = esf_ymap_check_keys(mo, kinds, err);
  if (rc) return rc;
  if (mo->n != 1)
    return esf_ynode_fail(
        mo, err, "a motion is exactly one of translate, rotate, oscillate, table, servo");
  if (esf_ymap_get(mo, "servo")) {
    if (!alone)
      return esf_ynode_fail(mo, err, "a servo cannot be part of a sequence of motions");
    return esf_scene_servo(esf_ymap_get(mo, "servo"), m, err);
  }
  memset(m, 0, sizeof *m);
  const esf_ynode *t = esf_ymap_get(mo, "translate"), *r = esf_ymap_get(mo, "rotate"),
                  *o = esf_ymap_get(mo, "oscillate"), *x = esf_ymap_get(mo, "table");
  const esf_ynode *k = t ? t : r ? r : o ? o : x;
  rc = esf_ynode_require_map(k, err);
  if (!rc) rc = esf_ymap_check_keys(k, t ? tkeys : r ? rkeys : o ? okeys : xkeys, err);
  if (!rc) rc = read_window(k, m, err);
  if (rc) return rc;
  if (t) {
    m->kind = ESF_MOTION_TRANSLATE;
    return esf_yget_doubles(t, "velocity", 1, m->vel, 3, err);
  }
  if (x) return read_table(x, m, w, err);
  if (r) {
    m->kind = ESF_MOTION_ROTATE;
    rc = esf_scene_unit_vector(r, "axis", 1, m->axis, err);
    if (!rc) rc = esf_yget_doubles(r, "center", 0, m->pivot, 3, err);
    const esf_ynode *rpm = esf_ymap_get(r, "rpm"), *om = esf_ymap_get(r, "omega");
    if (!rc && (rpm != NULL) == (om != NULL))
      return esf_ynode_fail(r, err,
                            "give the angular speed as exactly one of rpm, omega");
    double v = 0;
    if (!rc) rc = esf_yget_double(r, rpm ? "rpm" : "omega", 1, &v, err);
    m->rate = rpm ? v * 2.0 * ESF_PI / 60.0 : v;
    return rc;
  }
  m->kind = ESF_MOTION_OSCILLATE;
  rc = esf_scene_unit_vector(o, "direction", 1, m->dir, err);
  if (!rc) rc = esf_yget_double(o, "frequency", 1, &m->freq, err);
  if (!rc && !(m->freq > 0))
    return esf_ynode_fail(esf_ymap_get(o, "frequency"), err, "must be positive (Hz)");
  const esf_ynode *am = esf_ymap_get(o, "amplitude"),
                  *ac = esf_ymap_get(o, "acceleration");
  if (!rc && (am != NULL) == (ac != NULL))
    return esf_ynode_fail(o, err,
                          "give exactly one of amplitude (m) or acceleration (peak, in "
                          "units of g = 9.81 m/s^2)");
  double v = 0;
  if (!rc) rc = esf_yget_double(o, am ? "amplitude" : "acceleration", 1, &v, err);
  double wr = 2.0 * ESF_PI * m->freq;
  m->amp = am ? v : v * 9.81 / (wr * wr);
  if (!rc) rc = esf_yget_double(o, "phase", 0, &m->phase, err);
  return rc;
}

int esf_scene_motion(const esf_ynode *mo, esf_walls *w, int group, esf_error *err) {
  esf_wall_group *g = &w->g[group];
  if (mo->kind != ESF_YN_SEQ) return read_one(mo, &g->motion, w, 1, err);
  if (mo->n == 0) return esf_ynode_fail(mo, err, "an empty sequence of motions");
  esf_wall_motion *all = calloc(mo->n, sizeof *all);
  int rc = esf_walls_own(w, all, err);
  for (size_t k = 0; k < mo->n && !rc; k++)
    rc = read_one(mo->items[k], &all[k], w, 0, err);
  if (rc) return rc;
  size_t first = 0; /* the first rotation leads: wall_motion.c places by it */
  while (first < mo->n && all[first].kind != ESF_MOTION_ROTATE) first++;
  if (first == mo->n) first = 0;
  for (size_t k = 0; k < mo->n; k++) {
    const esf_wall_motion *a = &all[first], *b = &all[k];
    if (k == first || b->kind != ESF_MOTION_ROTATE) continue;
    for (int q = 0; q < 3; q++)
      if (a->axis[q] != b->axis[q] || a->pivot[q] != b->pivot[q])
        return esf_ynode_fail(mo->items[k], err,
                              "the rotations of one wall's motions share one axis and "
                              "center (those of item %zu)",
                              first);
  }
  g->motion = all[first];
  all[first] = all[0];
  all[0] = g->motion;
  g->more = all + 1;
  g->nmore = (int)mo->n - 1;
  return ESF_OK;
}
