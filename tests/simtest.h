/* simtest.h — helpers for physics tests: build a sim from a YAML scene string, step it
 * with a named integrator, and measure simple quantities. */
#ifndef ESF_SIMTEST_H
#define ESF_SIMTEST_H

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "forces.h"
#include "integrator.h"
#include "scene.h"
#include "vec3.h"

typedef struct simtest {
  esf_sim s;
  const esf_integrator_type *it;
  void *ist;
  esf_error err;
} simtest;

/* Parses yaml (with --set style overrides), reads and sets up; 0 on success. */
static inline int simtest_open(simtest *T, const char *yaml, const char *const *sets,
                               int nsets) {
  memset(T, 0, sizeof *T);
  esf_ydoc *doc = NULL;
  int rc = esf_ydoc_parse(yaml, "test.yaml", &doc, &T->err);
  for (int k = 0; k < nsets && !rc; k++) rc = esf_ydoc_override(doc, sets[k], &T->err);
  esf_config_default(&T->s.cfg);
  if (!rc) rc = esf_scene_read(doc, &T->s, &T->err);
  esf_ydoc_free(&doc);
  if (!rc) rc = esf_sim_setup(&T->s, &T->err);
  if (!rc) {
    T->it = esf_integrator_find(T->s.cfg.method);
    if (!T->it) rc = esf_fail(&T->err, ESF_EINPUT, "no integrator %s", T->s.cfg.method);
  }
  if (!rc) rc = T->it->create(&T->s, &T->ist, &T->err);
  if (rc) fprintf(stderr, "simtest_open: %s\n", T->err.msg);
  return rc;
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

#endif
