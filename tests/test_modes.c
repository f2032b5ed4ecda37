/* test_modes.c — the assembled contact system's highest frequency (modes.h) against
 * closed forms:
 * 1. a sphere pressed on a wall: omega^2 = max(kn/m, kt (1/m + l^2/I)), l the lever arm
 *    to the contact point (the tangential spring drives translation and rotation);
 * 2. the same for a 2D disk (I = m r^2 / 2: kt (1/m + 2 l^2 / r^2 / m));
 * 3. a free unequal pair: kn/m* along the line, and kt (1/mA + 1/mB + lA^2/IA + lB^2/IB)
 *    across it;
 * 4. a free chain of N equal spheres touching in a line with a negligible tangential
 *    stiffness: the free-free chain's top mode 2 sqrt(kn/m) sin((N - 1) pi / (2N));
 * 5. a Hertz-Mindlin sphere on a wall: the same with the tangent stiffnesses at its
 *    overlap (hertz_on_wall);
 * and the damped bound (2/omega)(sqrt(1 + xi^2) - xi) with xi the contacts' ratio, and
 * the top mode's own damping ratio (sphere on a wall: the contact's times
 * sqrt(1 + m l^2/I); the chain: sqrt(2) gamma sin((N - 1) pi / (2N))).
 * The live stability check (model/stability.h) on the same systems: its Lanczos
 * eigenvalue of dt^2 A + 2 dt B against the dense one (1e-6), and its limit against the
 * closed form min over modes (2/w)(sqrt(1 + xi^2) - xi) (sphere on a wall: the normal
 * and the tangential mode; the chain: its damped top mode), and with local damping
 * alpha_c (2/w)(sqrt(xi^2 + 1/(1 + alpha_c)) - xi), within 1e-6.
 * Relative tolerance 1e-9 (a dense symmetric eigensolve of at most 48 dofs). */
#include "app/modes.h"
#include "simtest.h"

static double modes_of(const char *yaml, simtest *T, esf_modes *m) {
  if (simtest_open(T, yaml, NULL, 0)) {
    CHECK(0, "scene opens");
    return -1;
  }
  esf_error err;
  esf_error_clear(&err);
  int rc = esf_modes_compute(&T->s, m, &err);
  CHECK(rc == 0, "modes computed: %s", err.msg);
  return rc;
}

static double fxi(double xi) { return sqrt(1 + xi * xi) - xi; }

static void check_live(const char *what, const esf_modes *m, double dt_closed) {
  CHECK(fabs(m->lambda_live / m->lambda - 1) < 1e-6,
        "%s: Lanczos lambda %.12g, dense %.12g", what, m->lambda_live, m->lambda);
  CHECK(fabs(m->dt_live / dt_closed - 1) < 1e-6,
        "%s: live limit %.10g s, closed form %.10g s", what, m->dt_live, dt_closed);
  printf("%-34s live limit %.10g s (closed form %.10g s), lambda %.6g (dense %.6g)\n",
         what, m->dt_live, dt_closed, m->lambda_live, m->lambda);
}

static void check_close(const char *what, double got, double want) {
  CHECK(fabs(got / want - 1) < 1e-9, "%s: %.12g against %.12g", what, got, want);
  printf("%-34s omega_max %.10g rad/s (closed form %.10g)\n", what, got, want);
}

static void on_wall(int dim) {
  char yaml[1024];
  snprintf(yaml, sizeof yaml,
           "name: w\ndimension: %d\ngravity: [0, 0, 0]\n"
           "materials: {g: {density: 2500, kn: 1.0e5, kt: %s, restitution: 0.5, "
           "friction: 0.3}}\n"
           "particles:\n  - {material: g, radius: 0.005, position: [0, 0, 0.00499]}\n"
           "walls:\n  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: g}\n"
           "contact: {allow_initial_overlap: true}\nrun: {steps: 1}\n",
           dim, "0.5e5");
  simtest T;
  esf_modes m;
  if (modes_of(yaml, &T, &m) == 0) {
    double mass = T.s.p.mass[0], I = T.s.p.inertia[0], l = 0.005 - 0.5e-5; /* r - u/2 */
    double w2 = fmax(1.0e5 / mass, 0.5e5 * (1 / mass + l * l / I));
    check_close(dim == 3 ? "sphere on a wall" : "disk on a wall", m.omega_max, sqrt(w2));
    CHECK(m.contacts == 1 && m.dofs == (dim == 3 ? 6u : 3u), "one contact, %zu dofs",
          m.dofs);
    double xi = esf_restitution_gamma(0.5);
    CHECK(fabs(m.xi_max / xi - 1) < 1e-12, "damping ratio %.6g (%.6g)", m.xi_max, xi);
    double dd = 2 / sqrt(w2) * (sqrt(1 + xi * xi) - xi);
    CHECK(fabs(m.dt_damped / dd - 1) < 1e-9, "damped bound %.6g s (%.6g s)", m.dt_damped,
          dd);
    /* the top mode is the tangential one: its dashpot acts through the same lever, so
       its ratio is the contact's times sqrt(1 + m l^2 / I) */
    double xm = xi * sqrt(1 + mass * l * l / I);
    CHECK(fabs(m.xi_mode / xm - 1) < 1e-9, "top mode's damping ratio %.9g (%.9g)",
          m.xi_mode, xm);
    printf("%-34s xi contact %.6f, xi of the top mode %.6f (closed form %.6f)\n",
           dim == 3 ? "sphere on a wall" : "disk on a wall", m.xi_max, m.xi_mode, xm);
    /* the normal mode (kn/m, xi) and the tangential one (w2, xm) are independent */
    double wn = sqrt(1.0e5 / mass), wt = sqrt(0.5e5 * (1 / mass + l * l / I));
    check_live(dim == 3 ? "sphere on a wall" : "disk on a wall", &m,
               fmin(2 / wn * fxi(xi), 2 / wt * fxi(xm)));
  }
  simtest_close(&T);
}

/* The sphere on a wall with Cundall's local damping (alpha_c 0.7): its force can add to
 * the unbalanced one in the period-two mode, so each mode's limit is the root of
 * (1 + alpha_c)(dt^2 w^2 + 4 xi w dt) = 4, (2/w)(sqrt(xi^2 + 1/(1 + alpha_c)) - xi). */
static void on_wall_local(void) {
  const char *yaml = "name: w\ngravity: [0, 0, 0]\n"
                     "materials: {g: {density: 2500, kn: 1.0e5, kt: 0.5e5, restitution: "
                     "0.5, friction: 0.3}}\n"
                     "particles:\n  - {material: g, radius: 0.005, position: [0, 0, "
                     "0.00499]}\n"
                     "walls:\n  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, "
                     "material: g}\n"
                     "damping: {local: {coefficient: 0.7}}\n"
                     "contact: {allow_initial_overlap: true}\nrun: {steps: 1}\n";
  simtest T;
  esf_modes m;
  if (modes_of(yaml, &T, &m) == 0) {
    double mass = T.s.p.mass[0], I = T.s.p.inertia[0], l = 0.005 - 0.5e-5, f = 1.7;
    double xi = esf_restitution_gamma(0.5), xm = xi * sqrt(1 + mass * l * l / I);
    double wn = sqrt(1.0e5 / mass), wt = sqrt(0.5e5 * (1 / mass + l * l / I));
    double dn = 2 / wn * (sqrt(xi * xi + 1 / f) - xi),
           dtt = 2 / wt * (sqrt(xm * xm + 1 / f) - xm);
    check_live("sphere on a wall, local damping", &m, fmin(dn, dtt));
  }
  simtest_close(&T);
}

static void free_pair(void) {
  const char *yaml = "name: p\ngravity: [0, 0, 0]\n"
                     "materials: {g: {density: 2500, kn: 1.0e5, kt: 0.8e5, restitution: "
                     "0.5, friction: 0.3}}\n"
                     "particles:\n"
                     "  - {material: g, radius: 0.005, position: [0, 0, 0]}\n"
                     "  - {material: g, radius: 0.003, position: [0.00795, 0, 0]}\n"
                     "contact: {allow_initial_overlap: true}\nrun: {steps: 1}\n";
  simtest T;
  esf_modes m;
  if (modes_of(yaml, &T, &m) == 0) {
    const esf_particles *p = &T.s.p;
    double un = 0.008 - 0.00795, la = 0.005 - un / 2, lb = 0.003 - un / 2;
    double ms = p->mass[0] * p->mass[1] / (p->mass[0] + p->mass[1]);
    double wt2 = 0.8e5 * (1 / p->mass[0] + 1 / p->mass[1] + la * la / p->inertia[0] +
                          lb * lb / p->inertia[1]);
    check_close("free unequal pair", m.omega_max, sqrt(fmax(1.0e5 / ms, wt2)));
  }
  simtest_close(&T);
}

static void chain(void) {
  enum { N = 8 };
  char yaml[2048];
  int l = snprintf(yaml, sizeof yaml,
                   "name: c\ngravity: [0, 0, 0]\n"
                   "materials: {g: {density: 2500, kn: 1.0e5, kt: 1.0e-3, restitution: "
                   "0.5, friction: 0.3}}\nparticles:\n");
  for (int i = 0; i < N; i++)
    l += snprintf(yaml + l, sizeof yaml - (size_t)l,
                  "  - {material: g, radius: 0.005, position: [%.6f, 0, 0]}\n",
                  i * 0.00999);
  snprintf(yaml + l, sizeof yaml - (size_t)l,
           "contact: {allow_initial_overlap: true}\nrun: {steps: 1}\n");
  simtest T;
  esf_modes m;
  if (modes_of(yaml, &T, &m) == 0) {
    double want = 2 * sqrt(1.0e5 / T.s.p.mass[0]) * sin((N - 1) * ESF_PI / (2.0 * N));
    check_close("free chain of 8", m.omega_max, want);
    /* normal dashpots in proportion to the springs: xi = c_n omega / (2 kn) with
       c_n = 2 gamma sqrt(kn m/2), i.e. sqrt(2) gamma sin((N - 1) pi / (2N)) */
    double xm =
        sqrt(2.0) * esf_restitution_gamma(0.5) * sin((N - 1) * ESF_PI / (2.0 * N));
    CHECK(fabs(m.xi_mode / xm - 1) < 1e-6, "chain's top mode damping ratio %.9g (%.9g)",
          m.xi_mode, xm);
    CHECK(m.contacts == N - 1, "%zu contacts", m.contacts);
    /* C proportional to K: every mode's ratio grows with its frequency, the top one
       sets the limit */
    check_live("free chain of 8", &m, 2 / want * fxi(xm));
  }
  simtest_close(&T);
}

/* 5. a Hertz-Mindlin sphere pressed 10 um on a wall of its material: the tangent
 * stiffnesses at that overlap, S_n = 2 E* sqrt(R u), S_t = 8 G* sqrt(R u) (E* = E/(2 (1 -
 * nu^2)), G* = E/(4 (2 - nu)(1 + nu))), in the sphere-on-a-wall closed form, and the
 * normal damping ratio the exact map's gamma (c_n = 2 gamma sqrt(m S_n)). */
static void hertz_on_wall(void) {
  const char *yaml =
      "name: hw\ngravity: [0, 0, 0]\n"
      "materials: {g: {density: 2500, youngs_modulus: 1.0e8, poisson_ratio: 0.3, "
      "restitution: 0.5, friction: 0.3}}\n"
      "particles:\n  - {material: g, radius: 0.005, position: [0, 0, 0.00499]}\n"
      "walls:\n  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: g}\n"
      "contact: {allow_initial_overlap: true}\nrun: {steps: 1}\n";
  simtest T;
  esf_modes m;
  if (modes_of(yaml, &T, &m) == 0) {
    const double E = 1e8, nu = 0.3, r = 0.005, u = 1e-5, l = r - u / 2; /* r - u/2 */
    const double es = E / (2 * (1 - nu * nu)), gs = E / (4 * (2 - nu) * (1 + nu));
    const double sn = 2 * es * sqrt(r * u), st = 8 * gs * sqrt(r * u);
    const double mass = T.s.p.mass[0], I = T.s.p.inertia[0];
    const double w2 = fmax(sn / mass, st * (1 / mass + l * l / I));
    check_close("Hertz sphere on a wall", m.omega_max, sqrt(w2));
    const double xi = esf_hertz_gamma(0.5);
    CHECK(fabs(m.xi_max / xi - 1) < 1e-9, "Hertz: damping ratio %.9g (%.9g)", m.xi_max,
          xi);
  }
  simtest_close(&T);
}

int main(void) {
  hertz_on_wall();
  on_wall(3);
  on_wall(2);
  on_wall_local();
  free_pair();
  chain();
  return check_finish("test_modes");
}
