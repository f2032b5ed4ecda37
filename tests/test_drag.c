/* test_drag.c — the one-way fluid force (docs/physics.md#fluid-force, drag.c).
 *
 * 1. Radial field: p - p_e, grad p and the Darcy velocity at r = 0.3 m and 1.7 m of a
 *    well (r_w 0.09 m, r_e 200 m, drop 15 MPa, k 1.8e-10 m^2, mu 0.0135 Pa s) against
 *    eq. 4.1 and Darcy's law; no force inside the well.
 * 2. A sphere at rest in that field: the force esf_forces_eval adds equals
 *    V beta/(1 - eps) u - V grad p with the Ergun beta written out here; before the
 *    start time, none.
 * 3. Terminal velocity in a uniform upward flow U with the hydrostatic gradient
 *    grad p = rho_f g (buoyancy): the slip w = U - v solves
 *      (A w + B w^2) / (1 - eps) = (rho_p - rho_f) g,
 *      A = 150 (1 - eps)^2 mu / (eps d^2), B = 1.75 (1 - eps) rho_f / d,
 *    in closed form; leapfrog, verlet and rk4 reach it within 1e-6 (relative).
 *    Wen-Yu (eps = 0.9): the balance solved here by bisection; within 1e-6.
 * 4. Porosity grid: a 6^3 simple cubic lattice (solid fraction pi/6) binned into 3^3
 *    cells of 2 x 2 x 2 spheres gives 1 - pi/6 in every cell to 1e-12, and the same
 *    force as the fixed porosity 1 - pi/6.
 * 5. Energy: with drag on, the balance residual stays below 1e-6 of the fluid work
 *    in the terminal runs (1e-4 for velocity Verlet, whose trapezoidal quadrature of
 *    the powers is second order) and below 2% of |work_fluid| + work_walls in a confined
 * packing drilled and then drawn into the well by the radial field (0.44-0.6 s). */
#include "loads/drag.h"
#include "servo_box.h"
#include "simtest.h"

static const char *const radial =
    "name: radial\n"
    "gravity: [0, 0, 0]\n"
    "materials: {m: {density: 2650, kn: 1.0e6}}\n"
    "particles:\n"
    "  - {material: m, radius: 0.005, position: [0.3, 0, 0]}\n"
    "fluid:\n"
    "  start: 0.001\n"
    "  porosity: 0.35\n"
    "  viscosity: 0.0135\n"
    "  density: 850\n"
    "  permeability: 1.8e-10\n"
    "  radial: {center: [0, 0, 0], axis: [0, 1, 0], well_radius: 0.09, "
    "drainage_radius: 200, pressure_drop: 15.0e6}\n"
    "integrator: {dt: 1.0e-6}\n"
    "run: {duration: 0.01}\n"
    "output: {energy_every: 0}\n";

static void radial_field(void) {
  simtest T;
  if (simtest_open(&T, radial, NULL, 0)) {
    CHECK(0, "radial scene opens");
    return;
  }
  const esf_drag *d = T.s.drag;
  double L = log(200 / 0.09), dp = 15e6, k = 1.8e-10, mu = 0.0135;
  const double rs[2] = {0.3, 1.7};
  for (int j = 0; j < 2; j++) {
    double r = rs[j], x[3] = {r * cos(0.7), 5.0, r * sin(0.7)}, p, g[3], u[3];
    int on = esf_drag_field(d, x, &p, g, u);
    CHECK(on == 1, "field acts at r = %g", r);
    CHECK_NEAR(p, -dp * log(200 / r) / L, 1e-9 * dp, "p - p_e");
    double gr = dp / (L * r);
    CHECK_NEAR(g[0], gr * cos(0.7), 1e-12 * gr, "grad p x");
    CHECK_NEAR(g[1], 0, 1e-12 * gr, "grad p along the axis");
    CHECK_NEAR(g[2], gr * sin(0.7), 1e-12 * gr, "grad p z");
    double ur = -k / mu * gr;
    CHECK_NEAR(u[0], ur * cos(0.7), 1e-12 * fabs(ur), "Darcy u x (toward the well)");
    CHECK_NEAR(u[2], ur * sin(0.7), 1e-12 * fabs(ur), "Darcy u z");
    printf("radial field at r = %g m: p - p_e = %.6g Pa, |grad p| = %.6g Pa/m, |u| = "
           "%.6g m/s\n",
           r, p, gr, fabs(ur));
  }
  double x[3] = {0.05, 0, 0}, p, g[3], u[3];
  CHECK(esf_drag_field(d, x, &p, g, u) == 0 && g[0] == 0 && u[0] == 0,
        "no field inside the well");

  /* the force on the sphere at rest, before and after the start time */
  esf_sim *s = &T.s;
  double fz0[3];
  int rc =
      esf_forces_eval(s, s->p.x, s->p.v, s->p.w, s->dt, ESF_FORCES_TRIAL, NULL, &T.err);
  v3_copy(fz0, s->p.f);
  CHECK(rc == 0 && v3_norm(fz0) == 0, "no fluid force before start: |F| = %g",
        v3_norm(fz0));
  s->t = 0.001;
  rc = esf_forces_eval(s, s->p.x, s->p.v, s->p.w, s->dt, ESF_FORCES_TRIAL, NULL, &T.err);
  double R = 0.005, V = 4.0 / 3.0 * ESF_PI * R * R * R, e = 0.35, dpart = 2 * R;
  double gr = dp / (L * 0.3), ur = -k / mu * gr; /* along +x */
  double beta = 150 * (1 - e) * (1 - e) / e * mu / (dpart * dpart) +
                1.75 * (1 - e) * 850 / dpart * fabs(ur);
  double fx = V * beta / (1 - e) * ur - V * gr;
  CHECK(rc == 0, "evaluation");
  CHECK_NEAR(s->p.f[0], fx, 1e-12 * fabs(fx), "radial force on a sphere at rest");
  CHECK(fabs(s->p.f[1]) + fabs(s->p.f[2]) < 1e-12 * fabs(fx), "no other component");
  printf(
      "sphere at rest at r = 0.3 m: F = %.8g N (formula %.8g N; pressure part %.6g N)\n",
      s->p.f[0], fx, -V * gr);
  simtest_close(&T);
}

static const char *const uniform =
    "name: terminal\n"
    "gravity: [0, 0, -9.81]\n"
    "materials: {m: {density: 2650, kn: 1.0}}\n"
    "particles:\n"
    "  - {material: m, radius: 0.001, position: [0, 0, 0]}\n"
    "fluid:\n"
    "  porosity: 0.4\n"
    "  viscosity: 1.0e-3\n"
    "  density: 1000\n"
    "  uniform: {velocity: [0, 0, 0.01], pressure_gradient: [0, 0, -9810]}\n"
    "integrator: {method: leapfrog, dt: 2.0e-5}\n"
    "run: {duration: 0.3}\n"
    "output: {energy_every: 1.0e-3}\n";

/* Wen-Yu balance residual for slip w (independent of drag.c's arrangement) */
static double wenyu_balance(double w, double e, double d, double mu, double rf,
                            double rp) {
  double re = e * rf * w * d / mu;
  double cd = re < 1000 ? 24 / re * (1 + 0.15 * pow(re, 0.687)) : 0.44;
  double beta = 0.75 * cd * e * (1 - e) * rf * w / d * pow(e, -2.65);
  return beta * w / (1 - e) - (rp - rf) * 9.81;
}

static void terminal(const char *method, double eps) {
  char m[64], por[64];
  snprintf(m, sizeof m, "integrator.method=%s", method);
  snprintf(por, sizeof por, "fluid.porosity=%g", eps);
  const char *sets[] = {m, por};
  simtest T;
  if (simtest_open(&T, uniform, sets, 2)) {
    CHECK(0, "terminal scene opens (%s)", method);
    return;
  }
  esf_sim *s = &T.s;
  double d = 0.002, mu = 1e-3, rf = 1000, rp = 2650, U = 0.01, w;
  if (eps < 0.8) {
    double A = 150 * (1 - eps) * (1 - eps) * mu / (eps * d * d),
           B = 1.75 * (1 - eps) * rf / d;
    double c = (1 - eps) * (rp - rf) * 9.81;
    w = (-A + sqrt(A * A + 4 * B * c)) / (2 * B);
  } else {
    double lo = 1e-9, hi = 10;
    for (int it = 0; it < 200; it++) {
      double mid = 0.5 * (lo + hi);
      if (wenyu_balance(mid, eps, d, mu, rf, rp) > 0)
        hi = mid;
      else
        lo = mid;
    }
    w = 0.5 * (lo + hi);
  }
  double vt = U - w;
  int rc = 0;
  /* relaxation times: 0.011 s (Ergun, eps 0.4), about 0.04 s (Wen-Yu, eps 0.9) */
  double t_end = eps < 0.8 ? 0.3 : 1.2;
  while (!rc && s->t < t_end - 1e-9) rc = simtest_step(&T);
  CHECK(rc == 0, "terminal run (%s)", method);
  double vz = s->p.v[2];
  CHECK_NEAR(vz, vt, 1e-6 * fabs(vt), "terminal velocity");
  double res = esf_ledger_total_error(&s->led), wf = s->led.w_fluid;
  /* the leapfrog's and rk4's balances are exact to rounding here; velocity Verlet
     integrates the powers by the trapezoidal rule, second order: (dt/tau)^2 ~ 3e-6 */
  double tol = strcmp(method, "verlet") == 0 ? 1e-4 : 1e-6;
  CHECK(fabs(res) < tol * fabs(wf),
        "ledger closes with drag (%s): residual %.3g J, "
        "work_fluid %.6g J",
        method, res, wf);
  printf("terminal velocity (%s, eps %.2f%s): %.9g m/s, closed form %.9g m/s; "
         "work_fluid %.6g J, balance residual %.3g J\n",
         method, eps, eps < 0.8 ? " Ergun" : " Wen-Yu", vz, vt, wf, res);
  simtest_close(&T);
}

/* a servo-confined packing (test_servo.c's), drilled at 0.45 s, the radial field from
   0.46 s toward the drilled hole (axis y through x = z = 0.02) */
static const char *const sandbox =
    "name: sandbox\n"
    "gravity: [0, 0, -9.81]\n"
    "materials: {m: {density: 2500, kn: 1.0e6, restitution: 0.2, friction: "
    "0.0}}\n" SERVO_BOX_YAML
    "events: [{at: 0.45, delete: {cylinder: {center: [0.02, 0.02, 0.02], axis: [0, 1, "
    "0], radius: 0.008}}}]\n"
    "fluid:\n"
    "  start: 0.46\n"
    "  porosity: 0.4\n" SERVO_BOX_RADIAL_FLOW "damping: {global: {translation: 20}}\n"
    "run: {duration: 1}\n"
    "output: {energy_every: 1.0e-3}\n";

static void sandbox_ledger(void) {
  simtest T;
  if (simtest_open(&T, sandbox, NULL, 0)) {
    CHECK(0, "sandbox opens");
    return;
  }
  esf_sim *s = &T.s;
  int rc = 0;
  while (!rc && s->t < 0.44) rc = simtest_step(&T);
  esf_ledger L0 = s->led;
  double r0 = esf_ledger_total_error(&L0);
  while (!rc && s->t < 0.6) rc = simtest_step(&T);
  CHECK(rc == 0, "sandbox run");
  const esf_ledger *L = &s->led;
  double r1 = esf_ledger_total_error(L), wf = L->w_fluid, ww = L->w_walls - L0.w_walls;
  double scale = fabs(wf) + fabs(ww) + (L->e_removed - L0.e_removed);
  CHECK(wf > 0, "the fluid does positive work drawing spheres to the well: %g J", wf);
  CHECK(fabs(r1 - r0) < 0.02 * scale,
        "balance with servo, drilling and drag: residual change %.4g J against %.4g J",
        r1 - r0, scale);
  printf("sandbox 0.44-0.6 s: work_fluid %.6g J, servo wall work %.6g J, removed %.6g J; "
         "balance residual changed by %.4g J (%.2g%%)\n",
         wf, ww, L->e_removed - L0.e_removed, r1 - r0, 100 * fabs(r1 - r0) / scale);
  simtest_close(&T);
}

/* a simple cubic lattice (solid fraction pi/6) of 6 x 6 x 6 spheres, r 5 mm, spacing
   10 mm, in a uniform flow: cells of 20 mm hold 8 whole spheres each */
static const char *const lattice =
    "name: lattice\n"
    "gravity: [0, 0, 0]\n"
    "materials: {m: {density: 2650, kn: 1.0}}\n"
    "particles:\n"
    "  - {generate: lattice, region: {min: [0, 0, 0], max: [0.06, 0.06, 0.06]}, radius: "
    "0.005, spacing: 0.01, material: m}\n"
    "fluid:\n"
    "  porosity: {cell: 0.02}\n"
    "  viscosity: 1.0e-3\n"
    "  density: 1000\n"
    "  uniform: {velocity: [0, 0, 0.05], pressure_gradient: [0, 0, -100]}\n"
    "integrator: {dt: 1.0e-4}\n"
    "run: {steps: 1}\n"
    "output: {energy_every: 0}\n";

static void porosity_grid(void) {
  simtest T;
  if (simtest_open(&T, lattice, NULL, 0)) {
    CHECK(0, "lattice opens");
    return;
  }
  esf_sim *s = &T.s;
  const esf_porosity_grid *g = &s->drag->pg;
  double want = 1 - ESF_PI / 6;
  CHECK(s->p.n == 216, "216 spheres, got %zu", s->p.n);
  CHECK(g->nc[0] == 3 && g->nc[1] == 3 && g->nc[2] == 3, "3 x 3 x 3 cells, got %d %d %d",
        g->nc[0], g->nc[1], g->nc[2]);
  CHECK_NEAR(g->eps_min, want, 1e-12, "lowest cell void fraction 1 - pi/6");
  CHECK_NEAR(g->eps_max, want, 1e-12, "highest cell void fraction 1 - pi/6");
  /* the force with the grid equals the force with the fixed value 1 - pi/6 */
  int rc =
      esf_forces_eval(s, s->p.x, s->p.v, s->p.w, s->dt, ESF_FORCES_TRIAL, NULL, &T.err);
  double fg = s->p.f[2];
  CHECK(rc == 0 && fg > 0, "grid force evaluates: %g N", fg);
  s->drag->grid = 0;
  s->drag->porosity = want;
  rc = esf_forces_eval(s, s->p.x, s->p.v, s->p.w, s->dt, ESF_FORCES_TRIAL, NULL, &T.err);
  CHECK_NEAR(fg, s->p.f[2], 1e-12 * fabs(fg),
             "grid porosity force = fixed 1 - pi/6 force");
  printf(
      "porosity grid: 216 spheres on a cubic lattice, 27 cells of 20 mm, void fraction "
      "%.15g .. %.15g (1 - pi/6 = %.15g); force %.10g N both ways\n",
      g->eps_min, g->eps_max, want, fg);
  simtest_close(&T);
}

int main(void) {
  porosity_grid();
  sandbox_ledger();
  radial_field();
  terminal("leapfrog", 0.4);
  terminal("verlet", 0.4);
  terminal("rk4", 0.4);
  terminal("leapfrog", 0.9);
  return check_finish("drag");
}
