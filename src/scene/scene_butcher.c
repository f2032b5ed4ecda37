/* scene_butcher.c — integrator.table: an explicit Runge-Kutta method given by its
 * Butcher table (docs/scene.md#integrator, docs/physics.md#butcher-tables-from-the-scene)
 *   table: {c: [...], A: [[...], ...], b: [...], b_embedded: [...], order: q,
 *           embedded_order: p}
 * Numbers are decimals or fractions "p/q" (divided in double, as SUNDIALS writes its own
 * tables). Checked, each failure at the offending node (file:line:column): sizes (s
 * stages from c, 1 <= s <= ESF_BUTCHER_MAX; A has s rows of i, i + 1 or s entries for
 * row i), explicitness (a_ij = 0 for j >= i), row sums c_i = sum_j a_ij to
 * ESF_BUTCHER_TOL relative to |c_i| + sum_j |a_ij|, the order conditions of b up to
 * `order` and of b_embedded up to `embedded_order` (integrators/butcher.h), and that a
 * table without b_embedded is not asked for adaptive steps (rtol > 0).
 * Entry: the integrator mapping, with method and rtol already read; exit: c->table. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "integrators/butcher.h"
#include "scene/scene_parts.h"

/* A number, or a fraction "p/q" of two numbers. */
static int read_coef(const esf_ynode *n, double *out, esf_error *err) {
  const char *sl =
      n && n->kind == ESF_YN_SCALAR && !n->quoted ? strchr(n->text, '/') : NULL;
  if (!sl) return esf_ynode_double(n, out, err);
  char *end = NULL;
  double p = strtod(n->text, &end);
  int ok = end == sl && end != n->text;
  const char *q0 = sl + 1;
  double q = ok ? strtod(q0, &end) : 0;
  ok = ok && end != q0 && *end == '\0' && isfinite(p) && isfinite(q) && q != 0;
  if (!ok || !isfinite(p / q))
    return esf_ynode_fail(n, err, "expected a number or a fraction p/q, got '%s'",
                          n->text);
  *out = p / q;
  return ESF_OK;
}

/* A vector of exactly s coefficients (s < 0: its length sets s). */
static int read_vec(const esf_ynode *tab, const char *key, int *s, double *v,
                    esf_error *err) {
  const esf_ynode *n = esf_ymap_get(tab, key);
  int rc = esf_ynode_require_seq(n, err);
  if (rc) return rc;
  if (*s < 0) {
    if (n->n < 1 || n->n > ESF_BUTCHER_MAX)
      return esf_ynode_fail(n, err, "a table has 1 to %d stages, c has %zu entries",
                            ESF_BUTCHER_MAX, n->n);
    *s = (int)n->n;
  } else if (n->n != (size_t)*s) {
    return esf_ynode_fail(n, err, "has %zu entries, c has %d (one per stage)", n->n, *s);
  }
  for (int i = 0; i < *s && !rc; i++) rc = read_coef(n->items[i], &v[i], err);
  return rc;
}

/* A: s rows; row i lists a_i0 .. a_i(i-1), or those and a zero diagonal, or all s. */
static int read_A(const esf_ynode *tab, esf_butcher *t, esf_error *err) {
  const esf_ynode *a = esf_ymap_get(tab, "A");
  int s = t->s, rc = esf_ynode_require_seq(a, err);
  if (rc) return rc;
  if (a->n != (size_t)s)
    return esf_ynode_fail(a, err, "has %zu rows, c has %d stages", a->n, s);
  for (int i = 0; i < s && !rc; i++) {
    const esf_ynode *row = a->items[i];
    rc = esf_ynode_require_seq(row, err);
    if (rc) return rc;
    if (row->n != (size_t)i && row->n != (size_t)i + 1 && row->n != (size_t)s) {
      char all[32] = "";
      if (i + 1 < s) snprintf(all, sizeof all, " or %d (the full row)", s);
      return esf_ynode_fail(row, err,
                            "row %d has %zu entries: give %d (the entries left of the "
                            "diagonal), %d (with the zero diagonal)%s",
                            i, row->n, i, i + 1, all);
    }
    for (size_t j = 0; j < row->n && !rc; j++) {
      double v = 0;
      rc = read_coef(row->items[j], &v, err);
      if (!rc && (int)j >= i && v != 0)
        return esf_ynode_fail(row->items[j], err,
                              "a_%d%zu = %g: an explicit table has a_ij = 0 for j >= i "
                              "(a stage uses only the stages before it)",
                              i, j, v);
      if ((int)j < i) t->A[i][j] = v;
    }
  }
  return rc;
}

/* The stated order of w against its conditions (butcher.h). */
static int check_order(const esf_ynode *tab, const char *key, const esf_butcher *t,
                       const double *w, const char *name, int *q, esf_error *err) {
  const esf_ynode *on = esf_ymap_get(tab, key);
  long v = 0;
  int rc = esf_ynode_long(on, &v, err);
  if (rc) return rc;
  if (v < 1 || v > ESF_BUTCHER_QMAX)
    return esf_ynode_fail(on, err,
                          "must be 1 to %d (the orders whose conditions are "
                          "checked), got %ld",
                          ESF_BUTCHER_QMAX, v);
  esf_butcher_miss m;
  int have = esf_butcher_order(t, w, name, (int)v, &m);
  if (have < v)
    return esf_ynode_fail(
        on, err,
        "order %ld claimed, but %s has order %d: the order-%d condition "
        "%s fails (%.17g, off by %.3g)",
        v, name, have, m.order, m.cond, m.value, m.value - m.want);
  *q = (int)v;
  return ESF_OK;
}

int esf_scene_butcher(const esf_ynode *in, esf_config *c, esf_error *err) {
  static const char *const keys[] = {
      "c", "A", "b", "b_embedded", "order", "embedded_order", NULL};
  const esf_ynode *tab = esf_ymap_get(in, "table");
  const esf_ynode *mn = esf_ymap_get(in, "method");
  memset(&c->table, 0, sizeof c->table);
  if (!tab) {
    if (strcmp(c->method, "erk") == 0)
      return esf_ynode_fail(mn, err,
                            "method erk takes its Butcher table from integrator.table "
                            "({c, A, b, order}); or name one: erk:ARKODE_<NAME>");
    return ESF_OK;
  }
  if (strcmp(c->method, "erk") != 0)
    return esf_ynode_fail(tab, err, "a Butcher table is for method: erk (method is %s)",
                          c->method);
  int rc = esf_ynode_require_map(tab, err);
  if (!rc) rc = esf_ymap_check_keys(tab, keys, err);
  static const char *const need[] = {"c", "A", "b", "order", NULL};
  for (int k = 0; need[k] && !rc; k++)
    if (!esf_ymap_get(tab, need[k]))
      rc = esf_ynode_fail(tab, err, "missing key '%s'", need[k]);
  esf_butcher *t = &c->table;
  int s = -1;
  if (!rc) rc = read_vec(tab, "c", &s, t->c, err);
  t->s = s;
  if (!rc) rc = read_A(tab, t, err);
  if (!rc) rc = read_vec(tab, "b", &s, t->b, err);
  const esf_ynode *dn = esf_ymap_get(tab, "b_embedded"),
                  *pn = esf_ymap_get(tab, "embedded_order");
  if (!rc && dn) rc = read_vec(tab, "b_embedded", &s, t->d, err);
  if (!rc && (dn != NULL) != (pn != NULL))
    return esf_ynode_fail(dn ? dn : pn, err, "b_embedded and embedded_order go together");
  for (int i = 0; i < s && !rc; i++) {
    double sum = 0, mag = fabs(t->c[i]);
    for (int j = 0; j < i; j++) {
      sum += t->A[i][j];
      mag += fabs(t->A[i][j]);
    }
    if (fabs(t->c[i] - sum) > ESF_BUTCHER_TOL * mag)
      return esf_ynode_fail(esf_ymap_get(tab, "c")->items[i], err,
                            "c_%d = %.17g, but row %d of A sums to %.17g: c_i must be "
                            "sum_j a_ij (to %g relative)",
                            i, t->c[i], i, sum, ESF_BUTCHER_TOL);
  }
  if (!rc) rc = check_order(tab, "order", t, t->b, "b", &t->q, err);
  if (!rc && dn) {
    int same = 1;
    for (int i = 0; i < s; i++) same = same && t->d[i] == t->b[i];
    if (same) return esf_ynode_fail(dn, err, "equals b: it would estimate no error");
    rc = check_order(tab, "embedded_order", t, t->d, "b_embedded", &t->p, err);
    t->has_d = 1;
  }
  if (!rc && !dn && c->rtol > 0) {
    const esf_ynode *r = esf_ymap_get(in, "rtol");
    return esf_ynode_fail(r ? r : tab, err,
                          "adaptive steps (rtol > 0) need an error estimate: the table "
                          "has no b_embedded; set rtol: 0 (fixed step) or add "
                          "b_embedded and embedded_order");
  }
  return rc;
}
