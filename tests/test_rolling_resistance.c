/* test_rolling_resistance.c — rolling and twisting resistance
 * (docs/physics.md#rolling-resistance) against closed forms, for a sphere (r, m,
 * I = 2/5 m r^2) on a plane, fn = m g cos(theta), R* = r:
 *   cdt, rolling without slip on a level plane (leapfrog, velocity Verlet): the torque
 *     mu_r r m g against the spin decelerates the centre at (5/7) mu_r g (m a = -F,
 *     I a/r = F r - mu_r r m g); a 2D disk (I = 1/2 m r^2) at (2/3) mu_r g;
 *   epsd on an incline of angle theta (gravity tilted): at rest while tan(theta) < mu_r
 *     (the spring holds m g r sin(theta) <= mu_r r m g cos(theta)), rolling above at
 *     a = (5/7) g (sin(theta) - mu_r cos(theta)) (the torque at its limit, no dashpot);
 *   twisting (both models) about the normal: w(t) = w0 - (5/2) mu_tw g t / r;
 *   the energy ledger closes with rolling (a rolling sphere; spheres dropped);
 *   a scene with mu_r = mu_tw = 0 keeps no rolling state;
 *   with the Hertz-Mindlin law (E 1e10 Pa, nu 0.3): the cdt plane, and the epsd
 *     incline at rest with the elastic displacement la^2 F / k_r + F / S_t, k_r from
 *     S_n = 2 E* sqrt(r u) at the static overlap, and rolling above the limit; the
 *     ledger of the dropped spheres (the rolling springs' stiffness change booked in
 *     work_tangential_stiffness);
 *   the live stability check's top mode is the twisting spring's (mu_tw = 1, no
 *   dashpots): w^2 = k_tw / I = 5.625 kn mu_tw^2 / m (normal kn/m, tangential-rolling
 *   3.5 kt/m). The sphere starts at its static overlap m g / kn (u/r ~ 1e-5). */
#include "model/stability.h"
#include "simtest.h"

static const char *scene =
    "name: rolling_resistance\n"
    "dimension: 3\n"
    "materials:\n"
    "  ball: {density: 2500, kn: 1.0e6, kt: 1.0e6, restitution: 0.3, friction: 0.5,\n"
    "         rolling_friction: 0.1, rolling_damping: 0.5}\n"
    "particles:\n"
    "  - {material: ball, radius: 0.01, position: [0, 0, 0.01]}\n"
    "walls:\n"
    "  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: ball}\n"
    "integrator: {dt: auto, frac: 0.1}\n"
    "contact: {allow_initial_overlap: true, rolling: epsd}\n"
    "run: {duration: 1}\n"
    "output: {energy_every: 0}\n";

static const double g = 9.81, r = 0.01, rho = 2500, kn = 1.0e6;

static int dim_ = 3; /* the scenes' dimension: 3 spheres, 2 disks (thickness 1 m) */

/* hertz_: the ball (and the plane) Hertz-Mindlin, E = 1e10 Pa, nu = 0.3, so that
 * E* = E/(2(1 - nu^2)), G* = E/(4(2 - nu)(1 + nu)), R* = r; k_r = 2.25 S_n mu_r^2 r^2
 * with S_n = 2 E* sqrt(r u) at the static overlap u. */
static int hertz_ = 0;
static const double E_h = 1.0e10, nu_h = 0.3;
static const char *const hertz_ball =
    "materials.ball={density: 2500, youngs_modulus: 1.0e10, poisson_ratio: 0.3, "
    "restitution: 0.3, friction: 0.5, rolling_friction: 0.1, rolling_damping: 0.5}";

static double mass(void) {
  return dim_ == 3 ? 4.0 / 3.0 * ESF_PI * r * r * r * rho : ESF_PI * r * r * rho;
}

static double estar(void) { return E_h / (2.0 * (1.0 - nu_h * nu_h)); }

/* The static overlap under a normal load f: f / kn, or Hertz's (3 f / (4 E*
 * sqrt(r)))^(2/3). */
static double overlap(double f) {
  return hertz_ ? pow(3.0 * f / (4.0 * estar() * sqrt(r)), 2.0 / 3.0) : f / kn;
}

/* Opens the scene with the sphere at its static overlap under gravity g (cos th) and
 * the extra overrides. */
static int open_sphere(simtest *T, double th, const char *const *extra, int nextra) {
  char z[96], gr[128], d[32];
  const double u = overlap(mass() * g * cos(th));
  snprintf(d, sizeof d, "dimension=%d", dim_);
  snprintf(z, sizeof z, "particles.0.position=[0, 0, %.17g]", r - u);
  snprintf(gr, sizeof gr, "gravity=[%.17g, 0, %.17g]", g * sin(th), -g * cos(th));
  const char *sets[10] = {z, gr, d};
  int ns = 3;
  if (hertz_) sets[ns++] = hertz_ball;
  for (int k = 0; k < nextra && k < 6; k++) sets[ns++] = extra[k];
  return simtest_open(T, scene, sets, ns);
}

/* The ledger of a single rolling sphere: the rolling resistance's dissipation and the
 * residual, which stays at rounding level (no impacts). */
static void ledger_closes(const simtest *T, const char *what, double tol) {
  const esf_ledger *L = &T->s.led;
  const double D = esf_ledger_dissipated(L), R = esf_ledger_total_error(L);
  CHECK(L->d_rolling > 0.9 * D, "%s: the rolling resistance dissipates (%.3g of %.3g J)",
        what, L->d_rolling, D);
  CHECK(fabs(R) < tol * D, "%s: the ledger closes: total_error %.3g J against %.3g J",
        what, R, D);
  printf("%s ledger: dissipated %.6g J (rolling %.6g J), stored rolling %.3g J, "
         "total_error %.3g J\n",
         what, D, L->d_rolling, L->el_r, R);
}

/* Type A: a sphere rolling without slip at v0 on a level plane (the leapfrog, or
 * velocity Verlet, whose ledger integrates the powers by the trapezoidal rule). */
static void cdt_plane(const char *method) {
  const double mu_r = 0.1, v0 = 1.0, kI = dim_ == 3 ? 0.4 : 0.5; /* I = kI m r^2 */
  const double a = mu_r * g / (1.0 + kI); /* sphere (5/7) mu_r g, disk (2/3) mu_r g */
  char w[96], me[64];
  snprintf(me, sizeof me, "integrator.method=%s", method);
  /* rolling without slip about the contact point at the lever r - u/2 (the default
     contact.wall_lever: seed) */
  snprintf(w, sizeof w, "particles.0.angular_velocity=[0, %.17g, 0]",
           v0 / (r - 0.5 * overlap(mass() * g)));
  const char *ex[] = {"contact.rolling=cdt", "particles.0.velocity=[1, 0, 0]", w,
                      "output.energy_every=1.0e-9", me};
  simtest T;
  if (open_sphere(&T, 0, ex, 5)) {
    CHECK(0, "cdt scene failed");
    return;
  }
  const esf_particles *p = &T.s.p;
  double worst = 0;
  for (int k = 1; k <= 10; k++) { /* until v = 0.3 v0 */
    const double t = 0.1 * k * 0.7 * v0 / a;
    while (T.s.t < t)
      if (simtest_step(&T)) break;
    const double ve = v0 - a * T.s.t, dv = fabs(p->v[0] - ve) / (v0 - ve);
    if (dv > worst) worst = dv;
  }
  CHECK(worst < 0.01,
        "cdt (%s, %dD): v(t) = v0 - mu_r g t / (1 + kI) within 1%% of the change (%.2e)",
        method, dim_, worst);
  const double slip = p->v[0] - p->w[1] * p->x[2];
  CHECK(fabs(slip) < 1e-3 * v0, "cdt: still rolling without slip (%.2e m/s)", slip);
  printf("cdt (%s, %dD%s): deceleration matches mu_r g / (1 + kI) to %.2e of the speed "
         "change\n",
         method, dim_, hertz_ ? ", Hertz" : "", worst);
  /* velocity Verlet: cdt's torque sees the half-step spin, so the trapezoid over its
     power is first order (7.8e-6 of the dissipation at frac 0.1, half at 0.05) */
  ledger_closes(&T, method, strcmp(method, "leapfrog") ? 2e-5 : 1e-9);
  simtest_close(&T);
}

/* Type C on an incline: at rest for tan(theta) = 0.8 mu_r, rolling for 1.25 mu_r. */
static void epsd_incline(const char *method) {
  const double mu_r = 0.1;
  char me[64];
  snprintf(me, sizeof me, "integrator.method=%s", method);
  for (int above = 0; above < 2; above++) {
    const double th = atan((above ? 1.25 : 0.8) * mu_r);
    const char *ex[] = {"output.energy_every=1.0e-9", me};
    simtest T;
    if (open_sphere(&T, th, ex, 2)) {
      CHECK(0, "epsd scene failed");
      return;
    }
    const esf_particles *p = &T.s.p;
    double t1 = 0.2, t2 = 0.6, v1 = 0;
    while (T.s.t < t1)
      if (simtest_step(&T)) break;
    v1 = p->v[0];
    while (T.s.t < t2)
      if (simtest_step(&T)) break;
    if (!above && hertz_) { /* at rest: the rolling spring holds F la (F = m g sin th,
                               la = r - u/2) over k_r, the tangential one F over S_t:
                               x = la^2 F / k_r + F / S_t */
      const double F = mass() * g * sin(th), u = overlap(mass() * g * cos(th));
      const double a = sqrt(r * u), sn = 2.0 * estar() * a, la = r - 0.5 * u;
      const double st = 8.0 * E_h / (4.0 * (2.0 - nu_h) * (1.0 + nu_h)) * a;
      const double kr = 2.25 * sn * mu_r * mu_r * r * r, xe = la * la * F / kr + F / st;
      CHECK_NEAR(p->x[0], xe, 1e-3 * xe,
                 "epsd (Hertz): the elastic displacement at rest");
      printf("epsd (%s, Hertz) at tan(theta) = 0.8 mu_r: x = %.6g m (closed form %.6g, "
             "k_r = %.4g N m/rad from S_n = %.4g N/m), v = %.3g m/s after %.1f s\n",
             method, p->x[0], xe, kr, sn, p->v[0], T.s.t);
    }
    if (!above) {
      CHECK(fabs(p->x[0]) < 1e-5 && fabs(p->v[0]) < 1e-4,
            "epsd (%s): tan(theta) = 0.8 mu_r: the sphere stays (x = %.3g m, v = %.3g "
            "m/s)",
            method, p->x[0], p->v[0]);
      printf(
          "epsd (%s%s) at tan(theta) = 0.8 mu_r: x = %.3g m, v = %.3g m/s after %.1f s\n",
          method, hertz_ ? ", Hertz" : "", p->x[0], p->v[0], T.s.t);
    } else {
      const double ae = 5.0 / 7.0 * g * (sin(th) - mu_r * cos(th));
      const double am = (p->v[0] - v1) / (t2 - t1);
      CHECK_NEAR(am, ae, 0.01 * ae, "epsd: tan(theta) = 1.25 mu_r: rolling acceleration");
      const double slip = p->v[0] - p->w[1] * p->x[2];
      CHECK(fabs(slip) < 1e-3 * p->v[0], "epsd: rolls without slip (%.2e m/s)", slip);
      printf("epsd (%s%s) at tan(theta) = 1.25 mu_r: a = %.6f m/s^2 (closed form %.6f)\n",
             method, hertz_ ? ", Hertz" : "", am, ae);
      ledger_closes(&T, method, strcmp(method, "leapfrog") ? 1e-6 : 1e-9);
    }
    simtest_close(&T);
  }
}

/* Twisting: a sphere spinning about the plane's normal at w0. */
static void twisting(int cdt) {
  const double mu_tw = 0.1, w0 = 50.0, al = 2.5 * mu_tw * g / r;
  const char *ex[] = {cdt ? "contact.rolling=cdt" : "contact.rolling=epsd",
                      "materials.ball.twisting_friction=0.1",
                      "particles.0.angular_velocity=[0, 0, 50]"};
  simtest T;
  if (open_sphere(&T, 0, ex, 3)) {
    CHECK(0, "twisting scene failed");
    return;
  }
  const esf_particles *p = &T.s.p;
  const double t = 0.5 * w0 / al;
  while (T.s.t < t)
    if (simtest_step(&T)) break;
  const double we = w0 - al * T.s.t;
  CHECK_NEAR(p->w[2], we, 0.01 * (w0 - we),
             cdt ? "cdt: twisting deceleration (5/2) mu_tw g / r"
                 : "epsd: twisting deceleration (5/2) mu_tw g / r");
  printf("%s twisting: w = %.6f rad/s at t = %.4f s (closed form %.6f)\n",
         cdt ? "cdt" : "epsd", p->w[2], T.s.t, we);
  simtest_close(&T);
}

/* The ledger with rolling: spheres dropped on the plane, rolling after the impacts. */
static const char *pile =
    "name: rolling_ledger\n"
    "materials:\n"
    "  ball: {density: 2500, kn: 1.0e5, restitution: 0.5, friction: 0.4,\n"
    "         rolling_friction: 0.2, rolling_damping: 0.3, twisting_friction: 0.1}\n"
    "particles:\n"
    "  - {material: ball, radius: 0.01, position: [0, 0, 0.03], velocity: [0.5, 0.2, "
    "0],\n"
    "     angular_velocity: [3, -20, 40]}\n"
    "  - {material: ball, radius: 0.008, position: [0.002, 0.001, 0.056], "
    "angular_velocity: [10, 0, "
    "0]}\n"
    "  - {material: ball, radius: 0.012, position: [0.03, 0, 0.02], velocity: [-0.4, 0, "
    "0]}\n"
    "walls:\n"
    "  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: ball}\n"
    "integrator: {dt: auto, frac: 0.02}\n"
    "run: {duration: 1}\n"
    "output: {energy_every: 1.0e-9}\n";

static void ledger(const char *model) {
  char set[64];
  snprintf(set, sizeof set, "contact.rolling=%s", model);
  const char *sets[] = {
      set,
      "materials.ball={density: 2500, youngs_modulus: 1.0e8, poisson_ratio: 0.3, "
      "restitution: 0.5, friction: 0.4, rolling_friction: 0.2, rolling_damping: 0.3, "
      "twisting_friction: 0.1}"};
  simtest T;
  if (simtest_open(&T, pile, sets, hertz_ ? 2 : 1)) {
    CHECK(0, "ledger scene failed");
    return;
  }
  while (T.s.t < 0.4)
    if (simtest_step(&T)) break;
  const esf_ledger *L = &T.s.led;
  const double D = esf_ledger_dissipated(L), R = esf_ledger_total_error(L);
  CHECK(L->d_rolling > 1e-3 * D, "%s: rolling dissipates (%.3g J of %.3g J)", model,
        L->d_rolling, D);
  CHECK(fabs(R) < 1e-4 * D, "%s: the ledger closes: total_error %.3g J against %.3g J",
        model, R, D);
  printf("%s%s ledger: dissipated %.6g J (rolling %.6g J), stored rolling %.3g J, "
         "work_tangential_stiffness %.4g J, total_error %.3g J\n",
         model, hertz_ ? " (Hertz)" : "", D, L->d_rolling, L->el_r, L->w_stiff, R);
  simtest_close(&T);
}

/* The live stability check's top mode: the twisting spring of a sphere on the plane. */
static void stability(void) {
  const char *ex[] = {"materials.ball.twisting_friction=1",
                      "materials.ball.restitution=1", "materials.ball.rolling_damping=0"};
  simtest T;
  if (open_sphere(&T, 0, ex, 3)) {
    CHECK(0, "stability scene failed");
    return;
  }
  simtest_step(&T);
  esf_stability st;
  if (esf_stability_estimate(&T.s, T.s.dt, 1, &st, &T.err)) {
    CHECK(0, "stability estimate: %s", T.err.msg);
  } else {
    const double w2 = 5.625 * kn / mass(), lam = T.s.dt * T.s.dt * w2;
    CHECK_NEAR(st.lambda, lam, 2e-3 * lam, "stability: lambda of the twisting mode");
    printf("stability: lambda %.6g (twisting mode dt^2 k_tw/I = %.6g), omega %.6g rad/s "
           "(%.6g)\n",
           st.lambda, lam, st.omega, sqrt(w2));
  }
  simtest_close(&T);
}

/* mu_r = mu_tw = 0: no rolling state is kept. */
static void off(void) {
  const char *ex[] = {"materials.ball.rolling_friction=0"};
  simtest T;
  if (open_sphere(&T, 0, ex, 1)) {
    CHECK(0, "scene failed");
    return;
  }
  simtest_step(&T);
  CHECK(!T.s.mats.any_rolling && !T.s.nb.pp.roll && !T.s.nb.pw.roll,
        "mu_r = mu_tw = 0: no rolling state");
  simtest_close(&T);
}

int main(void) {
  cdt_plane("leapfrog");
  cdt_plane("verlet");
  cdt_plane("rk4");
  dim_ = 2; /* a disk: (2/3) mu_r g */
  cdt_plane("leapfrog");
  dim_ = 3;
  epsd_incline("leapfrog");
  epsd_incline("rk4");
  twisting(0);
  twisting(1);
  ledger("epsd");
  ledger("cdt");
  off();
  stability();
  hertz_ = 1; /* the Hertz-Mindlin law: rolling's kn is S_n at the overlap */
  cdt_plane("leapfrog");
  epsd_incline("leapfrog");
  ledger("epsd"); /* the springs' stiffness change booked (w_k): 4.4e-5 of D, 2.6e-3
                     without it */
  ledger("cdt");
  hertz_ = 0;
  return check_finish("test_rolling_resistance");
}
