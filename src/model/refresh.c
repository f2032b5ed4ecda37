/* refresh.c — keeping the candidate lists valid between steps (model.h): the scene
 * events due, the particles inserted (a new count asks for a rebuild), the lists'
 * displacement check and, when it asks, the tuned skin, the particles that left the
 * domain removed, the particles renumbered along the cells, the lists rebuilt and, at the
 * first build, the start's bonds formed. */
#include "model/model.h"

#include <math.h>

#include "core/bonds.h"
#include "core/reorder.h"
#include "loads/events.h"
#include "loads/insert.h"
#include "par/par.h"

int esf_sim_refresh(esf_sim *s, int *rebuilt, esf_error *err) {
  int rebuild = 0, walls_changed = 0;
  if (rebuilt) *rebuilt = 0;
  if (s->events) { /* scene events due now (events.c) */
    int rc = esf_par_agree(s, esf_events_apply(s, err), err); /* MPI: all, or none */
    if (rc) return rc;
    walls_changed = s->events->walls_changed; /* a wall removed or added: rebuild */
    s->events->walls_changed = 0;
  }
  if (s->insert) { /* the batch due now (insert.c): the count changes, lists rebuild */
    size_t added = 0;
    int rc = esf_inserts_apply(s, &added, err);
    if (rc) return rc;
  }
  double moved_by = esf_walls_moved(&s->walls);
  if (s->cfg.per.le) { /* Lees-Edwards: the images drift by rate L_g (t - t_build) */
    esf_neighbor_le_time(&s->nb, s->t);
    moved_by = fmax(moved_by,
                    0.5 * esf_periodic_le_speed(&s->cfg.per) * (s->t - s->nb.pp.le_tb));
  }
  int rc = esf_neighbor_check(&s->nb, &s->p, moved_by, &rebuild, err);
  s->nb.disp_valid = 0;
  if (s->par) { /* MPI: every process rebuilds when one must (par.h) */
    rc = esf_par_agree_flag(s, rc, &rebuild, err);
  }
  if (rc) {
    esf_error_prefix(err,
                     "step %ld (t = %.6g s, dt = %.4g s, critical dt %.4g s): ", s->step,
                     s->t, s->dt, s->dte.crit[s->cfg.dt_rule]);
    return rc;
  }
  if (!rebuild && !walls_changed) return ESF_OK;
  if (s->par) { /* the idle candidates and particles of every process */
    const esf_neighbor *nb = &s->nb;
    const long long idle =
        esf_par_sum(s, (long long)esf_neighbor_idle(nb, s->own_lo, s->own_hi));
    const size_t n = esf_par_count(s);
    if (nb->skin_hi > 0 && nb->xref && nb->nref == s->p.n && n > 0 && nb->builds > 0)
      esf_neighbor_skin_tune_with(&s->nb, (size_t)idle, n, s->step);
  } else {
    esf_neighbor_skin_tune(&s->nb, s->p.n, s->step); /* before particles go or move */
  }
  /* into the periodic box: each pair's image follows at the build (periodic.c) */
  if (s->cfg.per.any) {
    if ((rc = esf_sim_forces_sync(s, err))) return rc;
    esf_periodic_wrap(&s->cfg.per, s->p.n, s->p.x, s->p.v, s->t, s->p.img);
  }
  int moved = 0;
  if (s->par) { /* MPI: removal, the cut, migration, the global order, ghosts */
    rc = esf_par_agree(s, esf_par_rebuild(s, err), err);
  } else {
    rc = esf_sim_remove_escaped(s, err);
    if (!rc && s->reorder_ok && s->cfg.reorder)
      rc = esf_reorder_particles(s, &moved, err);
  }
  s->nb.threads = esf_sim_threads_for(s, s->p.n);
  s->nb.le_t = s->t;
  if (!rc) rc = esf_neighbor_build(&s->nb, &s->p, &s->walls, err);
  if (!rc) s->nb.built_step = s->step;
  if (!rc) esf_walls_mark(&s->walls);
  if (!rc && s->bonds.pending) rc = esf_bonds_form(s, err); /* the start's contacts */
  if (!rc && rebuilt) *rebuilt = 1;
  return rc;
}
