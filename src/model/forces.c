/* forces.c — evaluation of the DEM forces (docs/physics.md#contact-kinematics,
 * #linear-springdashpot-law, #adhesive-normal-law-and-bonds).
 *
 * For every candidate pair (A, B) with overlap un = rA + rB - d > 0 (000 3-15):
 *   n = (xB - xA)/d; contact point xc = xA + (rA - un/2) n (000 3-16); lever arms
 *   lA = rA - un/2 and lB = rB - un/2 measured to xc, so that the tangential forces
 *   are equal, opposite and act at one point (angular momentum is conserved exactly;
 *   004 2.33–2.34 use the radii, which differ by un/2);
 *   vc = [vB + wB x (-lB n)] - [vA + wA x (lA n)] (000 3-21);
 *   the contact law gives the force on A; B gets the opposite (004 2.31);
 *   torques M_A = lA n x Ft, M_B = lB n x Ft (same sense, 004 2.34).
 * For a wall element: q its nearest point (wall_geom.h), un = rA - |q - xA|, n toward
 * q, lever lA = rA - un/2 to the contact point xc = xA + lA n as for pairs (000 3-16;
 * contact.wall_lever: surface takes lA = |q - xA|, xc = q),
 * vc = v_wall(xc) - [vA + wA x (lA n)], m* = mA. Hits of
 * one particle on edges and vertices shared by wall elements count once
 * (esf_forces_select_wall_hits, also used by the fast wall pass of wall_fast.c).
 * Rolling and twisting resistance (contact_rolling.h; scenes with some mu_r or mu_tw
 * only): torque M on A, -M on B, from the relative spin wA - wB (a wall: its angular
 * velocity), R* = rA rB/(rA + rB) (a wall: rA).
 * Gravity: f += m g. In 2D only x, z forces and the y torque act.
 * Entry: candidate lists valid for x; on exit f, t hold the totals. */
#include "model/forces.h"

#include <math.h>
#include <string.h>

#include "loads/drag.h"
#include "contact/contact_rolling.h"
#include "contact/lane_scalar.h"
#include "loads/servo.h"
#include "util/vec3.h"

int esf_forces_overlap_failure(const esf_sim *s, long long ida, long long idb, int wall,
                               double un, double rmin, esf_error *err) {
  const char *rule = esf_dt_rule_names[s->cfg.dt_rule];
  if (wall)
    return esf_fail(err, ESF_ENUMERIC,
                    "step %ld (t = %.6g s): particle id %lld overlaps wall element %lld "
                    "by %.3g m, %.0f%% of its radius (limit %.0f%%); dt = %.4g s, "
                    "critical dt (%s) = %.4g s. The wall pushes faster than contacts "
                    "can respond, or dt is too large: lower integrator.frac or dt, or "
                    "raise kn (youngs_modulus for the Hertz-Mindlin law)",
                    s->step, s->t, ida, idb, un, 100.0 * un / rmin,
                    100.0 * s->cfg.max_overlap, s->dt, rule, s->dte.crit[s->cfg.dt_rule]);
  return esf_fail(err, ESF_ENUMERIC,
                  "step %ld (t = %.6g s): particles id %lld and id %lld overlap by %.3g "
                  "m, %.0f%% of the smaller radius (limit %.0f%%); dt = %.4g s, "
                  "critical dt (%s) = %.4g s. The step is too large for the stiffness "
                  "(lower integrator.frac or dt) or the contacts are too soft for the "
                  "loads (raise kn, or youngs_modulus for the Hertz-Mindlin law)",
                  s->step, s->t, ida, idb, un, 100.0 * un / rmin,
                  100.0 * s->cfg.max_overlap, s->dt, rule, s->dte.crit[s->cfg.dt_rule]);
}

/* Relative velocity of the contact point (B minus A) for velocities v, w. */
static inline void contact_velocity(const double *v, const double *w, uint32_t a,
                                    const double *vb, const double *wb_or_null, double la,
                                    double lb, const double *n, double vc[3]) {
  double ra[3], ta[3], tb[3] = {0, 0, 0};
  v3_scale(ra, la, n);
  v3_cross(ta, w + 3 * a, ra);
  if (wb_or_null) {
    double rb[3];
    v3_scale(rb, -lb, n);
    v3_cross(tb, wb_or_null, rb);
  }
  for (int q = 0; q < 3; q++) vc[q] = vb[q] + tb[q] - v[3 * a + q] - ta[q];
}

/* Evaluates the law for candidate k of list c and updates its touching flag and
 * history (commit). A bond's rupture energy goes to the ledger rows of its first
 * particle ra (the leapfrog's ledger, ledger.h) or, without rows, to the ledger
 * directly. Returns 1 when the contact carries force. */
static int eval_contact(esf_sim *s, const esf_pair_params *pp, esf_contact_in *in,
                        esf_candidates *c, size_t k, int commit, double *ra,
                        esf_contact_out *out) {
  const esf_contact_bond *bond = esf_candidates_bond(c, k);
  if (c->xs) { /* history as ODE state: xi is y's, its rate goes to ydot */
    esf_contact_hist h;
    v3_copy(h.xi, c->xs + 3 * k);
    v3_copy(h.n, c->touch[k] ? c->h[k].n : in->n);
    in->dt = 0.0; /* the law tilts xi into the current plane; no increment */
    in->vinc = NULL;
    pp->law->eval(pp, s->beta, s->cfg.tframe, in, &h, bond, 0, commit ? &c->h[k] : NULL,
                  out);
    if (c->xsdot && out->touching) { /* xi' = vct + spin_n n x xi (Hertz: S_t vct) */
      double *r = c->xsdot + 3 * k, sp[3], fs[3];
      v3_copy(r, in->vc);
      v3_axpy(r, -v3_dot(in->vc, in->n), in->n);
      if (s->tally) { /* power into the tangential spring as applied (capped) */
        v3_sub(fs, out->ft, out->fd_t);
        s->tally->p_spring_t += v3_dot(fs, r);
      }
      if (pp->ht > 0) v3_scale(r, esf_law_hertz_st_s(pp->ht, in->rstar, in->un), r);
      v3_cross(sp, in->n, h.xi);
      v3_axpy(r, in->spin_n, sp);
    }
  } else {
    double vm[3];
    in->vinc = NULL;
    if (c->vc0 && c->touch[k]) { /* ODE methods: trapezoidal history increment */
      for (int q = 0; q < 3; q++) vm[q] = 0.5 * (c->vc0[3 * k + q] + in->vc[q]);
      in->vinc = vm;
    }
    pp->law->eval(pp, s->beta, s->cfg.tframe, in, &c->h[k], bond, !c->touch[k],
                  commit ? &c->h[k] : NULL, out);
  }
  if (commit && c->vc0 && out->touching)
    memcpy(c->vc0 + 3 * k, in->vc, 3 * sizeof(double));
  if (commit) c->touch[k] = (uint8_t)out->touching;
  if (commit && out->broke) { /* a bond ruptured (contact_adhesive.c): Phi = 0 */
    c->bond[k] = (esf_contact_bond){0}; /* for good: as a contact that never bonded */
    s->bonds.broken++;
    if (ra)
      ra[ESF_LR_BOND] += out->e_break;
    else
      s->led.d_bonds += out->e_break;
  }
  if (!out->touching) return 0;
  esf_force_tally *ty = s->tally;
  if (ty) {
    ty->p_normal -= out->fd_n * v3_dot(in->vc, in->n);
    ty->p_tangential += v3_dot(out->fd_t, in->vc);
    ty->e_el_n += out->e_el_n;
    ty->e_el_t += out->e_el_t;
    ty->slip += out->slip_work;
    if (pp->ht > 0 && c->xs) { /* history as ODE state: the rate of |F|^2/(2 S_t) at
                                  fixed F, |F|^2 vn / (4 S_t u); the other schemes book
                                  the law's w_st at their commits */
      double fs[3];
      v3_sub(fs, out->ft, out->fd_t);
      const double st = esf_law_hertz_st_s(pp->ht, in->rstar, in->un);
      ty->p_stiff += v3_norm2(fs) * v3_dot(in->vc, in->n) / (4.0 * st * in->un);
    }
  }
  return 1;
}

/* The rolling resistance of touching candidate k of c (contact_rolling.h), live: it
 * was touching at the last commit. Adds its torque to ta (A) and the opposite to tb
 * (B; NULL for a wall), commits its state, and adds to the leapfrog's ledger rows ra, rb
 * (or NULL; a wall: rb NULL and om its angular velocity), or to the other schemes'
 * tally (s->tally: the dissipative torque's power -md.wrel, the springs' energy, a
 * rotating wall's work rate M.om) and, committing, their ledger's plastic work. ta and tb
 * are the contact's own torques (lever arm times n x ft), so that the particles receive
 * lA n x ft + M in one addition as from the fused step's batches. rstar and the
 * overlap un give a Hertz pair's kn (esf_contact_rolling_kn); stiff (a Hertz pair,
 * committing with the ledger): returns the springs' stiffness-change energy w_k from
 * S_n at u0, the last commit's overlap (as the Hertz law's st0), else 0. */
static double rolling(esf_sim *s, const esf_pair_params *pp, esf_candidates *c, size_t k,
                      int commit, int live, int stiff, const double n[3],
                      const double wrel[3], double rstar, double un, double u0, double ir,
                      double itw, double fn, double dt, double *ta, double *tb,
                      double *ra, double *rb, const double *om) {
  esf_law_rout_s o;
  double wm[3], *wi = NULL;
  if (c->wr0 && live) { /* ODE methods: trapezoidal increment since the commit */
    for (int q = 0; q < 3; q++) wm[q] = 0.5 * (c->wr0[3 * k + q] + wrel[q]);
    wi = wm;
  }
  const double kn0 = stiff ? esf_law_hertz_sn_s(pp->hn, rstar, u0) : 0.0;
  esf_contact_rolling(pp, s->mats.rolling_model, esf_contact_rolling_kn(pp, rstar, un),
                      stiff, kn0, rstar, ir, itw, fn, dt, n, wrel, wi, &c->roll[k], live,
                      &o);
  if (commit) {
    v3_copy(c->roll[k].m, o.hm);
    c->roll[k].t = o.ht;
    if (c->wr0) v3_copy(c->wr0 + 3 * k, wrel);
  }
  for (int q = 0; q < 3; q++) {
    const double m = o.md[q] + o.ms[q];
    ta[q] += m;
    if (tb) tb[q] -= m;
  }
  if (ra) esf_ledger_roll_rows(ra, rb, o.md, o.ms, o.slip, o.e_el, om, dt);
  esf_force_tally *ty = s->tally;
  if (ty) {
    ty->p_rolling -= v3_dot(o.md, wrel);
    ty->e_el_r += o.e_el;
    ty->slip_r += o.slip;
    if (om)
      for (int q = 0; q < 3; q++) ty->p_walls += (o.md[q] + o.ms[q]) * om[q];
  }
  return stiff ? o.w_k : 0.0;
}

/* The tangential spring's force of a committed contact, on A (esf_contact_ket). */
static void spring_t(const esf_pair_params *pp, const esf_contact_hist *h,
                     double ket[3]) {
  esf_contact_ket(pp, h->xi, ket);
}

static int pair_forces(esf_sim *s, const double *x, const double *v, const double *w,
                       double dt, int commit, size_t *touching,
                       const esf_contact_probe *probe, esf_error *err) {
  esf_particles *p = &s->p;
  esf_candidates *c = &s->nb.pp;
  const esf_materials *mt = &s->mats;
  double *rows = commit && s->led.on ? s->led_rows : NULL; /* the leapfrog's (ledger.h) */
  const int slips = commit && s->led.on && !rows;          /* the other schemes' ledger */
  double slip = 0, wst = 0;
  size_t nt = 0;
  esf_neighbor_le_time(&s->nb, s->t); /* Lees-Edwards: the images' offset now */
  for (size_t k = 0; k < c->n; k++) {
    uint32_t a = c->a[k], b = c->b[k];
    if (probe && (a >= p->n || b >= p->n)) continue; /* stale entries (output) */
    const double ra = p->radius[a], rb = p->radius[b];
    double d[3], d2, xi[3];
    if (!esf_law_pair_overlap_s(x + 3 * a, esf_candidates_xb(c, k, x, xi), ra, rb, d,
                                &d2) &&
        !(c->touch[k] && esf_candidates_bonded(c, k))) { /* bonds pull */
      if (commit) c->touch[k] = 0;
      continue;
    }
    esf_contact_in in;
    double la, lb;
    const double *wa = w + 3 * a, *wb = w + 3 * b;
    double vi[3]; /* B's velocity, or its Lees-Edwards image's */
    esf_law_pair_kinematics_s(d, d2, ra, rb, v + 3 * a, esf_candidates_vb(c, k, v, vi),
                              wa, wb, in.n, &in.un, &la, &lb, in.vc);
    double rmin = fmin(ra, rb);
    if (in.un > s->cfg.max_overlap * rmin)
      return esf_forces_overlap_failure(s, (long long)p->id[a], (long long)p->id[b], 0,
                                        in.un, rmin, err);
    in.spin_n = 0.5 * (v3_dot(wa, in.n) + v3_dot(wb, in.n));
    in.mstar = p->mass[a] * p->mass[b] / (p->mass[a] + p->mass[b]);
    in.rstar = ra * rb / (ra + rb);
    in.dt = dt;
    const esf_pair_params *pp = &mt->pair[p->material[a] * mt->n + p->material[b]];
    esf_contact_out out;
    double *rows_a = rows ? rows + s->led_lr * a : NULL;
    const int live = c->touch[k]; /* before the commit (rolling) */
    if (!eval_contact(s, pp, &in, c, k, commit, rows_a, &out)) continue;
    nt++;
    double m[3], ma[3], mb[3];
    v3_cross(m, in.n, out.ft);
    v3_scale(ma, la, m);
    v3_scale(mb, lb, m);
    if (rows_a) {
      double ket[3];
      spring_t(pp, &c->h[k], ket);
      esf_ledger_pair_rows(rows_a, rows + s->led_lr * b, in.n, la, lb, out.fd_n, out.fel,
                           out.fd_t, ket, out.slip_work, out.e_el_n, out.e_el_t);
    }
    /* the stiffness changes' energy: the tangential spring's (Hertz), with the
       rolling springs' added first when they follow S_n (as the fused batches) */
    double w_st = out.w_st;
    if (c->roll) {
      const int stiff = pp->hn > 0 && commit && s->led.on;
      double wrel[3], rs, ir, itw;
      v3_sub(wrel, wa, wb);
      esf_law_rolling_pair_s(ra, rb, p->mass[a], p->mass[b], p->inertia[a], p->inertia[b],
                             &rs, &ir, &itw);
      const double u0 = in.un + dt * v3_dot(in.vc, in.n);
      const double wk =
          rolling(s, pp, c, k, commit, live, stiff, in.n, wrel, rs, in.un, u0, ir, itw,
                  out.fn, dt, ma, mb, rows_a, rows_a ? rows + s->led_lr * b : NULL, NULL);
      if (stiff) w_st = out.w_st + wk;
    }
    if (rows_a && pp->ht > 0) rows_a[ESF_LR_STIFF] += w_st;
    if (probe) { /* output (esf_forces_probe): reported, not added */
      esf_probe_contact pc = {a, b, -1, {0}, out.f, out.ft, {0}, out.fn};
      for (int q = 0; q < 3; q++) pc.pc[q] = x[3 * a + q] + la * in.n[q];
      v3_copy(pc.ta, ma);
      probe->fn(probe->ctx, &pc);
      continue;
    }
    v3_add(p->f + 3 * a, p->f + 3 * a, out.f);
    v3_sub(p->f + 3 * b, p->f + 3 * b, out.f);
    v3_add(p->t + 3 * a, p->t + 3 * a, ma);
    v3_add(p->t + 3 * b, p->t + 3 * b, mb);
    if (slips) slip += out.slip_work;
    if (slips) wst += w_st;
  }
  if (slips) s->led.d_friction += slip;
  if (slips) s->led.w_stiff += wst;
  *touching += nt;
  return ESF_OK;
}

/* Which of one particle's wall hits carry force. Meshes and boxes share edges and
 * vertices (and separate walls may meet), and the nearest point of a neighbouring
 * element is then a point that also belongs to an element the particle touches on its
 * face. Rule, over all the particle's wall elements:
 * every face hit counts; an edge or vertex hit counts unless its point lies on an
 * element with a face hit (it is part of that face's closed polygon, so the surface's
 * nearest point is that face's) or coincides with a hit already kept (a shared edge or
 * vertex reported by both its elements). Coincident face hits (a centre right above a
 * shared edge) count once. keep[k] is set for the kept hits among hits[0..m). */
void esf_forces_select_wall_hits(const esf_walls *walls, const uint32_t *elem,
                                 const esf_wall_hit *hits, const double *un, size_t m,
                                 double r, unsigned char *keep) {
  double tol = 1e-9 * r;
  for (size_t k = 0; k < m; k++)
    keep[k] = un[k] > 0 && hits[k].feature == ESF_FEATURE_FACE;
  for (int pass = 0; pass < 2; pass++) {
    for (size_t k = 0; k < m; k++) {
      if (!(un[k] > 0)) continue;
      int face = hits[k].feature == ESF_FEATURE_FACE;
      if (face != (pass == 0)) continue; /* faces first, then edges and vertices */
      keep[k] = 1;
      for (size_t j = 0; j < m && keep[k]; j++) {
        if (j == k || !keep[j] || (pass == 0 && j > k)) continue;
        const esf_wall_elem *f = &walls->e[elem[j]];
        double d[3];
        v3_sub(d, hits[j].q, hits[k].q);
        if (v3_norm2(d) <= tol * tol)
          keep[k] = 0; /* the same point */
        else if (!face && hits[j].feature == ESF_FEATURE_FACE) {
          esf_wall_hit on;
          esf_wall_nearest(f, hits[k].q, &on);
          if (fabs(on.dist) <= tol) keep[k] = 0; /* the point lies on a touched face */
        }
      }
    }
  }
}

static int wall_particle(esf_sim *s, size_t k0, size_t k1, const double *x,
                         const double *v, const double *w, double dt, int commit,
                         double *rows, double *slip, size_t *nt, double *f, double *t,
                         const esf_contact_probe *probe, esf_error *err) {
  esf_particles *p = &s->p;
  esf_candidates *c = &s->nb.pw;
  const esf_materials *mt = &s->mats;
  esf_wall_hit *hits = s->nb.wall_hits + k0;
  double *un = s->nb.wall_un + k0;
  unsigned char *keep = s->nb.wall_keep + k0;
  uint32_t a = c->a[k0];
  for (size_t k = k0; k < k1; k++) {
    esf_wall_nearest(&s->walls.e[c->b[k]], x + 3 * a, &hits[k - k0]);
    un[k - k0] = p->radius[a] - hits[k - k0].dist;
  }
  double r = p->radius[a];
  if (k1 - k0 == 1)
    keep[0] = un[0] > 0;
  else
    esf_forces_select_wall_hits(&s->walls, c->b + k0, hits, un, k1 - k0, r, keep);
  for (size_t k = k0; k < k1; k++) {
    const esf_wall_hit *hit = &hits[k - k0];
    if (!keep[k - k0]) {
      if (commit) c->touch[k] = 0;
      continue;
    }
    const esf_wall_elem *el = &s->walls.e[c->b[k]];
    if (un[k - k0] > s->cfg.max_overlap * r)
      return esf_forces_overlap_failure(s, (long long)p->id[a], (long long)c->b[k], 1,
                                        un[k - k0], r, err);
    const esf_wall_group *g = &s->walls.g[el->group];
    esf_contact_in in;
    v3_copy(in.n, hit->n);
    in.un = un[k - k0];
    const double la = esf_wall_lever(s->cfg.wall_lever, r, in.un, hit->dist);
    double vw[3], pc[3];
    esf_wall_contact_point(s->cfg.wall_lever, x + 3 * a, la, in.n, hit->q, pc);
    esf_wall_point_velocity(g, pc, vw);
    contact_velocity(v, w, a, vw, NULL, la, 0, in.n, in.vc);
    in.spin_n = 0.5 * (v3_dot(w + 3 * a, in.n) + v3_dot(g->omega, in.n));
    in.mstar = p->mass[a];
    in.rstar = p->radius[a];
    in.dt = dt;
    const esf_pair_params *pp = &mt->pair[p->material[a] * mt->n + el->material];
    esf_contact_out out;
    const int live = c->touch[k]; /* before the commit (rolling) */
    if (!eval_contact(s, pp, &in, c, k, commit, rows, &out)) continue;
    (*nt)++;
    if (rows) {
      double ket[3];
      spring_t(pp, &c->h[k], ket);
      esf_ledger_wall_rows(rows, in.n, la, out.fd_n, out.fel, out.fd_t, ket,
                           out.slip_work, out.e_el_n, out.e_el_t, out.f, vw, dt);
    }
    if (slip) *slip += out.slip_work;
    if (s->tally) s->tally->p_walls += v3_dot(out.f, vw);
    if (commit && s->walls.gforce) /* servo walls (servo.c) */
      esf_servo_add(esf_servo_slot(&s->walls, a - esf_sim_own_lo(s), el->group), &out,
                    in.n);
    v3_add(f, f, out.f);
    double m[3], ma[3];
    v3_cross(m, in.n, out.ft);
    v3_scale(ma, la, m);
    double w_st = out.w_st; /* with the rolling springs' (pair_forces) */
    if (c->roll) {
      const int stiff = pp->hn > 0 && commit && s->led.on;
      const double ia = p->inertia[a];
      double wrel[3];
      v3_sub(wrel, w + 3 * a, g->omega);
      const double u0 = in.un + dt * v3_dot(in.vc, in.n);
      const double wk = rolling(s, pp, c, k, commit, live, stiff, in.n, wrel, r, in.un,
                                u0, ia + p->mass[a] * r * r, ia, out.fn, dt, ma, NULL,
                                rows, NULL, g->omega);
      if (stiff) w_st = out.w_st + wk;
    }
    if (rows && pp->ht > 0) rows[ESF_LR_STIFF] += w_st;
    if (slip) s->led.w_stiff += w_st; /* the other schemes' ledger (as the slip) */
    v3_add(t, t, ma);
    if (probe) { /* output (esf_forces_probe) */
      esf_probe_contact o = {a, c->b[k], el->group, {0}, out.f, out.ft, {0}, out.fn};
      v3_copy(o.pc, pc);
      v3_copy(o.ta, ma);
      probe->fn(probe->ctx, &o);
    }
  }
  return ESF_OK;
}

int esf_forces_wall_particle(esf_sim *s, size_t k0, size_t k1, const double *x,
                             const double *v, const double *w, double dt, int commit,
                             double *rows, double *slip, size_t *nt, double *f, double *t,
                             esf_error *err) {
  return wall_particle(s, k0, k1, x, v, w, dt, commit, rows, slip, nt, f, t, NULL, err);
}

static int wall_forces(esf_sim *s, const double *x, const double *v, const double *w,
                       double dt, int commit, size_t *touching, esf_error *err) {
  esf_particles *p = &s->p;
  esf_candidates *c = &s->nb.pw;
  double *rows = commit && s->led.on ? s->led_rows : NULL; /* the leapfrog's (ledger.h) */
  const int slips = commit && s->led.on && !rows;          /* the other schemes' ledger */
  double slip = 0;
  size_t nt = 0;
  for (size_t k0 = 0, k1; k0 < c->n; k0 = k1) {
    uint32_t a = c->a[k0];
    for (k1 = k0; k1 < c->n && c->a[k1] == a; k1++) continue;
    int rc = esf_forces_wall_particle(
        s, k0, k1, x, v, w, dt, commit, rows ? rows + s->led_lr * a : NULL,
        slips ? &slip : NULL, &nt, p->f + 3 * a, p->t + 3 * a, err);
    if (rc) return rc;
  }
  if (slips) s->led.d_friction += slip;
  *touching += nt;
  return ESF_OK;
}

int esf_forces_eval(esf_sim *s, const double *x, const double *v, const double *w,
                    double dt, int mode, size_t *touching, esf_error *err) {
  esf_particles *p = &s->p;
  const double *g = s->cfg.gravity;
  s->ft_lazy = NULL; /* p.f, p.t are written here */
  int rc0 = esf_sim_forces_room(s, err);
  if (rc0) return rc0;
  for (size_t i = 0; i < p->n; i++) {
    double m = p->mass[i];
    p->f[3 * i] = m * g[0];
    p->f[3 * i + 1] = m * g[1];
    p->f[3 * i + 2] = m * g[2];
  }
  memset(p->t, 0, 3 * p->n * sizeof(double));
  if (s->tally) memset(s->tally, 0, sizeof *s->tally);
  size_t nt = 0;
  int commit = mode == ESF_FORCES_COMMIT;
  if (commit && s->walls.gforce) { /* servo walls: per-group forces (servo.c) */
    int rc = esf_servo_blocks(s, 1, err);
    if (rc) return rc;
  }
  int rc = pair_forces(s, x, v, w, dt, commit, &nt, NULL, err);
  if (!rc) rc = wall_forces(s, x, v, w, dt, commit, &nt, err);
  if (!rc && s->drag) rc = esf_drag_apply(s, x, v, err); /* fluid drag (drag.c) */
  if (rc) return rc;
  if (commit && s->walls.gforce) esf_servo_update(s);
  if (s->cfg.dim == 2) {
    for (size_t i = 0; i < p->n; i++) {
      p->f[3 * i + 1] = 0.0;
      p->t[3 * i] = 0.0;
      p->t[3 * i + 2] = 0.0;
    }
  }
  s->rhs_evals++;
  if (touching) *touching = nt;
  return ESF_OK;
}

int esf_forces_probe(esf_sim *s, int pairs, int walls, const esf_contact_probe *probe,
                     esf_error *err) {
  esf_particles *p = &s->p;
  esf_force_tally *ty = s->tally;
  s->tally = NULL; /* nothing is booked */
  size_t nt = 0;
  /* the increment since the last commit: the leapfrog's next step integrates it over
     dt; Verlet and the ODE methods committed at this very state */
  const double dt = strcmp(s->cfg.method, "leapfrog") == 0 ? s->dt : 0.0;
  int rc = pairs ? pair_forces(s, p->x, p->v, p->w, dt, 0, &nt, probe, err) : ESF_OK;
  const esf_candidates *c = &s->nb.pw;
  for (size_t k0 = 0, k1; walls && !rc && k0 < c->n; k0 = k1) {
    const uint32_t a = c->a[k0];
    for (k1 = k0; k1 < c->n && c->a[k1] == a; k1++) continue;
    if (a >= p->n) continue; /* stale entries (as contact_net.c's) */
    double f[3] = {0, 0, 0}, t[3] = {0, 0, 0};
    rc = wall_particle(s, k0, k1, p->x, p->v, p->w, s->dt, 0, NULL, NULL, &nt, f, t,
                       probe, err);
  }
  s->tally = ty;
  return rc;
}
