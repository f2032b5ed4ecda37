/* verlet.c — velocity Verlet (kick-drift-kick), the peers' default (LAMMPS, LIGGGHTS),
 * for comparison with the leapfrog. Second order; velocities on the steps.
 *
 * State between steps: x, v, w at t_n and the damped accelerations a_n, dw_n.
 * One step:
 *   1. v_{n+1/2} = v_n + a_n dt/2, likewise w;
 *   2. x_{n+1} = x_n + v_{n+1/2} dt; refresh the candidate lists;
 *   3. F_{n+1} = forces(x_{n+1}, v_{n+1/2}) (dashpots see the half-step velocity, as in
 *      the peers), committing the contact history over dt;
 *   4. a_{n+1} = (F + F_local)/m, local damping from the sign of v_{n+1/2};
 *   5. v_{n+1} = (v_{n+1/2} + a_{n+1} dt/2) / (1 + alpha dt/2): global damping is
 *      trapezoidal over the step (the first half kick applies -alpha v_n explicitly),
 *      so the scheme stays second order with it; contact dashpots see v_{n+1/2}, which
 *      makes them first order, as in the peers.
 * Start: forces at x_0, v_0 with the history committed over a zero interval.
 * Passes: up to s->burst steps a call; step 5 of each but the last and steps 1-2 of the
 * next are one pass over the particles (esf_fused_vv_drift: the same operations per
 * entry, vectorised for the CPU), which measures the displacements for the lists' check.
 * Ledger: stored energies on the step; dissipation by the trapezoidal rule over the
 * powers at successive evaluations (second order, so the residual falls as dt^2). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "fused/fused.h"
#include "integrators/dem_ode.h"
#include "integrators/integrator.h"
#include "model/forces.h"
#include "model/model.h"

typedef struct verlet {
  size_t cap;
  double *a, *dw;   /* 3 cap each */
  double p_prev[7]; /* normal, tangential, global, local, walls, fluid, rolling powers
                       at t_n */
  int started;
  esf_eval_path path;    /* the force evaluation's (dem_ode.h) */
  esf_vv_drift_fn drift; /* the particle pass, for this CPU (fused.h) */
} verlet;

static int vv_create(esf_sim *s, void **state, esf_error *err) {
  int rc = esf_dem_ode_check(s, "verlet", 0, 0, err); /* ODE-only options refused */
  if (rc) return rc;
  if (s->cfg.per.le) /* its evaluation at x_{n+1} runs before t moves on */
    return esf_fail(err, ESF_EINPUT,
                    "%s: domain.shear: Lees-Edwards shear runs with the leapfrog only",
                    esf_config_where(&s->cfg, "domain"));
  verlet *vv = calloc(1, sizeof *vv);
  if (!vv) return esf_fail(err, ESF_ENOMEM, "out of memory");
  rc = esf_fused_vv_drift(s->cfg.isa, &vv->drift, err);
  if (rc) {
    free(vv);
    return rc;
  }
  vv->path.name = "verlet";
  vv->path.threads = 1;
  *state = vv;
  return ESF_OK;
}

static void vv_destroy(void **state) {
  verlet *vv = *state;
  if (vv) {
    free(vv->a);
    free(vv->dw);
    esf_eval_path_free(&vv->path);
  }
  free(vv);
  *state = NULL;
}

static int reserve(verlet *vv, size_t n, esf_error *err) {
  if (vv->cap >= n) return ESF_OK;
  free(vv->a);
  free(vv->dw);
  vv->a = malloc(3 * n * sizeof(double));
  vv->dw = malloc(3 * n * sizeof(double));
  if (!vv->a || !vv->dw) return esf_fail(err, ESF_ENOMEM, "out of memory");
  vv->cap = n;
  return ESF_OK;
}

/* forces and accelerations at the current state; powers into pw[7] */
static int evaluate(esf_sim *s, verlet *vv, double dt, double pw[7], esf_error *err) {
  esf_particles *p = &s->p;
  esf_force_tally ty = {0};
  s->tally = s->led.on ? &ty : NULL;
  size_t touching = 0;
  int rc = reserve(vv, p->n, err);
  if (rc) return rc;
  /* the accelerations with the forces (without the ledger: its powers are below) */
  /* after the start, F and M may stay in the fused step's accumulators: the step's
     passes then take the accelerations from them (drift_all) */
  const esf_eval_accel ea = {vv->a, vv->dw, 0, vv->started};
  rc = esf_eval_forces(&vv->path, s, p->x, p->v, p->w, dt, ESF_FORCES_COMMIT, &touching,
                       s->led.on ? NULL : &ea, err);
  s->tally = NULL;
  if (rc) return rc;
  s->contacts_sum += (double)touching;
  double pd[2] = {0, 0};
  if (s->led.on) esf_sim_accel(s, p->v, p->w, vv->a, vv->dw, pd, 0, vv->path.threads);
  if (s->led.on) {
    pw[0] = ty.p_normal;
    pw[1] = ty.p_tangential;
    pw[2] = pd[0];
    pw[3] = pd[1];
    pw[4] = ty.p_walls;
    pw[5] = ty.p_fluid;
    pw[6] = ty.p_rolling;
    s->led.el_n = ty.e_el_n;
    s->led.el_t = ty.e_el_t;
    s->led.el_r = ty.e_el_r;
    s->led.d_rolling += ty.slip_r; /* plastic rolling (evaluate commits) */
  }
  return ESF_OK;
}

static void ledger_update(esf_sim *s, verlet *vv, const double pw[7]) {
  esf_ledger *L = &s->led;
  double h = 0.5 * s->dt;
  L->d_normal += h * (vv->p_prev[0] + pw[0]);
  L->d_tangential += h * (vv->p_prev[1] + pw[1]);
  L->d_global += h * (vv->p_prev[2] + pw[2]);
  L->d_local += h * (vv->p_prev[3] + pw[3]);
  L->w_walls += h * (vv->p_prev[4] + pw[4]);
  L->w_fluid += h * (vv->p_prev[5] + pw[5]);
  L->d_rolling += h * (vv->p_prev[6] + pw[6]);
  memcpy(vv->p_prev, pw, 7 * sizeof(double));
  esf_sim_energies(s, s->p.x, s->p.v, s->p.w, &L->kin_t, &L->kin_r, &L->pot_g);
  s->led_time = s->t;
}

/* The pass over every particle (esf_fused_vv_drift's, the kernels for this CPU) on nth
 * threads, each a contiguous share; the largest displacement goes to the lists
 * (esf_neighbor_check then needs no pass of its own, and decides the same: a maximum
 * does not depend on the order). */
static void drift_all(esf_sim *s, const verlet *vv, int end, int drift, const double *F,
                      int nth) {
  esf_particles *p = &s->p;
  esf_neighbor *nb = &s->nb;
  const double dt = s->dt, h = 0.5 * dt, ar = s->alpha_r, at = s->alpha_t;
  const int dsp = drift && nb->xref && nb->nref == p->n;
  const esf_vv_pass c = {.h = h,
                         .dt = dt,
                         .ar = ar,
                         .at = at,
                         .cr = 1.0 / (1.0 + h * ar),
                         .ct = 1.0 / (1.0 + h * at),
                         .x = p->x,
                         .v = p->v,
                         .w = p->w,
                         .a = vv->a,
                         .dw = vv->dw,
                         .F = F,
                         .im = p->inv_mass,
                         .ii = p->inv_inertia,
                         .ar0 = 0.0, /* evaluate's: global damping in the kicks */
                         .at0 = 0.0,
                         .xref = dsp ? nb->xref : NULL,
                         .lo3 = nb->dom_lo,
                         .hi3 = nb->dom_hi,
                         .end = end,
                         .drift = drift};
  const size_t n = p->n;
  esf_vv_disp d = {0, 0, 0};
#pragma omp parallel num_threads(nth) if (nth > 1)
  {
#ifdef _OPENMP
    const size_t t = (size_t)omp_get_thread_num(), m = (size_t)omp_get_num_threads();
#else
    const size_t t = 0, m = 1;
#endif
    esf_vv_disp o = {0, 0, 0};
    vv->drift(&c, n * t / m, n * (t + 1) / m, &o);
#pragma omp critical(esf_verlet_disp)
    {
      if (o.max_bits > d.max_bits) d.max_bits = o.max_bits;
      d.bad |= o.bad;
      d.out |= o.out;
    }
  }
  if (!drift) return;
  memcpy(&nb->max_disp2, &d.max_bits, sizeof nb->max_disp2);
  nb->escaped = d.out;
  nb->disp_valid = dsp && !d.bad;
}

/* Up to s->burst steps (one with the ledger, which reads the state at every step): the
 * second half kick of each step but the last goes with the next step's first half kick
 * and drift in one pass, the same operations per entry as two passes. */
static int vv_step(esf_sim *s, void *state, double t_stop, esf_error *err) {
  (void)t_stop;
  verlet *vv = state;
  esf_particles *p = &s->p;
  double pw[7] = {0, 0, 0, 0, 0, 0, 0};
  int rc;
  if (!vv->started) {
    esf_walls_set_time(&s->walls, s->t);
    rc = esf_sim_refresh(s, NULL, err);
    if (!rc) rc = evaluate(s, vv, 0.0, pw, err);
    if (rc) return rc;
    if (s->led.on) {
      memcpy(vv->p_prev, pw, 7 * sizeof(double));
      esf_sim_energies(s, p->x, p->v, p->w, &s->led.kin_t, &s->led.kin_r, &s->led.pot_g);
      s->led.e0 = esf_ledger_stored(&s->led);
      s->led.started = 1;
    }
    vv->started = 1;
  }
  const double dt = s->dt;
  const long steps = s->led.on || s->burst < 1 ? 1 : s->burst;
  /* the evaluation's threads; entry by entry: no bits; no parallel region on one
     (its start costs a tiny scene more than the step) */
  const int nth = vv->path.threads > 1 && p->n >= 4096 ? vv->path.threads : 1;
  drift_all(s, vv, 0, 1, NULL, nth);
  for (long k = 0;; k++) {
    size_t n_before = p->n;
    esf_walls_set_time(&s->walls, (double)(s->step + 1) * dt); /* x_{n+1}'s time */
    rc = esf_sim_refresh(s, NULL, err);
    if (!rc && p->n != n_before)
      rc = esf_fail(err, ESF_EINPUT,
                    "%s: verlet: particles left the domain at t = %.6g s; removal is "
                    "supported by the leapfrog only in this version",
                    esf_config_where(&s->cfg, "integrator.method"), s->t);
    if (!rc) rc = evaluate(s, vv, dt, pw, err);
    if (rc) return rc;
    if (k + 1 < steps) { /* this step's end with the next one's start */
      drift_all(s, vv, 1, 1, s->ft_lazy, nth);
      s->step++;
      s->t = (double)s->step * dt;
      continue;
    }
    break;
  }
  drift_all(s, vv, 1, 0, s->ft_lazy, nth); /* the last step's second half kick alone */
  s->step++;
  s->t = (double)s->step * dt;
  if (s->led.on) ledger_update(s, vv, pw);
  return ESF_OK;
}

const esf_integrator_type esf_integrator_verlet = {
    .name = "verlet",
    .summary = "velocity Verlet (kick-drift-kick), velocities on the steps; damping as "
               "force terms; the peers' default, for comparison",
    .order = 2,
    .flags = ESF_INTEG_FIXED_STEP | ESF_INTEG_HISTORY_INCREMENTAL,
    .create = vv_create,
    .step = vv_step,
    .destroy = vv_destroy,
};
