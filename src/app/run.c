/* run.c — the time loop of `esfera run`.
 *
 * Before any file is written: the step count (at most ESF_STEPS_MAX), the output
 * folder (another run's results only with --overwrite) and the scheme's set-up, so bad
 * input leaves nothing behind. Schedule: frames at t = 0, every cfg.out_every (rounded
 * to whole steps) and at the end; energy rows every cfg.energy_every (whole steps;
 * adaptive runs: at the first step past each time, however small the interval). After
 * each ledger row the balance is checked: energy appearing from nothing beyond a quarter
 * of the run's energy budget (the stored energy at the start plus everything dissipated,
 * the change of potential energy, the wall and fluid work) means the integration is
 * unstable, and the run stops with the step, the dt and the critical dt. log.txt and
 * energy.csv are line-buffered: whole lines reach them. Wall time is measured around
 * the loop alone (set-up excluded), as LAMMPS's "Loop time". */
#include "app/run.h"
#include "util/clock.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "ckpt/run_ckpt.h"
#include "model/stability.h"
#include "output/contact_net.h"
#include "output/frames.h"
#include "output/wall_loads.h"
#include "par/par.h"
#include "util/vec3.h"
#include "util/version.h"

int esf_mkdirs(const char *path, esf_error *err) {
  char buf[1024];
  if (snprintf(buf, sizeof buf, "%s", path) >= (int)sizeof buf)
    return esf_fail(err, ESF_EIO, "output path too long: %s", path);
  for (char *c = buf + 1;; c++) {
    if (*c == '/' || *c == '\0') {
      char keep = *c;
      *c = '\0';
      if (mkdir(buf, 0777) != 0 && errno != EEXIST)
        return esf_fail(err, ESF_EIO, "cannot create directory '%s': %s", buf,
                        strerror(errno));
      *c = keep;
      if (!keep) break;
    }
  }
  struct stat sb;
  if (stat(path, &sb) != 0 || !S_ISDIR(sb.st_mode))
    return esf_fail(err, ESF_EIO, "'%s' is not a directory", path);
  return ESF_OK;
}

/* The contact law of every material pair: laws are chosen per pair (material.c), so
 * the log names each, e.g. "contact laws: glass-glass linear, glass-steel linear". */
static void log_laws(const esf_sim *s) {
  const esf_materials *mt = &s->mats;
  char line[1024] = "contact laws:";
  size_t len = strlen(line);
  const char *sep = "";
  for (int a = 0; a < mt->n; a++)
    for (int b = a; b < mt->n && len < sizeof line; b++, sep = ",")
      len += (size_t)snprintf(line + len, sizeof line - len, "%s %s-%s %s", sep,
                              mt->m[a].name, mt->m[b].name,
                              mt->pair[a * mt->n + b].law->name);
  esf_sim_log(s, "%s", line);
}

static void log_setup(const esf_sim *s, const esf_integrator_type *it) {
  const esf_config *c = &s->cfg;
  esf_sim_log(s, "esfera %s", ESF_VERSION);
  esf_sim_log(s, "scene: %s (%s), %dD, %zu particles, %d materials, %zu wall elements",
              c->name, c->source, c->dim, s->p.n, s->mats.n, s->walls.n);
  esf_sim_log(s, "integrator: %s (order %d): %s", it->name, it->order, it->summary);
  esf_sim_log(s, "threads: %d (%s)", c->threads,
              c->threads_auto ? "all available: OMP_NUM_THREADS or the CPU affinity; "
                                "--threads N to choose"
                              : "--threads");
  esf_sim_log(s,
              "critical dt (FRAC = 1): cundall %.6g s, hart %.6g s, damped %.6g s "
              "(m_min %.6g kg, k_max %.6g N/m, damping ratio %.4g)",
              s->dte.crit[0], s->dte.crit[1], s->dte.crit[2], s->dte.m_min, s->dte.k_max,
              s->dte.xi);
  if (s->mats.all_hertz) /* docs/physics.md#time-step */
    esf_sim_log(s,
                "Hertz-Mindlin: k_max at the peak overlap of an impact at %.6g m/s; "
                "rayleigh %.6g s, collision time %.6g s",
                c->impact_speed, s->dte.crit[ESF_DT_RAYLEIGH],
                s->dte.crit[ESF_DT_COLLISION]);
  esf_sim_log(s, "dt used: %.6g s = %.4g x the %s critical dt (%.6g s)%s", s->dt,
              s->dt / s->dte.crit[c->dt_rule], esf_dt_rule_names[c->dt_rule],
              s->dte.crit[c->dt_rule], c->dt_auto ? " (dt: auto)" : "");
  if (s->dt > s->dte.crit[c->dt_rule])
    esf_sim_log(s,
                "WARNING: dt is %.4g x the '%s' rule's critical step, allowed by "
                "integrator.allow_unstable: true",
                s->dt / s->dte.crit[c->dt_rule], esf_dt_rule_names[c->dt_rule]);
  esf_sim_log(s,
              "damping: global alpha_r %.6g 1/s, alpha_t %.6g 1/s%s; local %s %.4g; "
              "Rayleigh beta %.6g s",
              s->alpha_r, s->alpha_t, c->autod.on ? " (adaptive)" : "",
              s->local ? s->local->name : "off", c->local_coef, s->beta);
  log_laws(s);
  esf_sim_log(s, "tangential frame: %s; skin %.6g m",
              c->tframe == ESF_TFRAME_ROTATE ? "rotate (seed)" : "project", c->skin);
  for (int a = 0; s->bonds.on && a < s->mats.n; a++)
    for (int b = a; b < s->mats.n; b++) {
      const esf_pair_params *pp = &s->mats.pair[a * s->mats.n + b];
      const esf_adhesion *A = &pp->adh;
      if (pp->law->flags & ESF_LAW_TENSION)
        esf_sim_log(s,
                    "adhesive law %s-%s: F %.6g N, epsilon %.6g, delta %.6g m, alpha "
                    "%.6g 1/m, peak tension at u %.6g m, rupture at u %.6g m, rest u "
                    "%.6g m, largest tangent stiffness %.6g N/m",
                    s->mats.m[a].name, s->mats.m[b].name, A->F, A->eps, A->delta,
                    A->alpha, A->u_peak, A->u_rupture, A->u_eq, A->k_max);
    }
  if (it->flags & ESF_INTEG_HALF_STEP_V)
    esf_sim_log(s, "note: frame velocities are the half-step ones, v(t - dt/2); energy "
                   "rows: kinetic at t + dt/2, elastic at t");
}

/* The ledger's residual against the energy that flowed (dissipated, wall and fluid
 * work, removed; docs/physics.md#failure-detection): above ESF_RESID_WARN of it (and
 * 1e-3 of the budget) a warning, logged and printed once; above ESF_RESID_STOP of it
 * (and 1e-2 of the budget), or energy from nothing beyond a quarter of the budget, the
 * run stops. Stable runs of the shipped scenes stay below 0.02 (docs/physics.md). */
#define ESF_RESID_WARN 0.05
#define ESF_RESID_STOP 0.25
static int check_energy(esf_sim *s, int *warned, esf_error *err) {
  const esf_ledger *L = &s->led;
  double err_e = esf_ledger_total_error(L);
  double flow = fabs(esf_ledger_dissipated(L)) + fabs(L->w_walls) + fabs(L->w_fluid) +
                fabs(L->e_removed) + fabs(L->w_stiff);
  double budget = fabs(L->e0) + fabs(L->d_normal) + fabs(L->d_tangential) +
                  fabs(L->d_friction) + fabs(L->d_global) + fabs(L->d_local) +
                  fabs(L->w_walls) + fabs(L->e_removed) + fabs(L->pot_g) + fabs(L->el_n) +
                  fabs(L->el_t) + fabs(L->d_bonds);
  budget += fabs(L->w_fluid);                   /* the fluid force (drag.c) */
  budget += fabs(L->el_r) + fabs(L->d_rolling); /* rolling resistance */
  budget += fabs(L->w_stiff);                   /* Hertz tangential stiffness changes */
  double r = fabs(err_e), ratio = flow > 0 ? r / flow : INFINITY;
  int from_nothing = err_e > 0.25 * budget && err_e > 1e-30;
  int stop = ratio > ESF_RESID_STOP && r > 1e-2 * budget;
  if (!from_nothing && !stop && isfinite(err_e)) {
    if (ratio > ESF_RESID_WARN && r > 1e-3 * budget && !*warned) {
      *warned = 1;
      char msg[600];
      snprintf(
          msg, sizeof msg,
          "WARNING: step %ld (t = %.6g s): the energy balance is off by %.4g J, %.3g "
          "of the %.4g J dissipated or exchanged (warning above %.2g, stop above "
          "%.2g): dt = %.4g s may be near the stability limit, or too coarse for "
          "the contacts; a smaller integrator.frac or dt is more accurate",
          s->step, s->t, err_e, ratio, flow, ESF_RESID_WARN, ESF_RESID_STOP, s->dt);
      esf_sim_log(s, "%s", msg);
      if (esf_par_rank(s) == 0) fprintf(stderr, "esfera: %s\n", msg);
    }
    return ESF_OK;
  }
  /* name the particle with the most kinetic energy: where the blow-up is */
  const esf_particles *p = &s->p;
  size_t worst = 0;
  double ek_max = -1;
  for (size_t i = 0; i < p->n; i++) {
    double ek =
        p->mass[i] * v3_norm2(p->v + 3 * i) + p->inertia[i] * v3_norm2(p->w + 3 * i);
    if (ek > ek_max) {
      ek_max = ek;
      worst = i;
    }
  }
  if (from_nothing || !isfinite(err_e))
    return esf_fail(err, ESF_ENUMERIC,
                    "step %ld (t = %.6g s): energy appeared from nothing: the balance "
                    "residual is %.4g J against an energy budget of %.4g J (fastest: "
                    "particle id %lld). The integration is unstable: dt = %.4g s, "
                    "critical dt (%s) = %.4g s. Lower integrator.frac or dt",
                    s->step, s->t, err_e, budget, p->n ? (long long)p->id[worst] : -1LL,
                    s->dt, esf_dt_rule_names[s->cfg.dt_rule],
                    s->dte.crit[s->cfg.dt_rule]);
  return esf_fail(
      err, ESF_ENUMERIC,
      "step %ld (t = %.6g s): the energy balance is off by %.4g J, %.3g of the "
      "%.4g J dissipated or exchanged (limit %.2g; fastest: particle id %lld): "
      "the integration is not accurate at dt = %.4g s (critical dt (%s) = "
      "%.4g s). Lower integrator.frac or dt",
      s->step, s->t, err_e, ratio, flow, ESF_RESID_STOP,
      p->n ? (long long)p->id[worst] : -1LL, s->dt, esf_dt_rule_names[s->cfg.dt_rule],
      s->dte.crit[s->cfg.dt_rule]);
}

/* A frame of the current state: particles, walls, and the contact network when the
 * scene asks for it (output.contacts). */
static int write_frame(esf_sim *s, esf_frames *fr, esf_contact_net *net, esf_error *err) {
  int rc = esf_sim_forces_sync(s, err);
  if (s->par) { /* MPI: the particles gathered on rank 0, which writes (par_io.c) */
    esf_particles all;
    rc = esf_par_agree(s, rc, err);
    if (!rc) rc = esf_par_gather(s, &all, err);
    rc = esf_par_agree(s, rc, err);
    if (!rc && esf_par_rank(s) == 0)
      rc = esf_frames_write(fr, s->t, &all, &s->walls, NULL, err);
    esf_particles_release(&all);
    rc = esf_par_bcast_status(s, rc, err);
  } else {
    if (!rc) rc = s->cfg.out_contacts ? esf_contact_net_build(s, 1, net, err) : ESF_OK;
    if (!rc)
      rc = esf_frames_write(fr, s->t, &s->p, &s->walls, s->cfg.out_contacts ? net : NULL,
                            err);
  }
  if (!rc && s->bonds.on && !s->bonds.pending) { /* bond counts per frame (bonds.h) */
    const long alive = esf_bonds_alive(s), broken = esf_bonds_broken(s);
    esf_sim_log(s, "frame t = %.6g s: %ld bonds intact, %ld broken", s->t, alive, broken);
  }
  return rc;
}

/* An energy row: energy.csv and the /energy table of frames.h5. */
static int energy_row(const esf_sim *s, FILE *ef, esf_frames *fr, esf_error *err) {
  double row[ESF_LEDGER_NCOLS];
  esf_ledger_values(s->led_time, &s->led, s->alpha_r, row);
  esf_ledger_row(ef, s->led_time, &s->led, s->alpha_r);
  if (ef && ferror(ef)) /* line-buffered: the row's write() failed just now */
    return esf_fail(err, ESF_EIO, "cannot write energy.csv: %s", strerror(errno));
  return esf_frames_append_energy(fr, ESF_LEDGER_NCOLS, esf_ledger_columns, row, err);
}

/* The progress line: rates over the last few seconds (an exponential average with a
 * 5 s time constant), so that the ETA follows the run's current speed (a bed that
 * settles, particles that leave), and a resumed run's does not count the time before. */
typedef struct prog {
  double wall, t, psum;  /* at the last update */
  double rate_t, rate_p; /* simulated s and particle-steps per wall s; < 0: none yet */
} prog;

static void progress(const esf_sim *s, double t_end, double now, double psum, prog *g) {
  const double dw = now - g->wall;
  if (dw > 0) {
    const double a = 1.0 - exp(-dw / 5.0), rt = (s->t - g->t) / dw,
                 rp = (psum - g->psum) / dw;
    g->rate_t = g->rate_t < 0 ? rt : g->rate_t + a * (rt - g->rate_t);
    g->rate_p = g->rate_p < 0 ? rp : g->rate_p + a * (rp - g->rate_p);
  }
  g->wall = now;
  g->t = s->t;
  g->psum = psum;
  double frac = t_end > 0 ? s->t / t_end : 1.0;
  fprintf(stdout, "\r  t = %.4g s  %5.1f%%  %.3g particle-steps/s  ", s->t, 100.0 * frac,
          g->rate_p > 0 ? g->rate_p : 0.0);
  if (g->rate_t > 0)
    fprintf(stdout, "ETA %.0f s   ", (t_end - s->t) / g->rate_t);
  else
    fputs("ETA ?   ", stdout);
  fflush(stdout);
}

/* The fixed-step schedule: how many steps, and every how many an energy row, a frame,
 * a checkpoint and (progress) a look at the clock are due. */
typedef struct sched {
  long nsteps, every_e, every_f, every_c, every_s; /* every_s: output.stress_every */
  int progress;
} sched;

/* The first time of the schedule next, next + every, ... past t (adaptive runs). Steps
 * over many intervals at once, and past t itself when every is below the resolution of
 * t (an interval of 1e-300 s: a row every step), so that it always ends. */
static double schedule_next(double next, double every, double t) {
  for (int k = 0; next <= t && k < 64; k++) {
    const double nn = next + every;
    if (!(nn > next)) break; /* every is lost in next's rounding */
    next = nn;
  }
  if (next > t) return next;
  next = every * (floor(t / every) + 1.0);
  return next > t && isfinite(next) ? next : nextafter(t, INFINITY);
}

#define BURST_MAX 32 /* steps in one call at most: bounds the wait for a stop signal */

/* Steps a scheme may take in one call from step index n without passing one after
 * which the loop below has something to do (the same tests, step by step). */
static long steps_to_event(const sched *c, long n) {
  long j = n;
  for (; j < n + BURST_MAX - 1; j++) {
    const int last = j + 1 >= c->nsteps;
    if (last || (c->every_e && j % c->every_e == 0) ||
        (c->every_f && (j + 1) % c->every_f == 0) ||
        (c->every_c && (j + 1) % c->every_c == 0) ||
        (c->every_s && (j + 1) % c->every_s == 0) || (c->progress && (j & 63) == 0))
      break;
  }
  return j - n + 1;
}

/* Whole steps in an interval of t seconds at the step dt (0: none asked): at least 1,
 * at most ESF_STEPS_MAX (a count beyond the run's is never reached). */
static long steps_in(double t, double dt) {
  if (!(t > 0)) return 0;
  const double k = floor(t / dt + 0.5);
  return k < 1 ? 1 : k < ESF_STEPS_MAX ? (long)k : (long)ESF_STEPS_MAX;
}

/* The run's length: *nsteps fixed steps to *t_end, or adaptive steps to *t_end.
 * ESF_EINPUT, located, when the step count cannot be represented or would not end. */
static int plan(const esf_sim *s, int adaptive, long *nsteps, double *t_end,
                esf_error *err) {
  const esf_config *c = &s->cfg;
  if (c->steps > ESF_STEPS_MAX)
    return esf_fail(err, ESF_EINPUT,
                    "%s: run.steps: %ld steps is more than one run takes (%.0e); split "
                    "the run",
                    esf_config_where(c, "run.steps"), c->steps, ESF_STEPS_MAX);
  const double x = c->steps > 0 ? (double)c->steps : c->duration / s->dt - 1e-9;
  if (!adaptive && !(x <= ESF_STEPS_MAX))
    return esf_fail(err, ESF_EINPUT,
                    "%s: run.duration = %.6g s at dt = %.6g s is %.3g steps, more than "
                    "one run takes (%.0e) and more than it could finish: raise dt "
                    "(integrator.dt or frac) or shorten the run",
                    esf_config_where(c, "run.duration"), c->duration, s->dt, x,
                    ESF_STEPS_MAX);
  *nsteps = c->steps > 0 ? c->steps : adaptive ? 0 : (long)ceil(x);
  if (*nsteps < 1 && !adaptive) *nsteps = 1; /* a duration below one step: one step */
  *t_end = adaptive && c->duration > 0 ? c->duration : (double)*nsteps * s->dt;
  return ESF_OK;
}

/* A new run refuses a folder holding another run's results unless told to overwrite
 * them (--overwrite); --resume continues the run they belong to. */
static int check_out_dir(const char *dir, int overwrite, esf_error *err) {
  static const char *const names[] = {"frames.h5",  "frames.d",   "frames.xdmf",
                                      "energy.csv", "log.txt",    ESF_CKPT_NAME,
                                      "walls.csv",  "stress.csv", NULL};
  char found[256] = "", path[1200];
  struct stat sb;
  int ckpt = 0;
  for (int k = 0; names[k]; k++) {
    snprintf(path, sizeof path, "%s/%s", dir, names[k]);
    if (stat(path, &sb) != 0) continue;
    size_t l = strlen(found);
    snprintf(found + l, sizeof found - l, "%s%s", l ? ", " : "", names[k]);
    ckpt |= strcmp(names[k], ESF_CKPT_NAME) == 0;
  }
  if (!found[0] || overwrite) return ESF_OK;
  return esf_fail(err, ESF_EINPUT,
                  "the output folder '%s' holds another run's results (%s): give "
                  "--overwrite to replace them or --out with another folder%s%s%s",
                  dir, found, ckpt ? ", or continue that run with --resume " : "",
                  ckpt ? dir : "", ckpt ? " (its checkpoint)" : "");
}

/* Creates out_dir (and parents) and opens its log.txt (mode "w" or "a") line-buffered:
 * each line reaches the file as it is logged. */
static int open_log(const char *out_dir, const char *mode, FILE **logf, esf_error *err) {
  int rc = esf_mkdirs(out_dir, err);
  if (rc) return rc;
  char path[1200];
  snprintf(path, sizeof path, "%s/log.txt", out_dir);
  *logf = fopen(path, mode);
  if (!*logf)
    return esf_fail(err, ESF_EIO, "cannot write '%s': %s", path, strerror(errno));
  setvbuf(*logf, NULL, _IOLBF, 1 << 14);
  return ESF_OK;
}

int esf_run(esf_sim *s, const esf_run_opts *o, esf_run_stats *st, esf_error *err) {
  memset(st, 0, sizeof *st);
  const esf_integrator_type *it = esf_integrator_find(s->cfg.method);
  if (!it) return esf_fail(err, ESF_EINPUT, "unknown integrator '%s'", s->cfg.method);
  const int adaptive = (it->flags & ESF_INTEG_ADAPTIVE) && s->cfg.rtol > 0;
  long nsteps = 0;
  double t_end = 0;
  int rc = plan(s, adaptive, &nsteps, &t_end, err);
  if (!rc && o->scene && s->cfg.ckpt_every > 0 && !it->save)
    rc = esf_fail(err, ESF_EINPUT,
                  "%s: output.checkpoint_every: integrator %s cannot write checkpoints "
                  "(leapfrog and erk: methods can)",
                  esf_config_where(&s->cfg, "output.checkpoint_every"), s->cfg.method);
  if (!rc && adaptive && s->cfg.stress_every > 0)
    rc = esf_fail(err, ESF_EINPUT,
                  "%s: output.stress_every: needs fixed steps (integrator %s with rtol "
                  "takes adaptive ones); use the energy rows",
                  esf_config_where(&s->cfg, "output.stress_every"), s->cfg.method);
  const int root = esf_par_rank(s) == 0; /* MPI: rank 0 alone writes files */
  if (!rc && !o->resume && root) rc = check_out_dir(o->out_dir, o->overwrite, err);
  rc = esf_par_bcast_status(s, rc, err);
  if (rc) return rc;
  char path[1200];
  FILE *logf = NULL, *ef = NULL;
  esf_frames *fr = NULL;
  esf_contact_net net = {0};
  esf_load_out lo = {0}; /* walls.csv, stress.csv (wall_loads.h) */
  void *ist = NULL;
  esf_ckpt_run cr = {0};
  if (!o->resume) { /* a new run: the scheme is set up before any file is written, so
                       that bad input leaves nothing behind; its log waits in memory */
    char *early = NULL;
    size_t len = 0;
    FILE *mem = open_memstream(&early, &len);
    if (!mem) return esf_fail(err, ESF_ENOMEM, "out of memory for the log");
    s->log = mem;
    log_setup(s, it);
    rc = it->create(s, &ist, err);
    s->log = NULL;
    fclose(mem);
    if (!rc && root) rc = open_log(o->out_dir, "w", &logf, err);
    if (!rc && root && fwrite(early, 1, len, logf) != len)
      rc = esf_fail(err, ESF_EIO, "cannot write log.txt: %s", strerror(errno));
    free(early);
    if (s->par) rc = esf_par_bcast_status(s, rc, err);
    if (rc && !logf) {
      if (ist) it->destroy(&ist);
      return rc;
    }
  } else {
    rc = root ? open_log(o->out_dir, "a", &logf, err) : ESF_OK;
    rc = esf_par_bcast_status(s, rc, err);
    if (rc) return rc;
  }
  s->log = logf;
  if (rc) goto done;
  if (o->resume) { /* the state, then the outputs cut back to the checkpoint's */
    log_setup(s, it);
    rc = it->create(s, &ist, err);
    if (!rc) rc = esf_ckpt_restore(o->resume, s, it, ist, &cr, err);
    if (s->par) { /* MPI: every process restored the whole run; each keeps its part */
      rc = esf_par_agree(s, rc, err);
      if (!rc) rc = esf_par_agree(s, esf_par_resumed(s, err), err);
    }
    if (!rc && root) rc = esf_run_ckpt_reopen(o->out_dir, s, &cr, &ef, &fr, err);
    rc = esf_par_bcast_status(s, rc, err);
    if (rc) goto done;
    esf_sim_log(s,
                "resumed from checkpoint %ld at step %ld, t = %.9g s (%ld frames, %ld "
                "energy rows kept)",
                cr.count, s->step, s->t, cr.frames, cr.erows);
  } else {
    if (root)
      esf_run_ckpt_forget(o->out_dir); /* a new run: an old checkpoint no
                                          longer fits */
    if (s->led.on && root) {
      snprintf(path, sizeof path, "%s/energy.csv", o->out_dir);
      ef = fopen(path, "w");
      if (!ef) {
        rc = esf_fail(err, ESF_EIO, "cannot write '%s': %s", path, strerror(errno));
        goto done;
      }
      setvbuf(ef, NULL, _IOLBF, 1 << 14); /* one write() per whole row: a reader (or a
                                             kill) never meets half a row */
      esf_ledger_header(ef);
    }
    snprintf(path, sizeof path, "%s/frames.h5", o->out_dir);
    rc = root ? esf_frames_open(path, s->cfg.name, ESF_VERSION, &fr, err) : ESF_OK;
    rc = esf_par_bcast_status(s, rc, err);
    if (!rc) rc = write_frame(s, fr, &net, err);
  }
  /* load rows (walls.csv, stress.csv): at the energy rows, or every every_s steps */
  const long every_s = adaptive ? 0 : steps_in(s->cfg.stress_every, s->dt);
  const long lrows = every_s ? cr.n / every_s : cr.erows;
  if (!rc) rc = esf_load_out_open(o->out_dir, s, o->resume ? lrows : -1, &lo, err);
  if (rc) goto done;

  long every_e = steps_in(s->cfg.energy_every, s->dt);
  long every_f = steps_in(s->cfg.out_every, s->dt);
  if (adaptive)
    esf_sim_log(s,
                "run: adaptive steps to t = %.6g s; frames every %.6g s, energy rows "
                "every %.6g s",
                t_end, s->cfg.out_every, s->cfg.energy_every);
  else
    esf_sim_log(s,
                "run: %ld steps to t = %.6g s; frames every %ld steps, energy rows "
                "every %ld steps",
                nsteps, t_end, every_f, every_e);
  /* adaptive methods are not forced onto the output times (that would cap their
     steps): rows and frames are written at the first step at or past each time */
  double te = s->cfg.energy_every, tf = s->cfg.out_every;
  double next_e = te > 0 ? te : INFINITY, next_f = tf > 0 ? tf : INFINITY;
  /* checkpoints: like frames, every_c whole steps or at the first step past next_c */
  double tc = o->scene ? s->cfg.ckpt_every : 0.0, next_c = tc > 0 ? tc : INFINITY;
  long every_c = steps_in(tc, s->dt);
  long n0 = 0;
  if (o->resume) {
    n0 = cr.n;
    next_e = cr.next_e;
    next_f = cr.next_f;
    if (tc > 0 && adaptive) /* the schedule continues (checkpoint_every may change) */
      next_c = isfinite(cr.next_c) ? cr.next_c : s->t + tc;
  }
  const sched sc = {nsteps,  every_e, every_f,
                    every_c, every_s, o->progress && !o->quiet && !adaptive};
  const long step0 = s->step;
  double t0 = esf_now_s(), next_prog = t0 + 0.5, psum = cr.psum;
  const double psum0 = psum;
  prog pg = {t0, s->t, psum, -1.0, -1.0};
  st->stepping = 1;
  int resid_warned = 0;
  for (long n = n0; adaptive ? s->t < t_end * (1 - 1e-12) : n < nsteps; n++) {
    long step_before = s->step;
    s->burst = adaptive ? 1 : steps_to_event(&sc, n);
    rc = it->step(s, ist, t_end, err);
    s->burst = 1;
    if (rc) break;
    if (s->step == step_before) { /* no step taken (an ODE method redoing one) */
      n--;
      continue;
    }
    n += s->step - step_before - 1; /* a scheme may take several (s->burst) */
    psum += (double)esf_par_count(s) * (double)(s->step - step_before); /* no removal
                                                                            between */
    int row, frame;
    if (adaptive) {
      double tol = 1e-9 * t_end;
      row = te > 0 && (s->t >= next_e - tol || s->t >= t_end * (1 - 1e-12));
      frame = tf > 0 && s->t >= next_f - tol && s->t < t_end * (1 - 1e-12);
      if (te > 0) next_e = schedule_next(next_e, te, s->t + tol);
      if (tf > 0) next_f = schedule_next(next_f, tf, s->t + tol);
    } else {
      row = every_e && (n % every_e == 0 || n == nsteps - 1);
      frame = every_f && (n + 1) % every_f == 0 && n + 1 < nsteps;
    }
    if (row) {
      rc = root ? energy_row(s, ef, fr, err) : ESF_OK;
      if (s->par) rc = esf_par_bcast_status(s, rc, err);
      if (!rc && !every_s) rc = esf_load_out_row(s, &lo, err);
      if (!rc) rc = check_energy(s, &resid_warned, err);
      if (rc) break;
    }
    if (every_s && ((n + 1) % every_s == 0 || n == nsteps - 1)) { /* and the end */
      rc = esf_load_out_row(s, &lo, err);
      if (rc) break;
    }
    if (frame) {
      if (it->trim) it->trim(s, ist);
      rc = write_frame(s, fr, &net, err);
      if (rc) break;
    }
    int last = adaptive ? s->t >= t_end * (1 - 1e-12) : n + 1 >= nsteps;
    int ckpt = 0, stop = o->stop && *o->stop && !last;
    if (s->par) /* every process stops at the same step: asked every 16 */
      stop = (n & 15) == 15 && esf_par_any(s, stop) && !last;
    if (tc > 0 && adaptive) {
      double tol = 1e-9 * t_end;
      ckpt = s->t >= next_c - tol && !last;
      next_c = schedule_next(next_c, tc, s->t + tol);
    } else if (tc > 0) {
      ckpt = (n + 1) % every_c == 0 && !last;
    }
    if (ckpt || (stop && o->scene && it->save)) {
      cr.n = n + 1;
      cr.next_e = next_e;
      cr.next_f = next_f;
      cr.next_c = next_c;
      cr.psum = psum;
      rc = esf_load_out_sync(&lo, err); /* the rows the checkpoint counts */
      if (!rc && s->par) { /* MPI: the whole run gathered on rank 0, which writes */
        esf_sim view;
        rc = esf_par_view(s, &view, err);
        if (!rc && root)
          rc = esf_run_ckpt_save(o->out_dir, &view, it, ist, o->scene, &cr, ef, fr, err);
        esf_par_view_release(&view);
        rc = esf_par_bcast_status(s, rc, err);
        if (!rc && !root) cr.count++; /* as rank 0 counts it */
      } else if (!rc) {
        rc = esf_run_ckpt_save(o->out_dir, s, it, ist, o->scene, &cr, ef, fr, err);
      }
      if (rc) break;
      st->checkpoints++;
      st->stop_checkpoint = stop;
    }
    if (stop) {
      st->interrupted = 1;
      break;
    }
    if (o->progress && !o->quiet && (n & 63) == 0) {
      double tn = esf_now_s();
      if (tn >= next_prog) {
        progress(s, t_end, tn, psum, &pg);
        next_prog = tn + 0.25;
      }
    }
  }
  double wall = esf_now_s() - t0;
  if (o->progress && !o->quiet) {
    fputs("\r\033[K", stdout); /* before any message on stderr: flushed */
    fflush(stdout);
  }
  if (!rc && !st->interrupted && s->step == step0)
    rc = esf_fail(err, ESF_EINTERNAL,
                  "the run ended after 0 steps at t = %.9g s (end: t = %.9g s, %ld "
                  "steps of %.6g s asked)",
                  s->t, t_end, nsteps, s->dt);
  if (it->trim) it->trim(s, ist); /* the check's and the final frame's scratch alone */
  if (!rc && !st->interrupted && (it->flags & ESF_INTEG_STABILITY_CHECK))
    rc = esf_stability_guard(s, 1, err); /* the final state is checked too */
  if (s->stab.checks)
    esf_sim_log(s, "stability: %ld checks, largest lambda / 4 = %.4g, %.3f s",
                s->stab.checks, s->stab.worst, s->stab.seconds);
  st->steps = s->step;
  st->resumed_step = o->resume ? step0 : 0;
  st->wall_s = wall;
  st->particles_mean = s->step ? psum / (double)s->step : (double)esf_par_count(s);
  /* MPI: each process counted its own contacts (integers: exact in any order) */
  const double csum =
      s->par ? (double)esf_par_sum(s, (long long)s->contacts_sum) : s->contacts_sum;
  st->contacts_mean = s->step ? csum / (double)s->step : 0.0;
  st->rate = wall > 0 ? (psum - psum0) / wall : 0.0;
  st->checkpoints_total = cr.count;
  memset(&st->integ, 0, sizeof st->integ);
  if (ist && it->stats)
    it->stats(s, ist, &st->integ);
  else {
    st->integ.steps = st->integ.attempts = s->step;
    st->integ.rhs_evals = s->rhs_evals;
    st->integ.h_last = s->dt;
  }
  st->energy_error = s->led.on ? esf_ledger_total_error(&s->led) : 0.0;
  st->dissipated = s->led.on ? esf_ledger_dissipated(&s->led) : 0.0;
  if (!rc && !st->stop_checkpoint) rc = write_frame(s, fr, &net, err);
  if (!rc && st->interrupted && st->stop_checkpoint)
    esf_sim_log(s, "interrupted at step %ld, t = %.9g s: checkpoint %ld written", s->step,
                s->t, cr.count);
  else if (!rc && st->interrupted)
    esf_sim_log(s,
                "interrupted at step %ld, t = %.9g s: no checkpoint (%s cannot write "
                "them), the final frame written",
                s->step, s->t, s->cfg.method);
  if (!rc && fr)
    esf_sim_log(s,
                "output: %ld frames, %ld energy rows in frames.h5; %.3f s writing them",
                esf_frames_count(fr), esf_frames_energy_rows(fr), esf_frames_seconds(fr));
  if (!rc && s->par) {
    esf_par_stat ps;
    esf_par_stats(s, &ps);
    const double steps = (double)(s->step > 0 ? s->step : 1);
    esf_sim_log(s,
                "mpi: %d processes, %ld cuts, %lld particles migrated; the busiest "
                "process sent %.4g bytes (%.4g a step) and spent %.3f s exchanging or "
                "waiting; at the end at most %lld particles and %lld ghosts a process",
                esf_par_size(s), ps.rebuilds, ps.migrated, ps.bytes_max,
                ps.bytes_max / steps, ps.seconds_max, ps.own_max, ps.ghosts_max);
  }
  if (s->bonds.on) { /* MPI: from here on, bonds.broken holds every process's */
    if (!rc) s->bonds.broken = esf_bonds_broken(s);
    const long alive = !rc ? esf_bonds_alive(s) : 0;
    esf_sim_log(s,
                "bonds: %ld at the start, %ld broken, %ld intact; %.6g J released by "
                "ruptures",
                s->bonds.formed, s->bonds.broken, alive, s->led.d_bonds);
  }
  if (!rc)
    esf_sim_log(s,
                "done: %ld steps, %.3f s of loop, %.4g particle-steps/s, %ld list "
                "builds, %ld force evaluations, %ld particles removed; integrator: %ld "
                "steps, %ld attempts, %ld rejected, %ld rhs evaluations, %ld limited "
                "by accuracy, %ld by stability, last step %.4g s, %ld events located, "
                "%ld restarts",
                st->steps, wall, st->rate, s->nb.builds, s->rhs_evals, s->removed,
                st->integ.steps, st->integ.attempts, st->integ.rejected,
                st->integ.rhs_evals, st->integ.acc_limited, st->integ.stab_limited,
                st->integ.h_last, st->integ.events, st->integ.restarts);
  if (!rc && o->resume)
    esf_sim_log(s,
                "this invocation: steps %ld to %ld (the loop time and rate above cover "
                "these); %ld checkpoints since the run's start, %ld of them now",
                step0, s->step, cr.count, st->checkpoints);
done:
  if (ist) it->destroy(&ist);
  {
    esf_error e2;
    esf_error_clear(&e2);
    int rc2 = esf_frames_close(&fr, &e2);
    if (!rc && rc2) {
      rc = rc2;
      *err = e2;
    }
  }
  esf_contact_net_release(&net);
  esf_load_out_close(&lo);
  if (ef && (ferror(ef) | fclose(ef)) != 0 && !rc)
    rc = esf_fail(err, ESF_EIO, "cannot finish energy.csv: %s", strerror(errno));
  if (rc) esf_sim_log(s, "FAILED: %s", err->msg);
  s->log = NULL;
  if (logf && (ferror(logf) | fclose(logf)) != 0 && !rc)
    rc = esf_fail(err, ESF_EIO, "cannot finish log.txt: %s", strerror(errno));
  return rc;
}
