/* events.c — scene events: deleting the particles in a region at a given time
 * (drilling; seed 004 §4.4, docs/physics.md#events-deleting-particles).
 *
 * An event with time `at` is applied at the start of the first step whose time t has
 * at <= t + dt/2 (the step nearest `at`), before the candidate lists are checked, from
 * esf_sim_refresh. Every particle whose centre lies in the region (an infinite
 * cylinder: distance from the axis <= radius; a box: min <= x <= max) is deleted with
 * esf_particles_compact, and the candidate lists are renumbered with
 * esf_neighbor_remap, as for particles leaving the domain (core/sim.c).
 * Ledger: energy_removed gains what the deleted particles carried: kinetic
 * (1/2 m v^2 + 1/2 I w^2, at the leapfrog's half-step velocity), gravitational
 * (-m g.x) and the elastic energy of their touching contacts (the pair law's normal
 * energy, bonds in tension included, + 1/2 kt |xi|^2 at the current positions), which
 * disappears from the stored elastic energy with them. The count is logged and kept per
 * event. Walls (docs/physics.md#walls-removed-and-added): removing a named wall marks
 * its group absent (the candidate search skips it) and its touching contacts' elastic
 * energy, at the current positions, goes to energy_removed as they end; adding one
 * back marks it present, refused when a particle overlaps it. Either rebuilds the
 * candidate lists at once (walls_changed, refresh.c). Units: SI. */
#include "loads/events.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "loads/servo.h"
#include "util/vec3.h"

int esf_region_contains(const esf_region *r, const double x[3]) {
  if (r->kind == ESF_REGION_BOX) {
    for (int k = 0; k < 3; k++)
      if (x[k] < r->min[k] || x[k] > r->max[k]) return 0;
    return 1;
  }
  double d[3];
  v3_sub(d, x, r->center);
  v3_axpy(d, -v3_dot(d, r->axis), r->axis);
  return v3_norm2(d) <= r->radius * r->radius;
}

int esf_events_setup(esf_sim *s, esf_error *err) {
  if (!s->events || s->events->n == 0) return ESF_OK;
  if (strcmp(s->cfg.method, "leapfrog") != 0)
    return esf_fail(err, ESF_EINPUT,
                    "%s: events (deleting particles, removing or adding walls) are "
                    "supported by the leapfrog only: the ODE methods cannot change the "
                    "particle count or the contact set within a run; use "
                    "integrator.method: leapfrog",
                    esf_config_where(&s->cfg, "integrator.method"));
  return ESF_OK;
}

/* elastic energy of the touching contacts that end: those of a deleted particle (keep
 * not NULL) and those with an element of wall group `group` (>= 0), J */
static double removed_elastic(const esf_sim *s, const unsigned char *keep, int group) {
  const esf_particles *p = &s->p;
  const esf_materials *mt = &s->mats;
  double e = esf_sim_chain_in(s, 0.0); /* MPI: the entries of this process's own A */
  const esf_candidates *c = &s->nb.pp;
  for (size_t k = 0; k < c->n && keep; k++) {
    uint32_t a = c->a[k], b = c->b[k];
    if (!c->touch[k] || (keep[a] && keep[b]) || !esf_sim_owns(s, a)) continue;
    double d[3], xb[3];
    v3_sub(d, esf_candidates_xb(c, k, p->x, xb), p->x + 3 * a);
    double un = p->radius[a] + p->radius[b] - v3_norm(d);
    const double rs = p->radius[a] * p->radius[b] / (p->radius[a] + p->radius[b]);
    const esf_pair_params *pp = &mt->pair[p->material[a] * mt->n + p->material[b]];
    double fel; /* a separated pair stores no normal energy unless a bond holds it */
    if (un > 0 || esf_candidates_bonded(c, k))
      e += pp->law->energy_n(pp, esf_candidates_bond(c, k), un, rs, &fel);
    e += esf_contact_energy_t(pp, c->h[k].xi, un, rs);
  }
  e = esf_sim_chain_out(s, e);
  e = esf_sim_chain_in(s, e); /* the wall entries continue the same sum */
  c = &s->nb.pw;
  for (size_t k = 0; k < c->n; k++) {
    uint32_t a = c->a[k];
    const esf_wall_elem *el = &s->walls.e[c->b[k]];
    if (!c->touch[k] || ((!keep || keep[a]) && el->group != group) || !esf_sim_owns(s, a))
      continue;
    esf_wall_hit hit;
    esf_wall_nearest(el, p->x + 3 * a, &hit);
    double un = p->radius[a] - hit.dist;
    const esf_pair_params *pp = &mt->pair[p->material[a] * mt->n + el->material];
    double fel; /* walls never bond */
    if (un > 0) e += pp->law->energy_n(pp, NULL, un, p->radius[a], &fel);
    e += esf_contact_energy_t(pp, c->h[k].xi, un, p->radius[a]);
  }
  return esf_sim_chain_out(s, e);
}

static int apply_one(esf_sim *s, esf_event *ev, esf_error *err) {
  esf_particles *p = &s->p;
  size_t n_old = p->n, out = 0;
  unsigned char *keep = malloc(n_old ? n_old : 1);
  size_t *remap = malloc((n_old ? n_old : 1) * sizeof *remap);
  if (!keep || !remap) {
    free(keep);
    free(remap);
    return esf_fail(err, ESF_ENOMEM, "out of memory");
  }
  double e_gone = esf_sim_chain_in(s, 0.0); /* MPI: each process's own particles */
  size_t own_left = 0;
  for (size_t i = 0; i < n_old; i++) {
    const double *x = p->x + 3 * i;
    keep[i] = !esf_region_contains(&ev->region, x);
    own_left += keep[i] && esf_sim_owns(s, i);
    if (keep[i] || !esf_sim_owns(s, i)) continue;
    out++;
    const double *v = p->v + 3 * i, *w = p->w + 3 * i;
    e_gone += 0.5 * p->mass[i] * v3_norm2(v) + 0.5 * p->inertia[i] * v3_norm2(w) -
              p->mass[i] * v3_dot(s->cfg.gravity, x);
  }
  e_gone = esf_sim_chain_out(s, e_gone);
  out = (size_t)esf_sim_sum(s, (long long)out); /* over every process */
  int rc = ESF_OK;
  if (out) {
    if (s->led.started) /* before the balance starts, e0 leaves them out too (the */
      s->led.e_removed +=
          e_gone + removed_elastic(s, keep, -1); /* same on every process) */
    rc = esf_sim_forces_sync(s, err);            /* compaction carries p.f, p.t along */
    if (rc) return rc;
    if (s->red) s->red->compact(s, keep);
    rc = esf_particles_compact(p, keep, remap, err);
    if (!rc) esf_neighbor_remap(&s->nb, remap, n_old);
  }
  free(keep);
  free(remap);
  if (rc) return rc;
  ev->done = 1;
  ev->deleted = (long)out;
  s->removed += (long)out;
  ev->t_done = s->t;
  esf_sim_log(s,
              "t = %.6g s (step %ld): event at %.6g s deleted %zu particles inside the "
              "%s; %zu remain",
              s->t, s->step, ev->at, out,
              ev->region.kind == ESF_REGION_BOX ? "box" : "cylinder",
              (size_t)esf_sim_sum(s, (long long)own_left));
  if (s->walls.gforce) esf_servo_log_state(s);
  return ESF_OK;
}

/* a particle overlapping wall group g's elements at the current placement: its index,
 * or SIZE_MAX; *un its overlap */
static size_t overlapping(const esf_sim *s, int g, double *un) {
  const esf_particles *p = &s->p;
  for (size_t e = 0; e < s->walls.n; e++) {
    if (s->walls.e[e].group != g) continue;
    for (size_t i = 0; i < p->n; i++) {
      esf_wall_hit hit;
      esf_wall_nearest(&s->walls.e[e], p->x + 3 * i, &hit);
      if (hit.dist < p->radius[i]) {
        *un = p->radius[i] - hit.dist;
        return i;
      }
    }
  }
  return SIZE_MAX;
}

/* remove_wall, add_wall */
static int apply_wall(esf_sim *s, esf_event *ev, esf_error *err) {
  esf_wall_group *g = &s->walls.g[ev->group];
  const int add = ev->kind == ESF_EVENT_ADD_WALL;
  double e_el = 0, un = 0;
  if (add) {
    const size_t i = overlapping(s, ev->group, &un);
    if (i != SIZE_MAX)
      return esf_fail(err, ESF_ENUMERIC,
                      "t = %.6g s (step %ld): the event at %.6g s adds wall '%s' where "
                      "particle %lld overlaps it by %.4g m; add it where no particle "
                      "touches it",
                      s->t, s->step, ev->at, g->label, (long long)s->p.id[i], un);
  } else {
    e_el = removed_elastic(s, NULL, ev->group);
    if (s->led.started) s->led.e_removed += e_el;
  }
  g->absent = !add;
  s->events->walls_changed = 1;
  ev->done = 1;
  ev->t_done = s->t;
  esf_sim_log(s,
              "t = %.6g s (step %ld): event at %.6g s %s wall '%s'%s (elastic energy "
              "%.6g J released)",
              s->t, s->step, ev->at, add ? "added" : "removed", g->label,
              add ? "" : " and ended its contacts", e_el);
  return ESF_OK;
}

int esf_event_before(const esf_events *E, int b, int a) {
  return E->e[b].at < E->e[a].at || (E->e[b].at == E->e[a].at && b < a);
}

void esf_events_wall_state(esf_sim *s) {
  const esf_events *E = s->events;
  for (int k = 0; E && k < E->n; k++) {
    const esf_event *ev = &E->e[k];
    if (ev->kind == ESF_EVENT_DELETE) continue;
    int first = 1, latest_done = 1; /* k is the group's first, its latest applied */
    for (int j = 0; j < E->n; j++) {
      if (j == k || E->e[j].kind == ESF_EVENT_DELETE || E->e[j].group != ev->group)
        continue;
      if (esf_event_before(E, j, k)) first = 0;
      if (E->e[j].done && esf_event_before(E, k, j)) latest_done = 0;
    }
    if (ev->done && latest_done)
      s->walls.g[ev->group].absent = ev->kind == ESF_EVENT_REMOVE_WALL;
    else if (first && !ev->done)
      s->walls.g[ev->group].absent = ev->kind == ESF_EVENT_ADD_WALL;
  }
}

int esf_events_apply(esf_sim *s, esf_error *err) {
  esf_events *E = s->events;
  for (;;) { /* the due events in time order (ties: list order) */
    int k = -1;
    for (int j = 0; j < E->n; j++)
      if (!E->e[j].done && E->e[j].at <= s->t + 0.5 * s->dt &&
          (k < 0 || esf_event_before(E, j, k)))
        k = j;
    if (k < 0) break;
    esf_event *ev = &E->e[k];
    int rc =
        ev->kind == ESF_EVENT_DELETE ? apply_one(s, ev, err) : apply_wall(s, ev, err);
    if (rc) return rc;
  }
  return ESF_OK;
}

int esf_events_pending(const esf_events *E) {
  for (int k = 0; E && k < E->n; k++)
    if (!E->e[k].done) return 1;
  return 0;
}

void esf_events_free(esf_events **ev) {
  if (!*ev) return;
  free((*ev)->e);
  free(*ev);
  *ev = NULL;
}
