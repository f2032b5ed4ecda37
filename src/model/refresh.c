/* integ_common.c — list refresh, damped accelerations and stored energies shared by
 * the integrators (the leapfrog keeps its own (1 -+ alpha dt/2) kick). */
#include "model/refresh.h"

#include "loads/events.h"
#include "core/reorder.h"
#include "util/vec3.h"

int esf_integ_refresh(esf_sim *s, int *rebuilt, esf_error *err) {
  int rebuild = 0;
  if (rebuilt) *rebuilt = 0;
  if (s->events) { /* scene events due now (events.c) */
    int rc = esf_events_apply(s, err);
    if (rc) return rc;
  }
  int rc = esf_neighbor_check(&s->nb, &s->p, esf_walls_moved(&s->walls), &rebuild, err);
  s->nb.disp_valid = 0;
  if (rc) {
    esf_error_prefix(err,
                     "step %ld (t = %.6g s, dt = %.4g s, critical dt %.4g s): ", s->step,
                     s->t, s->dt, s->dte.crit[s->cfg.dt_rule]);
    return rc;
  }
  if (!rebuild) return ESF_OK;
  esf_neighbor_skin_tune(&s->nb, s->p.n, s->step); /* before particles go or move */
  rc = esf_sim_remove_escaped(s, err);
  int moved = 0;
  if (!rc && s->reorder_ok && s->cfg.reorder) rc = esf_reorder_particles(s, &moved, err);
  s->nb.threads = s->cfg.threads;
  if (!rc) rc = esf_neighbor_build(&s->nb, &s->p, &s->walls, err);
  if (!rc) s->nb.built_step = s->step;
  if (!rc) esf_walls_mark(&s->walls);
  if (!rc && s->bonds.pending) rc = esf_bonds_form(s, err); /* the start's contacts */
  if (!rc && rebuilt) *rebuilt = 1;
  return rc;
}

void esf_integ_accel(const esf_sim *s, const double *v, const double *w, double *acc,
                     double *dw, double p_damp[2], int with_global) {
  const esf_particles *p = &s->p;
  const esf_local_damping *loc = s->local;
  const double lc = s->cfg.local_coef;
  const double ar = with_global ? s->alpha_r : 0.0, at = with_global ? s->alpha_t : 0.0;
  double pg = 0, pl = 0;
  for (size_t i = 0; i < p->n; i++) {
    const double *vi = v + 3 * i, *wi = w + 3 * i;
    double f[3], m[3], fd[3] = {0, 0, 0}, md[3] = {0, 0, 0};
    v3_copy(f, p->f + 3 * i);
    v3_copy(m, p->t + 3 * i);
    if (loc) {
      loc->force(lc, f, vi, fd);
      loc->force(lc, m, wi, md);
    }
    double mass = p->mass[i], I = p->inertia[i];
    for (int q = 0; q < 3; q++) {
      acc[3 * i + q] = (f[q] + fd[q]) * p->inv_mass[i] - ar * vi[q];
      dw[3 * i + q] = (m[q] + md[q]) * p->inv_inertia[i] - at * wi[q];
    }
    if (p_damp) {
      pg += s->alpha_r * mass * v3_norm2(vi) + s->alpha_t * I * v3_norm2(wi);
      pl -= v3_dot(fd, vi) + v3_dot(md, wi);
    }
  }
  if (p_damp) {
    p_damp[0] = pg;
    p_damp[1] = pl;
  }
}

void esf_integ_energies(const esf_sim *s, const double *x, const double *v,
                        const double *w, double *kin_t, double *kin_r, double *pot) {
  const esf_particles *p = &s->p;
  double kt = 0, kr = 0, pe = 0;
  for (size_t i = 0; i < p->n; i++) {
    kt += 0.5 * p->mass[i] * v3_norm2(v + 3 * i);
    kr += 0.5 * p->inertia[i] * v3_norm2(w + 3 * i);
    pe -= p->mass[i] * v3_dot(s->cfg.gravity, x + 3 * i);
  }
  *kin_t = kt;
  *kin_r = kr;
  *pot = pe;
}
