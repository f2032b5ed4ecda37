/* test_wall_index.c — generated walls and the wall element index (wall_gen.h,
 * wall_index.h).
 * Generators: a cylinder's facets are n quadrilaterals (2n triangles), its caps n
 * triangles each, facing as asked, with the exact lateral area of the inscribed prism;
 * a screw's flight has round(turns segments) x radial x 2 triangles whose vertices lie on
 * the helicoid z = start + pitch theta / (2 pi).
 * Index vs brute force: for random points about a screw and a cylinder (at rest, after a
 * rotation of the screw's group, and after a translation of the cylinder's), the query
 * reports every element whose nearest point lies within r (none missed), each once;
 * groups below ESF_WALL_INDEX_MIN and planes are always reported. The frame mesh
 * (wall_mesh.c) of the rotated screw is the rotated reference mesh. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bodies/wall_gen.h"
#include "bodies/wall_index.h"
#include "bodies/wall_mesh.h"
#include "check.h"
#include "util/vec3.h"

static void test_cylinder(void) {
  esf_walls w = {0};
  esf_error err = {0};
  int g;
  CHECK_OK(esf_walls_add_group(&w, "cyl", &g, &err), err);
  esf_cylinder_spec c = {.base = {1, 2, 3},
                         .axis = {0, 0, 1},
                         .radius = 0.5,
                         .height = 2,
                         .segments = 24,
                         .cap_bottom = 1,
                         .inward = 1,
                         .quads = 1};
  CHECK_OK(esf_wall_gen_cylinder(&c, 0, g, &w, &err), err);
  CHECK(w.n == 48, "cylinder with one cap: %zu elements", w.n);
  double area = 0;
  for (size_t k = 0; k < w.n; k++) {
    const esf_wall_elem *e = &w.e[k];
    if (e->nv != 4) continue;
    double a[3], b[3], n[3], r[3];
    v3_sub(a, e->v[1], e->v[0]);
    v3_sub(b, e->v[3], e->v[0]);
    v3_cross(n, a, b);
    area += v3_norm(n);
    v3_sub(r, e->p, c.base);
    r[2] = 0;
    CHECK(v3_dot(r, e->n) < 0, "inward facet %zu faces outward", k);
  }
  CHECK_NEAR(area, 2 * 24 * 0.5 * sin(ESF_PI / 24) * 2, 1e-12,
             "prism lateral area (m^2)");
  esf_walls_release(&w);
  CHECK_OK(esf_walls_add_group(&w, "cyl", &g, &err), err);
  c.quads = 0;
  c.cap_top = 1;
  c.inward = 0;
  CHECK_OK(esf_wall_gen_cylinder(&c, 0, g, &w, &err), err);
  CHECK(w.n == 96, "triangulated, both caps: %zu elements", w.n);
  for (size_t k = 0; k < w.n; k++) {
    double r[3];
    v3_sub(r, w.e[k].p, c.base);
    r[2] -= 1; /* from the cylinder's centre */
    CHECK(v3_dot(r, w.e[k].n) > 0, "outward element %zu faces inward", k);
  }
  c.segments = 2;
  CHECK(esf_wall_gen_cylinder(&c, 0, g, &w, &err) == ESF_EINPUT &&
            strstr(err.msg, "at least 3 segments"),
        "2 segments: %s", err.msg);
  esf_walls_release(&w);
}

static const esf_screw_spec screw = {.base = {0.15, 0.15, 0},
                                     .axis = {0, 0, 1},
                                     .shaft_radius = 0.03,
                                     .radius = 0.1,
                                     .pitch = 0.1,
                                     .turns = 2.5,
                                     .start = 0.02,
                                     .length = 0.3,
                                     .segments = 36,
                                     .radial = 2,
                                     .quads = 1,
                                     .cap_top = 1};

static void test_screw(void) {
  esf_walls w = {0};
  esf_error err = {0};
  int g;
  CHECK_OK(esf_walls_add_group(&w, "screw", &g, &err), err);
  CHECK_OK(esf_wall_gen_screw(&screw, 0, g, &w, &err), err);
  size_t shaft = 36 + 36, flight = 90 * 2 * 2;
  CHECK(w.n == shaft + flight, "screw: %zu elements, want %zu", w.n, shaft + flight);
  double worst = 0;
  for (size_t k = shaft; k < w.n; k++)
    for (int j = 0; j < 3; j++) {
      const double *v = w.e[k].v[j];
      /* theta from u = +y toward v = -x (wall_gen.c's frame for the z axis) */
      double th = atan2(-(v[0] - 0.15), v[1] - 0.15), z = v[2] - screw.start;
      /* z = pitch (theta + 2 pi m) / (2 pi) for some whole m */
      double m = z / screw.pitch - th / (2 * ESF_PI);
      worst = fmax(worst, fabs(m - round(m)) * screw.pitch);
      double r = hypot(v[0] - 0.15, v[1] - 0.15);
      CHECK(r > 0.03 - 1e-12 && r < 0.1 + 1e-12, "flight vertex at radius %g", r);
    }
  CHECK(worst < 1e-12, "flight vertices off the helicoid by %.3g m", worst);
  esf_screw_spec bad = screw;
  bad.length = 0.2;
  CHECK(esf_wall_gen_screw(&bad, 0, g, &w, &err) == ESF_EINPUT &&
            strstr(err.msg, "must lie on the shaft"),
        "short shaft: %s", err.msg);
  esf_walls_release(&w);
}

/* every element within r of x (brute force) is in the query's answer, each once; every
 * element flagged in always[] is in it whatever its distance */
static void compare(esf_wall_index *ix, const esf_walls *w, const unsigned char *always,
                    const double x[3], double r, long *found, long *reported,
                    long *missed, long *dup, long *always_missed) {
  const uint32_t *c;
  size_t n;
  static uint32_t scratch[4096];
  CHECK(esf_wall_index_scratch(ix) <= 4096, "scratch of %zu entries",
        esf_wall_index_scratch(ix));
  esf_wall_index_query(ix, w, x, r, scratch, &c, &n);
  static unsigned char seen[4096];
  memset(seen, 0, w->n);
  for (size_t k = 0; k < n; k++) {
    if (seen[c[k]]) (*dup)++;
    seen[c[k]] = 1;
  }
  *reported += (long)n;
  for (size_t e = 0; e < w->n; e++) {
    if (always[e] && !seen[e]) (*always_missed)++;
    esf_wall_hit h;
    esf_wall_nearest(&w->e[e], x, &h);
    if (fabs(h.dist) >= r) continue;
    (*found)++;
    if (!seen[e]) (*missed)++;
  }
}

static void test_index(void) {
  esf_walls w = {0};
  esf_error err = {0};
  int gs, gc, gp, gb;
  CHECK_OK(esf_walls_add_group(&w, "screw", &gs, &err), err);
  CHECK_OK(esf_wall_gen_screw(&screw, 0, gs, &w, &err), err);
  CHECK_OK(esf_walls_add_group(&w, "cyl", &gc, &err), err);
  esf_cylinder_spec cy = {.base = {0.15, 0.15, 0},
                          .axis = {0, 0, 1},
                          .radius = 0.13,
                          .height = 0.3,
                          .segments = 40,
                          .inward = 1,
                          .quads = 0};
  CHECK_OK(esf_wall_gen_cylinder(&cy, 0, gc, &w, &err), err);
  CHECK_OK(esf_walls_add_group(&w, "plane", &gp, &err), err);
  esf_wall_elem pl, box[6];
  CHECK_OK(
      esf_wall_plane_init(&pl, (double[3]){0, 0, 0}, (double[3]){0, 0, 1}, 0, gp, &err),
      err);
  CHECK_OK(esf_walls_add_elem(&w, &pl, &err), err);
  CHECK_OK(esf_walls_add_group(&w, "box", &gb, &err), err);
  int nb = 0;
  CHECK_OK(esf_wall_box((double[3]){0, 0, 0}, (double[3]){0.3, 0.3, 0.4}, 32, 0, gb, box,
                        &nb, &err),
           err);
  for (int k = 0; k < nb; k++) CHECK_OK(esf_walls_add_elem(&w, &box[k], &err), err);
  w.g[gs].motion = (esf_wall_motion){.kind = ESF_MOTION_ROTATE,
                                     .axis = {0, 0, -1},
                                     .pivot = {0.15, 0.15, 0},
                                     .rate = 10};
  w.g[gc].motion =
      (esf_wall_motion){.kind = ESF_MOTION_TRANSLATE, .vel = {0.01, 0, 0.02}};
  CHECK_OK(esf_walls_freeze(&w, 0, &err), err);
  esf_wall_index *ix = NULL;
  CHECK_OK(esf_wall_index_sync(&ix, &w, &err), err);
  CHECK(esf_wall_index_grids(ix) == 2, "%d groups indexed, want 2 (screw, cylinder)",
        esf_wall_index_grids(ix));
  /* the elements of groups with a plane or fewer than ESF_WALL_INDEX_MIN polygons */
  static unsigned char always[4096];
  size_t npoly[8] = {0}, nalways = 0;
  int has_plane[8] = {0};
  CHECK(w.ngroups <= 8 && w.n <= 4096, "test arrays too small");
  for (size_t k = 0; k < w.n; k++) {
    if (w.e[k].kind == ESF_WALL_PLANE)
      has_plane[w.e[k].group] = 1;
    else
      npoly[w.e[k].group]++;
  }
  for (size_t k = 0; k < w.n; k++) {
    int g = w.e[k].group;
    always[k] = has_plane[g] || npoly[g] < ESF_WALL_INDEX_MIN;
    nalways += always[k];
  }
  CHECK(nalways == 1 + (size_t)nb,
        "%zu elements always reported, want the plane and the "
        "box's %d",
        nalways, nb);
  srand(11);
  const double times[3] = {0, 0.137, 1.9};
  for (int ti = 0; ti < 3; ti++) {
    esf_walls_set_time(&w, times[ti]);
    esf_wall_index *same = ix;
    CHECK_OK(esf_wall_index_sync(&ix, &w, &err), err);
    CHECK(ix == same, "moving the walls rebuilt the index");
    long found = 0, reported = 0, missed = 0, dup = 0, always_missed = 0;
    for (int k = 0; k < 4000; k++) {
      double x[3] = {-0.02 + 0.34 * rand() / (double)RAND_MAX,
                     -0.02 + 0.34 * rand() / (double)RAND_MAX,
                     -0.02 + 0.4 * rand() / (double)RAND_MAX};
      double r = 0.005 + 0.03 * rand() / (double)RAND_MAX;
      compare(ix, &w, always, x, r, &found, &reported, &missed, &dup, &always_missed);
    }
    CHECK(always_missed == 0,
          "t = %g s: %ld omissions of plane or small-group elements (always reported)",
          times[ti], always_missed);
    CHECK(missed == 0 && dup == 0,
          "t = %g s: %ld of %ld elements within reach missed, "
          "%ld reported twice",
          times[ti], missed, found, dup);
    CHECK(found > 10000, "t = %g s: only %ld element hits: the test tests little",
          times[ti], found);
    printf("index at t = %g s: %ld elements within reach, %ld reported (of %zu x 4000 "
           "brute force), none missed\n",
           times[ti], found, reported, w.n);
  }
  /* the frame mesh of the rotated screw: its reference vertices turned by rate t */
  esf_wall_mesh m = {0};
  CHECK_OK(esf_wall_mesh_build(&w, 0.5, NULL, NULL, &m, &err), err);
  double worst = 0, a = -10 * 0.5;
  for (size_t k = 0, pt = 0; k < w.n; k++) {
    int nv = w.e[k].kind == ESF_WALL_PLANE ? 4 : w.e[k].nv;
    if (w.e[k].group == gs)
      for (int j = 0; j < nv; j++) {
        const double *v0 = w.e0[k].v[j], *v = m.points + 3 * (pt + j);
        double dx = v0[0] - 0.15, dy = v0[1] - 0.15;
        double want[3] = {0.15 + cos(-a) * dx + sin(-a) * dy,
                          0.15 - sin(-a) * dx + cos(-a) * dy, v0[2]};
        double d[3];
        v3_sub(d, v, want);
        worst = fmax(worst, v3_norm(d));
      }
    pt += (size_t)nv;
  }
  CHECK(worst < 1e-12, "frame mesh of the screw at 0.5 s off by %.3g m", worst);
  esf_wall_mesh_release(&m);
  esf_wall_index_free(&ix);
  CHECK(ix == NULL, "free sets NULL");
  esf_walls_release(&w);
}

int main(void) {
  test_cylinder();
  test_screw();
  test_index();
  return check_finish("wall_index");
}
