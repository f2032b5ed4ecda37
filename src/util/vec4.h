/* vec4.h — four doubles as one value (GCC vector extensions): AVX registers when the
 * build targets them, two SSE2 halves otherwise. Loads and stores go through memcpy,
 * so no alignment is assumed. Every operation is lane-wise IEEE arithmetic: a lane's
 * result is what the scalar expression gives. */
#ifndef ESF_VEC4_H
#define ESF_VEC4_H

#include <string.h>

/* The helpers are static and inlined, so no vector crosses a call boundary: GCC's
 * note that AVX-sized vectors change the ABI of non-AVX builds does not apply. */
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

typedef double esf_v4 __attribute__((vector_size(4 * sizeof(double))));
typedef long long esf_v4m __attribute__((vector_size(4 * sizeof(double)))); /* masks */

static inline esf_v4 v4_ld(const void *p) {
  esf_v4 v;
  memcpy(&v, p, sizeof v);
  return v;
}

static inline void v4_st(void *p, esf_v4 v) { memcpy(p, &v, sizeof v); }

/* d[0..4) += s[0..4) and -= */
static inline void v4_acc(double *d, const double *s) { v4_st(d, v4_ld(d) + v4_ld(s)); }
static inline void v4_dec(double *d, const double *s) { v4_st(d, v4_ld(d) - v4_ld(s)); }

#endif
