/* contact_net.c — the contact network for output (contact_net.h).
 *
 * esf_forces_probe (model/forces.c) evaluates every candidate of the particle-pair and,
 * on request, the particle-wall lists at the current state in trial mode, with the
 * kinematics, laws, wall-hit selection and rolling resistance of the force evaluation
 * itself (history read, nothing written), and reports each touching contact: its
 * particles (or particle and wall group), contact point, force on the first particle,
 * its tangential part and torque. This file keeps them as arrays. With the leapfrog the
 * velocities are the half-step ones, as in the frames. With the wall contacts, moving
 * walls are first placed at the state's time s->t (esf_walls_set_time; each step does
 * so before its forces, with the same result): a wall turning by omega dt between the
 * last evaluation and the row moves by more than the overlaps of stiff contacts. Cost: one pass over the
 * candidate lists per call, only when an output asks. Entry: candidate lists valid for
 * the positions; exit: net holds the touching contacts; the sim's state is unchanged. */
#include "output/contact_net.h"

#include <stdlib.h>
#include <string.h>

#include "core/sim.h"
#include "model/forces.h"
#include "util/vec3.h"

static int reserve(esf_contact_set *c, size_t n) {
  if (n <= c->cap) return ESF_OK;
  size_t cap = c->cap ? 2 * c->cap : 256;
  while (cap < n) cap *= 2;
  int64_t *pr = realloc(c->pair, 2 * cap * sizeof *pr);
  if (!pr) return ESF_ENOMEM;
  c->pair = pr;
  double **arr[5] = {&c->fn, &c->ft, &c->f, &c->pc, &c->ta};
  for (int k = 0; k < 5; k++) {
    double *d = realloc(*arr[k], (k ? 3 : 1) * cap * sizeof *d);
    if (!d) return ESF_ENOMEM;
    *arr[k] = d;
  }
  c->cap = cap;
  return ESF_OK;
}

typedef struct collect {
  esf_contact_net *net;
  int rc;
} collect;

static void keep(void *ctx, const esf_probe_contact *o) {
  collect *cl = ctx;
  esf_contact_set *c = o->group < 0 ? &cl->net->pp : &cl->net->pw;
  if (cl->rc || (cl->rc = reserve(c, c->n + 1))) return;
  const size_t k = c->n++;
  c->pair[2 * k] = o->a;
  c->pair[2 * k + 1] = o->group < 0 ? (int64_t)o->b : o->group;
  c->fn[k] = o->fn;
  v3_copy(c->ft + 3 * k, o->ft);
  v3_copy(c->f + 3 * k, o->f);
  v3_copy(c->pc + 3 * k, o->pc);
  v3_copy(c->ta + 3 * k, o->ta);
}

int esf_contact_net_build(struct esf_sim *s, int walls, esf_contact_net *net,
                          esf_error *err) {
  net->pp.n = net->pw.n = 0;
  if (walls) /* moving walls at the state's time, where the next step puts them */
    esf_walls_set_time(&s->walls, s->t);
  collect cl = {net, ESF_OK};
  const esf_contact_probe pr = {keep, &cl};
  int rc = esf_forces_probe(s, 1, walls, &pr, err);
  if (!rc && cl.rc)
    rc = esf_fail(err, ESF_ENOMEM, "out of memory for the contact network");
  return rc;
}

void esf_contact_net_coordination(const esf_contact_net *net, size_t n, int32_t *z) {
  memset(z, 0, n * sizeof *z);
  for (size_t k = 0; k < 2 * net->pp.n; k++) z[net->pp.pair[k]]++;
  for (size_t k = 0; k < net->pw.n; k++) z[net->pw.pair[2 * k]]++;
}

static void set_release(esf_contact_set *c) {
  free(c->pair);
  free(c->fn);
  free(c->ft);
  free(c->f);
  free(c->pc);
  free(c->ta);
  memset(c, 0, sizeof *c);
}

void esf_contact_net_release(esf_contact_net *net) {
  set_release(&net->pp);
  set_release(&net->pw);
}
