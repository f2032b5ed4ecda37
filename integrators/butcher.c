/* butcher.c — the order conditions of an explicit Runge-Kutta table checked tree by tree
 * (butcher.h; docs/physics.md#butcher-tables-from-the-scene; Butcher, Numerical Methods
 * for Ordinary Differential Equations, ch. 3: elementary weights and densities).
 *
 * The rooted trees up to ESF_BUTCHER_QMAX nodes are generated in order of size: a tree
 * of n nodes is a root with a multiset of smaller trees whose sizes add to n - 1, taken
 * as non-decreasing lists of tree indices, so each tree comes once (1, 1, 2, 4, 9, 20,
 * 48, 115 trees of orders 1..8). For each tree the stage vector A Phi(t) is kept, so
 * that a parent's Phi is the product of its subtrees' vectors. Entry: the table's A
 * (strictly lower triangular, s stages) and one weight vector; exit: the order. */
#include "integrators/butcher.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define NTREES  200 /* trees of orders 1..8 */
#define MAXKIDS (ESF_BUTCHER_QMAX - 1)

typedef struct tree {
  int order, nk;
  int kid[MAXKIDS]; /* indices of the root's subtrees, non-decreasing */
  double gamma;
} tree;

typedef struct forest {
  tree t[NTREES];
  int n;
} forest;

/* Appends every root over subtree lists kid[0..nk) extended by indices >= from whose
 * sizes add to rest. */
static void grow(forest *f, int order, int rest, int from, int *kid, int nk) {
  if (rest == 0) {
    if (f->n == NTREES) return;
    tree *t = &f->t[f->n++];
    t->order = order;
    t->nk = nk;
    t->gamma = order;
    for (int k = 0; k < nk; k++) {
      t->kid[k] = kid[k];
      t->gamma *= f->t[kid[k]].gamma;
    }
    return;
  }
  for (int u = from; u < f->n && f->t[u].order < order; u++) {
    if (f->t[u].order > rest || nk == MAXKIDS) continue;
    kid[nk] = u;
    grow(f, order, rest - f->t[u].order, u, kid, nk + 1);
  }
}

/* The trees up to qmax nodes, by size. */
static void plant(forest *f, int qmax) {
  int kid[MAXKIDS];
  f->n = 0;
  for (int q = 1; q <= qmax; q++) grow(f, q, q - 1, 0, kid, 0);
}

/* The product Phi(t) written out: leaves as c^k, other subtrees as A(...). */
static void phi_text(const forest *f, int i, char *buf, size_t len) {
  const tree *t = &f->t[i];
  size_t at = 0;
  buf[0] = '\0';
  int leaves = 0;
  for (int k = 0; k < t->nk; k++) leaves += f->t[t->kid[k]].order == 1;
  if (leaves)
    at += (size_t)snprintf(buf + at, len - at, leaves > 1 ? "c^%d" : "c", leaves);
  for (int k = 0; k < t->nk && at < len; k++) {
    const tree *u = &f->t[t->kid[k]];
    if (u->order == 1) continue;
    char sub[96];
    phi_text(f, t->kid[k], sub, sizeof sub);
    int wrap = u->nk > 1 && strchr(sub, ' ') != NULL; /* A (c A c), not A c^2 */
    at += (size_t)snprintf(buf + at, len - at, wrap ? "%sA (%s)" : "%sA %s",
                           at ? " " : "", sub);
  }
}

int esf_butcher_order(const esf_butcher *t, const double *w, const char *name, int qmax,
                      esf_butcher_miss *miss) {
  forest f;
  if (qmax > ESF_BUTCHER_QMAX) qmax = ESF_BUTCHER_QMAX;
  plant(&f, qmax);
  double aphi[NTREES][ESF_BUTCHER_MAX]; /* A Phi(t) per tree */
  int s = t->s;
  if (miss) memset(miss, 0, sizeof *miss);
  for (int i = 0; i < f.n; i++) {
    const tree *tr = &f.t[i];
    double phi[ESF_BUTCHER_MAX];
    for (int r = 0; r < s; r++) {
      phi[r] = 1.0;
      for (int k = 0; k < tr->nk; k++) phi[r] *= aphi[tr->kid[k]][r];
    }
    double sum = 0, mag = 0;
    for (int r = 0; r < s; r++) {
      sum += w[r] * phi[r];
      mag += fabs(w[r] * phi[r]);
    }
    double want = 1.0 / tr->gamma;
    if (!(fabs(sum - want) <= ESF_BUTCHER_TOL * (mag + want))) {
      if (miss) {
        char ph[96];
        phi_text(&f, i, ph, sizeof ph);
        miss->order = tr->order;
        miss->value = sum;
        miss->want = want;
        snprintf(miss->cond, sizeof miss->cond, "sum %s%s%s = 1/%.0f", name,
                 ph[0] ? " " : "", ph, tr->gamma);
      }
      return tr->order - 1;
    }
    for (int r = 0; r < s; r++) {
      aphi[i][r] = 0;
      for (int j = 0; j < r; j++) aphi[i][r] += t->A[r][j] * phi[j];
    }
  }
  return qmax;
}

int esf_butcher_conditions(int q) {
  if (q < 1 || q > ESF_BUTCHER_QMAX) return 0;
  forest f;
  plant(&f, q);
  int n = 0;
  for (int i = 0; i < f.n; i++) n += f.t[i].order == q;
  return n;
}
