/* test_fused_loads.c — the fused step takes servo walls, a drilling event, the fluid
 * force (radial flow, porosity from a grid), adhesive bonds that break and the energy
 * ledger, and gives the general path's results bit for bit on 1 and 2 threads (one
 * range each; the bonded block of scenes/block_impact-quick.yaml on 1-3 threads):
 * particle state, contact histories, the ledger (memcmp of esf_ledger), the servo lid's
 * displacement, velocity and measured stress, the fluid forces of the last step, and
 * the bonds broken (their energy is in the ledger). The
 * servo walls' contact sums and the ledger go through per-block sums (loads/servo.h,
 * core/ledger.h), so the threads' ranges do not change them; the fluid force is per
 * particle. */
#include <stdlib.h>

#include "fused/fused.h"
#include "loads/drag.h"
#include "loads/events.h"
#include "simtest.h"

/* 200 spheres of 1.5-2 mm in a 4 cm box under a servo lid (2e4 Pa) that presses on the
 * pack by 0.05 s; a well drilled at 0.06 s, the fluid on from 0.07 s; three blocks of
 * the ledger's 64 particles, so two threads get two ranges. */
static const char *const scene =
    "name: fusedloads\n"
    "gravity: [0, 0, -9.81]\n"
    "materials: {m: {density: 2500, kn: 1.0e5, restitution: 0.2, friction: 0.3}}\n"
    "particles:\n"
    "  - {generate: random, region: {min: [0, 0, 0], max: [0.04, 0.04, 0.028]}, count: "
    "200, radius: {uniform: [0.0015, 0.002]}, material: m, seed: 11}\n"
    "walls:\n"
    "  - {box: {min: [0, 0, 0], max: [0.04, 0.04, 0.2]}, open: [top], material: m}\n"
    "  - polygon: [[0, 0, 0.03], [0.04, 0, 0.03], [0.04, 0.04, 0.03], [0, 0.04, 0.03]]\n"
    "    material: m\n"
    "    motion: {servo: {stress: 2.0e4, direction: [0, 0, -1], max_speed: 0.5}}\n"
    "events: [{at: 0.06, delete: {cylinder: {center: [0.02, 0.02, 0.01], axis: [0, 1, "
    "0], radius: 0.006}}}]\n"
    "fluid:\n"
    "  start: 0.07\n"
    "  porosity: {cell: 0.02}\n"
    "  viscosity: 1.0e-3\n"
    "  density: 1000\n"
    "  permeability: 1.0e-10\n"
    "  radial: {center: [0.02, 0.02, 0.01], axis: [0, 1, 0], well_radius: 0.006, "
    "drainage_radius: 1, pressure_drop: 3.0e5}\n"
    "integrator: {method: leapfrog, dt: auto, frac: 0.1}\n"
    "run: {duration: 0.09}\n"
    "output: {energy_every: 1.0e-3}\n";

typedef struct result {
  size_t n, m;
  double *y, *fluid;
  esf_contact_hist *h;
  esf_ledger led;
  double lid[7]; /* servo lid: displacement (3), velocity (3), measured stress */
  int fused;
  long removed, broken;
} result;

static const char *root_; /* the source tree: block_impact-quick, or NULL: the box */

static int run(int threads, int fused, result *r) {
  memset(r, 0, sizeof *r);
  const char *sets[] = {fused ? "integrator.fused=true" : "integrator.fused=false"};
  simtest T;
  int rc = root_ ? simtest_open_scene(&T, root_, "block_impact-quick", sets, 1)
                 : simtest_open(&T, scene, sets, 1);
  if (rc) return rc;
  const double t_end = root_ ? T.s.cfg.duration : 0.09;
  T.s.cfg.threads = threads;
  T.s.cfg.range_work = 1; /* one range per thread */
  r->fused = fused && esf_fused_eligible(&T.s);
  while (!rc && T.s.t < t_end - 0.5 * T.s.dt) rc = simtest_step(&T);
  if (!rc) {
    CHECK_OK(esf_sim_forces_sync(&T.s, &T.err), T.err);
    r->n = T.s.p.n;
    r->m = T.s.nb.pp.n;
    r->y = malloc(9 * r->n * sizeof(double));
    r->h = malloc((r->m ? r->m : 1) * sizeof *r->h);
    r->fluid = malloc(3 * r->n * sizeof(double));
    memcpy(r->y, T.s.p.y, 9 * r->n * sizeof(double));
    memcpy(r->h, T.s.nb.pp.h, r->m * sizeof *r->h);
    if (T.s.drag)
      memcpy(r->fluid, T.s.drag->f, 3 * r->n * sizeof(double));
    else
      memset(r->fluid, 0, 3 * r->n * sizeof(double));
    r->broken = T.s.bonds.broken;
    r->led = T.s.led;
    r->removed = T.s.removed;
    for (int g = 0; g < T.s.walls.ngroups; g++) {
      const esf_wall_group *G = &T.s.walls.g[g];
      if (G->motion.kind != ESF_MOTION_SERVO) continue;
      memcpy(r->lid, G->disp, 3 * sizeof(double));
      memcpy(r->lid + 3, G->vel, 3 * sizeof(double));
      r->lid[6] = G->motion.sigma;
    }
  }
  simtest_close(&T);
  return rc;
}

static void same(const result *a, const result *g, const char *what) {
  CHECK(a->n == g->n && a->m == g->m && a->removed == g->removed &&
            a->broken == g->broken,
        "%s: sizes, bonds broken (%ld against %ld)", what, a->broken, g->broken);
  if (a->n != g->n || a->m != g->m) return;
  CHECK(memcmp(a->y, g->y, 9 * g->n * sizeof(double)) == 0, "%s: state differs", what);
  CHECK(memcmp(a->h, g->h, g->m * sizeof *g->h) == 0, "%s: histories differ", what);
  CHECK(memcmp(a->fluid, g->fluid, 3 * g->n * sizeof(double)) == 0,
        "%s: fluid forces differ", what);
  CHECK(memcmp(&a->led, &g->led, sizeof a->led) == 0, "%s: ledger differs", what);
  CHECK(memcmp(a->lid, g->lid, sizeof a->lid) == 0,
        "%s: servo lid differs (stress %.17g against %.17g)", what, a->lid[6], g->lid[6]);
}

static void release(result *r) {
  free(r->y);
  free(r->h);
  free(r->fluid);
}

/* The fused step on 1 .. tmax threads against the general path's g. */
static void against(const result *g, const char *label, int tmax) {
  result f;
  for (int t = 1; t <= tmax; t++) {
    char what[64];
    snprintf(what, sizeof what, "%s, fused, %d threads", label, t);
    CHECK(run(t, 1, &f) == 0, "%s", what);
    if (check_failures_) break;
#ifndef ESF_MINIMAL
    CHECK(f.fused, "%s: the fused step must run it", what);
#endif
    same(&f, g, what);
    release(&f);
  }
}

/* The bonded block of the source tree's block_impact-quick: the general path against
 * the fused step on 1, 2 and 3 threads. */
static void bonded(const char *root) {
  result g;
  root_ = root;
  if (run(1, 0, &g) == 0) {
    printf("bonded block: %zu particles, %ld bonds broken holding %.6g J, total error "
           "%.3g J of %.3g J dissipated\n",
           g.n, g.broken, g.led.d_bonds, esf_ledger_total_error(&g.led),
           esf_ledger_dissipated(&g.led));
    CHECK(g.broken > 0 && g.led.d_bonds > 0, "bonds break");
    against(&g, "bonded block", 3);
    release(&g);
  } else {
    CHECK(0, "bonded block: general path");
  }
  root_ = NULL;
}

int main(int argc, char **argv) {
  result g;
  CHECK(run(1, 0, &g) == 0, "general path");
  if (check_failures_) return check_finish("fused_loads");
  double fl = 0;
  for (size_t i = 0; i < 3 * g.n; i++) fl = fmax(fl, fabs(g.fluid[i]));
  printf("general path: %zu particles (%ld drilled), lid stress %.6g Pa, velocity %.3g "
         "m/s, largest fluid force %.3g N, fluid work %.6g J, total error %.3g J of "
         "%.3g J dissipated\n",
         g.n, g.removed, g.lid[6], g.lid[5], fl, g.led.w_fluid,
         esf_ledger_total_error(&g.led), esf_ledger_dissipated(&g.led));
  CHECK(g.removed > 0 && g.lid[6] > 0 && fl > 0 && g.led.w_fluid != 0,
        "the drilling, the lid and the fluid all act");
  against(&g, "loads", 2);
  release(&g);
  if (argc > 1) bonded(argv[1]);
  return check_finish("fused_loads");
}
