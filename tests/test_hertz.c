/* test_hertz.c — the Hertz-Mindlin law (docs/physics.md#hertz-mindlin-law) against
 * numbers: head-on impacts of two unequal spheres and of a sphere on a plane wall of
 * another material, on the fused leapfrog step (checked to be the one taken), at
 * impact speeds 0.05, 0.5 and 5 m/s:
 *   - restitution equal to the requested e in {0.1, 0.3, 0.5, 0.7, 0.9, 0.95} within
 *     1% (the exact map of hertz_map.c, the no-tension cut included);
 *   - undamped (e = 1): contact time 2.868 (m*^2 / (R* E*^2 v))^(1/5) (Johnson 1985,
 *     11.24) and peak overlap (15 m* v^2 / (16 E* sqrt(R*)))^(2/5) within 1%, E* and
 *     R* computed here from the materials (E*: 1/((1 - nu1^2)/E1 + (1 - nu2^2)/E2));
 *   - the map itself: e(gamma(e)) = e to 1e-9, and gamma = 0 gives e = 1;
 *   - the tangential force record: a contact pressed harder without tangential motion
 *     keeps its tangential force bit for bit, while the stiffness 8 G* sqrt(R* u) grew;
 *     an increment adds S_t vt dt.
 * The step is frac = 0.003 of the hart rule at the stiffness of the impact's peak
 * overlap (integrator.impact_speed set to the impact speed). */
#include "contact/contact_hertz.h"
#include "fused/fused.h"
#include "simtest.h"

static const double E1 = 1e9, NU1 = 0.3, E2 = 3e9, NU2 = 0.25;

/* One impact: pair (wall 0) or wall (1), speed v, requested restitution eta (1: none).
 * Returns the measured restitution; *dur the force duration, *umax the peak overlap,
 * and the closed forms' values. */
static const char *method_ = NULL; /* an integrator.method override, or NULL */
static const char *extra_ = NULL;  /* one more override, or NULL */
static const char *extra2_ = NULL; /* and another, or NULL (with extra_) */

static double impact_at(int wall, double v, double vimp, double eta, double *dur,
                        double *umax, double *t_ref, double *u_ref) {
  char yaml[2048];
  const double r0 = 0.005, r1 = 0.004, gap = 1e-5;
  if (wall)
    snprintf(yaml, sizeof yaml,
             "name: hertz_wall\n"
             "gravity: [0, 0, 0]\n"
             "materials: {ball: {density: 2500, youngs_modulus: %g, poisson_ratio: %g,\n"
             "                   restitution: %.17g, friction: 0.3},\n"
             "            plate: {density: 7800, youngs_modulus: %g, poisson_ratio: %g,\n"
             "                    restitution: %.17g, friction: 0.3}}\n"
             "particles:\n"
             "  - {material: ball, radius: %g, position: [0, 0, %.17g], velocity: [0, 0, "
             "%.17g]}\n"
             "walls:\n"
             "  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: plate}\n"
             "integrator: {dt: auto, frac: 0.003, impact_speed: %.17g}\n"
             "run: {duration: 1}\n"
             "output: {energy_every: 0}\n",
             E1, NU1, eta, E2, NU2, eta, r0, r0 + gap, -v, vimp);
  else
    snprintf(
        yaml, sizeof yaml,
        "name: hertz_pair\n"
        "gravity: [0, 0, 0]\n"
        "materials: {ball: {density: 2500, youngs_modulus: %g, poisson_ratio: %g,\n"
        "                   restitution: %.17g, friction: 0.3},\n"
        "            bead: {density: 7800, youngs_modulus: %g, poisson_ratio: %g,\n"
        "                   restitution: %.17g, friction: 0.3}}\n"
        "particles:\n"
        "  - {material: ball, radius: %g, position: [%.17g, 0, 0], velocity: [%.17g, "
        "0, 0]}\n"
        "  - {material: bead, radius: %g, position: [%.17g, 0, 0], velocity: [%.17g, "
        "0, 0]}\n"
        "integrator: {dt: auto, frac: 0.003, impact_speed: %.17g}\n"
        "run: {duration: 1}\n"
        "output: {energy_every: 0}\n",
        E1, NU1, eta, E2, NU2, eta, r0, -r0 - gap / 2, 0.5 * v, r1, r1 + gap / 2,
        -0.5 * v, v);
  simtest T;
  char set[96];
  snprintf(set, sizeof set, "integrator.method=%s", method_ ? method_ : "leapfrog");
  const char *sets[] = {set, extra_, extra2_};
  if (simtest_open(&T, yaml, sets, extra_ ? (extra2_ ? 3 : 2) : 1)) {
    CHECK(0, "scene failed");
    return NAN;
  }
#ifndef ESF_MINIMAL /* a minimal build sends the Hertz law to the general path */
  if (!method_)
    CHECK(esf_fused_eligible(&T.s), "the fused step takes the Hertz scene (%s)",
          esf_fused_refusal(&T.s));
#endif
  esf_particles *p = &T.s.p;
  const double es = 1.0 / ((1 - NU1 * NU1) / E1 + (1 - NU2 * NU2) / E2);
  const double ms =
      wall ? p->mass[0] : p->mass[0] * p->mass[1] / (p->mass[0] + p->mass[1]);
  const double rs = wall ? r0 : r0 * r1 / (r0 + r1);
  *t_ref = 2.868 * pow(ms * ms / (rs * es * es * v), 0.2);
  *u_ref = pow(15.0 * ms * v * v / (16.0 * es * sqrt(rs)), 0.4);
  double t_first = -1, t_last = -1, t_sep = -1;
  *umax = 0;
  for (long n = 0; n < 400000; n++) {
    if (simtest_step(&T)) break;
    double un =
        wall ? p->radius[0] - p->x[2] : p->radius[0] + p->radius[1] - (p->x[3] - p->x[0]);
    *umax = fmax(*umax, un);
    CHECK_OK(esf_sim_forces_sync(&T.s, &T.err), T.err);
    int force = fabs(p->f[0]) + fabs(p->f[2]) > 0;
    if (force && t_first < 0) t_first = T.s.t - T.s.dt;
    if (force) t_last = T.s.t - T.s.dt;
    if (t_first >= 0 && t_sep < 0 && *umax > 1e-3 * *u_ref && un <= 0) t_sep = T.s.t;
    if (t_sep > 0 && T.s.t - t_sep > 0.2 * *t_ref) break;
  }
  CHECK(t_sep > 0, "the impact ended");
  *dur = t_last - t_first + T.s.dt;
  double v_out = wall ? p->v[2] : p->v[3] - p->v[0];
  simtest_close(&T);
  return v_out / v;
}

static double impact(int wall, double v, double eta, double *dur, double *umax,
                     double *t_ref, double *u_ref) {
  return impact_at(wall, v, v, eta, dur, umax, t_ref, u_ref);
}

/* The pair table of one Hertz material "ball" (E1, NU1, restitution 0.5, friction
 * 0.5) into mt, whose mixing and options the caller set. */
static void ball_table(esf_materials *mt) {
  esf_material m = {.name = "ball",
                    .density = 2500,
                    .youngs_modulus = E1,
                    .poisson_ratio = NU1,
                    .restitution = 0.5,
                    .tangential_restitution = 0.5,
                    .friction = 0.5,
                    .tensile_limit = -1};
  esf_error err;
  esf_error_clear(&err);
  int32_t idx;
  CHECK_OK(esf_materials_add(mt, &m, &idx, &err), err);
  CHECK_OK(esf_materials_mix(mt, &err), err);
}

/* The force record: xi is the force; pressing harder keeps it. */
static void record_case(void) {
  esf_materials mt = {0};
  esf_mixing_default(&mt.mixing);
  ball_table(&mt);
  const esf_pair_params *pp = &mt.pair[0];
  CHECK(pp->law == &esf_contact_hertz, "a Hertz material pair uses the Hertz law");
  const double gs = 1.0 / (4 * (2 - NU1) * (1 + NU1) / E1);
  CHECK_NEAR(pp->gstar, gs, 1e-15 * gs, "G* of equal materials E/(4 (2 - nu)(1 + nu))");
  CHECK_NEAR(pp->estar, E1 / (2 * (1 - NU1 * NU1)), 1e-6, "E* of equal materials");
  esf_contact_in in = {.n = {0, 0, 1},
                       .un = 1e-5,
                       .vc = {1e-3, 0, 0},
                       .spin_n = 0,
                       .mstar = 1e-3,
                       .rstar = 2.5e-3,
                       .dt = 1e-6,
                       .vinc = NULL};
  esf_contact_hist h0 = {{0, 0, 0}, {0, 0, 1}}, h1, h2;
  esf_contact_out o1, o2;
  esf_contact_hertz_eval(pp, 0.0, ESF_TFRAME_ROTATE, &in, &h0, 0, &h1, &o1);
  const double st1 = pp->ht * sqrt(in.rstar * in.un);
  CHECK_NEAR(h1.xi[0], st1 * 1e-3 * 1e-6, 1e-14 * st1 * 1e-9,
             "the increment S_t vt dt, S_t = 8 G* sqrt(R* u)");
  CHECK(o1.sliding == 0, "sticking");
  /* pressed to four times the overlap, approaching, no tangential motion */
  in.un = 4e-5;
  in.vc[0] = 0.0;
  in.vc[2] = -1e-3;
  esf_contact_hertz_eval(pp, 0.0, ESF_TFRAME_ROTATE, &in, &h1, 0, &h2, &o2);
  CHECK(memcmp(h2.xi, h1.xi, sizeof h1.xi) == 0,
        "pressed harder without tangential motion: the force record unchanged");
  CHECK(o2.ft[0] == h1.xi[0] && o2.ft[1] == 0 && o2.ft[2] == 0,
        "the tangential force kept: %.17g (was %.17g)", o2.ft[0], h1.xi[0]);
  CHECK(o2.w_st < 0, "the stiffer spring holds less energy at the same force (%.3g J)",
        o2.w_st);
  const double st2 = pp->ht * sqrt(in.rstar * in.un);
  CHECK_NEAR(o2.e_el_t, 0.5 * h1.xi[0] * h1.xi[0] / st2, 1e-15 * o2.e_el_t,
             "elastic energy |F|^2 / (2 S_t)");
  esf_materials_release(&mt);
}

/* contact.hertz_damping: constant: the dashpot 2 gamma sqrt(m* S_n(u_p)) (u_p the
 * undamped peak overlap at impact_speed, gamma its own exact map) from the first touch,
 * its force c v there; the requested restitution within 1% at impact_speed (0.05, 0.5,
 * 5 m/s), and the speed dependence away from it (printed). */
static void constant_case(void) {
  esf_materials mt = {0};
  esf_mixing_default(&mt.mixing);
  mt.hertz_constant = 1;
  mt.impact_speed = 0.5;
  ball_table(&mt);
  const esf_pair_params *pp = &mt.pair[0];
  const double ms = 1e-3, rs = 2.5e-3, v = 0.5, es = pp->estar;
  const double up = pow(15 * ms * v * v / (16 * es * sqrt(rs)), 0.4);
  const double c = 2 * esf_hertz_gamma_form(0.5, 1) * sqrt(ms * 2 * es * sqrt(rs * up));
  esf_contact_in in = {.n = {0, 0, 1},
                       .un = 1e-15,
                       .vc = {0, 0, -v},
                       .spin_n = 0,
                       .mstar = ms,
                       .rstar = rs,
                       .dt = 1e-6,
                       .vinc = NULL};
  esf_contact_hist h0 = {{0, 0, 0}, {0, 0, 1}};
  esf_contact_out o;
  esf_contact_hertz_eval(pp, 0.0, ESF_TFRAME_ROTATE, &in, &h0, 1, NULL, &o);
  CHECK_NEAR(o.fd_n, c * v, 1e-12 * c * v,
             "constant dashpot: c v at first touch, c = 2 gamma sqrt(m* S_n(u_p))");
  esf_materials_release(&mt);
  extra_ = "contact.hertz_damping=constant";
  for (int j = 0; j < 3; j++) {
    double dur, umax, tr, ur;
    const double vv[] = {0.05, 0.5, 5.0};
    const double e = impact(1, vv[j], 0.5, &dur, &umax, &tr, &ur);
    char what[96];
    snprintf(what, sizeof what, "constant dashpot, v = impact_speed = %g: e = 0.5",
             vv[j]);
    CHECK_NEAR(e, 0.5, 0.01 * 0.5, what);
    printf("constant dashpot, impact_speed = v = %g, requested e=0.50: measured %.5f\n",
           vv[j], e);
  }
  extra_ = "contact.hertz_damping=constant";
  for (int j = 0; j < 2; j++) { /* impact_speed 0.5 m/s, the impact at 0.05 and 5 */
    double dur, umax, tr, ur;
    const double vv[] = {0.05, 5.0};
    const double e = impact_at(1, vv[j], 0.5, 0.5, &dur, &umax, &tr, &ur);
    printf("constant dashpot, impact_speed 0.5 m/s, impact at %g m/s, requested e=0.50: "
           "measured %.5f\n",
           vv[j], e);
  }
  extra_ = NULL;
}

int main(void) {
  /* the map */
  CHECK_NEAR(esf_hertz_restitution(0.0), 1.0, 1e-9, "undamped: e = 1");
  const double es[] = {0.1, 0.3, 0.5, 0.7, 0.9, 0.95};
  for (int i = 0; i < 6; i++) {
    const double g = esf_hertz_gamma(es[i]);
    CHECK_NEAR(esf_hertz_restitution(g), es[i], 1e-9, "e(gamma(e))");
    printf("e = %.2f: gamma = %.6f (linear formula %.6f)\n", es[i], g,
           esf_restitution_gamma(es[i]));
  }
  record_case();
  const double vs[] = {0.05, 0.5, 5.0};
  for (int wall = 0; wall < 2; wall++)
    for (int j = 0; j < 3; j++) {
      double dur, umax, tr, ur;
      const double e = impact(wall, vs[j], 1.0, &dur, &umax, &tr, &ur);
      char what[96];
      snprintf(what, sizeof what, "%s v=%g undamped contact time", wall ? "wall" : "pair",
               vs[j]);
      CHECK_NEAR(dur, tr, 0.01 * tr, what);
      snprintf(what, sizeof what, "%s v=%g peak overlap", wall ? "wall" : "pair", vs[j]);
      CHECK_NEAR(umax, ur, 0.01 * ur, what);
      snprintf(what, sizeof what, "%s v=%g undamped restitution", wall ? "wall" : "pair",
               vs[j]);
      CHECK_NEAR(e, 1.0, 0.01, what);
      printf("%s v=%g: e=%.5f, contact time %.6g s (closed form %.6g, %+.3f%%), peak "
             "overlap %.6g m (%.6g, %+.3f%%)\n",
             wall ? "wall" : "pair", vs[j], e, dur, tr, 100 * (dur / tr - 1), umax, ur,
             100 * (umax / ur - 1));
      for (int i = 0; i < 6; i++) {
        const double m = impact(wall, vs[j], es[i], &dur, &umax, &tr, &ur);
        snprintf(what, sizeof what, "%s v=%g e=%.2f restitution", wall ? "wall" : "pair",
                 vs[j], es[i]);
        CHECK_NEAR(m, es[i], 0.01 * es[i], what);
        printf("%s v=%g: requested e=%.2f, measured %.5f (%+.3f%%)\n",
               wall ? "wall" : "pair", vs[j], es[i], m, 100 * (m / es[i] - 1));
      }
    }
  /* the ODE methods (the same law through forces.c): fixed-step rk4, and adaptive
     Dormand-Prince at its fixed step (rtol 0) */
  const char *ode[] = {"rk4", "erk:ARKODE_DORMAND_PRINCE_7_4_5"};
  for (int q = 0; q < 2; q++) {
    method_ = ode[q];
    for (int wall = 0; wall < 2; wall++) {
      double dur, umax, tr, ur;
      const double m = impact(wall, 0.5, 0.3, &dur, &umax, &tr, &ur);
      char what[96];
      snprintf(what, sizeof what, "%s %s e=0.3 restitution", ode[q],
               wall ? "wall" : "pair");
      CHECK_NEAR(m, 0.3, 0.01 * 0.3, what);
      printf("%s %s v=0.5: requested e=0.30, measured %.5f\n", ode[q],
             wall ? "wall" : "pair", m);
    }
  }
  /* adaptive Dormand-Prince with root-finding: steps end at onset and at the no-tension
     cut (roots.c's Hertz event) */
  method_ = ode[1];
  extra_ = "integrator.rtol=1e-7";
  extra2_ = "integrator.roots=true";
  for (int wall = 0; wall < 2; wall++) {
    double dur, umax, tr, ur;
    const double m = impact(wall, 0.5, 0.3, &dur, &umax, &tr, &ur);
    char what[96];
    snprintf(what, sizeof what, "adaptive DP5 with roots, %s e=0.3 restitution",
             wall ? "wall" : "pair");
    CHECK_NEAR(m, 0.3, 0.01 * 0.3, what);
    printf("%s v=0.5, adaptive DP5 with roots: requested e=0.30, measured %.5f\n",
           wall ? "wall" : "pair", m);
  }
  extra_ = extra2_ = NULL;
  method_ = NULL;
  constant_case();
  return check_finish("hertz");
}
