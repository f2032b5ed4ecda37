/* test_stl.c — STL walls: ASCII and binary files written here read back exactly (a
 * binary file whose header begins with "solid" is still binary); every kind of bad file
 * (zero-area and sliver triangles, non-finite vertices, four vertices in a loop, a
 * truncated binary, a wrong count) is an ESF_EINPUT error naming the file and the line
 * (ASCII) or the triangle (binary); a box made of 12 STL triangles gives the same
 * nearest distance as the box's 6 quadrilaterals and as a dense sampling of its surface
 * (brute force); a sphere resting on a triangulated floor (over vertices shared by eight
 * and by four triangles, over a shared edge, inside a face) rests at the plane's height
 * r - m g / kn, without drifting sideways. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "bodies/wall_geom.h"
#include "check.h"
#include "formats/stl.h"
#include "simtest.h"
#include "util/vec3.h"

static char dir[64];

static const char *path_of(const char *name) {
  static char p[256];
  snprintf(p, sizeof p, "%s/%s", dir, name);
  return p;
}

static void write_text(const char *name, const char *text) {
  FILE *f = fopen(path_of(name), "w");
  fputs(text, f);
  fclose(f);
}

/* binary STL of nt triangles (9 floats each); header text; count written as given */
static void write_binary(const char *name, const char *header, const float *v, size_t nt,
                         uint32_t count, size_t cut) {
  unsigned char h[84] = {0};
  memcpy(h, header, strlen(header));
  for (int k = 0; k < 4; k++) h[80 + k] = (unsigned char)(count >> (8 * k));
  FILE *f = fopen(path_of(name), "wb");
  fwrite(h, 1, 84, f);
  for (size_t t = 0; t < nt; t++) {
    unsigned char r[50] = {0};
    for (int k = 0; k < 9; k++) {
      uint32_t u;
      memcpy(&u, &v[9 * t + k], 4);
      for (int b = 0; b < 4; b++) r[12 + 4 * k + b] = (unsigned char)(u >> (8 * b));
    }
    fwrite(r, 1, 50, f);
  }
  fclose(f);
  if (cut) truncate(path_of(name), (off_t)(84 + 50 * nt - cut));
}

static const char *tet_ascii =
    "solid tet\n"
    "  facet normal 0 0 -1\n"
    "    outer loop\n"
    "      vertex 0 0 0\n"
    "      vertex 0 1 0\n"
    "      vertex 1 0 0\n"
    "    endloop\n"
    "  endfacet\n"
    "  facet normal 0 -1 0\n"
    "    outer loop\n"
    "      vertex 0 0 0\n      vertex 1 0 0\n      vertex 0 0 1.5e-1\n"
    "    endloop\n"
    "  endfacet\n"
    "  FACET NORMAL 0 0 0\n    OUTER LOOP\n"
    "      vertex 0 0 0\n      vertex 0 0 0.15\n      vertex 0 1 0\n"
    "    ENDLOOP\n  ENDFACET\n"
    "endsolid tet\n"
    "solid second\n"
    "  facet normal 1 1 1\n    outer loop\n"
    "      vertex 1 0 0\n      vertex 0 1 0\n      vertex 0 0 0.15\n"
    "    endloop\n  endfacet\n"
    "endsolid\n";

static void test_round_trip(void) {
  esf_error err = {0};
  esf_stl s;
  write_text("tet.stl", tet_ascii);
  CHECK_OK(esf_stl_read(path_of("tet.stl"), &s, &err), err);
  CHECK(s.n == 4 && !s.binary, "ASCII: %zu triangles, binary %d", s.n, s.binary);
  const double want[4][3][3] = {{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}},
                                {{0, 0, 0}, {1, 0, 0}, {0, 0, 0.15}},
                                {{0, 0, 0}, {0, 0, 0.15}, {0, 1, 0}},
                                {{1, 0, 0}, {0, 1, 0}, {0, 0, 0.15}}};
  const long lines[4] = {2, 9, 16, 25};
  for (size_t t = 0; t < s.n && t < 4; t++) {
    CHECK(memcmp(s.v[t], want[t], sizeof want[t]) == 0, "ASCII triangle %zu differs", t);
    CHECK(s.line[t] == lines[t], "ASCII triangle %zu at line %ld, want %ld", t, s.line[t],
          lines[t]);
  }
  esf_stl_release(&s);

  /* binary, header starting with "solid": floats read back bit for bit */
  float v[2 * 9] = {0,    0,    0,    1,     0,     0,     0,    1,     0,
                    0.1f, 0.2f, 0.3f, -1.5f, 2.25f, 1e-3f, 3e4f, -7.0f, 0.5f};
  write_binary("bin.stl", "solid but binary", v, 2, 2, 0);
  CHECK_OK(esf_stl_read(path_of("bin.stl"), &s, &err), err);
  CHECK(s.n == 2 && s.binary == 1, "binary: %zu triangles, binary %d", s.n, s.binary);
  for (size_t t = 0; t < s.n; t++)
    for (int k = 0; k < 9; k++)
      CHECK(s.v[t][k / 3][k % 3] == (double)v[9 * t + k], "binary t%zu c%d: %g vs %g", t,
            k, s.v[t][k / 3][k % 3], (double)v[9 * t + k]);
  esf_stl_release(&s);
  /* an empty binary file (0 triangles) is valid */
  write_binary("empty.stl", "", v, 0, 0, 0);
  CHECK_OK(esf_stl_read(path_of("empty.stl"), &s, &err), err);
  CHECK(s.n == 0 && s.binary, "empty binary: %zu triangles", s.n);
  esf_stl_release(&s);
}

/* reading name fails with ESF_EINPUT and a message containing want */
static void expect_error(const char *name, const char *want) {
  esf_error err = {0};
  esf_stl s;
  int rc = esf_stl_read(path_of(name), &s, &err);
  CHECK(rc == ESF_EINPUT && strstr(err.msg, want) && strstr(err.msg, path_of(name)),
        "%s: status %d, message '%s' (want '%s')", name, rc, err.msg, want);
  CHECK(s.n == 0 && s.v == NULL, "%s: a failed read leaves no triangles", name);
}

static void test_errors(void) {
  char text[4096];
  /* zero area: collinear vertices in the 2nd facet (its `facet` on line 9) */
  snprintf(text, sizeof text, "%s", tet_ascii);
  char *p = strstr(text, "vertex 0 0 1.5e-1");
  memcpy(p, "vertex 2 0 0     ", 17);
  write_text("collinear.stl", text);
  expect_error("collinear.stl", ":9: ASCII STL facet 2: degenerate triangle (zero or "
                                "near-zero area");
  /* a sliver: height 1e-12 over a 1 m edge */
  write_text("sliver.stl", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                           "vertex 1 0 0\nvertex 0.5 1e-12 0\nendloop\nendfacet\n"
                           "endsolid\n");
  expect_error("sliver.stl", ":2: ASCII STL facet 1: degenerate triangle");
  /* repeated vertex */
  write_text("repeat.stl", "solid s\n\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                           "vertex 0 0 0\nvertex 0 0 0\nendloop\nendfacet\nendsolid\n");
  expect_error("repeat.stl", ":3: ASCII STL facet 1: degenerate triangle (its three "
                             "vertices coincide");
  /* non-finite */
  write_text("nan.stl", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                        "vertex 1 0 nan\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n");
  expect_error("nan.stl", ":2: ASCII STL facet 1: vertex 2 has a non-finite coordinate");
  /* four vertices in a loop */
  write_text("four.stl", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                         "vertex 1 0 0\nvertex 0 1 0\nvertex 1 1 0\nendloop\nendfacet\n"
                         "endsolid\n");
  expect_error("four.stl", ":7: ASCII STL: expected 'endloop' after three vertices");
  /* missing endsolid, a bad number */
  write_text("open.stl", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                         "vertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n");
  expect_error("open.stl", "end of file inside solid 1");
  write_text("word.stl", "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                         "vertex 1 zero 0\n");
  expect_error("word.stl", ":5: ASCII STL: expected a number, got 'zero'");
  /* binary: degenerate triangle 2, non-finite triangle 1, truncated, wrong count */
  float v[2 * 9] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1, 1, 1, 2, 2, 2};
  write_binary("bdeg.stl", "solid x", v, 2, 2, 0);
  expect_error("bdeg.stl", "binary STL triangle 2 (of 2, byte offset 134): degenerate");
  float w[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  w[4] = INFINITY;
  write_binary("binf.stl", "x", w, 1, 1, 0);
  expect_error("binf.stl", "binary STL triangle 1 (of 1, byte offset 84): vertex 2 has a "
                           "non-finite");
  write_binary("btrunc.stl", "mesh", v, 2, 2, 7);
  expect_error("btrunc.stl", "binary STL of 177 bytes, but its header announces 2 "
                             "triangles = 184 bytes");
  write_binary("bcount.stl", "mesh", v, 2, 3, 0);
  expect_error("bcount.stl", "header announces 3 triangles = 234 bytes");
  write_binary("bsolid.stl", "solid trap", v, 2, 5, 0); /* "solid", NULs, wrong count */
  expect_error("bsolid.stl", "binary STL of 184 bytes, but its header announces 5");
  char junk[160];
  snprintf(junk, sizeof junk, "solid junk\n%0120d\n", 7); /* text, not a binary size */
  write_text("junk.stl", junk);
  expect_error("junk.stl", ":2: ASCII STL: expected 'facet' or 'endsolid', got '0000");
  write_text("short.stl", "hello");
  expect_error("short.stl", "not an STL file");
  esf_error err = {0};
  esf_stl s;
  CHECK(esf_stl_read(path_of("missing.stl"), &s, &err) == ESF_EIO, "missing file: %s",
        err.msg);
}

/* a box [0,a]x[0,b]x[0,c] as 12 ASCII triangles */
static void write_box_stl(const char *name, const double h[3]) {
  static const int face[6][4] = {{0, 2, 6, 4}, {1, 5, 7, 3}, {0, 4, 5, 1},
                                 {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 6, 7, 5}};
  FILE *f = fopen(path_of(name), "w");
  fprintf(f, "solid box\n");
  for (int q = 0; q < 6; q++)
    for (int t = 0; t < 2; t++) {
      int c[3] = {face[q][0], face[q][1 + t], face[q][2 + t]};
      fprintf(f, "facet normal 0 0 0\nouter loop\n");
      for (int k = 0; k < 3; k++)
        fprintf(f, "vertex %.17g %.17g %.17g\n", c[k] & 1 ? h[0] : 0, c[k] & 2 ? h[1] : 0,
                c[k] & 4 ? h[2] : 0);
      fprintf(f, "endloop\nendfacet\n");
    }
  fprintf(f, "endsolid box\n");
  fclose(f);
}

static double min_dist(const esf_wall_elem *e, int n, const double x[3]) {
  double best = INFINITY;
  for (int k = 0; k < n; k++) {
    esf_wall_hit h;
    esf_wall_nearest(&e[k], x, &h);
    best = fmin(best, fabs(h.dist));
  }
  return best;
}

static void test_nearest(void) {
  const double h[3] = {0.3, 0.2, 0.1};
  write_box_stl("box.stl", h);
  esf_error err = {0};
  esf_stl s;
  CHECK_OK(esf_stl_read(path_of("box.stl"), &s, &err), err);
  CHECK(s.n == 12, "box: %zu triangles", s.n);
  esf_wall_elem tri[12], quad[6];
  for (size_t t = 0; t < s.n && t < 12; t++)
    CHECK_OK(esf_wall_polygon_init(&tri[t], 3, (const double(*)[3])s.v[t], 0, 0, &err),
             err);
  int nq = 0;
  const double lo[3] = {0, 0, 0};
  CHECK_OK(esf_wall_box(lo, h, 0, 0, 0, quad, &nq, &err), err);
  /* brute force: the surface sampled on a grid of spacing d; the true distance is
     below the sampled one by at most d / sqrt(2) */
  const double d = 0.0025;
  double worst = 0, worst_s = 0;
  srand(5);
  for (int trial = 0; trial < 200; trial++) {
    double x[3];
    for (int q = 0; q < 3; q++) x[q] = -0.1 + (h[q] + 0.2) * rand() / (double)RAND_MAX;
    double dt = min_dist(tri, 12, x), dq = min_dist(quad, nq, x), ds = INFINITY;
    worst = fmax(worst, fabs(dt - dq));
    for (int q = 0; q < 3; q++) /* faces normal to q at 0 and h[q] */
      for (int side = 0; side < 2; side++) {
        int a = (q + 1) % 3, b = (q + 2) % 3;
        for (double u = 0; u <= h[a] + 1e-12; u += d)
          for (double v = 0; v <= h[b] + 1e-12; v += d) {
            double p[3];
            p[q] = side ? h[q] : 0;
            p[a] = u;
            p[b] = v;
            double r[3];
            v3_sub(r, p, x);
            ds = fmin(ds, v3_norm(r));
          }
      }
    CHECK(dt <= ds + 1e-12 && ds - dt <= d / sqrt(2.0) + 1e-12,
          "point %d: mesh distance %.6g, sampled %.6g", trial, dt, ds);
    worst_s = fmax(worst_s, ds - dt);
  }
  CHECK(worst < 1e-14, "12 triangles vs 6 quads: distances differ by %.3g m", worst);
  printf("nearest point: triangles vs quads %.2g m, vs sampling (d %.4g m) <= %.3g m\n",
         worst, d, worst_s);
  esf_stl_release(&s);
}

/* A floor of 2 x nx x nx triangles over [-L, L]^2 at z = 0, every square split along
 * alternating diagonals so that grid points are shared by 4 or 8 triangles. */
static void write_floor(const char *name, int nx, double L) {
  FILE *f = fopen(path_of(name), "w");
  fprintf(f, "solid floor\n");
  double s = 2 * L / nx;
  for (int i = 0; i < nx; i++)
    for (int j = 0; j < nx; j++) {
      double x0 = -L + i * s, y0 = -L + j * s, x1 = x0 + s, y1 = y0 + s;
      double t[2][3][2];
      if ((i + j) % 2 == 0) {
        double a[2][3][2] = {{{x0, y0}, {x1, y0}, {x1, y1}},
                             {{x0, y0}, {x1, y1}, {x0, y1}}};
        memcpy(t, a, sizeof t);
      } else {
        double a[2][3][2] = {{{x0, y0}, {x1, y0}, {x0, y1}},
                             {{x1, y0}, {x1, y1}, {x0, y1}}};
        memcpy(t, a, sizeof t);
      }
      for (int k = 0; k < 2; k++) {
        fprintf(f, "facet normal 0 0 1\nouter loop\n");
        for (int v = 0; v < 3; v++)
          fprintf(f, "vertex %.17g %.17g 0\n", t[k][v][0], t[k][v][1]);
        fprintf(f, "endloop\nendfacet\n");
      }
    }
  fprintf(f, "endsolid\n");
  fclose(f);
}

/* rest height of a sphere dropped at (x, y) on the given wall */
static double rest(const char *wall, double x, double y, double *drift) {
  char yaml[2048];
  snprintf(yaml, sizeof yaml,
           "name: rest\ngravity: [0, 0, -9.81]\n"
           "materials: {glass: {density: 2500, kn: 1.0e5, restitution: 0.1, "
           "friction: 0.5}}\n"
           "particles:\n  - {material: glass, radius: 0.01, position: [%.17g, %.17g, "
           "0.0101]}\n"
           "walls:\n  - {%s, material: glass}\n"
           "integrator: {dt: auto, frac: 0.1}\nrun: {duration: 1}\n"
           "output: {energy_every: 0}\n",
           x, y, wall);
  simtest T;
  if (simtest_open(&T, yaml, NULL, 0)) return NAN;
  double t_end = 0.15;
  while (T.s.t < t_end)
    if (simtest_step(&T)) break;
  double z = T.s.p.x[2];
  *drift = hypot(T.s.p.x[0] - x, T.s.p.x[1] - y);
  simtest_close(&T);
  return z;
}

static void test_rest(void) {
  write_floor("floor.stl", 8, 0.08);
  char mesh[512];
  snprintf(mesh, sizeof mesh, "mesh: {file: %s}", path_of("floor.stl"));
  double drift = 0;
  double zp = rest("plane: {point: [0, 0, 0], normal: [0, 0, 1]}", 0, 0, &drift);
  double m = 2500 * 4.0 / 3.0 * ESF_PI * 1e-6, want = 0.01 - m * 9.81 / 1e5;
  CHECK_NEAR(zp, want, 1e-3 * (0.01 - want), "rest height on the plane (m)");
  /* over a vertex shared by 8 triangles, over a vertex shared by 4, over a shared
     edge, inside a face */
  const double at[4][2] = {{0, 0}, {0.02, 0}, {0.01, 0.005}, {0.013, 0.004}};
  for (int k = 0; k < 4; k++) {
    double zm = rest(mesh, at[k][0], at[k][1], &drift);
    CHECK_NEAR(zm, zp, 1e-12, "rest height on the mesh vs the plane (m)");
    CHECK(drift < 1e-12, "sphere drifted %.3g m sideways on the mesh", drift);
    printf(
        "rest on the mesh at (%g, %g): z = %.12g m, plane %.12g m, r - mg/kn %.12g m\n",
        at[k][0], at[k][1], zm, zp, want);
  }
}

/* the scene's mesh key: a relative file beside the scene, scale, rotate, translate */
static void test_scene_mesh(void) {
  const double h[3] = {0.3, 0.2, 0.1};
  write_box_stl("part.stl", h);
  write_text("part.yaml",
             "name: part\nmaterials: {g: {density: 2500, kn: 1.0e5}}\n"
             "particles:\n  - {material: g, radius: 0.01, position: [5, 5, 5]}\n"
             "walls:\n  - {mesh: {file: part.stl, scale: 2, rotate: {axis: [0, 0, 1], "
             "degrees: 90}, translate: [1, 2, 3]}, material: g}\nrun: {steps: 1}\n");
  esf_sim s;
  memset(&s, 0, sizeof s);
  esf_error err = {0};
  esf_config_default(&s.cfg);
  int rc = esf_scene_load(path_of("part.yaml"), NULL, 0, &s, &err);
  CHECK_OK(rc, err);
  CHECK(s.walls.n == 12 && s.walls.ngroups == 1, "mesh wall: %zu elements, %d groups",
        s.walls.n, s.walls.ngroups);
  esf_stl f;
  CHECK_OK(esf_stl_read(path_of("part.stl"), &f, &err), err);
  double worst = 0;
  for (size_t t = 0; t < s.walls.n && t < f.n; t++)
    for (int k = 0; k < 3; k++) {
      const double *x = f.v[t][k], *y = s.walls.e[t].v[k];
      /* 2 x turned 90 degrees about z: (x, y, z) -> (-y, x, z), then translated */
      double want[3] = {-2 * x[1] + 1, 2 * x[0] + 2, 2 * x[2] + 3};
      for (int q = 0; q < 3; q++) worst = fmax(worst, fabs(y[q] - want[q]));
    }
  CHECK(worst < 1e-15, "mesh placement off by %.3g m", worst);
  esf_stl_release(&f);
  esf_sim_release(&s);
}

int main(void) {
  snprintf(dir, sizeof dir, "/tmp/esf_stlXXXXXX");
  if (!mkdtemp(dir)) return 1;
  test_round_trip();
  test_errors();
  test_nearest();
  test_rest();
  test_scene_mesh();
  char cmd[128];
  snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
  if (system(cmd)) fprintf(stderr, "could not remove %s\n", dir);
  return check_finish("stl");
}
