/* test_butcher.c — Butcher tables from the scene (integrator.table, method erk).
 * 1. The order conditions (integrators/butcher.h): 1, 1, 2, 4, 9, 20, 48, 115 rooted
 *    trees of orders 1..8, and every explicit table of SUNDIALS 6.4 that erk offers by
 *    name has, by the tree conditions, exactly the orders ARKODE states for b and for
 *    its embedding (3 to 8 for b).
 * 2. A table typed into the scene with the coefficients of a built-in one
 *    (Bogacki-Shampine 3(2), FSAL; Heun-Euler 2(1), whose c_s = 1 takes esfera's
 *    zero-weight stage) gives the same bits (memcmp of positions, velocities, spins,
 *    time, step count) as the built-in method through a head-on collision, at fixed
 *    steps and with adaptive steps (rtol 1e-6); the same table with c_2 = a_21 moved
 *    1e-12 above 3/4 gives other bits (a control of the comparison; one ulp there is
 *    lost in the rounding of y + h sum a_ij k_j). */
#include "simtest.h" /* stdio.h first: arkode_butcher.h needs FILE */

#include <arkode/arkode_butcher_erk.h>

#include "integrators/butcher.h"

static void conditions(void) {
  const int want[] = {1, 1, 2, 4, 9, 20, 48, 115};
  for (int q = 1; q <= 8; q++)
    CHECK(esf_butcher_conditions(q) == want[q - 1], "order %d: %d conditions, want %d", q,
          esf_butcher_conditions(q), want[q - 1]);
  const ARKODE_ERKTableID ids[] = {
      ARKODE_HEUN_EULER_2_1_2,      ARKODE_BOGACKI_SHAMPINE_4_2_3,
      ARKODE_ARK324L2SA_ERK_4_2_3,  ARKODE_ZONNEVELD_5_3_4,
      ARKODE_ARK436L2SA_ERK_6_3_4,  ARKODE_SAYFY_ABURUB_6_3_4,
      ARKODE_CASH_KARP_6_4_5,       ARKODE_FEHLBERG_6_4_5,
      ARKODE_DORMAND_PRINCE_7_4_5,  ARKODE_ARK548L2SA_ERK_8_4_5,
      ARKODE_VERNER_8_5_6,          ARKODE_FEHLBERG_13_7_8,
      ARKODE_KNOTH_WOLKE_3_3,       ARKODE_ARK437L2SA_ERK_7_3_4,
      ARKODE_ARK548L2SAb_ERK_8_4_5,
  };
  for (size_t k = 0; k < sizeof ids / sizeof ids[0]; k++) {
    ARKodeButcherTable B = ARKodeButcherTable_LoadERK(ids[k]);
    CHECK(B != NULL, "table %d loads", (int)ids[k]);
    if (!B) continue;
    esf_butcher t;
    memset(&t, 0, sizeof t);
    t.s = B->stages;
    for (int i = 0; i < t.s; i++) {
      t.c[i] = B->c[i];
      t.b[i] = B->b[i];
      t.d[i] = B->d ? B->d[i] : 0;
      for (int j = 0; j < i; j++) t.A[i][j] = B->A[i][j];
    }
    esf_butcher_miss mb, md;
    int qb = esf_butcher_order(&t, t.b, "b", 8, &mb);
    int qd = B->d ? esf_butcher_order(&t, t.d, "d", 8, &md) : 0;
    printf("table %2d: %2d stages, ARKODE's orders %d(%d), by the trees %d(%d); next "
           "condition failed: %s (%.3g off)\n",
           (int)ids[k], t.s, B->q, B->p, qb, qd, mb.order ? mb.cond : "none",
           mb.value - mb.want);
    CHECK(qb == B->q, "table %d: b has order %d by the trees, ARKODE says %d",
          (int)ids[k], qb, B->q);
    CHECK(!B->d || qd == B->p, "table %d: d has order %d by the trees, ARKODE says %d",
          (int)ids[k], qd, B->p);
    ARKodeButcherTable_Free(B);
  }
}

static const char *const bs_table =
    "integrator.table={c: [0, 1/2, 3/4, 1], A: [[], [1/2], [0, 3/4], [2/9, 1/3, 4/9]], "
    "b: [2/9, 1/3, 4/9, 0], b_embedded: [7/24, 1/4, 1/3, 1/8], order: 3, "
    "embedded_order: 2}";
static const char *const bs_off = /* c_2 = a_21 = 3/4 + 1e-12 */
    "integrator.table={c: [0, 1/2, 0.750000000001, 1], A: [[], [1/2], [0, "
    "0.750000000001], [2/9, 1/3, 4/9]], b: [2/9, 1/3, 4/9, 0], order: 3}";
static const char *const he_table =
    "integrator.table={c: [0, 1], A: [[0, 0], [1, 0]], b: [1/2, 1/2], "
    "b_embedded: [1, 0], order: 2, embedded_order: 1}";

/* The pair collision up to t_end with the given overrides; the run's end state. */
static int collide(const char *const *sets, int n, double t_end, simtest *T) {
  const char *all[6] = {"integrator.frac=0.05"};
  for (int k = 0; k < n; k++) all[k + 1] = sets[k];
  if (simtest_open(T, simtest_pair_scene, all, n + 1)) return -1;
  while (T->s.t < t_end * (1 - 1e-12))
    if (T->it->step(&T->s, T->ist, t_end, &T->err)) return -1;
  return 0;
}

/* Same bits (expect 1), or other bits (expect 0: the control with two coefficients
 * 1e-12 off, which shows that the comparison sees a difference that small). */
static void same_bits(const char *name, const char *table, const char *tol, int expect) {
  char m[96];
  snprintf(m, sizeof m, "integrator.method=erk:ARKODE_%s", name);
  const char *built[] = {m, tol, "integrator.atol=1e-12"};
  const char *typed[] = {"integrator.method=erk", table, tol, "integrator.atol=1e-12"};
  simtest A, B;
  int ra = collide(built, 3, 4e-4, &A), rb = collide(typed, 4, 4e-4, &B);
  CHECK(ra == 0 && rb == 0, "%s %s: both run (%s / %s)", name, tol, A.err.msg, B.err.msg);
  if (!ra && !rb) {
    size_t n = A.s.p.n;
    int same = B.s.p.n == n && A.s.t == B.s.t && A.s.step == B.s.step &&
               memcmp(A.s.p.x, B.s.p.x, 3 * n * sizeof(double)) == 0 &&
               memcmp(A.s.p.v, B.s.p.v, 3 * n * sizeof(double)) == 0 &&
               memcmp(A.s.p.w, B.s.p.w, 3 * n * sizeof(double)) == 0;
    double e = (A.s.p.v[3] - A.s.p.v[0]) / 2.0;
    printf("%-22s %s: %ld steps to t = %.6g s, restitution %.9f: typed table%s %s\n",
           name, tol, A.s.step, A.s.t, e, expect ? "" : " (3/4 + 1e-12)",
           same ? "bit-identical" : "differs");
    CHECK(same == expect, "%s %s: the typed table gives %s bits (x %.17g / %.17g)", name,
          tol, same ? "the same" : "other", A.s.p.x[0], B.s.p.x[0]);
    CHECK(A.s.step > 20 && e > 0.3 && e < 0.7,
          "%s: the collision happened (%ld steps, "
          "e %.3f)",
          name, A.s.step, e);
  }
  simtest_close(&A);
  simtest_close(&B);
}

int main(void) {
  conditions();
  same_bits("BOGACKI_SHAMPINE_4_2_3", bs_table, "integrator.rtol=0", 1);
  same_bits("BOGACKI_SHAMPINE_4_2_3", bs_table, "integrator.rtol=1e-6", 1);
  same_bits("HEUN_EULER_2_1_2", he_table, "integrator.rtol=0", 1);
  same_bits("HEUN_EULER_2_1_2", he_table, "integrator.rtol=1e-6", 1);
  same_bits("BOGACKI_SHAMPINE_4_2_3", bs_off, "integrator.rtol=0", 0);
  return check_finish("test_butcher");
}
