/* test_loads_ckpt.c — a checkpoint of a run with servo walls, a drilling event and the
 * fluid force resumes bit for bit (checkpoint.h, section SAND): run A is checkpointed
 * after the drilling and before the fluid starts and goes on; run B is rebuilt from
 * the checkpoint and steps to the same time. Particle state, servo wall displacement
 * and velocity, the event's record and the ledger must be identical (memcmp). */
#include <stdlib.h>
#include <unistd.h>

#include "ckpt/checkpoint.h"
#include "loads/events.h"
#include "servo_box.h"
#include "simtest.h"

static const char *const scene =
    "name: sandckpt\n"
    "gravity: [0, 0, -9.81]\n"
    "materials: {m: {density: 2500, kn: 1.0e6, restitution: 0.2, friction: "
    "0.3}}\n" SERVO_BOX_YAML
    "events: [{at: 0.12, delete: {cylinder: {center: [0.02, 0.02, 0.02], axis: [0, 1, "
    "0], radius: 0.008}}}]\n"
    "fluid:\n"
    "  start: 0.16\n"
    "  porosity: {cell: 0.02}\n" SERVO_BOX_RADIAL_FLOW "run: {duration: 0.2}\n"
    "output: {energy_every: 1.0e-3}\n";

static int run_to(simtest *T, double t) {
  int rc = 0;
  while (!rc && T->s.t < t - 0.5 * T->s.dt) rc = simtest_step(T);
  return rc;
}

int main(void) {
  char dir[] = "/tmp/esf_loads_ckptXXXXXX";
  CHECK(mkdtemp(dir) != NULL, "temporary directory");
  char path[256];
  snprintf(path, sizeof path, "%s/checkpoint.esf", dir);
  simtest A;
  int rc = simtest_open(&A, scene, NULL, 0);
  CHECK(rc == 0, "scene opens");
  if (rc) return check_finish("loads_ckpt");
  rc = run_to(&A, 0.14);
  CHECK(rc == 0 && A.s.events->e[0].done, "run A reaches 0.14 s, drilled");
  esf_ckpt_scene sc = {"test.yaml", scene, strlen(scene), NULL, 0};
  esf_ckpt_run run;
  memset(&run, 0, sizeof run); /* the run driver's record, as it would fill it */
  run.n = A.s.step;
  run.frames = 1;
  run.count = 1;
  run.csv_bytes = A.s.led.on ? 0 : -1;
  rc = esf_ckpt_write(path, &A.s, A.it, A.ist, &sc, &run, &A.err);
  CHECK(rc == 0, "checkpoint written: %s", A.err.msg);
  double t_end = 0.19;
  rc = run_to(&A, t_end);
  CHECK(rc == 0, "run A goes on");

  esf_ckpt *c = NULL;
  simtest B;
  memset(&B, 0, sizeof B);
  rc = esf_ckpt_load(path, &c, &B.err);
  if (!rc) rc = esf_ckpt_load_scene(c, NULL, 0, &B.s, &B.err);
  if (!rc) rc = esf_sim_setup(&B.s, &B.err);
  B.it = A.it;
  if (!rc) rc = B.it->create(&B.s, &B.ist, &B.err);
  esf_ckpt_run runb;
  if (!rc) rc = esf_ckpt_restore(c, &B.s, B.it, B.ist, &runb, &B.err);
  CHECK(rc == 0, "checkpoint restored: %s", B.err.msg);
  esf_ckpt_free(&c);
  if (!rc) rc = run_to(&B, t_end);
  CHECK(rc == 0, "run B resumes");
  const esf_sim *a = &A.s, *b = &B.s;
  CHECK(a->step == b->step && a->p.n == b->p.n, "steps %ld/%ld, particles %zu/%zu",
        a->step, b->step, a->p.n, b->p.n);
  if (a->p.n == b->p.n) {
    CHECK(memcmp(a->p.y, b->p.y, 9 * a->p.n * sizeof(double)) == 0,
          "particle state identical");
    CHECK(memcmp(a->p.id, b->p.id, a->p.n * sizeof *a->p.id) == 0, "ids identical");
  }
  const esf_wall_group *ga = &a->walls.g[1], *gb = &b->walls.g[1];
  CHECK(memcmp(ga->disp, gb->disp, sizeof ga->disp) == 0 &&
            memcmp(ga->vel, gb->vel, sizeof ga->vel) == 0,
        "servo lid displacement and velocity identical: %.17g / %.17g", ga->disp[2],
        gb->disp[2]);
  CHECK(b->events->e[0].done && b->events->e[0].deleted == a->events->e[0].deleted,
        "event record carried (deleted %ld)", b->events->e[0].deleted);
  CHECK(memcmp(&a->led, &b->led, sizeof a->led) == 0,
        "ledger identical (work_fluid %g J)", b->led.w_fluid);
  printf("sand checkpoint at t = 0.14 s resumed to t = %.4g s: %zu particles, lid at "
         "%.9g m moving %.4g m/s, %ld deleted, work_fluid %.6g J\n",
         b->t, b->p.n, gb->disp[2], gb->vel[2], b->events->e[0].deleted, b->led.w_fluid);
  simtest_close(&A);
  simtest_close(&B);
  unlink(path);
  rmdir(dir);
  return check_finish("loads_ckpt");
}
