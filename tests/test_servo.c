/* test_servo.c — servo-controlled walls and deleting particles at a time (issue 4).
 *
 * 1. One sphere (r 10 mm, kn 1e6 N/m) between two square servo plates (A = 0.01 m^2)
 *    each holding sigma = 1e4 Pa, no gravity: at rest each plate's contact force is
 *    sigma A = 100 N, so the overlap is sigma A / kn = 1e-4 m and the plates are
 *    2 (r - 1e-4) apart. Checked: measured stress, contact force and gap against these
 *    within 1e-4 relative, and held (stress within 1e-3 over the last half).
 * 2. A packing of 80 frictionless spheres under gravity in a box whose top is a servo
 *    plate at 2e4 Pa: the plate's stress reaches the target within 1% and stays within
 *    2% over t > 0.4 s (the lid arrives at about 0.2 s); the floor (a fixed wall,
 * frictionless side walls) carries sigma A plus the weight of the spheres within 1%
 * (force balance).
 * 3. Drilling: the same packing, an event deletes the centres inside a cylinder at
 *    t_d. Nothing is deleted before t_d; the count deleted equals a brute-force count
 *    of centres inside the cylinder at the step it applies, at the step nearest t_d; the
 *    energy balance residual changes across the event by less than 1% of the energy
 *    the deleted particles carried (kinetic, gravity and their contacts' elastic). */
#include "loads/events.h"
#include "loads/servo.h"
#include "servo_box.h"
#include "simtest.h"

static const char *const plates =
    "name: plates\n"
    "gravity: [0, 0, 0]\n"
    "materials: {m: {density: 2500, kn: 1.0e6, restitution: 0.3, friction: 0.3}}\n"
    "particles:\n"
    "  - {material: m, radius: 0.01, position: [0, 0, 0]}\n"
    "walls:\n"
    "  - polygon: [[-0.05, -0.05, -0.0105], [0.05, -0.05, -0.0105], [0.05, 0.05, "
    "-0.0105], [-0.05, 0.05, -0.0105]]\n"
    "    material: m\n"
    "    motion: {servo: {stress: 1.0e4, direction: [0, 0, 1], max_speed: 0.01}}\n"
    "  - polygon: [[-0.05, -0.05, 0.0105], [0.05, -0.05, 0.0105], [0.05, 0.05, "
    "0.0105], [-0.05, 0.05, 0.0105]]\n"
    "    material: m\n"
    "    motion: {servo: {stress: 1.0e4, direction: [0, 0, -1], max_speed: 0.01}}\n"
    "integrator: {method: leapfrog, dt: auto, frac: 0.1}\n"
    "run: {duration: 0.2}\n"
    "output: {energy_every: 0}\n";

static double plate_z(const esf_sim *s, int g) {
  for (size_t i = 0; i < s->walls.n; i++)
    if (s->walls.e[i].group == g) return s->walls.e[i].p[2];
  return NAN;
}

static void two_plates(void) {
  simtest T;
  if (simtest_open(&T, plates, NULL, 0)) {
    CHECK(0, "plates scene opens");
    return;
  }
  esf_sim *s = &T.s;
  CHECK_NEAR(s->walls.g[0].motion.area, 0.01, 1e-15, "plate area from its polygon");
  double sig = 1.0e4, A = 0.01, kn = 1.0e6, F = sig * A, delta = F / kn;
  double worst = 0;
  int rc = 0;
  while (!rc && s->t < 0.2) {
    rc = simtest_step(&T);
    if (s->t > 0.1)
      for (int g = 0; g < 2; g++)
        worst = fmax(worst, fabs(s->walls.g[g].motion.sigma - sig) / sig);
  }
  CHECK(rc == 0, "plates run");
  for (int g = 0; g < 2; g++) {
    CHECK_NEAR(s->walls.g[g].motion.sigma, sig, 1e-4 * sig, "plate stress");
    CHECK_NEAR(fabs(s->walls.gforce[4 * g + 2]), F, 1e-4 * F, "plate contact force");
  }
  double gap = plate_z(s, 1) - plate_z(s, 0);
  CHECK_NEAR(gap, 2 * (0.01 - delta), 1e-4 * delta, "plate gap 2 (r - sigma A / kn)");
  CHECK(worst < 1e-3, "stress held over the last half: worst %.3g", worst);
  printf("two plates: sigma %.8g Pa (target %g), force %.8g N, gap %.10g m (expected "
         "%.10g), worst deviation over the last half %.2e\n",
         s->walls.g[0].motion.sigma, sig, fabs(s->walls.gforce[2]), gap,
         2 * (0.01 - delta), worst);
  simtest_close(&T);
}

/* box 0.04 x 0.04, open top; a servo lid from z = 0.06 down; floor is group 0 */
static const char *const packing =
    "name: packing\n"
    "gravity: [0, 0, -9.81]\n"
    "materials: {m: {density: 2500, kn: 1.0e6, restitution: 0.2, friction: "
    "0.0}}\n" SERVO_BOX_YAML "integrator: {method: leapfrog, dt: auto, frac: 0.2}\n"
    "damping: {global: {translation: 20}}\n"
    "run: {duration: 1}\n"
    "output: {energy_every: 1.0e-3}\n";

/* z force of group 0 (the box: floor and frictionless sides) on the spheres, N */
static double floor_force(const esf_sim *s) { return s->walls.gforce[2]; }

static void servo_packing(void) {
  simtest T;
  if (simtest_open(&T, packing, NULL, 0)) {
    CHECK(0, "packing scene opens");
    return;
  }
  esf_sim *s = &T.s;
  double sig = 2.0e4, A = 0.04 * 0.04, W = 0;
  for (size_t i = 0; i < s->p.n; i++) W += s->p.mass[i] * 9.81;
  int rc = 0;
  double t_end = 0.6, worst = 0, t_reach = -1;
  while (!rc && s->t < t_end) {
    rc = simtest_step(&T);
    double e = fabs(s->walls.g[1].motion.sigma - sig) / sig;
    if (t_reach < 0 && e < 0.01) t_reach = s->t;
    if (s->t > 0.4) worst = fmax(worst, e);
  }
  CHECK(rc == 0, "packing run");
  CHECK(t_reach > 0, "target stress reached (within 1%%)");
  CHECK(worst < 0.02, "stress held within 2%% over t > 0.4 s: worst %.3g", worst);
  /* floor: the box's elements are group 0; the floor's force on the spheres is +z */
  double ff = floor_force(s);
  /* the box group also holds the frictionless side walls, whose forces are horizontal */
  CHECK_NEAR(ff, sig * A + W, 0.01 * (sig * A + W), "floor force = sigma A + weight");
  printf("servo packing: %zu spheres, target %g Pa reached at t = %.4g s; final %.6g Pa; "
         "worst over t > 0.4 s %.3g%%; floor %.6g N vs sigma A + W = %.6g N\n",
         s->p.n, sig, t_reach, s->walls.g[1].motion.sigma, 100 * worst, ff, sig * A + W);
  simtest_close(&T);
}

static void drilling(void) {
  const char *sets[] = {"events=[{at: 0.45, delete: {cylinder: {center: [0.02, 0.02, 0], "
                        "axis: [0, 1, 0], radius: 0.008}}}]"};
  simtest T;
  if (simtest_open(&T, packing, sets, 1)) {
    CHECK(0, "drilling scene opens");
    return;
  }
  esf_sim *s = &T.s;
  const esf_event *ev = &s->events->e[0];
  size_t n0 = s->p.n;
  long expect = -1;
  int rc = 0, early = 0;
  double err_before = 0, err_after = 0, removed_before = 0;
  while (!rc && s->t < 0.55) {
    int due = !ev->done && ev->at <= s->t + 0.5 * s->dt;
    if (due) {
      expect = 0;
      for (size_t i = 0; i < s->p.n; i++) {
        double dx = s->p.x[3 * i] - 0.02, dz = s->p.x[3 * i + 2];
        expect += dx * dx + dz * dz <= 0.008 * 0.008;
      }
      err_before = esf_ledger_total_error(&s->led);
      removed_before = s->led.e_removed;
    }
    size_t nb = s->p.n;
    rc = simtest_step(&T);
    if (due) {
      err_after = esf_ledger_total_error(&s->led);
      CHECK(nb - s->p.n == (size_t)expect, "deleted %zu, brute force %ld", nb - s->p.n,
            expect);
    } else if (!ev->done && s->p.n != n0) {
      early = 1;
    }
  }
  CHECK(rc == 0, "drilling run");
  CHECK(!early, "nothing deleted before the event");
  CHECK(ev->done && ev->deleted == expect && expect > 0,
        "event deleted %ld (expected %ld)", ev->deleted, expect);
  CHECK(fabs(ev->t_done - 0.45) <= 0.5 * s->dt + 1e-12, "applied at t = %.6g",
        ev->t_done);
  double carried = s->led.e_removed - removed_before;
  CHECK(fabs(err_after - err_before) < 0.01 * carried,
        "balance across the event: residual %.4g -> %.4g J, removed %.4g J", err_before,
        err_after, carried);
  printf("drilling: %ld of %zu particles deleted at t = %.6g s (brute force %ld); they "
         "carried %.4g J; balance residual %.4g -> %.4g J; residual at the end %.4g J\n",
         ev->deleted, n0, ev->t_done, expect, carried, err_before, err_after,
         esf_ledger_total_error(&s->led));
  simtest_close(&T);
}

int main(void) {
  two_plates();
  servo_packing();
  drilling();
  return check_finish("servo");
}
