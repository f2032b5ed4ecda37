/* test_wall_motion.c — prescribed wall motion (wall_motion.c):
 * 1. kinematics: for translate, rotate and oscillate, every vertex of a moving square
 *    is where the motion puts it, and the velocity the contact sees
 *    (esf_wall_point_velocity) is the time derivative of that position (central
 *    difference, relative 1e-6);
 * 2. a wall translating at U strikes a sphere at rest (no gravity) from over 10 skins
 * away (the candidate lists must follow the wall): the sphere leaves at (1 + e) U with e
 *    the restitution of the cut damped oscillator (Galilean invariance), within 0.3%;
 * 3. a plate oscillating at peak acceleration 3 g under a resting sphere throws it:
 *    the walls' work enters the energy ledger and the balance closes to 1% of the
 *    energy that went through (work of the walls). */
#include "simtest.h"

static void kinematics(void) {
  const char *kinds[] = {
      "{translate: {velocity: [0.3, -0.2, 0.1]}}",
      "{rotate: {axis: [0, 0, 1], center: [0.05, 0.02, 0], rpm: 95}}",
      "{oscillate: {direction: [0, 1, 1], frequency: 20, amplitude: 0.002, phase: 0.3}}"};
  for (int k = 0; k < 3; k++) {
    char yaml[1024];
    snprintf(yaml, sizeof yaml,
             "name: k\ngravity: [0, 0, 0]\n"
             "materials: {g: {density: 2500, kn: 1.0e5, restitution: 0.5, friction: "
             "0.3}}\n"
             "particles:\n  - {material: g, radius: 0.005, position: [0.5, 0.5, 0.5]}\n"
             "walls:\n  - {polygon: [[0,0,0], [0.1,0,0], [0.1,0.1,0], [0,0.1,0]], "
             "material: g, motion: %s}\n"
             "run: {steps: 1}\n",
             kinds[k]);
    simtest T;
    if (simtest_open(&T, yaml, NULL, 0)) {
      CHECK(0, "kinematics scene %d opens", k);
      continue;
    }
    esf_walls *w = &T.s.walls;
    double t = 0.0123, h = 1e-6, worst = 0, worst_pos = 0;
    const esf_wall_motion *m = &w->g[0].motion;
    for (int j = 0; j < 4; j++) {
      double xm[3], xp[3], x0[3], v[3];
      esf_walls_set_time(w, t - h);
      v3_copy(xm, w->e[0].v[j]);
      esf_walls_set_time(w, t + h);
      v3_copy(xp, w->e[0].v[j]);
      esf_walls_set_time(w, t);
      v3_copy(x0, w->e[0].v[j]);
      esf_wall_point_velocity(&w->g[0], x0, v);
      double fd[3], d[3];
      for (int q = 0; q < 3; q++) fd[q] = (xp[q] - xm[q]) / (2 * h);
      v3_sub(d, fd, v);
      worst = fmax(worst, v3_norm(d) / fmax(v3_norm(v), 1e-12));
      /* where it should be */
      double r0[3], want[3];
      v3_copy(r0, w->e0[0].v[j]);
      if (m->kind == ESF_MOTION_TRANSLATE) {
        for (int q = 0; q < 3; q++) want[q] = r0[q] + m->vel[q] * t;
      } else if (m->kind == ESF_MOTION_ROTATE) {
        double a = m->rate * t, dx = r0[0] - 0.05, dy = r0[1] - 0.02;
        v3_set(want, 0.05 + dx * cos(a) - dy * sin(a), 0.02 + dx * sin(a) + dy * cos(a),
               r0[2]);
      } else {
        double s = 0.002 * sin(2 * ESF_PI * 20 * t + 0.3) / sqrt(2.0);
        v3_set(want, r0[0], r0[1] + s, r0[2] + s);
      }
      v3_sub(d, x0, want);
      worst_pos = fmax(worst_pos, v3_norm(d));
    }
    printf("%s: position error %.2e m, velocity vs finite difference %.2e\n", kinds[k],
           worst_pos, worst);
    CHECK(worst_pos < 1e-14, "motion %d: vertices placed exactly (%.2e m)", k, worst_pos);
    CHECK(worst < 1e-6, "motion %d: velocity is the derivative of position (%.2e)", k,
          worst);
    simtest_close(&T);
  }
}

static void struck_sphere(void) {
  const char *yaml =
      "name: strike\ngravity: [0, 0, 0]\n"
      "materials: {g: {density: 2500, kn: 1.0e5, restitution: 0.5, friction: 0.3}}\n"
      "particles:\n  - {material: g, radius: 0.005, position: [0.05, 0.05, 0.03]}\n"
      "walls:\n  - {polygon: [[0,0,0], [0.1,0,0], [0.1,0.1,0], [0,0.1,0]], material: g,\n"
      "     motion: {translate: {velocity: [0, 0, 0.5]}}}\n"
      "integrator: {frac: 0.01}\nrun: {steps: 1}\noutput: {energy_every: 0}\n";
  simtest T;
  if (simtest_open(&T, yaml, NULL, 0)) {
    CHECK(0, "strike scene opens");
    return;
  }
  CHECK(0.025 > 10 * T.s.nb.skin, "the wall starts %.3g m away, over 10 skins (%.3g m)",
        0.025, T.s.nb.skin);
  int rc = 0;
  while (!rc && T.s.t < 0.08) rc = simtest_step(&T);
  double m = T.s.p.mass[0];
  cut_impact x = cut_impact_closed_form(esf_restitution_gamma(0.5), sqrt(1.0e5 / m));
  double vz = T.s.p.v[2], want = (1 + x.e) * 0.5;
  printf("struck sphere: vz %.6f m/s, (1 + e) U = %.6f m/s; %ld list builds\n", vz, want,
         T.s.nb.builds);
  CHECK(rc == 0 && fabs(vz / want - 1) < 3e-3, "rebound (1 + e) U: %.6f against %.6f", vz,
        want);
  CHECK(fabs(T.s.p.v[0]) < 1e-12 && fabs(T.s.p.v[1]) < 1e-12, "no sideways motion");
  simtest_close(&T);
}

static void shaken_ledger(void) {
  const char *yaml =
      "name: shake\ngravity: [0, 0, -9.81]\n"
      "materials: {g: {density: 2500, kn: 1.0e5, restitution: 0.5, friction: 0.3}}\n"
      "particles:\n  - {material: g, radius: 0.005, position: [0.05, 0.05, 0.0051]}\n"
      "walls:\n  - {polygon: [[0,0,0], [0.1,0,0], [0.1,0.1,0], [0,0.1,0]], material: g,\n"
      "     motion: {oscillate: {direction: [0, 0, 1], frequency: 20, acceleration: "
      "3}}}\n"
      "run: {steps: 1}\noutput: {energy_every: 1.0e-9}\n";
  simtest T;
  if (simtest_open(&T, yaml, NULL, 0)) {
    CHECK(0, "shake scene opens");
    return;
  }
  double zmax = 0;
  int rc = 0;
  while (!rc && T.s.t < 0.5) {
    rc = simtest_step(&T);
    zmax = fmax(zmax, T.s.p.x[2]);
  }
  const esf_ledger *L = &T.s.led;
  double R = esf_ledger_total_error(L);
  printf("shaken sphere: highest centre %.4f m, walls' work %.4g J, dissipated %.4g J, "
         "residual %.3g J\n",
         zmax, L->w_walls, esf_ledger_dissipated(L), R);
  CHECK(rc == 0 && zmax > 0.0075, "the plate throws the sphere (z_max %.4f m)", zmax);
  CHECK(L->w_walls > 0, "walls do work (%.3g J)", L->w_walls);
  CHECK(fabs(R) < 0.01 * L->w_walls, "ledger closes: |%.3g| J < 1%% of %.3g J", R,
        L->w_walls);
  simtest_close(&T);
}

int main(void) {
  kinematics();
  struck_sphere();
  shaken_ledger();
  return check_finish("test_wall_motion");
}
