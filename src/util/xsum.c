/* xsum.c — the exact accumulator of xsum.h: a sum of doubles held as the integer
 * V = sum of terms / 2^-1074 in 32-bit digits of int64_t limbs (a long accumulator in
 * the manner of Kulisch's, with lazy carries).
 * Adding: a term's significand, shifted by its exponent's low five bits, goes to two
 * limbs (the low 32 bits, and the rest: < 2^52).
 * Normalisation: carries move up limb by limb (c = floor(l / 2^32)), leaving digits in
 * [0, 2^32) and the sign in the top limb; the result is the unique base-2^32 form of V.
 * Rounding (esf_xsum_value): the nonzero limbs carried (the highest as the signed
 * top), negated and carried again if V < 0; of |V|, the top 64 bits w
 * (leading bit set) and a sticky bit for everything below; q = w >> 11 rounded to
 * nearest, ties to even, gives q 2^(L - 53 - 1074) for L the bit length of |V| (ldexp
 * is then exact, or overflows to Inf as IEEE rounding does). Results below 2^-1021
 * have L <= 53 and are exact, so no subnormal is rounded twice.
 * Entry: an accumulator set by esf_xsum_zero. Units: those of the terms. */
#include "util/xsum.h"

#include <math.h>

/* Carries limbs lo..top-1 each into the next (floor division by 2^32, exact: int64_t is
 * two's complement, and l - (l & mask) is a multiple of 2^32); limb top keeps the
 * sign. */
static void carry(int64_t *l, int lo, int top) {
  for (int k = lo; k < top; k++) {
    const int64_t d = l[k] & (int64_t)0xffffffff;
    l[k + 1] += (l[k] - d) / ((int64_t)1 << 32);
    l[k] = d;
  }
}

void esf_xsum_zero(esf_xsum *a) {
  memset(a, 0, sizeof *a);
  a->pending = 1;
}

void esf_xsum_normalize(esf_xsum *a) {
  carry(a->limb, 0, ESF_XSUM_LIMBS - 1);
  a->pending = 1;
}

void esf_xsum_merge(esf_xsum *into, const esf_xsum *from) {
  esf_xsum tmp;
  if (into->pending + from->pending > ESF_XSUM_PENDING_MAX) esf_xsum_normalize(into);
  if (into->pending + from->pending > ESF_XSUM_PENDING_MAX) {
    tmp = *from;
    esf_xsum_normalize(&tmp);
    from = &tmp;
  }
  for (int k = 0; k < ESF_XSUM_LIMBS; k++) into->limb[k] += from->limb[k];
  into->nan += from->nan;
  into->pinf += from->pinf;
  into->ninf += from->ninf;
  into->pending += from->pending;
}

void esf_xsum_add_nonfinite(esf_xsum *a, uint64_t bits) {
  if (bits & (((uint64_t)1 << 52) - 1))
    a->nan++;
  else if (bits >> 63)
    a->ninf++;
  else
    a->pinf++;
}

void esf_xsum_add_n(esf_xsum *a, const double *x, size_t n, size_t stride) {
  const size_t chunk = (size_t)(ESF_XSUM_PENDING_MAX / ESF_XSUM_TERM) - 1;
  for (size_t i0 = 0; i0 < n; i0 += chunk) {
    const size_t i1 = n - i0 > chunk ? i0 + chunk : n;
    esf_xsum_reserve(a, (int64_t)(i1 - i0) * ESF_XSUM_TERM);
    for (size_t i = i0; i < i1; i++) esf_xsum_add_counted(a, x[i * stride]);
  }
}

double esf_xsum_value(const esf_xsum *a) {
  if (a->nan || (a->pinf && a->ninf)) return NAN;
  if (a->pinf) return INFINITY;
  if (a->ninf) return -INFINITY;
  /* V = sum over limbs lo..hi (the nonzero ones), limb hi the signed top */
  int lo = 0, hi = ESF_XSUM_LIMBS - 1;
  while (hi >= 0 && !a->limb[hi]) hi--;
  if (hi < 0) return 0.0;
  while (!a->limb[lo]) lo++;
  int64_t l[ESF_XSUM_LIMBS];
  memcpy(l + lo, a->limb + lo, (size_t)(hi - lo + 1) * sizeof *l);
  carry(l, lo, hi);
  const int neg = l[hi] < 0;
  if (neg) { /* |V|: the limbs negated, carried again (the top ends >= 0) */
    for (int k = lo; k <= hi; k++) l[k] = -l[k];
    carry(l, lo, hi);
  }
  /* |V| as 32-bit digits, two zero digits below (d[k + 2] is digit k), the top limb
   * (< 2^63) as two */
  enum { ND = ESF_XSUM_LIMBS + 3 };
  uint64_t d[ND];
  memset(d, 0, sizeof d);
  for (int k = lo; k < hi; k++) d[k + 2] = (uint64_t)l[k];
  d[hi + 2] = (uint64_t)l[hi] & 0xffffffffu;
  d[hi + 3] = (uint64_t)l[hi] >> 32;
  int t = hi + 3;
  while (t >= lo + 2 && !d[t]) t--;
  if (t < lo + 2) return 0.0;
  int b = 0; /* bit length of the top digit, 1..32 */
  while (b < 32 && (d[t] >> b)) b++;
  const int len = 32 * (t - 2) + b; /* bit length of |V| */
  const uint64_t w = (((d[t] << 32) | d[t - 1]) << (32 - b)) | (d[t - 2] >> b);
  int sticky = (d[t - 2] & ((((uint64_t)1) << b) - 1)) != 0;
  for (int k = lo + 2; k < t - 2 && !sticky; k++) sticky = d[k] != 0;
  uint64_t q = w >> 11;
  const uint64_t rem = w & 0x7ffu, half = 0x400u;
  if (rem > half || (rem == half && (sticky || (q & 1)))) q++; /* q = 2^53 is exact */
  const double r = ldexp((double)q, len - 53 - 1074);
  return neg ? -r : r;
}
