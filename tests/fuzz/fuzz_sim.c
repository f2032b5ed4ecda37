/* fuzz_sim.c — the part of `esfera run SCENE` the scene harnesses share (fuzz.h):
 * a parsed scene document read into a sim (esf_scene_read), the integrator found by
 * name, the sim set up (esf_sim_setup) on one thread and the integrator created and
 * destroyed, as the run driver does before its first step; then everything freed.
 * Returns the first failing status (with err's message) or ESF_OK. */
#include <stdio.h>
#include <string.h>

#include "fuzz.h"
#include "integrators/integrator.h"
#include "model/model.h"
#include "scene/scene.h"

int esf_fuzz_scene(esf_ydoc *doc, const char *source, esf_error *err) {
  esf_sim s;
  memset(&s, 0, sizeof s);
  esf_config_default(&s.cfg);
  snprintf(s.cfg.source, sizeof s.cfg.source, "%s", source);
  int rc = esf_scene_read(doc, &s, err);
  const esf_integrator_type *it = rc ? NULL : esf_integrator_find(s.cfg.method);
  if (!rc && !it)
    rc = esf_fail(err, ESF_EINPUT, "%s: integrator.method: unknown method '%s'",
                  esf_config_where(&s.cfg, "integrator.method"), s.cfg.method);
  s.cfg.threads = 1; /* as --threads 1: one fuzzer process per core */
  if (!rc) rc = esf_sim_setup(&s, err);
  void *ist = NULL;
  if (!rc) rc = it->create(&s, &ist, err);
  if (ist) it->destroy(&ist);
  esf_sim_release(&s);
  return rc;
}
