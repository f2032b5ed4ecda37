/* test_contact_net.c — the contact network written with output.contacts
 * (contact_net.h): two overlapping spheres approaching each other give one pair whose
 * normal force is the linear law's kn un + cn (approach speed), cn = 2 gamma sqrt(m* kn)
 * with gamma from the restitution, at the state's positions and velocities (to 1e-12);
 * a separated pair, a sphere far away and a sphere pressed on a wall add nothing (wall
 * contacts are not in the network); building the network leaves the contact lists and
 * histories untouched; a pair moving apart fast enough for the dashpot to cancel the
 * spring reports fn = 0 (the no-tension cut). */
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
  CHECK_OK(esf_contact_net_build(s, &net, &err), err);
  CHECK(net.n == 1, "%zu touching pairs, expected 1", net.n);
  CHECK(s->nb.pw.n > 0 && esf_neighbor_touching(&s->nb) == 2,
        "the sphere on the wall must touch it (%zu touching)",
        esf_neighbor_touching(&s->nb));
  if (net.n == 1) {
    CHECK(net.pair[0] == 0 && net.pair[1] == 1, "pair (%lld, %lld), expected (0, 1)",
          (long long)net.pair[0], (long long)net.pair[1]);
    double want = expected_fn(s, 0, 1);
    CHECK(want > 0, "the test pair must be compressed (fn %.6g)", want);
    CHECK_NEAR(net.fn[0], want, 1e-12 * want, "normal force (N)");
    printf("pair (0, 1): fn %.12g N, closed form %.12g N\n", net.fn[0], want);
  }
  CHECK(c->n == nc && memcmp(touch, c->touch, nc) == 0 &&
            memcmp(h, c->h, nc * sizeof *h) == 0,
        "building the network must not change the contact lists");

  /* separating fast: the dashpot cancels the spring, fn = 0 (still a touching pair) */
  esf_particles *p = &s->p;
  v3_set(p->v, -20.0, 0, 0);
  CHECK_OK(esf_contact_net_build(s, &net, &err), err);
  CHECK(net.n == 1 && net.fn[0] == 0.0 && expected_fn(s, 0, 1) == 0.0,
        "separating pair: %zu pairs, fn %.6g", net.n, net.n ? net.fn[0] : -1.0);

  /* moved apart: no pair (storage reused) */
  p->x[0] -= 0.01;
  CHECK_OK(esf_contact_net_build(s, &net, &err), err);
  CHECK(net.n == 0, "separated: %zu pairs", net.n);
  esf_contact_net_release(&net);
  CHECK(net.pair == NULL && net.n == 0, "release clears the network");
  free(touch);
  free(h);
  simtest_close(&T);
  return check_finish("test_contact_net");
}
