/* test_testbed.c — the integrator testbed on a head-on collision and on failures.
 * 1. Restitution, time to separation and peak overlap of a head-on pair collision
 *    (eta = 0.5, no tension) converge to the closed forms of test_collision.c for every
 *    method as dt -> 0 (fixed step) or the tolerance -> 0 (adaptive): the error at the
 *    finer setting is below the coarser one's and below 0.5%.
 * 2. A failure inside f (an overlap beyond contact.max_overlap) is retried with a
 *    smaller step by an adaptive method, and stops a fixed-step method with a message
 *    naming the particles, the time, the step size and the critical step. The impact
 *    (10 m/s on kn = 1e5 N/m) peaks at 23% of the radius, below the 50% limit: only a
 *    step far above the critical one overshoots it. */
#include "simtest.h"

typedef struct result {
  double e, t_sep, umax;
  long rhs;
} result;

static int collide(const char *const *sets, int nsets, result *r) {
  simtest T;
  const char *all[8] = {"integrator.frac=0.01"}; /* the shared scene has 0.002 */
  for (int k = 0; k < nsets && k < 7; k++) all[k + 1] = sets[k];
  if (simtest_open(&T, simtest_pair_scene, all, nsets + 1)) return -1;
  esf_particles *p = &T.s.p;
  double t_touch = -1, u_prev = -1, t_prev = 0;
  r->umax = 0;
  r->t_sep = -1;
  for (long n = 0; n < 2000000; n++) {
    if (simtest_step(&T)) {
      simtest_close(&T);
      return -1;
    }
    double u = p->radius[0] + p->radius[1] - (p->x[3] - p->x[0]);
    if (u > 0 && t_touch < 0) /* interpolate the first touch */
      t_touch = t_prev + (T.s.t - t_prev) * (0 - u_prev) / (u - u_prev);
    r->umax = fmax(r->umax, u);
    if (t_touch >= 0 && u <= 0 && r->t_sep < 0)
      r->t_sep = t_prev + (T.s.t - t_prev) * u_prev / (u_prev - u) - t_touch;
    if (r->t_sep > 0 && u < -1e-4) break;
    u_prev = u;
    t_prev = T.s.t;
  }
  r->e = (p->v[3] - p->v[0]) / 2.0;
  esf_integ_stats st = {0};
  if (T.it->stats) T.it->stats(&T.s, T.ist, &st);
  r->rhs = st.rhs_evals ? st.rhs_evals : T.s.rhs_evals;
  simtest_close(&T);
  return 0;
}

static void convergence(void) {
  /* closed forms for eta = 0.5 (gamma = 0.2155) with m* of the pair */
  double m0 = 4.0 / 3.0 * ESF_PI * 1.25e-7 * 2500,
         m1 = 4.0 / 3.0 * ESF_PI * 6.4e-8 * 2500;
  double ms = m0 * m1 / (m0 + m1), w = sqrt(1.0e5 / ms);
  cut_impact x = cut_impact_closed_form(esf_restitution_gamma(0.5), w);
  double e_x = x.e, tsep_x = x.t_sep, umax_x = 2.0 * x.u_max; /* approach speed 2 m/s */
  const char *methods[] = {"leapfrog",
                           "verlet",
                           "rk4",
                           "erk:ARKODE_BOGACKI_SHAMPINE_4_2_3",
                           "erk:ARKODE_DORMAND_PRINCE_7_4_5",
                           "erk:ARKODE_VERNER_8_5_6",
                           "erk:ARKODE_DORMAND_PRINCE_7_4_5",
                           "cvode-adams"};
  const int adaptive[] = {0, 0, 0, 0, 0, 0, 1, 1};
  for (int k = 0; k < 8; k++) {
    double err[2];
    result r[2];
    for (int j = 0; j < 2; j++) {
      char s1[96], s2[64], s3[64];
      snprintf(s1, sizeof s1, "integrator.method=%s", methods[k]);
      if (adaptive[k]) {
        snprintf(s2, sizeof s2, "integrator.rtol=%g", j ? 1e-8 : 1e-5);
        snprintf(s3, sizeof s3, "integrator.atol=%g", j ? 1e-13 : 1e-10);
      } else {
        snprintf(s2, sizeof s2, "integrator.frac=%g", j ? 0.0025 : 0.01);
        snprintf(s3, sizeof s3, "integrator.rtol=0");
      }
      const char *sets[] = {s1, s2, s3};
      if (collide(sets, 3, &r[j])) {
        CHECK(0, "%s: run failed", methods[k]);
        err[j] = NAN;
        continue;
      }
      err[j] = fmax(fabs(r[j].e / e_x - 1),
                    fmax(fabs(r[j].t_sep / tsep_x - 1), fabs(r[j].umax / umax_x - 1)));
    }
    printf("%-34s %s: e %.5f / %.5f (closed form %.5f), t_sep %.5g / %.5g (%.5g) s, "
           "u_max %.5g / %.5g (%.5g) m; worst relative error %.2e -> %.2e; rhs %ld -> "
           "%ld\n",
           methods[k], adaptive[k] ? "adaptive" : "fixed   ", r[0].e, r[1].e, e_x,
           r[0].t_sep, r[1].t_sep, tsep_x, r[0].umax, r[1].umax, umax_x, err[0], err[1],
           r[0].rhs, r[1].rhs);
    CHECK(err[1] < err[0] || err[1] < 1e-4, "%s: the error must fall (%.3g -> %.3g)",
          methods[k], err[0], err[1]);
    CHECK(err[1] < 5e-3, "%s: within 0.5%% at the fine setting (%.3g)", methods[k],
          err[1]);
  }
}

static const char *smash =
    "name: smash\n"
    "gravity: [0, 0, 0]\n"
    "materials: {glass: {density: 2500, kn: 1.0e5, restitution: 0.9, friction: 0.3}}\n"
    "particles:\n"
    "  - {material: glass, radius: 0.005, position: [0, 0, 0.0051], velocity: [0, 0, "
    "-10]}\n"
    "walls:\n"
    "  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: glass}\n"
    "integrator: {dt: 6.0e-4, allow_unstable: true}\n"
    "contact: {max_overlap: 0.5}\n"
    "run: {duration: 1.0e-3}\n"
    "output: {energy_every: 0}\n";

static void failures(void) {
  /* fixed step: stops with the promised message */
  const char *fixed[] = {"integrator.method=rk4"};
  simtest T;
  int rc = simtest_open(&T, smash, fixed, 1);
  CHECK(rc == 0, "smash scene opens");
  int failed = 0;
  for (int n = 0; n < 10 && !rc; n++) {
    rc = T.it->step(&T.s, T.ist, INFINITY, &T.err);
    if (rc) failed = 1;
  }
  CHECK(failed && rc == ESF_ENUMERIC, "a fixed-step rk4 stops (rc %d)", rc);
  CHECK(strstr(T.err.msg, "particle id 0") && strstr(T.err.msg, "step") &&
            strstr(T.err.msg, "critical dt") && strstr(T.err.msg, "t = "),
        "the message names particle, time, step and critical step: %s", T.err.msg);
  printf("fixed step: %s\n", T.err.msg);
  simtest_close(&T);
  /* adaptive: ARKODE retries with smaller steps and succeeds */
  const char *adapt[] = {"integrator.method=erk:ARKODE_DORMAND_PRINCE_7_4_5",
                         "integrator.rtol=1e-6", "integrator.atol=1e-10"};
  rc = simtest_open(&T, smash, adapt, 3);
  for (int n = 0; n < 20000 && !rc && T.s.t < 1e-3 * (1 - 1e-12); n++)
    rc = T.it->step(&T.s, T.ist, 1e-3, &T.err);
  CHECK(rc == 0, "the adaptive run recovers: %s", T.err.msg);
  esf_integ_stats st = {0};
  if (T.it && T.ist) T.it->stats(&T.s, T.ist, &st);
  CHECK(st.rejected > 0 || st.stab_limited > 0, "steps were cut (%ld rejected)",
        st.rejected);
  CHECK(T.s.p.v[2] > 0, "and the sphere rebounds (vz = %.3g m/s)", T.s.p.v[2]);
  printf("adaptive: recovered; %ld steps, %ld rejected, rebound vz = %.4g m/s\n",
         st.steps, st.rejected, T.s.p.v[2]);
  simtest_close(&T);
}

int main(void) {
  convergence();
  failures();
  return check_finish("test_testbed");
}
