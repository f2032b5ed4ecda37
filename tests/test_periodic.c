/* test_periodic.c — periodic boundaries (domain.periodic; docs/physics.md#periodic-
 * boundaries) against numbers.
 *
 * Search: random polydisperse sets (positions up to 0.2 L outside the box, wrapped
 * first) with 1, 2 and 3 periodic axes: the pairs and images are brute force's at the
 * nearest image.
 * Pair across the face: an oblique frictional impact whose B crosses the periodic face
 * x = L during the contact (the wrap at a rebuild, the history carried), against the
 * same pair in mid-domain without periodic axes: the relative velocity, spins and
 * (unwrapped) relative position agree to rounding (the image position x_b + L rounds at
 * the magnitude of L, so the bits differ by a few ulps of L: tolerance 1e-9 of the
 * approach speed), and the fused step gives the general path's bits.
 * Frictional cloud in a fully periodic box: total momentum conserved to 1e-13 of
 * sum m |v| over many wraps; 1, 2 and 3 threads and the general path give the same
 * state and image counters (memcmp), and so under Lees-Edwards shear.
 * Homogeneous cooling (Haff 1983; Brilliantov & Pöschel 2004, ch. 20-21): a dilute
 * (nu = 0.05) frictionless gas with e = 0.9 in a fully periodic box follows
 * T(t) = T0 / (1 + t/tau)^2 within 10%, 1/tau = (2/3)(1 - e^2) n sigma^2 chi
 * sqrt(pi T0/m), chi = (1 - nu/2)/(1 - nu)^3 (Carnahan-Starling), e the linear
 * dashpot's restitution with the no-tension cut (simtest.h's closed form).
 * Lees-Edwards shear (domain.shear): the search with a shear offset against brute force;
 * a dilute gas at rest on average develops the linear profile, slope the shear rate
 * within 10%, residuals within 5% of rate L.
 * Input: a box too small for the minimum image, or an ODE method, is refused with the
 * domain's place. */
#include "simtest.h"
#include "search/cells_grid.h"
#include "search/periodic.h"
#include "util/rng.h"

/* ---- the search against brute force ------------------------------------------ */

/* Every pair within skin at its nearest image, by brute force, against
 * esf_periodic_pairs: the same pairs with the same images (n particles, radii 1:3,
 * periodic axes per mask, positions wrapped first). */
static void check_search(unsigned mask, size_t n, uint64_t seed, int le) {
  esf_periodic pb = {0};
  const double L[3] = {0.02, 0.025, 0.03}, skin = 0.0004;
  for (int q = 0; q < 3; q++)
    if (mask >> q & 1) {
      pb.on[q] = pb.any = 1;
      pb.len[q] = L[q];
    }
  if (le) { /* flow x, gradient z, the offset 0.37 L_x */
    pb.le = 1;
    pb.flow = 0;
    pb.grad = 2;
    pb.rate = 5.0;
  }
  const double t = 0.37 * L[0] / (5.0 * L[2]) + 3 * L[0] / (5.0 * L[2]);
  const double off = le ? esf_periodic_le_offset(&pb, t, NULL) : 0;
  esf_rng r;
  esf_rng_seed(&r, seed);
  double *x = malloc(3 * n * sizeof *x), *rad = malloc(n * sizeof *rad);
  double *v = calloc(3 * n, sizeof *v);
  int32_t *img = calloc(3 * n, sizeof *img);
  for (size_t i = 0; i < n; i++) {
    rad[i] = 0.0005 + 0.001 * esf_rng_uniform(&r);
    for (int q = 0; q < 3; q++) x[3 * i + q] = (1.4 * esf_rng_uniform(&r) - 0.2) * L[q];
  }
  const size_t moved = esf_periodic_wrap(&pb, n, x, v, t, img);
  esf_cells *c = NULL;
  esf_pairbuf out = {0};
  int8_t *pim = NULL;
  size_t cap = 0;
  esf_error err = {0};
  int rc = esf_cells_create(&c, &err);
  if (!rc) rc = esf_periodic_pairs(&pb, c, n, x, rad, skin, off, &out, &pim, &cap, &err);
  CHECK_OK(rc, err);
  size_t found = 0, missed = 0, wrong = 0, across = 0;
  for (size_t i = 0; i < n && !rc; i++)
    for (size_t j = i + 1; j < n; j++) {
      int8_t m[3] = {0, 0, 0};
      for (int q = 2; q >= 0; q--) /* the nearest image of j (the gradient z first) */
        if (pb.on[q]) {
          const double d = x[3 * j + q] - x[3 * i + q] + (le && !q ? m[2] * off : 0);
          m[q] = (int8_t)-floor(d / L[q] + 0.5);
        }
      double xb[3];
      esf_periodic_image(x + 3 * j, m, pb.len, xb);
      if (le) esf_periodic_le_image(&pb, m, off, xb);
      if (!esf_pair_near(x + 3 * i, xb, rad[i], rad[j], skin)) continue;
      found++;
      across += m[0] || m[1] || m[2];
      size_t k = 0;
      while (k < out.n && !(out.i[k] == i && out.j[k] == j)) k++;
      if (k == out.n)
        missed++;
      else if (memcmp(pim + 3 * k, m, 3))
        wrong++;
    }
  int sorted = 1;
  for (size_t k = 1; k < out.n; k++)
    if (out.i[k] < out.i[k - 1] || (out.i[k] == out.i[k - 1] && out.j[k] <= out.j[k - 1]))
      sorted = 0;
  int inside = 1;
  for (size_t i = 0; i < n; i++)
    for (int q = 0; q < 3; q++)
      if (pb.on[q] && !(x[3 * i + q] >= 0 && x[3 * i + q] < L[q])) inside = 0;
  printf(
      "search (axes mask %u%s): %zu wrapped, %zu pairs (%zu across faces), brute force "
      "%zu; missed %zu, wrong image %zu\n",
      mask, le ? ", sheared" : "", moved, out.n, across, found, missed, wrong);
  CHECK(inside, "wrapped into the box");
  CHECK(moved > 0, "some particles wrapped");
  CHECK(across > 10, "pairs across the faces (%zu)", across);
  CHECK(out.n == found && missed == 0 && wrong == 0 && sorted,
        "the brute-force pairs and images (%zu of %zu, %zu missed, %zu wrong, sorted %d)",
        out.n, found, missed, wrong, sorted);
  esf_cells_free(&c);
  esf_pairbuf_release(&out);
  free(pim);
  free(x);
  free(rad);
  free(img);
  free(v);
}
/* ---- a pair across the face ----------------------------------------------------------
 */

static const char *const pair_fmt =
    "name: pbc_pair\n"
    "gravity: [0, 0, 0]\n"
    "domain: {min: [0, -0.05, -0.05], max: [0.1, 0.05, 0.05]%s}\n"
    "materials: {glass: {density: 2500, kn: 1.0e4, restitution: 0.5, friction: 0.3}}\n"
    "particles:\n"
    "  - {material: glass, radius: 0.005, position: [%.17g, 0, 0], velocity: [2, 0, "
    "0.3]}\n"
    "  - {material: glass, radius: 0.005, position: [%.17g, 0, 0.002], velocity: [0, 0, "
    "-0.3]}\n"
    "integrator: {method: leapfrog, dt: 2.0e-6, fused: %s}\n"
    "search: {skin: 0.0004}\n"
    "run: {steps: 2000}\n"
    "output: {energy_every: 0}\n";

typedef struct pair_out {
  double dv[3], dw[3], dx[3], wa[3];
  int32_t img_b;
  int wrap_touching;
  long builds;
  double y[18];
} pair_out;

static int run_pair(int periodic, int fused, pair_out *o) {
  char scene[2048];
  const double xa = periodic ? 0.0896 : 0.0396, xb = periodic ? 0.0998 : 0.0498;
  snprintf(scene, sizeof scene, pair_fmt, periodic ? ", periodic: [x]" : "", xa, xb,
           fused ? "true" : "false");
  simtest T;
  int rc = simtest_open(&T, scene, NULL, 0);
  o->wrap_touching = -1; /* whether the pair touched when B was wrapped */
  while (!rc && T.s.step < 2000) {
    rc = simtest_step(&T);
    const esf_particles *p = &T.s.p;
    if (!rc && o->wrap_touching < 0 && p->img && (p->img[0] || p->img[3]))
      o->wrap_touching = esf_neighbor_touching(&T.s.nb) > 0;
  }
  if (!rc) {
    const esf_particles *p = &T.s.p;
    int ia = p->id[0] == 0 ? 0 : 1, ib = 1 - ia;
    for (int q = 0; q < 3; q++) {
      o->dv[q] = p->v[3 * ib + q] - p->v[3 * ia + q];
      o->dw[q] = p->w[3 * ib + q] - p->w[3 * ia + q];
      double ub = p->x[3 * ib + q], ua = p->x[3 * ia + q];
      if (p->img) {
        ub += p->img[3 * ib + q] * T.s.cfg.per.len[q];
        ua += p->img[3 * ia + q] * T.s.cfg.per.len[q];
      }
      o->dx[q] = ub - ua;
      o->wa[q] = p->w[3 * ia + q];
    }
    o->img_b = p->img ? p->img[3 * ib] : 0;
    o->builds = T.s.nb.builds;
    memcpy(o->y, p->y, sizeof o->y);
  }
  simtest_close(&T);
  return rc;
}

static void check_pair(void) {
  pair_out mid, per, per_gen;
  int rc = run_pair(0, 1, &mid);
  if (!rc) rc = run_pair(1, 1, &per);
  if (!rc) rc = run_pair(1, 0, &per_gen);
  CHECK(rc == 0, "pair runs");
  if (rc) return;
  CHECK(per.img_b == 1, "B crossed x = L once (image %d)", per.img_b);
  CHECK(per.wrap_touching == 1 && per_gen.wrap_touching == 1,
        "B was wrapped during the contact (%d, %d)", per.wrap_touching,
        per_gen.wrap_touching);
  CHECK(per.builds > 3, "the lists were rebuilt during the run (%ld)", per.builds);
  CHECK(mid.dv[0] > 0.5, "the pair rebounded (relative velocity %g m/s)", mid.dv[0]);
  double ev = 0, ex = 0, ew = 0;
  for (int q = 0; q < 3; q++) {
    ev = fmax(ev, fabs(per.dv[q] - mid.dv[q]));
    ew = fmax(ew, fabs(per.dw[q] - mid.dw[q]));
    ex = fmax(ex, fabs(per.dx[q] - mid.dx[q]));
  }
  printf("pair across x = L vs mid-domain: |d(v_b - v_a)| %.3g m/s, |d(w_b - w_a)| %.3g "
         "rad/s, |d(x_b - x_a)| %.3g m; relative velocity (%.6f, %.6f, %.6f)\n",
         ev, ew, ex, per.dv[0], per.dv[1], per.dv[2]);
  CHECK(ev < 1e-9, "relative velocity as in mid-domain (%.3g m/s)", ev);
  CHECK(ew < 1e-6, "relative spin as in mid-domain (%.3g rad/s)", ew);
  CHECK(ex < 1e-12, "relative position as in mid-domain (%.3g m)", ex);
  CHECK(fabs(mid.wa[1]) > 1, "friction spun the spheres (%g rad/s)", mid.wa[1]);
  CHECK(memcmp(per.wa, mid.wa, sizeof per.wa) == 0 || fabs(per.wa[1] - mid.wa[1]) < 1e-6,
        "A's spin as in mid-domain (%.17g, %.17g rad/s)", per.wa[1], mid.wa[1]);
  CHECK(memcmp(per.y, per_gen.y, sizeof per.y) == 0,
        "periodic pair: fused step and general path give the same bits");
}

/* ---- a frictional cloud --------------------------------------------------------------
 */

static const char *const cloud =
    "name: pbc_cloud\n"
    "gravity: [0, 0, 0]\n"
    "domain: {min: [0, 0, 0], max: [0.03, 0.03, 0.03], periodic: [x, y, z]}\n"
    "materials: {glass: {density: 2500, kn: 2.0e4, restitution: 0.5, friction: 0.5}}\n"
    "particles:\n"
    "  - generate: random\n"
    "    region: {min: [0, 0, 0], max: [0.03, 0.03, 0.03]}\n"
    "    count: 300\n"
    "    radius: {uniform: [0.001, 0.0018]}\n"
    "    material: glass\n"
    "    seed: 5\n"
    "integrator: {method: leapfrog, dt: auto, frac: 0.3}\n"
    "run: {steps: 3000}\n"
    "output: {energy_every: 0}\n";

/* Gaussian velocities (Box-Muller), std sd per component; spin: uniform spins too. */
static void random_velocities(esf_particles *p, double sd, uint64_t seed, int spin) {
  esf_rng r;
  esf_rng_seed(&r, seed);
  for (size_t i = 0; i < 3 * p->n; i++) {
    const double u1 = 1.0 - esf_rng_uniform(&r), u2 = esf_rng_uniform(&r);
    p->v[i] = sd * sqrt(-2 * log(u1)) * cos(2 * ESF_PI * u2);
    if (spin) p->w[i] = 100 * sd * (esf_rng_uniform(&r) - 0.5);
  }
}

typedef struct cloud_out {
  size_t n;
  double *y;
  int32_t *img;
  double p0[3], p1[3], pabs;
  long wraps;
} cloud_out;

static int run_cloud(int threads, int fused, int shear, cloud_out *o) {
  const char *sets[] = {fused ? "integrator.fused=true" : "integrator.fused=false",
                        "domain.shear={rate: 20, flow: x, gradient: z}"};
  simtest T;
  int rc = simtest_open(&T, cloud, sets, shear ? 2 : 1);
  if (rc) return rc;
  T.s.cfg.threads = threads;
  T.s.cfg.range_work = 1; /* one range per thread, however small the scene */
  esf_particles *p = &T.s.p;
  random_velocities(p, 0.5, 17, 1);
  o->pabs = 0;
  for (int q = 0; q < 3; q++) o->p0[q] = o->p1[q] = 0;
  for (size_t i = 0; i < p->n; i++)
    for (int q = 0; q < 3; q++) {
      o->p0[q] += p->mass[i] * p->v[3 * i + q];
      o->pabs += p->mass[i] * fabs(p->v[3 * i + q]);
    }
  while (!rc && T.s.step < 3000) {
    T.s.burst = 3000 - T.s.step < 50 ? 3000 - T.s.step : 50;
    rc = simtest_step(&T);
  }
  if (!rc) {
    o->n = p->n;
    o->y = malloc(9 * p->n * sizeof *o->y);
    o->img = malloc(3 * p->n * sizeof *o->img);
    for (size_t i = 0; i < p->n; i++) { /* by id: the schemes renumber differently */
      const size_t d = (size_t)p->id[i];
      for (int b = 0; b < 3; b++)
        memcpy(o->y + 3 * (b * p->n + d), p->y + 3 * (b * p->n + i), 3 * sizeof *o->y);
      memcpy(o->img + 3 * d, p->img + 3 * i, 3 * sizeof *o->img);
    }
    o->wraps = 0;
    for (size_t i = 0; i < p->n; i++)
      for (int q = 0; q < 3; q++) {
        o->p1[q] += p->mass[i] * p->v[3 * i + q];
        o->wraps += labs((long)p->img[3 * i + q]);
      }
  }
  simtest_close(&T);
  return rc;
}

/* shear: under Lees-Edwards shear (momentum not conserved: the wraps change it). */
static void check_cloud(int shear) {
  cloud_out o[4] = {{0}};
  int rc = 0;
  for (int t = 0; t < 3 && !rc; t++) rc = run_cloud(t + 1, 1, shear, &o[t]);
  if (!rc) rc = run_cloud(2, 0, shear, &o[3]);
  CHECK(rc == 0, "cloud runs");
  if (rc) return;
  double dp = 0;
  for (int q = 0; q < 3; q++) dp = fmax(dp, fabs(o[0].p1[q] - o[0].p0[q]));
  printf(
      "periodic cloud%s: %zu particles, %ld wraps, |dP| %.3g of sum m|v| %.3g kg m/s\n",
      shear ? " (sheared)" : "", o[0].n, o[0].wraps, dp, o[0].pabs);
  CHECK(o[0].wraps > 100, "many wraps (%ld)", o[0].wraps);
  CHECK(shear || dp < 1e-13 * o[0].pabs, "momentum conserved (|dP| %.3g, sum m|v| %.3g)",
        dp, o[0].pabs);
  for (int k = 1; k < 4; k++) {
    CHECK(o[k].n == o[0].n, "same count");
    if (o[k].n != o[0].n) continue;
    CHECK(memcmp(o[k].y, o[0].y, 9 * o[0].n * sizeof(double)) == 0,
          "%s: the same state bit for bit", k < 3 ? "threads" : "general path");
    CHECK(memcmp(o[k].img, o[0].img, 3 * o[0].n * sizeof(int32_t)) == 0,
          "%s: the same image counters", k < 3 ? "threads" : "general path");
  }
  for (int k = 0; k < 4; k++) {
    free(o[k].y);
    free(o[k].img);
  }
}

/* ---- homogeneous cooling -------------------------------------------------------------
 */

static const char *const haff =
    "name: haff\n"
    "gravity: [0, 0, 0]\n"
    "domain: {min: [0, 0, 0], max: [0.0347, 0.0347, 0.0347], periodic: [x, y, z]}\n"
    "materials: {glass: {density: 2500, kn: 1.0e4, restitution: 0.9, friction: 0}}\n"
    "particles:\n"
    "  - generate: random\n"
    "    region: {min: [0, 0, 0], max: [0.0347, 0.0347, 0.0347]}\n"
    "    count: 500\n"
    "    radius: 0.001\n"
    "    material: glass\n"
    "    seed: 9\n"
    "integrator: {method: leapfrog, dt: auto, frac: 0.1}\n"
    "run: {duration: 1}\n"
    "output: {energy_every: 0}\n";

static double temperature(const esf_particles *p) {
  double V[3] = {0, 0, 0}, M = 0, e = 0;
  for (size_t i = 0; i < p->n; i++) {
    M += p->mass[i];
    for (int q = 0; q < 3; q++) V[q] += p->mass[i] * p->v[3 * i + q];
  }
  for (int q = 0; q < 3; q++) V[q] /= M;
  for (size_t i = 0; i < p->n; i++)
    for (int q = 0; q < 3; q++) {
      const double u = p->v[3 * i + q] - V[q];
      e += p->mass[i] * u * u;
    }
  return e / (3.0 * (double)p->n); /* energy per degree of freedom, J */
}

/* Opens a gas scene and gives it Gaussian velocities of std sd (the mean removed when
 * still); 0 on success. */
static int open_gas(simtest *T, const char *scene, double sd, uint64_t seed, int still) {
  int rc = simtest_open(T, scene, NULL, 0);
  CHECK(rc == 0, "gas scene %s", T->s.cfg.name);
  if (rc) return rc;
  esf_particles *p = &T->s.p;
  random_velocities(p, sd, seed, 0);
  double V[3] = {0, 0, 0};
  for (size_t i = 0; i < p->n && still; i++)
    for (int q = 0; q < 3; q++) V[q] += p->v[3 * i + q] / (double)p->n;
  for (size_t i = 0; i < p->n && still; i++)
    for (int q = 0; q < 3; q++) p->v[3 * i + q] -= V[q];
  return ESF_OK;
}

static void check_haff(void) {
  simtest T;
  int rc = open_gas(&T, haff, 1.0, 23, 0);
  if (rc) return;
  esf_particles *p = &T.s.p;
  const double L = 0.0347, sigma = 0.002, m = p->mass[0], N = (double)p->n;
  const double n = N / (L * L * L), nu = n * ESF_PI * sigma * sigma * sigma / 6;
  const double chi = (1 - nu / 2) / ((1 - nu) * (1 - nu) * (1 - nu));
  const double w = sqrt(1.0e4 / (0.5 * m));
  const double e = cut_impact_closed_form(esf_restitution_gamma(0.9), w).e;
  const double T0 = temperature(p);
  const double tau =
      1.0 / (2.0 / 3.0 * (1 - e * e) * n * sigma * sigma * chi * sqrt(ESF_PI * T0 / m));
  printf("haff: N %.0f, nu %.4f, chi %.4f, e %.5f, T0 %.4g J, tau %.4g s, dt %.3g s\n", N,
         nu, chi, e, T0, tau, T.s.dt);
  const double marks[] = {0.25, 0.5, 1.0, 1.5};
  double worst = 0;
  for (int k = 0; k < 4 && !rc; k++) {
    const double t_end = marks[k] * tau;
    while (!rc && T.s.t < t_end) {
      T.s.burst = 100;
      rc = simtest_step(&T);
    }
    const double Tm = temperature(p), Th = T0 / ((1 + T.s.t / tau) * (1 + T.s.t / tau));
    printf("  t/tau %.3f: T/T0 %.4f, Haff %.4f, ratio %.4f\n", T.s.t / tau, Tm / T0,
           Th / T0, Tm / Th);
    worst = fmax(worst, fabs(Tm / Th - 1));
  }
  CHECK(rc == 0, "haff run");
  CHECK(worst < 0.10, "T(t) follows Haff's law within 10%% (worst %.3f)", worst);
  simtest_close(&T);
}

/* ---- Lees-Edwards shear -------------------------------------------------------------
 */

static const char *const sheared =
    "name: shear\n"
    "gravity: [0, 0, 0]\n"
    "domain: {min: [0, 0, 0], max: [0.03, 0.03, 0.03], periodic: [x, y, z],\n"
    "         shear: {rate: 20, flow: x, gradient: z}}\n"
    "materials: {glass: {density: 2500, kn: 2.0e3, restitution: 0.9, friction: 0}}\n"
    "particles:\n"
    "  - generate: random\n"
    "    region: {min: [0, 0, 0], max: [0.03, 0.03, 0.03]}\n"
    "    count: 600\n"
    "    radius: 0.001\n"
    "    material: glass\n"
    "    seed: 13\n"
    "integrator: {method: leapfrog, dt: auto, frac: 0.3}\n"
    "run: {duration: 1}\n"
    "output: {energy_every: 0}\n";

/* A dilute gas (nu = 0.09) at rest on average, sheared by the Lees-Edwards images at
 * rate 20/s: the mean flow velocity across 6 layers of the gradient axis, averaged
 * over 0.35 to 0.45 s, is linear with slope the shear rate. */
static void check_shear(void) {
  simtest T;
  int rc = open_gas(&T, sheared, 0.3, 29, 1);
  if (rc) return;
  esf_particles *p = &T.s.p;
  enum { NB = 6 };
  const double L = 0.03, rate = 20;
  double sum[NB] = {0}, cnt[NB] = {0};
  long wraps = 0;
  while (!rc && T.s.t < 0.45) {
    rc = simtest_step(&T);
    if (rc || T.s.t < 0.35 || T.s.step % 20) continue;
    for (size_t i = 0; i < p->n; i++) {
      int b = (int)(p->x[3 * i + 2] / L * NB);
      b = b < 0 ? 0 : b >= NB ? NB - 1 : b;
      sum[b] += p->v[3 * i];
      cnt[b] += 1;
    }
  }
  CHECK(rc == 0, "shear run");
  for (size_t i = 0; i < p->n; i++) wraps += labs((long)p->img[3 * i + 2]);
  double sz = 0, su = 0, szz = 0, szu = 0, u[NB], z[NB];
  for (int b = 0; b < NB; b++) {
    z[b] = (b + 0.5) * L / NB;
    u[b] = cnt[b] ? sum[b] / cnt[b] : 0;
    sz += z[b];
    su += u[b];
    szz += z[b] * z[b];
    szu += z[b] * u[b];
  }
  const double slope = (NB * szu - sz * su) / (NB * szz - sz * sz);
  const double icpt = (su - slope * sz) / NB;
  double worst = 0;
  for (int b = 0; b < NB; b++) worst = fmax(worst, fabs(u[b] - (icpt + slope * z[b])));
  printf("shear: %ld gradient wraps; mean u_x by layer:", wraps);
  for (int b = 0; b < NB; b++) printf(" %.4f", u[b]);
  printf(" m/s; slope %.3f 1/s (rate %.0f), largest residual %.4f m/s (%.3f of rate L)\n",
         slope, rate, worst, worst / (rate * L));
  CHECK(wraps > 20, "particles crossed the gradient faces (%ld)", wraps);
  CHECK(fabs(slope / rate - 1) < 0.1, "linear profile with the shear rate (%.3f)", slope);
  CHECK(worst < 0.05 * rate * L, "linear within 5%% of rate L (%.4f m/s)", worst);
  simtest_close(&T);
}

/* ---- refusals ------------------------------------------------------------------------
 */

static void check_refusals(void) {
  simtest T;
  const char *small[] = {"domain.max=[0.007, 0.03, 0.03]"};
  int rc = simtest_open(&T, cloud, small, 1);
  CHECK(rc == ESF_EINPUT && strstr(T.err.msg, "test.yaml:3:") &&
            strstr(T.err.msg, "periodic"),
        "box too small for the minimum image: %s", T.err.msg);
  simtest_close(&T);
  const char *folded[] = {"domain.max=[0.02, 0.03, 0.03]"}; /* x in (0.02, 0.03) wraps */
  rc = simtest_open(&T, cloud, folded, 1);
  CHECK(rc == ESF_EINPUT && strstr(T.err.msg, "start overlapping"),
        "particles overlapping across a periodic face at the start: %s", T.err.msg);
  simtest_close(&T);
  const char *ode[] = {"integrator.method=rk4"};
  rc = simtest_open(&T, cloud, ode, 1);
  CHECK(rc == ESF_EINPUT && strstr(T.err.msg, "test.yaml:3:") &&
            strstr(T.err.msg, "periodic"),
        "ODE methods refuse periodic axes: %s", T.err.msg);
  simtest_close(&T);
  const char *vv[] = {"integrator.method=verlet",
                      "domain.shear={rate: 20, flow: x, gradient: z}"};
  rc = simtest_open(&T, cloud, vv, 2);
  CHECK(rc == ESF_EINPUT && strstr(T.err.msg, "test.yaml:3:") &&
            strstr(T.err.msg, "leapfrog only"),
        "Verlet refuses the shear: %s", T.err.msg);
  simtest_close(&T);
  const char *twod[] = {"dimension=2", "domain.periodic=[x, y]"};
  rc = simtest_open(&T, cloud, twod, 2);
  CHECK(rc == ESF_EINPUT && strstr(T.err.msg, "y cannot be periodic"),
        "2D: y is not periodic: %s", T.err.msg);
  simtest_close(&T);
}

int main(void) {
  check_search(7, 1500, 3, 0);
  check_search(1, 1200, 4, 0);
  check_search(5, 1000, 5, 0);
  check_search(5, 1000, 6, 1);
  check_search(7, 1500, 7, 1);
  check_pair();
  check_cloud(0);
  check_cloud(1);
  check_haff();
  check_shear();
  check_refusals();
  return check_finish("periodic");
}
