/* test_contact_net.c — the contact network written with output.contacts
 * (contact_net.h): two overlapping spheres approaching each other give one pair whose
 * normal force is the linear law's kn un + cn (approach speed), cn = 2 gamma sqrt(m* kn)
 * with gamma from the restitution, at the state's positions and velocities (to 1e-12);
 * a separated pair and a sphere far away add nothing; the sphere pressed on the wall is
 * one wall contact (wall 0) whose normal force is kn un + cn vn with the particle's
 * mass, at the contact point on the plane's side; the pair's tangential force lies in
 * the contact plane within the Coulomb cap; the coordination numbers are 1 1 0 1;
 * building the network leaves the contact lists and histories untouched; a pair moving
 * apart fast enough for the dashpot to cancel the spring reports fn = 0 (the no-tension
 * cut). */
#include <stdlib.h>

#include "output/contact_net.h"
#include "simtest.h"

static const char *scene =
    "name: net\n"
    "gravity: [0, 0, 0]\n"
    "materials:\n"
    "  g: {density: 2500, kn: 1.0e4, restitution: 0.5, friction: 0.3}\n"
    "particles:\n"
    "  - {material: g, radius: 0.002, position: [0, 0, 0.01], velocity: [0.1, 0, 0]}\n"
    "  - {material: g, radius: 0.003, position: [0.0049, 0.0003, 0.0101], velocity: "
    "[-0.05, 0.02, 0], angular_velocity: [0, 0, 30]}\n"
    "  - {material: g, radius: 0.002, position: [0.05, 0, 0.01]}\n"
    "  - {material: g, radius: 0.002, position: [0.08, 0, 0.0019]}\n"
    "walls:\n"
    "  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: g}\n"
    "contact: {allow_initial_overlap: true}\n"
    "integrator: {method: leapfrog, dt: auto, frac: 0.05}\n"
    "run: {steps: 10}\n"
    "output: {energy_every: 0}\n";

/* The linear law's normal force between particles a and b of s at their state. */
static double expected_fn(const esf_sim *s, size_t a, size_t b) {
  const esf_particles *p = &s->p;
  double d[3], dv[3];
  v3_sub(d, p->x + 3 * b, p->x + 3 * a);
  v3_sub(dv, p->v + 3 * b, p->v + 3 * a);
  double dist = v3_norm(d), un = p->radius[a] + p->radius[b] - dist;
  double vn = v3_dot(dv, d) / dist; /* rotation adds nothing along the normal */
  double ms = p->mass[a] * p->mass[b] / (p->mass[a] + p->mass[b]);
  double eta = 0.5, l = log(eta), gamma = -l / sqrt(ESF_PI * ESF_PI + l * l);
  double cn = 2 * gamma * sqrt(ms * 1.0e4);
  double fn = 1.0e4 * un - cn * vn;
  return fn > 0 ? fn : 0.0;
}

/* The ODE methods commit their forces at the state a step ends on: the network's
 * contact forces plus gravity give p.f of every particle (1e-12). (Verlet commits at
 * x_{n+1} with the half-kicked velocities; the network uses the state's v_{n+1}, so
 * its dashpot forces differ from p.f's.) */
static void schemes_commit(const char *method) {
  const char *sets[2] = {method, "gravity=[0,0,-9.81]"};
  simtest T;
  if (simtest_open(&T, scene, sets, 2)) {
    CHECK(0, "%s: scene failed: %s", method, T.err.msg);
    return;
  }
  for (int k = 0; k < 5; k++) simtest_step(&T);
  esf_sim *s = &T.s;
  esf_contact_net net = {0};
  esf_error err = {0};
  CHECK_OK(esf_sim_forces_sync(s, &err), err);
  CHECK_OK(esf_contact_net_build(s, 1, &net, &err), err);
  const esf_particles *p = &s->p;
  double *f = calloc(3 * p->n, sizeof *f), worst = 0;
  for (size_t i = 0; i < p->n; i++) v3_scale(f + 3 * i, p->mass[i], s->cfg.gravity);
  for (size_t k = 0; k < net.pp.n; k++) {
    v3_add(f + 3 * net.pp.pair[2 * k], f + 3 * net.pp.pair[2 * k], net.pp.f + 3 * k);
    v3_sub(f + 3 * net.pp.pair[2 * k + 1], f + 3 * net.pp.pair[2 * k + 1],
           net.pp.f + 3 * k);
  }
  for (size_t k = 0; k < net.pw.n; k++)
    v3_add(f + 3 * net.pw.pair[2 * k], f + 3 * net.pw.pair[2 * k], net.pw.f + 3 * k);
  for (size_t q = 0; q < 3 * p->n; q++) worst = fmax(worst, fabs(f[q] - p->f[q]));
  CHECK(net.pp.n == 1 && net.pw.n == 1 && worst <= 1e-12 * v3_norm(p->f + 3),
        "%s: %zu pairs, %zu wall contacts; contact forces + gravity vs p.f: %.3g N",
        method, net.pp.n, net.pw.n, worst);
  printf("%s: the network's forces give p.f to %.3g N\n", method, worst);
  free(f);
  esf_contact_net_release(&net);
  simtest_close(&T);
}

int main(void) {
  simtest T;
  if (simtest_open(&T, scene, NULL, 0)) {
    CHECK(0, "scene failed: %s", T.err.msg);
    return check_finish("test_contact_net");
  }
  for (int k = 0; k < 3; k++) simtest_step(&T);
  esf_sim *s = &T.s;
  esf_candidates *c = &s->nb.pp;
  size_t nc = c->n;
  uint8_t *touch = malloc(nc ? nc : 1);
  esf_contact_hist *h = malloc((nc ? nc : 1) * sizeof *h);
  memcpy(touch, c->touch, nc);
  memcpy(h, c->h, nc * sizeof *h);
  esf_contact_net net = {0};
  esf_error err = {0};
  CHECK_OK(esf_contact_net_build(s, 1, &net, &err), err);
  const esf_contact_set *pp = &net.pp, *pw = &net.pw;
  CHECK(pp->n == 1, "%zu touching pairs, expected 1", pp->n);
  CHECK(s->nb.pw.n > 0 && esf_neighbor_touching(&s->nb) == 2,
        "the sphere on the wall must touch it (%zu touching)",
        esf_neighbor_touching(&s->nb));
  if (pp->n == 1) {
    CHECK(pp->pair[0] == 0 && pp->pair[1] == 1, "pair (%lld, %lld), expected (0, 1)",
          (long long)pp->pair[0], (long long)pp->pair[1]);
    double want = expected_fn(s, 0, 1);
    CHECK(want > 0, "the test pair must be compressed (fn %.6g)", want);
    CHECK_NEAR(pp->fn[0], want, 1e-12 * want, "normal force (N)");
    printf("pair (0, 1): fn %.12g N, closed form %.12g N\n", pp->fn[0], want);
    double d[3];
    v3_sub(d, s->p.x + 3, s->p.x);
    const double ftn = v3_norm(pp->ft);
    CHECK(ftn > 0 && fabs(v3_dot(pp->ft, d)) <= 1e-12 * ftn * v3_norm(d) &&
              ftn <= 0.3 * pp->fn[0] * (1 + 1e-12),
          "tangential force |ft| %.6g N in the contact plane, <= mu fn", ftn);
  }
  CHECK(pw->n == 1 && pw->pair[0] == 3 && pw->pair[1] == 0,
        "%zu wall contacts, expected particle 3 on wall 0", pw->n);
  if (pw->n == 1) {
    const esf_particles *q = &s->p;
    const double un = q->radius[3] - q->x[3 * 3 + 2], eta = 0.5, l = log(eta);
    const double gamma = -l / sqrt(ESF_PI * ESF_PI + l * l);
    const double want =
        1.0e4 * un - 2 * gamma * sqrt(q->mass[3] * 1.0e4) * q->v[3 * 3 + 2];
    CHECK_NEAR(pw->fn[0], want, 1e-12 * want, "wall normal force (N)");
    CHECK_NEAR(pw->pc[2], q->x[3 * 3 + 2] - (q->radius[3] - 0.5 * un), 1e-15,
               "wall contact point z (m)");
  }
  int32_t z[4];
  esf_contact_net_coordination(&net, 4, z);
  CHECK(z[0] == 1 && z[1] == 1 && z[2] == 0 && z[3] == 1, "coordination %d %d %d %d",
        z[0], z[1], z[2], z[3]);
  CHECK(c->n == nc && memcmp(touch, c->touch, nc) == 0 &&
            memcmp(h, c->h, nc * sizeof *h) == 0,
        "building the network must not change the contact lists");

  /* separating fast: the dashpot cancels the spring, fn = 0 (still a touching pair) */
  esf_particles *p = &s->p;
  v3_set(p->v, -20.0, 0, 0);
  CHECK_OK(esf_contact_net_build(s, 1, &net, &err), err);
  CHECK(pp->n == 1 && pp->fn[0] == 0.0 && expected_fn(s, 0, 1) == 0.0,
        "separating pair: %zu pairs, fn %.6g", pp->n, pp->n ? pp->fn[0] : -1.0);

  /* moved apart: no pair (storage reused) */
  p->x[0] -= 0.01;
  CHECK_OK(esf_contact_net_build(s, 0, &net, &err), err);
  CHECK(pp->n == 0 && pw->n == 0, "separated, walls not asked: %zu pairs, %zu wall",
        pp->n, pw->n);
  esf_contact_net_release(&net);
  CHECK(pp->pair == NULL && pp->n == 0, "release clears the network");
  free(touch);
  free(h);
  simtest_close(&T);
  schemes_commit("integrator.method=rk4");
  return check_finish("test_contact_net");
}
