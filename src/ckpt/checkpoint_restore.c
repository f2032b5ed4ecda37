/* checkpoint_restore.c — a loaded checkpoint back into a sim, and `esfera info` on
 * one (checkpoint.h).
 *
 * Restoring, on a sim set up from the stored scene (its overrides, then the resuming
 * command's) with the integrator created: the method, dt (bitwise), materials and pair
 * table, wall count and groups must equal the saved ones (else ESF_EINPUT: the
 * checkpoint does not fit). Then the particle arrays are replaced (n may differ from the
 * scene's: particles leave the domain); the scalars, rng and ledger set; moving walls
 * placed at the saved time (their placement is a function of time; servo walls' from
 * their saved displacement, with the events applied and the fluid's state, section
 * SAND, loads_ckpt.c) with the rebuild marks restored; the candidate lists built once
 * (which sizes every derived scratch array) and overwritten with the saved lists, xref
 * and build count; last the integrator's own state (integrator.h restore). Every count
 * read from the file is checked against its section's size and every index against what
 * it indexes, and every value against the scene and the other sections (the counters'
 * ranges, t against step x dt, the particles' radii, masses and materials against their
 * ids', finite numbers, sorted lists) before use, so that a file that passed its
 * checksums but does not fit fails cleanly (ESF_EINPUT). */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "ckpt/checkpoint_format.h"
#include "ckpt/loads_ckpt.h"
#include "loads/insert.h"
#include "scene/scene.h"

int esf_ckpt_load_scene(const esf_ckpt *c, const char *const *extra, int nextra,
                        esf_sim *s, esf_error *err) {
  esf_ckpt_scene sc;
  esf_ckpt_scene_of(c, &sc);
  esf_ydoc *doc = NULL;
  int rc = esf_ydoc_parse_as(sc.text, sc.len, sc.path, &doc, err);
  for (int k = 0; k < sc.nsets && !rc; k++) rc = esf_ydoc_override(doc, sc.sets[k], err);
  for (int k = 0; k < nextra && !rc; k++) rc = esf_ydoc_override(doc, extra[k], err);
  esf_config_default(&s->cfg);
  snprintf(s->cfg.source, sizeof s->cfg.source, "%s", sc.path);
  if (!rc) rc = esf_scene_read(doc, s, err);
  esf_ydoc_free(&doc);
  if (rc) esf_error_prefix(err, "the scene stored in %s: ", c->path);
  return rc;
}

static int mismatch(const esf_ckpt *c, esf_error *err, const char *what) {
  return esf_fail(err, ESF_EINPUT,
                  "%s does not fit its own scene: %s (written by another esfera "
                  "version?); cannot resume",
                  c->path, what);
}

static int invalid(const esf_ckpt *c, esf_error *err, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static int invalid(const esf_ckpt *c, esf_error *err, const char *fmt, ...) {
  char what[400];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(what, sizeof what, fmt, ap);
  va_end(ap);
  return esf_fail(err, ESF_EINPUT,
                  "%s does not fit its scene or itself: %s (the file passed its "
                  "checksums: changed by hand or written by another build?); cannot "
                  "resume",
                  c->path, what);
}

static int all_finite(const double *v, size_t n) {
  for (size_t k = 0; k < n; k++)
    if (!isfinite(v[k])) return 0;
  return 1;
}

/* The sim's scalars against the scene: n particles saved of the scene's n_scene. */
static int check_sim(const esf_ckpt *c, const esf_sim *s, const esf_integrator_type *it,
                     const ck_sim *cs, uint64_t n, size_t n_scene, esf_error *err) {
  const double v[] = {cs->t,       cs->led_time,     cs->alpha_r,
                      cs->alpha_t, cs->contacts_sum, cs->walls_t};
  if (!all_finite(v, sizeof v / sizeof *v))
    return invalid(c, err, "a time or rate in the SIM section is not finite");
  if (!(cs->step >= 1 && (double)cs->step <= ESF_STEPS_MAX))
    return invalid(c, err, "step %lld is out of range (1 to %.0e)", (long long)cs->step,
                   ESF_STEPS_MAX);
  const esf_config *cf = &s->cfg;
  const int adaptive = (it->flags & ESF_INTEG_ADAPTIVE) && cf->rtol > 0;
  const double nsteps =
      cf->steps > 0 ? (double)cf->steps : ceil(cf->duration / s->dt - 1e-9);
  const double t_end = adaptive && cf->duration > 0 ? cf->duration : nsteps * s->dt;
  if (!adaptive && cs->t != (double)cs->step * s->dt)
    return invalid(c, err, "t = %.17g s is not step %lld x dt %.17g s", cs->t,
                   (long long)cs->step, s->dt);
  if (!adaptive && (double)cs->step >= nsteps)
    return invalid(c, err, "step %lld is at or past the run's end (%.0f steps)",
                   (long long)cs->step, nsteps);
  if (!(cs->t > 0 && cs->t < t_end))
    return invalid(c, err, "t = %.17g s is not within the run (0 to %.17g s)", cs->t,
                   t_end);
  if (cs->removed < 0 || n + (uint64_t)cs->removed != n_scene)
    return invalid(c, err,
                   "%llu particles and %lld removed do not make the %zu the scene "
                   "defined and inserted",
                   (unsigned long long)n, (long long)cs->removed, n_scene);
  if (cs->rhs_evals < 0 || cs->builds < 0 || cs->bonds_formed < 0 ||
      cs->bonds_broken < 0 || cs->bonds_broken > cs->bonds_formed)
    return invalid(c, err,
                   "a counter of the SIM section is negative (or more bonds "
                   "broken than formed)");
  if (!(cs->alpha_r >= 0 && cs->alpha_t >= 0 && cs->contacts_sum >= 0 &&
        cs->led_time >= 0))
    return invalid(c, err, "negative global damping, contact sum or ledger time");
  return ESF_OK;
}

/* The particles read (p) against the scene's (sc; ids 0 to n_ids - 1, those that
 * started outside the domain already removed): every id once, each particle's radius,
 * mass, inertia and material its id's; finite state. */
/* The saved particles against the scene's sc (ids below n_ids), and those inserted
 * during the run (ids n_ids .. next_id - 1: radius, mass, inertia and material
 * plausible; each id once). */
static int check_particles(const esf_ckpt *c, const esf_particles *p,
                           const esf_particles *sc, size_t n_ids, size_t next_id,
                           int nmat, esf_error *err) {
  if (!all_finite(p->y, 9 * p->n) || !all_finite(p->f, 3 * p->n) ||
      !all_finite(p->t, 3 * p->n))
    return invalid(c, err,
                   "a particle's position, velocity, spin, force or torque is "
                   "not finite");
  size_t *at = calloc(next_id ? next_id : 1, sizeof *at); /* id -> scene index + 1 */
  if (!at) return esf_fail(err, ESF_ENOMEM, "out of memory");
  for (size_t j = n_ids; j < next_id; j++) at[j] = SIZE_MAX; /* inserted, not seen */
  for (size_t j = 0; j < sc->n; j++)
    if (sc->id[j] >= 0 && (uint64_t)sc->id[j] < n_ids) at[sc->id[j]] = j + 1;
  int rc = ESF_OK;
  for (size_t i = 0; i < p->n && !rc; i++) {
    const int64_t id = p->id[i];
    if (id < 0 || (uint64_t)id >= next_id || !at[id]) {
      rc = invalid(c, err, "particle id %lld is unknown to the scene or repeated",
                   (long long)id);
      break;
    }
    if (at[id] == SIZE_MAX) { /* inserted during the run */
      at[id] = 0;
      const double r = p->radius[i], m = p->mass[i], I = p->inertia[i];
      if (!(r > 0) || !(m > 0) || !(I > 0) || !isfinite(r) || !isfinite(m) ||
          !isfinite(I) || p->inv_mass[i] != 1.0 / m || p->inv_inertia[i] != 1.0 / I ||
          p->material[i] < 0 || p->material[i] >= nmat)
        rc = invalid(c, err,
                     "inserted particle id %lld has an invalid radius, mass, inertia "
                     "or material",
                     (long long)id);
      continue;
    }
    const size_t j = at[id] - 1;
    at[id] = 0; /* seen */
    if (p->radius[i] != sc->radius[j] || p->mass[i] != sc->mass[j] ||
        p->inv_mass[i] != sc->inv_mass[j] || p->inertia[i] != sc->inertia[j] ||
        p->inv_inertia[i] != sc->inv_inertia[j] || p->material[i] != sc->material[j])
      rc = invalid(c, err,
                   "particle id %lld has another radius, mass, inertia or material "
                   "than in the scene",
                   (long long)id);
  }
  free(at);
  return rc;
}

static int check_ledger(const esf_ckpt *c, const esf_sim *s, const esf_ledger *L,
                        esf_error *err) {
  if (L->on != s->led.on)
    return invalid(c, err, "the energy ledger is %s in it, %s in its scene",
                   L->on ? "on" : "off", s->led.on ? "on" : "off");
  const double v[] = {
      L->kin_t,        L->kin_r,      L->pot_g,    L->el_n,    L->el_t,      L->d_normal,
      L->d_tangential, L->d_friction, L->d_global, L->d_local, L->w_walls,   L->e_removed,
      L->d_bonds,      L->w_fluid,    L->e0,       L->el_r,    L->d_rolling, L->w_stiff};
  if ((L->started != 0 && L->started != 1) || !all_finite(v, sizeof v / sizeof *v))
    return invalid(c, err, "the energy ledger holds a non-finite value or flag");
  return ESF_OK;
}

/* The run loop's state against the step it was saved at. */
static int check_run(const esf_ckpt *c, const esf_sim *s, const esf_ckpt_run *r,
                     const ck_sim *cs, esf_error *err) {
  const long long step = (long long)cs->step;
  if (r->n != cs->step)
    return invalid(c, err, "its loop counter %ld is not its step %lld", r->n, step);
  if (isnan(r->next_e) || isnan(r->next_f) || isnan(r->next_c) || !isfinite(r->psum) ||
      r->psum < 0)
    return invalid(c, err, "the output schedule holds a value that is not a number");
  if (r->frames < 1 || r->frames > step + 1 || r->erows < 0 || r->erows > step + 1)
    return invalid(c, err,
                   "it counts %ld frames and %ld energy rows at step %lld (a run "
                   "writes at most one frame and one row a step)",
                   r->frames, r->erows, step);
  if ((r->csv_bytes >= 0) != (s->led.on != 0) || r->csv_bytes < -1)
    return invalid(c, err, "its size of energy.csv (%ld) does not fit the ledger (%s)",
                   r->csv_bytes, s->led.on ? "on" : "off");
  if (r->count < 1 || r->count > step)
    return invalid(c, err, "checkpoint number %ld at step %lld", r->count, step);
  return ESF_OK;
}

/* A list saved in the order the builder keeps (neighbor.c): by (a, b), each pair
 * once, a < b for particle pairs; finite histories, flags 0 or 1. */
static int check_contacts(const esf_ckpt *c, const esf_candidates *l, size_t m, int pairs,
                          esf_error *err) {
  for (size_t k = 0; k < m; k++) {
    const int order = k == 0 || l->a[k] > l->a[k - 1] ||
                      (l->a[k] == l->a[k - 1] && l->b[k] > l->b[k - 1]);
    if (!order || (pairs && l->a[k] >= l->b[k]))
      return invalid(c, err, "a contact list is not in the order of its build");
    if (l->touch[k] > 1 || !all_finite(l->h[k].xi, 3) || !all_finite(l->h[k].n, 3) ||
        (l->vc0 && !all_finite(l->vc0 + 3 * k, 3)) ||
        (l->wr0 && !all_finite(l->wr0 + 3 * k, 3)) ||
        (l->bond && (!isfinite(l->bond[k].s) || (uint32_t)l->bond[k].on > 1)) ||
        (l->roll && (!all_finite(l->roll[k].m, 3) || !isfinite(l->roll[k].t))))
      return invalid(c, err, "a contact's history or flags are not valid");
  }
  return ESF_OK;
}

static int get_contacts(const esf_ckpt *c, const char *tag, esf_candidates *dst,
                        size_t np, size_t nb_other, esf_error *err) {
  esf_blob_in in = esf_ckpt_sec(c, tag);
  uint64_t m = 0;
  uint8_t has_vc0 = 0, has_bond = 0, has_roll = 0;
  esf_blob_get(&in, &m, 8);
  esf_blob_get(&in, &has_vc0, 1);
  esf_blob_get(&in, &has_bond, 1);
  esf_blob_get(&in, &has_roll, 1);
  if (in.short_read || m > in.n ||
      (m > 0 &&
       ((has_vc0 != 0) != (dst->vc0 != NULL) || (has_bond != 0) != (dst->bond != NULL) ||
        (has_roll != 0) != (dst->roll != NULL))))
    return mismatch(c, err, "a contact list's header");
  esf_blob_get(&in, dst->a, m * sizeof *dst->a);
  esf_blob_get(&in, dst->b, m * sizeof *dst->b);
  esf_blob_get(&in, dst->h, m * sizeof *dst->h);
  esf_blob_get(&in, dst->touch, m * sizeof *dst->touch);
  if (has_vc0 && dst->vc0) esf_blob_get(&in, dst->vc0, 3 * m * sizeof *dst->vc0);
  if (has_vc0 && has_roll && dst->wr0)
    esf_blob_get(&in, dst->wr0, 3 * m * sizeof *dst->wr0);
  if (has_bond && dst->bond) esf_blob_get(&in, dst->bond, m * sizeof *dst->bond);
  if (has_roll && dst->roll) esf_blob_get(&in, dst->roll, m * sizeof *dst->roll);
  if (in.short_read || in.pos != in.n) return mismatch(c, err, "a contact list's size");
  for (uint64_t k = 0; k < m; k++)
    if (dst->a[k] >= np || dst->b[k] >= nb_other)
      return mismatch(c, err, "a contact names a particle or wall that does not exist");
  int rc = check_contacts(c, dst, (size_t)m, nb_other == np, err);
  dst->n = rc ? 0 : (size_t)m;
  return rc;
}

/* The PERIODIC section (periodic axes only): the particles' image counters, the
 * particle pairs' images (each in {-1, 0, 1}; -2 .. 2 on the flow axis of a
 * Lees-Edwards shear) and with the shear the list's offset reference and build time. */
static int get_periodic(const esf_ckpt *c, esf_sim *s, esf_error *err) {
  esf_blob_in in = esf_ckpt_sec(c, "PERIODIC");
  if (!s->cfg.per.any) return in.short_read ? ESF_OK : mismatch(c, err, "periodic axes");
  const size_t n = s->p.n, m = s->nb.pp.n, nle = s->cfg.per.le ? 2 : 0;
  if (in.short_read || !s->p.img || !s->nb.pp.img ||
      in.n != 3 * n * sizeof *s->p.img + 3 * m * sizeof *s->nb.pp.img + nle * 8)
    return mismatch(c, err, "the PERIODIC section");
  esf_blob_get(&in, s->p.img, 3 * n * sizeof *s->p.img);
  esf_blob_get(&in, s->nb.pp.img, 3 * m * sizeof *s->nb.pp.img);
  double le[2] = {0, 0};
  if (nle) esf_blob_get(&in, le, sizeof le);
  for (size_t k = 0; k < 3 * m; k++) {
    const int q = (int)(k % 3), lim = s->cfg.per.le && q == s->cfg.per.flow ? 2 : 1;
    if (abs(s->nb.pp.img[k]) > lim || (s->nb.pp.img[k] && !s->cfg.per.on[q]))
      return invalid(c, err, "a pair's periodic image is out of range");
  }
  if (!isfinite(le[0]) || !isfinite(le[1]))
    return invalid(c, err, "the Lees-Edwards offset is not finite");
  s->nb.pp.le_ref = le[0];
  s->nb.pp.le_tb = le[1];
  esf_neighbor_le_time(&s->nb, s->t);
  return ESF_OK;
}

int esf_ckpt_restore(const esf_ckpt *c, esf_sim *s, const esf_integrator_type *it,
                     void *ist, esf_ckpt_run *run, esf_error *err) {
  esf_blob_in in = esf_ckpt_sec(c, "METHOD");
  if (strcmp((const char *)in.d, s->cfg.method) != 0)
    return mismatch(c, err, "integrator.method differs");
  if (!it->restore) return mismatch(c, err, "the integrator cannot restore");
  ck_sim cs;
  in = esf_ckpt_sec(c, "SIM");
  if (esf_blob_get(&in, &cs, sizeof cs) || in.pos != in.n)
    return mismatch(c, err, "the SIM section's size");
  if (memcmp(&cs.dt, &s->dt, sizeof cs.dt) != 0) {
    char m[160];
    snprintf(m, sizeof m, "dt %.17g s saved, %.17g s from the scene", cs.dt, s->dt);
    return mismatch(c, err, m);
  }
  in = esf_ckpt_sec(c, "MATS");
  int32_t nm = 0;
  esf_blob_get(&in, &nm, 4);
  size_t mb = (size_t)s->mats.n * sizeof *s->mats.m;
  size_t pb = (size_t)s->mats.n * (size_t)s->mats.n * sizeof *s->mats.pair;
  const void *mm = nm == s->mats.n ? esf_blob_take(&in, mb) : NULL;
  const void *pm = mm ? esf_blob_take(&in, pb) : NULL;
  int same = pm && in.pos == in.n && !memcmp(mm, s->mats.m, mb);
  for (size_t k = 0; same && k < pb / sizeof *s->mats.pair; k++) {
    esf_pair_params pp = s->mats.pair[k]; /* stored without the law pointer (derived */
    pp.law = NULL;                        /* from the materials, which are compared) */
    same = !memcmp((const char *)pm + k * sizeof pp, &pp, sizeof pp);
  }
  if (!same) return mismatch(c, err, "the materials or their pair table differ");
  in = esf_ckpt_sec(c, "WALLS");
  int32_t ng = 0;
  uint64_t ne = 0;
  esf_blob_get(&in, &ng, 4);
  esf_blob_get(&in, &ne, 8);
  if (ng != s->walls.ngroups || ne != s->walls.n)
    return mismatch(c, err, "the walls differ");
  for (int g = 0; g < ng; g++) {
    esf_blob_get(&in, s->walls.g[g].disp_mark, 3 * sizeof(double));
    esf_blob_get(&in, &s->walls.g[g].angle_mark, sizeof(double));
    if (!all_finite(s->walls.g[g].disp_mark, 3) || !isfinite(s->walls.g[g].angle_mark))
      return invalid(c, err, "a wall's placement at the last build is not finite");
  }
  if (in.short_read || in.pos != in.n)
    return mismatch(c, err, "the WALLS section's size");

  /* particles: every array, any n */
  in = esf_ckpt_sec(c, "PART");
  uint64_t n = 0;
  esf_blob_get(&in, &n, 8);
  size_t need = (size_t)n * (9 + 3 + 3 + 5) * sizeof(double) +
                (size_t)n * (sizeof(int32_t) + sizeof(int64_t));
  if (in.short_read || n > in.n || in.n - in.pos != need)
    return mismatch(c, err, "the particle section's size");
  /* the scene's particles, less those the scheme's set-up found outside the domain */
  const size_t n_ids = s->p.n + (size_t)s->removed;
  esf_blob_in ins = esf_ckpt_sec(c, "INSERT"); /* insertion (loads/insert.c) */
  if (esf_inserts_restore(s, &ins))
    return mismatch(c, err, "the insert entries (INSERT section)");
  const int64_t next_id = s->insert ? s->insert->next_id : (int64_t)n_ids;
  if (next_id < (int64_t)n_ids ||
      (uint64_t)(next_id - (int64_t)n_ids) != (uint64_t)esf_inserts_total(s))
    return invalid(c, err,
                   "the next id %lld and %lld inserted do not make the scene's %zu",
                   (long long)next_id, esf_inserts_total(s), n_ids);
  int rc = check_sim(c, s, it, &cs, n, (size_t)next_id, err);
  if (rc) return rc;
  esf_particles *p = &s->p, scene = *p; /* the scene's, to check the saved ones by */
  memset(p, 0, sizeof *p);
  rc = esf_particles_alloc(p, (size_t)n, err);
  if (!rc && s->cfg.per.any) rc = esf_particles_images(p, err);
  if (rc) {
    esf_particles_release(&scene);
    return rc;
  }
  esf_blob_get(&in, p->y, 9 * n * sizeof(double));
  s->ft_lazy = NULL;
  esf_blob_get(&in, p->f, 3 * n * sizeof(double));
  esf_blob_get(&in, p->t, 3 * n * sizeof(double));
  double *cols[] = {p->radius, p->mass, p->inv_mass, p->inertia, p->inv_inertia};
  for (int k = 0; k < 5; k++) esf_blob_get(&in, cols[k], n * sizeof(double));
  esf_blob_get(&in, p->material, n * sizeof *p->material);
  esf_blob_get(&in, p->id, n * sizeof *p->id);
  rc = check_particles(c, p, &scene, n_ids, (size_t)next_id, s->mats.n, err);
  esf_particles_release(&scene);
  if (rc) return rc;

  /* scalars, rng, ledger, walls at the saved time */
  s->t = cs.t;
  s->led_time = cs.led_time;
  s->alpha_r = cs.alpha_r;
  s->alpha_t = cs.alpha_t;
  s->contacts_sum = cs.contacts_sum;
  s->step = cs.step;
  s->removed = cs.removed;
  s->rhs_evals = cs.rhs_evals;
  memcpy(s->rng.s, cs.rng, sizeof cs.rng);
  s->bonds.formed = cs.bonds_formed; /* formed at the first build, long before */
  s->bonds.broken = cs.bonds_broken;
  s->bonds.pending = 0;
  in = esf_ckpt_sec(c, "LEDGER");
  esf_ledger led;
  if (esf_blob_get(&in, &led, sizeof led) || in.pos != in.n)
    return mismatch(c, err, "the LEDGER section's size");
  rc = check_ledger(c, s, &led, err);
  if (rc) return rc;
  s->led = led;
  in = esf_ckpt_sec(c, "SAND"); /* servo walls, events, fluid (loads_ckpt.c) */
  if (esf_loads_ckpt_restore(s, &in))
    return mismatch(c, err, "the servo walls, events or fluid force (SAND section)");
  s->walls.t = NAN; /* so that set_time places moving walls at the saved time */
  esf_walls_set_time(&s->walls, cs.walls_t);
  s->walls.t = cs.walls_t;

  /* candidate lists: one build sizes the derived scratch, then the saved lists */
  s->nb.threads = s->cfg.threads;
  s->nb.le_t = s->t;
  rc = esf_neighbor_build(&s->nb, p, &s->walls, err);
  uint64_t npp = 0, npw = 0;
  memcpy(&npp, esf_ckpt_sec(c, "CONTPP").d, 8);
  memcpy(&npw, esf_ckpt_sec(c, "CONTPW").d, 8);
  if (!rc && (npp > esf_ckpt_sec(c, "CONTPP").n || npw > esf_ckpt_sec(c, "CONTPW").n))
    return mismatch(c, err, "a contact list's size");
  if (!rc) rc = esf_neighbor_reserve(&s->nb, (size_t)npp, (size_t)npw, err);
  if (!rc) rc = get_contacts(c, "CONTPP", &s->nb.pp, p->n, p->n, err);
  if (!rc) rc = get_contacts(c, "CONTPW", &s->nb.pw, p->n, s->walls.n, err);
  if (!rc) rc = get_periodic(c, s, err);
  if (rc) return rc;
  in = esf_ckpt_sec(c, "NBREF");
  uint64_t nref = 0;
  esf_blob_get(&in, &nref, 8);
  if (in.short_read || (nref != 0 && nref != n) ||
      in.n - in.pos != 3 * nref * sizeof(double))
    return mismatch(c, err, "the list reference positions");
  free(s->nb.xref);
  s->nb.xref = NULL;
  s->nb.nref = 0;
  if (nref) {
    s->nb.xref = malloc(3 * nref * sizeof(double));
    if (!s->nb.xref) return esf_fail(err, ESF_ENOMEM, "out of memory");
    esf_blob_get(&in, s->nb.xref, 3 * nref * sizeof(double));
    s->nb.nref = (size_t)nref;
    if (!all_finite(s->nb.xref, 3 * nref))
      return invalid(c, err, "a reference position of the lists is not finite");
  }
  s->nb.builds = cs.builds;
  in = esf_ckpt_sec(c, "NBSKIN"); /* absent from older checkpoints: the skin stays */
  if (!in.short_read) {
    double sk[2];
    if (esf_blob_get(&in, sk, sizeof sk) || in.pos != in.n || !(sk[0] > 0) ||
        !isfinite(sk[0]) || !(sk[1] >= 0 && sk[1] <= (double)cs.step))
      return mismatch(c, err, "the NBSKIN section");
    s->nb.skin = sk[0];
    s->nb.built_step = (long)sk[1];
  } else
    s->nb.built_step = (long)cs.step;

  in = esf_ckpt_sec(c, "RUN");
  if (esf_blob_get(&in, run, sizeof *run) || in.pos != in.n)
    return mismatch(c, err, "the RUN section's size");
  rc = check_run(c, s, run, &cs, err);
  if (rc) return rc;
  in = esf_ckpt_sec(c, "INTEG");
  rc = it->restore(s, ist, &in, err);
  if (rc) esf_error_prefix(err, "%s: ", c->path);
  return rc;
}

int esf_ckpt_describe(const char *path, FILE *out, esf_error *err) {
  esf_ckpt *c = NULL;
  int rc = esf_ckpt_load(path, &c, err);
  if (rc) return rc;
  esf_blob_in m = esf_ckpt_sec(c, "META");
  fprintf(out, "kind: checkpoint\nfile: %s\nbytes: %zu\n", c->path, c->len);
  fwrite(m.d, 1, m.n, out);
  esf_ckpt_run run;
  esf_blob_in r = esf_ckpt_sec(c, "RUN");
  esf_blob_get(&r, &run, sizeof run);
  uint64_t n = 0;
  memcpy(&n, esf_ckpt_sec(c, "PART").d, 8);
  if (n) fprintf(out, "bytes_per_particle: %.1f\n", (double)c->len / (double)n);
  for (int k = 0; k < c->nsets; k++) fprintf(out, "override: %s\n", c->sets[k]);
  char dir[1200];
  snprintf(dir, sizeof dir, "%s", c->path);
  char *slash = strrchr(dir, '/');
  if (slash)
    *slash = '\0';
  else
    snprintf(dir, sizeof dir, ".");
  fprintf(out, "resume: esfera run --resume %s\n", dir);
  esf_ckpt_free(&c);
  return ESF_OK;
}
