/* material.c — material table and pair mixing
 * (docs/physics.md#material-parameters-and-mixing).
 *
 * Damping from restitution (Tsuji et al., 004 eqs. 2.27–2.29): c = 2 gamma sqrt(m* k)
 * with gamma = -ln eta / sqrt(pi^2 + ln^2 eta) and m* the reduced mass (the particle's
 * mass against a wall). m* depends on the particles, so the table stores
 * 2 gamma sqrt(k) and the force loop multiplies by sqrt(m*).
 * Rayleigh (001 3.47): when beta > 0 the contact dashpots are c = beta k instead; the
 * table then stores cn_factor = ct_factor = 0 and the force loop uses beta. */
#include "contact/material.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "contact/contact_law.h"
#include "util/vec3.h"

const char *const esf_mix_names[] = {"harmonic", "arithmetic", "geometric",
                                     "min",      "max",        NULL};

void esf_mixing_default(esf_mixing *m) {
  m->kn = ESF_MIX_HARMONIC;
  m->kt = ESF_MIX_HARMONIC;
  m->restitution = ESF_MIX_MIN;
  m->tangential_restitution = ESF_MIX_MIN;
  m->friction = ESF_MIX_MIN;
  m->cohesion = ESF_MIX_MIN;
  m->tensile_limit = ESF_MIX_MIN;
  m->adhesion_force = ESF_MIX_MIN;
  m->adhesion_epsilon = ESF_MIX_GEOMETRIC; /* the mean of ln eps */
  m->adhesion_gap = ESF_MIX_MIN;
}

double esf_mix(int rule, double a, double b) {
  if (a == b) return a; /* exact for equal materials under every rule */
  switch (rule) {
  case ESF_MIX_HARMONIC:
    return (a + b) > 0 ? 2.0 * a * b / (a + b) : 0.0;
  case ESF_MIX_ARITHMETIC:
    return 0.5 * (a + b);
  case ESF_MIX_GEOMETRIC:
    return sqrt(a * b);
  case ESF_MIX_MIN:
    return a < b ? a : b;
  default:
    return a > b ? a : b;
  }
}

double esf_restitution_gamma(double eta) {
  if (eta >= 1.0) return 0.0;
  double l = log(eta);
  return -l / sqrt(ESF_PI * ESF_PI + l * l);
}

int esf_materials_add(esf_materials *t, const esf_material *m, int32_t *index,
                      esf_error *err) {
  if (esf_materials_find(t, m->name) >= 0)
    return esf_fail(err, ESF_EINPUT, "material '%s' is defined twice", m->name);
  esf_material *mm = realloc(t->m, (size_t)(t->n + 1) * sizeof *mm);
  if (!mm) return esf_fail(err, ESF_ENOMEM, "out of memory for materials");
  t->m = mm;
  t->m[t->n] = *m;
  if (index) *index = t->n;
  t->n++;
  return ESF_OK;
}

int32_t esf_materials_find(const esf_materials *t, const char *name) {
  for (int k = 0; k < t->n; k++)
    if (strcmp(t->m[k].name, name) == 0) return k;
  return -1;
}

/* A Hertz-Mindlin pair (docs/physics.md#hertz-mindlin-law): E* = 1/((1 - nu_a^2)/E_a +
 * (1 - nu_b^2)/E_b), G* = 1/(2 (2 - nu_a)(1 + nu_a)/E_a + 2 (2 - nu_b)(1 + nu_b)/E_b)
 * (Johnson 1985; G = E/(2 (1 + nu)) each), the damping ratios from the exact map of the
 * mixed restitutions (esf_hertz_gamma). For equal materials: exactly E/(2 (1 - nu^2)),
 * E/(4 (2 - nu)(1 + nu)). */
static void hertz_pair(const esf_materials *t, const esf_material *A,
                       const esf_material *B, double en, double et, esf_pair_params *p) {
  const double na = A->poisson_ratio, nb = B->poisson_ratio;
  p->law = &esf_contact_hertz;
  p->kn = p->kt = 0.0;
  p->estar =
      1.0 / ((1 - na * na) / A->youngs_modulus + (1 - nb * nb) / B->youngs_modulus);
  p->gstar = 1.0 / (2 * (2 - na) * (1 + na) / A->youngs_modulus +
                    2 * (2 - nb) * (1 + nb) / B->youngs_modulus);
  p->hn = 4.0 / 3.0 * p->estar;
  p->ht = 8.0 * p->gstar;
  p->hertz_constant = t->hertz_constant;
  p->v_imp = t->impact_speed;
  if (t->rayleigh_beta > 0) {
    p->gamma_n = p->gamma_t = 0.0;
    p->cn_factor = p->ct_factor = 0.0;
    return;
  }
  p->gamma_n = esf_hertz_gamma_form(en, t->hertz_constant);
  p->gamma_t = esf_hertz_gamma_form(et, t->hertz_constant);
  /* tsuji: c = 2 gamma sqrt(m* S), S = 1.5 hn a or ht a: factor sqrt(m*) sqrt(a) */
  p->cn_factor = 2.0 * p->gamma_n * sqrt(1.5 * p->hn);
  p->ct_factor = 2.0 * p->gamma_t * sqrt(p->ht);
}

int esf_materials_mix(esf_materials *t, esf_error *err) {
  free(t->pair);
  t->pair = calloc((size_t)t->n * (size_t)(t->n ? t->n : 1), sizeof *t->pair);
  if (!t->pair) return esf_fail(err, ESF_ENOMEM, "out of memory for the pair table");
  const esf_mixing *r = &t->mixing;
  t->all_linear = 1;
  t->all_hertz = t->n > 0;
  t->any_cohesion = 0;
  for (int a = 0; a < t->n; a++) {
    for (int b = 0; b < t->n; b++) {
      const esf_material *A = &t->m[a], *B = &t->m[b];
      esf_pair_params *p = &t->pair[a * t->n + b];
      p->kn = esf_mix(r->kn, A->kn, B->kn);
      p->kt = esf_mix(r->kt, A->kt, B->kt);
      double en = esf_mix(r->restitution, A->restitution, B->restitution);
      double et = esf_mix(r->tangential_restitution, A->tangential_restitution,
                          B->tangential_restitution);
      p->gamma_n = esf_restitution_gamma(en);
      p->gamma_t = esf_restitution_gamma(et);
      p->estar = p->gstar = p->hn = p->ht = 0.0;
      if (t->rayleigh_beta > 0) {
        /* c = beta k per contact; the damping ratio beta omega / 2 depends on the
           contact's frequency, so the restitution-derived gammas do not apply */
        p->cn_factor = p->ct_factor = 0.0;
        p->gamma_n = p->gamma_t = 0.0;
      } else {
        p->cn_factor = 2.0 * p->gamma_n * sqrt(p->kn);
        p->ct_factor = 2.0 * p->gamma_t * sqrt(p->kt);
      }
      p->mu = esf_mix(r->friction, A->friction, B->friction);
      p->cohesion = esf_mix(r->cohesion, A->cohesion, B->cohesion);
      double ta = A->tensile_limit, tb = B->tensile_limit;
      /* no limit given: the apex of the Mohr-Coulomb line, c / mu (0 when c = 0) */
      double apex = p->mu > 0 ? p->cohesion / p->mu : 0.0;
      if (ta < 0 && tb < 0)
        p->tensile_limit = apex;
      else if (ta < 0)
        p->tensile_limit = tb;
      else if (tb < 0)
        p->tensile_limit = ta;
      else
        p->tensile_limit = esf_mix(r->tensile_limit, ta, tb);
      /* the adhesive law where both materials are adhesive (F > 0) */
      p->law = &esf_contact_linear;
      p->adh = (esf_adhesion){0};
      if (A->adhesion_force > 0 && B->adhesion_force > 0) {
        double F = esf_mix(r->adhesion_force, A->adhesion_force, B->adhesion_force);
        double eps =
            esf_mix(r->adhesion_epsilon, A->adhesion_epsilon, B->adhesion_epsilon);
        int rc = esf_adhesion_derive(F, eps, p->kn, &p->adh, err);
        if (rc) {
          esf_error_prefix(err, "materials '%s' and '%s' (mixed adhesion): ", A->name,
                           B->name);
          return rc;
        }
        p->adh.gap = esf_mix(r->adhesion_gap, A->adhesion_gap, B->adhesion_gap);
        p->law = &esf_contact_adhesive;
      }
      const int ha = A->youngs_modulus > 0, hb = B->youngs_modulus > 0;
      if (ha != hb)
        return esf_fail(
            err, ESF_EINPUT,
            "materials '%s' and '%s': a Hertz-Mindlin material (youngs_modulus) "
            "meets a linear one (kn); there is no mixing rule between the laws",
            ha ? A->name : B->name, ha ? B->name : A->name);
      if (ha) {
        if (p->law != &esf_contact_linear)
          return esf_fail(err, ESF_EINPUT,
                          "materials '%s' and '%s': adhesion is not defined for the "
                          "Hertz-Mindlin law",
                          A->name, B->name);
        hertz_pair(t, A, B, en, et, p);
      }
      t->all_linear &= p->law == &esf_contact_linear;
      t->all_hertz &= p->law == &esf_contact_hertz;
      t->any_cohesion |= p->cohesion != 0.0;
    }
  }
  t->particles_fused = t->all_linear;
  return ESF_OK;
}

void esf_materials_release(esf_materials *t) {
  free(t->m);
  free(t->pair);
  t->m = NULL;
  t->pair = NULL;
  t->n = 0;
}
