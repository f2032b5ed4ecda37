/* test_wall_lever.c — where a wall contact acts (contact.wall_lever).
 * An undamped oblique impact of a sphere on a plane: kt/kn = 2/7, mu = 0.3, incidence
 * 25 degrees from the normal, approach speed set so that the peak overlap is 2% of the
 * radius. The lever arm from the centre to the contact point sets how much of the
 * tangential impulse goes into spin, hence the rebound's tangential velocity. Reference:
 * the contact's equations of motion for each rule (lever r - u/2, the seed's 000 3-16,
 * or r - u, the wall's surface) integrated here by RK4 with 200 000 steps per contact
 * time, the Coulomb cap applied after each step. The leapfrog at frac 0.01 must agree
 * within 0.1% of the tangential velocity, for both rules, and the two rules must differ
 * by more than 1% (the reference gives 0.4222 and 0.4158 of the incoming tangential
 * velocity: 1.5%). */
#include "simtest.h"

enum { SEED = 0, SURFACE = 1 };
static const double R = 0.01, RHO = 2500, KN = 1.0e5, MU = 0.3, ANG = 25.0;

/* The rebound's tangential velocity over the incoming one, by RK4 on
 * y = (u, vn, vt, w, xi): u the overlap, vn its rate, vt the centre's tangential
 * velocity, w the spin (positive when the bottom moves backward), xi the spring. */
static void rhs(int rule, double m, double I, const double y[5], double d[5]) {
  const double u = y[0], kt = KN * 2.0 / 7.0;
  const double la = rule == SEED ? R - 0.5 * u : R - u;
  const double fn = u > 0 ? KN * u : 0.0, ft = u > 0 ? -kt * y[4] : 0.0;
  d[0] = y[1];
  d[1] = -fn / m;
  d[2] = ft / m;
  d[3] = -la * ft / I;
  d[4] = u > 0 ? y[2] - la * y[3] : 0.0; /* the contact point's slip velocity */
}

static double reference(int rule, double vn, double vt) {
  const double m = RHO * 4.0 / 3.0 * ESF_PI * R * R * R, I = 0.4 * m * R * R;
  const double T = ESF_PI * sqrt(m / KN), h = T / 200000.0, kt = KN * 2.0 / 7.0;
  double y[5] = {0, vn, vt, 0, 0};
  for (long i = 0; i < 400000 && (i < 10 || y[0] > 0); i++) {
    double k1[5], k2[5], k3[5], k4[5], t[5];
    rhs(rule, m, I, y, k1);
    for (int q = 0; q < 5; q++) t[q] = y[q] + 0.5 * h * k1[q];
    rhs(rule, m, I, t, k2);
    for (int q = 0; q < 5; q++) t[q] = y[q] + 0.5 * h * k2[q];
    rhs(rule, m, I, t, k3);
    for (int q = 0; q < 5; q++) t[q] = y[q] + h * k3[q];
    rhs(rule, m, I, t, k4);
    for (int q = 0; q < 5; q++) y[q] += h / 6.0 * (k1[q] + 2 * k2[q] + 2 * k3[q] + k4[q]);
    const double cap = MU * KN * (y[0] > 0 ? y[0] : 0.0) / kt; /* radial return */
    if (fabs(y[4]) > cap) y[4] = y[4] > 0 ? cap : -cap;
  }
  return y[2] / vt;
}

static double simulate(const char *lever, double vn, double vt) {
  char yaml[1024];
  snprintf(yaml, sizeof yaml,
           "name: lever\n"
           "gravity: [0, 0, 0]\n"
           "materials: {ball: {density: %g, kn: %g, kt: %.17g, restitution: 1.0,\n"
           "  tangential_restitution: 1.0, friction: %g}}\n"
           "particles:\n"
           "  - {material: ball, radius: %g, position: [0, 0, %.17g],\n"
           "     velocity: [%.17g, 0, %.17g]}\n"
           "walls:\n"
           "  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: ball}\n"
           "contact: {wall_lever: %s}\n"
           "integrator: {dt: auto, frac: 0.01}\n"
           "run: {duration: 1}\n"
           "output: {energy_every: 0}\n",
           RHO, KN, KN * 2.0 / 7.0, MU, R, R * 1.0001, vt, -vn, lever);
  simtest T;
  if (simtest_open(&T, yaml, NULL, 0)) return NAN;
  const double m = T.s.p.mass[0], tc = ESF_PI * sqrt(m / KN);
  const double t_end = (1e-4 * R) / vn + 1.5 * tc; /* reach, cross and leave */
  while (T.s.t < t_end)
    if (simtest_step(&T)) break;
  const double ratio = T.s.p.v[0] / vt;
  const int apart = T.s.p.x[2] > R;
  simtest_close(&T);
  return apart ? ratio : NAN;
}

int main(void) {
  const double m = RHO * 4.0 / 3.0 * ESF_PI * R * R * R;
  const double vn = 0.02 * R * sqrt(KN / m); /* peak overlap 0.02 R, undamped */
  const double vt = vn * tan(ANG * ESF_PI / 180.0);
  const double ref_seed = reference(SEED, vn, vt), ref_surf = reference(SURFACE, vn, vt);
  const double sim_seed = simulate("seed", vn, vt),
               sim_surf = simulate("surface", vn, vt);
  printf("vt_out/vt_in: seed rule %.5f (reference %.5f), surface rule %.5f "
         "(reference %.5f)\n",
         sim_seed, ref_seed, sim_surf, ref_surf);
  CHECK_NEAR(sim_seed, ref_seed, 1e-3 * ref_seed, "seed rule against its reference");
  CHECK_NEAR(sim_surf, ref_surf, 1e-3 * ref_surf, "surface rule against its reference");
  CHECK(ref_seed - ref_surf > 0.01 * ref_seed, "the rules differ by %.4f",
        ref_seed - ref_surf);
  /* the default is the seed's rule */
  simtest T;
  CHECK(simtest_open(&T, simtest_pair_scene, NULL, 0) == 0, "open");
  CHECK(T.s.cfg.wall_lever == ESF_WALL_LEVER_SEED, "default rule %d", T.s.cfg.wall_lever);
  simtest_close(&T);
  return check_finish("test_wall_lever");
}
