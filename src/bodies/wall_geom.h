/* wall_geom.h — geometry of wall elements: infinite planes and finite convex planar
 * polygons (triangles, quadrilaterals), and the point of an element nearest a sphere
 * centre (004 §2.3.2, eqs. 2.4–2.5): the foot of the normal when it falls inside the
 * polygon (face contact), else the nearest point of its boundary (edge or vertex).
 *
 * A plane is one-sided: particles live on the side its normal points to, and a centre
 * behind it is still pushed back along the normal (its distance is negative).
 * A polygon is two-sided: the distance is unsigned. */
#ifndef ESF_WALL_GEOM_H
#define ESF_WALL_GEOM_H

#include <math.h>
#include <stdint.h>

#include "util/esf_error.h"
#include "util/vec3.h"

enum { ESF_WALL_PLANE = 0, ESF_WALL_POLYGON = 1 };
enum { ESF_FEATURE_FACE = 0, ESF_FEATURE_EDGE = 1, ESF_FEATURE_VERTEX = 2 };

#define ESF_WALL_MAX_VERTS 4

typedef struct esf_wall_elem {
  int kind;                        /* ESF_WALL_PLANE or ESF_WALL_POLYGON */
  int nv;                          /* polygon: 3 or 4 vertices; plane: 0 */
  double v[ESF_WALL_MAX_VERTS][3]; /* polygon vertices in order, m */
  double p[3];                     /* plane: its point; polygon: the centroid, m */
  double n[3];                     /* unit normal (polygon: right hand over v order) */
  double edge_n[ESF_WALL_MAX_VERTS][3]; /* in-plane unit outward normal of edge k
                                           (v[k] -> v[k+1]), for the inside test */
  double bound_r;   /* polygon: radius of the sphere about p holding it */
  int32_t material; /* material index */
  int32_t group;    /* the wall this element belongs to (box, plane...) */
} esf_wall_elem;

/* The nearest point of an element to a centre. */
typedef struct esf_wall_hit {
  double q[3]; /* the nearest point on the element, m */
  double n[3]; /* unit contact normal, from the centre toward q (plane: -normal) */
  double dist; /* distance centre -> q along n, m (plane: signed, negative behind) */
  int feature; /* ESF_FEATURE_FACE, _EDGE or _VERTEX (plane: always FACE) */
} esf_wall_hit;

/* Builds an infinite plane through point with the given normal (normalised here).
 * Error: zero or non-finite normal. */
int esf_wall_plane_init(esf_wall_elem *e, const double point[3], const double normal[3],
                        int32_t material, int32_t group, esf_error *err);

/* Builds a polygon from nv = 3 or 4 vertices. Errors (ESF_EINPUT): nv out of range,
 * repeated vertices or zero area (degenerate), a quadrilateral that is not planar
 * (within 1e-9 of its size) or not convex. */
int esf_wall_polygon_init(esf_wall_elem *e, int nv, const double (*verts)[3],
                          int32_t material, int32_t group, esf_error *err);

/* esf_wall_polygon_init's element without its checks, for vertices a rigid motion took
 * from a polygon it accepted (bodies/wall_motion.c): the same operations, so the same
 * fields as esf_wall_polygon_init would give. */
void esf_wall_polygon_set(esf_wall_elem *e, int nv, const double (*verts)[3],
                          int32_t material, int32_t group);

/* The signed height (x - p).n of centre x over element e's plane, m. */
static inline double esf_wall_height(const esf_wall_elem *e, const double x[3]) {
  double r[3];
  v3_sub(r, x, e->p);
  return v3_dot(r, e->n);
}

/* max(|a0|, |a1|, |a2|) */
static inline double esf_max3abs(const double a[3]) {
  const double x = fabs(a[0]), y = fabs(a[1]), z = fabs(a[2]);
  const double m = x > y ? x : y;
  return m > z ? m : z;
}

/* 1 when polygon e's plane lies at least `reach` from centre x, measured with a slack
 * that covers rounding, so that esf_wall_nearest's distance is >= reach too: every
 * point of a polygon lies within 2e-9 bound_r of its plane (esf_wall_polygon_init
 * accepts quadrilaterals planar within 1e-9 of their size, at most 2 bound_r), and the
 * computed height and boundary distance round by a few units of 1e-16 of the
 * coordinates' magnitude; slack = 4e-9 bound_r + 1e-12 (|x| + |p| + bound_r + reach)
 * (max-norms). h is esf_wall_height(e, x). One comparison when |h| < reach. */
static inline int esf_wall_out_of_reach(const esf_wall_elem *e, const double x[3],
                                        double h, double reach) {
  if (fabs(h) < reach) return 0; /* within reach whatever the slack (>= 0) */
  const double slack = 4e-9 * e->bound_r +
                       1e-12 * (esf_max3abs(x) + esf_max3abs(e->p) + e->bound_r + reach);
  return !(fabs(h) < reach + slack);
}

/* Inside test slack of a polygon's face test, as a fraction of bound_r. */
#define ESF_WALL_INSIDE_TOL 1e-12

/* The face test of esf_wall_nearest for a polygon e, given the signed height h of
 * centre x over the polygon's plane (esf_wall_height): the foot of the normal, and
 * whether it lies inside every edge (then it is the nearest point, a FACE hit). Inline
 * so that the fast wall pass (wall_fast.c) computes the same bits as
 * esf_wall_nearest. */
static inline int esf_wall_polygon_foot(const esf_wall_elem *e, const double x[3],
                                        double h, double foot[3]) {
  v3_copy(foot, x);
  v3_axpy(foot, -h, e->n);
  const double tol = ESF_WALL_INSIDE_TOL * e->bound_r;
  for (int k = 0; k < e->nv; k++) {
    double d[3];
    v3_sub(d, foot, e->v[k]);
    if (v3_dot(d, e->edge_n[k]) > tol) return 0;
  }
  return 1;
}

/* The nearest point of e to centre x. When x lies on a polygon's plane inside it
 * (dist 0) the normal is -e->n. */
void esf_wall_nearest(const esf_wall_elem *e, const double x[3], esf_wall_hit *hit);

/* The six inward-facing quadrilaterals of an axis-aligned box, less the open faces.
 * open_mask bits: 1 xmin, 2 xmax, 4 ymin, 8 ymax, 16 zmin (bottom), 32 zmax (top).
 * Writes up to 6 elements into out and their count into *count. Error: min >= max. */
int esf_wall_box(const double min[3], const double max[3], unsigned open_mask,
                 int32_t material, int32_t group, esf_wall_elem out[6], int *count,
                 esf_error *err);

#endif
