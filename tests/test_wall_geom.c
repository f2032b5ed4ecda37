/* test_wall_geom.c — planes, triangles, quadrilaterals and boxes: nearest points over
 * the face, beyond each edge and each vertex (analytic q, dist, feature), the same for a
 * rotated and shifted quadrilateral, signed plane distances, construction errors, and
 * the box helper (open faces, inward normals, distances near a corner). */
#include <math.h>
#include <string.h>

#include "bodies/wall_geom.h"
#include "check.h"
#include "util/vec3.h"

#define TOL     1e-12
#define SQRT1_2 0.70710678118654752440

static void check_vec(const double *got, const double *want, const char *what) {
  double d[3];
  v3_sub(d, got, want);
  CHECK(v3_norm(d) <= TOL,
        "%s: got (%.12g, %.12g, %.12g), expected (%.12g, %.12g, %.12g)", what, got[0],
        got[1], got[2], want[0], want[1], want[2]);
}

/* Checks a hit against the expected nearest point and feature; dist and normal follow
 * from q (unless on the element). */
static void check_hit(const esf_wall_elem *e, const double x[3], const double q[3],
                      int feature, const char *what) {
  esf_wall_hit h;
  esf_wall_nearest(e, x, &h);
  char buf[160];
  snprintf(buf, sizeof buf, "%s: q", what);
  check_vec(h.q, q, buf);
  CHECK(h.feature == feature, "%s: feature %d, expected %d", what, h.feature, feature);
  double d[3];
  v3_sub(d, q, x);
  double dist = v3_norm(d);
  snprintf(buf, sizeof buf, "%s: dist", what);
  CHECK_NEAR(h.dist, dist, TOL, buf);
  double n[3];
  if (dist > 0)
    v3_scale(n, 1 / dist, d);
  else
    v3_scale(n, -1, e->n);
  snprintf(buf, sizeof buf, "%s: normal", what);
  check_vec(h.n, n, buf);
}

/* A rigid motion: rotation R (about a skew axis) then shift t. */
static double R[3][3], T[3] = {0.3, -1.7, 2.2};
static void make_rotation(void) {
  double a[3] = {1, 2, 2}, th = 0.7; /* |a| = 3 */
  v3_scale(a, 1.0 / 3, a);
  double c = cos(th), s = sin(th);
  for (int i = 0; i < 3; i++)
    for (int j = 0; j < 3; j++) R[i][j] = (i == j ? c : 0) + (1 - c) * a[i] * a[j];
  R[0][1] -= s * a[2];
  R[0][2] += s * a[1];
  R[1][0] += s * a[2];
  R[1][2] -= s * a[0];
  R[2][0] -= s * a[1];
  R[2][1] += s * a[0];
}
static void move(double *o, const double *p) {
  double y[3];
  for (int i = 0; i < 3; i++)
    y[i] = R[i][0] * p[0] + R[i][1] * p[1] + R[i][2] * p[2] + T[i];
  v3_copy(o, y);
}

static void test_triangle(void) {
  esf_error err = {0};
  esf_wall_elem e;
  const double v[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  CHECK_OK(esf_wall_polygon_init(&e, 3, v, 4, 9, &err), err);
  CHECK(e.kind == ESF_WALL_POLYGON && e.nv == 3 && e.material == 4 && e.group == 9,
        "triangle fields");
  check_vec(e.n, (double[]){0, 0, 1}, "triangle normal");
  check_vec(e.p, (double[]){1.0 / 3, 1.0 / 3, 0}, "triangle centroid");
  check_vec(e.edge_n[0], (double[]){0, -1, 0}, "edge normal 0");
  check_vec(e.edge_n[1], (double[]){SQRT1_2, SQRT1_2, 0}, "edge normal 1");
  check_vec(e.edge_n[2], (double[]){-1, 0, 0}, "edge normal 2");
  CHECK_NEAR(e.bound_r, sqrt(5.0) / 3, TOL, "triangle bound_r");

  check_hit(&e, (double[]){0.2, 0.2, 0.5}, (double[]){0.2, 0.2, 0}, ESF_FEATURE_FACE,
            "triangle over the face");
  check_hit(&e, (double[]){0.2, 0.3, -0.4}, (double[]){0.2, 0.3, 0}, ESF_FEATURE_FACE,
            "triangle under the face (two-sided)");
  esf_wall_hit h;
  esf_wall_nearest(&e, (double[]){0.2, 0.3, -0.4}, &h);
  CHECK_NEAR(h.dist, 0.4, TOL, "polygon distance is unsigned");
  check_vec(h.n, (double[]){0, 0, 1}, "normal from below points up to the face");
  check_hit(&e, (double[]){0.25, 0.25, 0}, (double[]){0.25, 0.25, 0}, ESF_FEATURE_FACE,
            "triangle on the face");
  esf_wall_nearest(&e, (double[]){0.25, 0.25, 0}, &h);
  CHECK(h.dist == 0, "on the face: dist %g", h.dist);
  check_hit(&e, (double[]){0.5, 0.5, 0.1}, (double[]){0.5, 0.5, 0}, ESF_FEATURE_FACE,
            "triangle over the hypotenuse (inclusive)");
  check_hit(&e, (double[]){0.5, -0.4, 0.3}, (double[]){0.5, 0, 0}, ESF_FEATURE_EDGE,
            "triangle beyond edge 1-2");
  check_hit(&e, (double[]){0.75, 0.75, -0.2}, (double[]){0.5, 0.5, 0}, ESF_FEATURE_EDGE,
            "triangle beyond edge 2-3");
  check_hit(&e, (double[]){-0.5, 0.3, 0.2}, (double[]){0, 0.3, 0}, ESF_FEATURE_EDGE,
            "triangle beyond edge 3-1");
  check_hit(&e, (double[]){-1, -1, 0.5}, (double[]){0, 0, 0}, ESF_FEATURE_VERTEX,
            "triangle beyond vertex 1");
  check_hit(&e, (double[]){2, -0.5, 0}, (double[]){1, 0, 0}, ESF_FEATURE_VERTEX,
            "triangle beyond vertex 2");
  check_hit(&e, (double[]){-0.5, 2, 0.3}, (double[]){0, 1, 0}, ESF_FEATURE_VERTEX,
            "triangle beyond vertex 3");

  /* clockwise order flips the normal, edge normals still point out */
  const double w[3][3] = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}};
  CHECK_OK(esf_wall_polygon_init(&e, 3, w, 0, 0, &err), err);
  check_vec(e.n, (double[]){0, 0, -1}, "clockwise triangle normal");
  check_vec(e.edge_n[0], (double[]){-1, 0, 0}, "clockwise edge normal 0");
  check_hit(&e, (double[]){0.2, 0.2, 0.5}, (double[]){0.2, 0.2, 0}, ESF_FEATURE_FACE,
            "clockwise triangle over the face");
  check_hit(&e, (double[]){2, -0.5, 0}, (double[]){1, 0, 0}, ESF_FEATURE_VERTEX,
            "clockwise triangle beyond a vertex");
}

/* The rectangle [0,2] x [0,1] at z = 1, optionally moved rigidly. */
static void test_quad(int moved) {
  esf_error err = {0};
  esf_wall_elem e;
  double v[4][3] = {{0, 0, 1}, {2, 0, 1}, {2, 1, 1}, {0, 1, 1}};
  if (moved)
    for (int k = 0; k < 4; k++) move(v[k], v[k]);
  CHECK_OK(esf_wall_polygon_init(&e, 4, (const double(*)[3])v, 1, 2, &err), err);
  double n[3] = {0, 0, 1}, p[3] = {1, 0.5, 1};
  if (moved) {
    double o[3] = {0, 0, 0};
    move(n, n);
    move(o, o);
    v3_sub(n, n, o);
    move(p, p);
  }
  check_vec(e.n, n, moved ? "moved quad normal" : "quad normal");
  check_vec(e.p, p, moved ? "moved quad centroid" : "quad centroid");
  CHECK_NEAR(e.bound_r, sqrt(1.25), TOL, "quad bound_r");

  static const struct {
    double x[3], q[3];
    int feature;
    const char *what;
  } cases[] = {
      {{0.5, 0.5, 3}, {0.5, 0.5, 1}, ESF_FEATURE_FACE, "over the face"},
      {{1.9, 0.1, 0.2}, {1.9, 0.1, 1}, ESF_FEATURE_FACE, "under the face"},
      {{1.2, 0.7, 1}, {1.2, 0.7, 1}, ESF_FEATURE_FACE, "on the face"},
      {{2, 1, 1.5}, {2, 1, 1}, ESF_FEATURE_FACE, "over a corner (inclusive)"},
      {{1.5, -0.5, 1.5}, {1.5, 0, 1}, ESF_FEATURE_EDGE, "beyond edge 1-2"},
      {{3, 0.25, 0.5}, {2, 0.25, 1}, ESF_FEATURE_EDGE, "beyond edge 2-3"},
      {{0.5, 1.3, 1}, {0.5, 1, 1}, ESF_FEATURE_EDGE, "beyond edge 3-4 (in plane)"},
      {{-0.1, 0.9, 0.8}, {0, 0.9, 1}, ESF_FEATURE_EDGE, "beyond edge 4-1"},
      {{-1, -1, 1}, {0, 0, 1}, ESF_FEATURE_VERTEX, "beyond vertex 1"},
      {{2.5, -0.2, 2}, {2, 0, 1}, ESF_FEATURE_VERTEX, "beyond vertex 2"},
      {{2.1, 1.1, 0.9}, {2, 1, 1}, ESF_FEATURE_VERTEX, "beyond vertex 3"},
      {{-3, 4, -2}, {0, 1, 1}, ESF_FEATURE_VERTEX, "beyond vertex 4"},
  };
  for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
    double x[3], q[3];
    v3_copy(x, cases[c].x);
    v3_copy(q, cases[c].q);
    if (moved) {
      move(x, x);
      move(q, q);
    }
    char what[120];
    snprintf(what, sizeof what, "%squad %s", moved ? "moved " : "", cases[c].what);
    check_hit(&e, x, q, cases[c].feature, what);
  }
}

static void test_plane(void) {
  esf_error err = {0};
  esf_wall_elem e;
  CHECK_OK(esf_wall_plane_init(&e, (double[]){0, 0, 1}, (double[]){0, 0, 2}, 3, 5, &err),
           err);
  CHECK(e.kind == ESF_WALL_PLANE && e.nv == 0 && e.material == 3 && e.group == 5,
        "plane fields");
  check_vec(e.n, (double[]){0, 0, 1}, "plane normal normalised");
  esf_wall_hit h;
  esf_wall_nearest(&e, (double[]){3, 4, 3}, &h);
  CHECK_NEAR(h.dist, 2, TOL, "plane distance in front");
  check_vec(h.q, (double[]){3, 4, 1}, "plane foot in front");
  check_vec(h.n, (double[]){0, 0, -1}, "plane contact normal in front");
  CHECK(h.feature == ESF_FEATURE_FACE, "plane feature");
  esf_wall_nearest(&e, (double[]){3, 4, 0.5}, &h);
  CHECK_NEAR(h.dist, -0.5, TOL, "plane distance behind is negative");
  check_vec(h.q, (double[]){3, 4, 1}, "plane foot behind");
  check_vec(h.n, (double[]){0, 0, -1}, "plane contact normal behind is still -normal");

  /* a tilted plane: x + y = 1 */
  CHECK_OK(
      esf_wall_plane_init(&e, (double[]){1, 0, 0}, (double[]){-1, -1, 0}, 0, 0, &err),
      err);
  esf_wall_nearest(&e, (double[]){0, 0, 7}, &h);
  CHECK_NEAR(h.dist, SQRT1_2, TOL, "tilted plane distance");
  check_vec(h.q, (double[]){0.5, 0.5, 7}, "tilted plane foot");

  int rc = esf_wall_plane_init(&e, (double[]){0, 0, 0}, (double[]){0, 0, 0}, 0, 0, &err);
  CHECK(rc == ESF_EINPUT, "zero plane normal: status %d", rc);
  rc = esf_wall_plane_init(&e, (double[]){0, 0, 0}, (double[]){0, NAN, 1}, 0, 0, &err);
  CHECK(rc == ESF_EINPUT, "NaN plane normal: status %d", rc);
  rc = esf_wall_plane_init(&e, (double[]){INFINITY, 0, 0}, (double[]){0, 0, 1}, 0, 0,
                           &err);
  CHECK(rc == ESF_EINPUT, "infinite plane point: status %d", rc);
}

static void expect_error(int nv, const double (*v)[3], const char *needle,
                         const char *what) {
  esf_error err = {0};
  esf_wall_elem e;
  int rc = esf_wall_polygon_init(&e, nv, v, 0, 0, &err);
  CHECK(rc == ESF_EINPUT, "%s: status %d", what, rc);
  CHECK(strstr(err.msg, needle) != NULL, "%s: message \"%s\" lacks \"%s\"", what, err.msg,
        needle);
}

static void test_errors(void) {
  const double tri[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  expect_error(2, tri, "3 or 4 vertices", "two vertices");
  expect_error(5, tri, "3 or 4 vertices", "five vertices");
  const double line[3][3] = {{0, 0, 0}, {1, 1, 1}, {3, 3, 3}};
  expect_error(3, line, "zero area", "collinear triangle");
  const double rep[3][3] = {{0, 0, 0}, {1, 0, 0}, {1, 0, 0}};
  expect_error(3, rep, "vertices 2 and 3 coincide", "repeated triangle vertex");
  const double repq[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}};
  expect_error(4, repq, "vertices 1 and 4 coincide", "repeated quad vertex");
  const double bent[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0.002}};
  expect_error(4, bent, "not planar (vertex 4 is 0.002 m off", "non-planar quad");
  const double dart[4][3] = {{0, 0, 0}, {2, 0, 0}, {0.5, 0.5, 0}, {0, 2, 0}};
  expect_error(4, dart, "not convex", "dart quad");
  const double bowtie[4][3] = {{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1.5, 0}};
  expect_error(4, bowtie, "not convex", "bow-tie quad");
  const double three[4][3] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1, 1, 0}};
  expect_error(4, three, "degenerate", "quad with three collinear vertices");
  const double nan[3][3] = {{0, 0, 0}, {1, NAN, 0}, {0, 1, 0}};
  expect_error(3, nan, "vertex 2 has a non-finite", "NaN vertex");

  /* tiny but well-shaped polygons are fine (tolerances are relative) */
  esf_error err = {0};
  esf_wall_elem e;
  const double small[4][3] = {{0, 0, 0}, {1e-6, 0, 0}, {1e-6, 1e-6, 0}, {0, 1e-6, 0}};
  CHECK_OK(esf_wall_polygon_init(&e, 4, small, 0, 0, &err), err);
  /* planar within tolerance: 1e-11 off over a size of 1.4 */
  const double nearly[4][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 1e-11}};
  CHECK_OK(esf_wall_polygon_init(&e, 4, nearly, 0, 0, &err), err);
}

static void test_box(void) {
  esf_error err = {0};
  esf_wall_elem f[6];
  int count = -1;
  const double lo[3] = {0, 0, 0}, hi[3] = {1, 2, 3}, mid[3] = {0.5, 1, 1.5};
  CHECK_OK(esf_wall_box(lo, hi, 32, 7, 11, f, &count, &err), err);
  CHECK(count == 5, "box with an open top has %d faces", count);
  int seen[6] = {0};
  for (int k = 0; k < count; k++) {
    CHECK(f[k].kind == ESF_WALL_POLYGON && f[k].nv == 4, "box face %d is a quad", k);
    CHECK(f[k].material == 7 && f[k].group == 11, "box face %d material/group", k);
    double to_mid[3];
    v3_sub(to_mid, mid, f[k].p);
    CHECK(v3_dot(to_mid, f[k].n) > 0, "box face %d normal points inward", k);
    int axis = -1;
    for (int d = 0; d < 3; d++)
      if (fabs(fabs(f[k].n[d]) - 1) < TOL) axis = d;
    CHECK(axis >= 0, "box face %d normal is axis-aligned", k);
    if (axis >= 0) seen[2 * axis + (f[k].n[axis] < 0)]++;
  }
  CHECK(seen[0] == 1 && seen[1] == 1 && seen[2] == 1 && seen[3] == 1 && seen[4] == 1 &&
            seen[5] == 0,
        "faces: xmin %d xmax %d ymin %d ymax %d zmin %d zmax %d", seen[0], seen[1],
        seen[2], seen[3], seen[4], seen[5]);
  CHECK(f[4].n[2] == 1, "the bottom (zmin) face has normal +z");

  /* a centre inside near the corner (0, 0, 0): distances from the three faces there */
  const double x[3] = {0.1, 0.2, 0.05};
  const double want[6] = {0.1, 0.9, 0.2, 1.8, 0.05, 0};
  for (int k = 0; k < count; k++) {
    esf_wall_hit h;
    esf_wall_nearest(&f[k], x, &h);
    int axis = 0;
    for (int d = 0; d < 3; d++)
      if (fabs(f[k].n[d]) > 0.5) axis = d;
    int face = 2 * axis + (f[k].n[axis] < 0);
    char what[64];
    snprintf(what, sizeof what, "box face %d distance", face);
    CHECK_NEAR(h.dist, want[face], TOL, what);
    CHECK(h.feature == ESF_FEATURE_FACE, "box face %d: feature %d", face, h.feature);
    double nn[3];
    v3_scale(nn, -1, f[k].n);
    snprintf(what, sizeof what, "box face %d contact normal", face);
    check_vec(h.n, nn, what);
  }

  CHECK_OK(esf_wall_box(lo, hi, 0, 0, 0, f, &count, &err), err);
  CHECK(count == 6, "closed box has %d faces", count);
  CHECK_OK(esf_wall_box(lo, hi, 63, 0, 0, f, &count, &err), err);
  CHECK(count == 0, "all-open box has %d faces", count);
  int rc = esf_wall_box(lo, (double[]){1, 0, 3}, 0, 0, 0, f, &count, &err);
  CHECK(rc == ESF_EINPUT && count == 0, "min >= max: status %d", rc);
  rc = esf_wall_box(lo, hi, 64, 0, 0, f, &count, &err);
  CHECK(rc == ESF_EINPUT, "unknown open bits: status %d", rc);
}

int main(void) {
  make_rotation();
  test_triangle();
  test_quad(0);
  test_quad(1);
  test_plane();
  test_errors();
  test_box();
  return check_finish("test_wall_geom");
}
