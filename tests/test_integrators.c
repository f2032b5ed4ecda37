/* test_integrators.c — every fixed-step scheme shows its nominal order on a smooth
 * problem: a sphere resting on a plane under gravity, released from 1.5 times its static
 * overlap, oscillates while always in contact (linear spring, no dashpot, no friction),
 *   u(t) - u_eq = A e^{-a t/2} (cos(wd t) + a/(2 wd) sin(wd t)),  wd^2 = w^2 - a^2/4,
 * undamped (a = 0) and with global viscous damping a = 0.2 w (a force term for the
 * Runge-Kutta methods, the (1 -+ a dt/2) form in the leapfrog). The slope of
 * log(max position error over two periods) against log(dt) must be within 0.3 of the
 * order (0.1 for Ralston's third-order method typed in as integrator.table). Step counts
 * per period are chosen per order so that the errors stay between the asymptotic range's
 * top and round-off. */
#include "simtest.h"

static const char *scene =
    "name: spring\n"
    "materials: {b: {density: 2500, kn: 1.0e5, restitution: 1.0, friction: 0.0}}\n"
    "particles:\n"
    "  - {material: b, radius: 0.01, position: [0, 0, 0.01]}\n"
    "walls:\n"
    "  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: b}\n"
    "integrator: {dt: 1.0e-5}\n"
    "contact: {allow_initial_overlap: true}\n" /* pressed in at equilibrium */
    "run: {steps: 1}\n"
    "output: {energy_every: 0}\n";

static double max_error(const char *method, const char *table, int spp, double damp) {
  const double r = 0.01, kn = 1.0e5, g = 9.81;
  double m = 4.0 / 3.0 * ESF_PI * r * r * r * 2500;
  double w = sqrt(kn / m), ueq = m * g / kn, A = 0.5 * ueq, a = damp * w;
  double wd = sqrt(w * w - 0.25 * a * a);
  double T = 2 * ESF_PI / w, dt = T / spp;
  char s1[96], s2[96], s3[96], s4[96];
  snprintf(s1, sizeof s1, "integrator.dt=%.17g", dt);
  snprintf(s2, sizeof s2, "particles.0.position=[0, 0, %.17g]", r - ueq - A);
  snprintf(s3, sizeof s3, "integrator.method=%s", method);
  snprintf(s4, sizeof s4, "damping={global: {translation: %.17g, rotation: 0}}", a);
  const char *sets[] = {s1, s2, s3, s4, table};
  simtest T_;
  if (simtest_open(&T_, scene, sets, table ? 5 : 4)) return NAN;
  double worst = 0;
  for (int n = 0; n < 2 * spp; n++) {
    if (simtest_step(&T_)) return NAN;
    double t = T_.s.t;
    double u = ueq + A * exp(-0.5 * a * t) * (cos(wd * t) + 0.5 * a / wd * sin(wd * t));
    worst = fmax(worst, fabs(T_.s.p.x[2] - (r - u)));
  }
  simtest_close(&T_);
  return worst / A;
}

typedef struct scheme {
  const char *method;
  int order;
  int spp[4];
  const char *table; /* method erk: integrator.table */
  double tol;        /* of the slope; 0: 0.3 */
} scheme;

/* Ralston's third-order method (Ralston 1962, the minimum error bound choice), typed
 * into the scene: within 0.1 of order 3. */
static const char *const ralston3 =
    "integrator.table={c: [0, 1/2, 3/4], A: [[], [1/2], [0, 3/4]], b: [2/9, 1/3, 4/9], "
    "order: 3}";

int main(void) {
  const scheme sch[] = {
      {"leapfrog", 2, {40, 80, 160, 320}, NULL, 0},
      {"verlet", 2, {40, 80, 160, 320}, NULL, 0},
      {"erk:ARKODE_HEUN_EULER_2_1_2", 2, {40, 80, 160, 320}, NULL, 0},
      {"erk:ARKODE_BOGACKI_SHAMPINE_4_2_3", 3, {40, 80, 160, 320}, NULL, 0},
      {"rk4", 4, {20, 40, 80, 160}, NULL, 0},
      {"erk:ARKODE_ZONNEVELD_5_3_4", 4, {20, 40, 80, 160}, NULL, 0},
      {"erk:ARKODE_DORMAND_PRINCE_7_4_5", 5, {20, 30, 45, 68}, NULL, 0},
      {"erk:ARKODE_VERNER_8_5_6", 6, {12, 17, 24, 34}, NULL, 0},
      {"erk:ARKODE_FEHLBERG_13_7_8", 8, {8, 11, 16, 22}, NULL, 0},
      {"erk", 3, {40, 80, 160, 320}, ralston3, 0.1},
  };
  for (size_t k = 0; k < sizeof sch / sizeof *sch; k++) {
    for (int d = 0; d < 2; d++) {
      double damp = d ? 0.2 : 0.0;
      double lx[4], ly[4], mx = 0, my = 0;
      for (int j = 0; j < 4; j++) {
        double e = max_error(sch[k].method, sch[k].table, sch[k].spp[j], damp);
        lx[j] = -log((double)sch[k].spp[j]);
        ly[j] = log(e);
        mx += lx[j] / 4;
        my += ly[j] / 4;
      }
      double sxx = 0, sxy = 0;
      for (int j = 0; j < 4; j++) {
        sxx += (lx[j] - mx) * (lx[j] - mx);
        sxy += (lx[j] - mx) * (ly[j] - my);
      }
      double slope = sxy / sxx;
      printf("%-36s %s: errors %.2e .. %.2e, observed order %.2f (nominal %d)\n",
             sch[k].table ? "erk (Ralston 3, integrator.table)" : sch[k].method,
             d ? "damped  " : "undamped", exp(ly[0]), exp(ly[3]), slope, sch[k].order);
      char what[96];
      snprintf(what, sizeof what, "%s %s order", sch[k].method,
               d ? "damped" : "undamped");
      CHECK_NEAR(slope, (double)sch[k].order, sch[k].tol > 0 ? sch[k].tol : 0.3, what);
    }
  }
  return check_finish("test_integrators");
}
