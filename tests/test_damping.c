/* test_damping.c — damping of particle motion against closed forms
 * (docs/physics.md#damping).
 * 1. Local non-viscous damping, component form (001 3.50): a sphere in free fall feels
 *    the whole unbalanced force m g damped by alpha_c, so it accelerates at
 *    (1 - alpha_c) g (the sign is the half-step velocity's; see the first kick below).
 * The vector form (000 3-11) gives the same in a straight fall, and for a sphere thrown
 * sideways it opposes the velocity with magnitude alpha |m g|.
 * 2. Global viscous damping in the (1 -+ a dt/2) form: a free sphere's speed falls by
 *    ((1 - a dt/2)/(1 + a dt/2)) each step, within O((a dt)^3) of exp(-a t).
 * 3. Rayleigh settings (001 3.59–3.60): omega = 2 pi f, alpha = 2 omega zeta,
 *    beta = 2 zeta / omega; contact dashpots c = beta k: a head-on collision then has
 *    the damping ratio beta w / 2 of the reduced-mass oscillator.
 * 4. Adaptive damping (001 3.62–3.63): the update rule's two branches and its bounds. */
#include "simtest.h"

static const char *fall = "name: fall\n"
                          "materials: {b: {density: 2500, kn: 1.0e5}}\n"
                          "particles:\n"
                          "  - {material: b, radius: 0.01, position: [0, 0, 1]}\n"
                          "integrator: {dt: 1.0e-4}\n"
                          "damping: {local: {coefficient: 0.3, form: component}}\n"
                          "run: {steps: 1}\n"
                          "output: {energy_every: 0}\n";

static void local_damping(void) {
  const char *forms[] = {"damping.local.form=component", "damping.local.form=vector"};
  for (int f = 0; f < 2; f++) {
    simtest T;
    const char *sets[] = {forms[f]};
    if (simtest_open(&T, fall, sets, 1)) continue;
    for (int n = 0; n < 1000; n++) simtest_step(&T);
    /* The start sets v_{-1/2} = v_0 - (dt/2)(-g) = +g dt/2, upward: the first kick takes
       its sign from that half-step velocity and so accelerates at (1 + alpha) g; every
       later one at (1 - alpha) g. */
    double g = 9.81, dt = T.s.dt;
    double expect = 0.5 * g * dt - 1.3 * g * dt - 0.7 * g * 999 * dt;
    CHECK_NEAR(T.s.p.v[2], expect, 1e-9, forms[f]);
    simtest_close(&T);
  }
  /* vector form, sideways throw: one step from a known state */
  simtest T;
  const char *sets[] = {"damping.local.form=vector", "particles.0.velocity=[3, 0, 4]"};
  if (simtest_open(&T, fall, sets, 2)) return;
  simtest_step(&T); /* start + first step: check the damping force directly */
  double v[3] = {3, 0, 4}, f[3] = {0, 0, -9.81 * T.s.p.mass[0]}, fd[3];
  esf_local_vector.force(0.3, f, v, fd);
  double fm = 0.3 * 9.81 * T.s.p.mass[0];
  CHECK_NEAR(fd[0], -fm * 0.6, 1e-15, "vector form x");
  CHECK_NEAR(fd[2], -fm * 0.8, 1e-15, "vector form z");
  esf_local_component.force(0.3, f, v, fd);
  CHECK(fd[0] == 0.0 && fabs(fd[2] + fm) < 1e-15, "component form damps only z here");
  simtest_close(&T);
}

static const char *free_sphere =
    "name: free\n"
    "gravity: [0, 0, 0]\n"
    "materials: {b: {density: 2500, kn: 1.0e5}}\n"
    "particles:\n"
    "  - {material: b, radius: 0.01, position: [0, 0, 0], velocity: [1, 0, 0],\n"
    "     angular_velocity: [0, 0, 10]}\n"
    "integrator: {dt: 1.0e-4}\n"
    "damping: {global: {translation: 5.0, rotation: 20.0}}\n"
    "run: {steps: 1}\n"
    "output: {energy_every: 0}\n";

static void global_damping(void) {
  simtest T;
  if (simtest_open(&T, free_sphere, NULL, 0)) return;
  int N = 2000;
  for (int n = 0; n < N; n++) simtest_step(&T);
  double h = 0.5e-4;
  double fr = (1 - 5.0 * h) / (1 + 5.0 * h), fw = (1 - 20.0 * h) / (1 + 20.0 * h);
  CHECK_NEAR(T.s.p.v[0], pow(fr, N), 1e-12, "discrete global damping, translation");
  CHECK_NEAR(T.s.p.w[2], 10 * pow(fw, N), 1e-11, "discrete global damping, rotation");
  double t = N * 1e-4;
  CHECK_NEAR(T.s.p.v[0], exp(-5.0 * t), 1e-6, "close to exp(-alpha t)");
  simtest_close(&T);
}

static const char *pair = "name: rayleigh\n"
                          "gravity: [0, 0, 0]\n"
                          "materials: {b: {density: 2500, kn: 1.0e5}}\n"
                          "particles:\n"
                          "  - {material: b, radius: 0.005, position: [-0.00501, 0, 0], "
                          "velocity: [0.5, 0, 0]}\n"
                          "  - {material: b, radius: 0.005, position: [0.00501, 0, 0], "
                          "velocity: [-0.5, 0, 0]}\n"
                          "integrator: {dt: auto, frac: 0.002}\n"
                          "damping: {rayleigh: {zeta: 0.05, frequency: 200}}\n"
                          "run: {steps: 1}\n"
                          "output: {energy_every: 0}\n";

static void rayleigh(void) {
  simtest T;
  if (simtest_open(&T, pair, NULL, 0)) return;
  double w = 2 * ESF_PI * 200;
  CHECK_NEAR(T.s.alpha_r, 2 * w * 0.05, 1e-9, "alpha = 2 omega zeta");
  CHECK_NEAR(T.s.beta, 2 * 0.05 / w, 1e-15, "beta = 2 zeta / omega");
  /* contact damping ratio of this pair: zeta_c = beta wc / 2, wc = sqrt(k / m*) */
  double m = T.s.p.mass[0], wc = sqrt(1.0e5 / (0.5 * m)), zc = 0.5 * T.s.beta * wc;
  /* run the collision with the body dampers off to isolate c = beta k */
  T.s.alpha_r = T.s.alpha_t = 0;
  for (int n = 0; n < 400000 && T.s.p.x[3] - T.s.p.x[0] < 0.0102; n++) simtest_step(&T);
  double e = (T.s.p.v[3] - T.s.p.v[0]) / 1.0;
  double expect = cut_impact_closed_form(zc, wc).e;
  CHECK_NEAR(e, expect, 0.005 * expect, "restitution with c = beta k");
  printf("Rayleigh: alpha %.4g 1/s, beta %.4g s, contact zeta %.4f, e %.5f (closed form "
         "%.5f)\n",
         2 * w * 0.05, T.s.beta, zc, e, expect);
  simtest_close(&T);
}

static void adaptive(void) {
  esf_auto_damping a = {1, 0.95, 1.1, 0.1, 100.0};
  /* steady kinetic energy: the dampers dominate, alpha falls */
  CHECK_NEAR(esf_auto_damping_update(&a, 10, 1.0, 1.0, 1e-3), 10 / 1.1, 1e-12, "falls");
  /* fast change: 2 alpha Ek = 20 W < 0.95 x 1000 W: alpha rises */
  CHECK_NEAR(esf_auto_damping_update(&a, 10, 1.0, 2.0, 1e-3), 11, 1e-12, "rises");
  CHECK_NEAR(esf_auto_damping_update(&a, 0.1, 1.0, 1.0, 1e-3), 0.1, 1e-15, "lower bound");
  CHECK_NEAR(esf_auto_damping_update(&a, 99, 1.0, 9.0, 1e-3), 100, 1e-12, "upper bound");
}

int main(void) {
  local_damping();
  global_damping();
  rayleigh();
  adaptive();
  return check_finish("test_damping");
}
