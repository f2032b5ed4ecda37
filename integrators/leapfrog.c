/* leapfrog.c — the production scheme: central differences (leapfrog) with global
 * viscous damping in the (1 -+ alpha dt/2) form and Cundall's local damping.
 * Sources: 000 (3-6..3-8), 004 (2.38–2.47), 001 (3.50–3.54).
 *
 * State between steps: x at t_n, v and w at t_n - dt/2, contact history at t_{n-1}.
 * One step, in this order:
 *   1. if a particle moved more than skin/2: drop particles outside the domain, rebuild
 *      the candidate lists (history carried over);
 *   2. F_n, M_n = forces(x_n, v_{n-1/2}, w_{n-1/2}), committing the contact history
 *      with the increment vct dt (the relative velocity over [t_{n-1}, t_n]);
 *   3. local damping F_d from F_n and the sign of v_{n-1/2} (and M_d from w);
 *   4. kick: v_{n+1/2} = [(1 - a_r dt/2) v_{n-1/2} + (F_n + F_d) dt/m] / (1 + a_r dt/2),
 *            w_{n+1/2} likewise with a_t, M and I (001 3.53–3.54);
 *   5. ledger (when on): every path's dissipation with the mid-step velocity vbar, for
 *      which the kinetic energy balances exactly (lf_step, at the ledger);
 *   6. adaptive damping (when on): alpha from the kinetic energies either side;
 *   7. drift: x_{n+1} = x_n + v_{n+1/2} dt; t += dt.
 * Scenes needing neither the ledger nor adaptive damping take steps 2-4 and 7 in
 * fused/fused.c's fused, threaded passes (the same physics and order of operations).
 * Start: v_{-1/2} from v_0 (start): second order from the initial conditions. */
#include <stdlib.h>
#include <string.h>

#include "fused/fused.h"
#include "integrators/dem_ode.h"
#include "integrators/integrator.h"
#include "loads/drag.h"
#include "loads/insert.h"
#include "model/forces.h"
#include "model/model.h"
#include "model/stability.h"
#include "par/par.h"
#include "util/vec3.h"

typedef struct leapfrog {
  int started;
  esf_fused *fast; /* the fused threaded step (fused/fused.h) */
  int logged;      /* the path last logged: 1 fused, 2 general, 0 none yet */
} leapfrog;

static int lf_create(esf_sim *s, void **state, esf_error *err) {
  int rc = esf_dem_ode_check(s, "leapfrog", 0, 0, err); /* ODE-only options refused */
  if (rc) return rc;
  leapfrog *lf = calloc(1, sizeof *lf);
  if (!lf) return esf_fail(err, ESF_ENOMEM, "out of memory");
  *state = lf;
  s->reorder_ok = 1; /* x, v, w and p.f, p.t are all the state between steps */
  return esf_fused_create(&lf->fast, s->cfg.isa, err);
}

static void lf_destroy(void **state) {
  leapfrog *lf = *state;
  if (lf) {
    esf_fused_free(&lf->fast);
  }
  free(lf);
  *state = NULL;
}

/* v_{-1/2} = v_0 - (dt/2) F(x_0, v_0)/m (likewise w): half a step back with the initial
 * forces (history not touched), so the scheme is second order from the initial
 * conditions. */
static int start(esf_sim *s, esf_error *err) {
  esf_particles *p = &s->p;
  int rc = esf_forces_eval(s, p->x, p->v, p->w, s->dt, ESF_FORCES_TRIAL, NULL, err);
  if (rc) return rc;
  double h = 0.5 * s->dt;
  for (size_t i = 0; i < p->n; i++) {
    v3_axpy(p->v + 3 * i, -h * p->inv_mass[i], p->f + 3 * i);
    v3_axpy(p->w + 3 * i, -h * p->inv_inertia[i], p->t + 3 * i);
  }
  return ESF_OK;
}

/* Steps 3-4: the kick with local and global damping; with blk (the ledger or adaptive
 * damping), each particle's energies and damping work go to its block's sums
 * (esf_ledger_kick_particle, the fused step's own). */
static void kick(esf_sim *s, double *blk) {
  esf_particles *p = &s->p;
  const double dt = s->dt, h = 0.5 * dt;
  const double ar = s->alpha_r, at = s->alpha_t;
  const double cr0 = 1.0 - ar * h, cr1 = 1.0 / (1.0 + ar * h);
  const double ct0 = 1.0 - at * h, ct1 = 1.0 / (1.0 + at * h);
  const esf_local_damping *loc = s->local;
  const double lc = s->cfg.local_coef;
  const esf_ledger_kick K = {.dt = dt,
                             .alpha_r = ar,
                             .alpha_t = at,
                             .g = s->cfg.gravity,
                             .roll = s->mats.any_rolling};
  /* the fluid force's work (drag.c keeps the last evaluation's forces) */
  const double *ff = s->drag && s->led.on && s->drag->n == p->n ? s->drag->f : NULL;
  const double *rows = s->led.on ? s->led_rows : NULL;
  for (size_t i = 0; i < p->n; i++) {
    double *v = p->v + 3 * i, *w = p->w + 3 * i, *x = p->x + 3 * i;
    double f[3], m[3], fd[3] = {0, 0, 0}, md[3] = {0, 0, 0};
    v3_copy(f, p->f + 3 * i);
    v3_copy(m, p->t + 3 * i);
    if (loc) {
      loc->force(lc, f, v, fd);
      loc->force(lc, m, w, md);
      v3_add(f, f, fd);
      v3_add(m, m, md);
    }
    double v0[3], w0[3];
    v3_copy(v0, v);
    v3_copy(w0, w);
    double im = p->inv_mass[i] * dt, ii = p->inv_inertia[i] * dt;
    for (int q = 0; q < 3; q++) {
      v[q] = (cr0 * v[q] + f[q] * im) * cr1;
      w[q] = (ct0 * w[q] + m[q] * ii) * ct1;
    }
    if (blk)
      esf_ledger_kick_particle(&K, p->mass[i], p->inertia[i], x, v0, v, w0, w,
                               loc ? fd : NULL, loc ? md : NULL, ff ? ff + 3 * i : NULL,
                               rows ? rows + s->led_lr * i : NULL,
                               blk + ESF_LB_N * (i / ESF_LEDGER_BLOCK));
  }
}

static int lf_step(esf_sim *s, void *state, double t_stop, esf_error *err) {
  (void)t_stop;
  leapfrog *lf = state;
  esf_particles *p = &s->p;
  esf_walls_set_time(&s->walls, s->t); /* moving walls at x_n's time */
  int rebuilt = 0;
  int rc = esf_sim_refresh(s, &rebuilt, err);
  if (!lf->started && !s->ft_lazy) /* no forces yet: start() evaluates them */
    esf_sim_forces_release(s);     /* (not held through the first stability check) */
  if (!rc && rebuilt) rc = esf_stability_runaway(s, err); /* no particle runs away */
  if (!rc) rc = esf_stability_guard(s, 0, err);           /* every stability_every */
  if (s->par && (rebuilt || (s->cfg.stability != ESF_STAB_OFF &&
                             s->step % s->cfg.stability_every == 0)))
    rc = esf_par_agree(s, rc, err); /* MPI: all stop when one must */
  if (rc) return rc;
  if (!lf->started) {
    rc = esf_par_agree(s, start(s, err), err);
    if (rc) return rc;
  }
  if (s->par) { /* MPI: the ghosts at x_n, v_{n-1/2}, w_{n-1/2}, one step at a time */
    rc = esf_par_ghosts(s, err);
    if (rc) return rc;
  }
  size_t touching = 0;
  const char *why = esf_fused_refusal(s);
  if (!lf->logged || (why == NULL) != (lf->logged == 1)) { /* the path, when it changes */
    if (why)
      esf_sim_log(s, "t = %.6g s: leapfrog on the general path, one thread (%s)", s->t,
                  why);
    else
      esf_sim_log(s, "t = %.6g s: leapfrog on the fused step, %s kernels, %d threads",
                  s->t, esf_fused_isa(lf->fast), s->cfg.threads);
    lf->logged = why ? 2 : 1;
  }
  if (!why) {       /* steps 2-4 and 7 fused and threaded, s->burst of */
    long taken = 0; /* them at most in one go, up to the next stability check */
    long burst = esf_stability_steps_left(s);
    if (s->burst < burst) burst = s->burst;
    if (s->insert) { /* up to the next insertion batch (insert.c) */
      const long left = esf_inserts_steps_left(s);
      if (left < burst) burst = left;
    }
    if (s->cfg.per.le) burst = 1; /* the shear images' offset is set per step */
    esf_par_busy(s, 0); /* MPI: the step's computing time, the next cut's balance */
    rc = esf_fused_run(s, lf->fast, burst, &taken, err);
    esf_par_busy(s, 1);
    rc = esf_par_agree(s, rc, err);
    if (taken > 0) lf->started = 1;
    return rc;
  }
  const int ledger = s->led.on, tally = ledger || s->cfg.autod.on;
  if (tally) { /* the step's ledger rows and blocks, zeroed (ledger.h) */
    rc = esf_sim_ledger_room(s, 1, err);
    if (rc) return rc;
  }
  rc = esf_forces_eval(s, p->x, p->v, p->w, s->dt, ESF_FORCES_COMMIT, &touching, err);
  if (rc) return rc;
  s->contacts_sum += (double)touching;
  /* Step 5: the dissipation of every path with the mid-step velocity
   * vbar = (v_{n-1/2} + v_{n+1/2})/2, for which the discrete identity
   * KE_{n+1/2} - KE_{n-1/2} = (F_n + F_d - a_r m vbar) . vbar dt holds exactly; stored
   * energies: kinetic at t_n + dt/2, gravity at the mean of x_n and x_{n+1}, elastic at
   * x_n (led_time = t_n). */
  double *blk = tally ? s->led_blocks : NULL;
  kick(s, blk);
  const size_t nb = esf_ledger_nblocks(p->n);
  if (ledger) {
    esf_ledger_step(&s->led, blk, nb);
    s->led_time = s->t;
  }
  if (s->cfg.autod.on) esf_sim_adapt_damping(s, blk, nb);
  for (size_t j = 0; j < 3 * p->n; j++) p->x[j] += p->v[j] * s->dt;
  lf->started = 1;
  s->step++;
  s->t = (double)s->step * s->dt;
  return ESF_OK;
}

/* Checkpoint: the only state between steps is whether v_{-1/2} was set up (vold is
 * scratch of one step). */
static int lf_save(esf_sim *s, void *state, esf_blob *out, esf_error *err) {
  (void)s;
  (void)err;
  const leapfrog *lf = state;
  int32_t started = lf->started;
  esf_blob_put(out, &started, sizeof started);
  return ESF_OK;
}

static int lf_restore(esf_sim *s, void *state, esf_blob_in *in, esf_error *err) {
  (void)s;
  leapfrog *lf = state;
  int32_t started = 0;
  if (esf_blob_get(in, &started, sizeof started) || in->pos != in->n)
    return esf_fail(err, ESF_EINPUT, "leapfrog: the saved state has the wrong size");
  lf->started = started != 0;
  return ESF_OK;
}

static void lf_trim(esf_sim *s, void *state) {
  leapfrog *lf = state;
  esf_fused_trim(s, lf->fast);
}

const esf_integrator_type esf_integrator_leapfrog = {
    .name = "leapfrog",
    .summary = "central differences (leapfrog), velocities at half steps, with global "
               "(1 -+ alpha dt/2) and local damping; the production scheme",
    .order = 2,
    .flags = ESF_INTEG_FIXED_STEP | ESF_INTEG_HALF_STEP_V |
             ESF_INTEG_HISTORY_INCREMENTAL | ESF_INTEG_STABILITY_CHECK,
    .create = lf_create,
    .step = lf_step,
    .destroy = lf_destroy,
    .save = lf_save,
    .restore = lf_restore,
    .trim = lf_trim,
};
