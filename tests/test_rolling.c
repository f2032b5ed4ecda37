/* test_rolling.c — a sphere (3D) and a disk (2D) launched sliding on a plane with no
 * spin: friction mu m g decelerates the centre and spins the body up until it rolls.
 * Closed forms (I = k m r^2, k = 2/5 sphere, 1/2 disk):
 *   rolling starts at t_r = v0 / (mu g (1 + 1/k))  (sphere: 2 v0 / (7 mu g))
 *   and the rolling speed is v0 / (1 + k)          (sphere: 5/7 v0; disk: 2/3 v0).
 * The body starts at its static overlap m g / kn, so it neither bounces nor lifts; the
 * lever arm r - u/2 differs from r by u/2r = 5e-5, below the tolerances (0.3%). */
#include "simtest.h"

static const char *scene =
    "name: rolling\n"
    "dimension: 3\n"
    "materials:\n"
    "  ball: {density: 2500, kn: 1.0e6, kt: 1.0e6, restitution: 0.3, friction: 0.3}\n"
    "particles:\n"
    "  - {material: ball, radius: 0.01, position: [0, 0, 0.01], velocity: [1, 0, 0]}\n"
    "walls:\n"
    "  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: ball}\n"
    "integrator: {dt: auto, frac: 0.05}\n"
    "contact: {allow_initial_overlap: true}\n" /* pressed in at equilibrium */
    "run: {duration: 1}\n"
    "output: {energy_every: 0}\n";

static void roll(int dim) {
  const double g = 9.81, mu = 0.3, v0 = 1.0, r = 0.01;
  double kI = dim == 3 ? 0.4 : 0.5;
  char d[32], z[64];
  snprintf(d, sizeof d, "dimension=%d", dim);
  /* static overlap m g / kn */
  double m =
      dim == 3 ? 4.0 / 3.0 * ESF_PI * r * r * r * 2500 : ESF_PI * r * r * 1.0 * 2500;
  snprintf(z, sizeof z, "particles.0.position=[0, 0, %.17g]", r - m * g / 1.0e6);
  const char *sets[] = {d, z};
  simtest T;
  if (simtest_open(&T, scene, sets, 2)) {
    CHECK(0, "scene failed");
    return;
  }
  esf_particles *p = &T.s.p;
  double t_roll_exact = v0 / (mu * g * (1.0 + 1.0 / kI));
  double v_roll_exact = v0 / (1.0 + kI);
  double t_roll = -1;
  while (T.s.t < 3 * t_roll_exact) {
    if (simtest_step(&T)) break;
    double lever = p->x[2];                  /* distance to the plane: r - u */
    double slip = p->v[0] - p->w[1] * lever; /* contact point speed (w_y > 0 rolls +x) */
    if (t_roll < 0 && slip < 1e-3 * v0) t_roll = T.s.t;
  }
  char what[64];
  snprintf(what, sizeof what, "%dD rolling speed / v0", dim);
  CHECK_NEAR(p->v[0] / v0, v_roll_exact / v0, 3e-3 * v_roll_exact, what);
  snprintf(what, sizeof what, "%dD time to rolling", dim);
  CHECK_NEAR(t_roll, t_roll_exact, 3e-3 * t_roll_exact, what);
  CHECK(fabs(p->v[1]) < 1e-12 && fabs(p->w[0]) < 1e-9 && fabs(p->w[2]) < 1e-9,
        "%dD: motion stays in the x-z plane", dim);
  printf(
      "%dD: rolling speed %.6f v0 (exact %.6f), rolling from t = %.6f s (exact %.6f)\n",
      dim, p->v[0] / v0, v_roll_exact / v0, t_roll, t_roll_exact);
  simtest_close(&T);
}

int main(void) {
  roll(3);
  roll(2);
  return check_finish("test_rolling");
}
