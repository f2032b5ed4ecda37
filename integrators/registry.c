/* registry.c — the table of time integrators, looked up by integrator.method. */
#include <string.h>

#include "integrators/integrator.h"

const esf_integrator_type *const esf_integrators[] = {
    &esf_integrator_leapfrog, &esf_integrator_verlet, &esf_integrator_erk,
    &esf_integrator_cvode, NULL};

const esf_integrator_type *esf_integrator_find(const char *name) {
  if (strncmp(name, "erk:", 4) == 0 || strcmp(name, "rk4") == 0)
    return &esf_integrator_erk;
  for (int k = 0; esf_integrators[k]; k++)
    if (strcmp(esf_integrators[k]->name, name) == 0) return esf_integrators[k];
  return NULL;
}
