/* test_wall_fast.c — the fast wall pass (src/wall_fast.c) gives the same bits as the
 * general one (forces.c's esf_forces_wall_particle, committing), and the fused step
 * still words an overlap failure as the general path does.
 *
 * Each scene runs with the fused leapfrog (which now takes the fast pass); before every
 * step, for every particle with wall candidates, both passes evaluate the same state
 * from the same history, once adding to zero and once to the particle's last totals
 * (the summation order), and f, t, the touching count, the return code and every
 * candidate's history record and flag are compared with memcmp. Scenes:
 *   box    — 300 spheres of two materials fall into a 5-face box with a triangular
 *            shelf; spheres start in a corner (3 faces), on an edge (2 faces) and
 *            sliding and spinning on the floor (Coulomb cap); rotate and project frames;
 *   edges  — a ridge roof and a V trough of two quadrilaterals each (shared edge and
 *            vertex hits counted once, two face hits), a triangle, a plane floor;
 *   fan    — a faceted cylinder of 40 quads with a triangle-fan bottom: a sphere on
 *            the fan's centre touches 40 coincident faces (more than the pass keeps on
 *            the stack: the lists' scratch);
 *   one    — one material for spheres and box (the pass then skips the particle's
 *            material: a wrong shortcut there differs in 1590 of 409012 evaluations);
 *   disks  — 2D: disks in a box with a plane in a corner;
 *   moving — a box with an oscillating floor and a turning paddle (the walls' point
 *            velocities and spins: the moving variant).
 * The box also runs on 1 and 2 threads (the fused step's ranges) to the same bits.
 * The counts of what was exercised (multi-wall contacts, edge or vertex contacts,
 * dropped duplicates, sliding contacts, scratch) must be positive, so that the
 * comparison cannot pass vacuously. */
#include <stdlib.h>

#include "fused/wall_fast.h"
#include "simtest.h"

static const char *const box_scene =
    "name: wallfast-box\n"
    "materials:\n"
    "  glass: {density: 2500, kn: 1.0e4, restitution: 0.5, friction: 0.5}\n"
    "  steel: {density: 7800, kn: 2.0e4, restitution: 0.7, tangential_restitution: 0.6,"
    " friction: 0.3}\n"
    "particles:\n"
    "  - {material: glass, radius: 0.001, position: [0.00099, 0.00099, 0.00099]}\n"
    "  - {material: steel, radius: 0.001, position: [0.01901, 0.01, 0.00099]}\n"
    "  - {material: glass, radius: 0.0012, position: [0.004, 0.016, 0.00119],"
    " velocity: [0.4, 0, 0]}\n"
    "  - {material: steel, radius: 0.001, position: [0.012, 0.003, 0.00099],"
    " velocity: [0, 0.3, -0.05], angular_velocity: [20, 0, 60]}\n"
    "  - generate: random\n"
    "    region: {min: [0.0005, 0.0005, 0.007], max: [0.0195, 0.0195, 0.03]}\n"
    "    count: 300\n"
    "    radius: {uniform: [0.0006, 0.0011]}\n"
    "    material: {mix: {glass: 0.5, steel: 0.5}}\n"
    "    seed: 5\n"
    "    velocity: [0.05, -0.02, -0.4]\n"
    "walls:\n"
    "  - {box: {min: [0, 0, 0], max: [0.02, 0.02, 0.04]}, open: [top], material: steel}\n"
    "  - {polygon: [[0.006, 0.006, 0.004], [0.013, 0.006, 0.004], [0.012, 0.013, "
    "0.005]], material: glass}\n"
    "integrator: {method: leapfrog, dt: auto, frac: 0.3}\n"
    "contact: {allow_initial_overlap: true}\n" /* some start pressed in */
    "run: {steps: 100000}\n"
    "output: {energy_every: 0}\n";

static const char *const edges_scene =
    "name: wallfast-edges\n"
    "materials:\n"
    "  glass: {density: 2500, kn: 1.0e4, restitution: 0.5, friction: 0.5}\n"
    "  steel: {density: 7800, kn: 2.0e4, restitution: 0.7, friction: 0.3}\n"
    "particles:\n"
    "  - {material: glass, radius: 0.001, position: [0.01, 0.01, 0.0092]}\n"
    "  - {material: steel, radius: 0.001, position: [0.0, 0.01, 0.0092]}\n"
    "  - {material: glass, radius: 0.001, position: [0.04, 0.01, 0.0035]}\n"
    "  - generate: random\n"
    "    region: {min: [-0.003, -0.003, 0.010], max: [0.078, 0.023, 0.016]}\n"
    "    count: 200\n"
    "    radius: {uniform: [0.0007, 0.0012]}\n"
    "    material: {mix: {glass: 0.5, steel: 0.5}}\n"
    "    seed: 9\n"
    "    velocity: [0, 0, -0.5]\n"
    "walls:\n"
    "  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: steel}\n"
    "  - {polygon: [[0, 0, 0.004], [0.02, 0, 0.004], [0.02, 0.01, 0.008], [0, 0.01, "
    "0.008]], material: steel}\n"
    "  - {polygon: [[0, 0.01, 0.008], [0.02, 0.01, 0.008], [0.02, 0.02, 0.004], [0, "
    "0.02, 0.004]], material: steel}\n"
    "  - {polygon: [[0.03, 0, 0.006], [0.05, 0, 0.006], [0.05, 0.01, 0.002], [0.03, "
    "0.01, 0.002]], material: glass}\n"
    "  - {polygon: [[0.03, 0.01, 0.002], [0.05, 0.01, 0.002], [0.05, 0.02, 0.006], "
    "[0.03, 0.02, 0.006]], material: glass}\n"
    "  - {polygon: [[0.06, 0, 0.003], [0.075, 0, 0.003], [0.0675, 0.015, 0.005]],"
    " material: glass}\n"
    "integrator: {method: leapfrog, dt: auto, frac: 0.3}\n"
    "contact: {allow_initial_overlap: true}\n" /* some start pressed in */
    "run: {steps: 100000}\n"
    "output: {energy_every: 0}\n";

static const char *const fan_scene =
    "name: wallfast-fan\n"
    "materials:\n"
    "  glass: {density: 2500, kn: 1.0e4, restitution: 0.5, friction: 0.5}\n"
    "  steel: {density: 7800, kn: 2.0e4, restitution: 0.7, friction: 0.3}\n"
    "particles:\n"
    "  - {material: glass, radius: 0.001, position: [0, 0, 0.0012], velocity: [0, 0, "
    "-0.2]}\n"
    "  - generate: random\n"
    "    region: {min: [-0.0034, -0.0034, 0.003], max: [0.0034, 0.0034, 0.018]}\n"
    "    count: 60\n"
    "    radius: {uniform: [0.0007, 0.001]}\n"
    "    material: {mix: {glass: 0.5, steel: 0.5}}\n"
    "    seed: 3\n"
    "    velocity: [0.1, 0.05, -0.3]\n"
    "walls:\n"
    "  - {cylinder: {base: [0, 0, 0], radius: 0.006, height: 0.02, segments: 40,"
    " caps: [bottom]}, material: steel}\n"
    "integrator: {method: leapfrog, dt: auto, frac: 0.3}\n"
    "contact: {allow_initial_overlap: true}\n" /* some start pressed in */
    "run: {steps: 100000}\n"
    "output: {energy_every: 0}\n";

/* One material for particles and walls: the pass takes the pair parameters without
 * the particle's material. */
static const char *const one_scene =
    "name: wallfast-one\n"
    "materials:\n"
    "  grain: {density: 2500, kn: 1.0e4, restitution: 0.5, friction: 0.5}\n"
    "particles:\n"
    "  - {material: grain, radius: 0.001, position: [0.00099, 0.00099, 0.00099]}\n"
    "  - {material: grain, radius: 0.001, position: [0.012, 0.003, 0.00099],"
    " velocity: [0, 0.3, -0.05], angular_velocity: [20, 0, 60]}\n"
    "  - generate: random\n"
    "    region: {min: [0.0005, 0.0005, 0.007], max: [0.0195, 0.0195, 0.03]}\n"
    "    count: 200\n"
    "    radius: {uniform: [0.0006, 0.0011]}\n"
    "    material: grain\n"
    "    seed: 7\n"
    "    velocity: [0.05, -0.02, -0.4]\n"
    "walls:\n"
    "  - {box: {min: [0, 0, 0], max: [0.02, 0.02, 0.04]}, open: [top], material: grain}\n"
    "integrator: {method: leapfrog, dt: auto, frac: 0.3}\n"
    "contact: {allow_initial_overlap: true}\n" /* some start pressed in */
    "run: {steps: 100000}\n"
    "output: {energy_every: 0}\n";

static const char *const disks_scene =
    "name: wallfast-disks\n"
    "dimension: 2\n"
    "disk_thickness: 0.002\n"
    "materials:\n"
    "  glass: {density: 2500, kn: 1.0e4, restitution: 0.5, friction: 0.5}\n"
    "  steel: {density: 7800, kn: 2.0e4, restitution: 0.7, friction: 0.3}\n"
    "particles:\n"
    "  - {material: glass, radius: 0.001, position: [0.00099, 0, 0.00099]}\n"
    "  - {material: steel, radius: 0.001, position: [0.01, 0, 0.00099], velocity: [0.3,"
    " 0, 0]}\n"
    "  - generate: random\n"
    "    region: {min: [0.0005, 0, 0.003], max: [0.0295, 0, 0.025]}\n"
    "    count: 80\n"
    "    radius: {uniform: [0.0007, 0.0012]}\n"
    "    material: {mix: {glass: 0.5, steel: 0.5}}\n"
    "    seed: 4\n"
    "    velocity: [-0.1, 0, -0.4]\n"
    "walls:\n"
    "  - {box: {min: [0, -0.01, 0], max: [0.03, 0.01, 0.04]}, open: [top], material: "
    "steel}\n"
    "  - {plane: {point: [0.03, 0, 0], normal: [-0.5, 0, 1]}, material: glass}\n"
    "integrator: {method: leapfrog, dt: auto, frac: 0.3}\n"
    "contact: {allow_initial_overlap: true}\n" /* some start pressed in */
    "run: {steps: 100000}\n"
    "output: {energy_every: 0}\n";

/* Moving walls: spheres fall into a box whose floor oscillates and onto a square
 * paddle turning about the vertical through its centre (its tip about 0.3 m/s), so
 * that the walls' point velocities and spins enter the contacts. */
static const char *const moving_scene =
    "name: wallfast-moving\n"
    "materials:\n"
    "  glass: {density: 2500, kn: 1.0e4, restitution: 0.5, friction: 0.5}\n"
    "  steel: {density: 7800, kn: 2.0e4, restitution: 0.7, tangential_restitution: 0.6,"
    " friction: 0.3}\n"
    "particles:\n"
    "  - generate: random\n"
    "    region: {min: [0.001, 0.001, 0.0045], max: [0.019, 0.019, 0.016]}\n"
    "    count: 150\n"
    "    radius: {uniform: [0.0007, 0.0011]}\n"
    "    material: {mix: {glass: 0.5, steel: 0.5}}\n"
    "    seed: 9\n"
    "    velocity: [0.05, 0.02, -0.8]\n"
    "walls:\n"
    "  - {box: {min: [0, 0, 0], max: [0.02, 0.02, 0.05]}, open: [top, bottom], material:"
    " steel}\n"
    "  - {polygon: [[0, 0, 0.0005], [0.02, 0, 0.0005], [0.02, 0.02, 0.0005],"
    " [0, 0.02, 0.0005]], material: glass,\n"
    "     motion: {oscillate: {direction: [0, 0, 1], frequency: 60, amplitude: "
    "0.0004}}}\n"
    "  - {polygon: [[0.004, 0.004, 0.003], [0.016, 0.004, 0.0035], [0.016, 0.016, 0.003],"
    " [0.004, 0.016, 0.0025]], material: steel,\n"
    "     motion: {rotate: {axis: [0, 0, 1], center: [0.01, 0.01, 0.003], omega: 40}}}\n"
    "integrator: {method: leapfrog, dt: auto, frac: 0.3}\n"
    "run: {steps: 100000}\n"
    "output: {energy_every: 0}\n";

typedef struct stats {
  long compared;   /* particle evaluations compared */
  long contacts;   /* wall contacts carrying force */
  long multi;      /* particles touching two or more wall elements */
  long feature;    /* contacts on an edge or a vertex */
  long dropped;    /* particles with an overlapping hit not counted (duplicates) */
  long sliding;    /* single-contact particles on the Coulomb cap */
  long scratch;    /* touching particles with more than 8 candidates */
  int nmat;        /* materials in the scene (one: the pass skips the particle's) */
  long mismatches; /* evaluations that differ */
} stats;

typedef struct result {
  int rc;
  size_t nt;
  double f[3], t[3];
  esf_contact_hist *h;
  uint8_t *touch;
} result;

/* One pass on candidates [k0, k1) from history (h0, t0), into r; the history is left
 * as it was. */
static void eval_pass(esf_sim *s, int fast, size_t k0, size_t k1, const double *f0,
                      const double *t0, const esf_contact_hist *h0, const uint8_t *tc0,
                      result *r) {
  esf_candidates *c = &s->nb.pw;
  const size_t m = k1 - k0;
  memcpy(r->f, f0, sizeof r->f);
  memcpy(r->t, t0, sizeof r->t);
  r->nt = 5;
  if (fast) /* the pass the step takes (the moving walls' variant with moving walls) */
    r->rc = esf_wall_pass_select(s)(s, k0, k1, s->dt, &r->nt, r->f, r->t, NULL);
  else
    r->rc =
        esf_forces_wall_particle(s, k0, k1, s->p.x, s->p.v, s->p.w, s->dt,
                                 ESF_FORCES_COMMIT, NULL, NULL, &r->nt, r->f, r->t, NULL);
  memcpy(r->h, c->h + k0, m * sizeof *r->h);
  memcpy(r->touch, c->touch + k0, m);
  memcpy(c->h + k0, h0, m * sizeof *h0);
  memcpy(c->touch + k0, tc0, m);
}

static int same(const result *a, const result *b, size_t m) {
  return (a->rc != 0) == (b->rc != 0) && a->nt == b->nt &&
         !memcmp(a->f, b->f, sizeof a->f) && !memcmp(a->t, b->t, sizeof a->t) &&
         !memcmp(a->h, b->h, m * sizeof *a->h) && !memcmp(a->touch, b->touch, m);
}

/* Compares the passes for every particle with wall candidates at the current state. */
static void compare_all(esf_sim *s, stats *st) {
  esf_error e;
  CHECK_OK(esf_sim_forces_sync(s, &e), e); /* p.f, p.t: released during fused steps */
  esf_candidates *c = &s->nb.pw;
  size_t cap = c->n ? c->n : 1;
  esf_contact_hist *h0 = malloc(cap * sizeof *h0);
  uint8_t *tc0 = malloc(cap);
  result R[4];
  for (int q = 0; q < 4; q++) {
    R[q].h = malloc(cap * sizeof *R[q].h);
    R[q].touch = malloc(cap);
  }
  const double zero[3] = {0, 0, 0};
  for (size_t k0 = 0, k1; k0 < c->n; k0 = k1) {
    const uint32_t a = c->a[k0];
    for (k1 = k0; k1 < c->n && c->a[k1] == a; k1++) continue;
    const size_t m = k1 - k0;
    memcpy(h0, c->h + k0, m * sizeof *h0);
    memcpy(tc0, c->touch + k0, m);
    const double *fa = s->p.f + 3 * a, *ta = s->p.t + 3 * a;
    eval_pass(s, 0, k0, k1, zero, zero, h0, tc0, &R[0]);
    eval_pass(s, 1, k0, k1, zero, zero, h0, tc0, &R[1]);
    eval_pass(s, 0, k0, k1, fa, ta, h0, tc0, &R[2]);
    eval_pass(s, 1, k0, k1, fa, ta, h0, tc0, &R[3]);
    st->compared += 2;
    if (!same(&R[0], &R[1], m)) st->mismatches++;
    if (!same(&R[2], &R[3], m)) st->mismatches++;
    /* what was exercised, from the general pass */
    const size_t nt = R[0].nt - 5;
    st->contacts += (long)nt;
    st->multi += nt >= 2;
    /* more than 8 candidates (FAST_MAX, private to src/wall_fast.c) use the scratch */
    st->scratch += nt >= 1 && m > 8;
    const double *x = s->p.x + 3 * a, r = s->p.radius[a];
    size_t over = 0;
    for (size_t j = 0; j < m; j++) {
      esf_wall_hit hit;
      esf_wall_nearest(&s->walls.e[c->b[k0 + j]], x, &hit);
      over += r - hit.dist > 0;
      if (R[0].touch[j] && hit.feature != ESF_FEATURE_FACE) st->feature++;
    }
    st->dropped += over > nt;
    if (nt == 1) { /* the contact force alone: sliding when |ft| = mu fn */
      size_t j = 0;
      while (!R[0].touch[j]) j++;
      const esf_wall_elem *el = &s->walls.e[c->b[k0 + j]];
      const esf_materials *mt = &s->mats;
      const double mu = mt->pair[s->p.material[a] * mt->n + el->material].mu;
      const double *n = R[0].h[j].n;
      const double fn = -v3_dot(R[0].f, n);
      double ft[3];
      v3_copy(ft, R[0].f);
      v3_axpy(ft, fn, n);
      if (fn > 0 && v3_norm(ft) >= mu * fn * (1 - 1e-9)) st->sliding++;
    }
  }
  for (int q = 0; q < 4; q++) {
    free(R[q].h);
    free(R[q].touch);
  }
  free(h0);
  free(tc0);
}

static void run_scene(const char *name, const char *yaml, const char *tframe, int steps,
                      stats *st) {
  char s_tf[64];
  snprintf(s_tf, sizeof s_tf, "contact.tangential_frame=%s", tframe);
  const char *sets[] = {s_tf, "integrator.fused=true"};
  simtest T;
  int rc = simtest_open(&T, yaml, sets, 2);
  CHECK(rc == 0, "%s: open", name);
  if (rc) return;
  CHECK(esf_wall_pass_select(&T.s) ==
            (T.s.walls.moving ? esf_wall_fast_particle_moving : esf_wall_fast_particle),
        "%s: fast pass chosen", name);
  memset(st, 0, sizeof *st);
  st->nmat = T.s.mats.n;
  for (int k = 0; k < steps && !rc; k++) {
    compare_all(&T.s, st);
    rc = simtest_step(&T);
  }
  CHECK(rc == 0, "%s (%s): run", name, tframe);
  printf("%s (%s): %ld steps, t = %.4g s, dt = %.3g s, %zu particles\n", name, tframe,
         T.s.step, T.s.t, T.s.dt, T.s.p.n);
  printf("%s (%s): %ld compared, %ld mismatches; contacts %ld, multi %ld, edge/vertex "
         "%ld, dropped %ld, sliding %ld, scratch %ld\n",
         name, tframe, st->compared, st->mismatches, st->contacts, st->multi, st->feature,
         st->dropped, st->sliding, st->scratch);
  CHECK(st->mismatches == 0, "%s (%s): %ld of %ld evaluations differ", name, tframe,
        st->mismatches, st->compared);
  CHECK(st->contacts > 0, "%s: no wall contacts", name);
  simtest_close(&T);
}

/* The fused step with the fast pass on 1 and 2 threads: the same state bit for bit. */
static void threads_same(void) {
  double *y[2] = {NULL, NULL};
  esf_contact_hist *h[2] = {NULL, NULL};
  size_t n[2] = {0, 0}, m[2] = {0, 0};
  for (int q = 0; q < 2; q++) {
    const char *sets[] = {"integrator.fused=true"};
    simtest T;
    int rc = simtest_open(&T, box_scene, sets, 1);
    CHECK(rc == 0, "threads: open");
    if (rc) return;
    T.s.cfg.threads = q + 1;
    T.s.cfg.range_work = 1; /* one range per thread */
    for (int k = 0; k < 4000 && !rc; k++) rc = simtest_step(&T);
    CHECK(rc == 0, "threads %d: run", q + 1);
    n[q] = T.s.p.n;
    m[q] = T.s.nb.pw.n;
    y[q] = malloc(9 * n[q] * sizeof(double));
    h[q] = malloc((m[q] ? m[q] : 1) * sizeof *h[q]);
    memcpy(y[q], T.s.p.y, 9 * n[q] * sizeof(double));
    memcpy(h[q], T.s.nb.pw.h, m[q] * sizeof *h[q]);
    simtest_close(&T);
  }
  CHECK(n[0] == n[1], "1 and 2 threads: %zu and %zu particles", n[0], n[1]);
  CHECK(m[0] == m[1], "1 and 2 threads: %zu and %zu wall pairs", m[0], m[1]);
  CHECK(n[0] == n[1] && m[0] == m[1] && !memcmp(y[0], y[1], 9 * n[0] * sizeof(double)) &&
            !memcmp(h[0], h[1], m[0] * sizeof *h[0]),
        "1 and 2 threads differ");
  for (int q = 0; q < 2; q++) {
    free(y[q]);
    free(h[q]);
  }
}

/* A sphere too deep in a wall: the fused step (fast pass) and the general path stop
 * with the same message. The scene reader refuses such a start (bad input, exit 2), so
 * the sphere is put there after it, before the first step. */
static void overlap_failure(const double pos[3], int fused_general_same) {
  char yaml[1024];
  snprintf(yaml, sizeof yaml,
           "name: wallfast-fail\n"
           "materials: {glass: {density: 2500, kn: 1.0e4, restitution: 0.5, friction: "
           "0.5}}\n"
           "particles:\n"
           "  - {material: glass, radius: 0.001, position: [0.005, 0.005, 0.01]}\n"
           "  - {material: glass, radius: 0.001, position: [0.01, 0.01, 0.0012]}\n"
           "walls:\n"
           "  - {box: {min: [0, 0, 0], max: [0.02, 0.02, 0.04]}, open: [top], "
           "material: glass}\n"
           "integrator: {method: leapfrog, dt: 1.0e-6}\n"
           "run: {steps: 10}\n"
           "output: {energy_every: 0}\n");
  char msg[2][sizeof(esf_error){0}.msg];
  for (int fused = 0; fused < 2; fused++) {
    const char *sets[] = {fused ? "integrator.fused=true" : "integrator.fused=false"};
    simtest T;
    int rc = simtest_open(&T, yaml, sets, 1);
    CHECK(rc == 0, "failure scene: open");
    if (rc) return;
    memcpy(T.s.p.x, pos, 3 * sizeof(double));
    if (fused)
      CHECK(esf_wall_pass_select(&T.s) == esf_wall_fast_particle, "fast pass chosen");
    rc = T.it->step(&T.s, T.ist, INFINITY, &T.err);
    CHECK(rc == ESF_ENUMERIC, "fused %d: status %d, expected ESF_ENUMERIC", fused, rc);
    snprintf(msg[fused], sizeof msg[fused], "%s", T.err.msg);
    simtest_close(&T);
  }
  printf("overlap failure: %s\n", msg[1]);
  CHECK(strstr(msg[1], "overlaps wall element") != NULL, "message: %s", msg[1]);
  if (fused_general_same)
    CHECK(!strcmp(msg[0], msg[1]), "messages differ:\n  general: %s\n  fused:   %s",
          msg[0], msg[1]);
}

int main(void) {
  stats st;
  run_scene("box", box_scene, "rotate", 8000, &st);
  CHECK(st.multi > 0 && st.sliding > 0, "box: multi %ld, sliding %ld", st.multi,
        st.sliding);
  run_scene("box", box_scene, "project", 5000, &st);
  CHECK(st.multi > 0 && st.sliding > 0, "box/project: multi %ld, sliding %ld", st.multi,
        st.sliding);
  run_scene("edges", edges_scene, "rotate", 5000, &st);
  CHECK(st.feature > 0 && st.dropped > 0 && st.multi > 0,
        "edges: edge/vertex %ld, dropped %ld, multi %ld", st.feature, st.dropped,
        st.multi);
  run_scene("fan", fan_scene, "rotate", 3000, &st);
  CHECK(st.scratch > 0 && st.dropped > 0, "fan: scratch %ld, dropped %ld", st.scratch,
        st.dropped);
  run_scene("one", one_scene, "rotate", 5000, &st);
  CHECK(st.nmat == 1 && st.multi > 0 && st.sliding > 0,
        "one: %d materials, multi %ld, sliding %ld", st.nmat, st.multi, st.sliding);
  run_scene("disks", disks_scene, "rotate", 5000, &st);
  CHECK(st.multi > 0 && st.sliding > 0, "disks: multi %ld, sliding %ld", st.multi,
        st.sliding);

  threads_same();

  /* the overlap limit (50% of the radius): a face, and a corner with three hits */
  overlap_failure((const double[3]){0.01, 0.005, 0.0004}, 1);
  overlap_failure((const double[3]){0.0004, 0.0008, 0.0009}, 1);

  /* moving walls: the fast pass's moving variant against the general one */
  run_scene("moving", moving_scene, "rotate", 8000, &st);
  CHECK(st.multi > 0 && st.sliding > 0 && st.feature > 0,
        "moving: multi %ld, sliding %ld, edge/vertex %ld", st.multi, st.sliding,
        st.feature);
  {
    const char *sets[] = {"walls.0.motion={translate: {velocity: [0, 0, 0.01]}}"};
    simtest T;
    int rc = simtest_open(&T, box_scene, sets, 1);
    CHECK(rc == 0, "moving box: open");
    if (!rc)
      CHECK(esf_wall_pass_select(&T.s) == esf_wall_fast_particle_moving,
            "moving walls: the fast pass's moving variant");
    simtest_close(&T);
  }
  return check_finish("wall_fast");
}
