/* roots.c — event functions for contact onset and separation (see the header).
 *
 * Pair k (A, B): d = xB - xA, n = d/|d|, un = rA + rB - |d|, vn = (vB - vA).n (rotation
 * adds nothing along n). Wall candidate (A, element e): q the element's nearest point
 * to xA, n toward q, un = rA - |q - xA|, vn = (v_wall(q) - vA).n. The dashpot ratio
 * c_n/k_n is the pair's: beta under Rayleigh damping, else cn_factor sqrt(m*)/k_n (m* =
 * mA at a wall); Hertz-Mindlin: c_n/k_s at the current overlap (k_s u the elastic force).
 * A candidate whose wall hit is shared with a neighbouring element (forces.c counts it
 * once) still reports its own event: an extra event only shortens a step. Units: SI; g in
 * m. Entry: candidate lists valid for x. */
#include "model/roots.h"

#include <math.h>

#include "contact/lane_scalar.h"
#include "util/vec3.h"

size_t esf_roots_count(const esf_sim *s) { return s->nb.pp.n + s->nb.pw.n; }

static double event_value(const esf_pair_params *pp, double beta, double mstar,
                          double rstar, double un, double vn) {
  if (pp->law == &esf_contact_hertz) { /* c_n/k_s at un (contact_hertz.h) */
    if (!(un > 0)) return un;
    double ks, sn, st, qa, cn, ct, sm = sqrt(mstar);
    esf_law_hertz_springs_s(pp->hn, pp->ht, rstar, un, &ks, &sn, &st, &qa);
    if (pp->hertz_constant) qa = esf_law_hertz_qref_s(pp->estar, sm, rstar, pp->v_imp);
    esf_law_hertz_dashpots_s(beta, pp->cn_factor, pp->ct_factor, sm, qa, sn, st, &cn,
                             &ct);
    return fmin(un, un - cn / ks * vn);
  }
  double cn = beta > 0 ? beta * pp->kn : pp->cn_factor * sqrt(mstar);
  double ratio = pp->kn > 0 ? cn / pp->kn : 0.0;
  return fmin(un, un - ratio * vn);
}

void esf_roots_eval(const esf_sim *s, const double *x, const double *v, double *g) {
  const esf_particles *p = &s->p;
  const esf_materials *mt = &s->mats;
  const esf_candidates *c = &s->nb.pp;
  for (size_t k = 0; k < c->n; k++) {
    uint32_t a = c->a[k], b = c->b[k];
    double d[3], dv[3];
    v3_sub(d, x + 3 * b, x + 3 * a);
    v3_sub(dv, v + 3 * b, v + 3 * a);
    double dist = v3_norm(d);
    double un = p->radius[a] + p->radius[b] - dist;
    double vn = dist > 0 ? v3_dot(dv, d) / dist : 0.0;
    const esf_pair_params *pp = &mt->pair[p->material[a] * mt->n + p->material[b]];
    double mstar = p->mass[a] * p->mass[b] / (p->mass[a] + p->mass[b]);
    g[k] =
        event_value(pp, s->beta, mstar,
                    p->radius[a] * p->radius[b] / (p->radius[a] + p->radius[b]), un, vn);
  }
  double *gw = g + c->n;
  c = &s->nb.pw;
  for (size_t k = 0; k < c->n; k++) {
    uint32_t a = c->a[k];
    const esf_wall_elem *el = &s->walls.e[c->b[k]];
    esf_wall_hit hit;
    esf_wall_nearest(el, x + 3 * a, &hit);
    double vw[3], dv[3];
    esf_wall_point_velocity(&s->walls.g[el->group], hit.q, vw);
    v3_sub(dv, vw, v + 3 * a);
    double un = p->radius[a] - hit.dist;
    const esf_pair_params *pp = &mt->pair[p->material[a] * mt->n + el->material];
    gw[k] = event_value(pp, s->beta, p->mass[a], p->radius[a], un, v3_dot(dv, hit.n));
  }
}
