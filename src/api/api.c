/* api.c — the public C API (api/esfera.h, docs/library.md): one esf_handle holds one
 * esf_sim with its error, and drives it either with the scene's integrator (the
 * scheme's create and step, as the run driver calls them, without its files) or as the
 * ODE of integrators/dem_ode.h (the right-hand side the SUNDIALS methods integrate,
 * with history frozen at the last commit, the commit and the list refresh as
 * cvode_adams.c does them between steps). The handle remembers which of the two the
 * first call chose; the quadratures of the last committed y (Q, J) continue in y0.
 * A failure of open, step or commit leaves the handle failed: it then repeats that
 * message (the sim may be half-way through a step). Units: SI. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/ledger.h"
#include "core/sim.h"
#include "integrators/dem_ode.h"
#include "integrators/integrator.h"
#include "loads/insert.h"
#include "model/model.h"
#include "scene/scene.h"
#include "util/esf_error.h"
#include "util/version.h"

#include "api/esfera.h"

_Static_assert(ESF_ENERGY_COLUMNS == ESF_LEDGER_NCOLS, "energy columns");

enum { MODE_NONE, MODE_STEP, MODE_ODE };

struct esf_handle {
  esf_sim s;
  esf_error err;
  int set_up;   /* esf_sim_setup done (the integrator and the ODE view need it) */
  int failed;   /* open, a step or a commit failed: err holds why */
  int mode;     /* MODE_* */
  double t_end; /* the scene's end time, s */
  const esf_integrator_type *it;
  void *ist;
  esf_dem_ode ode;
  double q[ESF_ODE_QR + 1]; /* the quadratures of the last committed y (ode.nq) */
};

const char *esf_version(void) { return ESF_VERSION; }

int esf_api_version(void) { return ESF_API_VERSION; }

/* ESF_OK when the handle can take a call; clears the last message. */
static int usable(esf_handle *h) {
  if (!h) return ESF_EINPUT;
  if (h->failed) return h->err.code;
  esf_error_clear(&h->err);
  return ESF_OK;
}

static int poison(esf_handle *h, int rc) {
  if (rc) h->failed = 1;
  return rc;
}

int esf_handle_open(esf_handle **out, const char *scene, const char *const *sets,
                    int nsets) {
  esf_handle *h = calloc(1, sizeof *h);
  *out = h;
  if (!h) return ESF_ENOMEM;
  esf_error *err = &h->err;
  esf_sim *s = &h->s;
  int rc = ESF_OK;
  if (!scene || nsets < 0 || (nsets > 0 && !sets))
    rc = esf_fail(err, ESF_EINPUT,
                  "esf_handle_open: give a scene path and nsets >= 0 "
                  "overrides");
  if (!rc) rc = esf_scene_load(scene, sets, nsets, s, err);
  if (!rc && !(h->it = esf_integrator_find(s->cfg.method)))
    rc = esf_fail(err, ESF_EINPUT,
                  "%s: integrator.method: unknown method '%s' (`esfera --help` lists "
                  "them)",
                  esf_config_where(&s->cfg, "integrator.method"), s->cfg.method);
  if (!rc) rc = esf_sim_setup(s, err);
  if (!rc) {
    h->set_up = 1;
    const esf_config *c = &s->cfg;
    h->t_end = c->steps > 0 ? (double)c->steps * s->dt : c->duration;
  }
  return poison(h, rc);
}

void esf_handle_close(esf_handle **hp) {
  if (!hp || !*hp) return;
  esf_handle *h = *hp;
  if (h->ist) h->it->destroy(&h->ist);
  if (h->mode == MODE_ODE) esf_dem_ode_free(&h->ode);
  esf_sim_release(&h->s);
  free(h);
  *hp = NULL;
}

int esf_handle_status(const esf_handle *h) { return h ? h->err.code : ESF_EINPUT; }

const char *esf_handle_message(const esf_handle *h) {
  return h ? h->err.msg : "esf_handle_message: no handle (NULL)";
}

size_t esf_handle_count(const esf_handle *h) { return h ? h->s.p.n : 0; }
double esf_handle_time(const esf_handle *h) { return h ? h->s.t : NAN; }
double esf_handle_dt(const esf_handle *h) { return h ? h->s.dt : NAN; }
long esf_handle_steps(const esf_handle *h) { return h ? h->s.step : 0; }
double esf_handle_end_time(const esf_handle *h) { return h ? h->t_end : NAN; }
const char *esf_handle_method(const esf_handle *h) { return h ? h->s.cfg.method : ""; }
int esf_handle_dim(const esf_handle *h) { return h ? h->s.cfg.dim : 0; }

int esf_handle_set_threads(esf_handle *h, int n) {
  int rc = usable(h);
  if (rc) return rc;
  if (n < 1 || n > 1024)
    return esf_fail(&h->err, ESF_EINPUT,
                    "esf_handle_set_threads: %d threads: give 1 to "
                    "1024",
                    n);
  if (h->mode != MODE_NONE)
    return esf_fail(&h->err, ESF_EINPUT,
                    "esf_handle_set_threads: the handle has "
                    "started; set the threads before the first step or ODE call");
  h->s.cfg.threads = n;
  h->s.cfg.threads_auto = 0;
  return ESF_OK;
}

const double *esf_handle_array(esf_handle *h, int which, size_t *len) {
  *len = 0;
  if (!h || !h->set_up) return NULL;
  esf_particles *p = &h->s.p;
  if ((which == ESF_ARRAY_FORCE || which == ESF_ARRAY_TORQUE) &&
      esf_sim_forces_sync(&h->s, &h->err))
    return NULL;
  const double *a[ESF_ARRAY_COUNT] = {p->x, p->v,      p->w,    p->f,
                                      p->t, p->radius, p->mass, p->inertia};
  if (which < 0 || which >= ESF_ARRAY_COUNT) return NULL;
  *len = which <= ESF_ARRAY_TORQUE ? 3 * p->n : p->n;
  return a[which];
}

const int64_t *esf_handle_ids(const esf_handle *h) {
  return h && h->set_up ? h->s.p.id : NULL;
}

/* The ODE state's quadratures, in dem_ode.h's order: ESF_ODE_NQ in every scene, then
 * the rolling resistance's (ESF_ODE_QR) in scenes with it (esf_dem_ode.nq). */
static const char *const quadratures[] = {
    "dissipated_normal", "dissipated_tangential",
    "dissipated_global", "dissipated_local",
    "work_walls",        "work_tangential_springs",
    "work_fluid",        "work_tangential_stiffness",
    "dissipated_rolling"};
enum { NQ_ALL = (int)(sizeof quadratures / sizeof *quadratures) };
_Static_assert(NQ_ALL == ESF_ODE_NQ + 1 && ESF_ODE_QR == ESF_ODE_NQ,
               "a name for every quadrature of dem_ode.h");

const char *esf_ode_quadrature(int k) {
  return k >= 0 && k < NQ_ALL ? quadratures[k] : NULL;
}

const char *esf_energy_column(int k) {
  return k >= 0 && k < ESF_LEDGER_NCOLS ? esf_ledger_columns[k] : NULL;
}

int esf_handle_energies(esf_handle *h, double row[ESF_ENERGY_COLUMNS]) {
  int rc = usable(h);
  if (rc) return rc;
  const esf_sim *s = &h->s;
  if (!s->led.on)
    return esf_fail(&h->err, ESF_EINPUT,
                    "%s: output.energy_every: the energy ledger is off in this scene; "
                    "set output.energy_every to a positive interval (any: the library "
                    "keeps the ledger at every step)",
                    esf_config_where(&s->cfg, "output.energy_every"));
  if (!s->led.started)
    return esf_fail(&h->err, ESF_EINPUT,
                    "esf_handle_energies: the ledger starts with the first step or ODE "
                    "call (esf_handle_step, esf_handle_ode_size, esf_handle_y0)");
  esf_ledger_values(s->led_time, &s->led, s->alpha_r, row);
  return ESF_OK;
}

/* The handle's use is fixed by its first driving call. */
static int mode_conflict(esf_handle *h, int want) {
  static const char *const what[] = {"", "its integrator (esf_handle_step)",
                                     "the ODE view (esf_handle_y0, rhs, commit)"};
  return esf_fail(&h->err, ESF_EINPUT,
                  "this handle is driven by %s; %s cannot drive it too: open another "
                  "handle on the scene",
                  what[h->mode], what[want]);
}

int esf_handle_step(esf_handle *h, long k) {
  int rc = usable(h);
  if (rc) return rc;
  esf_sim *s = &h->s;
  esf_error *err = &h->err;
  if (h->mode == MODE_ODE) return mode_conflict(h, MODE_STEP);
  if (h->mode == MODE_NONE) {
    h->mode = MODE_STEP;
    rc = h->it->create(s, &h->ist, err);
    if (rc) return poison(h, rc);
  }
  const int adaptive = (h->it->flags & ESF_INTEG_ADAPTIVE) && s->cfg.rtol > 0;
  long taken = 0, idle = 0;
  while (taken < k) {
    if (adaptive && s->t >= h->t_end * (1 - 1e-12) && taken > 0) break; /* the end */
    if (adaptive && s->t >= h->t_end * (1 - 1e-12))
      return esf_fail(err, ESF_EINPUT,
                      "%s: run.duration: the adaptive method %s is at the scene's end "
                      "time t = %.9g s (open the scene with a longer run.duration to go "
                      "on)",
                      esf_config_where(&s->cfg, "run.duration"), s->cfg.method, s->t);
    /* fixed-step schemes ignore the stop time, or need it beyond this call's steps */
    double t_stop = adaptive ? h->t_end : fmax(h->t_end, s->t + (double)(k + 1) * s->dt);
    long before = s->step;
    s->burst = k - taken; /* the fused leapfrog may take them at once (same bits) */
    rc = h->it->step(s, h->ist, t_stop, err);
    s->burst = 1;
    if (rc) return poison(h, rc);
    taken += s->step - before;
    idle = s->step == before ? idle + 1 : 0; /* an ODE method redoing a step */
    if (idle > 1000)
      return poison(h, esf_fail(err, ESF_EINTERNAL, "%s: no step taken in 1000 calls",
                                s->cfg.method));
  }
  return ESF_OK;
}

/* The first ODE call: the ODE view of the sim, its first list build and the ledger's
 * start, as the SUNDIALS methods' create does them. */
static int ode_enter(esf_handle *h) {
  if (h->mode == MODE_ODE) return ESF_OK;
  if (h->mode == MODE_STEP) return mode_conflict(h, MODE_ODE);
  esf_sim *s = &h->s;
  h->mode = MODE_ODE;
  if (s->insert) /* the count would change under the ODE solver */
    return poison(h, esf_fail(&h->err, ESF_EINPUT,
                              "%s: particles inserted during the run change the "
                              "particle count, which the ODE view keeps fixed; take "
                              "steps with esf_handle_step (the leapfrog)",
                              s->insert->e[0].where));
  esf_dem_ode_init(&h->ode, s, "the ODE view");
  int rc = esf_sim_refresh(s, NULL, &h->err);
  if (rc) return poison(h, rc);
  size_t len = esf_dem_ode_layout(&h->ode);
  double *y = malloc(len * sizeof *y);
  if (!y) return poison(h, esf_fail(&h->err, ESF_ENOMEM, "out of memory"));
  esf_dem_ode_pack(&h->ode, NULL, y);
  rc = esf_dem_ode_start(&h->ode, y, &h->err);
  free(y);
  return poison(h, rc);
}

size_t esf_handle_ode_size(esf_handle *h) {
  if (usable(h) || ode_enter(h)) return 0;
  return h->ode.len;
}

size_t esf_handle_ode_nq(esf_handle *h) {
  if (usable(h) || ode_enter(h)) return 0;
  return h->ode.nq;
}

int esf_handle_y0(esf_handle *h, double *y) {
  int rc = usable(h);
  if (!rc) rc = ode_enter(h);
  if (rc) return rc;
  esf_dem_ode_pack(&h->ode, h->q, y);
  return ESF_OK;
}

int esf_handle_rhs(esf_handle *h, double t, const double *y, double *ydot) {
  int rc = usable(h);
  if (!rc) rc = ode_enter(h);
  if (rc) return rc;
  esf_error_clear(&h->ode.err);
  if (esf_dem_ode_rhs(&h->ode, t, y, ydot) == 0) return ESF_OK;
  return esf_fail(&h->err, h->ode.err.code ? h->ode.err.code : ESF_ENUMERIC, "%s",
                  h->ode.err.msg);
}

int esf_handle_commit(esf_handle *h, double t, const double *y) {
  int rc = usable(h);
  if (!rc) rc = ode_enter(h);
  if (rc) return rc;
  esf_sim *s = &h->s;
  if (!(t >= s->t))
    return esf_fail(&h->err, ESF_EINPUT,
                    "esf_handle_commit: t = %.17g s is before the last commit's %.17g s",
                    t, s->t);
  const size_t n = h->ode.n;
  rc = esf_dem_ode_commit(&h->ode, t, y, &h->err);
  if (rc) return poison(h, rc);
  memcpy(h->q, y + 9 * n, h->ode.nq * sizeof *h->q);
  s->step++;
  rc = esf_sim_refresh(s, NULL, &h->err);
  if (!rc && s->p.n != n)
    rc = esf_fail(&h->err, ESF_EINPUT,
                  "%s: particles left the domain at t = %.9g s; the ODE view keeps a "
                  "fixed particle count (drop domain, or widen it)",
                  esf_config_where(&s->cfg, "domain"), s->t);
  if (!rc) esf_dem_ode_layout(&h->ode);
  return poison(h, rc);
}
