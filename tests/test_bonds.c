/* test_bonds.c — the adhesive normal law and the bond rule
 * (docs/physics.md#adhesive-normal-law-and-bonds; 004 2.22–2.25) against closed forms,
 * and the block impact quick scene.
 *
 * 1. The law (F = 0.96 N, kn = 6.4e4 N/m; eps = 0.5, 1e-2, 1e-4, 1e-8): a fine scan of
 *    the elastic force f(u) over the bonded range finds the largest tension, which must
 *    be F (rel. 1e-9 after a golden-section refinement), at u* = ln(L)/alpha; f
 *    vanishes at the rupture point (u = 0 for eps < 1/e, the negative root for eps >
 *    1/e, -delta exactly for eps = 1/2) and is tensile just inside it and compressive
 *    just past it; W(u) agrees with a Simpson quadrature of f; k_max with the largest
 *    |f'| on the scan.
 * 2. Quasi-static pull of a bonded pair (velocities zero, the pair opened in steps of
 *    delta/2000 through the force loop, committing): the largest tension is F within the
 *    step's resolution, the bond breaks at the first u below u_rupture, and the force is
 *    zero after. Pushed back into overlap the pair feels kn u (linear, no adhesive term),
 *    opened again it feels no tension; thrown at each other it bounces off with the
 *    linear law's restitution (cut_impact closed form, 0.5%) — a bond would have held
 *    it (the rebound energy is far below the bond's work of separation).
 * 3. Rest: a damped bonded pair settles at the law's rest overlap: u_eq (the positive
 *    root, within delta (1 - 2e-4) and delta for eps = 1e-4) or u = 0 for eps = 1/2.
 * 4. Ledger: an undamped bonded pair oscillating in the law's well keeps the balance
 *    residual below (w dt)^2 of its energy, falling as dt^2; pulled apart faster than
 *    the well holds, it breaks once, the ledger books W(u_rupture) (2%) into
 *    dissipated_bonds and the pair leaves with the initial kinetic energy less that (2%
 *    of W), with the same residual bounds.
 * 5. block_impact-quick (scene path from the command line): bonds break (at least the
 *    bonds across the lateral faces of the columns of the target under the projectile's
 *    cross-section, 4 k layers for k x k columns) but only near the impact (no more
 *    than the bonds touching the columns under the cross-section and one ring around
 *    them, plus every projectile bond), and the projectile perforates the slab: the
 *    mean x of its original front layer ends past the slab's back face. */
#include <stdlib.h>

#include "core/bonds.h"
#include "model/model.h"
#include "simtest.h"

static const double KN = 6.4e4, FF = 0.96;

/* ---- 1. the law ----------------------------------------------------------------- */

static double tension(const esf_adhesion *a, double u) {
  return -esf_adhesion_force(KN, a, u);
}

static void law_closed_form(double eps) {
  esf_adhesion a;
  esf_error err;
  esf_error_clear(&err);
  int rc = esf_adhesion_derive(FF, eps, KN, &a, &err);
  CHECK_OK(rc, err);
  if (rc) return;
  double L = -log(eps);
  CHECK_NEAR(a.alpha * a.delta, L, 1e-12 * L, "alpha delta = -ln eps");
  /* scan the bonded range: from u_r (or, when u_r = 0, a little beyond) to u_eq + delta
   */
  double lo = a.u_rupture < 0 ? a.u_rupture : 0.0, hi = a.u_eq + a.delta;
  int N = 200000;
  double best = -INFINITY, ubest = 0, kmax = 0;
  for (int i = 0; i <= N; i++) {
    double u = lo + (hi - lo) * i / N;
    double t = tension(&a, u);
    if (t > best) best = t, ubest = u;
    double h = 1e-9 * a.delta;
    double k =
        fabs(esf_adhesion_force(KN, &a, u + h) - esf_adhesion_force(KN, &a, u - h)) /
        (2 * h);
    if (k > kmax) kmax = k;
  }
  /* golden-section refinement around the scanned peak */
  double x0 = ubest - (hi - lo) / N, x1 = ubest + (hi - lo) / N, g = 0.5 * (sqrt(5) - 1);
  for (int it = 0; it < 200; it++) {
    double c = x1 - g * (x1 - x0), d = x0 + g * (x1 - x0);
    if (tension(&a, c) > tension(&a, d))
      x1 = d;
    else
      x0 = c;
  }
  double ustar = 0.5 * (x0 + x1);
  char what[128];
  snprintf(what, sizeof what, "eps %g: largest tension", eps);
  CHECK_NEAR(tension(&a, ustar), FF, 1e-9 * FF, what);
  snprintf(what, sizeof what, "eps %g: u* = ln(L)/alpha", eps);
  CHECK_NEAR(ustar, log(L) / a.alpha, 1e-6 * a.delta, what);
  CHECK_NEAR(a.u_peak, log(L) / a.alpha, 1e-15 * a.delta, "u_peak field");
  CHECK(eps < exp(-1) ? ustar > 0 : ustar < 0, "eps %g: peak on the %s side", eps,
        eps < exp(-1) ? "overlap" : "gap");
  /* rupture point */
  double ur = a.u_rupture, h = 1e-6 * a.delta;
  snprintf(what, sizeof what, "eps %g: f(u_rupture)", eps);
  CHECK_NEAR(esf_adhesion_force(KN, &a, ur), 0.0, 1e-12 * FF, what);
  CHECK(eps < exp(-1) ? ur == 0.0 : ur < 0.0, "eps %g: u_rupture %g", eps, ur);
  CHECK(tension(&a, ur + h) > 0, "eps %g: tensile just inside rupture", eps);
  CHECK(tension(&a, ur - h) < 0, "eps %g: compressive just past rupture", eps);
  if (eps == 0.5) CHECK_NEAR(ur, -a.delta, 1e-12 * a.delta, "eps 1/2: u_r = -delta");
  if (eps < exp(-1)) {
    snprintf(what, sizeof what, "eps %g: f(u_eq)", eps);
    CHECK_NEAR(esf_adhesion_force(KN, &a, a.u_eq), 0.0, 1e-9 * FF, what);
    CHECK(tension(&a, 0.5 * (ur + a.u_eq)) > 0, "eps %g: tension between 0 and u_eq",
          eps);
  }
  /* energy against Simpson's rule from 0 */
  double targets[3] = {ur, ustar, a.u_eq + 0.5 * a.delta};
  for (int k = 0; k < 3; k++) {
    double u1 = targets[k], s = 0;
    int M = 20000;
    for (int i = 0; i <= M; i++) {
      double w = (i == 0 || i == M) ? 1 : (i % 2 ? 4 : 2);
      s += w * esf_adhesion_force(KN, &a, u1 * i / M);
    }
    s *= u1 / M / 3.0;
    snprintf(what, sizeof what, "eps %g: W(%.3g delta) vs quadrature", eps, u1 / a.delta);
    CHECK_NEAR(esf_adhesion_energy(KN, &a, u1), s, 1e-9 * fabs(s) + 1e-20, what);
  }
  snprintf(what, sizeof what, "eps %g: k_max vs the scan's largest |f'|", eps);
  CHECK_NEAR(a.k_max, fmax(KN, kmax), 1e-4 * a.k_max, what);
  printf("law eps=%-6g delta=%.6e m alpha=%.6e 1/m peak=%.12g N at u*=%+.6e m "
         "(%.4f delta), rupture u_r=%+.6e m (%.4f delta), rest u_eq=%.6e m "
         "(%.6f delta), k_max=%.4g kn, W(u_r)=%.4e J\n",
         eps, a.delta, a.alpha, tension(&a, ustar), ustar, ustar / a.delta, ur,
         ur / a.delta, a.u_eq, a.u_eq / a.delta, a.k_max / KN,
         esf_adhesion_energy(KN, &a, ur));
}

static void bad_parameters(void) {
  esf_adhesion a;
  esf_error err;
  double bad[] = {exp(-1.0), 1.0, 1.5, 0.0, -0.1};
  for (int k = 0; k < 5; k++) {
    esf_error_clear(&err);
    CHECK(esf_adhesion_derive(FF, bad[k], KN, &a, &err) == ESF_EINPUT,
          "eps %g must be refused", bad[k]);
  }
  esf_error_clear(&err);
  CHECK(esf_adhesion_derive(-1.0, 0.5, KN, &a, &err) == ESF_EINPUT, "F < 0 refused");
  esf_error_clear(&err);
  CHECK(esf_adhesion_derive(0.0, 0.5, KN, &a, &err) == 0 && a.delta == 0 && a.k_max == KN,
        "F = 0: the linear law");
}

/* ---- a bonded pair ------------------------------------------------------------------
 */

/* Two r = 5 mm spheres on the x axis at overlap u0, velocities -v and +v along x. */
static int pair_open(simtest *T, double eps, double eta, double u0, double v, double frac,
                     double energy_every) {
  char yaml[2048];
  double r = 0.005, x = r - 0.5 * u0;
  snprintf(yaml, sizeof yaml,
           "name: bpair\n"
           "gravity: [0, 0, 0]\n"
           "materials: {g: {density: 2500, kn: %.17g, kt: 9.6e3, restitution: %.17g,\n"
           "   friction_angle: 26.5, adhesion: {force: %.17g, epsilon: %.17g}}}\n"
           "particles:\n"
           "  - {material: g, radius: %.17g, position: [%.17g, 0, 0], velocity: [%.17g, "
           "0, 0]}\n"
           "  - {material: g, radius: %.17g, position: [%.17g, 0, 0], velocity: [%.17g, "
           "0, 0]}\n"
           "contact: {allow_initial_overlap: true}\n"
           "integrator: {dt: auto, frac: %.17g}\n"
           "run: {duration: 1}\n"
           "output: {energy_every: %.17g}\n",
           KN, eta, FF, eps, r, -x, -v, r, x, v, frac, energy_every);
  return simtest_open(T, yaml, NULL, 0);
}

static size_t by_id(const esf_sim *s, long long id) {
  for (size_t i = 0; i < s->p.n; i++)
    if (s->p.id[i] == id) return i;
  return 0;
}

static double overlap(const esf_sim *s) {
  size_t a = by_id(s, 0), b = by_id(s, 1);
  return s->p.radius[a] + s->p.radius[b] - (s->p.x[3 * b] - s->p.x[3 * a]);
}

/* Places the pair at overlap u (velocities zero), evaluates and commits; returns the
 * tension on particle 0 (its +x force). */
static double quasi_static(simtest *T, double u) {
  esf_sim *s = &T->s;
  size_t a = by_id(s, 0), b = by_id(s, 1);
  double r = s->p.radius[a] + s->p.radius[b];
  s->p.x[3 * a] = -0.5 * (r - u);
  s->p.x[3 * b] = 0.5 * (r - u);
  memset(s->p.v, 0, 3 * s->p.n * sizeof(double));
  memset(s->p.w, 0, 3 * s->p.n * sizeof(double));
  int rc = esf_sim_refresh(s, NULL, &T->err);
  if (!rc)
    rc = esf_forces_eval(s, s->p.x, s->p.v, s->p.w, s->dt, ESF_FORCES_COMMIT, NULL,
                         &T->err);
  CHECK_OK(rc, T->err);
  return s->p.f[3 * by_id(s, 0)];
}

static void pull_and_recontact(double eps) {
  esf_adhesion a;
  esf_error e;
  esf_adhesion_derive(FF, eps, KN, &a, &e);
  double eta = 0.5;
  simtest T;
  if (pair_open(&T, eps, eta, a.u_eq, 0.0, 0.002, 0)) {
    CHECK(0, "pair scene");
    return;
  }
  esf_sim *s = &T.s;
  double du = a.delta / 2000, peak = -INFINITY, u_break = NAN, last_bonded = NAN;
  long steps = 0;
  for (double u = a.u_eq; u > a.u_rupture - 0.5 * a.delta; u -= du, steps++) {
    double t = quasi_static(&T, u);
    if (s->bonds.broken == 0) {
      if (t > peak) peak = t;
      last_bonded = t;
    } else if (isnan(u_break)) {
      u_break = u;
      CHECK(t == 0.0, "eps %g: no force once broken (got %g N)", eps, t);
    } else {
      CHECK(t == 0.0, "eps %g: no force at u = %g after the break", eps, u);
    }
  }
  char what[96];
  CHECK(s->bonds.formed == 1, "eps %g: one bond formed (%ld)", eps, s->bonds.formed);
  CHECK(s->bonds.broken == 1, "eps %g: one bond broken (%ld)", eps, s->bonds.broken);
  /* a scan of step du misses the peak by at most |f''| (du/2)^2 / 2 = kn alpha du^2 / 8
     (|f''(u*)| = kn delta alpha^2 e^{-alpha u*} = kn alpha) */
  snprintf(what, sizeof what, "eps %g: largest tension on the pull", eps);
  double miss = KN * a.alpha * du * du / 8;
  CHECK(peak <= FF * (1 + 1e-12) && peak >= FF - miss * 1.000001 - 1e-12 * FF,
        "%s: %.12g N, F %.12g N, resolution %.3g N", what, peak, FF, miss);
  snprintf(what, sizeof what, "eps %g: breaks at the first step past u_rupture", eps);
  CHECK(u_break < a.u_rupture && u_break >= a.u_rupture - du * 1.000001,
        "%s: u_break %.9g, u_r %.9g, du %.3g", what, u_break, a.u_rupture, du);
  snprintf(what, sizeof what, "eps %g: tension at the last bonded step", eps);
  CHECK_NEAR(last_bonded, 0.0, a.k_max * du, what);
  printf("pull eps=%-6g: peak tension %.9f N (F %.2f), broke at u = %+.6e m (u_r %+.6e, "
         "step %.2e)\n",
         eps, peak, FF, u_break, a.u_rupture, du);

  /* re-contact: linear compression, no tension */
  double u1 = 0.5 * a.delta;
  double t1 = quasi_static(&T, u1);
  CHECK_NEAR(-t1, KN * u1, 1e-9 * KN * u1, "pushed back: the linear law kn u");
  double t2 = quasi_static(&T, -0.1 * a.delta);
  CHECK(t2 == 0.0, "eps %g: no tension after re-contact (got %g N)", eps, t2);
  CHECK(s->bonds.broken == 1, "no second rupture (%ld)", s->bonds.broken);

  /* thrown together: the linear law's restitution */
  size_t ia = by_id(s, 0), ib = by_id(s, 1);
  double v = 0.1, r = s->p.radius[ia] + s->p.radius[ib];
  s->p.x[3 * ia] = -0.5 * r - 1e-5;
  s->p.x[3 * ib] = 0.5 * r + 1e-5;
  s->p.v[3 * ia] = v;
  s->p.v[3 * ib] = -v;
  double mstar = 0.5 * s->p.mass[ia];
  cut_impact x = cut_impact_closed_form(esf_restitution_gamma(eta), sqrt(KN / mstar));
  int touched = 0;
  for (long n = 0; n < 400000; n++) {
    if (simtest_step(&T)) break;
    double u = overlap(s);
    if (u > 0) touched = 1;
    if (touched && u < -1e-4) break;
  }
  ia = by_id(s, 0);
  ib = by_id(s, 1);
  double e_out = (s->p.v[3 * ib] - s->p.v[3 * ia]) / (2 * v);
  snprintf(what, sizeof what, "eps %g: restitution after rupture (linear)", eps);
  CHECK(touched && overlap(s) < -1e-4, "%s: the pair separated", what);
  CHECK_NEAR(e_out, x.e, 0.005 * x.e, what);
  double w_rebound = 0.5 * mstar * pow(2 * v * e_out, 2);
  /* the work to open the bond from rest, W(u_rupture) - W(u_eq) (W(u_rupture) alone is 0
     for eps < 1/e, where u_rupture = 0) */
  double w_open =
      esf_adhesion_energy(KN, &a, a.u_rupture) - esf_adhesion_energy(KN, &a, a.u_eq);
  CHECK(w_rebound < w_open,
        "eps %g: the rebound energy %g J must be below the bond's work "
        "of separation from rest %g J",
        eps, w_rebound, w_open);
  printf(
      "recontact eps=%-6g: restitution %.5f (linear closed form %.5f), rebound %.3e J, "
      "work to open from rest %.3e J\n",
      eps, e_out, x.e, w_rebound, w_open);
  simtest_close(&T);
}

static void rest(double eps) {
  esf_adhesion a;
  esf_error e;
  esf_adhesion_derive(FF, eps, KN, &a, &e);
  double u0 = eps < exp(-1) ? 0.5 * a.u_eq : 0.5 * a.delta;
  simtest T;
  if (pair_open(&T, eps, 0.3, u0, 0.0, 0.05, 0)) {
    CHECK(0, "rest scene");
    return;
  }
  for (int n = 0; n < 4000; n++)
    if (simtest_step(&T)) break;
  double u = overlap(&T.s);
  char what[96];
  snprintf(what, sizeof what, "eps %g: rest overlap", eps);
  CHECK_NEAR(u, a.u_eq, 1e-6 * a.delta, what);
  if (eps < exp(-1))
    CHECK(a.u_eq < a.delta && a.u_eq > a.delta * (1 - 2e-4),
          "eps %g: u_eq/delta = %.8f, expected 1 - O(eps)", eps, a.u_eq / a.delta);
  CHECK(T.s.bonds.formed == 1 && T.s.bonds.broken == 0, "eps %g: bond intact", eps);
  printf("rest eps=%-6g: settled at u = %.9e m (u_eq %.9e m, delta %.9e m)\n", eps, u,
         a.u_eq, a.delta);
  simtest_close(&T);
}

/* Undamped pair opened at speed v each, dt = frac x the Hart step; returns the ledger's
 * worst balance residual over the kinetic energy E0. The leapfrog's energy measure
 * (forces.c: W(u_n) + f(u_n)(u_{n+1} - u_n)/2) is exact for a linear spring; for this
 * law the residual is the trapezoid error of each step's work, second order in
 * w dt (w = sqrt(kn/m*)): bounded by (w dt)^2 E0 and falling 4x when dt halves. */
static double ledger_case(double v, int expect_break, double frac) {
  double eps = 0.5;
  esf_adhesion a;
  esf_error e;
  esf_adhesion_derive(FF, eps, KN, &a, &e);
  simtest T;
  if (pair_open(&T, eps, 1.0, 0.0, v, frac, 1e-300)) {
    CHECK(0, "ledger scene");
    return NAN;
  }
  esf_sim *s = &T.s;
  double mstar = 0.5 * s->p.mass[0], ke0 = 0.5 * mstar * 4 * v * v, worst = 0;
  double wdt = sqrt(KN / mstar) * s->dt;
  long nsteps = (long)(0.01 / s->dt); /* 10 ms: 15 periods of the well */
  for (long n = 0; n < nsteps; n++) {
    if (simtest_step(&T)) break;
    worst = fmax(worst, fabs(esf_ledger_total_error(&s->led)));
  }
  double wr = esf_adhesion_energy(KN, &a, a.u_rupture);
  size_t ia = by_id(s, 0), ib = by_id(s, 1);
  double vrel = s->p.v[3 * ib] - s->p.v[3 * ia];
  double ke1 = 0.5 * mstar * vrel * vrel;
  CHECK(worst < wdt * wdt * ke0, "v %g: ledger residual %.3g J vs (w dt)^2 E0 = %.3g J",
        v, worst, wdt * wdt * ke0);
  CHECK(s->bonds.broken == expect_break, "v %g: %ld ruptures, expected %d", v,
        s->bonds.broken, expect_break);
  if (expect_break) {
    /* the rupture is detected at the first step past u_rupture, not at it: measured
       errors 2.4e-4 (dissipated, w dt 0.02), 4.7e-5 (w dt 0.01), 8.3e-5 and 1.5e-5
       (kinetic energy) of W(u_rupture); 1e-3 leaves 4x margin */
    CHECK_NEAR(s->led.d_bonds, wr, 1e-3 * wr, "dissipated_bonds vs W(u_rupture)");
    CHECK_NEAR(ke1, ke0 - wr, 1e-3 * wr, "kinetic energy after the rupture");
  } else {
    CHECK(s->led.d_bonds == 0.0, "no rupture energy");
  }
  printf("ledger v=%.2f w dt=%.4f: KE0 %.6e J, W(u_r) %.6e J, worst residual %.3e J "
         "(%.2e of KE0), dissipated_bonds %.6e J, KE after %.6e J\n",
         v, wdt, ke0, wr, worst, worst / ke0, s->led.d_bonds, ke1);
  simtest_close(&T);
  return worst / ke0;
}

static void ledger(void) {
  double vs[2] = {0.1, 0.5};
  for (int k = 0; k < 2; k++) {
    double r1 = ledger_case(vs[k], k, 0.01), r2 = ledger_case(vs[k], k, 0.005);
    CHECK(r2 < r1 / 3, "v %g: residual must fall as dt^2: %.3g then %.3g", vs[k], r1, r2);
  }
}

/* ---- 5. the block impact quick scene ------------------------------------------------
 */

static void block_impact(const char *dir) {
  simtest T;
  int rc = simtest_open_scene(&T, dir, "block_impact-quick", NULL, 0);
  CHECK_OK(rc, T.err);
  if (rc) return;
  esf_sim *s = &T.s;
  int32_t m1 = esf_materials_find(&s->mats, "b1"),
          m2 = esf_materials_find(&s->mats, "b2");
  /* the geometry from the initial state: projectile cross-section, slab faces */
  double py = 0, px_front = -INFINITY, sx_back = -INFINITY;
  for (size_t i = 0; i < s->p.n; i++) {
    const double *x = s->p.x + 3 * i;
    if (s->p.material[i] == m2) {
      py = fmax(py, fmax(fabs(x[1]), fabs(x[2])) + s->p.radius[i]);
      px_front = fmax(px_front, x[0]);
    } else {
      sx_back = fmax(sx_back, x[0] + s->p.radius[i]);
    }
  }
  /* the projectile's front layer, by id */
  size_t nf = 0;
  long long *front = malloc(s->p.n * sizeof *front);
  for (size_t i = 0; i < s->p.n; i++)
    if (s->p.material[i] == m2 && s->p.x[3 * i] > px_front - 1e-9)
      front[nf++] = s->p.id[i];
  /* the target's columns under the cross-section (|y|, |z| of the centre < py) and the
     zone one lattice spacing (18 mm) around it */
  double spacing = 0.018;
  rc = simtest_step(&T); /* forms the bonds */
  CHECK_OK(rc, T.err);
  long near = 0, b2bonds = 0;
  int k_cols = 0;
  {
    const esf_candidates *c = &s->nb.pp;
    for (size_t k = 0; k < c->n; k++) {
      if (!esf_candidates_bonded(c, k)) continue;
      uint32_t a = c->a[k], b = c->b[k];
      if (s->p.material[a] == m2 && s->p.material[b] == m2) {
        b2bonds++;
        continue;
      }
      int in = 0;
      for (int q = 0; q < 2; q++) {
        const double *x = s->p.x + 3 * (q ? b : a);
        if (fabs(x[1]) < py + spacing && fabs(x[2]) < py + spacing) in = 1;
      }
      near += in;
    }
    double ys[64];
    int ny = 0;
    for (size_t i = 0; i < s->p.n && ny < 64; i++) {
      double y = s->p.x[3 * i + 1];
      if (s->p.material[i] != m1 || fabs(y) >= py) continue;
      int seen = 0;
      for (int j = 0; j < ny; j++) seen |= fabs(ys[j] - y) < 1e-9;
      if (!seen) ys[ny++] = y;
    }
    k_cols = ny;
  }
  int layers = 0;
  {
    double xs[64];
    for (size_t i = 0; i < s->p.n && layers < 64; i++) {
      if (s->p.material[i] != m1) continue;
      int seen = 0;
      for (int j = 0; j < layers; j++) seen |= fabs(xs[j] - s->p.x[3 * i]) < 1e-9;
      if (!seen) xs[layers++] = s->p.x[3 * i];
    }
  }
  long nsteps = (long)ceil(s->cfg.duration / s->dt - 1e-9);
  for (long n = 1; n < nsteps && !rc; n++) rc = simtest_step(&T);
  CHECK_OK(rc, T.err);
  double xf = 0;
  for (size_t k = 0; k < nf; k++) xf += s->p.x[3 * by_id(s, front[k])];
  xf /= (double)nf;
  free(front);
  long lo = 4L * k_cols * layers, hi = near + b2bonds;
  CHECK(s->bonds.broken >= lo,
        "broken bonds %ld, at least %ld (4 k layers, k = %d, %d "
        "layers)",
        s->bonds.broken, lo, k_cols, layers);
  CHECK(s->bonds.broken <= hi,
        "broken bonds %ld, at most %ld (near the impact %ld + "
        "projectile %ld)",
        s->bonds.broken, hi, near, b2bonds);
  CHECK(xf > sx_back,
        "the projectile's front layer at x = %.4f m must pass the slab's "
        "back face %.4f m",
        xf, sx_back);
  printf("block_impact-quick: %ld bonds, %ld broken (bounds %ld..%ld); front layer of "
         "B2 at x = %.4f m, slab back face %.4f m (%.1f projectile diameters past it), "
         "t = %.4g s\n",
         s->bonds.formed, s->bonds.broken, lo, hi, xf, sx_back, (xf - sx_back) / 0.01,
         s->t);
  simtest_close(&T);
}

int main(int argc, char **argv) {
  double eps[] = {0.5, 1e-2, 1e-4, 1e-8};
  for (int k = 0; k < 4; k++) law_closed_form(eps[k]);
  bad_parameters();
  for (int k = 0; k < 4; k++) pull_and_recontact(eps[k]);
  rest(1e-4);
  rest(0.5);
  ledger();
  if (argc > 1) block_impact(argv[1]);
  return check_finish("bonds");
}
