/* wall_fast.c — the particle-wall contacts of one particle, static or moving walls, the
 * linear or the Hertz-Mindlin law (wall_fast.h): the fused step's wall pass.
 *
 * Physics: exactly model/forces.c's wall contacts (docs/physics.md#contact-kinematics,
 * #linear-springdashpot-law; 004 §2.3.2, eqs. 2.4–2.5 for the nearest point; 000
 * 3-15..3-26 and 004 2.16–2.29 for the law), with the same operations in the same
 * order, so the results are the same bits:
 *   1. per candidate element, the nearest point and the overlap un = r - dist
 *      (wall_overlap);
 *   2. which hits carry force: with at most one overlapping candidate, that one; with
 *      more, esf_forces_select_wall_hits itself (faces first, shared points once);
 *   3. per kept hit, in candidate order: the overlap limit, then the law (wall_contact;
 *      a moving wall's velocity at the contact point and spin as forces.c's).
 * The only arithmetic forces.c does not do: a polygon out of reach costs one dot
 * product (wall_overlap). Up to FAST_MAX candidates per particle the hits live on the
 * stack; more use the neighbour lists' wall scratch at k0 (as forces.c), so particles
 * run in parallel.
 * Entry: lists valid for s->p.x; all pairs linear or all Hertz-Mindlin, no tally, servo
 * walls or ODE-state history (esf_wall_pass_select, _eval check). SI. Exit: as
 * esf_forces_wall_particle committing; with the ODE methods' carry, also a trial. */
#include "fused/wall_fast.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#include "bodies/walls.h"
#include "contact/contact_hertz.h"
#include "contact/contact_linear.h"
#include "model/forces.h"
#include "util/vec3.h"
#include "util/vec4.h"

#define FAST_MAX 8 /* candidates per particle whose hits go on the stack */

_Static_assert(offsetof(esf_wall_hit, dist) ==
                   offsetof(esf_wall_hit, n) + 3 * sizeof(double),
               "a hit's n and dist contiguous");

/* hit->n = s e_n (v3_scale's operations) and hit->dist = dist, in one 32-byte store:
 * wall_contact's loads of n then come whole from the store buffer (three 8-byte stores
 * read back by 16-byte loads cannot be forwarded and wait for the stores to retire). */
static inline void put_n_dist(esf_wall_hit *hit, double s, const double *en,
                              double dist) {
  const esf_v4 r = {s * en[0], s * en[1], s * en[2], dist};
  v4_st(hit->n, r);
}

static const double zero3[3] = {0.0, 0.0, 0.0}; /* a static wall's omega, rad/s */

/* Candidate e for centre x, radius r: the overlap r - dist of
 * esf_wall_nearest, and *hit when it is > 0. Returns 0 for a polygon out of reach.
 * The signed height over the element's plane, once (esf_wall_height); a plane by it; a
 * polygon by its face test given it (esf_wall_polygon_foot; both wall_geom.h, shared
 * with esf_wall_nearest); a centre whose foot falls outside goes to esf_wall_nearest
 * for the edge or vertex. Shortcut (the only arithmetic forces.c does not do): a
 * polygon whose plane is farther than r, by a slack that covers rounding, from the
 * centre is not touched and costs one dot product (esf_wall_out_of_reach, wall_geom.h:
 * esf_wall_nearest's overlap is <= 0 there too). */
static inline double wall_overlap(const esf_wall_elem *e, const double *x, double r,
                                  esf_wall_hit *hit) {
  const double h0 = esf_wall_height(e, x); /* signed height of x over the plane */
  if (e->kind == ESF_WALL_PLANE) {
    const double un = r - h0;
    if (un > 0) {
      v3_copy(hit->q, x);
      v3_axpy(hit->q, -h0, e->n);
      put_n_dist(hit, -1, e->n, h0);
      hit->feature = ESF_FEATURE_FACE;
    }
    return un;
  }
  if (esf_wall_out_of_reach(e, x, h0, r)) return 0.0; /* (the shortcut) */
  double foot[3];
  if (esf_wall_polygon_foot(e, x, h0, foot)) { /* as esf_wall_nearest */
    const double dist = fabs(h0), un = r - dist;
    if (un > 0) {
      v3_copy(hit->q, foot);
      put_n_dist(hit, h0 < 0 ? 1 : -1, e->n, dist);
      hit->feature = ESF_FEATURE_FACE;
    }
    return un;
  }
  esf_wall_nearest(e, x, hit); /* an edge or a vertex (rare) */
  return r - hit->dist;
}

/* The contact of particle a with kept hit `hit` on element el, candidate k: the law
 * (esf_contact_linear_eval, contact_linear.h, inline: no strategy-table call) with the
 * contact velocity vc = v_wall - [vA + wA x (lA n)], lA = esf_wall_lever's, where a
 * static wall's point velocity is +0 exactly as esf_wall_point_velocity computes it for a
 * group with zero vel and omega, and the spin (wA.n + 0.n)/2; f += force, t += lA n x ft.
 */
static inline __attribute__((always_inline)) void
wall_contact(esf_sim *s, const esf_wall_elem *el, const esf_wall_hit *hit, double un,
             size_t a, size_t k, double dt, size_t *nt, double *f, double *t,
             double *rows, unsigned set, int ode, int trial, const int moving) {
  const esf_particles *p = &s->p;
  esf_candidates *c = &s->nb.pw;
  const double *v = p->v + 3 * a, *w = p->w + 3 * a;
  esf_contact_in in;
  v3_copy(in.n, hit->n);
  in.un = un;
  const double la = esf_wall_lever(s->cfg.wall_lever, p->radius[a], un, hit->dist);
  double ra[3], ta[3], vw[3] = {0.0, 0.0, 0.0};
  const double *om = zero3;
  if (moving) { /* forces.c's: the group's velocity at the contact point */
    const esf_wall_group *g = &s->walls.g[el->group];
    double pc[3];
    esf_wall_contact_point(s->cfg.wall_lever, p->x + 3 * a, la, in.n, hit->q, pc);
    esf_wall_point_velocity(g, pc, vw);
    om = g->omega;
  }
  v3_scale(ra, la, in.n);
  v3_cross(ta, w, ra);
  for (int q = 0; q < 3; q++)
    in.vc[q] = (vw[q] + 0.0) - v[q] - ta[q]; /* v_wall + 0 - ... */
  in.spin_n = 0.5 * (v3_dot(w, in.n) + v3_dot(om, in.n));
  in.mstar = p->mass[a];
  in.rstar = p->radius[a];
  in.dt = dt;
  in.vinc = NULL;
  double vm[3];
  if (ode && c->vc0 && c->touch[k]) { /* as forces.c: the trapezoidal history increment */
    for (int q = 0; q < 3; q++) vm[q] = 0.5 * (c->vc0[3 * k + q] + in.vc[q]);
    in.vinc = vm;
  }
  esf_contact_hist *const ho = trial ? NULL : &c->h[k]; /* a trial commits nothing */
  const esf_materials *mt = &s->mats;
  const esf_pair_params *pp = /* one material: no load of the particle's */
      mt->n == 1 ? mt->pair : &mt->pair[p->material[a] * mt->n + el->material];
  esf_contact_out out;
  if (s->mats.all_hertz) /* the laws never mix (material.c) */
    esf_contact_hertz_eval(pp, s->beta, s->cfg.tframe, &in, &c->h[k], !c->touch[k], ho,
                           &out);
  else
    esf_contact_linear_eval(pp, s->beta, s->cfg.tframe, &in, &c->h[k], !c->touch[k], ho,
                            &out);
  if (ode && !trial && c->vc0 && out.touching) v3_copy(c->vc0 + 3 * k, in.vc);
  if (!trial) c->touch[k] = (uint8_t)out.touching;
  if (!out.touching) return;
  (*nt)++;
  v3_add(f, f, out.f);
  double m[3];
  v3_cross(m, in.n, out.ft);
  v3_axpy(t, la, m);
  if (rows) { /* the ledger, as forces.c's (a static wall: its point velocity +0) */
    double ket[3];
    esf_contact_ket(pp, c->h[k].xi, ket);
    esf_ledger_wall_rows_set(rows, in.n, la, out.fd_n, out.fel, out.fd_t, ket,
                             out.slip_work, out.e_el_n, out.e_el_t, out.f, vw, dt, set);
    if (pp->ht > 0) rows[ESF_LR_STIFF] += out.w_st;
  }
}

static inline __attribute__((always_inline)) int
fast_particle(esf_sim *s, size_t k0, size_t k1, double dt, size_t *nt, double *f,
              double *t, double *rows, unsigned set, int ode, int trial,
              const int moving) {
  const esf_particles *p = &s->p;
  esf_candidates *c = &s->nb.pw;
  const esf_wall_elem *E = s->walls.e;
  const size_t m = k1 - k0, a = c->a[k0];
  const double *x = p->x + 3 * a, r = p->radius[a];
  esf_wall_hit hb[FAST_MAX];
  double ub[FAST_MAX];
  unsigned char kb[FAST_MAX];
  esf_wall_hit *hits = hb;
  double *un = ub;
  unsigned char *keep = kb;
  if (m > FAST_MAX) { /* many candidates (meshes): the lists' scratch, as forces.c */
    hits = s->nb.wall_hits + k0;
    un = s->nb.wall_un + k0;
    keep = s->nb.wall_keep + k0;
  }
  size_t touching = 0, last = 0;
  for (size_t j = 0; j < m; j++) {
    un[j] = wall_overlap(&E[c->b[k0 + j]], x, r, &hits[j]);
    if (un[j] > 0) touching++, last = j;
  }
  if (touching == 0) {
    if (!trial)
      for (size_t k = k0; k < k1; k++) c->touch[k] = 0;
    return 0;
  }
  if (touching == 1)
    for (size_t j = 0; j < m; j++) keep[j] = j == last;
  else
    esf_forces_select_wall_hits(&s->walls, c->b + k0, hits, un, m, r, keep);
  const double lim = s->cfg.max_overlap * r;
  for (size_t j = 0; j < m; j++) {
    const size_t k = k0 + j;
    if (!keep[j]) {
      if (!trial) c->touch[k] = 0;
      continue;
    }
    if (un[j] > lim) return 1; /* esf_forces_wall_particle words the failure */
    wall_contact(s, &E[c->b[k]], &hits[j], un[j], a, k, dt, nt, f, t, rows, set, ode,
                 trial, moving);
  }
  return 0;
}

int esf_wall_fast_particle(esf_sim *s, size_t k0, size_t k1, double dt, size_t *nt,
                           double *f, double *t, double *rows) {
  return fast_particle(s, k0, k1, dt, nt, f, t, rows, 0, 0, 0, 0);
}

int esf_wall_fast_particle_moving(esf_sim *s, size_t k0, size_t k1, double dt, size_t *nt,
                                  double *f, double *t, double *rows) {
  return fast_particle(s, k0, k1, dt, nt, f, t, rows, 0, 0, 0, 1);
}

int esf_wall_fast_particle_light(esf_sim *s, size_t k0, size_t k1, double dt, size_t *nt,
                                 double *f, double *t, double *rows) {
  return fast_particle(s, k0, k1, dt, nt, f, t, rows, ESF_LEDGER_LIGHT | ESF_LEDGER_NO_W,
                       0, 0, 0);
}

int esf_wall_fast_particle_light_n(esf_sim *s, size_t k0, size_t k1, double dt,
                                   size_t *nt, double *f, double *t, double *rows) {
  return fast_particle(s, k0, k1, dt, nt, f, t, rows,
                       ESF_LEDGER_LIGHT | ESF_LEDGER_NO_T | ESF_LEDGER_NO_W, 0, 0, 0);
}

int esf_wall_general_particle(esf_sim *s, size_t k0, size_t k1, double dt, size_t *nt,
                              double *f, double *t, double *rows) {
  const esf_particles *p = &s->p;
  return esf_forces_wall_particle(s, k0, k1, p->x, p->v, p->w, dt, ESF_FORCES_COMMIT,
                                  rows, NULL, nt, f, t, NULL);
}

/* esf_forces_wall_particle without committing (an ODE method's stage). */
static int wall_trial_particle(esf_sim *s, size_t k0, size_t k1, double dt, size_t *nt,
                               double *f, double *t, double *rows) {
  const esf_particles *p = &s->p;
  return esf_forces_wall_particle(s, k0, k1, p->x, p->v, p->w, dt, ESF_FORCES_TRIAL, rows,
                                  NULL, nt, f, t, NULL);
}

/* The fast pass for the ODE methods (forces.c's carry: with the lists' vc0, a live
 * contact's history increments with the mean of the committed and the current contact
 * velocity, and a commit stores the current one): committing, and as a trial (no
 * history, touch flag or carry written). */
static int wall_fast_ode_commit(esf_sim *s, size_t k0, size_t k1, double dt, size_t *nt,
                                double *f, double *t, double *rows) {
  return fast_particle(s, k0, k1, dt, nt, f, t, rows, 0, 1, 0, 0);
}

static int wall_fast_ode_trial(esf_sim *s, size_t k0, size_t k1, double dt, size_t *nt,
                               double *f, double *t, double *rows) {
  return fast_particle(s, k0, k1, dt, nt, f, t, rows, 0, 1, 1, 0);
}

/* The fast pass's conditions but the carry and the walls' motion (all pairs: wall
 * materials may pair by a law the particles' pairs do not use). */
static int fast_ok(const esf_sim *s) {
  return (s->mats.all_linear || s->mats.all_hertz) && !s->mats.any_rolling && !s->tally &&
         !s->walls.gforce && !s->nb.pw.xs;
}

esf_wall_pass_fn esf_wall_pass_eval(const esf_sim *s, int trial) {
  if (!fast_ok(s) || (s->walls.moving && (trial || s->nb.pw.vc0)))
    return trial ? wall_trial_particle : esf_wall_general_particle;
  if (trial) return wall_fast_ode_trial;
  if (s->nb.pw.vc0) return wall_fast_ode_commit;
  return s->walls.moving ? esf_wall_fast_particle_moving : esf_wall_fast_particle;
}

esf_wall_pass_fn esf_wall_pass_select(const esf_sim *s) {
  if (!fast_ok(s) || s->nb.pw.vc0) return esf_wall_general_particle;
  return s->walls.moving ? esf_wall_fast_particle_moving : esf_wall_fast_particle;
}
