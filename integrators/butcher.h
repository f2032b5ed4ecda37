/* butcher.h — the order conditions of an explicit Runge-Kutta table, from the rooted
 * trees (docs/physics.md#butcher-tables-from-the-scene): for every rooted tree t of
 * order |t| <= ESF_BUTCHER_QMAX, the weights w (b, or the embedding's d) satisfy
 *   sum_i w_i Phi_i(t) = 1 / gamma(t),
 * Phi(t) = prod over the root's subtrees u of (A Phi(u)) (the single node: Phi = 1),
 * gamma(t) = |t| prod_u gamma(u). Order 1: sum b = 1; 2: sum b c = 1/2; 3: sum b c^2 =
 * 1/3, sum b A c = 1/6; 4: four more; 5: nine; 6: twenty; 7: 48; 8: 115. */
#ifndef ESF_BUTCHER_H
#define ESF_BUTCHER_H

#include "core/sim.h"

#define ESF_BUTCHER_QMAX 8       /* the highest order whose conditions are checked */
#define ESF_BUTCHER_TOL  1.0e-10 /* relative to sum |w_i Phi_i| + 1/gamma */

/* The first condition a weight vector fails. */
typedef struct esf_butcher_miss {
  int order;          /* the tree's order; 0 when none failed */
  char cond[160];     /* "sum b A c = 1/6" */
  double value, want; /* its two sides */
} esf_butcher_miss;

/* The highest order q <= qmax (<= ESF_BUTCHER_QMAX) whose conditions w (s entries, A
 * of t) satisfies to ESF_BUTCHER_TOL; miss (may be NULL) gets the first condition of
 * order q + 1 that fails (order 0 when q == qmax). name names w in miss->cond. */
int esf_butcher_order(const esf_butcher *t, const double *w, const char *name, int qmax,
                      esf_butcher_miss *miss);

/* The number of order conditions of order q (rooted trees of q nodes), 1 <= q <=
 * ESF_BUTCHER_QMAX; 0 otherwise. */
int esf_butcher_conditions(int q);

#endif
