/* vec3.h — small inline helpers for 3-vectors stored as double[3]. */
#ifndef ESF_VEC3_H
#define ESF_VEC3_H

#include <math.h>

#define ESF_PI 3.14159265358979323846

static inline double v3_dot(const double *a, const double *b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
static inline double v3_norm2(const double *a) { return v3_dot(a, a); }
static inline double v3_norm(const double *a) { return sqrt(v3_dot(a, a)); }
static inline void v3_set(double *o, double x, double y, double z) {
  o[0] = x;
  o[1] = y;
  o[2] = z;
}
static inline void v3_copy(double *o, const double *a) {
  o[0] = a[0];
  o[1] = a[1];
  o[2] = a[2];
}
static inline void v3_sub(double *o, const double *a, const double *b) {
  o[0] = a[0] - b[0];
  o[1] = a[1] - b[1];
  o[2] = a[2] - b[2];
}
static inline void v3_add(double *o, const double *a, const double *b) {
  o[0] = a[0] + b[0];
  o[1] = a[1] + b[1];
  o[2] = a[2] + b[2];
}
static inline void v3_scale(double *o, double s, const double *a) {
  o[0] = s * a[0];
  o[1] = s * a[1];
  o[2] = s * a[2];
}
/* o += s a */
static inline void v3_axpy(double *o, double s, const double *a) {
  o[0] += s * a[0];
  o[1] += s * a[1];
  o[2] += s * a[2];
}
/* 1 when a lies outside the box [lo, hi] (on a face is inside); no branches. */
static inline int v3_outside(const double *a, const double *lo, const double *hi) {
  return (a[0] < lo[0]) | (a[0] > hi[0]) | (a[1] < lo[1]) | (a[1] > hi[1]) |
         (a[2] < lo[2]) | (a[2] > hi[2]);
}
static inline void v3_cross(double *o, const double *a, const double *b) {
  double x = a[1] * b[2] - a[2] * b[1];
  double y = a[2] * b[0] - a[0] * b[2];
  double z = a[0] * b[1] - a[1] * b[0];
  o[0] = x;
  o[1] = y;
  o[2] = z;
}
/* o = v rotated by angle a (rad) about the unit axis k (Rodrigues' formula); o may
 * alias v. */
/* v3_rotate by the angle whose cosine and sine are c, s (one angle, many vectors). */
static inline void v3_rotate_cs(double *o, const double *v, const double *k, double c,
                                double s) {
  double kxv[3];
  v3_cross(kxv, k, v);
  double kv = v3_dot(k, v) * (1 - c);
  for (int q = 0; q < 3; q++) o[q] = v[q] * c + kxv[q] * s + k[q] * kv;
}
static inline void v3_rotate(double *o, const double *v, const double *k, double a) {
  v3_rotate_cs(o, v, k, cos(a), sin(a));
}
/* u, v completing the unit vector n to a right-handed orthonormal frame (u, v, n):
 * u = unit(n x e) with e the coordinate axis least aligned with n, v = n x u. */
static inline void v3_basis(double *u, double *v, const double *n) {
  int ax = 0;
  for (int q = 1; q < 3; q++)
    if (fabs(n[q]) < fabs(n[ax])) ax = q;
  double e[3] = {0, 0, 0};
  e[ax] = 1.0;
  v3_cross(u, n, e);
  v3_scale(u, 1.0 / v3_norm(u), u);
  v3_cross(v, n, u);
}

#endif
