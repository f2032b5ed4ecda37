/* test_conservation.c — invariants of the production scheme.
 *
 * 1. Momentum in free space: 60 spheres with random velocities and spins, friction and
 *    dashpots, collide without gravity or walls. Contact forces are equal and opposite
 *    and the tangential forces act at one contact point, so with the leapfrog state
 *    (x at t_n, v at t_n - dt/2) P = sum m v and L = sum (m x x v + I w) are conserved
 *    to round-off (x_{n+1} - x_n is parallel to v_{n+1/2}).
 * 2. Energy without dissipation: an elastic pair collision (eta = 1, no friction), and
 *    a frictionless, undamped pack bouncing in a closed box under gravity. The leapfrog
 *    conserves a nearby energy; what remains is an O((w dt)^2) error made at each
 *    contact's first and last step, which does not grow systematically. The bounds
 *    below are stated against the measured figures printed by the test. */
#include "simtest.h"

#include "util/rng.h"

static const char *cloud =
    "name: cloud\n"
    "gravity: [0, 0, 0]\n"
    "materials: {g: {density: 2500, kn: 1.0e4, kt: 7.0e3, restitution: 0.5, friction: "
    "0.5}}\n"
    "particles:\n"
    "  - {generate: random, region: {min: [0, 0, 0], max: [0.04, 0.04, 0.04]}, count: "
    "60,\n"
    "     radius: {uniform: [0.002, 0.004]}, material: g, seed: 3}\n"
    "integrator: {dt: auto, frac: 0.1}\n"
    "run: {steps: 1}\n"
    "output: {energy_every: 0}\n";

static void momenta(const esf_particles *p, double P[3], double L[3]) {
  v3_set(P, 0, 0, 0);
  v3_set(L, 0, 0, 0);
  for (size_t i = 0; i < p->n; i++) {
    double mv[3], xm[3];
    v3_scale(mv, p->mass[i], p->v + 3 * i);
    v3_add(P, P, mv);
    v3_cross(xm, p->x + 3 * i, mv);
    v3_add(L, L, xm);
    v3_axpy(L, p->inertia[i], p->w + 3 * i);
  }
}

static void test_momentum(void) {
  simtest T;
  if (simtest_open(&T, cloud, NULL, 0)) {
    CHECK(0, "scene failed");
    return;
  }
  esf_particles *p = &T.s.p;
  esf_rng r;
  esf_rng_seed(&r, 11);
  for (size_t j = 0; j < 3 * p->n; j++) {
    p->v[j] = 0.5 * (2 * esf_rng_uniform(&r) - 1); /* m/s */
    p->w[j] = 200 * (2 * esf_rng_uniform(&r) - 1); /* rad/s */
  }
  /* a converging flow so that many collisions happen */
  for (size_t i = 0; i < p->n; i++)
    for (int k = 0; k < 3; k++) p->v[3 * i + k] -= 10 * (p->x[3 * i + k] - 0.02);
  simtest_step(&T);
  double P0[3], L0[3], P1[3], L1[3];
  momenta(p, P0, L0);
  double contacts = 0;
  for (int n = 0; n < 3000; n++) {
    if (simtest_step(&T)) break;
    contacts += (double)esf_neighbor_touching(&T.s.nb);
  }
  momenta(p, P1, L1);
  double pscale = 0, lscale = 0;
  for (size_t i = 0; i < p->n; i++) {
    pscale += p->mass[i] * v3_norm(p->v + 3 * i);
    lscale += p->inertia[i] * v3_norm(p->w + 3 * i) +
              p->mass[i] * v3_norm(p->x + 3 * i) * v3_norm(p->v + 3 * i);
  }
  double dP = 0, dL = 0;
  for (int k = 0; k < 3; k++) {
    dP = fmax(dP, fabs(P1[k] - P0[k]));
    dL = fmax(dL, fabs(L1[k] - L0[k]));
  }
  CHECK(contacts > 1000, "the cloud must collide (contact-steps %.0f)", contacts);
  CHECK(dP <= 1e-13 * pscale, "linear momentum drift %.3g vs scale %.3g", dP, pscale);
  CHECK(dL <= 1e-13 * lscale, "angular momentum drift %.3g vs scale %.3g", dL, lscale);
  printf("momentum: %0.f contact-steps; |dP|/scale = %.2g, |dL|/scale = %.2g\n", contacts,
         dP / pscale, dL / lscale);
  simtest_close(&T);
}

static const char *pair =
    "name: pair\n"
    "gravity: [0, 0, 0]\n"
    "materials: {g: {density: 2500, kn: 1.0e5, restitution: 1.0, friction: 0.0}}\n"
    "particles:\n"
    "  - {material: g, radius: 0.005, position: [-0.0051, 0, 0], velocity: [1, 0.2, 0]}\n"
    "  - {material: g, radius: 0.005, position: [0.0051, 0, 0], velocity: [-1, 0, 0]}\n"
    "integrator: {dt: auto, frac: 0.1}\n"
    "run: {steps: 1}\n"
    "output: {energy_every: 1.0e-9}\n";

static double pair_error(double frac) {
  char f[64];
  snprintf(f, sizeof f, "integrator.frac=%g", frac);
  const char *sets[] = {f};
  simtest T;
  if (simtest_open(&T, pair, sets, 1)) return NAN;
  for (int n = 0; n < (int)(0.3 / frac) * 60; n++)
    if (simtest_step(&T)) break;
  double e = esf_ledger_total_error(&T.s.led) / T.s.led.e0;
  simtest_close(&T);
  return e;
}

static const char *pack =
    "name: bouncing pack\n"
    "materials: {g: {density: 2500, kn: 1.0e4, restitution: 1.0, friction: 0.0}}\n"
    "particles:\n"
    "  - {generate: random, region: {min: [0, 0, 0.0], max: [0.03, 0.03, 0.06]}, count: "
    "150,\n"
    "     radius: {uniform: [0.0015, 0.0025]}, material: g, seed: 5, velocity: [0.2, 0, "
    "0]}\n"
    "walls:\n"
    "  - {box: {min: [0, 0, 0], max: [0.03, 0.03, 0.06]}, material: g}\n"
    "integrator: {dt: auto, frac: 0.1}\n"
    "run: {steps: 1}\n"
    "output: {energy_every: 1.0e-9}\n";

static void test_energy(void) {
  double e1 = pair_error(0.1), e2 = pair_error(0.05), e3 = pair_error(0.025);
  /* an elastic collision: energy error of the whole event, relative */
  CHECK(fabs(e1) < 2e-3, "elastic pair at frac 0.1: relative energy error %.3g", e1);
  CHECK(fabs(e3) < 2e-4, "elastic pair at frac 0.025: relative energy error %.3g", e3);
  printf("elastic pair: relative energy error after the collision %.3g (frac 0.1), %.3g "
         "(0.05), %.3g (0.025)\n",
         e1, e2, e3);

  simtest T;
  if (simtest_open(&T, pack, NULL, 0)) {
    CHECK(0, "pack scene failed");
    return;
  }
  double worst = 0, e0 = 0;
  long steps = 20000;
  double err_mid = 0;
  for (long n = 0; n < steps; n++) {
    if (simtest_step(&T)) break;
    if (n == 0)
      e0 = T.s.led.kin_t + T.s.led.kin_r + T.s.led.el_n + T.s.led.el_t +
           fabs(T.s.led.pot_g);
    double e = fabs(esf_ledger_total_error(&T.s.led));
    if (e > worst) worst = e;
    if (n == steps / 2) err_mid = esf_ledger_total_error(&T.s.led);
  }
  double ek = T.s.led.kin_t + T.s.led.kin_r;
  double err_end = esf_ledger_total_error(&T.s.led);
  CHECK(ek > 1e-4 * e0, "the pack keeps bouncing (kinetic %.3g J)", ek);
  CHECK(worst < 1e-3 * e0, "bouncing pack: worst |energy error| %.3g J vs scale %.3g J",
        worst, e0);
  CHECK(T.s.led.d_normal == 0 && T.s.led.d_friction == 0, "nothing dissipates");
  printf(
      "bouncing pack, %ld steps (%.3g s): energy error %.3g J at the middle, %.3g J at "
      "the end, worst %.3g J; relative to the energy scale %.3g J: %.2g\n",
      steps, T.s.t, err_mid, err_end, worst, e0, worst / e0);
  simtest_close(&T);
}

int main(void) {
  test_momentum();
  test_energy();
  return check_finish("test_conservation");
}
