/* test_timestep.c — the critical-step rules give the seeds' values, dt: auto applies
 * FRAC, and a dt above the chosen rule's critical value is refused unless the scene
 * allows it (docs/physics.md#time-step). Scene: two materials, the softer particle
 * material sets m_min; the stiffest pair (particle-wall) sets k_max. */
#include "simtest.h"

static const char *scene =
    "name: dt\n"
    "materials:\n"
    "  a: {density: 2000, kn: 2.0e5, kt: 1.0e5, restitution: 0.5}\n"
    "  b: {density: 8000, kn: 4.0e5, kt: 4.0e5, restitution: 0.9}\n"
    "  w: {kn: 8.0e5, kt: 1.0e5, restitution: 0.5}\n"
    "mixing: {kn: harmonic, kt: harmonic, restitution: min}\n"
    "particles:\n"
    "  - {material: a, radius: 0.002, position: [0, 0, 0.01]}\n"
    "  - {material: b, radius: 0.003, position: [0.01, 0, 0.01]}\n"
    "walls:\n"
    "  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: w}\n"
    "integrator: {dt: auto, dt_rule: hart, frac: 0.1}\n"
    "run: {steps: 1}\n"
    "output: {energy_every: 0}\n";

/* The Hertz-Mindlin rules (docs/physics.md#time-step), by hand: two particle
 * materials and a wall material; the smallest particle (a, r = 2 mm) sets m_min and its
 * radius; k is the largest tangent stiffness at the peak overlap of an impact at
 * impact_speed (a pair of two such particles, or one on the wall); rayleigh the
 * smallest pi r sqrt(rho/G)/(0.1631 nu + 0.8766) over the particles; collision the
 * shortest Hertz contact time of those impacts. */
static const char *hscene =
    "name: dt_hertz\n"
    "materials:\n"
    "  a: {density: 2000, youngs_modulus: 1.0e8, poisson_ratio: 0.25, restitution: 0.5}\n"
    "  b: {density: 8000, youngs_modulus: 2.0e9, poisson_ratio: 0.3, restitution: 0.9}\n"
    "  w: {youngs_modulus: 5.0e9, poisson_ratio: 0.2, restitution: 0.5}\n"
    "particles:\n"
    "  - {material: a, radius: 0.002, position: [0, 0, 0.01]}\n"
    "  - {material: b, radius: 0.003, position: [0.01, 0, 0.01]}\n"
    "walls:\n"
    "  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: w}\n"
    "integrator: {dt: auto, dt_rule: hart, frac: 0.1, impact_speed: 2.0}\n"
    "run: {steps: 1}\n"
    "output: {energy_every: 0}\n";

static double estar(double e1, double n1, double e2, double n2) {
  return 1.0 / ((1 - n1 * n1) / e1 + (1 - n2 * n2) / e2);
}
static double gstar(double e1, double n1, double e2, double n2) {
  return 1.0 / (2 * (2 - n1) * (1 + n1) / e1 + 2 * (2 - n2) * (1 + n2) / e2);
}

static void hertz_rules(void) {
  simtest T;
  if (simtest_open(&T, hscene, NULL, 0)) {
    CHECK(0, "Hertz scene");
    return;
  }
  const double m = 4.0 / 3.0 * ESF_PI * 8e-9 * 2000, r = 0.002, v = 2.0;
  const double E[3] = {1e8, 2e9, 5e9}, nu[3] = {0.25, 0.3, 0.2};
  double k = 0, tc = INFINITY;
  for (int a = 0; a < 2; a++) /* particle materials */
    for (int b = 0; b < 3; b++) {
      const double es = estar(E[a], nu[a], E[b], nu[b]),
                   gs = gstar(E[a], nu[a], E[b], nu[b]);
      const double ms = b == 2 ? m : m / 2, rs = b == 2 ? r : r / 2;
      const double up = pow(15 * ms * v * v / (16 * es * sqrt(rs)), 0.4);
      k = fmax(k, fmax(2 * es, 8 * gs) * sqrt(rs * up));
      tc = fmin(tc, 2.868 * pow(ms * ms / (rs * es * es * v), 0.2));
    }
  double ray = INFINITY;
  const double rad[2] = {0.002, 0.003}, rho[2] = {2000, 8000};
  for (int i = 0; i < 2; i++) {
    const double G = E[i] / (2 * (1 + nu[i]));
    ray = fmin(ray, ESF_PI * rad[i] * sqrt(rho[i] / G) / (0.1631 * nu[i] + 0.8766));
  }
  const esf_dt_estimate *e = &T.s.dte;
  CHECK_NEAR(e->k_max, k, 1e-12 * k, "Hertz: k_max at the peak overlap");
  CHECK_NEAR(e->crit[ESF_DT_HART], 2 * sqrt(m / (2 * k)), 1e-12 * sqrt(m / k),
             "Hertz: hart");
  CHECK_NEAR(e->crit[ESF_DT_RAYLEIGH], ray, 1e-12 * ray, "Hertz: rayleigh");
  CHECK_NEAR(e->crit[ESF_DT_COLLISION], tc, 1e-12 * tc, "Hertz: collision");
  CHECK_NEAR(T.s.dt, 0.1 * 2 * sqrt(m / (2 * k)), 1e-12 * sqrt(m / k), "Hertz: dt auto");
  printf("Hertz: k_max %.6g N/m, hart %.6g s, rayleigh %.6g s, collision %.6g s\n", k,
         2 * sqrt(m / (2 * k)), ray, tc);
  simtest_close(&T);
  const char *sets[] = {"integrator.dt_rule=rayleigh", "integrator.frac=0.2"};
  if (simtest_open(&T, hscene, sets, 2) == 0) {
    CHECK_NEAR(T.s.dt, 0.2 * ray, 1e-12 * ray, "Hertz: dt auto with rayleigh");
    simtest_close(&T);
  }
  /* the linear scene: no Rayleigh time; collision the half period pi sqrt(m/2k) */
  if (simtest_open(&T, scene, NULL, 0) == 0) {
    CHECK(isinf(T.s.dte.crit[ESF_DT_RAYLEIGH]), "linear: no rayleigh rule");
    const double kl = T.s.dte.k_max, ml = T.s.dte.m_min;
    CHECK_NEAR(T.s.dte.crit[ESF_DT_COLLISION], ESF_PI * sqrt(ml / (2 * kl)),
               1e-12 * sqrt(ml / kl), "linear: collision");
    simtest_close(&T);
  }
}

int main(void) {
  simtest T;
  if (simtest_open(&T, scene, NULL, 0)) return check_finish("test_timestep");
  /* by hand: m_min = 4/3 pi (0.002)^3 2000; k_max = harmonic(4e5, 8e5) = 5.333e5 (b-w) */
  double m_min = 4.0 / 3.0 * ESF_PI * 8e-9 * 2000;
  double k_max = 2 * 4e5 * 8e5 / (4e5 + 8e5);
  double l = log(0.5), gamma = -l / sqrt(ESF_PI * ESF_PI + l * l);
  double cund = sqrt(m_min / k_max);           /* 000 (3-27) with FRAC = 1 */
  double hart = 2 * sqrt(m_min / (2 * k_max)); /* 004 (2.48) */
  double damp =
      2 * sqrt(m_min / k_max) * (sqrt(1 + gamma * gamma) - gamma); /* 001 3.66 */
  const esf_dt_estimate *e = &T.s.dte;
  CHECK_NEAR(e->m_min, m_min, 1e-15 * m_min, "m_min");
  CHECK_NEAR(e->k_max, k_max, 1e-9 * k_max, "k_max");
  CHECK_NEAR(e->xi, gamma, 1e-12, "damping ratio (eta = 0.5)");
  CHECK_NEAR(e->crit[ESF_DT_CUNDALL], cund, 1e-12 * cund, "cundall");
  CHECK_NEAR(e->crit[ESF_DT_HART], hart, 1e-12 * hart, "hart");
  CHECK_NEAR(e->crit[ESF_DT_DAMPED], damp, 1e-12 * damp, "damped");
  CHECK_NEAR(T.s.dt, 0.1 * hart, 1e-12 * hart, "dt auto = frac x hart");
  printf("m_min %.6g kg, k_max %.6g N/m, xi %.4f: cundall %.6g s, hart %.6g s, damped "
         "%.6g s\n",
         m_min, k_max, gamma, cund, hart, damp);
  simtest_close(&T);

  /* each rule with dt: auto */
  const char *rules[] = {"cundall", "hart", "damped"};
  double crit[] = {cund, hart, damp};
  for (int r = 0; r < 3; r++) {
    char s1[64];
    snprintf(s1, sizeof s1, "integrator.dt_rule=%s", rules[r]);
    const char *sets[] = {s1, "integrator.frac=0.25"};
    if (simtest_open(&T, scene, sets, 2)) continue;
    CHECK_NEAR(T.s.dt, 0.25 * crit[r], 1e-12 * crit[r], rules[r]);
    simtest_close(&T);
  }

  /* a dt above the rule's critical step is refused with the figures, unless allowed */
  char s1[64];
  snprintf(s1, sizeof s1, "integrator.dt=%.17g", 1.01 * hart);
  const char *bad[] = {s1};
  int rc = simtest_open(&T, scene, bad, 1);
  CHECK(rc == ESF_EINPUT, "dt above critical must be refused (rc %d)", rc);
  CHECK(strstr(T.err.msg, "critical step") && strstr(T.err.msg, "allow_unstable"),
        "message names the critical step and the way out: %s", T.err.msg);
  simtest_close(&T);
  const char *ok[] = {s1, "integrator.allow_unstable=true"};
  rc = simtest_open(&T, scene, ok, 2);
  CHECK(rc == 0, "allow_unstable accepts it (rc %d)", rc);
  simtest_close(&T);
  snprintf(s1, sizeof s1, "integrator.dt=%.17g", 0.99 * hart);
  const char *below[] = {s1};
  rc = simtest_open(&T, scene, below, 1);
  CHECK(rc == 0, "dt just below critical is accepted (rc %d)", rc);
  simtest_close(&T);
  hertz_rules();
  return check_finish("test_timestep");
}
