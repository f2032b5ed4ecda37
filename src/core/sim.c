/* sim.c — the simulation object's own operations: the configuration's defaults and the
 * places of its keys in the scene (for located messages), the run's log, syncing the
 * fused step's forces into p.f and p.t, and removing the particles that left the domain
 * (their energy booked as removed). Setting a sim up from a filled scene and tearing it
 * down is model/setup.c's. */
#include "core/sim.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/lines.h"
#include "util/vec3.h"

const char *const esf_history_names[] = {"frozen", "state", NULL};

void esf_config_default(esf_config *c) {
  memset(c, 0, sizeof *c);
  snprintf(c->name, sizeof c->name, "scene");
  c->dim = 3;
  c->threads = 0; /* all available */
  c->fused = 1;
  c->disk_thickness = 1.0;
  v3_set(c->gravity, 0, 0, -9.81);
  snprintf(c->method, sizeof c->method, "leapfrog");
  c->dt_auto = 1;
  c->dt_rule = ESF_DT_HART;
  c->frac = 0.1;
  c->stability = ESF_STAB_AUTO;
  c->stability_every = ESF_STAB_EVERY;
  c->local_form = ESF_LOCAL_OFF;
  c->autod.a_fac = 0.95;
  c->autod.a_mul = 1.1;
  c->autod.alpha_min = -1; /* set from the contact frequency at set-up */
  c->autod.alpha_max = -1;
  c->tframe = ESF_TFRAME_ROTATE;
  c->wall_lever = ESF_WALL_LEVER_SEED;
  c->rtol = 0;
  c->atol = 1e-9;
  c->history = ESF_HIST_FROZEN;
  c->max_steps = 100000000;
  c->max_overlap = 0.5;
  c->hertz_damping = 0;
  c->impact_speed = 1.0;
  c->skin = -1;
  c->reorder = 1;
  c->out_every = 0;
  c->energy_every = 0;
}

const char *esf_config_where(const esf_config *c, const char *key) {
  const char *best = NULL;
  size_t best_len = 0;
  for (int k = 0; k < c->nwhere; k++) {
    const char *w = c->where[k].key;
    size_t l = strlen(w);
    int match = strcmp(w, key) == 0;
    int parent = l == 0 || (strncmp(w, key, l) == 0 && key[l] == '.');
    if (match) return c->where[k].place;
    if (parent && (!best || l >= best_len)) {
      best = c->where[k].place;
      best_len = l;
    }
  }
  return best ? best : c->source[0] ? c->source : "the scene";
}

void esf_config_set_where(esf_config *c, const char *key, const char *place) {
  int k = 0;
  while (k < c->nwhere && strcmp(c->where[k].key, key) != 0) k++;
  if (k == ESF_WHERE_N) return;
  if (k == c->nwhere) c->nwhere++;
  snprintf(c->where[k].key, sizeof c->where[k].key, "%s", key);
  snprintf(c->where[k].place, sizeof c->where[k].place, "%s", place);
}

void esf_sim_log(const esf_sim *s, const char *fmt, ...) {
  if (!s->log) return;
  va_list ap;
  va_start(ap, fmt);
  vfprintf(s->log, fmt, ap);
  va_end(ap);
  fputc('\n', s->log);
}

int esf_sim_forces_room(esf_sim *s, esf_error *err) {
  esf_particles *p = &s->p;
  if (p->f && p->t) return ESF_OK;
  const size_t m = p->n ? 3 * p->n : 3;
  free(p->f);
  free(p->t);
  p->f = calloc(m, sizeof *p->f);
  p->t = calloc(m, sizeof *p->t);
  if (!p->f || !p->t) {
    esf_sim_forces_release(s);
    return esf_fail(err, ESF_ENOMEM, "out of memory for the forces of %zu particles",
                    p->n);
  }
  return ESF_OK;
}

void esf_sim_forces_release(esf_sim *s) {
  free(s->p.f);
  free(s->p.t);
  s->p.f = s->p.t = NULL;
}

int esf_sim_forces_sync(esf_sim *s, esf_error *err) {
  int rc = esf_sim_forces_room(s, err);
  const double *a = s->ft_lazy;
  if (rc || !a) return rc;
  esf_particles *p = &s->p;
  for (size_t i = 0; i < p->n; i++) {
    v3_copy(p->f + 3 * i, a + ESF_FT_STRIDE * i);
    v3_copy(p->t + 3 * i, a + ESF_FT_STRIDE * i + 4);
  }
  s->ft_lazy = NULL;
  return ESF_OK;
}

int esf_sim_remove_escaped(esf_sim *s, esf_error *err) {
  if (!s->cfg.has_domain) return ESF_OK;
  esf_particles *p = &s->p;
  const double *lo = s->cfg.keep_lo, *hi = s->cfg.keep_hi; /* periodic axes: open */
  size_t out = 0;
  for (size_t i = 0; i < p->n; i++) out += (size_t)v3_outside(p->x + 3 * i, lo, hi);
  if (!out) return ESF_OK;
  int rc = esf_sim_forces_sync(s, err); /* compaction carries p.f, p.t along */
  if (rc) return rc;
  unsigned char *keep = malloc(p->n);
  size_t *remap = malloc(p->n * sizeof *remap);
  if (!keep || !remap) {
    free(keep);
    free(remap);
    return esf_fail(err, ESF_ENOMEM, "out of memory");
  }
  for (size_t i = 0; i < p->n; i++) {
    const double *x = p->x + 3 * i;
    keep[i] = (unsigned char)!v3_outside(x, lo, hi);
    if (!keep[i]) {
      const double *v = p->v + 3 * i, *w = p->w + 3 * i;
      double ek = 0.5 * p->mass[i] * v3_norm2(v) + 0.5 * p->inertia[i] * v3_norm2(w);
      double ep = -p->mass[i] * v3_dot(s->cfg.gravity, x);
      if (s->led.started) s->led.e_removed += ek + ep; /* else not in e0 either */
      esf_sim_log(s,
                  "t = %.6g s: particle id %lld left the domain at (%g, %g, %g); removed",
                  s->t, (long long)p->id[i], x[0], x[1], x[2]);
    }
  }
  size_t n_old = p->n;
  rc = esf_particles_compact(p, keep, remap, err);
  if (!rc) esf_neighbor_remap(&s->nb, remap, n_old);
  free(keep);
  free(remap);
  if (rc) return rc;
  s->removed += (long)out;
  return ESF_OK;
}

int esf_sim_ledger_room(esf_sim *s, int zero, esf_error *err) {
  const size_t n = s->p.n;
  s->led_lr = esf_ledger_lr(s->mats.any_rolling);
  if (n > s->led_cap || !s->led_rows) {
    const size_t cap = n > 64 ? n + n / 4 : 64;
    double *r = esf_lines_realloc(s->led_rows, 0, cap * ESF_LR * sizeof(double));
    /* (room for the rolling rows; a scene uses esf_ledger_lr of them a particle) */
    if (!r) return esf_fail(err, ESF_ENOMEM, "out of memory for the energy ledger");
    s->led_rows = r;
    double *b = realloc(s->led_blocks, esf_ledger_nblocks(cap) * ESF_LB_N * sizeof *b);
    if (!b) return esf_fail(err, ESF_ENOMEM, "out of memory for the energy ledger");
    s->led_blocks = b;
    s->led_cap = cap;
  }
  if (!zero) return ESF_OK;
  memset(s->led_rows, 0, n * s->led_lr * sizeof(double));
  memset(s->led_blocks, 0, esf_ledger_nblocks(n) * ESF_LB_N * sizeof(double));
  return ESF_OK;
}

void esf_sim_damping_sums(const double *blocks, size_t nb, esf_xsum acc[2]) {
  esf_xsum_add_n(&acc[0], blocks + ESF_LB_KO, nb, ESF_LB_N);
  esf_xsum_add_n(&acc[1], blocks + ESF_LB_KT, nb, ESF_LB_N);
  esf_xsum_add_n(&acc[1], blocks + ESF_LB_KR, nb, ESF_LB_N);
}

void esf_sim_damping_apply(esf_sim *s, double ke_old, double ke_new) {
  const double a =
      esf_auto_damping_update(&s->cfg.autod, s->alpha_r, ke_old, ke_new, s->dt);
  const double ratio = s->alpha_r > 0 ? a / s->alpha_r : 1.0;
  s->alpha_r = a;
  s->alpha_t *= ratio;
}

void esf_sim_adapt_damping(esf_sim *s, const double *blocks, size_t nb) {
  esf_xsum acc[2];
  esf_xsum_zero(&acc[0]);
  esf_xsum_zero(&acc[1]);
  esf_sim_damping_sums(blocks, nb, acc);
  esf_sim_damping_apply(s, esf_xsum_value(&acc[0]), esf_xsum_value(&acc[1]));
}
