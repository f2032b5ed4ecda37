/* contact_net.c — the contact network for output (contact_net.h).
 *
 * For every particle-particle candidate (neighbor.h) with overlap un = rA + rB - d > 0
 * at the current positions, the contact kinematics are formed as in forces.c (normal
 * n = (xB - xA)/d, lever arms rA - un/2 and rB - un/2, relative contact velocity with
 * the current v and w, spin, reduced mass) and the contact law is evaluated in trial
 * mode (history read, nothing written) over the sim's dt; its fn is kept. With the
 * leapfrog the velocities are the half-step ones, as in the frames. Cost: one pass
 * over the candidate list per frame. Entry: candidate lists valid for the positions;
 * exit: net holds the touching pairs; the sim is unchanged. */
#include "output/contact_net.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/sim.h"
#include "util/vec3.h"

static int reserve(esf_contact_net *net, size_t n, esf_error *err) {
  if (n <= net->cap) return ESF_OK;
  size_t cap = net->cap ? net->cap : 256;
  while (cap < n) cap *= 2;
  int64_t *pr = realloc(net->pair, 2 * cap * sizeof *pr);
  if (pr) net->pair = pr;
  double *fn = pr ? realloc(net->fn, cap * sizeof *fn) : NULL;
  if (!fn) return esf_fail(err, ESF_ENOMEM, "out of memory for the contact network");
  net->fn = fn;
  net->cap = cap;
  return ESF_OK;
}

/* The law's normal force of candidate k (touching: un > 0 given, or a bond). */
static double normal_force(const esf_sim *s, size_t k, const double d[3], double dist,
                           double un) {
  const esf_particles *p = &s->p;
  const esf_candidates *c = &s->nb.pp;
  uint32_t a = c->a[k], b = c->b[k];
  esf_contact_in in;
  if (dist > 0)
    v3_scale(in.n, 1.0 / dist, d);
  else
    v3_set(in.n, 0, 0, 1);
  in.un = un;
  double la = p->radius[a] - 0.5 * un, lb = p->radius[b] - 0.5 * un;
  double ra[3], rb[3], ta[3], tb[3];
  v3_scale(ra, la, in.n);
  v3_scale(rb, -lb, in.n);
  v3_cross(ta, p->w + 3 * a, ra);
  v3_cross(tb, p->w + 3 * b, rb);
  for (int q = 0; q < 3; q++)
    in.vc[q] = p->v[3 * b + q] + tb[q] - p->v[3 * a + q] - ta[q];
  in.spin_n = 0.5 * (v3_dot(p->w + 3 * a, in.n) + v3_dot(p->w + 3 * b, in.n));
  in.mstar = p->mass[a] * p->mass[b] / (p->mass[a] + p->mass[b]);
  in.rstar = p->radius[a] * p->radius[b] / (p->radius[a] + p->radius[b]);
  in.dt = s->dt;
  in.vinc = NULL;
  const esf_materials *mt = &s->mats;
  const esf_pair_params *pp = &mt->pair[p->material[a] * mt->n + p->material[b]];
  esf_contact_out out;
  pp->law->eval(pp, s->beta, s->cfg.tframe, &in, &c->h[k], esf_candidates_bond(c, k),
                !c->touch[k], NULL, &out);
  return out.touching ? out.fn : 0.0;
}

int esf_contact_net_build(const esf_sim *s, esf_contact_net *net, esf_error *err) {
  const esf_particles *p = &s->p;
  const esf_candidates *c = &s->nb.pp;
  net->n = 0;
  for (size_t k = 0; k < c->n; k++) {
    uint32_t a = c->a[k], b = c->b[k];
    if (a >= p->n || b >= p->n) continue; /* stale list entry: not a pair of this state */
    double d[3], xb[3];
    v3_sub(d, esf_candidates_xb(c, k, p->x, xb), p->x + 3 * a);
    double R = p->radius[a] + p->radius[b], d2 = v3_norm2(d);
    if (d2 >= R * R && !(c->touch[k] && esf_candidates_bonded(c, k)))
      continue; /* bonds in tension */
    int rc = reserve(net, net->n + 1, err);
    if (rc) return rc;
    double dist = sqrt(d2);
    net->pair[2 * net->n] = a;
    net->pair[2 * net->n + 1] = b;
    net->fn[net->n] = normal_force(s, k, d, dist, R - dist);
    net->n++;
  }
  return ESF_OK;
}

void esf_contact_net_release(esf_contact_net *net) {
  free(net->pair);
  free(net->fn);
  memset(net, 0, sizeof *net);
}
