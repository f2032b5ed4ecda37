/* stability_guard.c — when the leapfrog checks its stability, and what it says
 * (stability.h, docs/physics.md#live-stability-check).
 *
 * A check at every cfg.stability_every-th step (step 0 included) and at the run's end;
 * the estimate is stability.c's lambda of dt^2 A + 2 dt B, stable below 4. Above it the
 * run stops (ESF_ENUMERIC) naming the step, the top mode's particles, dt and the step
 * at which that mode would be stable, with what to change; with `stability: warn` the
 * log gets one warning and the run goes on; `off` never checks. The first check logs
 * lambda, the top mode and its limit; the summary reports the largest lambda / 4. The
 * checks read the state and change nothing, so results do not depend on them.
 * esf_stability_runaway, at every list rebuild: no particle may travel more than
 * ESF_RUNAWAY_TRAVEL of its radius (or turn as many radians) in one step. */
#include <limits.h>
#include <math.h>
#include <stdio.h>

#include "model/stability.h"
#include "util/clock.h"
#include "util/vec3.h"

long esf_stability_steps_left(const esf_sim *s) {
  if (s->cfg.stability == ESF_STAB_OFF) return LONG_MAX;
  long e = s->cfg.stability_every, r = s->step % e;
  return r == 0 ? e : e - r;
}

static void describe(char *buf, size_t n, const esf_stability *st) {
  if (st->other >= 0)
    snprintf(buf, n, "particle id %lld against particle id %lld", (long long)st->id,
             (long long)st->other);
  else if (st->other == -1)
    snprintf(buf, n, "particle id %lld against a wall", (long long)st->id);
  else
    snprintf(buf, n, "particle id %lld", (long long)st->id);
}

int esf_stability_guard(esf_sim *s, int final, esf_error *err) {
  const esf_config *c = &s->cfg;
  if (c->stability == ESF_STAB_OFF || s->p.n == 0) return ESF_OK;
  if (!final && s->step % c->stability_every != 0) return ESF_OK;
  double t0 = esf_now_s();
  esf_stability st;
  int first = !isfinite(s->stab.dt_limit); /* no check with contacts yet */
  int rc = esf_stability_estimate(s, s->dt, first, &st, err);
  if (!rc && st.lambda >= 4 && !first) rc = esf_stability_estimate(s, s->dt, 1, &st, err);
  if (rc) return rc;
  s->stab.checks++;
  s->stab.worst = fmax(s->stab.worst, st.lambda / 4);
  s->stab.seconds += esf_now_s() - t0;
  char who[128];
  describe(who, sizeof who, &st);
  if (first && (st.contacts || s->stab.checks == 1)) {
    s->stab.dt_limit = st.dt_limit;
    if (st.contacts)
      esf_sim_log(s,
                  "stability check at step %ld: lambda %.4g of 4 (%zu contacts, %d "
                  "Lanczos steps); top mode %.6g rad/s, damping ratio %.3g, stable below "
                  "dt = %.6g s (%.3g x dt; %s); every %ld steps",
                  s->step, st.lambda, st.contacts, st.iters, st.omega, st.xi, st.dt_limit,
                  st.dt_limit / s->dt, who, c->stability_every);
    else
      esf_sim_log(s, "stability check at step %ld: no contacts yet; every %ld steps",
                  s->step, c->stability_every);
  }
  if (!(st.lambda >= 4)) return ESF_OK;
  double crit = s->dte.crit[c->dt_rule];
  if (c->stability == ESF_STAB_WARN) {
    if (!s->stab.warned)
      esf_sim_log(s,
                  "WARNING: step %ld (t = %.6g s): the leapfrog is unstable at dt = %.6g "
                  "s: the contact network's fastest mode (%s; %.6g rad/s, damping ratio "
                  "%.3g) needs dt < %.6g s (lambda %.4g >= 4); going on "
                  "(integrator.stability: warn). Further instability is not logged",
                  s->step, s->t, s->dt, who, st.omega, st.xi, st.dt_limit, st.lambda);
    s->stab.warned = 1;
    return ESF_OK;
  }
  return esf_fail(err, ESF_ENUMERIC,
                  "step %ld (t = %.6g s): the leapfrog is unstable at dt = %.6g s: the "
                  "contact network's fastest mode (%s; %.6g rad/s, damping ratio %.3g, "
                  "rotations and dashpots included) needs dt < %.6g s (lambda %.4g >= 4; "
                  "docs/physics.md#live-stability-check). The '%s' rule's critical dt is "
                  "%.6g s: use integrator.frac <= %.3g with it (or dt <= %.4g s). "
                  "integrator.stability: warn runs on regardless",
                  s->step, s->t, s->dt, who, st.omega, st.xi, st.dt_limit, st.lambda,
                  esf_dt_rule_names[c->dt_rule], crit, 0.9 * st.dt_limit / crit,
                  0.9 * st.dt_limit);
}

int esf_stability_runaway(const esf_sim *s, esf_error *err) {
  const esf_particles *p = &s->p;
  const double dt = s->dt;
  size_t worst = SIZE_MAX;
  double big = ESF_RUNAWAY_TRAVEL, spin = 0;
  for (size_t i = 0; i < p->n; i++) {
    double tr = sqrt(v3_norm2(p->v + 3 * i)) * dt / p->radius[i];
    double an = sqrt(v3_norm2(p->w + 3 * i)) * dt;
    if (!(tr <= big && an <= big)) { /* NaN too */
      big = isfinite(fmax(tr, an)) ? fmax(tr, an) : INFINITY;
      spin = an, worst = i;
    }
  }
  if (worst == SIZE_MAX) return ESF_OK;
  const double *v = p->v + 3 * worst, *w = p->w + 3 * worst;
  char what[96], lim[96] = "";
  if (spin >= big)
    snprintf(what, sizeof what, "turns %.3g rad", spin);
  else
    snprintf(what, sizeof what, "moves %.3g of its radius",
             sqrt(v3_norm2(v)) * dt / p->radius[worst]);
  if (isfinite(s->stab.dt_limit))
    snprintf(lim, sizeof lim, "; the live check's limit at its first check: %.4g s",
             s->stab.dt_limit);
  return esf_fail(
      err, ESF_ENUMERIC,
      "step %ld (t = %.6g s): particle id %lld %s in one step of dt = %.4g s, "
      "critical dt (%s) = %.4g s (speed %.4g m/s, spin %.4g rad/s): contacts "
      "would be skipped (the limit is %.2g of a radius, or radian, a step). "
      "The run has run away (unstable%s) or dt is too large for the speeds "
      "in the scene. Lower integrator.frac or dt",
      s->step, s->t, (long long)p->id[worst], what, dt, esf_dt_rule_names[s->cfg.dt_rule],
      s->dte.crit[s->cfg.dt_rule], sqrt(v3_norm2(v)), sqrt(v3_norm2(w)),
      ESF_RUNAWAY_TRAVEL, lim);
}
