/* bonds.c — forming bonds at the start and the bond bookkeeping (bonds.h;
 * docs/physics.md#adhesive-normal-law-and-bonds, 004 2.25).
 *
 * esf_bonds_setup, on entry: pair table mixed, cfg.skin set. It scans the particle
 * material pairs for the adhesive law and takes the bond reach
 *   reach = max over those pairs of (bond_gap > 0 ? bond_gap + u_eq : 0) - u_rupture,
 * an upper bound of the gap at which any bond ruptures (m). It also records
 * mats.particles_fused (every pair of the particles' materials has a law the fused
 * step computes: fused/fused.c requires it). esf_bonds_form, on entry: the candidate list
 * just built at the initial positions, no force evaluated yet. For each candidate of an
 * adhesive pair that meets the rule of bonds.h it sets touch = 1, xi = 0, n = the current
 * normal, and the bond state (nb.pp.bond, which only scenes with bonds allocate: sim.c
 * sets nb.bonds): on = 1 and the offset s. On exit pending = 0 and formed counts the
 * bonds. Rupture is counted where the force loop commits it (forces.c), with its energy.
 */
#include "core/bonds.h"

#include <math.h>
#include <stdlib.h>

#include "core/sim.h"
#include "util/vec3.h"

int esf_bonds_setup(esf_sim *s, int skin_auto, esf_error *err) {
  esf_materials *mt = &s->mats;
  esf_bonds *B = &s->bonds;
  *B = (esf_bonds){0};
  unsigned char *used = calloc((size_t)(mt->n ? mt->n : 1), 1);
  if (!used) return esf_fail(err, ESF_ENOMEM, "out of memory");
  for (size_t i = 0; i < s->p.n; i++) used[s->p.material[i]] = 1;
  mt->particles_fused = 1;
  for (int a = 0; a < mt->n; a++)
    for (int b = 0; b < mt->n; b++) {
      const esf_pair_params *pp = &mt->pair[a * mt->n + b];
      if (used[a] && used[b])
        mt->particles_fused &= (pp->law->flags & ESF_LAW_FUSED) != 0;
      if (!used[a] || !used[b] || !(pp->law->flags & ESF_LAW_TENSION)) continue;
      B->on = 1;
      double G = pp->adh.gap;
      double r = (G > 0 ? G + pp->adh.u_eq : 0.0) - pp->adh.u_rupture;
      if (r > B->reach) B->reach = r;
    }
  free(used);
  B->pending = B->on;
  if (!B->on || s->cfg.skin > B->reach) return ESF_OK;
  if (skin_auto) {
    s->cfg.skin = 1.25 * B->reach;
    return ESF_OK;
  }
  return esf_fail(err, ESF_EINPUT,
                  "%s: search.skin = %.6g m does not exceed the bond reach %.6g m (the "
                  "largest bond_gap plus the rest overlap and rupture opening of the "
                  "adhesive law): bonded pairs opening in tension would drop out of the "
                  "contact candidates. Set search.skin above %.6g m, or leave it "
                  "automatic",
                  esf_config_where(&s->cfg, "search.skin"), s->cfg.skin, B->reach,
                  B->reach);
}

int esf_bonds_form(esf_sim *s, esf_error *err) {
  (void)err;
  esf_bonds *B = &s->bonds;
  const esf_particles *p = &s->p;
  const esf_materials *mt = &s->mats;
  esf_candidates *c = &s->nb.pp;
  for (size_t k = 0; k < c->n; k++) {
    uint32_t a = c->a[k], b = c->b[k];
    const esf_pair_params *pp = &mt->pair[p->material[a] * mt->n + p->material[b]];
    if (!(pp->law->flags & ESF_LAW_TENSION)) continue;
    double d[3];
    v3_sub(d, p->x + 3 * b, p->x + 3 * a);
    double dist = v3_norm(d);
    double u0 = p->radius[a] + p->radius[b] - dist;
    double off = 0.0, G = pp->adh.gap;
    if (G > 0) {
      if (u0 < -G) continue;
      if (u0 < pp->adh.u_eq) off = pp->adh.u_eq - u0;
    } else if (u0 < pp->adh.u_rupture) {
      continue;
    }
    esf_contact_hist *h = &c->h[k];
    *h = (esf_contact_hist){{0, 0, 0}, {0, 0, 1}};
    c->bond[k] = (esf_contact_bond){off, 1, 0}; /* the list has them (nb.bonds) */
    if (dist > 0) v3_scale(h->n, 1.0 / dist, d);
    c->touch[k] = 1;
    B->formed += esf_sim_owns(s, a); /* MPI: each bond counted where A is owned */
  }
  B->formed = esf_sim_sum(s, B->formed);
  B->pending = 0;
  esf_sim_log(s,
              "bonds: %ld formed at t = %.6g s; the largest gap a bond opens to "
              "before rupture is %.6g m, skin %.6g m",
              B->formed, s->t, B->reach, s->nb.skin);
  return ESF_OK;
}

long esf_bonds_alive(const esf_sim *s) {
  const esf_candidates *c = &s->nb.pp;
  long m = 0;
  for (size_t k = 0; k < c->n; k++)
    m += c->touch[k] && esf_candidates_bonded(c, k) && esf_sim_owns(s, c->a[k]);
  return (long)esf_sim_sum(s, m);
}

long esf_bonds_broken(const esf_sim *s) { return (long)esf_sim_sum(s, s->bonds.broken); }
