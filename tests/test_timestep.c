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
  return check_finish("test_timestep");
}
