/* test_ledger.c — the energy ledger closes on a settling pack with friction and
 * damping. Every dissipation path is tallied independently (dashpots and global and
 * local damping with the mid-step velocity, for which the leapfrog's kinetic-energy
 * change is exact; Coulomb slip as force x slip), so the residual is not zero by
 * construction: it is the integrator's own energy error at contact onsets and ends,
 * sliding, and the frame rotation of the tangential springs. For these packs at FRAC
 * 0.1 it stays below 1% of the energy dissipated (measured figures are printed); the
 * bound holds because those errors are O((w dt)^2) per contact event and do not
 * accumulate systematically. The Hertz-Mindlin packs close to the same level once the
 * tangential springs' stiffness changes (work_tangential_stiffness) are booked; without
 * that column their residual is 4% of the dissipated energy (leapfrog; 18% for rk4 with
 * the history as state); Verlet and rk4 close as they do for the linear law (measured).
 */
#include "simtest.h"

static const char *pack =
    "name: settle\n"
    "materials:\n"
    "  g: {density: 2500, kn: 1.0e4, kt: 7.0e3, restitution: 0.4,\n"
    "      tangential_restitution: 0.6, friction: 0.5}\n"
    "  wallmat: {kn: 2.0e4, restitution: 0.3, friction: 0.3}\n"
    "particles:\n"
    "  - {generate: random, region: {min: [0, 0, 0.0], max: [0.03, 0.03, 0.09]}, count: "
    "300,\n"
    "     radius: {uniform: [0.0012, 0.0022]}, material: g, seed: 9}\n"
    "walls:\n"
    "  - {box: {min: [0, 0, 0], max: [0.03, 0.03, 0.1]}, open: [top], material: "
    "wallmat}\n"
    "integrator: {dt: auto, frac: 0.1}\n"
    "damping: {global: {translation: 2.0, rotation: 2.0}}\n"
    "run: {steps: 1}\n"
    "output: {energy_every: 1.0e-9}\n";

static void settle(const char *label, const char *const *sets, int nsets, int want_local,
                   int want_global, double bound) {
  simtest T;
  if (simtest_open(&T, pack, sets, nsets)) {
    CHECK(0, "%s: scene failed", label);
    return;
  }
  long steps = 12000;
  for (long n = 0; n < steps; n++)
    if (simtest_step(&T)) break;
  const esf_ledger *L = &T.s.led;
  double D = esf_ledger_dissipated(L), R = esf_ledger_total_error(L);
  printf(
      "%s: t = %.3f s, dissipated %.4g J (normal %.3g, tangential %.3g, friction %.3g, "
      "global %.3g, local %.3g), kinetic %.3g J, residual %.3g J = %.3g of "
      "dissipated\n",
      label, T.s.t, D, L->d_normal, L->d_tangential, L->d_friction, L->d_global,
      L->d_local, L->kin_t + L->kin_r, R, R / D);
  if (strncmp(label, "Hertz", 5) == 0)
    CHECK(fabs(L->w_stiff) > bound * D,
          "%s: the stiffness column carries more than the bound (%.3g J)", label,
          L->w_stiff);
  if (L->w_stiff != 0)
    printf("%s: work_tangential_stiffness %.4g J (the residual without it: %.3g of "
           "dissipated)\n",
           label, L->w_stiff, (R + L->w_stiff) / D);
  /* the Coulomb slip and, for the Hertz law, the tangential springs' stiffness changes
     together: their split depends on dt at contact onsets (docs/physics.md#hertz-mindlin-
     law); for the linear law w_stiff = 0 */
  CHECK(L->d_normal > 0 && L->d_tangential > 0 && L->d_friction - L->w_stiff > 0,
        "%s: every contact path dissipates", label);
  CHECK(want_global ? L->d_global > 0 : L->d_global == 0, "%s: global damping tally",
        label);
  CHECK(want_local ? L->d_local > 0 : L->d_local == 0, "%s: local damping tally", label);
  CHECK(fabs(R) < bound * D,
        "%s: |residual| %.3g J must stay below %.0f%% of the %.3g J dissipated", label, R,
        100 * bound, D);
  simtest_close(&T);
}

/* Issue 3, test 4: Dormand-Prince 5(4) with the adaptive controller at a loose
 * tolerance on the same pack to the same time: most steps are limited by the DEM
 * stability bound (ERKStepSetStabilityFn; ARKODE takes at most half of it, its CFL
 * fraction, which erk.c states), no step exceeds that, the run stays stable
 * (completes without a failure) and its ledger closes (1% of the dissipated energy). */
static void adaptive_at_limit(const char *history, double bound) {
  char hs[48];
  snprintf(hs, sizeof hs, "integrator.history=%s", history);
  const char *sets[] = {"integrator.method=erk:ARKODE_DORMAND_PRINCE_7_4_5",
                        "integrator.rtol=1e-3", "integrator.atol=1e-6", hs};
  simtest T;
  if (simtest_open(&T, pack, sets, 4)) {
    CHECK(0, "DP5 %s: scene failed", history);
    return;
  }
  double t_end = 0.063, h_max = 0;
  esf_integ_stats st = {0};
  int rc = 0;
  while (!rc && T.s.t < t_end * (1 - 1e-12)) {
    rc = T.it->step(&T.s, T.ist, t_end, &T.err);
    T.it->stats(&T.s, T.ist, &st);
    h_max = fmax(h_max, st.h_last);
  }
  CHECK(rc == 0, "DP5 %s: the run completes (%s)", history, T.err.msg);
  const esf_ledger *L = &T.s.led;
  double D = esf_ledger_dissipated(L), R = esf_ledger_total_error(L);
  printf("DP5 adaptive, rtol 1e-3, history %s: %ld steps (%ld limited by stability, %ld "
         "by accuracy), %ld rejected, %ld rhs, %ld restarts; h_max %.4g s, h_stab %.4g s "
         "(leapfrog dt %.4g s); residual %.3g J = %.3g of the %.4g J dissipated\n",
         history, st.steps, st.stab_limited, st.acc_limited, st.rejected, st.rhs_evals,
         st.restarts, h_max, st.h_stab, T.s.dt, R, R / D, D);
  CHECK(st.h_stab > 0 && h_max <= 0.5 * st.h_stab * (1 + 1e-9),
        "DP5 %s: no step above the stability bound (%.4g > %.4g)", history, h_max,
        st.h_stab);
  CHECK(st.stab_limited > st.steps / 2,
        "DP5 %s: most steps at the stability limit "
        "(%ld of %ld)",
        history, st.stab_limited, st.steps);
  CHECK(fabs(R) < bound * D, "DP5 %s: |residual| %.3g J below %.0f%% of %.3g J", history,
        R, 100 * bound, D);
  simtest_close(&T);
}

int main(void) {
  settle("global damping", NULL, 0, 0, 1, 0.01);
  const char *loc[] = {"damping.global.translation=0", "damping.global.rotation=0",
                       "damping.local={coefficient: 0.3, form: component}"};
  settle("local damping (component)", loc, 3, 1, 0, 0.01);
  const char *vec[] = {"damping.global.translation=0", "damping.global.rotation=0",
                       "damping.local={coefficient: 0.3, form: vector}"};
  settle("local damping (vector)", vec, 3, 1, 0, 0.01);
  const char *aut[] = {"damping.global.auto=true"};
  settle("adaptive global damping", aut, 1, 0, 1, 0.01);
  const char *prj[] = {"contact.tangential_frame=project"};
  settle("projected tangential frame", prj, 1, 0, 1, 0.01);
  /* The Hertz-Mindlin law (contact_hertz.c): the tangential springs' stiffness changes
     under a carried force are booked in work_tangential_stiffness; without it the
     residual would hold them */
  const char *hz[] = {
      "materials.g={density: 2500, youngs_modulus: 2.0e7, poisson_ratio: "
      "0.3, restitution: 0.4, tangential_restitution: 0.6, friction: 0.5}",
      "materials.wallmat={youngs_modulus: 4.0e7, poisson_ratio: 0.25, "
      "restitution: 0.3, friction: 0.3}"};
  settle("Hertz-Mindlin", hz, 2, 0, 1, 0.01);
  const char *hzp[] = {hz[0], hz[1], "contact.tangential_frame=project"};
  settle("Hertz-Mindlin, projected frame", hzp, 3, 0, 1, 0.01);
  /* The other integrators' ledgers: a regression guard for the slip work, which was
     once booked twice outside the leapfrog (residual 35% of dissipated). rk4 with the
     trapezoidal history carry closes like the leapfrog (measured 0.03%); Verlet's
     trapezoidal quadrature of dashpot powers that jump at every contact onset is first
     order (measured 1.5% at FRAC 0.1), hence 3% for it. */
  const char *vv[] = {"integrator.method=verlet"};
  settle("verlet", vv, 1, 0, 1, 0.03);
  const char *rk[] = {"integrator.method=rk4"};
  settle("rk4 (frozen history)", rk, 1, 0, 1, 0.01);
  const char *hzv[] = {hz[0], hz[1], "integrator.method=verlet"};
  settle("Hertz-Mindlin, verlet", hzv, 3, 0, 1, 0.03);
  const char *hzr[] = {hz[0], hz[1], "integrator.method=rk4"};
  settle("Hertz-Mindlin, rk4 (frozen history)", hzr, 3, 0, 1, 0.01);
  const char *hzs[] = {hz[0], hz[1], "integrator.method=rk4", "integrator.history=state"};
  settle("Hertz-Mindlin, rk4 (history as state)", hzs, 4, 0, 1, 0.01);
  adaptive_at_limit("frozen", 0.01);
  adaptive_at_limit("state", 0.01);
  return check_finish("test_ledger");
}
