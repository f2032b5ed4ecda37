/* servo.c — the servo controller of stress-controlled walls
 * (docs/physics.md#servo-walls).
 *
 * Measured stress of group g with unit compression direction d (the way the wall moves
 * to squeeze the packing): sigma = (sum of the contact forces the group's elements put
 * on particles, less their dashpot parts) . d / A, compressive positive. A is the
 * group's polygon area projected on d (or the scene's `area`). The dashpots are left
 * out because they respond to the wall's own velocity at once: with them the loop gain
 * would be G N c / A, and c/dt is several times kn at the usual steps (the controller
 * oscillates between +-vmax); at rest the two measures agree.
 * Control law (the classic DEM servo, Itasca PFC's wall servo): the wall velocity is
 *   v = G (sigma_target - sigma) d,   |v| <= vmax,
 * set after each committed force evaluation and used over the next step (the wall is
 * drifted by v dt in esf_walls_set_time: a leapfrog for the wall itself). The gain is
 * G = alpha A / (kn N_c dt) (esf_servo_update) or a fixed one, m/(s Pa).
 * The wall's work on the particles enters the ledger as wall work through the wall
 * velocity (forces.c), as for prescribed motion. The blocks' forces are summed exactly
 * (util/xsum.h), so the walls' motion does not depend on the blocks' order. Units: SI. */
#include "loads/servo.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/vec3.h"

double esf_wall_elem_area(const esf_wall_elem *e, const double d[3]) {
  if (e->kind != ESF_WALL_POLYGON) return 0.0;
  double a[3] = {0, 0, 0};
  for (int k = 1; k + 1 < e->nv; k++) { /* fan from vertex 0 */
    double u[3], w[3], c[3];
    v3_sub(u, e->v[k], e->v[0]);
    v3_sub(w, e->v[k + 1], e->v[0]);
    v3_cross(c, u, w);
    v3_add(a, a, c);
  }
  return 0.5 * fabs(v3_dot(a, d));
}

int esf_servo_setup(esf_sim *s, esf_error *err) {
  esf_walls *w = &s->walls;
  int any = 0;
  for (int k = 0; k < w->ngroups; k++) any |= w->g[k].motion.kind == ESF_MOTION_SERVO;
  if (!any) return ESF_OK;
  if (s->mats.all_hertz) /* the gain rule needs a constant kn */
    return esf_fail(err, ESF_EINPUT,
                    "%s: servo walls need the linear law's kn for their gain; the "
                    "Hertz-Mindlin law (youngs_modulus) does not support them yet",
                    esf_config_where(&s->cfg, "walls"));
  if (strcmp(s->cfg.method, "leapfrog") != 0)
    return esf_fail(err, ESF_EINPUT,
                    "%s: servo walls are supported by the leapfrog only (their velocity "
                    "is set by feedback after each committed step, which an ODE "
                    "method's trial stages cannot follow); use integrator.method: "
                    "leapfrog",
                    esf_config_where(&s->cfg, "integrator.method"));
  const esf_materials *m = &s->mats;
  for (int k = 0; k < w->ngroups; k++) {
    esf_wall_motion *mo = &w->g[k].motion;
    if (mo->kind != ESF_MOTION_SERVO) continue;
    double area = 0;
    int plane = 0;
    mo->kn = 0;
    for (size_t i = 0; i < w->n; i++) {
      const esf_wall_elem *e = &w->e[i];
      if (e->group != k) continue;
      plane |= e->kind == ESF_WALL_PLANE;
      area += esf_wall_elem_area(e, mo->dir);
      for (size_t j = 0; j < s->p.n; j++) {
        double kn = m->pair[s->p.material[j] * m->n + e->material].kn;
        if (kn > mo->kn) mo->kn = kn;
      }
    }
    if (!(mo->area > 0)) {
      if (plane || s->cfg.dim == 2)
        return esf_fail(
            err, ESF_EINPUT, "%s: servo wall '%s': give motion.servo.area (m^2) for %s",
            esf_config_where(&s->cfg, "walls"), w->g[k].label,
            plane ? "an infinite plane" : "a 2D scene (wall length x disk_thickness)");
      if (!(area > 0))
        return esf_fail(err, ESF_EINPUT,
                        "%s: servo wall '%s' has no area across its direction; give "
                        "motion.servo.area or a direction normal to the wall",
                        esf_config_where(&s->cfg, "walls"), w->g[k].label);
      mo->area = area;
    }
    if (!(mo->kn > 0)) mo->kn = 1.0; /* no particles: any gain, nothing to push */
  }
  free(w->gforce);
  w->gforce = calloc(4 * (size_t)w->ngroups, sizeof *w->gforce);
  if (!w->gforce) return esf_fail(err, ESF_ENOMEM, "out of memory");
  return ESF_OK;
}

/* Gain rule: moving the wall by v dt changes the stress by about kn N_c v dt / A
 * (N_c touching contacts of normal stiffness kn in parallel), so
 *   G = alpha A / (kn N_c dt)
 * removes the fraction alpha of the stress error per step if the packing behind the
 * contacts were rigid; the packing is softer than its wall contacts, so the real
 * change is smaller and alpha < 1 is a stable, non-overshooting choice (default 0.5).
 * N_c = 0 (no contact yet) uses N_c = 1, so the wall approaches at vmax. A fixed gain
 * (m/(s Pa)) may be given instead. kn is the largest normal stiffness between the
 * wall's materials and those of the particles (esf_servo_setup). */
int esf_servo_blocks(esf_sim *s, int zero, esf_error *err) {
  esf_walls *w = &s->walls;
  const size_t nb = esf_ledger_nblocks(s->p.n), per = 4 * (size_t)w->ngroups;
  if (nb > w->gforce_nb || !w->gforce_blk) {
    const size_t cap = nb + nb / 4 + 1;
    double *b = realloc(w->gforce_blk, cap * per * sizeof *b);
    if (!b) return esf_fail(err, ESF_ENOMEM, "out of memory for the servo walls");
    w->gforce_blk = b;
    w->gforce_nb = cap;
  }
  if (zero) memset(w->gforce_blk, 0, nb * per * sizeof(double));
  return ESF_OK;
}

void esf_servo_block_sums(const esf_sim *s, esf_xsum *acc) {
  const esf_walls *w = &s->walls; /* (an MPI run's blocks: its own particles') */
  const size_t nb = esf_ledger_nblocks(esf_sim_own_hi(s) - esf_sim_own_lo(s)),
               per = 4 * (size_t)w->ngroups;
  for (size_t q = 0; q < per; q++) esf_xsum_add_n(&acc[q], w->gforce_blk + q, nb, per);
}

void esf_servo_update(esf_sim *s) {
  esf_walls *w = &s->walls;
  const size_t nb = esf_ledger_nblocks(s->p.n), per = 4 * (size_t)w->ngroups;
  for (size_t q = 0; q < per; q++) { /* one channel at a time: no accumulator array */
    esf_xsum acc;
    esf_xsum_zero(&acc);
    esf_xsum_add_n(&acc, w->gforce_blk + q, nb, per);
    w->gforce[q] = esf_xsum_value(&acc);
  }
  esf_servo_control(s);
}

void esf_servo_control(esf_sim *s) {
  esf_walls *w = &s->walls;
  for (int k = 0; k < w->ngroups; k++) {
    esf_wall_group *g = &w->g[k];
    esf_wall_motion *mo = &g->motion;
    if (mo->kind != ESF_MOTION_SERVO) continue;
    if (s->step == 0) /* the run's log is open from the first step on */
      esf_sim_log(s,
                  "servo wall '%s': target %.6g Pa over %.6g m^2 along (%g, %g, %g), "
                  "gain %s %.6g, max speed %.6g m/s",
                  w->g[k].label, mo->stress, mo->area, mo->dir[0], mo->dir[1], mo->dir[2],
                  mo->gain > 0 ? "fixed" : "auto, alpha",
                  mo->gain > 0 ? mo->gain : mo->alpha, mo->vmax);

    const double *F = w->gforce + 4 * k;
    mo->sigma = v3_dot(F, mo->dir) / mo->area;
    double nc = F[3] > 1 ? F[3] : 1.0;
    double G = mo->gain > 0 ? mo->gain : mo->alpha * mo->area / (mo->kn * nc * s->dt);
    double v = G * (mo->stress - mo->sigma);
    if (v > mo->vmax) v = mo->vmax;
    if (v < -mo->vmax) v = -mo->vmax;
    v3_scale(g->vel, v, mo->dir);
  }
}

void esf_servo_log_state(const esf_sim *s) {
  const esf_walls *w = &s->walls;
  for (int k = 0; k < w->ngroups; k++) {
    const esf_wall_group *g = &w->g[k];
    if (g->motion.kind != ESF_MOTION_SERVO) continue;
    esf_sim_log(s,
                "  servo wall '%s': stress %.6g Pa (target %.6g), %g contacts, "
                "speed %.4g m/s, moved %.6g m",
                g->label, g->motion.sigma, g->motion.stress, w->gforce[4 * k + 3],
                v3_dot(g->vel, g->motion.dir), v3_dot(g->disp, g->motion.dir));
  }
}
