/* cvode_adams.c — SUNDIALS CVODE's variable-order, variable-step Adams-Moulton method
 * (orders 1-12) on the DEM right-hand side (dem_ode.h), with the fixed-point nonlinear
 * solver (no Jacobian: the DEM right-hand side is non-stiff at the steps Adams takes).
 * Always adaptive: rtol (integrator.rtol, default 1e-6 when 0) and atol on x, v, w; the
 * ledger quadratures take part in the error test (esf_dem_ode_qtol). Each step() takes
 * one internal step (CV_ONE_STEP) not past t_stop, then commits the contact history. The
 * commit changes f's derivative (not its value) at the step's end, which the multistep
 * history sees as non-smoothness: the cost of that is one of the testbed's results. */
#include <cvode/cvode.h>
#include <math.h>
#include <nvector/nvector_serial.h>
#include <stdlib.h>
#include <string.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include "integrators/dem_ode.h"
#include "integrators/integrator.h"
#include "model/model.h"

typedef struct cvadams {
  SUNContext ctx;
  void *mem;
  N_Vector y, atol;
  SUNNonlinearSolver nls;
  esf_dem_ode ode;
} cvadams;

static int cv_rhs(realtype t, N_Vector y, N_Vector ydot, void *data) {
  cvadams *c = data;
  return esf_dem_ode_rhs(&c->ode, t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
}

static int cv_fail(cvadams *c, esf_error *err, int flag) {
  esf_sim *s = c->ode.s;
  realtype h = 0, t = 0;
  CVodeGetCurrentStep(c->mem, &h);
  CVodeGetCurrentTime(c->mem, &t);
  if (c->ode.err.code)
    return esf_fail(err, ESF_ENUMERIC,
                    "cvode-adams failed at t = %.6g s with step %.4g s (critical dt %.4g "
                    "s): %s",
                    t, h, s->dte.crit[s->cfg.dt_rule], c->ode.err.msg);
  return esf_fail(err, ESF_ENUMERIC,
                  "cvode-adams failed at t = %.6g s with step %.4g s: %s", t, h,
                  CVodeGetReturnFlagName(flag));
}

static int cv_create(esf_sim *s, void **state, esf_error *err) {
  const esf_config *cf = &s->cfg;
  cvadams *c = calloc(1, sizeof *c);
  if (!c) return esf_fail(err, ESF_ENOMEM, "out of memory");
  *state = c;
  int hc = esf_dem_ode_check(s, "cvode-adams", 0, 0, err);
  if (!hc) hc = esf_dem_ode_periodic(s, "cvode-adams", err);
  if (hc) return hc;
  if (SUNContext_Create(NULL, &c->ctx))
    return esf_fail(err, ESF_EINTERNAL, "cannot create a SUNDIALS context");
  esf_dem_ode_init(&c->ode, s, "cvode-adams");
  int rc = esf_sim_refresh(s, NULL, err);
  if (rc) return rc;
  sunindextype len = (sunindextype)esf_dem_ode_layout(&c->ode);
  c->y = esf_dem_ode_vector((size_t)len, &c->ode.path.threads, c->ctx);
  c->atol = esf_dem_ode_vector((size_t)len, &c->ode.path.threads, c->ctx);
  if (!c->y || !c->atol) return esf_fail(err, ESF_ENOMEM, "out of memory");
  esf_dem_ode_pack(&c->ode, NULL, N_VGetArrayPointer(c->y));
  rc = esf_dem_ode_start(&c->ode, N_VGetArrayPointer(c->y), err);
  if (rc) return rc;
  c->mem = CVodeCreate(CV_ADAMS, c->ctx);
  if (!c->mem || CVodeInit(c->mem, cv_rhs, s->t, c->y))
    return esf_fail(err, ESF_EINTERNAL, "CVodeCreate/CVodeInit failed");
  CVodeSetUserData(c->mem, c);
  CVodeSetErrHandlerFn(c->mem, esf_sundials_silent, NULL);
  double rtol = cf->rtol > 0 ? cf->rtol : 1e-6;
  esf_dem_ode_atol(&c->ode, N_VGetArrayPointer(c->atol), rtol, cf->atol);
  CVodeSVtolerances(c->mem, rtol, c->atol);
  c->nls = SUNNonlinSol_FixedPoint(c->y, 0, c->ctx);
  if (!c->nls || CVodeSetNonlinearSolver(c->mem, c->nls))
    return esf_fail(err, ESF_EINTERNAL, "cannot attach the fixed-point solver");
  CVodeSetMaxNumSteps(c->mem, cf->max_steps);
  CVodeSetInitStep(c->mem, s->dt);
  CVodeSetMaxStep(c->mem, 10.0 * s->dte.crit[ESF_DT_HART]);
  esf_sim_log(s, "cvode-adams: rtol %.3g, atol %.3g, fixed-point nonlinear solver",
              cf->rtol > 0 ? cf->rtol : 1e-6, cf->atol);
  return ESF_OK;
}

static int cv_step(esf_sim *s, void *state, double t_stop, esf_error *err) {
  cvadams *c = state;
  CVodeSetStopTime(c->mem, t_stop);
  realtype tret = 0;
  esf_error_clear(&c->ode.err);
  int flag = CVode(c->mem, t_stop, c->y, &tret, CV_ONE_STEP);
  if (flag < 0) return cv_fail(c, err, flag);
  int rc = esf_dem_ode_commit(&c->ode, tret, N_VGetArrayPointer(c->y), err);
  if (rc) return rc;
  s->step++;
  size_t n_before = s->p.n;
  rc = esf_sim_refresh(s, NULL, err);
  if (!rc && s->p.n != n_before)
    rc = esf_fail(err, ESF_EINPUT,
                  "%s: cvode-adams: particles left the domain at t = %.6g s; removal "
                  "is supported by the leapfrog only in this version",
                  esf_config_where(&s->cfg, "integrator.method"), s->t);
  return rc;
}

static void cv_stats(const esf_sim *s, void *state, esf_integ_stats *o) {
  (void)s;
  cvadams *c = state;
  memset(o, 0, sizeof *o);
  long v = 0;
  CVodeGetNumSteps(c->mem, &v);
  o->steps = v;
  CVodeGetNumErrTestFails(c->mem, &v);
  o->rejected = v;
  o->attempts = o->steps + o->rejected;
  CVodeGetNumRhsEvals(c->mem, &v);
  o->rhs_evals = v + c->ode.ncommit;
  o->acc_limited = o->steps;
  realtype h = 0;
  CVodeGetLastStep(c->mem, &h);
  o->h_last = h;
}

static void cv_destroy(void **state) {
  cvadams *c = *state;
  if (c) {
    if (c->mem) CVodeFree(&c->mem);
    if (c->nls) SUNNonlinSolFree(c->nls);
    if (c->y) N_VDestroy(c->y);
    if (c->atol) N_VDestroy(c->atol);
    if (c->ctx) SUNContext_Free(&c->ctx);
    esf_dem_ode_free(&c->ode);
  }
  free(c);
  *state = NULL;
}

const esf_integrator_type esf_integrator_cvode = {
    .name = "cvode-adams",
    .summary =
        "SUNDIALS CVODE variable-order Adams with the fixed-point solver; adaptive "
        "(rtol, atol)",
    .order = 0, /* variable, 1-12 */
    .flags = ESF_INTEG_ADAPTIVE,
    .create = cv_create,
    .step = cv_step,
    .destroy = cv_destroy,
    .stats = cv_stats,
};
