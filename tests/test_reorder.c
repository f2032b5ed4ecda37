/* test_reorder.c — renumbering the particles along cells at list rebuilds (reorder.c)
 * changes nothing but rounding: the same run with search.reorder on and off agrees,
 * particle by particle (matched by id), and every touching contact's history agrees
 * pair by pair, with the sign turned where the pair's order was turned round (A and B
 * swapped: xi and n change sign).
 *
 * The scene is test_threads.c's: 400 polydisperse spheres of two materials, created in
 * random order (so the first rebuild moves nearly all of them), thrown onto an
 * oscillating floor with friction, dashpots and both damping forms; 1500 steps with
 * about 20 rebuilds. Rounding differs between the two orders (a particle's forces are
 * summed in another order) and collisions amplify it, as between the fused and the
 * general path: the bounds are the same, 1e-9 of the mean radius for positions and
 * 1e-7 of the largest speed for velocities; a history carried to the wrong pair or
 * with the wrong sign would differ by the size of the history itself. Both the fused
 * step and the general path are run. */
#include <stdlib.h>

#include "simtest.h"

static const char *const scene =
    "name: reorder\n"
    "materials:\n"
    "  glass: {density: 2500, kn: 2.0e4, restitution: 0.4, tangential_restitution: 0.6,"
    " friction: 0.4}\n"
    "  steel: {density: 7800, kn: 4.0e4, restitution: 0.7, friction: 0.2}\n"
    "particles:\n"
    "  - generate: random\n"
    "    region: {min: [0.001, 0.001, 0.0012], max: [0.039, 0.039, 0.02]}\n"
    "    count: 400\n"
    "    radius: {uniform: [0.0008, 0.0024]}\n"
    "    material: {mix: {glass: 0.6, steel: 0.4}}\n"
    "    seed: 11\n"
    "    velocity: [0.05, -0.03, -0.6]\n"
    "walls:\n"
    "  - {box: {min: [0, 0, 0], max: [0.04, 0.04, 0.06]}, open: [top], material: steel}\n"
    "  - {polygon: [[0, 0, 0.001], [0.04, 0, 0.001], [0.04, 0.04, 0.001],"
    " [0, 0.04, 0.001]], material: glass,\n"
    "     motion: {oscillate: {direction: [0, 0, 1], frequency: 50, amplitude: "
    "0.0005}}}\n"
    "damping: {global: {translation: 2.0, rotation: 1.0},"
    " local: {coefficient: 0.05, form: component}}\n"
    "integrator: {method: leapfrog, dt: auto, frac: 0.3}\n"
    "run: {steps: 1500}\n"
    "output: {energy_every: 0}\n";

enum { STEPS = 1500 };

/* The state at the end, indexed by id (ids are 0 .. n-1 here). */
typedef struct result {
  size_t n, m;
  double *y;        /* 9 n: x | v | w by id */
  int64_t *ida;     /* m: the ids of each touching contact's A and B */
  int64_t *idb;     /*    (in the run's own order, A < B by number) */
  double *xi;       /* 3 m */
  size_t out_of_id; /* particles not at the position of their id's rank */
  long builds;
} result;

static int run(int reorder, int fused, result *R) {
  char s_re[64], s_fu[64];
  snprintf(s_re, sizeof s_re, "search.reorder=%s", reorder ? "true" : "false");
  snprintf(s_fu, sizeof s_fu, "integrator.fused=%s", fused ? "true" : "false");
  const char *sets[] = {s_re, s_fu};
  simtest T;
  int rc = simtest_open(&T, scene, sets, 2);
  if (rc) return rc;
  for (int k = 0; k < STEPS && !rc; k++) rc = simtest_step(&T);
  const esf_particles *p = &T.s.p;
  const esf_candidates *c = &T.s.nb.pp;
  memset(R, 0, sizeof *R);
  if (!rc) {
    R->n = p->n;
    R->y = malloc(9 * p->n * sizeof(double));
    R->ida = malloc((c->n + 1) * sizeof *R->ida);
    R->idb = malloc((c->n + 1) * sizeof *R->idb);
    R->xi = malloc(3 * (c->n + 1) * sizeof(double));
    for (size_t i = 0; i < p->n; i++) {
      const size_t d = (size_t)p->id[i];
      if (d >= p->n) return 1; /* ids are 0 .. n-1 in this scene */
      R->out_of_id += d != i;
      for (int s = 0; s < 3; s++)
        memcpy(R->y + 3 * (s * p->n + d), p->y + 3 * (s * p->n + i), 3 * sizeof(double));
    }
    for (size_t k = 0; k < c->n; k++) {
      if (!c->touch[k]) continue;
      R->ida[R->m] = p->id[c->a[k]];
      R->idb[R->m] = p->id[c->b[k]];
      memcpy(R->xi + 3 * R->m, c->h[k].xi, 3 * sizeof(double));
      R->m++;
    }
    R->builds = T.s.nb.builds;
  }
  simtest_close(&T);
  return rc;
}

static void release(result *R) {
  free(R->y);
  free(R->ida);
  free(R->idb);
  free(R->xi);
}

static void compare(int fused) {
  const char *path = fused ? "fused" : "general";
  result on, off;
  CHECK(run(1, fused, &on) == 0, "%s: run with reordering", path);
  CHECK(run(0, fused, &off) == 0, "%s: run without reordering", path);
  if (check_failures_) return;
  CHECK(off.out_of_id == 0, "%s: without reordering the particles keep their order",
        path);
  CHECK(on.out_of_id > on.n / 2, "%s: reordering moved %zu of %zu particles", path,
        on.out_of_id, on.n);
  CHECK(on.builds > 5, "%s: lists rebuilt %ld times", path, on.builds);
  CHECK(on.n == off.n, "%s: same particle count", path);
  double dx = 0, dv = 0, vmax = 0, rmean = 0.0016;
  for (size_t i = 0; i < 3 * on.n && on.n == off.n; i++) {
    dx = fmax(dx, fabs(on.y[i] - off.y[i]));
    dv = fmax(dv, fabs(on.y[3 * on.n + i] - off.y[3 * on.n + i]));
    vmax = fmax(vmax, fabs(off.y[3 * on.n + i]));
  }
  /* history: every touching contact of one run is a touching contact of the other */
  size_t matched = 0, turned = 0;
  double dxi = 0, ximax = 0;
  for (size_t k = 0; k < off.m; k++) {
    size_t j = 0;
    while (j < on.m && !((on.ida[j] == off.ida[k] && on.idb[j] == off.idb[k]) ||
                         (on.ida[j] == off.idb[k] && on.idb[j] == off.ida[k])))
      j++;
    if (j == on.m) continue;
    matched++;
    const double sg = on.ida[j] == off.ida[k] ? 1.0 : -1.0;
    turned += sg < 0;
    for (int q = 0; q < 3; q++) {
      dxi = fmax(dxi, fabs(sg * on.xi[3 * j + q] - off.xi[3 * k + q]));
      ximax = fmax(ximax, fabs(off.xi[3 * k + q]));
    }
  }
  printf("%s: %zu of %zu particles renumbered, %ld builds; max |dx| = %.3g radii, "
         "max |dv| = %.3g of %.3g m/s; %zu of %zu touching contacts matched (%zu turned "
         "round), max |dxi| = %.3g of %.3g m\n",
         path, on.out_of_id, on.n, on.builds, dx / rmean, dv, vmax, matched, off.m,
         turned, dxi, ximax);
  CHECK(dx <= 1e-9 * rmean, "%s: positions differ by %.3g m", path, dx);
  CHECK(dv <= 1e-7 * vmax, "%s: velocities differ by %.3g m/s", path, dv);
  CHECK(matched == off.m && on.m == off.m,
        "%s: touching contacts: %zu and %zu, %zu shared", path, on.m, off.m, matched);
  CHECK(turned > 0, "%s: some pairs turned round (%zu)", path, turned);
  CHECK(ximax > 0 && dxi <= 1e-7 * ximax, "%s: histories differ by %.3g m (largest %.3g)",
        path, dxi, ximax);
  release(&on);
  release(&off);
}

int main(void) {
  compare(1);
  compare(0);
  return check_finish("reorder");
}
