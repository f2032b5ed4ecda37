/* wall_geom.c — wall elements (infinite planes, convex triangles and quadrilaterals) and
 * the point of an element nearest a sphere centre (004 §2.3.2, eqs. 2.4–2.5).
 *
 * Plane (one-sided): dist = (x - p)·n is signed (negative behind the plane), the nearest
 * point is the foot q = x - dist n and the contact normal is -n whatever the side.
 * Polygon (two-sided): the centre is projected onto the polygon's plane; when the foot
 * lies inside every edge (edge_n[k]·(foot - v[k]) <= a tolerance of 1e-12 of the
 * polygon's size) it is the nearest point (FACE); otherwise the nearest point is the
 * closest over the edges of the clamped projection onto each segment, a VERTEX when the
 * segment parameter was clamped to 0 or 1, else an EDGE point. dist = |x - q| and the
 * normal is (q - x)/dist, or -n when the centre lies on the polygon (dist 0).
 *
 * Construction (esf_wall_polygon_init): n by Newell's method (right hand over the vertex
 * order), p the vertex centroid, bound_r the largest |v - p|, edge_n[k] the unit
 * in-plane normal of edge k pointing out of the polygon. Inputs are checked: 3 or 4
 * finite vertices, none repeated, area > 1e-12 size^2, a quadrilateral planar within
 * 1e-9 size and strictly convex; failures are ESF_EINPUT with a message naming the
 * problem. Units: m throughout. Nothing here allocates. */
#include "bodies/wall_geom.h"

#include <math.h>
#include <string.h>

#include "util/vec3.h"

#define AREA_TOL   1e-12 /* zero area below this fraction of size^2 */
#define REPEAT_TOL 1e-12 /* vertices closer than this fraction of the size coincide */
/* a quadrilateral may bend off its plane this much of its size */
#define PLANAR_TOL 1e-9

static int finite3(const double *a) {
  return isfinite(a[0]) && isfinite(a[1]) && isfinite(a[2]);
}

int esf_wall_plane_init(esf_wall_elem *e, const double point[3], const double normal[3],
                        int32_t material, int32_t group, esf_error *err) {
  if (!finite3(point))
    return esf_fail(err, ESF_EINPUT, "plane point (%g, %g, %g) is not finite", point[0],
                    point[1], point[2]);
  double len = v3_norm(normal);
  if (!finite3(normal) || !(len > 0) || !isfinite(len))
    return esf_fail(err, ESF_EINPUT, "plane normal (%g, %g, %g) is zero or not finite",
                    normal[0], normal[1], normal[2]);
  memset(e, 0, sizeof *e);
  e->kind = ESF_WALL_PLANE;
  e->nv = 0;
  v3_copy(e->p, point);
  v3_scale(e->n, 1 / len, normal);
  e->bound_r = INFINITY;
  e->material = material;
  e->group = group;
  return ESF_OK;
}

/* Area of triangle (a, b, c) times 2. */
static double tri_area2(const double *a, const double *b, const double *c, double *nrm) {
  double ab[3], ac[3];
  v3_sub(ab, b, a);
  v3_sub(ac, c, a);
  v3_cross(nrm, ab, ac);
  return v3_norm(nrm);
}

/* Centroid c and Newell normal about it (for accuracy), made unit in n; returns the
 * area (n is not finite when it is 0). */
static double newell(int nv, const double (*verts)[3], double c[3], double n[3]) {
  double nn[3] = {0, 0, 0};
  c[0] = c[1] = c[2] = 0.0;
  for (int k = 0; k < nv; k++) v3_axpy(c, 1.0 / nv, verts[k]);
  for (int k = 0; k < nv; k++) {
    double a[3], b[3], t[3];
    v3_sub(a, verts[k], c);
    v3_sub(b, verts[(k + 1) % nv], c);
    v3_cross(t, a, b);
    v3_add(nn, nn, t);
  }
  const double area = 0.5 * v3_norm(nn);
  v3_scale(n, 0.5 / area, nn);
  return area;
}

static void fill(esf_wall_elem *e, int nv, const double (*verts)[3], const double c[3],
                 const double n[3], int32_t material, int32_t group);

int esf_wall_polygon_init(esf_wall_elem *e, int nv, const double (*verts)[3],
                          int32_t material, int32_t group, esf_error *err) {
  if (nv < 3 || nv > ESF_WALL_MAX_VERTS)
    return esf_fail(err, ESF_EINPUT, "a polygon must have 3 or 4 vertices (got %d)", nv);
  for (int k = 0; k < nv; k++)
    if (!finite3(verts[k]))
      return esf_fail(err, ESF_EINPUT,
                      "polygon vertex %d has a non-finite coordinate (%g, %g, %g)", k + 1,
                      verts[k][0], verts[k][1], verts[k][2]);

  /* size: the largest distance between two vertices; repeated vertices */
  double size2 = 0;
  for (int a = 0; a < nv; a++)
    for (int b = a + 1; b < nv; b++) {
      double d[3];
      v3_sub(d, verts[a], verts[b]);
      if (v3_norm2(d) > size2) size2 = v3_norm2(d);
    }
  double size = sqrt(size2);
  for (int a = 0; a < nv; a++)
    for (int b = a + 1; b < nv; b++) {
      double d[3];
      v3_sub(d, verts[a], verts[b]);
      if (v3_norm(d) <= REPEAT_TOL * size)
        return esf_fail(err, ESF_EINPUT,
                        "polygon is degenerate (vertices %d and %d coincide at "
                        "(%g, %g, %g))",
                        a + 1, b + 1, verts[a][0], verts[a][1], verts[a][2]);
    }

  double c[3], n[3];
  const double area = newell(nv, verts, c, n);
  if (!(area > AREA_TOL * size2))
    return esf_fail(err, ESF_EINPUT,
                    "polygon is degenerate (zero area: its vertices are collinear)");

  if (nv == 4) {
    /* how far vertex 4 lies off the plane of vertices 1-3; when that triangle is
       badly shaped (its area under half the largest of the four), the vertex left out
       of the largest triangle instead */
    double a2[4], tk[4][3], best = 0, tn[3], off[3];
    for (int k = 0; k < 4; k++) {
      a2[k] =
          tri_area2(verts[(k + 1) % 4], verts[(k + 2) % 4], verts[(k + 3) % 4], tk[k]);
      if (a2[k] > best) best = a2[k];
    }
    int off_k = 3;
    if (a2[3] < 0.5 * best)
      for (int k = 0; k < 4; k++)
        if (a2[k] == best) off_k = k;
    best = a2[off_k];
    v3_copy(tn, tk[off_k]);
    v3_scale(tn, 1 / best, tn); /* best > 0: the quad's area is not zero */
    v3_sub(off, verts[off_k], verts[(off_k + 1) % 4]);
    double h = fabs(v3_dot(off, tn));
    if (h > PLANAR_TOL * size)
      return esf_fail(err, ESF_EINPUT,
                      "quadrilateral is not planar (vertex %d is %.3g m off the plane of "
                      "the other three)",
                      off_k + 1, h);
    /* convex: every turn v[k-1] -> v[k] -> v[k+1] to the same side (left about n) */
    for (int k = 0; k < 4; k++) {
      double e0[3], e1[3], t[3];
      v3_sub(e0, verts[k], verts[(k + 3) % 4]);
      v3_sub(e1, verts[(k + 1) % 4], verts[k]);
      v3_cross(t, e0, e1);
      double turn = v3_dot(t, n);
      if (turn < -AREA_TOL * size2)
        return esf_fail(err, ESF_EINPUT,
                        "quadrilateral is not convex (it turns the other way at vertex "
                        "%d)",
                        k + 1);
      if (turn <= AREA_TOL * size2)
        return esf_fail(err, ESF_EINPUT,
                        "quadrilateral is degenerate (vertex %d lies on the line through "
                        "its neighbours)",
                        k + 1);
    }
  }

  fill(e, nv, verts, c, n, material, group);
  return ESF_OK;
}

void esf_wall_polygon_set(esf_wall_elem *e, int nv, const double (*verts)[3],
                          int32_t material, int32_t group) {
  double c[3], n[3];
  newell(nv, verts, c, n);
  fill(e, nv, verts, c, n, material, group);
}

/* The element's fields from its vertices, centroid c and unit normal n. */
static void fill(esf_wall_elem *e, int nv, const double (*verts)[3], const double c[3],
                 const double n[3], int32_t material, int32_t group) {
  memset(e, 0, sizeof *e);
  e->kind = ESF_WALL_POLYGON;
  e->nv = nv;
  for (int k = 0; k < nv; k++) v3_copy(e->v[k], verts[k]);
  v3_copy(e->p, c);
  v3_copy(e->n, n);
  double br2 = 0;
  for (int k = 0; k < nv; k++) {
    double d[3], en[3];
    v3_sub(d, verts[k], c);
    if (v3_norm2(d) > br2) br2 = v3_norm2(d);
    v3_sub(d, verts[(k + 1) % nv], verts[k]);
    v3_cross(en, d, n); /* right of the edge seen from +n: outward for this winding */
    double l = v3_norm(en);
    v3_scale(e->edge_n[k], 1 / l, en);
    double toc[3];
    v3_sub(toc, c, verts[k]);
    if (v3_dot(e->edge_n[k], toc) > 0) v3_scale(e->edge_n[k], -1, e->edge_n[k]);
  }
  e->bound_r = sqrt(br2);
  e->material = material;
  e->group = group;
}

void esf_wall_nearest(const esf_wall_elem *e, const double x[3], esf_wall_hit *hit) {
  const double h = esf_wall_height(e, x); /* signed height of x over the plane */
  if (e->kind == ESF_WALL_PLANE) {
    v3_copy(hit->q, x);
    v3_axpy(hit->q, -h, e->n);
    v3_scale(hit->n, -1, e->n);
    hit->dist = h;
    hit->feature = ESF_FEATURE_FACE;
    return;
  }

  double foot[3];
  if (esf_wall_polygon_foot(e, x, h, foot)) { /* wall_geom.h */
    v3_copy(hit->q, foot);
    hit->dist = fabs(h);
    v3_scale(hit->n, h < 0 ? 1 : -1, e->n); /* (q - x)/dist; -n when on the face */
    hit->feature = ESF_FEATURE_FACE;
    return;
  }

  /* the nearest point of the boundary: clamped projection onto each edge */
  double best = INFINITY;
  for (int k = 0; k < e->nv; k++) {
    const double *a = e->v[k], *b = e->v[(k + 1) % e->nv];
    double ab[3], ax[3], q[3];
    v3_sub(ab, b, a);
    v3_sub(ax, x, a);
    double t = v3_dot(ax, ab) / v3_norm2(ab);
    int feature = ESF_FEATURE_EDGE;
    if (t <= 0) {
      t = 0;
      feature = ESF_FEATURE_VERTEX;
    } else if (t >= 1) {
      t = 1;
      feature = ESF_FEATURE_VERTEX;
    }
    if (feature == ESF_FEATURE_VERTEX)
      v3_copy(q, t == 0 ? a : b);
    else {
      v3_copy(q, a);
      v3_axpy(q, t, ab);
    }
    double d[3];
    v3_sub(d, q, x);
    double d2 = v3_norm2(d);
    if (d2 < best) {
      best = d2;
      v3_copy(hit->q, q);
      hit->feature = feature;
    }
  }
  v3_sub(hit->n, hit->q, x);
  hit->dist = v3_norm(hit->n);
  if (hit->dist > 0)
    v3_scale(hit->n, 1 / hit->dist, hit->n);
  else
    v3_scale(hit->n, -1, e->n);
}

int esf_wall_box(const double min[3], const double max[3], unsigned open_mask,
                 int32_t material, int32_t group, esf_wall_elem out[6], int *count,
                 esf_error *err) {
  *count = 0;
  if (open_mask & ~63u)
    return esf_fail(err, ESF_EINPUT, "box open mask 0x%x has unknown bits", open_mask);
  for (int d = 0; d < 3; d++)
    if (!isfinite(min[d]) || !isfinite(max[d]) || !(min[d] < max[d]))
      return esf_fail(err, ESF_EINPUT,
                      "box is empty or not finite along %c (min %g m, max %g m)", 'x' + d,
                      min[d], max[d]);
  /* corners by bits (x, y, z) = (1, 2, 4); each face listed counter-clockwise when
     seen from inside the box, so the right-hand normal points inward */
  static const int face[6][4] = {
      {0, 2, 6, 4}, /* xmin, normal +x */
      {1, 5, 7, 3}, /* xmax, normal -x */
      {0, 4, 5, 1}, /* ymin, normal +y */
      {2, 3, 7, 6}, /* ymax, normal -y */
      {0, 1, 3, 2}, /* zmin, normal +z */
      {4, 6, 7, 5}, /* zmax, normal -z */
  };
  static const char *name[6] = {"xmin", "xmax", "ymin", "ymax", "zmin", "zmax"};
  int m = 0;
  for (int f = 0; f < 6; f++) {
    if (open_mask & (1u << f)) continue;
    double v[4][3];
    for (int k = 0; k < 4; k++) {
      int corner = face[f][k];
      for (int d = 0; d < 3; d++) v[k][d] = (corner >> d) & 1 ? max[d] : min[d];
    }
    int rc =
        esf_wall_polygon_init(&out[m], 4, (const double(*)[3])v, material, group, err);
    if (rc) {
      if (err) esf_error_prefix(err, "box face %s: ", name[f]);
      return rc;
    }
    m++;
  }
  *count = m;
  return ESF_OK;
}
