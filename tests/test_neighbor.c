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
 * for pair. Also the adaptive skin's rule and bounds, the rebuild asked for by a
 * particle leaving the domain, and the history transfer of a build (check_transfer). */
#include <math.h>
#include <stdlib.h>

#include "simtest.h"
#include "util/rng.h"

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
    "contact: {max_overlap: 2.0}\n" /* the random fill ignores the cylinder: lists only */
    "integrator: {dt: 1.0e-6}\n"
    "run: {steps: 1}\n"
    "output: {energy_every: 0}\n";

static int has_pair(const esf_candidates *c, uint32_t a, uint32_t b) {
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
  const esf_candidates *l[2] = {&nb->pp, &nb->pw};
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
  CHECK(s->nb.pp.bond == NULL && s->nb.pw.bond == NULL,
        "a scene without bonds keeps bond states");

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

/* A value for field q of the history of the contact with key (a, b) (a pseudo-random
 * function of the key, so that a carried history is recognised wherever it lands). */
static double keyed(uint32_t a, uint32_t b, int q) {
  uint64_t z =
      ((uint64_t)a << 32 | b) * 0x9E3779B97F4A7C15u + (uint64_t)q * 0xBF58476D1CE4E5B9u;
  z ^= z >> 29;
  z *= 0x94D049BB133111EBu;
  z ^= z >> 32;
  return (double)(z % 1000003u) + 0.125; /* never 0 */
}

/* Which contacts are marked touching: those whose key the hash picks (about 60%),
 * none when off, and for particle pairs (p not NULL) only those closer than gmax
 * surface to surface (so that a build with a smaller skin keeps them as candidates). */
typedef struct mark_rule {
  const esf_particles *p;
  double gmax; /* m */
  int off;
} mark_rule;

static int marked(const mark_rule *m, uint32_t a, uint32_t b) {
  if (m->off || keyed(a, b, 99) >= 600000.0) return 0;
  if (!m->p) return 1;
  double d[3];
  v3_sub(d, m->p->x + 3 * (size_t)b, m->p->x + 3 * (size_t)a);
  return v3_norm(d) - m->p->radius[a] - m->p->radius[b] < m->gmax;
}

/* Marks the contacts of a list touching by the rule and gives every one a keyed
 * history, carried velocity and (where the list keeps them) bond state (the others'
 * must not be carried); returns how many touch. */
static size_t mark_list(esf_candidates *c, const mark_rule *m) {
  size_t nt = 0;
  for (size_t k = 0; k < c->n; k++) {
    const uint32_t a = c->a[k], b = c->b[k];
    c->touch[k] = (uint8_t)marked(m, a, b);
    nt += c->touch[k];
    esf_contact_hist *h = &c->h[k];
    for (int q = 0; q < 3; q++) {
      h->xi[q] = keyed(a, b, q);
      h->n[q] = keyed(a, b, 3 + q);
      c->vc0[3 * k + q] = keyed(a, b, 6 + q);
    }
    if (c->bond)
      c->bond[k] = (esf_contact_bond){keyed(a, b, 9), (int32_t)keyed(a, b, 10), 0};
  }
  return nt;
}

/* After a build: every candidate whose key was in the old list (its keys in old) and
 * marked has its keyed history, velocity and flag, every other one zeros; *carried
 * counts the former. Returns the candidates that were wrong. */
static long check_list(const esf_candidates *c, const esf_candidates *old,
                       const mark_rule *m, size_t *carried) {
  long bad = 0;
  for (size_t k = 0; k < c->n; k++) {
    const uint32_t a = c->a[k], b = c->b[k];
    const int was = has_pair(old, a, b) && marked(m, a, b);
    const esf_contact_hist *h = &c->h[k];
    int ok = c->touch[k] == was;
    for (int q = 0; q < 3; q++) {
      ok &= h->xi[q] == (was ? keyed(a, b, q) : 0.0);
      ok &= h->n[q] == (was ? keyed(a, b, 3 + q) : 0.0);
      ok &= c->vc0[3 * k + q] == (was ? keyed(a, b, 6 + q) : 0.0);
    }
    if (c->bond) {
      ok &= c->bond[k].s == (was ? keyed(a, b, 9) : 0.0);
      ok &= c->bond[k].on == (was ? (int32_t)keyed(a, b, 10) : 0);
      ok &= c->bond[k].spare == 0;
    }
    bad += !ok;
    *carried += (size_t)was;
  }
  return bad;
}

/* The history transfer of a build: the lists built, their contacts marked touching or
 * not with keyed histories, then built again with a larger skin (more candidates, a
 * larger storage), on 3 threads, and again with a much smaller one (a fraction of
 * the candidates: the storage is let go and taken afresh), the pairs marked only
 * where they stay candidates and no wall contact marked: each marked contact's
 * history, carried velocity and flag (and bond state: the particle list of a scene
 * with bonds keeps them, the wall list never) reach the new candidate with its key,
 * for particle pairs and wall contacts alike, and nothing of the others does. */
static void check_transfer(void) {
  simtest T;
  if (open_case(&T, 1500, 0.0005, 0.0015, 5, 0.0002)) return;
  esf_sim *s = &T.s;
  esf_neighbor *nb = &s->nb;
  esf_error err;
  nb->carry = 1; /* as the ODE methods: the carried velocities too */
  nb->bonds = 1; /* as a scene with bonds: the particle pairs' bond states too */
  const double skins[3] = {0.0006, 0.0012, 0.00005};
  const int threads[3] = {1, 3, 2};
  CHECK_OK(esf_neighbor_build(nb, &s->p, &s->walls, &err), err);
  for (int r = 0; r < 3; r++) {
    esf_candidates *l[2] = {&nb->pp, &nb->pw};
    const int shrink = skins[r] < nb->skin;
    const mark_rule rule[2] = {{&s->p, shrink ? 0.5 * skins[r] : INFINITY, 0},
                               {NULL, 0.0, shrink}};
    size_t nmark[2], carried[2] = {0, 0}, cap0 = nb->pp.cap;
    long bad[2];
    esf_candidates old[2]; /* the old lists' keys (sorted by (a, b), for has_pair) */
    for (int q = 0; q < 2; q++) {
      nmark[q] = mark_list(l[q], &rule[q]);
      memset(&old[q], 0, sizeof old[q]);
      old[q].n = l[q]->n;
      old[q].a = malloc((old[q].n ? old[q].n : 1) * sizeof(uint32_t));
      old[q].b = malloc((old[q].n ? old[q].n : 1) * sizeof(uint32_t));
      memcpy(old[q].a, l[q]->a, old[q].n * sizeof(uint32_t));
      memcpy(old[q].b, l[q]->b, old[q].n * sizeof(uint32_t));
    }
    nb->skin = skins[r];
    nb->threads = threads[r];
    CHECK_OK(esf_neighbor_build(nb, &s->p, &s->walls, &err), err);
    for (int q = 0; q < 2; q++) {
      bad[q] = check_list(l[q], &old[q], &rule[q], &carried[q]);
      free(old[q].a);
      free(old[q].b);
    }
    printf("transfer, skin %g, %d threads: %zu pair candidates (room %zu -> %zu), %zu of "
           "%zu touching carried; walls %zu of %zu; wrong %ld, %ld\n",
           skins[r], threads[r], nb->pp.n, cap0, nb->pp.cap, carried[0], nmark[0],
           carried[1], nmark[1], bad[0], bad[1]);
    CHECK(nmark[0] >= (shrink ? 50u : 500u) && (shrink || nmark[1] >= 20),
          "enough touching contacts (%zu, %zu)", nmark[0], nmark[1]);
    CHECK(carried[0] == nmark[0] && carried[1] == nmark[1],
          "touching contacts lost: pairs %zu of %zu, walls %zu of %zu", carried[0],
          nmark[0], carried[1], nmark[1]);
    CHECK(nb->pp.bond && !nb->pw.bond, "bond states kept where they should not be, or "
                                       "not where they should");
    CHECK(bad[0] == 0 && bad[1] == 0,
          "%ld pair and %ld wall candidates with a wrong history, velocity or flag",
          bad[0], bad[1]);
    if (shrink)
      CHECK(nb->pp.cap < cap0, "the long list's storage kept (%zu for %zu candidates)",
            nb->pp.cap, nb->pp.n);
  }
  nb->threads = 1;
  simtest_close(&T);
}

int main(void) {
  check_skin();
  check_transfer();
  /* radii chosen so that the random fill is dense: many pairs come within the skin */
  check_case(1500, 0.0010, 0.0010, 0.0004, 1);
  check_case(1500, 0.0005, 0.0015, 0.0002, 2);
  check_case(800, 0.0004, 0.0020, 0.0008, 3);
  check_case(800, 0.0004, 0.0020, 0.00005, 4);
  return check_finish("neighbor");
}
