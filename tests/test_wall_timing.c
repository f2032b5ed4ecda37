/* test_wall_timing.c — wall motion in time (wall_motion.c, scene_motion.c, events.c):
 * 1. a tabulated displacement puts the wall at the table's positions at the table's
 *    times exactly (==), linear between them within 1e-15 m, at the segment's slope;
 *    a velocity table per axis integrates to the exact displacements; after its last
 *    row a displacement table stops and a velocity table moves on at its last row;
 * 2. start, stop: a translation, a rotation and an oscillation with a window, stepped
 *    by the leapfrog (dt = 2^-14 s), sit at the window's clamped time at every step
 *    and have zero velocity outside [start, stop); a sequence (rotation, then a
 *    translation) sums them;
 * 3. a plate driven by a displacement table lifts a resting sphere 2 mm and lowers it
 *    (dt = 2^-18 s): the ledger's total_error stays below 1e-3 of the energy flow (wall
 *    work and dissipation; measured 2e-5);
 * 4. a gate (a named polygon) under four resting spheres is removed at t1 = 0.01 s:
 *    removed at the step nearest t1, no candidate with the gate afterwards, the spheres
 *    at rest before and in the leapfrog's free fall after (x_n+k = x_n - g dt^2
 *    k(k+1)/2 to 1e-12 m; against g t^2/2 within g t dt/2), the ledger closed (its
 *    released contact energy in energy_removed);
 * 5. a lid added at 0.06 s: a sphere starting inside its place falls through before
 *    (the leapfrog's free fall from rest, x_k = x_0 - g dt^2 k^2/2, to 1e-12 m), another
 *    lands on it after, the ledger closed to 1%; adding it over a sphere stops
 *    the run (ESF_ENUMERIC naming the particle);
 * 6. a silo filled with 60 spheres, its gate removed at 0.05 s, with static walls (the
 *    fused step's fast wall pass) and with a side plate following a velocity table:
 *    the fused step on 1, 2 and 3 threads and the general path give the same state
 *    bit for bit (memcmp); the ledger closes to 2% of the energy flow. */
#include <stdlib.h>

#include "fused/fused.h"
#include "loads/events.h"
#include "simtest.h"

#define MAT                                                                              \
  "materials: {g: {density: 2500, kn: 1.0e5, restitution: 0.5, friction: 0.3}}\n"

static simtest *open_plate(const char *motion) {
  static simtest T;
  char yaml[2048];
  snprintf(yaml, sizeof yaml,
           "name: k\ngravity: [0, 0, 0]\n" MAT
           "particles:\n  - {material: g, radius: 0.005, position: [0.5, 0.5, 0.5]}\n"
           "walls:\n  - {polygon: [[0,0,0], [0.1,0,0], [0.1,0.1,0], [0,0.1,0]], "
           "material: g, motion: %s}\n"
           "integrator: {dt: 6.103515625e-05}\n"
           "run: {steps: 1}\n",
           motion);
  return simtest_open(&T, yaml, NULL, 0) ? NULL : &T;
}

static void tables(void) {
  static const double tt[4] = {0.125, 0.25, 0.5, 1.0};
  static const double dd[4][3] = {
      {0.001, 0, 0}, {0.002, -0.001, 0.003}, {0.002, 0.0005, -0.001}, {0, 0, 0}};
  simtest *T = open_plate("{table: {time: [0.125, 0.25, 0.5, 1.0], displacement: "
                          "[[0.001, 0, 0], [0.002, -0.001, 0.003], [0.002, 0.0005, "
                          "-0.001], [0, 0, 0]]}}");
  CHECK(T != NULL, "displacement table scene opens");
  if (!T) return;
  esf_walls *w = &T->s.walls;
  int exact = 1;
  double worst = 0, worst_v = 0;
  for (int i = 0; i < 4; i++) {
    esf_walls_set_time(w, tt[i]);
    for (int j = 0; j < 4; j++)
      for (int q = 0; q < 3; q++) exact &= w->e[0].v[j][q] == w->e0[0].v[j][q] + dd[i][q];
    if (i == 3) break;
    const double tm = 0.5 * (tt[i] + tt[i + 1]); /* halfway: the mean, at the slope */
    esf_walls_set_time(w, tm);
    for (int q = 0; q < 3; q++) {
      const double want = w->e0[0].v[2][q] + 0.5 * (dd[i][q] + dd[i + 1][q]);
      const double slope = (dd[i + 1][q] - dd[i][q]) / (tt[i + 1] - tt[i]);
      worst = fmax(worst, fabs(w->e[0].v[2][q] - want));
      worst_v = fmax(worst_v, fabs(w->g[0].vel[q] - slope));
    }
  }
  CHECK(exact, "the wall is at the tabulated positions at the table's times exactly");
  CHECK(worst < 1e-15 && worst_v < 1e-15,
        "halfway between rows: position %.3g m, velocity %.3g m/s off", worst, worst_v);
  esf_walls_set_time(w, 0.05); /* before the first row: the first row, at rest */
  CHECK(w->e[0].v[0][0] == w->e0[0].v[0][0] + 0.001 && v3_norm(w->g[0].vel) == 0,
        "before the first row: the first row's displacement, at rest");
  esf_walls_set_time(w, 2.0);
  CHECK(w->e[0].v[1][0] == w->e0[0].v[1][0] && v3_norm(w->g[0].vel) == 0,
        "after the last row: the last row's displacement, at rest");
  simtest_close(T);

  T = open_plate(
      "{table: {time: [0, 0.25, 0.5], velocity: {z: [0.004, -0.002, 0.001]}}}");
  CHECK(T != NULL, "velocity table scene opens");
  if (!T) return;
  w = &T->s.walls;
  const double z0 = w->e0[0].v[0][2];
  const double at[4] = {0.25, 0.5, 0.75, 0.375};
  const double want[4] = {0.001, 0.0005, 0.00075, 0.00075};
  const double vel[4] = {-0.002, 0.001, 0.001, -0.002};
  int ok = 1;
  for (int i = 0; i < 4; i++) {
    esf_walls_set_time(w, at[i]);
    ok &= fabs(w->e[0].v[0][2] - (z0 + want[i])) < 1e-17 && w->g[0].vel[2] == vel[i] &&
          w->g[0].vel[0] == 0 && w->g[0].vel[1] == 0;
  }
  CHECK(ok, "velocity table (z only): displacements 1, 0.5, 0.75 mm at 0.25, 0.5, "
            "0.75 s; the last row's velocity after it");
  simtest_close(T);
}

/* the expected window: d = v (clamp(t, a, b) - a), velocity v inside [a, b) */
static double clampw(double t, double a, double b) {
  return (t < a ? a : t > b ? b : t) - a;
}

static void windows(void) {
  simtest *T = open_plate(
      "[{rotate: {axis: [0, 0, 1], center: [0.05, 0.05, 0], omega: 3, start: 0.002, "
      "stop: 0.004}}, {translate: {velocity: [0.1, 0, 0], start: 0.001, stop: 0.003}}, "
      "{oscillate: {direction: [0, 0, 1], frequency: 200, amplitude: 0.001, start: "
      "0.003}}]");
  CHECK(T != NULL, "window scene opens");
  if (!T) return;
  esf_walls *w = &T->s.walls;
  esf_wall_group *g = &w->g[0];
  CHECK(g->motion.kind == ESF_MOTION_ROTATE && g->nmore == 2,
        "the sequence's rotation leads, two more terms");
  long bad = 0, steps = 0, inside[3] = {0, 0, 0};
  for (long n = 0; n < 100 && !bad; n++) {
    if (simtest_step(T)) {
      bad = -1;
      break;
    }
    const double t = w->t; /* the step's time t_n: the walls placed at x_n's time */
    bad += t != (double)n * T->s.dt;
    const double ang = 3 * clampw(t, 0.002, 0.004), dx = 0.1 * clampw(t, 0.001, 0.003);
    const double wr = 2 * ESF_PI * 200, ph = wr * clampw(t, 0.003, INFINITY);
    const double dz = 0.001 * sin(ph);
    const int on_r = t >= 0.002 && t < 0.004, on_t = t >= 0.001 && t < 0.003,
              on_o = t >= 0.003;
    inside[0] += on_r, inside[1] += on_t, inside[2] += on_o;
    bad += g->angle != ang || g->disp[0] != dx || g->disp[2] != dz;
    bad += g->omega[2] != (on_r ? 3.0 : 0.0) || g->vel[0] != (on_t ? 0.1 : 0.0);
    bad += g->vel[2] != (on_o ? 0.001 * wr * cos(ph) : 0.0);
    steps++;
  }
  CHECK(bad == 0 && steps == 100,
        "start/stop to the step: %ld of %ld steps off (windows hold %ld, %ld, %ld steps)",
        bad, steps, inside[0], inside[1], inside[2]);
  CHECK(inside[0] == 33 && inside[1] == 33 && inside[2] == 50,
        "the windows [2, 4), [1, 3), [3, inf) ms hold 33, 33 and 50 steps of 2^-14 s");
  simtest_close(T);
}

/* a sphere resting on a plate that a displacement table lifts 2 mm and lowers again */
static void ledger_table(void) {
  const double r = 0.005, m = 2500 * 4.0 / 3.0 * ESF_PI * r * r * r, u = m * 9.81 / 1e5;
  char yaml[2048];
  snprintf(yaml, sizeof yaml,
           "name: lift\ngravity: [0, 0, -9.81]\n" MAT
           "particles:\n  - {material: g, radius: 0.005, position: [0.05, 0.05, %.17g]}\n"
           "walls:\n  - {polygon: [[0,0,0], [0.1,0,0], [0.1,0.1,0], [0,0.1,0]], "
           "material: g, motion: {table: {time: [0.01, 0.03, 0.05, 0.07], "
           "displacement: {z: [0, 0.002, 0.002, 0]}}}}\n"
           "contact: {allow_initial_overlap: true}\n"
           "integrator: {dt: 3.814697265625e-06}\n"
           "output: {energy_every: 1.0e-3}\n"
           "run: {duration: 0.1}\n",
           r - u);
  simtest T;
  int rc = simtest_open(&T, yaml, NULL, 0);
  CHECK(rc == 0, "lift scene opens");
  if (rc) return;
  double zmax = 0, flow = 0;
  while (!rc && T.s.t < 0.1) {
    rc = simtest_step(&T);
    zmax = fmax(zmax, T.s.p.x[2]);
  }
  const esf_ledger *L = &T.s.led;
  flow = fabs(L->w_walls) + fabs(esf_ledger_dissipated(L));
  const double e = esf_ledger_total_error(L);
  printf("lift: work_walls %.6g J (mg * 2 mm = %.6g J), dissipated %.3g J, "
         "total_error %.3g J (%.3g of the flow), peak height %.6g m\n",
         L->w_walls, m * 9.81 * 0.002, esf_ledger_dissipated(L), e, fabs(e) / flow, zmax);
  CHECK(rc == 0, "lift runs");
  CHECK(zmax > r - u + 0.002 - 1e-6, "the sphere rides the plate up 2 mm (peak %.4g m)",
        zmax);
  CHECK(fabs(e) < 1e-3 * flow, "ledger closed: total_error %.3g of the flow",
        fabs(e) / flow);
  simtest_close(&T);
}

/* four spheres at rest on a gate removed at t1 */
static void gate(void) {
  const double r = 0.005, m = 2500 * 4.0 / 3.0 * ESF_PI * r * r * r, u = m * 9.81 / 1e5;
  const double z0 = r - u, dt = 6.103515625e-05, t1 = 0.01, g = 9.81;
  char yaml[4096];
  snprintf(yaml, sizeof yaml,
           "name: gate\ngravity: [0, 0, -9.81]\n" MAT "particles:\n"
           "  - {material: g, radius: 0.005, position: [0.02, 0.02, %.17g]}\n"
           "  - {material: g, radius: 0.005, position: [0.04, 0.02, %.17g]}\n"
           "  - {material: g, radius: 0.005, position: [0.02, 0.04, %.17g]}\n"
           "  - {material: g, radius: 0.005, position: [0.04, 0.04, %.17g]}\n"
           "walls:\n  - {name: gate, polygon: [[0,0,0], [0.06,0,0], [0.06,0.06,0], "
           "[0,0.06,0]], material: g}\n"
           "events: [{at: %g, remove_wall: gate}]\n"
           "contact: {allow_initial_overlap: true}\n"
           "integrator: {dt: %.17g}\n"
           "output: {energy_every: 1.0e-3}\n"
           "run: {duration: 0.05}\n",
           z0, z0, z0, z0, t1, dt);
  simtest T;
  int rc = simtest_open(&T, yaml, NULL, 0);
  CHECK(rc == 0, "gate scene opens");
  if (rc) return;
  const long n1 = lround(ceil((t1 - 0.5 * dt) / dt)); /* the step nearest t1 */
  double rest = 0, fall = 0, fall_t2 = 0;
  long after_cands = 0, applied = -1;
  while (!rc && T.s.step < 600) {
    const long n = T.s.step;
    rc = simtest_step(&T);
    if (applied < 0 && T.s.events->e[0].done) applied = n;
    const long k = T.s.step - n1; /* steps of free fall, x_{n1+k} */
    for (size_t i = 0; i < T.s.p.n; i++) {
      const double z = T.s.p.x[3 * i + 2];
      if (k <= 0) {
        rest = fmax(rest, fabs(z - z0));
        continue;
      }
      fall = fmax(fall, fabs(z - (z0 - g * dt * dt * (double)(k * (k + 1)) / 2)));
      const double tau = (double)k * dt; /* against g tau^2/2, within g tau dt/2 */
      fall_t2 = fmax(fall_t2, fabs(z0 - z - 0.5 * g * tau * tau) - 0.5 * g * tau * dt);
    }
    if (k > 0) after_cands += (long)T.s.nb.pw.n;
  }
  CHECK(rc == 0, "gate run");
  CHECK(applied == n1 && fabs((double)n1 * dt - t1) <= 0.5 * dt,
        "removed at step %ld (t = %.6g s), the step nearest t1 (%ld)", applied,
        (double)applied * dt, n1);
  CHECK(after_cands == 0, "no candidate with the gate after t1 (%ld)", after_cands);
  CHECK(rest < 1e-12, "at rest on the gate before t1: %.3g m", rest);
  CHECK(fall < 1e-12, "leapfrog free fall after t1: %.3g m off", fall);
  CHECK(fall_t2 < 1e-12, "g t^2/2 within g t dt/2 (excess %.3g m)", fall_t2);
  const esf_ledger *L = &T.s.led;
  const double ke = 0.5 * 4 * m * pow(g * (double)(T.s.step - n1) * dt, 2);
  printf("gate: removed at step %ld, t = %.6g s; energy_removed %.6g J (4 x kn u^2/2 = "
         "%.6g J); total_error %.3g J, kinetic at the end %.4g J\n",
         applied, (double)applied * dt, L->e_removed, 4 * 0.5 * 1e5 * u * u,
         esf_ledger_total_error(L), ke);
  CHECK(fabs(L->e_removed - 4 * 0.5 * 1e5 * u * u) < 1e-6 * L->e_removed,
        "the gate's contact energy released into energy_removed");
  CHECK(fabs(esf_ledger_total_error(L)) < 1e-9 * ke, "ledger closed after release");
  simtest_close(&T);
}

/* a plate added at 0.06 s: sphere A starts inside its place and falls through before,
 * sphere B lands on it after; adding it at 0.01 s, over A, stops the run */
static void added(void) {
  const double dt = 1.52587890625e-05, g = 9.81;
  char yaml[2048];
  const char *fmt = "name: lid\ngravity: [0, 0, -9.81]\n" MAT "particles:\n"
                    "  - {material: g, radius: 0.005, position: [0.02, 0.02, 0.003]}\n"
                    "  - {material: g, radius: 0.005, position: [0.05, 0.05, 0.05]}\n"
                    "walls:\n  - {name: lid, polygon: [[0,0,0], [0.1,0,0], [0.1,0.1,0], "
                    "[0,0.1,0]], material: g}\n"
                    "events: [{at: %g, add_wall: lid}]\n"
                    "integrator: {dt: %.17g}\n"
                    "output: {energy_every: 1.0e-3}\n"
                    "run: {duration: 0.2}\n";
  snprintf(yaml, sizeof yaml, fmt, 0.06, dt);
  simtest T;
  int rc = simtest_open(&T, yaml, NULL, 0);
  CHECK(rc == 0 && T.s.walls.g[0].absent, "lid scene opens, the lid absent at first");
  if (rc) return;
  double fall = 0, zb = 1;
  long cand_before = 0;
  while (!rc && T.s.step < 13000) {
    rc = simtest_step(&T);
    const double k = (double)T.s.step, za = 0.003 - g * dt * dt * k * k / 2;
    for (size_t i = 0; i < T.s.p.n; i++) {
      if (T.s.p.id[i] == 0) fall = fmax(fall, fabs(T.s.p.x[3 * i + 2] - za));
      if (T.s.p.id[i] == 1) zb = fmin(zb, T.s.p.x[3 * i + 2]);
    }
    if (!T.s.events->e[0].done) cand_before += (long)T.s.nb.pw.n;
  }
  CHECK(rc == 0, "lid run");
  CHECK(cand_before == 0 && !T.s.walls.g[0].absent, "no wall candidate before the add");
  CHECK(fall < 1e-12, "sphere A falls through the lid's place freely (%.3g m off)", fall);
  CHECK(zb > 0.004 && zb < 0.005, "sphere B lands on the added lid (lowest z %.4g m)",
        zb);
  const esf_ledger *L = &T.s.led;
  const double e_rel = fabs(esf_ledger_total_error(L)) / esf_ledger_dissipated(L);
  printf("lid: sphere B's lowest centre %.5g m (radius 0.005); total_error %.3g of the "
         "dissipated energy\n",
         zb, e_rel);
  CHECK(e_rel < 0.01, "lid: ledger closed (%.3g of the dissipated energy)", e_rel);
  simtest_close(&T);
  snprintf(yaml, sizeof yaml, fmt, 0.01, dt);
  rc = simtest_open(&T, yaml, NULL, 0);
  while (!rc && T.s.step < 1000) rc = T.it->step(&T.s, T.ist, INFINITY, &T.err);
  CHECK(rc == ESF_ENUMERIC && strstr(T.err.msg, "adds wall 'lid' where particle 0"),
        "adding the lid over sphere A stops the run: %s", T.err.msg);
  simtest_close(&T);
}

/* a filled silo: gate removed at 0.05 s; %s: a side plate on a velocity table, or
 * nothing (static walls: the fused step's fast wall pass) */
static const char *const plate =
    "  - {polygon: [[0.027,0,0.005], [0.027,0.03,0.005], [0.027,0.03,0.03], "
    "[0.027,0,0.03]], material: g, motion: {table: {time: [0, 0.03, 0.06], velocity: "
    "[[-0.05, 0, 0], [0.05, 0, 0], [0, 0, 0]]}}}\n";
static const char *const silo =
    "name: silo\ngravity: [0, 0, -9.81]\n" MAT
    "particles:\n  - generate: random\n    region: {min: [0.0005, 0.0005, 0.0005], max: "
    "[0.0265, 0.0295, 0.06]}\n    count: 60\n    radius: 0.0025\n    material: g\n"
    "    seed: 5\n"
    "walls:\n  - {box: {min: [0, 0, 0], max: [0.03, 0.03, 0.1]}, open: [bottom, top], "
    "material: g}\n"
    "  - {name: gate, polygon: [[0,0,0], [0.03,0,0], [0.03,0.03,0], [0,0.03,0]], "
    "material: g}\n%s"
    "events: [{at: 0.05, remove_wall: gate}]\n"
    "damping: {global: {translation: 2.0}}\n"
    "integrator: {dt: auto, frac: 0.2}\n"
    "output: {energy_every: 1.0e-4}\n"
    "run: {duration: 0.08}\n";

static int silo_run(int moving, int threads, int fused, double **y, size_t *n, int *on,
                    double *err_rel) {
  const char *sets[1] = {fused ? "integrator.fused=true" : "integrator.fused=false"};
  char yaml[2048];
  snprintf(yaml, sizeof yaml, silo, moving ? plate : "");
  simtest T;
  int rc = simtest_open(&T, yaml, sets, 1);
  if (rc) return rc;
  T.s.cfg.threads = threads;
  T.s.cfg.range_work = 1;
  T.s.burst = 16; /* the fused step's bursts once the gate is gone (static walls) */
  *on = esf_fused_refusal(&T.s) == NULL;
  long calls = 0;
  for (; !rc && T.s.t < 0.08; calls++) rc = simtest_step(&T);
  if (!rc && fused && !moving) /* bursts once the gate is gone */
    CHECK(calls < T.s.step, "silo: %ld calls for %ld steps", calls, T.s.step);
  if (!rc) {
    *n = T.s.p.n;
    *y = malloc(9 * *n * sizeof(double));
    memcpy(*y, T.s.p.y, 9 * *n * sizeof(double));
    const esf_ledger *L = &T.s.led;
    *err_rel = fabs(esf_ledger_total_error(L)) /
               (fabs(L->w_walls) + fabs(esf_ledger_dissipated(L)) + L->e_removed);
  }
  simtest_close(&T);
  return rc;
}

static void silo_threads(int moving) {
  const char *what = moving ? "silo with a tabulated plate" : "silo";
  double *ref = NULL, e_rel = 0;
  size_t n0 = 0;
  int on = 0;
  int rc = silo_run(moving, 1, 0, &ref, &n0, &on, &e_rel);
  CHECK(rc == 0 && !on, "%s: general path runs", what);
  if (rc) return;
  double zmin = INFINITY;
  for (size_t i = 0; i < n0; i++) zmin = fmin(zmin, ref[3 * i + 2]);
  CHECK(zmin < -0.005, "%s: the fill falls out of the opened gate (lowest z %.3g m)",
        what, zmin);
  printf("%s: total_error %.3g of the energy flow\n", what, e_rel);
  CHECK(e_rel < 0.02, "%s: ledger closed (%.3g of the flow)", what, e_rel);
  for (int t = 1; t <= 3; t++) {
    double *y = NULL;
    size_t n = 0;
    rc = silo_run(moving, t, 1, &y, &n, &on, &e_rel);
    CHECK(rc == 0 && on && n == n0 && memcmp(y, ref, 9 * n * sizeof(double)) == 0,
          "%s: fused step on %d threads = general path, bit for bit", what, t);
    free(y);
  }
  free(ref);
}

int main(void) {
  tables();
  windows();
  ledger_table();
  gate();
  added();
  silo_threads(0);
  silo_threads(1);
  return check_finish("wall_timing");
}
