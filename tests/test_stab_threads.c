/* test_stab_threads.c — the live stability check (model/stability.h) gives the same
 * bits on 1, 2 and 3 threads.
 *
 * A jittered simple cubic pack of 4096 spheres (16^3, spacing 1.9 mm, radii 0.95-1.05
 * mm, so every neighbour overlaps) in a box whose floor and two side walls touch the
 * outer layers: four blocks of the threaded pass, pairs crossing between them, wall
 * contacts. After two leapfrog steps (tangential histories), the check with its top
 * mode (esf_stability_estimate, with_mode 1) on 1, 2 and 3 threads: lambda, omega, xi,
 * dt_limit compared with memcmp, the contacts, Lanczos steps and the mode's particles
 * equal. Variants: the linear law with dashpots, friction and rolling resistance
 * (epsd); the Hertz-Mindlin law; local damping; 4096 disks (64^2, 2D: frozen
 * coordinates). */
#include <stdlib.h>
#include <string.h>

#include "model/stability.h"
#include "simtest.h"

#define SIDE 16

static const char *const scene_fmt = /* %d: dimension; %s: the pack; the box's y, x */
    "name: stab_threads\n"
    "dimension: %d\n"
    "materials:\n"
    "  glass: {density: 2500, kn: 1.0e4, restitution: 0.5, friction: 0.5,"
    " rolling_friction: 0.05}\n"
    "particles:\n"
    "  - {file: %s, material: glass}\n"
    "walls:\n"
    "  - {box: {min: [0, %s, 0], max: [%s, %s, 0.2]}, open: [top],"
    " material: glass}\n"
    "integrator: {method: leapfrog, dt: auto, frac: 0.2, stability: off}\n"
    "run: {steps: 2}\n"
    "output: {every: 0, energy_every: 0}\n";

/* 16^3 spheres, or 64^2 disks in the x-z plane (dim 2) */
static int write_pack(const char *path, int dim) {
  FILE *f = fopen(path, "w");
  if (!f) return 1;
  fprintf(f, "x,y,z,radius\n");
  uint64_t h = 0x2545F4914F6CDD1Dull;
  const double sp = 0.0019, r = 0.001;
  for (int k = 0; k < SIDE * SIDE * SIDE; k++) {
    double q[4];
    for (int j = 0; j < 4; j++) { /* xorshift: jitter 0.05 mm, radius +-5% */
      h ^= h << 13, h ^= h >> 7, h ^= h << 17;
      q[j] = (double)(h >> 11) * 0x1p-53 - 0.5;
    }
    int i[3] = {k % SIDE, k / SIDE % SIDE, k / (SIDE * SIDE)};
    if (dim == 2) i[0] = k % (4 * SIDE), i[1] = 0, i[2] = k / (4 * SIDE), q[1] = 0;
    fprintf(f, "%.17g,%.17g,%.17g,%.17g\n", 0.0009 + i[0] * sp + 1e-4 * q[0],
            dim == 2 ? 0.0 : 0.0009 + i[1] * sp + 1e-4 * q[1],
            0.0009 + i[2] * sp + 1e-4 * q[2], r * (1 + 0.1 * q[3]));
  }
  return fclose(f) != 0;
}

static void same(const char *what, const esf_stability *a, const esf_stability *b,
                 int nth) {
  CHECK(!memcmp(&a->lambda, &b->lambda, sizeof a->lambda) &&
            !memcmp(&a->omega, &b->omega, sizeof a->omega) &&
            !memcmp(&a->xi, &b->xi, sizeof a->xi) &&
            !memcmp(&a->dt_limit, &b->dt_limit, sizeof a->dt_limit),
        "%s, %d threads: lambda %.17g omega %.17g xi %.17g dt_limit %.17g against one "
        "thread's %.17g %.17g %.17g %.17g",
        what, nth, b->lambda, b->omega, b->xi, b->dt_limit, a->lambda, a->omega, a->xi,
        a->dt_limit);
  CHECK(a->contacts == b->contacts && a->iters == b->iters && a->id == b->id &&
            a->other == b->other,
        "%s, %d threads: %zu contacts, %d steps, mode %lld-%lld against %zu, %d, "
        "%lld-%lld",
        what, nth, b->contacts, b->iters, (long long)b->id, (long long)b->other,
        a->contacts, a->iters, (long long)a->id, (long long)a->other);
}

static void variant(const char *what, const char *yaml, const char *const *sets,
                    int nsets) {
  simtest T;
  if (simtest_open(&T, yaml, sets, nsets)) {
    CHECK(0, "%s: scene opens", what);
    return;
  }
  for (int k = 0; k < 2; k++)
    if (simtest_step(&T)) CHECK(0, "%s: step", what);
  esf_stability st[3];
  for (int t = 1; t <= 3; t++) {
    T.s.cfg.threads = t;
    int rc = esf_stability_estimate(&T.s, T.s.dt, 1, &st[t - 1], &T.err);
    CHECK(rc == 0, "%s, %d threads: estimate: %s", what, t, T.err.msg);
  }
  const double per = T.s.cfg.dim == 3 ? 2.5 : 1.8; /* contacts a particle, at least */
  CHECK(st[0].contacts > per * SIDE * SIDE * SIDE && st[0].lambda > 0 &&
            st[0].other >= -1,
        "%s: the pack's network (%zu contacts, lambda %g)", what, st[0].contacts,
        st[0].lambda);
  for (int t = 2; t <= 3; t++) same(what, &st[0], &st[t - 1], t);
  printf("%s: %zu contacts, %d Lanczos steps, lambda %.17g, omega %.10g rad/s, xi %.6g, "
         "mode %lld-%lld: the same bits on 1, 2, 3 threads\n",
         what, st[0].contacts, st[0].iters, st[0].lambda, st[0].omega, st[0].xi,
         (long long)st[0].id, (long long)st[0].other);
  simtest_close(&T);
}

int main(void) {
  const char *pack = "test_stab_threads_pack.csv";
  char yaml[1024];
  for (int dim = 3; dim >= 2; dim--) {
    if (write_pack(pack, dim)) {
      CHECK(0, "writes %s", pack);
      return check_finish("stab_threads");
    }
    if (dim == 3)
      snprintf(yaml, sizeof yaml, scene_fmt, 3, pack, "0", "0.0305", "0.0305");
    else
      snprintf(yaml, sizeof yaml, scene_fmt, 2, pack, "-0.01", "0.1225", "0.01");
    if (dim == 2) {
      variant("2D disks", yaml, NULL, 0);
      break;
    }
    variant("linear, rolling resistance", yaml, NULL, 0);
    const char *hz[] = {"materials.glass={density: 2500, youngs_modulus: 1.0e8, "
                        "poisson_ratio: 0.3, restitution: 0.3, friction: 0.3}"};
    variant("Hertz-Mindlin", yaml, hz, 1);
    const char *loc[] = {"damping={local: {coefficient: 0.1}}"};
    variant("local damping", yaml, loc, 1);
  }
  remove(pack);
  return check_finish("stab_threads");
}
