/* simtest.h — helpers for physics tests: build a sim from a YAML scene string, step it
 * with a named integrator, and measure simple quantities. */
#ifndef ESF_SIMTEST_H
#define ESF_SIMTEST_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "integrators/integrator.h"
#include "model/forces.h"
#include "model/model.h"
#include "scene/scene.h"
#include "util/vec3.h"

/* The linear spring-dashpot impact with the no-tension cut (test_collision.c derives
 * it): damping ratio zeta, frequency w = sqrt(k/m*), per unit approach speed. */
typedef struct cut_impact {
  double e;     /* restitution */
  double t_end; /* force duration, s */
  double t_sep; /* time until the overlap returns to zero, s */
  double u_max; /* peak overlap per unit approach speed, s */
} cut_impact;

static inline cut_impact cut_impact_closed_form(double zeta, double w) {
  double z = zeta, s = sqrt(1 - z * z);
  double th = ESF_PI - atan2(2 * z * s, 1 - 2 * z * z), thp = atan2(s, z);
  cut_impact x;
  x.t_end = th / (w * s);
  x.e = -exp(-z * th / s) * (cos(th) - z / s * sin(th));
  x.u_max = exp(-z * thp / s) * sin(thp) / (w * s);
  /* after the force vanishes the bodies coast apart at e v0 from overlap u(t_end) */
  x.t_sep = x.t_end + exp(-z * th / s) * sin(th) / (w * s) / x.e;
  return x;
}

/* A head-on collision of unequal glass spheres (r 5 and 4 mm, 1 m/s each) in free
 * space, eta = 0.5: test_collision and test_testbed measure it. */
static const char *const simtest_pair_scene =
    "name: pair\n"
    "gravity: [0, 0, 0]\n"
    "materials: {glass: {density: 2500, kn: 1.0e5, restitution: 0.5, friction: 0.3}}\n"
    "particles:\n"
    "  - {material: glass, radius: 0.005, position: [-0.00502, 0, 0], velocity: [1, 0, "
    "0]}\n"
    "  - {material: glass, radius: 0.004, position: [0.00402, 0, 0], velocity: [-1, 0, "
    "0]}\n"
    "integrator: {dt: auto, frac: 0.002}\n"
    "run: {duration: 1}\n"
    "output: {energy_every: 0}\n";

typedef struct simtest {
  esf_sim s;
  const esf_integrator_type *it;
  void *ist;
  esf_error err;
} simtest;

/* As simtest_open, with erk_arkode set in the configuration before the integrator is
 * created (1: the fixed-step erk methods on ARKODE's ERKStep, as ESF_ERK_DRIVER=arkode)
 * and prep (or NULL) run on the set-up simulation before that. */
static inline int simtest_open_prep(simtest *T, const char *yaml, const char *const *sets,
                                    int nsets, int erk_arkode, void (*prep)(esf_sim *)) {
  memset(T, 0, sizeof *T);
  esf_ydoc *doc = NULL;
  int rc = esf_ydoc_parse(yaml, "test.yaml", &doc, &T->err);
  for (int k = 0; k < nsets && !rc; k++) rc = esf_ydoc_override(doc, sets[k], &T->err);
  esf_config_default(&T->s.cfg);
  if (!rc) rc = esf_scene_read(doc, &T->s, &T->err);
  esf_ydoc_free(&doc);
  if (!rc) rc = esf_sim_setup(&T->s, &T->err);
  T->s.cfg.erk_arkode = erk_arkode;
  if (!rc && prep) prep(&T->s); /* the particles before the integrator reads them */
  if (!rc) {
    T->it = esf_integrator_find(T->s.cfg.method);
    if (!T->it) rc = esf_fail(&T->err, ESF_EINPUT, "no integrator %s", T->s.cfg.method);
  }
  if (!rc) rc = T->it->create(&T->s, &T->ist, &T->err);
  if (rc) fprintf(stderr, "simtest_open: %s\n", T->err.msg);
  return rc;
}

static inline int simtest_open_drv(simtest *T, const char *yaml, const char *const *sets,
                                   int nsets, int erk_arkode) {
  return simtest_open_prep(T, yaml, sets, nsets, erk_arkode, NULL);
}

/* Parses yaml (with --set style overrides), reads and sets up; 0 on success. */
static inline int simtest_open(simtest *T, const char *yaml, const char *const *sets,
                               int nsets) {
  return simtest_open_drv(T, yaml, sets, nsets, 0);
}

static inline int simtest_step(simtest *T) {
  int rc = T->it->step(&T->s, T->ist, INFINITY, &T->err);
  if (rc) fprintf(stderr, "simtest_step: %s\n", T->err.msg);
  return rc;
}

static inline void simtest_close(simtest *T) {
  if (T->it && T->ist) T->it->destroy(&T->ist);
  esf_sim_release(&T->s);
}

/* The whole file at path as a NUL-terminated string (free it), or NULL. */
static inline char *simtest_slurp(const char *path) {
  FILE *f = fopen(path, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long n = ftell(f);
  fseek(f, 0, SEEK_SET);
  char *b = n >= 0 ? malloc((size_t)n + 1) : NULL;
  if (b && fread(b, 1, (size_t)n, f) != (size_t)n) {
    free(b);
    b = NULL;
  }
  if (b) b[n] = 0;
  fclose(f);
  return b;
}

/* Opens the bundled scene DIR/scenes/NAME.yaml (see simtest_open); 0 on success. */
static inline int simtest_open_scene(simtest *T, const char *dir, const char *name,
                                     const char *const *sets, int nsets) {
  char path[1024];
  snprintf(path, sizeof path, "%s/scenes/%s.yaml", dir, name);
  char *yaml = simtest_slurp(path);
  if (!yaml) {
    memset(T, 0, sizeof *T);
    fprintf(stderr, "simtest_open_scene: cannot read %s\n", path);
    return -1;
  }
  int rc = simtest_open(T, yaml, sets, nsets);
  free(yaml);
  return rc;
}

#endif
