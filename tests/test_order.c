/* test_order.c — the leapfrog is second order on a smooth problem: a sphere resting on
 * a plane under gravity, released from 1.5 times its static overlap, oscillates while
 * always in contact (undamped: eta = 1, no friction). Exact solution, with
 * w = sqrt(kn/m), u_eq = m g / kn, amplitude A = u_eq/2:
 *   z(t) = r - u_eq - A cos(w t).
 * The largest position error over 5 periods must fall as dt^2: the fitted slope of
 * log(error) against log(dt) is within 0.3 of 2. */
#include "simtest.h"

static const char *scene =
    "name: spring\n"
    "materials: {b: {density: 2500, kn: 1.0e5, restitution: 1.0, friction: 0.0}}\n"
    "particles:\n"
    "  - {material: b, radius: 0.01, position: [0, 0, 0.01]}\n"
    "walls:\n"
    "  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: b}\n"
    "integrator: {dt: 1.0e-5}\n"
    "run: {steps: 1}\n"
    "output: {energy_every: 0}\n";

static double max_error(int steps_per_period, double *dt_out) {
  const double r = 0.01, kn = 1.0e5, g = 9.81;
  double m = 4.0 / 3.0 * ESF_PI * r * r * r * 2500;
  double w = sqrt(kn / m), ueq = m * g / kn, A = 0.5 * ueq;
  double T = 2 * ESF_PI / w, dt = T / steps_per_period;
  char sdt[64], sz[80];
  snprintf(sdt, sizeof sdt, "integrator.dt=%.17g", dt);
  snprintf(sz, sizeof sz, "particles.0.position=[0, 0, %.17g]", r - ueq - A);
  const char *sets[] = {sdt, sz};
  simtest T_;
  if (simtest_open(&T_, scene, sets, 2)) return NAN;
  double worst = 0;
  for (int n = 0; n < 5 * steps_per_period; n++) {
    if (simtest_step(&T_)) return NAN;
    double t = T_.s.t;
    double z = r - ueq - A * cos(w * t);
    worst = fmax(worst, fabs(T_.s.p.x[2] - z));
  }
  simtest_close(&T_);
  *dt_out = dt;
  return worst / A;
}

int main(void) {
  const int spp[] = {20, 40, 80, 160, 320};
  double lx[5], ly[5];
  for (int k = 0; k < 5; k++) {
    double dt = 0;
    double e = max_error(spp[k], &dt);
    lx[k] = log(dt);
    ly[k] = log(e);
    printf("steps/period %4d: dt = %.4g s, max |z error| / amplitude = %.4g\n", spp[k],
           dt, e);
  }
  double mx = 0, my = 0, sxx = 0, sxy = 0;
  for (int k = 0; k < 5; k++) {
    mx += lx[k] / 5;
    my += ly[k] / 5;
  }
  for (int k = 0; k < 5; k++) {
    sxx += (lx[k] - mx) * (lx[k] - mx);
    sxy += (lx[k] - mx) * (ly[k] - my);
  }
  double slope = sxy / sxx;
  printf("observed order: %.3f\n", slope);
  CHECK_NEAR(slope, 2.0, 0.3, "leapfrog order");
  return check_finish("test_order");
}
