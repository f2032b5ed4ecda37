/* erk.c — ARKODE ERKStep explicit Runge-Kutta methods on the DEM right-hand side
 * (dem_ode.h): `erk:<TABLE>` for any explicit table of SUNDIALS 6.4 by name
 * (ARKODE_HEUN_EULER_2_1_2 ... ARKODE_VERNER_8_5_6, ARKODE_FEHLBERG_13_7_8), `rk4`,
 * the classical fourth-order method as a custom Butcher table, and `erk` with the
 * scene's own table (integrator.table, checked by the scene reader: scene_butcher.c).
 *
 * Fixed step (integrator.rtol = 0): dt from integrator.dt or frac x the critical step.
 * Adaptive (rtol > 0, tables with an embedding only): tolerances rtol and atol on x, v,
 * w (the ledger quadratures take part in the error test with esf_dem_ode_qtol), ARKODE's
 * step limit raised to integrator.max_steps, and the DEM stability bound given through
 * ERKStepSetStabilityFn: h_stab = r / omega_max, with r where the table's stability
 * polynomial R(z) first leaves the unit disc along the ray of the stiffest contact mode
 * (damping ratio xi: z = r exp(i (pi - acos xi))), and omega_max the highest contact
 * frequency including the rotation a tangential spring drives:
 * omega_max^2 = k_max / m_min x (7 for spheres, 6 for disks; 1/m + r^2/I per body).
 *
 * Each call of step() takes one step: a fixed one on esfera's own driver (own_step:
 * ERKStep's operations, the same bits; ESF_ERK_DRIVER=arkode: on ERKStep), an adaptive
 * one on ERKStep (ARK_ONE_STEP, not past t_stop); then commits the history and refreshes
 * the lists. */
#include <arkode/arkode_erkstep.h>
#include <math.h>
#include <nvector/nvector_serial.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "integrators/dem_ode.h"
#include "integrators/integrator.h"
#include "model/model.h"
#include "model/roots.h"

typedef struct erk {
  SUNContext ctx;
  void *mem;
  N_Vector y, atol, ysave; /* ysave: the last accepted state, for retries */
  double t_save;
  long retries; /* steps retried after a failure inside f */
  esf_dem_ode ode;
  ARKodeButcherTable table; /* owned copy, for the stability polynomial */
  double h_stab;            /* s; <= 0: no stability bound */
  long resizes;             /* history as state: restarts on a new y */
  int nroots;               /* event functions registered (integrator.roots) */
  int roots_off;            /* events disabled until t_event (a step being redone) */
  double t_event;           /* s: the located event the redone step ends at */
  long events;              /* events located (each costs a redone step) */
  double r_stab;            /* the table's stability radius (for the log) */
  long base[6]; /* ARKODE's counters of the ERKStep memories freed at checkpoints:
                   steps, attempts, error-test failures, rhs, accuracy-, stability-
                   limited steps */
  /* esfera's fixed-step driver (own = 1; mem is then NULL): ARKODE's state, kept as
     ERKStep keeps it */
  int own;
  N_Vector *F, ycur; /* the stages' derivatives (table->stages), a stage's state */
  double *cv;        /* the combinations' coefficients (stages + 1) */
  N_Vector *X;       /* and their vectors */
  double tn;         /* ERKStep's t_n: the steps' sum since the last (re)start, s */
  int fn_current;    /* F[0] holds f(t_n, y_n) (else the next step evaluates it) */
  int committed; /* own_step's last stage committed the step (esf_dem_ode_rhs_commit) */
  long merged;   /* such steps (esf_integ_stats.merged) */
  long nst, nfe; /* steps and rhs evaluations since the last (re)start */
  char name[128];
} erk;

static int erk_rhs(realtype t, N_Vector y, N_Vector ydot, void *data) {
  erk *e = data;
  return esf_dem_ode_rhs(&e->ode, t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
}

static int erk_events(realtype t, N_Vector y, realtype *g, void *data) {
  erk *e = data;
  const double *yy = N_VGetArrayPointer(y);
  esf_walls_set_time(&e->ode.s->walls, t);
  esf_roots_eval(e->ode.s, yy, yy + 3 * e->ode.n, g);
  return 0;
}

/* Registers one event function per candidate contact (none while events are off).
 * ARKODE takes the signs to watch at its initial set-up, so every change of the
 * functions (a new count, a list rebuild, events back on) is followed by a restart on
 * the current state at the current step size, unless one was just made. */
static int erk_roots_init(erk *e, int changed, int restarted) {
  int m = e->roots_off ? 0 : (int)esf_roots_count(e->ode.s);
  if (m == e->nroots && !changed) return 0;
  e->nroots = m;
  if (ERKStepRootInit(e->mem, m, m ? erk_events : NULL) != ARK_SUCCESS) return -1;
  if (restarted) return 0;
  realtype h = 0;
  ERKStepGetLastStep(e->mem, &h);
  if (h > 0) ERKStepSetInitStep(e->mem, h);
  return ERKStepReset(e->mem, e->ode.s->t, e->y) == ARK_SUCCESS ? 0 : -1;
}

static int erk_stab(N_Vector y, realtype t, realtype *hstab, void *data) {
  (void)y;
  (void)t;
  erk *e = data;
  *hstab = e->h_stab;
  return 0;
}

/* SUNDIALS 6.4's explicit tables by name (ARKodeButcherTable_LoadERKByName prints its
 * own error to stderr for an unknown name, so names are looked up here). */
#define TABLE(id)                                                                        \
  { #id, id }
static const struct {
  const char *name;
  ARKODE_ERKTableID id;
} erk_tables[] = {
    TABLE(ARKODE_HEUN_EULER_2_1_2),      TABLE(ARKODE_BOGACKI_SHAMPINE_4_2_3),
    TABLE(ARKODE_ARK324L2SA_ERK_4_2_3),  TABLE(ARKODE_ZONNEVELD_5_3_4),
    TABLE(ARKODE_ARK436L2SA_ERK_6_3_4),  TABLE(ARKODE_SAYFY_ABURUB_6_3_4),
    TABLE(ARKODE_CASH_KARP_6_4_5),       TABLE(ARKODE_FEHLBERG_6_4_5),
    TABLE(ARKODE_DORMAND_PRINCE_7_4_5),  TABLE(ARKODE_ARK548L2SA_ERK_8_4_5),
    TABLE(ARKODE_VERNER_8_5_6),          TABLE(ARKODE_FEHLBERG_13_7_8),
    TABLE(ARKODE_KNOTH_WOLKE_3_3),       TABLE(ARKODE_ARK437L2SA_ERK_7_3_4),
    TABLE(ARKODE_ARK548L2SAb_ERK_8_4_5),
};
#undef TABLE

static ARKodeButcherTable load_table(const char *name) {
  for (size_t k = 0; k < sizeof erk_tables / sizeof erk_tables[0]; k++)
    if (strcmp(erk_tables[k].name, name) == 0)
      return ARKodeButcherTable_LoadERK(erk_tables[k].id);
  return NULL;
}

/* the classical RK4 */
static ARKodeButcherTable rk4_table(void) {
  realtype c[4] = {0, 0.5, 0.5, 1};
  realtype A[16] = {0, 0, 0, 0, 0.5, 0, 0, 0, 0, 0.5, 0, 0, 0, 0, 1, 0};
  realtype b[4] = {1.0 / 6, 1.0 / 3, 1.0 / 3, 1.0 / 6};
  return ARKodeButcherTable_Create(4, 4, 0, c, A, b, NULL);
}

/* The scene's table (cfg.table, s > 0), with its stated orders. */
static ARKodeButcherTable scene_table(const esf_butcher *u) {
  realtype A[ESF_BUTCHER_MAX * ESF_BUTCHER_MAX], c[ESF_BUTCHER_MAX], b[ESF_BUTCHER_MAX],
      d[ESF_BUTCHER_MAX];
  int s = u->s;
  for (int i = 0; i < s; i++) {
    c[i] = u->c[i];
    b[i] = u->b[i];
    d[i] = u->d[i];
    for (int j = 0; j < s; j++) A[i * s + j] = u->A[i][j];
  }
  return ARKodeButcherTable_Create(s, u->q, u->has_d ? u->p : 0, c, A, b,
                                   u->has_d ? d : NULL);
}

/* SUNDIALS 6.4.1's ERKStep takes any table with c_s = 1 for "first same as last" and
 * reuses f of the last stage as the next step's first stage, which is only right when
 * the last row of A is b (llnl/sundials issue #311, fixed in later releases). Affected
 * here: rk4, HEUN_EULER_2_1_2, VERNER_8_5_6, FEHLBERG_13_7_8 and the ARK*_ERK tables
 * (measured: Verner's order fell to 3). Workaround: append a stage with row b and zero
 * weight; it computes f(t + h, y_{n+1}), exactly what the reuse then needs, so the cost
 * per step stays s evaluations and the method is unchanged. Returns B itself when it is
 * not affected, else a new table (B is freed). */
static ARKodeButcherTable fix_fsal(ARKodeButcherTable B) {
  int s = B->stages;
  if (fabs(B->c[s - 1] - 1.0) > 1e-14) return B;
  int fsal = 1;
  for (int j = 0; j < s; j++)
    if (B->A[s - 1][j] != B->b[j]) fsal = 0;
  if (fsal) return B;
  ARKodeButcherTable N = ARKodeButcherTable_Alloc(s + 1, B->d != NULL);
  if (!N) return NULL;
  N->q = B->q;
  N->p = B->p;
  for (int i = 0; i < s; i++) {
    N->c[i] = B->c[i];
    N->b[i] = B->b[i];
    if (B->d) N->d[i] = B->d[i];
    for (int j = 0; j < s; j++) N->A[i][j] = B->A[i][j];
  }
  N->c[s] = 1.0;
  N->b[s] = 0.0;
  if (B->d) N->d[s] = 0.0;
  for (int j = 0; j < s; j++) N->A[s][j] = B->b[j];
  ARKodeButcherTable_Free(B);
  return N;
}

/* r where |R(r e^{i theta})| first exceeds 1 (0 when it does so at once). */
static double stability_radius(ARKodeButcherTable B, double xi) {
  int s = B->stages;
  double coef[32] = {0}; /* c_k = b^T A^{k-1} 1, R(z) = 1 + sum c_k z^k */
  double u[32], t[32];
  for (int i = 0; i < s; i++) u[i] = 1.0;
  for (int k = 1; k <= s && k < 32; k++) {
    double ck = 0;
    for (int i = 0; i < s; i++) ck += B->b[i] * u[i];
    coef[k] = ck;
    for (int i = 0; i < s; i++) {
      t[i] = 0;
      for (int j = 0; j < s; j++) t[i] += B->A[i][j] * u[j];
    }
    memcpy(u, t, (size_t)s * sizeof(double));
  }
  double th = acos(-fmin(xi, 1.0)); /* pi - acos(xi) */
  double ct = cos(th), st = sin(th), last_ok = 0;
  for (double r = 1e-3; r < 4.0 * s; r += 1e-3) {
    double re = 1, im = 0, pr = 1, pi = 0; /* z^k accumulated */
    for (int k = 1; k <= s; k++) {
      double nr = pr * r * ct - pi * r * st, ni = pr * r * st + pi * r * ct;
      pr = nr;
      pi = ni;
      re += coef[k] * pr;
      im += coef[k] * pi;
    }
    if (re * re + im * im > 1.0 + 1e-10) break;
    last_ok = r;
  }
  return last_ok;
}

static int fail_flag(erk *e, esf_error *err, int flag, const char *what) {
  esf_sim *s = e->ode.s;
  realtype h = s->dt, t = e->tn; /* esfera's driver: t_n or the failed stage's time */
  if (e->mem) {
    ERKStepGetCurrentStep(e->mem, &h);
    ERKStepGetCurrentTime(e->mem, &t);
  }
  if (e->ode.err.code)
    return esf_fail(err, ESF_ENUMERIC,
                    "%s (%s) failed at t = %.6g s with step %.4g s (critical dt %.4g s): "
                    "%s",
                    e->name, what, t, h, s->dte.crit[s->cfg.dt_rule], e->ode.err.msg);
  return esf_fail(err, ESF_ENUMERIC,
                  "%s (%s) failed at t = %.6g s with step %.4g s: %s (flag %d)", e->name,
                  what, t, h, ERKStepGetReturnFlagName(flag), flag);
}

/* esfera's fixed-step driver (e->own: a fixed step, so no rootfinding, and not
 * ESF_ERK_DRIVER=arkode): one step of the table as SUNDIALS 6.4.1's ERKStep takes it,
 * the same vector operations on the same vectors in the same order, so the same bits
 * and counters, without its Hermite interpolant's copies, its weights and norm.
 * F_0 = f(t_n, y_n): evaluated after a (re)start, else the step before's last stage
 * (first same as last; fix_fsal leaves no table with c_s = 1 whose last row is not b);
 * stage i: z_i = sum_{j<i} (h a_ij) F_j + 1 y_n (one N_VLinearCombination, this order),
 * F_i = f(t_n + c_i h, z_i); y_{n+1} = sum_j (h b_j) F_j + 1 y_n (zero weights
 * included); t_{n+1} = t_n + h (a sum, as ERKStep's); a table with c_s != 1 evaluates
 * F_0 = f(t_{n+1}, y_{n+1}) at the step's end, as ERKStep does for its interpolant. */
static void own_free(erk *e) {
  for (int i = 0; e->F && i < e->table->stages; i++)
    if (e->F[i]) N_VDestroy(e->F[i]);
  if (e->ycur) N_VDestroy(e->ycur);
  free(e->F);
  free(e->X);
  free(e->cv);
  e->F = e->X = NULL;
  e->ycur = NULL;
  e->cv = NULL;
}

/* The driver's vectors for the length of e->y, and a restart at (s->t, e->y) with its
 * counters from zero (a new ERKStep memory; ERKStepResize keeps them: `counters` 0). */
static int own_start(erk *e, int counters) {
  const int st = e->table->stages;
  if (!e->F || N_VGetLength(e->ycur) != N_VGetLength(e->y)) {
    own_free(e);
    e->F = calloc((size_t)st, sizeof *e->F);
    e->X = calloc((size_t)st + 1, sizeof *e->X);
    e->cv = calloc((size_t)st + 1, sizeof *e->cv);
    e->ycur = N_VClone(e->y);
    if (!e->F || !e->X || !e->cv || !e->ycur) return -1;
    for (int i = 0; i < st; i++)
      if (!(e->F[i] = N_VClone(e->y))) return -1;
  }
  e->tn = e->ode.s->t;
  e->fn_current = 0;
  if (counters) e->nst = e->nfe = 0;
  return 0;
}

/* z = sum_{j<m} (h w_j) F_j + 1 y_n, ERKStep's combination (w a row of A, or b), its
 * bits by esf_dem_ode_lincomb_nz (the zero terms left out); returns the zeros in z. */
static long own_combine(erk *e, int m, const double *w, double h, N_Vector z,
                        int resum_only) {
  int nv = 0;
  for (int j = 0; j < m; j++) {
    e->cv[nv] = h * w[j];
    e->X[nv++] = e->F[j];
  }
  e->cv[nv] = 1.0;
  e->X[nv++] = e->y;
  return esf_dem_ode_lincomb_nz(nv, e->cv, e->X, z, resum_only);
}

/* The last stage's state is y_{n+1} but for the sign of zeros: its row is b and its
 * weight 0 (the tables with first same as last, those fix_fsal extends). */
static int own_last_is_solution(ARKodeButcherTable B) {
  const int st = B->stages;
  if (st < 2 || B->b[st - 1] != 0.0) return 0;
  for (int j = 0; j < st - 1; j++)
    if (B->A[st - 1][j] != B->b[j]) return 0;
  return 1;
}

/* One step; 0, or f's nonzero return (e->tn then the failed evaluation's time). */
static int own_step(erk *e, double *tret) {
  ARKodeButcherTable B = e->table;
  const int st = B->stages;
  const double h = e->ode.s->dt, t0 = e->tn;
  int rc = 0;
  long zeros = 0; /* in the last stage's state */
  if (!e->fn_current) {
    rc = erk_rhs(t0, e->y, e->F[0], e);
    e->nfe++;
    if (rc) return rc;
    e->fn_current = 1;
  }
  e->committed = 0;
  for (int i = 1; i < st; i++) {
    const double tc = t0 + B->c[i] * h;
    zeros = own_combine(e, i, B->A[i], h, e->ycur, 0);
    /* the last stage at (t_{n+1}, y_{n+1}) exactly: it commits the step too. Its zeros
       are those of y_{n+1} with the same signs when they are the nq quadratures alone:
       without the ledger those are +0 in y_n and in every F_j, and a sum with a +0
       term (1 y_n) and otherwise +-0 terms is +0; a zero elsewhere could take another
       sign in y_{n+1}'s re-sum (which needs F of this stage): no merge then */
    const int merge = i == st - 1 && B->c[i] == 1.0 && zeros == (long)e->ode.nq &&
                      own_last_is_solution(B) && esf_dem_ode_can_merge(&e->ode);
    rc = merge ? esf_dem_ode_rhs_commit(&e->ode, tc, N_VGetArrayPointer(e->ycur),
                                        N_VGetArrayPointer(e->F[i]))
               : erk_rhs(tc, e->ycur, e->F[i], e);
    e->committed = merge && !rc;
    e->nfe++;
    if (rc) {
      e->tn = tc;
      return rc;
    }
  }
  if (!own_last_is_solution(B))
    own_combine(e, st, B->b, h, e->ycur, 0);
  else if (zeros) /* the last stage's state, its zeros summed as y_{n+1}'s */
    own_combine(e, st, B->b, h, e->ycur, 1);
  N_Vector y = e->ycur; /* the new state: the vectors trade places */
  e->ycur = e->y;
  e->y = y;
  e->tn = t0 + h;
  e->nst++;
  *tret = e->tn;
  if (fabs(B->c[st - 1] - 1.0) <= 1e-14) { /* the last stage is f(t_{n+1}, y_{n+1}) */
    N_Vector f = e->F[0];
    e->F[0] = e->F[st - 1];
    e->F[st - 1] = f;
    return 0;
  }
  e->fn_current = 0;
  rc = erk_rhs(e->tn, e->y, e->F[0], e);
  e->nfe++;
  if (!rc) e->fn_current = 1;
  return rc;
}

/* A new ERKStep memory at (s->t, e->y) with every setting, the first step h0 (adaptive)
 * or the fixed step s->dt; e->atol filled (adaptive). Used by create and at every
 * checkpoint (erk_save, erk_restore). */
static int erk_mem_create(erk *e, double h0, esf_error *err) {
  esf_sim *s = e->ode.s;
  const esf_config *c = &s->cfg;
  if (e->own) /* esfera's driver: a restart instead */
    return own_start(e, 1) ? esf_fail(err, ESF_ENOMEM, "out of memory") : ESF_OK;
  e->mem = ERKStepCreate(erk_rhs, s->t, e->y, e->ctx);
  if (!e->mem) return esf_fail(err, ESF_EINTERNAL, "ERKStepCreate failed");
  ERKStepSetUserData(e->mem, e);
  ERKStepSetErrHandlerFn(e->mem, esf_sundials_silent, NULL);
  int flag = ERKStepSetTable(e->mem, e->table);
  if (flag) return fail_flag(e, err, flag, "table");
  ERKStepSetMaxNumSteps(e->mem, c->max_steps);
  if (c->rtol > 0) {
    ERKStepSVtolerances(e->mem, c->rtol, e->atol);
    ERKStepSetInitStep(e->mem, h0);
    ERKStepSetMaxStep(e->mem, 10.0 * s->dte.crit[ESF_DT_HART]);
    if (e->h_stab > 0) ERKStepSetStabilityFn(e->mem, erk_stab, e);
    ERKStepSetCFLFraction(e->mem,
                          0.5); /* ARKODE's default, stated: steps <= h_stab / 2 */
    e->nroots = -1;             /* register the event functions afresh */
    if (c->roots && erk_roots_init(e, 1, 1))
      return esf_fail(err, ESF_EINTERNAL, "ERKStepRootInit failed");
  } else {
    ERKStepSetFixedStep(e->mem, s->dt);
  }
  return ESF_OK;
}

static int erk_create(esf_sim *s, void **state, esf_error *err) {
  const esf_config *c = &s->cfg;
  erk *e = calloc(1, sizeof *e);
  if (!e) return esf_fail(err, ESF_ENOMEM, "out of memory");
  *state = e;
  const char *tname = strncmp(c->method, "erk:", 4) == 0 ? c->method + 4 : c->method;
  snprintf(e->name, sizeof e->name, "%s", c->method);
  int hc = esf_dem_ode_check(s, c->method, 1, c->rtol > 0, err);
  if (!hc) hc = esf_dem_ode_periodic(s, c->method, err);
  if (hc) return hc;
  if (SUNContext_Create(NULL, &e->ctx))
    return esf_fail(err, ESF_EINTERNAL, "cannot create a SUNDIALS context");
  int own = strcmp(c->method, "erk") == 0 && c->table.s > 0;
  if (own)
    e->table = scene_table(&c->table);
  else if (strcmp(tname, "rk4") == 0)
    e->table = rk4_table();
  else
    e->table = load_table(tname);
  if (e->table) e->table = fix_fsal(e->table);
  if (!e->table) {
    char list[1024] = "";
    for (size_t k = 0; k < sizeof erk_tables / sizeof erk_tables[0]; k++) {
      size_t l = strlen(list);
      snprintf(list + l, sizeof list - l, "%s%s", k ? ", " : "", erk_tables[k].name + 7);
    }
    return esf_fail(err, ESF_EINPUT,
                    "%s: integrator.method: '%s' is not an explicit Runge-Kutta table "
                    "of SUNDIALS 6.4: give rk4, erk with integrator.table, or "
                    "erk:ARKODE_<NAME>, NAME one of %s",
                    esf_config_where(c, "integrator.method"), c->method, list);
  }
  int adaptive = c->rtol > 0;
  e->own = !adaptive && !c->erk_arkode; /* the driver, chosen here only */
  if (adaptive && !e->table->d)
    return esf_fail(err, ESF_EINPUT,
                    "%s: integrator.method: %s has no embedded error estimate: it runs "
                    "with a fixed step only (set integrator.rtol: 0 and give dt or frac)",
                    esf_config_where(c, "integrator.method"), c->method);
  esf_dem_ode_init(&e->ode, s, e->name);
  int rc = esf_sim_refresh(s, NULL, err);
  if (rc) return rc;
  e->y = esf_dem_ode_vector(esf_dem_ode_layout(&e->ode), &e->ode.path.threads, e->ctx);
  if (!e->y) return esf_fail(err, ESF_ENOMEM, "out of memory");
  esf_dem_ode_pack(&e->ode, NULL, N_VGetArrayPointer(e->y));
  rc = esf_dem_ode_start(&e->ode, N_VGetArrayPointer(e->y), err);
  if (rc) return rc;
  double w2 = (c->dim == 2 ? 6.0 : 7.0) * s->dte.k_max / s->dte.m_min;
  double r = stability_radius(e->table, s->dte.xi);
  e->r_stab = r;
  e->h_stab = (r > 0.05 && w2 > 0) ? r / sqrt(w2) : -1.0;
  if (adaptive) {
    e->atol =
        esf_dem_ode_vector((size_t)N_VGetLength(e->y), &e->ode.path.threads, e->ctx);
    e->ysave = N_VClone(e->y);
    if (!e->atol || !e->ysave) return esf_fail(err, ESF_ENOMEM, "out of memory");
    esf_dem_ode_atol(&e->ode, N_VGetArrayPointer(e->atol), c->rtol, c->atol);
  }
  rc = erk_mem_create(e, s->dt, err);
  if (rc) return rc;
  esf_sim_log(s,
              "%s%s: %d stages, order %d%s; stability radius %.3f along the xi = %.3f "
              "ray, omega_max %.4g rad/s: h_stab %.4g s; %s (%s); history %s%s",
              c->method, own ? " (the scene's table)" : "", e->table->stages, e->table->q,
              e->table->d ? " with an embedding" : "", e->r_stab, s->dte.xi, sqrt(w2),
              e->h_stab, adaptive ? "adaptive" : "fixed step",
              e->own ? "esfera's fixed-step driver" : "ARKODE's ERKStep",
              esf_history_names[c->history],
              c->roots ? "; steps end at contact onset and separation (roots)" : "");
  return ESF_OK;
}

/* History as state: after a commit and a possible list rebuild, y is rebuilt from the
 * committed history; when it differs from the integrator's (values or length) the
 * integrator restarts on it (ERKStepResize keeps the step size; the tolerance vector
 * and the retry copy follow the length). */
static int erk_sync(erk *e, int *restarted, esf_error *err) {
  esf_sim *s = e->ode.s;
  size_t old = e->ode.len, len = esf_dem_ode_layout(&e->ode);
  N_Vector yn =
      len == old ? N_VClone(e->y) : esf_dem_ode_vector(len, &e->ode.path.threads, e->ctx);
  if (!yn) return esf_fail(err, ESF_ENOMEM, "out of memory");
  const double *y = N_VGetArrayPointer(e->y);
  double *ny = N_VGetArrayPointer(yn);
  esf_dem_ode_pack(&e->ode, y + 9 * e->ode.n, ny);
  int same = len == old;
  for (size_t j = 9 * e->ode.n + e->ode.nq; same && j < len; j++)
    same = ny[j] == y[j]; /* by value: -0 and 0 are the same history */
  if (same) {
    N_VDestroy(yn);
    return ESF_OK;
  }
  N_VDestroy(e->y);
  e->y = yn;
  if (e->own ? own_start(e, 0) != 0
             : ERKStepResize(e->mem, e->y, 1.0, s->t, NULL, NULL) != ARK_SUCCESS)
    return esf_fail(err, ESF_EINTERNAL, "%s: the restart on a new state failed", e->name);
  e->resizes++;
  *restarted = 1;
  if (e->atol && len != old) {
    N_VDestroy(e->atol);
    N_VDestroy(e->ysave);
    e->atol = N_VClone(e->y);
    e->ysave = N_VClone(e->y);
    if (!e->atol || !e->ysave) return esf_fail(err, ESF_ENOMEM, "out of memory");
    esf_dem_ode_atol(&e->ode, N_VGetArrayPointer(e->atol), s->cfg.rtol, s->cfg.atol);
  }
  if (e->atol) ERKStepSVtolerances(e->mem, s->cfg.rtol, e->atol);
  return ESF_OK;
}

/* A located event at t_ev inside the step just taken: the step is undone and redone
 * from its start to end exactly at t_ev (events off until then), so that the
 * non-smoothness falls on a step boundary. An event at the step's very start (the one
 * just landed on) is only stepped over. */
static int erk_redo(erk *e, double t_ev, esf_error *err) {
  esf_sim *s = e->ode.s;
  N_VScale(1.0, e->ysave, e->y);
  e->roots_off = 1;
  if (t_ev - s->t > 1e-6 * s->dte.crit[ESF_DT_HART]) {
    e->t_event = t_ev;
    e->events++;
    ERKStepSetInitStep(e->mem, t_ev - s->t);
  } else {
    e->t_event = s->t; /* events back on after the next step */
  }
  if (erk_roots_init(e, 1, 1) || ERKStepReset(e->mem, s->t, e->y) != ARK_SUCCESS)
    return esf_fail(err, ESF_EINTERNAL, "%s: cannot restart at an event", e->name);
  return ESF_OK;
}

/* ERKStep of SUNDIALS 6.4 does not retry after a recoverable failure of f; an adaptive
 * run does it here: back to the last accepted state, a quarter of the step, up to 20
 * times in a row and down to 1e-6 of the critical step; past that (the failure is
 * physical, not numerical) and in fixed-step runs, the run stops with its message.
 * Order per call: one internal step to at most t_stop (or the pending event), commit,
 * list refresh, then (history as state) the restart on the rebuilt y and (roots) the
 * event functions for the new lists. */
static int erk_step(esf_sim *s, void *state, double t_stop, esf_error *err) {
  erk *e = state;
  int adaptive = s->cfg.rtol > 0;
  double t_to = t_stop;
  if (e->roots_off && e->t_event > s->t && e->t_event < t_to) t_to = e->t_event;
  if (adaptive) {
    ERKStepSetStopTime(e->mem, t_to);
    N_VScale(1.0, e->y, e->ysave);
  }
  realtype tret = 0;
  int flag = 0;
  if (e->own) {
    esf_error_clear(&e->ode.err);
    int r = own_step(e, &tret);
    if (r)
      return fail_flag(e, err, r < 0 ? ARK_RHSFUNC_FAIL : ARK_UNREC_RHSFUNC_ERR, "step");
  }
  for (int attempt = 0; !e->own; attempt++) {
    esf_error_clear(&e->ode.err);
    flag = ERKStepEvolve(e->mem, t_to, e->y, &tret, ARK_ONE_STEP);
    if (flag >= 0 || !adaptive || !e->ode.err.code || attempt == 20) break;
    realtype h = 0;
    ERKStepGetCurrentStep(e->mem, &h);
    if (0.25 * h < 1e-6 * s->dte.crit[ESF_DT_HART]) break; /* cannot recover */
    N_VScale(1.0, e->ysave, e->y);
    ERKStepSetInitStep(e->mem, 0.25 * h);
    if (ERKStepReset(e->mem, s->t, e->y) != ARK_SUCCESS) break;
    e->retries++;
  }
  if (flag < 0) return fail_flag(e, err, flag, "step");
  if (flag == ARK_ROOT_RETURN) return erk_redo(e, tret, err);
  int rc = e->committed
               ? ESF_OK
               : esf_dem_ode_commit(&e->ode, tret, N_VGetArrayPointer(e->y), err);
  if (rc) return rc;
  e->merged += e->committed;
  e->committed = 0;
  s->step++;
  if (!adaptive) s->t = (double)s->step * s->dt; /* fixed step: exact times */
  int events_back = e->roots_off && tret >= e->t_event;
  if (events_back) e->roots_off = 0;
  size_t n_before = s->p.n;
  int rebuilt = 0, restarted = 0;
  rc = esf_sim_refresh(s, &rebuilt, err);
  if (!rc && s->p.n != n_before)
    rc = esf_fail(err, ESF_EINPUT,
                  "%s: %s: particles left the domain at t = %.6g s; removal is "
                  "supported by the leapfrog only in this version",
                  esf_config_where(&s->cfg, "integrator.method"), e->name, s->t);
  if (!rc && e->ode.state) rc = erk_sync(e, &restarted, err);
  if (!rc && s->cfg.roots && erk_roots_init(e, rebuilt || events_back, restarted))
    rc = esf_fail(err, ESF_EINTERNAL, "%s: ERKStepRootInit failed", e->name);
  return rc;
}

/* ARKODE's counters, those of memories freed at checkpoints included. */
static void mem_counters(const erk *e, long v[6]) {
  long x[6] = {e->nst, e->nst, 0, e->nfe, 0, 0}; /* esfera's driver's */
  if (e->mem) {
    ERKStepGetNumSteps(e->mem, &x[0]);
    ERKStepGetNumStepAttempts(e->mem, &x[1]);
    ERKStepGetNumErrTestFails(e->mem, &x[2]);
    ERKStepGetNumRhsEvals(e->mem, &x[3]);
    ERKStepGetNumAccSteps(e->mem, &x[4]);
    ERKStepGetNumExpSteps(e->mem, &x[5]);
  }
  for (int k = 0; k < 6; k++) v[k] = e->base[k] + x[k];
}

/* Checkpoints. ARKODE 6.4 exposes neither its step-size controller's error history
 * nor a way to set it, so a resumed ERKStep cannot continue the old one's controller.
 * Instead the run that writes a checkpoint restarts ARKODE here: a new ERKStep memory at
 * the same (t, y) with the step size ARKODE proposed next (ERKStepGetCurrentStep), and
 * a resumed run builds its memory from exactly the same values, so both continue
 * identically (bitwise). Cost per checkpoint: one extra rhs evaluation (the first
 * stage is not reused) and a controller without history for the next step or two. */
typedef struct erk_saved {
  double h, t_save, t_event, t_commit, el_t0, slip_r;
  int64_t len, has_atol, retries, resizes, events, roots_off, nrhs, ncommit, nfail;
  int64_t base[6];
} erk_saved;

static int erk_save(esf_sim *s, void *state, esf_blob *out, esf_error *err) {
  erk *e = state;
  erk_saved v = {0};
  realtype h = s->dt;
  if (s->cfg.rtol > 0) ERKStepGetCurrentStep(e->mem, &h);
  long cnt[6];
  mem_counters(e, cnt);
  v.h = h;
  v.t_save = e->t_save;
  v.t_event = e->t_event;
  v.t_commit = e->ode.t_commit;
  v.el_t0 = e->ode.el_t0;
  v.slip_r = e->ode.slip_r;
  v.len = (int64_t)e->ode.len;
  v.has_atol = e->atol != NULL;
  v.retries = e->retries;
  v.resizes = e->resizes;
  v.events = e->events;
  v.roots_off = e->roots_off;
  v.nrhs = e->ode.nrhs;
  v.ncommit = e->ode.ncommit;
  v.nfail = e->ode.nfail;
  for (int k = 0; k < 6; k++) v.base[k] = cnt[k];
  esf_blob_put(out, &v, sizeof v);
  esf_blob_put(out, N_VGetArrayPointer(e->y), e->ode.len * sizeof(double));
  if (e->atol)
    esf_blob_put(out, N_VGetArrayPointer(e->atol), e->ode.len * sizeof(double));
  if (s->cfg.table.s > 0) /* the scene's table, for the resumed run to compare */
    esf_blob_put(out, &s->cfg.table, sizeof s->cfg.table);
  /* the restart both runs make */
  if (e->mem) ERKStepFree(&e->mem);
  for (int k = 0; k < 6; k++) e->base[k] = cnt[k];
  return erk_mem_create(e, h, err);
}

static int erk_restore(esf_sim *s, void *state, esf_blob_in *in, esf_error *err) {
  erk *e = state;
  erk_saved v;
  if (esf_blob_get(in, &v, sizeof v))
    return esf_fail(err, ESF_EINPUT, "%s: the saved state is cut short", e->name);
  e->ode.n = s->p.n;
  size_t len = esf_dem_ode_layout(&e->ode);
  size_t own = s->cfg.table.s > 0 ? sizeof s->cfg.table : 0;
  if ((size_t)v.len != len || (v.has_atol != 0) != (s->cfg.rtol > 0) ||
      in->n - in->pos != (v.has_atol ? 2 : 1) * len * sizeof(double) + own)
    return esf_fail(err, ESF_EINPUT,
                    "%s: the saved ODE state has %lld entries, the restored lists need "
                    "%zu",
                    e->name, (long long)v.len, len);
  const double tv[] = {v.h, v.t_save, v.t_event, v.t_commit, v.el_t0, v.slip_r};
  int ok = v.h > 0 && v.retries >= 0 && v.resizes >= 0 && v.events >= 0 &&
           (v.roots_off == 0 || v.roots_off == 1) && v.nrhs >= 0 && v.ncommit >= 0 &&
           v.nfail >= 0;
  for (int k = 0; k < 6; k++) ok = ok && isfinite(tv[k]);
  for (int k = 0; k < 6; k++) ok = ok && v.base[k] >= 0;
  if (!ok)
    return esf_fail(err, ESF_EINPUT,
                    "%s: the saved step, times or counters are out of range", e->name);
  N_VDestroy(e->y);
  e->y = esf_dem_ode_vector(len, &e->ode.path.threads, e->ctx);
  if (!e->y) return esf_fail(err, ESF_ENOMEM, "out of memory");
  esf_blob_get(in, N_VGetArrayPointer(e->y), len * sizeof(double));
  const double *y = N_VGetArrayPointer(e->y);
  for (size_t j = 0; j < len && ok; j++) ok = isfinite(y[j]);
  if (!ok || memcmp(y, s->p.y, 9 * s->p.n * sizeof(double)) != 0)
    return esf_fail(err, ESF_EINPUT,
                    "%s: the saved ODE state is not finite or not the particles' state",
                    e->name);
  if (e->atol) {
    N_VDestroy(e->atol);
    N_VDestroy(e->ysave);
    e->atol = N_VClone(e->y);
    e->ysave = N_VClone(e->y);
    if (!e->atol || !e->ysave) return esf_fail(err, ESF_ENOMEM, "out of memory");
    esf_blob_get(in, N_VGetArrayPointer(e->atol), len * sizeof(double));
    const double *a = N_VGetArrayPointer(e->atol);
    for (size_t j = 0; j < len; j++)
      if (!(a[j] > 0) || !isfinite(a[j]))
        return esf_fail(err, ESF_EINPUT, "%s: a saved tolerance is not positive",
                        e->name);
  }
  esf_butcher saved;
  if (own && (esf_blob_get(in, &saved, sizeof saved) ||
              memcmp(&saved, &s->cfg.table, sizeof saved) != 0))
    return esf_fail(err, ESF_EINPUT,
                    "%s: integrator.table: the scene's Butcher table differs from the "
                    "one the checkpoint was written with",
                    esf_config_where(&s->cfg, "integrator.table"));
  e->t_save = v.t_save;
  e->t_event = v.t_event;
  e->ode.t_commit = v.t_commit;
  e->ode.el_t0 = v.el_t0;
  e->ode.slip_r = v.slip_r;
  e->retries = v.retries;
  e->resizes = v.resizes;
  e->events = v.events;
  e->roots_off = (int)v.roots_off;
  e->ode.nrhs = v.nrhs;
  e->ode.ncommit = v.ncommit;
  e->ode.nfail = v.nfail;
  for (int k = 0; k < 6; k++) e->base[k] = v.base[k];
  if (e->mem) ERKStepFree(&e->mem);
  return erk_mem_create(e, v.h, err);
}

static void erk_stats(const esf_sim *s, void *state, esf_integ_stats *o) {
  erk *e = state;
  memset(o, 0, sizeof *o);
  long v[6];
  mem_counters(e, v);
  o->steps = v[0];
  o->attempts = v[1];
  o->rejected = v[2] + e->retries;
  o->rhs_evals = v[3] + e->ode.ncommit;
  o->merged = e->merged;
  o->acc_limited = v[4];
  o->stab_limited = v[5];
  realtype h = e->nst > 0 ? s->dt : 0.0;
  if (e->mem) ERKStepGetLastStep(e->mem, &h);
  o->h_last = h;
  o->h_stab = e->h_stab > 0 ? e->h_stab : 0.0;
  o->events = e->events;
  o->restarts = e->resizes;
}

static void erk_destroy(void **state) {
  erk *e = *state;
  if (e) {
    if (e->mem) ERKStepFree(&e->mem);
    own_free(e);
    if (e->y) N_VDestroy(e->y);
    if (e->atol) N_VDestroy(e->atol);
    if (e->ysave) N_VDestroy(e->ysave);
    if (e->table) ARKodeButcherTable_Free(e->table);
    if (e->ctx) SUNContext_Free(&e->ctx);
    esf_dem_ode_free(&e->ode);
  }
  free(e);
  *state = NULL;
}

const esf_integrator_type esf_integrator_erk = {
    .name = "erk",
    .summary = "erk:<TABLE>, rk4, or erk with integrator.table: SUNDIALS ARKODE explicit "
               "Runge-Kutta, fixed step or "
               "adaptive (rtol, atol) with the DEM stability bound",
    .order = 0, /* the table's */
    .flags = ESF_INTEG_FIXED_STEP | ESF_INTEG_ADAPTIVE,
    .create = erk_create,
    .step = erk_step,
    .destroy = erk_destroy,
    .stats = erk_stats,
    .save = erk_save,
    .restore = erk_restore,
};
