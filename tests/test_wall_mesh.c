/* test_wall_mesh.c — the walls as a triangle mesh (wall_mesh.h): a box open at the top
 * gives 5 quadrilaterals = 20 points and 10 triangles whose right-hand normals are the
 * elements' inward normals and whose areas add up to the faces' areas; a triangle is
 * kept as is; an inclined plane becomes a square patch, wound along its normal, lying in
 * the plane, centred on the projection of the sizing box's centre, with side = the box's
 * diagonal, covering the projection of every corner of the box; without a box it falls
 * back to the finite elements' box, and with none at all to a 1 m square about the
 * plane's point; a moving wall is drawn where its motion puts it at the time asked for
 * while the walls handed in stay put. Storage is reused across builds. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "bodies/wall_mesh.h"
#include "check.h"
#include "util/vec3.h"

/* Unit normal and area of triangle k of m. */
static double tri_normal(const esf_wall_mesh *m, size_t k, double n[3]) {
  const int32_t *t = m->tri + 3 * k;
  double a[3], b[3];
  v3_sub(a, m->points + 3 * t[1], m->points + 3 * t[0]);
  v3_sub(b, m->points + 3 * t[2], m->points + 3 * t[0]);
  v3_cross(n, a, b);
  double area2 = v3_norm(n);
  if (area2 > 0) v3_scale(n, 1.0 / area2, n);
  return 0.5 * area2;
}

static void test_box(void) {
  esf_walls w = {0};
  esf_error err = {0};
  int g;
  CHECK_OK(esf_walls_add_group(&w, "box", &g, &err), err);
  esf_wall_elem faces[6];
  int nf = 0;
  const double lo[3] = {0, 0, 0}, hi[3] = {0.04, 0.03, 0.15};
  CHECK_OK(esf_wall_box(lo, hi, 32, 7, g, faces, &nf, &err), err);
  CHECK(nf == 5, "open box: %d faces", nf);
  for (int k = 0; k < nf; k++) CHECK_OK(esf_walls_add_elem(&w, &faces[k], &err), err);
  esf_wall_mesh m = {0};
  CHECK_OK(esf_wall_mesh_build(&w, 0.0, NULL, NULL, &m, &err), err);
  CHECK(m.np == 20 && m.nt == 10, "box mesh: %zu points, %zu triangles", m.np, m.nt);
  double area = 0, worst = 0;
  for (size_t k = 0; k < m.nt; k++) {
    double n[3];
    area += tri_normal(&m, k, n);
    const esf_wall_elem *e = &w.e[k / 2];
    worst =
        fmax(worst, v3_norm((double[3]){n[0] - e->n[0], n[1] - e->n[1], n[2] - e->n[2]}));
    CHECK(m.group[k] == g && m.material[k] == 7, "triangle %zu: group %d material %d", k,
          m.group[k], m.material[k]);
    for (int j = 0; j < 3; j++)
      CHECK(m.tri[3 * k + j] >= 0 && (size_t)m.tri[3 * k + j] < m.np,
            "triangle %zu: point index %d", k, m.tri[3 * k + j]);
  }
  double want = 0.04 * 0.03 + 2 * 0.04 * 0.15 + 2 * 0.03 * 0.15;
  CHECK_NEAR(area, want, 1e-15, "box mesh area (m^2)");
  CHECK(worst < 1e-12, "triangle normals differ from the faces' by %.3g", worst);
  printf(
      "box: %zu points, %zu triangles, area %.6g m^2 (faces %.6g), normal error %.2g\n",
      m.np, m.nt, area, want, worst);

  /* a triangle, appended: storage grows and is reused */
  int g2;
  CHECK_OK(esf_walls_add_group(&w, "polygon", &g2, &err), err);
  esf_wall_elem tri;
  const double tv[3][3] = {{0, 0, 1}, {1, 0, 1}, {0, 2, 1}};
  CHECK_OK(esf_wall_polygon_init(&tri, 3, tv, 2, g2, &err), err);
  CHECK_OK(esf_walls_add_elem(&w, &tri, &err), err);
  CHECK_OK(esf_wall_mesh_build(&w, 0.0, NULL, NULL, &m, &err), err);
  CHECK(m.np == 23 && m.nt == 11, "box + triangle: %zu points, %zu triangles", m.np,
        m.nt);
  for (int j = 0; j < 3; j++)
    CHECK(memcmp(m.points + 3 * (20 + j), tv[j], sizeof tv[j]) == 0, "triangle vertex %d",
          j);
  CHECK(m.group[10] == g2 && m.material[10] == 2, "triangle group %d material %d",
        m.group[10], m.material[10]);
  esf_wall_mesh_release(&m);
  CHECK(m.points == NULL && m.np == 0, "release clears the mesh");
  esf_walls_release(&w);
}

/* Checks the plane patch in m (points 0..3) for plane e and sizing box lo..hi. */
static void check_patch(const esf_wall_mesh *m, const esf_wall_elem *e, const double *c,
                        double side, const char *what) {
  CHECK(m->np == 4 && m->nt == 2, "%s: %zu points, %zu triangles", what, m->np, m->nt);
  if (m->np != 4 || m->nt != 2) return;
  double area = 0;
  for (size_t k = 0; k < 2; k++) {
    double n[3];
    area += tri_normal(m, k, n);
    CHECK(v3_dot(n, e->n) > 1 - 1e-12, "%s: triangle %zu faces away from the normal",
          what, k);
  }
  CHECK_NEAR(area, side * side, 1e-12 * side * side, what);
  double mid[3] = {0, 0, 0};
  for (int j = 0; j < 4; j++) {
    double d[3];
    v3_sub(d, m->points + 3 * j, e->p);
    CHECK(fabs(v3_dot(d, e->n)) < 1e-12 * (1 + side), "%s: point %d off the plane", what,
          j);
    v3_axpy(mid, 0.25, m->points + 3 * j);
  }
  double dc[3];
  v3_sub(dc, mid, c);
  CHECK(v3_norm(dc) < 1e-12 * (1 + side), "%s: centre off by %.3g m", what, v3_norm(dc));
}

static void test_plane(void) {
  esf_walls w = {0};
  esf_error err = {0};
  int g;
  CHECK_OK(esf_walls_add_group(&w, "plane", &g, &err), err);
  esf_wall_elem pl;
  const double pt[3] = {0.1, -0.2, 0.05}, nrm[3] = {0.3, -0.2, 1.0};
  CHECK_OK(esf_wall_plane_init(&pl, pt, nrm, 1, g, &err), err);
  CHECK_OK(esf_walls_add_elem(&w, &pl, &err), err);
  const double lo[3] = {-0.02, 0.01, 0.2}, hi[3] = {0.03, 0.07, 0.26};
  esf_wall_mesh m = {0};
  CHECK_OK(esf_wall_mesh_build(&w, 0.0, lo, hi, &m, &err), err);
  double mid[3], d[3], c[3], diag[3];
  for (int q = 0; q < 3; q++) {
    mid[q] = 0.5 * (lo[q] + hi[q]);
    diag[q] = hi[q] - lo[q];
  }
  v3_sub(d, mid, pl.p);
  v3_copy(c, mid);
  v3_axpy(c, -v3_dot(d, pl.n), pl.n);
  double side = v3_norm(diag);
  check_patch(&m, &pl, c, side, "inclined plane patch");
  /* every corner of the box projects inside the square */
  double u[3], v[3];
  v3_sub(u, m.points + 3, m.points);
  v3_sub(v, m.points + 9, m.points);
  double worst = 1e300;
  for (int k = 0; k < 8; k++) {
    double corner[3] = {k & 1 ? hi[0] : lo[0], k & 2 ? hi[1] : lo[1],
                        k & 4 ? hi[2] : lo[2]};
    double r[3];
    v3_sub(r, corner, m.points);
    double a = v3_dot(r, u) / v3_norm2(u), b = v3_dot(r, v) / v3_norm2(v);
    worst = fmin(worst, fmin(fmin(a, 1 - a), fmin(b, 1 - b)));
  }
  CHECK(worst > 0, "a box corner projects outside the patch (margin %.3g)", worst);
  printf("plane: patch side %.6g m, smallest margin of a box corner %.3g of the side\n",
         side, worst);

  /* no box: the finite elements' box; none either: 1 m about the plane's point */
  CHECK_OK(esf_wall_mesh_build(&w, 0.0, NULL, NULL, &m, &err), err);
  check_patch(&m, &pl, pl.p, 1.0, "plane without a box");
  const double empty_lo[3] = {1, 1, 1}, empty_hi[3] = {0, 0, 0};
  CHECK_OK(esf_wall_mesh_build(&w, 0.0, empty_lo, empty_hi, &m, &err), err);
  check_patch(&m, &pl, pl.p, 1.0, "plane with an empty box");
  int g2;
  CHECK_OK(esf_walls_add_group(&w, "polygon", &g2, &err), err);
  esf_wall_elem sq;
  const double sv[4][3] = {{0, 0, 2}, {2, 0, 2}, {2, 2, 2}, {0, 2, 2}};
  CHECK_OK(esf_wall_polygon_init(&sq, 4, sv, 1, g2, &err), err);
  CHECK_OK(esf_walls_add_elem(&w, &sq, &err), err);
  CHECK_OK(esf_wall_mesh_build(&w, 0.0, NULL, NULL, &m, &err), err);
  CHECK(m.np == 8 && m.nt == 4, "plane + square: %zu points, %zu triangles", m.np, m.nt);
  /* the square's box is [0,2]^2 x {2}: centre (1,1,2), diagonal sqrt(8) */
  double sc[3] = {1, 1, 2}, dd[3];
  v3_sub(dd, sc, pl.p);
  v3_axpy(sc, -v3_dot(dd, pl.n), pl.n);
  esf_wall_mesh first = m;
  first.np = 4;
  first.nt = 2;
  check_patch(&first, &pl, sc, sqrt(8.0), "plane sized by the polygons");
  esf_wall_mesh_release(&m);
  esf_walls_release(&w);
}

/* A translating triangle beside a static one: the mesh at t = 0.25 s has the moving
 * one's points displaced by vel t and the static one's unchanged; the walls handed in
 * stay at their own time. */
static void test_moving(void) {
  esf_walls w = {0};
  esf_error err = {0};
  int gs, gm;
  esf_wall_elem a, b;
  const double va[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const double vb[3][3] = {{0, 0, 1}, {1, 0, 1}, {0, 1, 1}};
  CHECK_OK(esf_walls_add_group(&w, "static", &gs, &err), err);
  CHECK_OK(esf_walls_add_group(&w, "moving", &gm, &err), err);
  CHECK_OK(esf_wall_polygon_init(&a, 3, va, 0, gs, &err), err);
  CHECK_OK(esf_wall_polygon_init(&b, 3, vb, 0, gm, &err), err);
  CHECK_OK(esf_walls_add_elem(&w, &a, &err), err);
  CHECK_OK(esf_walls_add_elem(&w, &b, &err), err);
  w.g[gm].motion.kind = ESF_MOTION_TRANSLATE;
  v3_set(w.g[gm].motion.vel, 0.2, -0.1, 0.4);
  CHECK_OK(esf_walls_freeze(&w, 0.0, &err), err);
  esf_wall_mesh m = {0};
  CHECK_OK(esf_wall_mesh_build(&w, 0.25, NULL, NULL, &m, &err), err);
  double worst = 0;
  for (int j = 0; j < 3; j++)
    for (int q = 0; q < 3; q++) {
      worst = fmax(worst, fabs(m.points[3 * j + q] - va[j][q]));
      double want = vb[j][q] + 0.25 * w.g[gm].motion.vel[q];
      worst = fmax(worst, fabs(m.points[3 * (3 + j) + q] - want));
    }
  CHECK(worst < 1e-15, "moving wall mesh off by %.3g m", worst);
  CHECK(w.t == 0.0 && memcmp(w.e[1].v, vb, sizeof vb) == 0,
        "the walls handed in must stay at t = 0 (t = %g)", w.t);
  CHECK_OK(esf_wall_mesh_build(&w, 0.0, NULL, NULL, &m, &err), err);
  CHECK(memcmp(m.points + 9, vb, sizeof vb) == 0, "at t = 0 the moving wall is in place");
  printf("moving: mesh off the prescribed motion by %.2g m\n", worst);
  esf_wall_mesh_release(&m);
  esf_walls_release(&w);
}

int main(void) {
  test_box();
  test_plane();
  test_moving();
  return check_finish("test_wall_mesh");
}
