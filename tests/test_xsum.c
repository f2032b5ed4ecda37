/* test_xsum.c — the exact accumulator (util/xsum.h).
 * 1. Sums whose exact value is known in closed form: 1e308 + 1 - 1e308 = 1; ten 0.1s
 *    round to 1 (a plain sum gives 1 - 2^-53); k smallest subnormals are k 2^-1074;
 *    ties to even at 1 + 2^-53 and 1 + 3 2^-53, broken by a 2^-1074; DBL_MAX + 2^970
 *    (a tie, odd) is Inf, DBL_MAX + 2^969 is DBL_MAX, DBL_MAX + DBL_MAX - DBL_MAX is
 *    DBL_MAX; 2^j for j = -1074..1000 is 2^1001 - 2^-1074, rounded to 2^1001; cancelling
 *    pairs of random terms over the whole range leave the one term added besides.
 * 2. Random sets over the whole range (exponents -1074..1000, mixed signs, subnormals,
 *    exact and near cancellations): several random permutations, each cut into random
 *    parts merged along a random tree, and a strided add, give memcmp-identical values
 *    and normalised limbs; the value equals an independent correctly rounded reference
 *    (Shewchuk's exact expansion of two-sums with the round-half-even correction, the
 *    algorithm of Python's math.fsum); well-conditioned positive sets agree with a long
 *    double sum to 1 ulp.
 * 3. Large counts: 2^30 + 5 adds of -DBL_MAX (past a lazy normalisation), and 2^40
 *    copies of DBL_MAX by merges, cancel exactly against the other side.
 * 4. Non-finite terms: NaN, +-Inf, +Inf with -Inf, through merges, as a plain sum.
 * 5. The ledger's and adaptive damping's block sums split as processes would: the
 *    blocks permuted and cut into parts, each part's accumulators merged, then booked
 *    (esf_ledger_step_sums), give the ledger esf_ledger_step gives on the whole (memcmp),
 *    and the damping sums the same limbs. */
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/sim.h"
#include "util/rng.h"
#include "util/xsum.h"

static double sum_of(const double *x, size_t n) {
  esf_xsum a;
  esf_xsum_zero(&a);
  esf_xsum_add_n(&a, x, n, 1);
  return esf_xsum_value(&a);
}

static int same_bits(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

static void closed_forms(void) {
  const double a[] = {1e308, 1.0, -1e308};
  CHECK(sum_of(a, 3) == 1.0, "1e308 + 1 - 1e308 = %.17g", sum_of(a, 3));
  double t[10];
  for (int k = 0; k < 10; k++) t[k] = 0.1;
  CHECK(sum_of(t, 10) == 1.0, "ten 0.1: %.17g", sum_of(t, 10));
  const double d = ldexp(1.0, -1074);
  for (int k = 1; k <= 5000; k += 499) {
    esf_xsum s;
    esf_xsum_zero(&s);
    for (int i = 0; i < k; i++) {
      esf_xsum_add(&s, d);
      esf_xsum_add(&s, 3 * d);
      esf_xsum_add(&s, -3 * d);
    }
    CHECK(esf_xsum_value(&s) == k * d, "%d 2^-1074 = %g", k, esf_xsum_value(&s));
  }
  const double u = ldexp(1.0, -53);
  const double ties[][4] = {{1.0, u, 0, 1.0},
                            {1.0, u, d, 1.0 + 2 * u},
                            {1.0, 2 * u, u, 1.0 + 4 * u},
                            {-1.0, -u, -d, -1.0 - 2 * u},
                            {DBL_MAX, ldexp(1.0, 970), 0, INFINITY},
                            {DBL_MAX, ldexp(1.0, 969), 0, DBL_MAX},
                            {DBL_MAX, DBL_MAX, -DBL_MAX, DBL_MAX},
                            {0x1p-1022, -d, d, 0x1p-1022},
                            {0x1p-1022, -d, 0, 0x1p-1022 - d},
                            {-0.0, 0.0, -0.0, 0.0}};
  for (size_t k = 0; k < sizeof ties / sizeof ties[0]; k++) {
    const double v = sum_of(ties[k], 3);
    CHECK(same_bits(v, ties[k][3]), "case %zu: %a, want %a", k, v, ties[k][3]);
  }
  esf_xsum s;
  esf_xsum_zero(&s);
  for (int j = -1074; j <= 1000; j++) esf_xsum_add(&s, ldexp(1.0, j));
  CHECK(esf_xsum_value(&s) == ldexp(1.0, 1001), "sum of 2^j: %a", esf_xsum_value(&s));
  esf_rng r;
  esf_rng_seed(&r, 5);
  esf_xsum_zero(&s);
  esf_xsum_add(&s, 0x1.23456789abcdep-3);
  for (int i = 0; i < 4000; i++) {
    const double x =
        ldexp(1.0 + esf_rng_uniform(&r), (int)(esf_rng_next(&r) % 2074) - 1074);
    esf_xsum_add(&s, x);
    esf_xsum_add(&s, 3.0 * x); /* 3x rounded: cancelled by -(3x) below */
    esf_xsum_add(&s, -(3.0 * x));
    esf_xsum_add(&s, -x);
  }
  CHECK(esf_xsum_value(&s) == 0x1.23456789abcdep-3, "cancelling pairs: %a",
        esf_xsum_value(&s));
}

/* Reference: the exact sum as a nonoverlapping expansion (Shewchuk's partials, kept by
 * two-sums), rounded half to even from its top (no term here is near overflow). */
static double ref_sum(const double *x, size_t n) {
  double *p = malloc((n + 2) * sizeof *p);
  size_t np = 0;
  for (size_t i = 0; i < n; i++) {
    double v = x[i];
    size_t k = 0;
    for (size_t j = 0; j < np; j++) {
      double y = p[j];
      if (fabs(v) < fabs(y)) {
        const double t = v;
        v = y;
        y = t;
      }
      const double hi = v + y, lo = y - (hi - v);
      if (lo != 0.0) p[k++] = lo;
      v = hi;
    }
    p[k++] = v;
    np = k;
  }
  double hi = 0.0, lo = 0.0;
  size_t k = np;
  if (k > 0) {
    hi = p[--k];
    while (k > 0) {
      const double v = hi, y = p[--k];
      hi = v + y;
      lo = y - (hi - v);
      if (lo != 0.0) break;
    }
    if (k > 0 && ((lo < 0 && p[k - 1] < 0) || (lo > 0 && p[k - 1] > 0))) {
      const double y = 2.0 * lo, v = hi + y;
      if (y == v - hi) hi = v;
    }
  }
  free(p);
  return hi;
}

/* A term over the whole range: sign, exponent -1074..1000, 53 random bits; a tenth are
 * raw subnormals. */
static double term(esf_rng *r) {
  const uint64_t b = esf_rng_next(r);
  double x;
  if (b % 10 == 0) {
    const uint64_t u = esf_rng_next(r) >> 12; /* exponent field 0 */
    memcpy(&x, &u, sizeof x);
  } else {
    const int e = (int)(esf_rng_next(r) % 2075) - 1074;
    x = ldexp((double)((esf_rng_next(r) >> 11) | ((uint64_t)1 << 52)), e - 52);
  }
  return (b >> 8) & 1 ? -x : x;
}

static void shuffle(esf_rng *r, double *x, size_t n) {
  for (size_t i = n; i > 1; i--) {
    const size_t j = esf_rng_next(r) % i;
    const double t = x[i - 1];
    x[i - 1] = x[j];
    x[j] = t;
  }
}

/* x cut into random parts, each summed apart, the parts merged along a random tree;
 * the result normalised into out. */
static void grouped(esf_rng *r, const double *x, size_t n, esf_xsum *out) {
  enum { MAXP = 16 };
  esf_xsum part[MAXP];
  const size_t np = 1 + esf_rng_next(r) % MAXP;
  size_t cut[MAXP + 1];
  cut[0] = 0;
  cut[np] = n;
  for (size_t k = 1; k < np; k++) cut[k] = esf_rng_next(r) % (n + 1);
  for (size_t k = 1; k < np; k++) /* sorted cut points */
    for (size_t j = k; j > 1 && cut[j] < cut[j - 1]; j--) {
      const size_t t = cut[j];
      cut[j] = cut[j - 1];
      cut[j - 1] = t;
    }
  for (size_t k = 0; k < np; k++) {
    esf_xsum_zero(&part[k]);
    esf_xsum_add_n(&part[k], x + cut[k], cut[k + 1] - cut[k], 1);
  }
  for (size_t m = np; m > 1; m--) { /* merge a random part into another, drop it */
    const size_t i = esf_rng_next(r) % m, j = (i + 1 + esf_rng_next(r) % (m - 1)) % m;
    esf_xsum_merge(&part[j], &part[i]);
    part[i] = part[m - 1];
  }
  *out = part[0];
  esf_xsum_normalize(out);
}

static void random_sets(void) {
  esf_rng r;
  esf_rng_seed(&r, 17);
  int bad_order = 0, bad_ref = 0, sets = 0;
  for (int set = 0; set < 60; set++, sets++) {
    const size_t n = 1 + esf_rng_next(&r) % 3000;
    double *x = malloc(2 * n * sizeof *x), *y = malloc(4 * n * sizeof *y);
    size_t m = 0;
    for (size_t i = 0; i < n; i++) {
      const double t = term(&r);
      x[m++] = t;
      const uint64_t c = esf_rng_next(&r) % 4; /* exact or near cancellation */
      if (set % 3 == 0 && c == 0) x[m++] = -t;
      if (set % 3 == 0 && c == 1) x[m++] = -nextafter(t, 0.0);
    }
    esf_xsum first;
    grouped(&r, x, m, &first);
    const double v0 = esf_xsum_value(&first), ref = ref_sum(x, m);
    if (!same_bits(v0, ref)) {
      if (bad_ref++ < 5)
        CHECK(0, "set %d (%zu terms): %a, reference %a", set, m, v0, ref);
    }
    for (int perm = 0; perm < 4; perm++) {
      shuffle(&r, x, m);
      esf_xsum g, s;
      grouped(&r, x, m, &g);
      for (size_t i = 0; i < m; i++) y[2 * i] = x[i], y[2 * i + 1] = 0.0;
      esf_xsum_zero(&s);
      esf_xsum_add_n(&s, y, m, 2);
      const double vg = esf_xsum_value(&g), vs = esf_xsum_value(&s);
      esf_xsum_normalize(&s);
      if (!same_bits(vg, v0) || !same_bits(vs, v0) ||
          memcmp(g.limb, first.limb, sizeof g.limb) ||
          memcmp(s.limb, first.limb, sizeof s.limb))
        if (bad_order++ < 5)
          CHECK(0, "set %d, permutation %d: %a, %a, first %a", set, perm, vg, vs, v0);
    }
    free(x);
    free(y);
  }
  CHECK(bad_order == 0, "%d of %d sets depend on the order", bad_order, sets);
  CHECK(bad_ref == 0, "%d of %d sets differ from the reference", bad_ref, sets);
  int bad_ld = 0;
  for (int set = 0; set < 20; set++) { /* well conditioned: positive, exponents -20..20 */
    double x[1000];
    long double ld = 0;
    for (int i = 0; i < 1000; i++) {
      x[i] = ldexp(1.0 + esf_rng_uniform(&r), (int)(esf_rng_next(&r) % 41) - 20);
      ld += x[i];
    }
    const double v = sum_of(x, 1000), l = (double)ld;
    bad_ld += fabs(v - l) > nextafter(l, INFINITY) - l;
  }
  CHECK(bad_ld == 0, "%d of 20 well-conditioned sets off the long double sum by > 1 ulp",
        bad_ld);
  printf("random sets: %d over the whole range, 4 orders and groupings each, "
         "%d off the reference, %d order-dependent\n",
         sets, bad_ref, bad_order);
}

static void large_counts(void) {
  const long n = (1L << 30) + 5;
  esf_xsum a, b;
  esf_xsum_zero(&a);
  for (long i = 0; i < n; i++) esf_xsum_add(&a, -DBL_MAX);
  CHECK(esf_xsum_value(&a) == -INFINITY, "%ld terms -DBL_MAX: %g", n, esf_xsum_value(&a));
  esf_xsum_zero(&b); /* + (n - 1) DBL_MAX: 2^30 by doubling merges, then 4 adds */
  esf_xsum_add(&b, DBL_MAX);
  for (int k = 0; k < 30; k++) {
    const esf_xsum c = b;
    esf_xsum_merge(&b, &c);
  }
  for (int k = 0; k < 4; k++) esf_xsum_add(&b, DBL_MAX);
  esf_xsum_merge(&a, &b);
  CHECK(esf_xsum_value(&a) == -DBL_MAX,
        "2^30 + 5 adds of -DBL_MAX, 2^30 + 4 of DBL_MAX: %a", esf_xsum_value(&a));
  esf_xsum_zero(&a); /* 2^40 DBL_MAX - (2^40 - 1) DBL_MAX + 2^-1074 */
  esf_xsum_zero(&b);
  esf_xsum_add(&a, DBL_MAX);
  esf_xsum_add(&b, -DBL_MAX);
  for (int k = 0; k < 40; k++) {
    esf_xsum c = a;
    esf_xsum_merge(&a, &c);
    c = b;
    esf_xsum_merge(&b, &c);
  }
  esf_xsum_add(&b, DBL_MAX);
  esf_xsum_add(&b, 0x1p-1074);
  esf_xsum_merge(&a, &b);
  CHECK(esf_xsum_value(&a) == DBL_MAX, "2^40 DBL_MAX - (2^40 - 1) DBL_MAX: %a",
        esf_xsum_value(&a));
  esf_xsum_add(&a, -DBL_MAX);
  CHECK(esf_xsum_value(&a) == 0x1p-1074, "... - DBL_MAX: %a", esf_xsum_value(&a));
}

static void non_finite(void) {
  const double cases[][3] = {{1.0, NAN, 2.0},         {INFINITY, 1.0, -5.0},
                             {-INFINITY, DBL_MAX, 0}, {INFINITY, -INFINITY, 0},
                             {INFINITY, INFINITY, 1}, {NAN, INFINITY, 0}};
  for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
    const double *c = cases[k];
    const double plain = c[0] + c[1] + c[2];
    esf_xsum a, b;
    esf_xsum_zero(&a);
    esf_xsum_zero(&b);
    esf_xsum_add(&a, c[0]);
    esf_xsum_add_n(&b, c + 1, 2, 1);
    esf_xsum_merge(&b, &a);
    const double v = esf_xsum_value(&b);
    CHECK(isnan(plain) ? isnan(v) : v == plain, "case %zu: %g, plain sum %g", k, v,
          plain);
  }
}

static void book(esf_ledger *l, esf_xsum acc[ESF_LB_N]) {
  double t[ESF_LB_N];
  for (int c = 0; c < ESF_LB_N; c++) t[c] = esf_xsum_value(&acc[c]);
  esf_ledger_step_sums(l, t);
}

static void ledger_split(void) {
  enum { NB = 300, NP = 7 };
  static double blk[NB * ESF_LB_N], perm[NB * ESF_LB_N];
  esf_rng r;
  esf_rng_seed(&r, 23);
  for (int i = 0; i < NB * ESF_LB_N; i++) /* energies of blocks: wide range, signs */
    blk[i] = (esf_rng_uniform(&r) - 0.3) * ldexp(1.0, (int)(esf_rng_next(&r) % 60) - 40);
  esf_ledger whole, split;
  memset(&whole, 0, sizeof whole);
  memset(&split, 0, sizeof split);
  esf_xsum dw[2], ds[2], part[NP][ESF_LB_N], dpart[2];
  for (int step = 0; step < 3; step++) {
    esf_ledger_step(&whole, blk, NB);
    memcpy(perm, blk, sizeof perm); /* the blocks permuted, as another numbering */
    for (int i = NB; i > 1; i--) {
      const int j = (int)(esf_rng_next(&r) % (uint64_t)i);
      double t[ESF_LB_N];
      memcpy(t, perm + ESF_LB_N * (i - 1), sizeof t);
      memcpy(perm + ESF_LB_N * (i - 1), perm + ESF_LB_N * j, sizeof t);
      memcpy(perm + ESF_LB_N * j, t, sizeof t);
    }
    esf_xsum_zero(&ds[0]);
    esf_xsum_zero(&ds[1]);
    for (int k = 0; k < NP; k++) { /* part k: blocks [k NB / NP, (k + 1) NB / NP) */
      const int b0 = k * NB / NP, b1 = (k + 1) * NB / NP;
      for (int c = 0; c < ESF_LB_N; c++) esf_xsum_zero(&part[k][c]);
      esf_ledger_block_sums(perm + ESF_LB_N * b0, (size_t)(b1 - b0), part[k]);
      esf_xsum_zero(&dpart[0]);
      esf_xsum_zero(&dpart[1]);
      esf_sim_damping_sums(perm + ESF_LB_N * b0, (size_t)(b1 - b0), dpart);
      esf_xsum_merge(&ds[0], &dpart[0]);
      esf_xsum_merge(&ds[1], &dpart[1]);
    }
    for (int k = NP - 1; k > 0; k--) /* merged from the last part down */
      for (int c = 0; c < ESF_LB_N; c++) esf_xsum_merge(&part[0][c], &part[k][c]);
    book(&split, part[0]);
  }
  CHECK(memcmp(&whole, &split, sizeof whole) == 0,
        "ledger from permuted, split blocks differs: kinetic %a vs %a", whole.kin_t,
        split.kin_t);
  esf_xsum_zero(&dw[0]);
  esf_xsum_zero(&dw[1]);
  esf_sim_damping_sums(blk, NB, dw);
  for (int k = 0; k < 2; k++) {
    esf_xsum_normalize(&dw[k]);
    esf_xsum_normalize(&ds[k]);
    CHECK(memcmp(dw[k].limb, ds[k].limb, sizeof dw[k].limb) == 0,
          "damping sum %d depends on the split", k);
  }
}

int main(void) {
  closed_forms();
  ledger_split();
  random_sets();
  large_counts();
  non_finite();
  return check_finish("xsum");
}
