/* test_threads.c — the fused leapfrog step (src/fused/) gives the same state bit
 * for bit on 1, 2 and 3 threads, with every instruction set's kernels, and on the
 * general path (model/forces.c).
 *
 * The scene exercises every feature the fused step handles: polydisperse spheres (1:3)
 * thrown onto an oscillating floor in a box (moving wall, wall edges and corners),
 * friction with sliding, tangential and normal dashpots, global and local damping, two
 * materials. After 1500 steps (about 30 contacts at a time, opening and closing; the
 * lists rebuilt about 20 times) the positions, velocities, angular velocities and
 * contact histories of the threaded runs are compared with memcmp, and with the general
 * path's, which computes the same formulas (contact/law_body.h) in the same order and
 * sums every particle's forces in the same order, so it agrees bit for bit. The kernels
 * of every instruction set this CPU runs (base, AVX2, AVX-512; fused_isa.h) give the
 * base kernels' state bit for bit.
 * A minimal build (meson -Dfeatures=minimal) drops the damping, which it compiles out of
 * the fused step, and checks that the projected frame, also compiled out, goes to the
 * general path at one step per call.
 * Failures: two clouds meeting head on with the overlap limited (1-5% of a radius)
 * stop at the same step with the same message (pair, overlap to three digits: one
 * drift of either particle would change it) on 1, 2, 3 threads and the general path.
 * Leaving the domain: a sphere drifting out is removed at the general path's step by
 * the fused step on 1 and 2 threads, one and 32 steps per call (without the drift's
 * domain check it goes 200 steps late; without the burst's stop on it, 24).
 * Rolling and twisting resistance (both models, mixed between the materials): the
 * fused step on 1, 2 and 3 threads gives the general path's state and rolling states
 * bit for bit; with the Hertz-Mindlin law too (1 and 2 threads, with the ledger). */
#include <stdlib.h>

#include "fused/fused.h"
#include "simtest.h"

/* A minimal build (meson -Dfeatures=minimal) compiles damping out of the fused step:
 * there the scene goes without it, so that the fused step still runs it. */
#ifdef ESF_MINIMAL
#define DAMPING ""
#else
#define DAMPING                                                                          \
  "damping: {global: {translation: 2.0, rotation: 1.0},"                                 \
  " local: {coefficient: 0.05, form: component}}\n"
#endif

static const char *const scene_fmt = /* %s: the floor's motion, or nothing */
    "name: threads\n"
    "materials:\n"
    "  glass: {density: 2500, kn: 2.0e4, restitution: 0.4, tangential_restitution: 0.6,"
    " friction: 0.4}\n"
    "  steel: {density: 7800, kn: 4.0e4, restitution: 0.7, friction: 0.2}\n"
    "particles:\n"
    "  - generate: random\n"
    "    region: {min: [0.001, 0.001, 0.0012], max: [0.039, 0.039, 0.02]}\n"
    "    count: 400\n"
    "    radius: {uniform: [0.0008, 0.0024]}\n"
    "    material: {mix: {glass: 0.6, steel: 0.4}}\n"
    "    seed: 11\n"
    "    velocity: [0.05, -0.03, -0.6]\n"
    "walls:\n"
    "  - {box: {min: [0, 0, 0], max: [0.04, 0.04, 0.06]}, open: [top], material: steel}\n"
    "  - {polygon: [[0, 0, 0.001], [0.04, 0, 0.001], [0.04, 0.04, 0.001],"
    " [0, 0.04, 0.001]], material: glass%s}\n" DAMPING
    "integrator: {method: leapfrog, dt: auto, frac: 0.3}\n"
    "run: {steps: 1500}\n"
    "output: {energy_every: 0}\n";

static const char *const oscillate = ",\n     motion: {oscillate: {direction: [0, 0, 1], "
                                     "frequency: 50, amplitude: 0.0005}}";

typedef struct snapshot {
  size_t n, m;
  double *y;
  esf_contact_hist *h;
  esf_contact_roll *roll; /* the pair list's rolling states, or NULL */
  long builds;
  double contacts_mean; /* touching contacts per step, averaged over the run */
  long calls;           /* calls of the scheme's step */
  int fused;            /* the fused step ran it (esf_fused_eligible) */
  esf_ledger led;       /* the energy ledger at the end (ledger_) */
} snapshot;

/* 1500 steps with the floor oscillating or still, `burst` steps at most per call of
 * the scheme (s->burst, as the driver sets it: more than one only with static walls). */
/* The fused step's kernels for run(): "" for the CPU's widest, or base, avx2, avx512
 * (fused_isa.h); and whether the energy ledger is on (a row every 1e-5 s). */
static const char *isa_ = "";
static int ledger_ = 0;
static const char *extra_ = NULL;  /* one more override, or NULL */
static const char *extra2_ = NULL; /* and another, or NULL */
static const char *extra3_ = NULL; /* and a third, or NULL */
static int hertz_ = 0;             /* both materials Hertz-Mindlin (check_hertz) */
static const char *const hertz_sets[] = {
    "materials.glass={density: 2500, youngs_modulus: 5.0e7, poisson_ratio: 0.3, "
    "restitution: 0.4, tangential_restitution: 0.6, friction: 0.4}",
    "materials.steel={density: 7800, youngs_modulus: 2.0e8, poisson_ratio: 0.28, "
    "restitution: 0.7, friction: 0.2}"};

static int run(int threads, int fused, const char *tframe, int moving, long burst,
               snapshot *out) {
  char s_fu[64], s_tf[64], scene[2048];
  snprintf(s_fu, sizeof s_fu, "integrator.fused=%s", fused ? "true" : "false");
  snprintf(s_tf, sizeof s_tf, "contact.tangential_frame=%s", tframe);
  snprintf(scene, sizeof scene, scene_fmt, moving ? oscillate : "");
  const char *sets[8] = {s_fu, s_tf, extra_ ? extra_ : s_fu};
  int nsets = 3;
  if (extra2_) sets[nsets++] = extra2_;
  if (extra3_) sets[nsets++] = extra3_;
  if (ledger_) sets[nsets++] = "output.energy_every=1.0e-5";
  if (hertz_) {
    sets[nsets++] = hertz_sets[0];
    sets[nsets++] = hertz_sets[1];
  }
  simtest T;
  int rc = simtest_open(&T, scene, sets, nsets);
  if (rc) return rc;
  T.s.cfg.threads = threads;
  T.s.cfg.range_work = 1; /* one range per thread, however small the scene */
  if (*isa_) {            /* the scheme again, with these kernels */
    T.it->destroy(&T.ist);
    snprintf(T.s.cfg.isa, sizeof T.s.cfg.isa, "%s", isa_);
    rc = T.it->create(&T.s, &T.ist, &T.err);
    if (rc) {
      simtest_close(&T);
      return rc;
    }
  }
  const int on = fused && esf_fused_eligible(&T.s);
  long calls = 0;
  for (; T.s.step < 1500 && !rc; calls++) {
    T.s.burst = 1500 - T.s.step < burst ? 1500 - T.s.step : burst;
    rc = simtest_step(&T);
  }
  if (!rc) {
    out->n = T.s.p.n;
    out->m = T.s.nb.pp.n;
    out->y = malloc(9 * out->n * sizeof(double));
    out->h = malloc((out->m ? out->m : 1) * sizeof *out->h);
    memcpy(out->y, T.s.p.y, 9 * out->n * sizeof(double));
    memcpy(out->h, T.s.nb.pp.h, out->m * sizeof *out->h);
    out->roll = NULL;
    if (T.s.nb.pp.roll) {
      out->roll = malloc((out->m ? out->m : 1) * sizeof *out->roll);
      memcpy(out->roll, T.s.nb.pp.roll, out->m * sizeof *out->roll);
    }
    out->builds = T.s.nb.builds;
    out->contacts_mean = T.s.contacts_sum / (double)T.s.step;
    out->calls = calls;
    out->fused = on;
    out->led = T.s.led;
  }
  simtest_close(&T);
  return rc;
}

/* Same state, bit for bit (sizes, positions, velocities, spins, histories, contact
 * count, list builds). */
static void check_same(const snapshot *a, const snapshot *ref, const char *what) {
  CHECK(a->n == ref->n && a->m == ref->m, "%s: same sizes", what);
  if (a->n != ref->n || a->m != ref->m) return;
  CHECK(memcmp(a->y, ref->y, 9 * ref->n * sizeof(double)) == 0, "%s: state differs",
        what);
  CHECK(memcmp(a->h, ref->h, ref->m * sizeof *ref->h) == 0, "%s: contact history differs",
        what);
  CHECK(!a->roll == !ref->roll &&
            (!a->roll || memcmp(a->roll, ref->roll, ref->m * sizeof *ref->roll) == 0),
        "%s: rolling states differ", what);
  CHECK(a->contacts_mean == ref->contacts_mean && a->builds == ref->builds,
        "%s: %.6f contacts per step, %ld builds (reference %.6f, %ld)", what,
        a->contacts_mean, a->builds, ref->contacts_mean, ref->builds);
  CHECK(memcmp(&a->led, &ref->led, sizeof a->led) == 0,
        "%s: energy ledger differs (dissipated normal %.17g, reference %.17g)", what,
        a->led.d_normal, ref->led.d_normal);
}

/* Two clouds of spheres meeting head on, no walls in reach: the first overlaps beyond
 * the limit are between particles. */
static const char *const clash =
    "name: clash\n"
    "materials:\n"
    "  glass: {density: 2500, kn: 2.0e4, restitution: 0.4, friction: 0.4}\n"
    "  steel: {density: 7800, kn: 4.0e4, restitution: 0.7, friction: 0.2}\n"
    "particles:\n"
    "  - generate: random\n"
    "    region: {min: [0.001, 0.001, 0.001], max: [0.019, 0.039, 0.039]}\n"
    "    count: 250\n"
    "    radius: {uniform: [0.0008, 0.0024]}\n"
    "    material: {mix: {glass: 0.6, steel: 0.4}}\n"
    "    seed: 5\n"
    "    velocity: [1.5, 0, 0.1]\n"
    "  - generate: random\n"
    "    region: {min: [0.021, 0.001, 0.001], max: [0.039, 0.039, 0.039]}\n"
    "    count: 250\n"
    "    radius: {uniform: [0.0008, 0.0024]}\n"
    "    material: {mix: {glass: 0.6, steel: 0.4}}\n"
    "    seed: 6\n"
    "    velocity: [-1.5, 0, -0.1]\n"
    "walls:\n"
    "  - {box: {min: [-0.5, -0.5, -0.5], max: [0.5, 0.5, 0.5]}, material: steel}\n"
    "gravity: [0, 0, 0]\n"
    "integrator: {method: leapfrog, dt: auto, frac: 0.3}\n"
    "run: {steps: 1500}\n"
    "output: {energy_every: 0}\n";

/* The run with overlaps limited to `limit` of the smaller radius, `burst` steps at
 * most per call: the step that failed (-1: none) and the message. */
static long run_fail(int threads, int fused, const char *limit, long burst, char *msg,
                     size_t cap) {
  char s_fu[64], s_lim[64];
  snprintf(s_fu, sizeof s_fu, "integrator.fused=%s", fused ? "true" : "false");
  snprintf(s_lim, sizeof s_lim, "contact.max_overlap=%s", limit);
  const char *sets[] = {s_fu, s_lim};
  simtest T;
  msg[0] = '\0';
  if (simtest_open(&T, clash, sets, 2)) return -1;
  T.s.cfg.threads = threads;
  T.s.cfg.range_work = 1; /* one range per thread, however small the scene */
  int rc = 0;
  while (T.s.step < 1500 && !rc) {
    T.s.burst = burst;
    rc = simtest_step(&T);
  }
  const long step = rc ? T.s.step : -1;
  if (rc) snprintf(msg, cap, "%s", T.err.msg);
  simtest_close(&T);
  return step;
}

/* A pair overlapping beyond the limit stops the run at the same step with the same
 * message (the lowest failing pair, its overlap at x_n) on 1, 2 and 3 threads, one
 * step or up to 32 per call, and on the general path, for several limits (the first
 * failure falls on other pairs). */
static void check_failure(void) {
  const char *limits[] = {"0.01", "0.03", "0.05"};
  for (int q = 0; q < 3; q++) {
    char m1[2048], mx[2048];
    const long s1 = run_fail(1, 1, limits[q], 1, m1, sizeof m1);
    printf("limit %s: step %ld: %s\n", limits[q], s1, m1);
    CHECK(s1 > 0, "limit %s: the run fails (step %ld)", limits[q], s1);
    const struct {
      int threads, fused;
      long burst;
    } v[] = {{2, 1, 1}, {3, 1, 1}, {1, 1, 32}, {2, 1, 32}, {3, 1, 32}, {1, 0, 1}};
    for (size_t j = 0; j < sizeof v / sizeof v[0]; j++) {
      const long sx =
          run_fail(v[j].threads, v[j].fused, limits[q], v[j].burst, mx, sizeof mx);
      CHECK(sx == s1 && strcmp(mx, m1) == 0,
            "limit %s, %d threads, %s, %ld steps per call: step %ld '%s'", limits[q],
            v[j].threads, v[j].fused ? "fused" : "general path", v[j].burst, sx, mx);
    }
  }
}

static void release(snapshot *s) {
  free(s->y);
  free(s->h);
  free(s->roll);
}

/* A sphere drifting slowly out of the domain (0.05 m/s, far less than half the skin
 * before it crosses): only the drift's domain check can call for the rebuild that
 * removes it. The fused step (plain kick, one and 32 steps per call, 1 and 2 threads)
 * must remove it at the general path's step, the first after the centre crosses. */
static const char *const leave =
    "name: leave\n"
    "domain: {min: [0, 0, 0], max: [0.02, 0.02, 0.02]}\n"
    "gravity: [0, 0, 0]\n"
    "materials:\n"
    "  glass: {density: 2500, kn: 2.0e4, restitution: 0.4, friction: 0.4}\n"
    "particles:\n"
    "  - {material: glass, radius: 0.001, position: [0.01, 0.01, 0.01990],"
    " velocity: [0, 0, 0.05]}\n"
    "  - {material: glass, radius: 0.001, position: [0.005, 0.005, 0.005]}\n"
    "  - {material: glass, radius: 0.001, position: [0.005, 0.0075, 0.005]}\n"
    "integrator: {method: leapfrog, dt: 1.0e-5}\n"
    "run: {steps: 1000}\n"
    "output: {energy_every: 0}\n";

/* The steps done when the sphere was removed (-1: never in 1000 steps). */
static long leave_step(int threads, int fused, long burst) {
  const char *sets[] = {fused ? "integrator.fused=true" : "integrator.fused=false"};
  simtest T;
  if (simtest_open(&T, leave, sets, 1)) return -2;
  T.s.cfg.threads = threads;
  T.s.cfg.range_work = 1; /* one range per thread, however small the scene */
  CHECK(!fused || esf_fused_eligible(&T.s), "leave: the fused step must run it");
  long at = -1;
  int rc = 0;
  while (T.s.step < 1000 && at < 0 && !rc) {
    T.s.burst = burst;
    const long before = T.s.step; /* the call's rebuild removes it, then steps on */
    rc = simtest_step(&T);
    if (T.s.removed > 0) at = before;
  }
  CHECK(rc == 0, "leave: run");
  simtest_close(&T);
  return at;
}

static void check_leave(void) {
  /* the centre crosses z = 0.02 after (0.02 - 0.0199) / 0.05 = 2 ms, 200 steps */
  const long gen = leave_step(1, 0, 1);
  printf("leave: general path removes the sphere after step %ld\n", gen);
  CHECK(gen >= 200 && gen <= 203, "leave: general path removed it after step %ld", gen);
  const struct {
    int threads;
    long burst;
  } v[] = {{1, 1}, {2, 1}, {1, 32}, {2, 32}};
  for (size_t j = 0; j < sizeof v / sizeof v[0]; j++) {
    const long at = leave_step(v[j].threads, 1, v[j].burst);
    CHECK(at == gen,
          "leave: fused, %d threads, %ld steps per call: removed after step %ld,"
          " general path %ld",
          v[j].threads, v[j].burst, at, gen);
  }
}

/* The fused step on 1 to tmax threads against the general path's run gen, bit for bit
 * (floor moving or still, burst steps per call); what names the case. */
static void fused_vs_general(const snapshot *gen, int tmax, int moving, long burst,
                             const char *what0) {
  for (int t = 1; t <= tmax; t++) {
    snapshot b;
    char what[192];
    snprintf(what, sizeof what, "%s, %d threads", what0, t);
    CHECK(run(t, 1, "rotate", moving, burst, &b) == 0, "%s", what);
    if (check_failures_) break;
#ifndef ESF_MINIMAL
    CHECK(b.fused, "%s: the fused step must run it", what);
#endif
    check_same(&b, gen, what);
    release(&b);
  }
}

/* With the energy ledger on (every column booked each step from per-particle rows and
 * fixed blocks, core/ledger.h): the fused step on 1, 2 and 3 threads, in bursts of 32
 * steps with the floor still and of 1 with it moving, gives the general path's state
 * and ledger, bit for bit. The fourth round has neither tangential dashpots nor
 * damping: the light steps' compact rows of the normal dashpots alone and their
 * vectorised kick (fused_kick.c's kick_ledger_light). */
static void check_ledger(void) {
  ledger_ = 1;
  for (int round = 0; round < 4; round++) {
    snapshot gen;
    const int moving = round == 1;
    const long burst = moving ? 1 : 32;
    /* the third round: adaptive global damping (alpha after every step, from the
       ledger's blocks) */
    extra_ = round == 2 ? "damping.global={translation: 5, auto: true}" : NULL;
    if (round == 3) {
      extra_ = "materials.glass={density: 2500, kn: 2.0e4, restitution: 0.4, "
               "tangential_restitution: 1, friction: 0.4}";
      extra2_ = "materials.steel={density: 7800, kn: 4.0e4, restitution: 0.7, "
                "tangential_restitution: 1, friction: 0.2}";
      extra3_ =
          "damping={global: {translation: 0, rotation: 0}, local: {coefficient: 0}}";
    }
    if (run(1, 0, "rotate", moving, 1, &gen) != 0) {
      CHECK(0, "ledger: general path");
      break;
    }
    CHECK(gen.led.on && gen.led.d_normal > 0 && gen.led.d_friction > 0 &&
              (round == 3 ? gen.led.d_global == 0 && gen.led.d_tangential == 0
                          : gen.led.d_global > 0) &&
              gen.led.el_n > 0,
          "ledger: every path books energy");
    char what[96];
    snprintf(what, sizeof what, "ledger, floor %s%s", moving ? "oscillating" : "still",
             round == 3 ? ", no tangential dashpot, no damping"
             : extra_   ? ", adaptive damping"
                        : "");
    printf("%s: dissipated normal %.6g J, tangential %.6g J, friction "
           "%.6g J, global %.6g J, local %.6g J; walls' work %.6g J\n",
           what, gen.led.d_normal, gen.led.d_tangential, gen.led.d_friction,
           gen.led.d_global, gen.led.d_local, gen.led.w_walls);
    fused_vs_general(&gen, 3, moving, burst, what);
    release(&gen);
  }
  ledger_ = 0;
  extra_ = extra2_ = extra3_ = NULL;
}

/* The Hertz-Mindlin law (contact_hertz.c) on both materials: the fused step on 1 and
 * 2 threads gives the general path's state bit for bit, with the floor oscillating
 * (one step per call) and still (32), the second time with the energy ledger (its
 * work_tangential_stiffness column included). */
static void check_hertz(void) {
  hertz_ = 1;
  for (int round = 0; round < 2; round++) {
    snapshot gen;
    const int moving = round == 0;
    ledger_ = round == 1;
    if (run(1, 0, "rotate", moving, 1, &gen) != 0) {
      CHECK(0, "Hertz: general path");
      break;
    }
    printf("Hertz, floor %s: %.1f contacts per step%s", moving ? "oscillating" : "still",
           gen.contacts_mean, ledger_ ? "" : "\n");
    if (ledger_)
      printf(", dissipated normal %.6g J, friction %.6g J, work_tangential_stiffness "
             "%.6g J\n",
             gen.led.d_normal, gen.led.d_friction, gen.led.w_stiff);
    CHECK(gen.contacts_mean > 0.05 * (double)gen.n, "Hertz: collisions all along");
    CHECK(!ledger_ || gen.led.w_stiff != 0.0, "Hertz: the stiffness column books");
    char what[96];
    snprintf(what, sizeof what, "Hertz, floor %s%s", moving ? "oscillating" : "still",
             ledger_ ? ", ledger" : "");
    fused_vs_general(&gen, 2, moving, moving ? 1 : 32, what);
    release(&gen);
  }
  hertz_ = 0;
  ledger_ = 0;
}

/* The materials of check_rolling: the linear law, and the Hertz-Mindlin law (rolling's
 * kn: S_n at the overlap) with check_hertz's moduli. */
static const char *const roll_linear =
    "materials={glass: {density: 2500, kn: 2.0e4, restitution: 0.4, "
    "tangential_restitution: 0.6, friction: 0.4, rolling_friction: 0.3, "
    "rolling_damping: 0.4, twisting_friction: 0.1}, steel: {density: 7800, kn: 4.0e4, "
    "restitution: 0.7, friction: 0.2, rolling_friction: 0.1}}";
static const char *const roll_hertz =
    "materials={glass: {density: 2500, youngs_modulus: 5.0e7, poisson_ratio: 0.3, "
    "restitution: 0.4, tangential_restitution: 0.6, friction: 0.4, "
    "rolling_friction: 0.3, rolling_damping: 0.4, twisting_friction: 0.1}, "
    "steel: {density: 7800, youngs_modulus: 2.0e8, poisson_ratio: 0.28, "
    "restitution: 0.7, friction: 0.2, rolling_friction: 0.1}}";

/* Rolling and twisting resistance, epsd and cdt, mixed (min) between the materials
 * (mats: the materials override, law: its name): the fused step on 1 to tmax threads
 * against the general path, floor oscillating, without (q0 = 0) and with the energy
 * ledger (its rolling rows and columns). */
static void check_rolling(const char *mats, const char *law, int q0, int tmax) {
  extra_ = mats;
  const char *models[] = {"contact.rolling=epsd", "contact.rolling=cdt"};
  for (int q = q0; q < 4; q++) {
    extra2_ = models[q % 2];
    ledger_ = q >= 2;
    snapshot gen;
    if (run(1, 0, "rotate", 1, 1, &gen) != 0) {
      CHECK(0, "rolling, %s law: general path (%s)", law, extra2_);
      break;
    }
    CHECK(gen.roll != NULL, "%s: the lists keep rolling states", extra2_);
    if (ledger_)
      CHECK(gen.led.d_rolling > 0 && (q == 3 || gen.led.el_r > 0),
            "%s: the ledger books rolling (%.3g J dissipated, %.3g J stored)", extra2_,
            gen.led.d_rolling, gen.led.el_r);
    double mmax = 0;
    for (size_t k = 0; gen.roll && k < gen.m; k++)
      mmax = fmax(mmax, fabs(gen.roll[k].m[0]) + fabs(gen.roll[k].m[1]) +
                            fabs(gen.roll[k].m[2]) + fabs(gen.roll[k].t));
    if (q % 2 == 0) CHECK(mmax > 0, "epsd: rolling springs loaded (%.3g N m)", mmax);
    char what[128];
    snprintf(what, sizeof what, "%s law, %s%s", law, extra2_, ledger_ ? ", ledger" : "");
    fused_vs_general(&gen, tmax, 1, 1, what);
    printf("%s law, %s%s: fused on 1-%d threads = general path; %.1f contacts per step, "
           "largest stored rolling torque %.3g N m; rolling dissipated %.4g J, total "
           "error %.3g J\n",
           law, extra2_, ledger_ ? ", ledger" : "", tmax, gen.contacts_mean, mmax,
           gen.led.d_rolling, esf_ledger_total_error(&gen.led));
    release(&gen);
  }
  extra_ = extra2_ = NULL;
  ledger_ = 0;
}

/* Every instruction set's kernels (fused_isa.h) that this CPU runs give the base
 * kernels' state bit for bit, on 2 threads. */
static void check_isas(void) {
  const char *isas[] = {"base", "avx2", "avx512"};
  snapshot ref, b;
  int nref = 0;
  for (int q = 0; q < 3; q++) {
    isa_ = isas[q];
    if (run(2, 1, "rotate", 1, 1, q ? &b : &ref) != 0) {
      CHECK(q > 0, "base kernels must run");
      printf("isa %s: not run here (not built, or the CPU lacks it)\n", isas[q]);
      continue;
    }
    if (q) {
      check_same(&b, &ref, isas[q]);
      release(&b);
      printf("isa %s: the same state as the base kernels\n", isas[q]);
    }
    nref++;
  }
  isa_ = "";
  printf("kernels compared: %d instruction sets\n", nref);
  if (nref) release(&ref);
}

int main(void) {
  const char *frames[] = {"rotate", "project"};
  for (int f = 0; f < 2; f++) {
    snapshot one, two, three, gen;
    CHECK(run(1, 1, frames[f], 1, 1, &one) == 0, "fused, 1 thread (%s)", frames[f]);
    CHECK(run(2, 1, frames[f], 1, 1, &two) == 0, "fused, 2 threads (%s)", frames[f]);
    CHECK(run(3, 1, frames[f], 1, 1, &three) == 0, "fused, 3 threads (%s)", frames[f]);
    CHECK(run(1, 0, frames[f], 1, 1, &gen) == 0, "general path (%s)", frames[f]);
    if (check_failures_) return check_finish("threads");
    printf("%s: %zu particles, %zu candidates, %.1f contacts per step, %ld list builds\n",
           frames[f], one.n, one.m, one.contacts_mean, one.builds);
    CHECK(one.contacts_mean > 0.05 * (double)one.n, "collisions all along (%.1f)",
          one.contacts_mean);
    CHECK(one.builds > 1, "lists rebuilt during the run (%ld)", one.builds);
    check_same(&two, &one, "2 threads");
    check_same(&three, &one, "3 threads");
    check_same(&gen, &one, "the general path");
    release(&one);
    release(&two);
    release(&three);
    release(&gen);
    /* the floor still: up to 32 steps per call (rebuilds and re-cuts inside the
       bursts), against one step per call on one thread */
    snapshot ref, b;
    CHECK(run(1, 1, frames[f], 0, 1, &ref) == 0, "still floor, 1 thread (%s)", frames[f]);
    if (check_failures_) return check_finish("threads");
    CHECK(ref.builds > 1, "still floor: lists rebuilt during the run (%ld)", ref.builds);
    for (int t = 1; t <= 3; t++) {
      char what[64];
      snprintf(what, sizeof what, "still floor, %d threads, 32 steps per call", t);
      CHECK(run(t, 1, frames[f], 0, 32, &b) == 0, "%s (%s)", what, frames[f]);
      if (check_failures_) break;
      printf("%s: %ld calls for 1500 steps, %ld list builds\n", what, b.calls, b.builds);
      if (b.fused)
        CHECK(b.calls <= 1500 / 32 + 2 * b.builds + 1, "%s: %ld calls", what, b.calls);
      else /* the general path takes one step per call */
        CHECK(b.calls == 1500, "%s: %ld calls on the general path", what, b.calls);
#ifndef ESF_MINIMAL
      CHECK(b.fused, "%s (%s): the fused step must run it", what, frames[f]);
#endif
      check_same(&b, &ref, what);
      release(&b);
    }
    release(&ref);
  }
  check_isas();
  check_rolling(roll_linear, "linear", 0, 3);
  check_rolling(roll_hertz, "Hertz", 2, 2);
  check_ledger();
  check_hertz();
  check_failure();
  check_leave();
  return check_finish("threads");
}
