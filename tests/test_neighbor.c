/* test_neighbor.c — the Verlet candidate lists never miss a contact.
 *
 * The lists are built with skin s and kept while no particle has moved more than s/2
 * (esf_neighbor_check). The guarantee: any two particles touching after such moves
 * were closer than s surface to surface at the build, so they are candidates; likewise
 * a particle touching a wall element. Checked against brute force (all pairs, all
 * elements) after random displacements of every particle up to just under s/2, for
 * size ratios 1:1, 1:3 and 1:5 and several skins, in a box with walls; and a single
 * particle moved just over s/2 makes the check ask for a rebuild. The walls are a box
 * and a faceted cylinder (indexed: its elements are found through the wall index's
 * grid); each build is repeated on 2 and 3 threads and must give the same lists, pair
 * for pair. Also the adaptive skin's rule and bounds, and the rebuild asked for by a
 * particle leaving the domain. */
#include <math.h>
#include <stdlib.h>

#include "rng.h"
#include "simtest.h"

static const char *const scene_fmt =
    "name: lists\n"
    "materials: {m: {density: 2500, kn: 1.0e4, friction: 0.3}}\n"
    "particles:\n"
    "  - generate: random\n"
    "    region: {min: [0.0, 0.0, 0.0], max: [0.03, 0.03, 0.03]}\n"
    "    count: %d\n"
    "    radius: {uniform: [%g, %g]}\n"
    "    material: m\n"
    "    seed: %d\n"
    "walls:\n"
    "  - {box: {min: [0, 0, 0], max: [0.03, 0.03, 0.03]},"
    " material: m}\n"
    "  - {cylinder: {base: [0.015, 0.015, 0.002], radius: 0.008, height: 0.026,"
    " segments: 40, caps: [top]}, material: m}\n"
    "search: {skin: %g}\n"
    "integrator: {dt: 1.0e-6}\n"
    "run: {steps: 1}\n"
    "output: {energy_every: 0}\n";

static int has_pair(const esf_contacts *c, uint32_t a, uint32_t b) {
  size_t lo = 0, hi = c->n; /* sorted by (a, b) */
  while (lo < hi) {
    size_t mid = (lo + hi) / 2;
    if (c->a[mid] < a || (c->a[mid] == a && c->b[mid] < b))
      lo = mid + 1;
    else
      hi = mid;
  }
  return lo < c->n && c->a[lo] == a && c->b[lo] == b;
}

static double uni(esf_rng *g, double a, double b) {
  return a + (b - a) * esf_rng_uniform(g);
}

/* Moves every particle by a random vector of length up to frac * skin / 2. */
static void jiggle(esf_particles *p, esf_rng *g, double skin, double frac) {
  for (size_t i = 0; i < p->n; i++) {
    double d[3], n2;
    do {
      for (int q = 0; q < 3; q++) d[q] = uni(g, -1, 1);
      n2 = v3_norm2(d);
    } while (n2 > 1 || n2 < 1e-6);
    double len = uni(g, 0, frac * 0.5 * skin) / sqrt(n2);
    for (int q = 0; q < 3; q++) p->x[3 * i + q] += len * d[q];
  }
}

/* The test scene with these particles and skin; 0 when it opened. */
static int open_case(simtest *T, int count, double rmin, double rmax, int seed,
                     double skin) {
  char yaml[2048];
  snprintf(yaml, sizeof yaml, scene_fmt, count, rmin, rmax, seed, skin);
  const int rc = simtest_open(T, yaml, NULL, 0);
  CHECK(rc == 0, "scene did not open: %s", T->err.msg);
  return rc;
}

/* Builds the lists on 2 and 3 threads too: the same pairs in the same order as on
 * nb->threads (1); returns the builds that differed. */
static int threads_differ(esf_sim *s) {
  esf_neighbor *nb = &s->nb;
  const esf_contacts *l[2] = {&nb->pp, &nb->pw};
  size_t n[2];
  uint32_t *ab[2][2];
  for (int q = 0; q < 2; q++) {
    n[q] = l[q]->n;
    for (int e = 0; e < 2; e++) {
      ab[q][e] = malloc((n[q] ? n[q] : 1) * sizeof(uint32_t));
      memcpy(ab[q][e], e ? l[q]->b : l[q]->a, n[q] * sizeof(uint32_t));
    }
  }
  const int t0 = nb->threads;
  int differ = 0;
  esf_error err;
  for (int T = 2; T <= 3; T++) {
    nb->threads = T;
    CHECK_OK(esf_neighbor_build(nb, &s->p, &s->walls, &err), err);
    for (int q = 0; q < 2; q++) /* l[q]: nb's lists, the new build's contents */
      if (l[q]->n != n[q] || memcmp(ab[q][0], l[q]->a, n[q] * sizeof(uint32_t)) ||
          memcmp(ab[q][1], l[q]->b, n[q] * sizeof(uint32_t)))
        differ++;
  }
  nb->threads = t0;
  for (int q = 0; q < 2; q++)
    for (int e = 0; e < 2; e++) free(ab[q][e]);
  return differ;
}

static void check_case(int count, double rmin, double rmax, double skin, int seed) {
  simtest T;
  if (open_case(&T, count, rmin, rmax, seed, skin)) return;
  esf_sim *s = &T.s;
  esf_particles *p = &s->p;
  esf_rng g;
  esf_rng_seed(&g, (uint64_t)seed * 7919u + 1);
  esf_error err;
  long missed_pp = 0, missed_pw = 0, touching_pp = 0, touching_pw = 0;
  int bad_check = 0, differ = 0;
  for (int round = 0; round < 6; round++) {
    int rc = esf_neighbor_build(&s->nb, p, &s->walls, &err);
    CHECK_OK(rc, err);
    if (rc) break;
    differ += threads_differ(s);
    /* half the rounds compress the packing first so that many pairs touch */
    jiggle(p, &g, skin, 0.999);
    int rebuild = 0;
    rc = esf_neighbor_check(&s->nb, p, 0.0, &rebuild, &err);
    CHECK_OK(rc, err);
    if (rebuild) bad_check++;
    for (size_t i = 0; i < p->n; i++) {
      for (size_t j = i + 1; j < p->n; j++) {
        double d[3];
        v3_sub(d, p->x + 3 * j, p->x + 3 * i);
        double R = p->radius[i] + p->radius[j];
        if (v3_norm2(d) >= R * R) continue;
        touching_pp++;
        if (!has_pair(&s->nb.pp, (uint32_t)i, (uint32_t)j)) missed_pp++;
      }
      for (size_t e = 0; e < s->walls.n; e++) {
        esf_wall_hit hit;
        esf_wall_nearest(&s->walls.e[e], p->x + 3 * i, &hit);
        if (hit.dist >= p->radius[i]) continue;
        touching_pw++;
        if (!has_pair(&s->nb.pw, (uint32_t)i, (uint32_t)e)) missed_pw++;
      }
    }
  }
  printf("n %d, radii %g-%g m, skin %g m: %ld pair and %ld wall contacts after moves, "
         "%ld and %ld missed\n",
         count, rmin, rmax, skin, touching_pp, touching_pw, missed_pp, missed_pw);
  CHECK(touching_pp >= 100, "enough touching pairs to test (%ld)", touching_pp);
  CHECK(touching_pw > 0, "some wall contacts to test (%ld)", touching_pw);
  CHECK(missed_pp == 0, "%ld particle pairs touching but not candidates", missed_pp);
  CHECK(missed_pw == 0, "%ld wall contacts touching but not candidates", missed_pw);
  CHECK(bad_check == 0, "moves under skin/2 asked for %d rebuilds", bad_check);
  CHECK(differ == 0, "%d builds on 2 or 3 threads gave other lists than on 1", differ);

  /* one particle moved just over skin/2 must trigger a rebuild */
  int rc = esf_neighbor_build(&s->nb, p, &s->walls, &err);
  CHECK_OK(rc, err);
  p->x[3 * (p->n / 2)] += 0.5 * skin * 1.001;
  int rebuild = 0;
  rc = esf_neighbor_check(&s->nb, p, 0.0, &rebuild, &err);
  CHECK(rc == 0 && rebuild == 1, "a move over skin/2 did not ask for a rebuild");
  simtest_close(&T);
}

/* The adaptive skin (esf_neighbor_skin_tune) on lists built for a given skin, with
 * the idle candidates m_s counted from the touch flags, set here: the balance
 * s' = s sqrt(C / (m_s I)) within a factor 2 of s and within the range; a fixed skin
 * (no range) untouched. And a particle outside the domain asks for a rebuild. */
static void check_skin(void) {
  simtest T;
  if (open_case(&T, 1500, 0.0010, 0.0010, 1, 0.0004)) return;
  esf_sim *s = &T.s;
  esf_neighbor *nb = &s->nb;
  const size_t n = s->p.n;
  esf_error err;
  CHECK_OK(esf_neighbor_build(nb, &s->p, &s->walls, &err), err);
  const size_t m = nb->pp.n;
  CHECK(m > n, "enough candidates (%zu for %zu particles)", m, n);
  for (size_t k = 0; k < m; k++) nb->pp.touch[k] = (uint8_t)(k % 2); /* half idle */
  const double ms = (double)(m - m / 2) / (double)n, s0 = 0.0004;
  esf_neighbor_skin_range(nb, 1e-5, 1e-3);
  /* I steps such that the balance asks for 0.8 s: s sqrt(C / (ms I)) = 0.8 s */
  const long I = (long)(ESF_SKIN_BUILD_COST / (ms * 0.64) + 0.5);
  nb->built_step = 1000;
  esf_neighbor_skin_tune(nb, n, 1000 + I);
  const double want = s0 * sqrt(ESF_SKIN_BUILD_COST / (ms * (double)I));
  CHECK(fabs(nb->skin - want) < 1e-12 * s0 && fabs(want / s0 - 0.8) < 0.01,
        "balance: skin %g, expected %g (0.8 of %g)", nb->skin, want, s0);
  nb->skin = s0; /* lists that lasted 100 times longer: at most halved */
  esf_neighbor_skin_tune(nb, n, 1000 + 100 * I);
  CHECK(nb->skin == 0.5 * s0, "long-lived lists: skin %g, expected %g", nb->skin,
        0.5 * s0);
  nb->skin = s0; /* a rebuild every step: at most doubled */
  esf_neighbor_skin_tune(nb, n, 1001);
  CHECK(nb->skin == 2 * s0, "short-lived lists: skin %g, expected %g", nb->skin, 2 * s0);
  nb->skin = s0; /* the range bounds it */
  esf_neighbor_skin_range(nb, 3.5e-4, 1e-3);
  esf_neighbor_skin_tune(nb, n, 1000 + 100 * I);
  CHECK(nb->skin == 3.5e-4, "lower bound: skin %g", nb->skin);
  nb->skin = s0; /* a fixed skin stays */
  esf_neighbor_skin_range(nb, 0, 0);
  esf_neighbor_skin_tune(nb, n, 1001);
  CHECK(nb->skin == s0, "fixed skin moved to %g", nb->skin);
  printf("adaptive skin: %zu particles, %.2f idle candidates each, I = %ld: skin %g -> "
         "%g (0.8)\n",
         n, ms, I, s0, want);

  /* a particle leaving the domain: the list check (general path) asks for a build */
  const double lo[3] = {-1e-3, -1e-3, -1e-3}, hi[3] = {0.031, 0.031, 0.031};
  nb->dom_lo = lo;
  nb->dom_hi = hi;
  CHECK_OK(esf_neighbor_build(nb, &s->p, &s->walls, &err), err);
  int rebuild = 1;
  CHECK_OK(esf_neighbor_check(nb, &s->p, 0.0, &rebuild, &err), err);
  CHECK(rebuild == 0, "inside the domain: no rebuild asked");
  s->p.x[3 * 7 + 2] = hi[2] + 1e-9; /* 1 nm over the top, far under skin/2 */
  CHECK_OK(esf_neighbor_check(nb, &s->p, 0.0, &rebuild, &err), err);
  CHECK(rebuild == 1, "a particle over the domain's top did not ask for a rebuild");
  nb->dom_lo = nb->dom_hi = NULL;
  simtest_close(&T);
}

int main(void) {
  check_skin();
  /* radii chosen so that the random fill is dense: many pairs come within the skin */
  check_case(1500, 0.0010, 0.0010, 0.0004, 1);
  check_case(1500, 0.0005, 0.0015, 0.0002, 2);
  check_case(800, 0.0004, 0.0020, 0.0008, 3);
  check_case(800, 0.0004, 0.0020, 0.00005, 4);
  return check_finish("neighbor");
}
