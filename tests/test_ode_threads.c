/* test_ode_threads.c — velocity Verlet and the ODE methods (rk4 with a fixed step,
 * Dormand-Prince adaptive, CVODE Adams) evaluate their forces on the fused step's
 * kernels (fused.h: esf_fused_forces, trial and committing, with the ODE methods'
 * trapezoidal carry) and give, bit for bit, the state and contact histories of the
 * general path (model/forces.c, integrator.fused: false) on 1, 2 and 3 threads (state,
 * the particle pairs' and the walls' histories, touch flags and carry).
 *
 * The scene: 400 polydisperse spheres of two materials falling into a box with a
 * tilted polygon floor under global and local damping (the damping forms act outside
 * the force evaluation, esf_sim_accel), linear law with both tangential frames, and
 * the Hertz-Mindlin law. Each run takes a fixed number of the scheme's steps; every
 * run on the fused kernels is checked to have taken them (esf_fused_eval_refusal).
 * Verlet taking up to 32 steps a call gives one step a call's bits. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "fused/fused.h"
#include "integrators/dem_ode.h"
#include "simtest.h"

static const char *const scene =
    "name: ode_threads\n"
    "materials:\n"
    "  glass: {density: 2500, kn: 2.0e4, restitution: 0.4, tangential_restitution: 0.6,"
    " friction: 0.4}\n"
    "  steel: {density: 7800, kn: 4.0e4, restitution: 0.7, friction: 0.2}\n"
    "particles:\n"
    "  - generate: random\n"
    "    region: {min: [0.001, 0.001, 0.0030], max: [0.029, 0.029, 0.016]}\n"
    "    count: 400\n"
    "    radius: {uniform: [0.0008, 0.0016]}\n"
    "    material: {mix: {glass: 0.6, steel: 0.4}}\n"
    "    seed: 5\n"
    "    velocity: [0.05, -0.03, -1.5]\n"
    "walls:\n"
    "  - {box: {min: [0, 0, 0], max: [0.03, 0.03, 0.06]}, open: [top], material: steel}\n"
    "  - {polygon: [[0, 0, 0.001], [0.03, 0, 0.002], [0.03, 0.03, 0.002],"
    " [0, 0.03, 0.001]], material: glass}\n"
    "damping: {global: {translation: 2.0, rotation: 1.0},"
    " local: {coefficient: 0.05, form: component}}\n"
    "integrator: {method: leapfrog, dt: auto, frac: 0.3}\n"
    "run: {steps: 100000}\n"
    "output: {energy_every: 0}\n";

static const char *const hertz_sets[] = {
    "materials.glass={density: 2500, youngs_modulus: 5.0e7, poisson_ratio: 0.3, "
    "restitution: 0.4, tangential_restitution: 0.6, friction: 0.4}",
    "materials.steel={density: 7800, youngs_modulus: 2.0e8, poisson_ratio: 0.28, "
    "restitution: 0.7, friction: 0.2}"};

typedef struct snapshot {
  size_t n, m; /* m: the particle pairs' candidates, then the walls' */
  double *y;
  esf_contact_hist *h;
  uint8_t *touch;
  double *vc0; /* the ODE methods' carry, or NULL */
  double t, contacts;
  int fused; /* the evaluations took the fused kernels */
  esf_integ_stats st;
} snapshot;

/* `steps` calls of the scheme's step with method (and its overrides), threads, fused
 * or the general path. */
/* Every particle spun (no state entry exactly zero: esfera's fixed-step driver then
 * commits in the last stage, erk.c's own_step). */
static void spin_all(esf_sim *s) {
  for (size_t i = 0; i < s->p.n; i++)
    for (int q = 0; q < 3; q++) s->p.w[3 * i + q] = 0.5 + 0.01 * (double)((i + q) % 97);
}

static void (*prep_of_run)(esf_sim *) = NULL; /* run_drv's prep (check_driver's) */
static long burst_ =
    1; /* run_drv's steps a call at most (s->burst; check_verlet_burst) */

static int run_drv(const char *const *msets, int nm, int hertz, int threads, int fused,
                   int arkode, long steps, snapshot *out) {
  const char *sets[12];
  int n = 0;
  for (int k = 0; k < nm; k++) sets[n++] = msets[k];
  sets[n++] = fused ? "integrator.fused=true" : "integrator.fused=false";
  if (hertz) {
    sets[n++] = hertz_sets[0];
    sets[n++] = hertz_sets[1];
  }
  simtest T;
  int rc = simtest_open_prep(&T, scene, sets, n, arkode, prep_of_run);
  if (rc) return rc;
  T.s.cfg.threads = threads;
  T.s.cfg.range_work = 1; /* one range per thread, however small the scene */
  const int ode = strcmp(T.s.cfg.method, "verlet") != 0;
  if (burst_ > 1) /* up to burst_ steps a call, as the run driver lets a scheme take */
    for (const long s0 = T.s.step; T.s.step - s0 < steps && !rc;) {
      const long left = steps - (T.s.step - s0);
      T.s.burst = burst_ < left ? burst_ : left;
      rc = simtest_step(&T);
    }
  else
    for (long i = 0; i < steps && !rc; i++) rc = simtest_step(&T);
  if (!rc) {
    const esf_candidates *pp = &T.s.nb.pp, *pw = &T.s.nb.pw;
    out->n = T.s.p.n;
    out->m = pp->n + pw->n;
    out->y = malloc(9 * out->n * sizeof(double));
    out->h = malloc((out->m ? out->m : 1) * sizeof *out->h);
    out->touch = malloc(out->m ? out->m : 1);
    memcpy(out->y, T.s.p.y, 9 * out->n * sizeof(double));
    memcpy(out->h, pp->h, pp->n * sizeof *out->h);
    memcpy(out->h + pp->n, pw->h, pw->n * sizeof *out->h);
    memcpy(out->touch, pp->touch, pp->n);
    memcpy(out->touch + pp->n, pw->touch, pw->n);
    out->vc0 = NULL;
    if (pp->vc0 && (pw->vc0 || !pw->n)) {
      out->vc0 = malloc((out->m ? out->m : 1) * 3 * sizeof(double));
      memcpy(out->vc0, pp->vc0, pp->n * 3 * sizeof(double));
      if (pw->n) memcpy(out->vc0 + 3 * pp->n, pw->vc0, pw->n * 3 * sizeof(double));
    }
    out->t = T.s.t;
    out->contacts = T.s.contacts_sum;
    out->fused = esf_fused_eval_refusal(&T.s, ode) == NULL;
    if (T.it->stats) T.it->stats(&T.s, T.ist, &out->st);
  }
  simtest_close(&T);
  return rc;
}

static int run(const char *const *msets, int nm, int hertz, int threads, int fused,
               long steps, snapshot *out) {
  return run_drv(msets, nm, hertz, threads, fused, 0, steps, out);
}

static void release(snapshot *a) {
  free(a->y);
  free(a->h);
  free(a->touch);
  free(a->vc0);
}

static void check_same(const snapshot *a, const snapshot *ref, const char *what) {
  CHECK(a->n == ref->n && a->m == ref->m, "%s: same sizes", what);
  if (a->n != ref->n || a->m != ref->m) return;
  CHECK(memcmp(a->y, ref->y, 9 * ref->n * sizeof(double)) == 0, "%s: state differs",
        what);
  CHECK(memcmp(a->h, ref->h, ref->m * sizeof *ref->h) == 0, "%s: contact history differs",
        what);
  CHECK(memcmp(a->touch, ref->touch, ref->m) == 0, "%s: touching flags differ", what);
  CHECK(!a->vc0 == !ref->vc0 &&
            (!a->vc0 || memcmp(a->vc0, ref->vc0, 3 * ref->m * sizeof(double)) == 0),
        "%s: the carried contact velocities differ", what);
  CHECK(a->t == ref->t && a->contacts == ref->contacts,
        "%s: t = %.17g s, %.0f contacts summed (reference %.17g, %.0f)", what, a->t,
        a->contacts, ref->t, ref->contacts);
}

static void check_method(const char *name, const char *const *msets, int nm, int hertz,
                         long steps) {
  snapshot gen = {0};
  int rc = run(msets, nm, hertz, 1, 0, steps, &gen);
  CHECK(rc == 0, "%s: general path ran", name);
  if (rc) return;
  CHECK(!gen.fused, "%s: integrator.fused: false takes the general path", name);
  CHECK(gen.contacts > 0, "%s: contacts formed (%.0f)", name, gen.contacts);
  printf("%s: %ld steps to t = %.4g s, %.1f contacts per step\n", name, steps, gen.t,
         gen.contacts / (double)steps);
  for (int th = 1; th <= 3; th++) {
    snapshot b = {0};
    char what[160];
    snprintf(what, sizeof what, "%s, fused kernels on %d threads", name, th);
    rc = run(msets, nm, hertz, th, 1, steps, &b);
    CHECK(rc == 0, "%s: ran", what);
    if (rc) continue;
    CHECK(b.fused, "%s: took the fused kernels", what);
    check_same(&b, &gen, what);
    release(&b);
  }
  release(&gen);
}

/* The fixed-step erk methods on esfera's driver (erk.c) and on ARKODE's ERKStep
 * (ESF_ERK_DRIVER=arkode): the same bits (state, histories, carry) and counters, on
 * the fused kernels on 1 and 2 threads. */
static void check_driver(const char *name, const char *const *msets, int nm, long steps,
                         int spin) {
  prep_of_run = spin ? spin_all : NULL;
  for (int th = 1; th <= 2; th++) {
    snapshot a = {0}, b = {0};
    char what[160];
    snprintf(what, sizeof what, "%s, esfera's driver against ERKStep, %d threads", name,
             th);
    int rc = run_drv(msets, nm, 0, th, 1, 1, steps, &a);
    if (!rc) rc = run_drv(msets, nm, 0, th, 1, 0, steps, &b);
    CHECK(rc == 0, "%s: ran", what);
    if (!rc) {
      check_same(&b, &a, what);
      /* esfera's driver commits in the last stage where it may: one evaluation less */
      CHECK(a.st.merged == 0 && b.st.merged >= 0 && b.st.merged <= b.st.steps &&
                (!spin || b.st.merged == b.st.steps),
            "%s: %ld merged commits of %ld steps (ERKStep: %ld)", what, b.st.merged,
            b.st.steps, a.st.merged);
      CHECK(b.st.steps == a.st.steps && b.st.attempts == a.st.attempts &&
                b.st.rhs_evals + b.st.merged == a.st.rhs_evals &&
                b.st.rejected == a.st.rejected && b.st.restarts == a.st.restarts &&
                b.st.h_last == a.st.h_last,
            "%s: counters: %ld steps, %ld rhs, %ld restarts, h %.17g (ERKStep: %ld, "
            "%ld, %ld, %.17g)",
            what, b.st.steps, b.st.rhs_evals, b.st.restarts, b.st.h_last, a.st.steps,
            a.st.rhs_evals, a.st.restarts, a.st.h_last);
      if (th == 1)
        printf("%s: %ld steps, %ld rhs evaluations, %ld restarts, %ld merged commits\n",
               name, b.st.steps, b.st.rhs_evals, b.st.restarts, b.st.merged);
    }
    release(&a);
    release(&b);
  }
  prep_of_run = NULL;
}

/* Velocity Verlet taking up to 32 steps a call (s->burst, as the run driver sets it
 * between frames: each step's second half kick and the next one's first half kick and
 * drift in one pass, the displacement check measured on the way) gives the state and
 * histories of one step a call, bit for bit, on the fused kernels on 1 and 2 threads
 * and on the general path. */
static void check_verlet_burst(void) {
  const char *verlet[] = {"integrator.method=verlet"};
  for (int v = 0; v < 3; v++) {
    const int th = v == 2 ? 1 : v + 1, fused = v < 2;
    snapshot a = {0}, b = {0};
    char what[160];
    snprintf(what, sizeof what, "verlet, 32 steps a call against one, %s, %d threads",
             fused ? "fused kernels" : "general path", th);
    burst_ = 1;
    int rc = run(verlet, 1, 0, th, fused, 1500, &a);
    burst_ = 32;
    if (!rc) rc = run(verlet, 1, 0, th, fused, 1500, &b);
    burst_ = 1;
    CHECK(rc == 0, "%s: ran", what);
    if (!rc) {
      CHECK(b.fused == fused, "%s: the path taken", what);
      check_same(&b, &a, what);
    }
    release(&a);
    release(&b);
  }
}

/* esf_dem_ode_lincomb_nz against SUNDIALS' N_VLinearCombination on vectors of small
 * integers and signed zeros (exact cancellations, so many zero results of either sign)
 * over several blocks, zero coefficients among the terms: the same bits, the re-sum
 * only included; and the plain sum of the nonzero terms does differ in some zero's sign
 * (the case the re-sum is there for). */
static void check_lincomb_nz(void) {
  SUNContext ctx;
  CHECK(SUNContext_Create(NULL, &ctx) == 0, "SUNDIALS context");
  const int threads = 2, nv = 6;
  const size_t len = 9001;
  N_Vector X[6], za, zb, zs;
  for (int i = 0; i < nv; i++) X[i] = esf_dem_ode_vector(len, &threads, ctx);
  za = esf_dem_ode_vector(len, &threads, ctx);
  zb = N_VClone(za);
  zs = N_VClone(za);
  uint64_t r = 12345;
  for (int i = 0; i < nv; i++) {
    double *x = N_VGetArrayPointer(X[i]);
    for (size_t j = 0; j < len; j++) {
      r = r * 6364136223846793005ULL + 1442695040888963407ULL;
      const int k = (int)(r >> 60); /* 0 .. 15 */
      x[j] = k < 4 ? (k & 1 ? -0.0 : 0.0) : (double)(k - 10);
    }
  }
  const double cs[][6] = {{0.0, 0.25, 0.0, 0.5, -0.25, 1.0},
                          {0.0, 0.0, 0.0, 0.0, 0.0, 1.0},
                          {0.5, 0.0, 0.25, 0.0, 0.0, 1.0},
                          {0.0, 0.5, 1.0}};
  const int ns[] = {6, 6, 6, 3};
  int sign_cases = 0;
  for (int c = 0; c < 4; c++) {
    double cv[6], cp[6];
    N_Vector Xp[6];
    int np = 0;
    for (int i = 0; i < ns[c]; i++) {
      cv[i] = cs[c][i];
      if (cv[i] != 0.0) {
        cp[np] = cv[i];
        Xp[np++] = X[i];
      }
    }
    N_VLinearCombination(ns[c], cv, X, za);
    N_VLinearCombination(np, cp, Xp, zs); /* the nonzero terms only */
    const double *a = N_VGetArrayPointer(za), *s = N_VGetArrayPointer(zs);
    for (size_t j = 0; j < len; j++) sign_cases += signbit(a[j]) != signbit(s[j]);
    long zeros = esf_dem_ode_lincomb_nz(ns[c], cv, X, zb, 0);
    CHECK(memcmp(a, N_VGetArrayPointer(zb), len * sizeof(double)) == 0 && zeros > 0,
          "lincomb_nz, coefficients %d: the bits of N_VLinearCombination (%ld zeros)", c,
          zeros);
    esf_dem_ode_lincomb_nz(ns[c], cv, X, zs, 1);
    CHECK(memcmp(a, N_VGetArrayPointer(zs), len * sizeof(double)) == 0,
          "lincomb_nz, coefficients %d: the re-sum of the zeros", c);
  }
  CHECK(sign_cases > 0, "the nonzero terms alone give %d zeros another sign", sign_cases);
  for (int i = 0; i < nv; i++) N_VDestroy(X[i]);
  N_VDestroy(za);
  N_VDestroy(zb);
  N_VDestroy(zs);
  SUNContext_Free(&ctx);
}

int main(void) {
  check_lincomb_nz();
  const char *verlet[] = {"integrator.method=verlet"};
  const char *rk4[] = {"integrator.method=rk4"};
  const char *rk4p[] = {"integrator.method=rk4", "contact.tangential_frame=project"};
  const char *dp5[] = {"integrator.method=erk:ARKODE_DORMAND_PRINCE_7_4_5",
                       "integrator.rtol=1.0e-5", "integrator.atol=1.0e-9"};
  const char *adams[] = {"integrator.method=cvode-adams", "integrator.rtol=1.0e-5",
                         "integrator.atol=1.0e-9"};
  const char *heun[] = {"integrator.method=erk:ARKODE_HEUN_EULER_2_1_2"};
  const char *bs3[] = {"integrator.method=erk:ARKODE_BOGACKI_SHAMPINE_4_2_3"};
  const char *f45[] = {"integrator.method=erk:ARKODE_FEHLBERG_6_4_5"}; /* c_s != 1 */
  const char *rk4s[] = {"integrator.method=rk4", "integrator.history=state"};
  check_driver("rk4", rk4, 1, 600, 0);
  check_driver("rk4, spinning", rk4, 1, 600, 1);
  check_driver("Heun-Euler", heun, 1, 600, 0);
  check_driver("Bogacki-Shampine", bs3, 1, 600, 1);
  check_driver("Fehlberg 4(5)", f45, 1, 600, 0);
  check_driver("rk4, history as state", rk4s, 2, 600, 0);
  check_method("verlet", verlet, 1, 0, 1500);
  check_verlet_burst();
  check_method("rk4", rk4, 1, 0, 1500);
  check_method("rk4, projected frame", rk4p, 2, 0, 1500);
  check_method("rk4, Hertz-Mindlin", rk4, 1, 1, 1500);
  check_method("erk DP5 adaptive", dp5, 3, 0, 1000);
  check_method("cvode-adams", adams, 3, 0, 2000);
  return check_finish("ode_threads");
}
