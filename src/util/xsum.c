/* xsum.c — the exact accumulator of xsum.h: a sum of doubles held as the integer
 * V = sum of terms / 2^-1074 in 32-bit digits of int64_t limbs (a long accumulator in
 * the manner of Kulisch's, with lazy carries).
 * Normalisation: carries move up limb by limb (c = floor(l / 2^32)), leaving digits in
 * [0, 2^32) and the sign in the top limb; the result is the unique base-2^32 form of V.
 * Rounding (esf_xsum_value): |V| normalised again as a magnitude; its top 64 bits w
 * (leading bit set) and a sticky bit for everything below; q = w >> 11 rounded to
 * nearest, ties to even, gives q 2^(L - 53 - 1074) for L the bit length of |V| (ldexp
 * is then exact, or overflows to Inf as IEEE rounding does). Results below 2^-1021
 * have L <= 53 and are exact, so no subnormal is rounded twice.
 * Entry: an accumulator set by esf_xsum_zero. Units: those of the terms. */
#include "util/xsum.h"

#include <math.h>

/* Carries limbs 0..ESF_XSUM_LIMBS-2 into the next (floor division by 2^32, exact:
 * int64_t is two's complement, and l - (l & mask) is a multiple of 2^32). */
static void carry(int64_t *l) {
  for (int k = 0; k + 1 < ESF_XSUM_LIMBS; k++) {
    const int64_t lo = l[k] & (int64_t)0xffffffff;
    l[k + 1] += (l[k] - lo) / ((int64_t)1 << 32);
    l[k] = lo;
  }
}

void esf_xsum_zero(esf_xsum *a) {
  memset(a, 0, sizeof *a);
  a->pending = 1;
}

void esf_xsum_normalize(esf_xsum *a) {
  carry(a->limb);
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
  for (size_t i = 0; i < n; i++) esf_xsum_add(a, x[i * stride]);
}

double esf_xsum_value(const esf_xsum *a) {
  if (a->nan || (a->pinf && a->ninf)) return NAN;
  if (a->pinf) return INFINITY;
  if (a->ninf) return -INFINITY;
  int64_t l[ESF_XSUM_LIMBS];
  memcpy(l, a->limb, sizeof l);
  carry(l);
  const int neg = l[ESF_XSUM_LIMBS - 1] < 0;
  if (neg) { /* |V|: the limbs negated, carried again (the top limb ends >= 0) */
    for (int k = 0; k < ESF_XSUM_LIMBS; k++) l[k] = -l[k];
    carry(l);
  }
  /* |V| as 32-bit digits, two zero digits below (d[k + 2] is digit k) */
  enum { ND = ESF_XSUM_LIMBS + 3 };
  uint64_t d[ND];
  d[0] = d[1] = 0;
  for (int k = 0; k + 1 < ESF_XSUM_LIMBS; k++) d[k + 2] = (uint64_t)l[k];
  d[ND - 2] = (uint64_t)l[ESF_XSUM_LIMBS - 1] & 0xffffffffu;
  d[ND - 1] = (uint64_t)l[ESF_XSUM_LIMBS - 1] >> 32;
  int t = ND - 1;
  while (t >= 2 && !d[t]) t--;
  if (t < 2) return 0.0;
  int b = 0; /* bit length of the top digit, 1..32 */
  while (b < 32 && (d[t] >> b)) b++;
  const int len = 32 * (t - 2) + b; /* bit length of |V| */
  const uint64_t w = (((d[t] << 32) | d[t - 1]) << (32 - b)) | (d[t - 2] >> b);
  int sticky = (d[t - 2] & ((((uint64_t)1) << b) - 1)) != 0;
  for (int k = 0; k < t - 2 && !sticky; k++) sticky = d[k] != 0;
  uint64_t q = w >> 11;
  const uint64_t rem = w & 0x7ffu, half = 0x400u;
  if (rem > half || (rem == half && (sticky || (q & 1)))) q++; /* q = 2^53 is exact */
  const double r = ldexp((double)q, len - 53 - 1074);
  return neg ? -r : r;
}
