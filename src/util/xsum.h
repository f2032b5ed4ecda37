/* xsum.h — exact, order-independent summation of doubles: an accumulator holds the
 * exact sum of any number of finite doubles as a fixed-point integer (unit 2^-1074,
 * the smallest subnormal) in ESF_XSUM_LIMBS signed 64-bit limbs of 32-bit digits, so
 * the sum of a set of terms is the same bits whatever their order or grouping, and is
 * rounded to a double once (esf_xsum_value, to nearest, ties to even).
 *
 * Every field is an int64_t that adds: two accumulators merge word by word
 * (esf_xsum_merge), which is what MPI_Allreduce with MPI_SUM on ESF_XSUM_WORDS words of
 * MPI_INT64_T does, provided each was normalised first (esf_xsum_normalize) and the
 * ranks are fewer than 2^30. Adds are lazy: a term touches two limbs; carries are
 * propagated every 1023 terms, or when asked (about 2 ns a term). */
#ifndef ESF_XSUM_H
#define ESF_XSUM_H

#include <stddef.h>
#include <stdint.h>
#include <string.h>

/* 2098 bits from 2^-1074 to the top of DBL_MAX, and room above them for the carries of
 * 2^76 terms of the largest magnitude: 67 digits of 32 bits. */
#define ESF_XSUM_LIMBS       67
#define ESF_XSUM_WORDS       (ESF_XSUM_LIMBS + 4) /* int64_t words of an esf_xsum */
#define ESF_XSUM_PENDING_MAX ((int64_t)1 << 30)   /* the bound's limit: |limb| < 2^62 */
#define ESF_XSUM_TERM        ((int64_t)1 << 20)   /* a term's share: < 2^52 to a limb */

typedef struct esf_xsum {
  /* limb k weighs 2^(32k - 1074). Normalised: limbs 0..65 in [0, 2^32), the top limb
   * signed (the sign of the sum), so a value has one representation. */
  int64_t limb[ESF_XSUM_LIMBS];
  int64_t nan, pinf, ninf; /* non-finite terms seen: NaN, +Inf, -Inf */
  int64_t pending; /* bound: every limb below the top has |limb| < 2^32 pending (1 when
                      normalised; sums under merges, ESF_XSUM_TERM a term) */
} esf_xsum;
_Static_assert(sizeof(esf_xsum) == ESF_XSUM_WORDS * sizeof(int64_t),
               "an esf_xsum is ESF_XSUM_WORDS int64_t words (MPI_SUM adds them)");

void esf_xsum_zero(esf_xsum *a);
/* Carries propagated: the canonical form of the exact sum (pending 1). */
void esf_xsum_normalize(esf_xsum *a);
/* Adds the accumulator from into into (exactly; from unchanged). */
void esf_xsum_merge(esf_xsum *into, const esf_xsum *from);
/* The sum rounded to the nearest double (ties to even; +0 for an exact zero; +-Inf
 * past DBL_MAX as IEEE rounding gives); NaN if a NaN was added or both infinities,
 * +-Inf if one of them was. A function of the exact sum only. */
double esf_xsum_value(const esf_xsum *a);
/* Adds x[0], x[stride], ..., x[(n - 1) stride] (stride in doubles). */
void esf_xsum_add_n(esf_xsum *a, const double *x, size_t n, size_t stride);
void esf_xsum_add_nonfinite(esf_xsum *a, uint64_t bits);

/* Room in the bound for n (< ESF_XSUM_PENDING_MAX): normalises first if the bound
 * would pass ESF_XSUM_PENDING_MAX, then adds n to it; n = k ESF_XSUM_TERM (k < 1024)
 * lets k calls of esf_xsum_add_counted follow without checks. */
static inline void esf_xsum_reserve(esf_xsum *a, int64_t n) {
  if (a->pending + n > ESF_XSUM_PENDING_MAX) esf_xsum_normalize(a);
  a->pending += n;
}

/* Adds x, reserved by esf_xsum_reserve: its 53-bit significand m, shifted by its
 * exponent to bit p = e - 1 above 2^-1074 (p = 0 for subnormals), is split into the low
 * 32 bits, for limb p/32, and the rest (< 2^52), for limb p/32 + 1, each added or
 * subtracted. Zeros are skipped. */
static inline void esf_xsum_add_counted(esf_xsum *a, double x) {
  uint64_t u;
  memcpy(&u, &x, sizeof u);
  if (!(u << 1)) return; /* +-0 */
  const unsigned e = (unsigned)(u >> 52) & 0x7ffu;
  if (e == 0x7ffu) {
    esf_xsum_add_nonfinite(a, u);
    return;
  }
  uint64_t m = u & (((uint64_t)1 << 52) - 1);
  unsigned p = 0;
  if (e) {
    m |= (uint64_t)1 << 52;
    p = e - 1;
  }
  const unsigned k = p >> 5, s = p & 31u;
  const int64_t neg = -(int64_t)(u >> 63); /* 0 or -1: (d ^ neg) - neg is -d or d */
  const int64_t d0 = (int64_t)((m << s) & 0xffffffffu);
  const int64_t d1 = (int64_t)(m >> (32 - s));
  a->limb[k] += (d0 ^ neg) - neg;
  a->limb[k + 1] += (d1 ^ neg) - neg;
}

/* Adds x. */
static inline void esf_xsum_add(esf_xsum *a, double x) {
  esf_xsum_reserve(a, ESF_XSUM_TERM);
  esf_xsum_add_counted(a, x);
}

#endif
