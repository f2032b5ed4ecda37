/* insert.c — particles inserted during the run (insert.h; docs/physics.md#insertion).
 *
 * Schedule: an entry inserts in batches at the steps n that are multiples of
 * every_steps = max(1, round(every / dt)), while start <= t_n <= stop + every. A batch
 * brings the entry's total to what is due at t = min(t_n, stop): N(t) =
 * floor(rate (t - start) + 1e-9) particles (at most `count`), or, with mass_rate, as
 * many as keep the inserted mass within mass_rate (t - start) (the total stays within
 * one particle's mass below it). So after each batch the count is rate x time, to one
 * particle.
 * Placement: random sequential addition (as the scene's random fill, bodies/fill.h):
 * the next particle's radius and material are drawn (and kept until it is placed, so
 * the draws do not depend on how many attempts it took), then up to ATTEMPTS centres
 * uniform in the region shrunk by the radius, each rejected when it overlaps a
 * particle (the placement grid holds the particles whose box meets the region, and the
 * batch's newborns) or a wall element near the region (esf_wall_nearest: distance <
 * r; touching is allowed). A particle that finds no place ends the batch: the rest
 * wait for the next one, and the log says so once, with the numbers.
 * Newborns: velocity `velocity` (the leapfrog's v_{n-1/2}), no spin, mass and inertia
 * from esf_particle_mass, ids from next_id on. Ledger: energy_inserted gains
 * 1/2 m v^2 - m g.(x_n - v dt/2) of each (the kinetic energy at v_{n-1/2} and the
 * gravity at the position it belongs to, as the start's e0 counts them: ledger.h),
 * once the balance has started. Reproducible: three
 * xoshiro streams per entry (radius, material, position) seeded from `seed`, saved in
 * checkpoints; the placement depends on the positions only, not on their order. */
#include "loads/insert.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/vec3.h"

enum { ATTEMPTS = 200 }; /* placement attempts per particle and batch */

int esf_inserts_add(esf_inserts **list, const esf_insert *in, esf_error *err) {
  if (!*list) {
    *list = calloc(1, sizeof **list);
    if (!*list) return esf_fail(err, ESF_ENOMEM, "out of memory");
  }
  esf_inserts *L = *list;
  esf_insert *e = realloc(L->e, (size_t)(L->n + 1) * sizeof *e);
  if (!e) return esf_fail(err, ESF_ENOMEM, "out of memory");
  L->e = e;
  esf_insert *d = &e[L->n++];
  *d = *in;
  esf_fill_seed(d->fill.seed, &d->rr, &d->rm, &d->rp);
  d->inserted = 0;
  d->mass_in = 0.0;
  d->pending = 0;
  d->logged = 0;
  d->short_batches = 0;
  return ESF_OK;
}

void esf_inserts_free(esf_inserts **list) {
  if (!*list) return;
  for (int k = 0; k < (*list)->n; k++) {
    free((*list)->e[k].sbuf);
    free((*list)->e[k].mats);
    free((*list)->e[k].fr);
  }
  free((*list)->e);
  free(*list);
  *list = NULL;
}

int esf_inserts_probes(const esf_sim *s, esf_particles *q, esf_error *err) {
  const esf_inserts *L = s->insert;
  size_t extra = 0;
  for (int k = 0; k < L->n; k++) extra += 2 * L->e[k].fill.mix.n;
  const esf_particles *p = &s->p;
  int rc = esf_particles_alloc(q, p->n + extra, err);
  if (rc) return rc;
  memcpy(q->radius, p->radius, p->n * sizeof(double));
  memcpy(q->mass, p->mass, p->n * sizeof(double));
  memcpy(q->material, p->material, p->n * sizeof(int32_t));
  size_t i = p->n;
  for (int k = 0; k < L->n; k++) {
    const esf_insert *e = &L->e[k];
    for (size_t j = 0; j < 2 * e->fill.mix.n; j++, i++) {
      const esf_material *mt = &s->mats.m[e->fill.mix.material[j / 2]];
      if (!(mt->density > 0)) {
        esf_particles_release(q);
        return esf_fail(err, ESF_EINPUT,
                        "%s: insert: material '%s' needs a positive density", e->where,
                        mt->name);
      }
      q->material[i] = e->fill.mix.material[j / 2];
      q->radius[i] = j % 2 ? e->rmax : e->rmin;
      esf_particle_mass(s->cfg.dim, q->radius[i], s->mats.m[q->material[i]].density,
                        s->cfg.disk_thickness, &q->mass[i], &q->inertia[i]);
    }
  }
  return ESF_OK;
}

int esf_inserts_setup(esf_sim *s, esf_error *err) {
  esf_inserts *L = s->insert;
  if (!L || L->n == 0) return ESF_OK;
  if (strcmp(s->cfg.method, "leapfrog") != 0)
    return esf_fail(err, ESF_EINPUT,
                    "%s: inserting particles during the run is supported by the "
                    "leapfrog only (%s: %s): the ODE methods and velocity Verlet "
                    "cannot change the particle count within a run; use "
                    "integrator.method: leapfrog",
                    L->e[0].where, esf_config_where(&s->cfg, "integrator.method"),
                    s->cfg.method);
  int64_t top = -1;
  for (size_t i = 0; i < s->p.n; i++)
    if (s->p.id[i] > top) top = s->p.id[i];
  if (L->next_id <= top) L->next_id = top + 1;
  for (int k = 0; k < L->n; k++) {
    esf_insert *e = &L->e[k];
    if (s->cfg.has_domain)
      for (int q = 0; q < 3; q++) {
        if (s->cfg.dim == 2 && q == 1) continue;
        if (e->fill.min[q] < s->cfg.domain_min[q] ||
            e->fill.max[q] > s->cfg.domain_max[q])
          return esf_fail(err, ESF_EINPUT,
                          "%s: insert: the region [%g, %g] along %c is not inside the "
                          "domain [%g, %g]: its particles would be removed at once",
                          e->where, e->fill.min[q], e->fill.max[q], "xyz"[q],
                          s -> cfg.domain_min[q], s->cfg.domain_max[q]);
      }
    if (!(e->every > 0)) e->every = 100.0 * s->dt;
    double k_steps = floor(e->every / s->dt + 0.5);
    e->every_steps = k_steps < 1.0 ? 1 : k_steps > 1e9 ? 1000000000L : (long)k_steps;
  }
  return ESF_OK;
}

long long esf_inserts_total(const esf_sim *s) {
  long long n = 0;
  for (int k = 0; s->insert && k < s->insert->n; k++) n += s->insert->e[k].inserted;
  return n;
}

/* 1 when the entry has batches left at or after step n */
static int active(const esf_sim *s, const esf_insert *e, long n) {
  const double t = (double)n * s->dt;
  if (e->fill.count && e->inserted >= (int64_t)e->fill.count) return 0;
  return t <= e->stop + (double)e->every_steps * s->dt;
}

long esf_inserts_steps_left(const esf_sim *s) {
  const esf_inserts *L = s->insert;
  long left = LONG_MAX;
  for (int k = 0; L && k < L->n; k++) {
    const esf_insert *e = &L->e[k];
    if (!active(s, e, s->step)) continue;
    long d = e->every_steps - s->step % e->every_steps;
    if (d < left) left = d;
  }
  return left;
}

/* The next particle's radius and material (drawn once, kept until placed). */
static void draw_next(esf_insert *e) {
  if (e->pending) return;
  e->r_next = esf_draw_radius(&e->fill.size, &e->rr, esf_size_weights(&e->fill.size));
  e->m_next = e->fill.mix.material[esf_draw_index(
      &e->rm, e->fill.mix.n, e->fill.mix.fraction, esf_mix_weights(&e->fill.mix))];
  e->pending = 1;
}

/* 1 when a sphere at x of radius r overlaps one of the wall elements near[0 .. nn) */
static int hits_wall(const esf_walls *w, const size_t *near, size_t nn, const double *x,
                     double r) {
  for (size_t j = 0; j < nn; j++) {
    esf_wall_hit hit;
    esf_wall_nearest(&w->e[near[j]], x, &hit);
    if (hit.dist < r) return 1;
  }
  return 0;
}

/* The particles whose bounding box meets the region go into the grid; the wall elements
 * that may come within rmax of it into near (a 1-Lipschitz bound from its centre). */
static int prepare(const esf_sim *s, const esf_insert *e, esf_fill_grid *g, size_t *near,
                   size_t *nn, esf_error *err) {
  const esf_particles *p = &s->p;
  const int dim = s->cfg.dim;
  size_t nmeet = 0; /* first their count, for the grid's size */
  for (int pass = 0; pass < 2; pass++) {
    if (pass == 1) {
      int rc =
          esf_fill_grid_init(g, e->fill.min, e->fill.max, dim, e->rmax, nmeet + 64, err);
      if (rc) return rc;
    }
    for (size_t i = 0; i < p->n; i++) {
      const double *x = p->x + 3 * i;
      int meets = 1;
      for (int k = 0; k < 3; k++) {
        if (dim == 2 && k == 1) continue;
        if (x[k] + p->radius[i] <= e->fill.min[k] ||
            x[k] - p->radius[i] >= e->fill.max[k])
          meets = 0;
      }
      if (!meets) continue;
      nmeet++;
      esf_fill_sphere sp = {{x[0], x[1], x[2]}, p->radius[i]};
      int rc = pass == 1 ? esf_fill_grid_add(g, &sp, err) : ESF_OK;
      if (rc) return rc;
    }
  }
  int rc = ESF_OK;
  double c[3], half = 0.0;
  for (int k = 0; k < 3; k++) {
    const int flat = dim == 2 && k == 1;
    c[k] = flat ? 0.0 : 0.5 * (e->fill.min[k] + e->fill.max[k]);
    const double hk = flat ? 0.0 : 0.5 * (e->fill.max[k] - e->fill.min[k]);
    half += hk * hk;
  }
  half = sqrt(half);
  *nn = 0;
  for (size_t j = 0; !rc && j < s->walls.n; j++) {
    if (s->walls.g[s->walls.e[j].group].absent) continue; /* removed by an event */
    esf_wall_hit hit;
    esf_wall_nearest(&s->walls.e[j], c, &hit);
    if (hit.dist - half < e->rmax) near[(*nn)++] = j;
  }
  return rc;
}

/* Particles due at time t (count, or mass within one particle). */
static int due(const esf_insert *e, double t) {
  const double el = (t < e->stop ? t : e->stop) - e->start;
  if (el < 0) return 0;
  if (e->mass_rate > 0) return e->mass_in + 1e-12 < e->mass_rate * el; /* one more */
  double n = floor(e->rate * el + 1e-9);
  if (e->fill.count && n > (double)e->fill.count) n = (double)e->fill.count;
  return (double)e->inserted < n;
}

static int batch(esf_sim *s, esf_insert *e, size_t *added, esf_error *err) {
  esf_particles *p = &s->p;
  const int dim = s->cfg.dim;
  const double t = s->t;
  esf_fill_grid g;
  size_t *near = malloc((s->walls.n ? s->walls.n : 1) * sizeof *near), nn = 0;
  if (!near) return esf_fail(err, ESF_ENOMEM, "out of memory");
  int rc = prepare(s, e, &g, near, &nn, err);
  const int axes[3] = {1, dim == 3, 1};
  int full = 0;
  const int64_t before = e->inserted;
  int32_t *mat = NULL; /* the newborns' materials */
  size_t nmat = 0, capmat = 0;
  while (!rc && due(e, t)) {
    draw_next(e);
    double m, inertia;
    const double r = e->r_next, rho = s->mats.m[e->m_next].density;
    esf_particle_mass(dim, r, rho, s->cfg.disk_thickness, &m, &inertia);
    if (e->mass_rate > 0 &&
        e->mass_in + m > e->mass_rate * ((t < e->stop ? t : e->stop) - e->start))
      break; /* the next one would take the mass above what is due */
    esf_fill_sphere sp = {{0.0, 0.0, 0.0}, r};
    int placed = 0;
    for (int a = 0; a < ATTEMPTS && !placed; a++) {
      for (int k = 0; k < 3; k++) {
        if (!axes[k]) continue;
        const double lo = e->fill.min[k] + r, hi = e->fill.max[k] - r;
        const double x = lo + (hi - lo) * esf_rng_uniform(&e->rp);
        sp.x[k] = x > hi ? hi : x;
      }
      placed =
          !esf_fill_grid_overlaps(&g, &sp) && !hits_wall(&s->walls, near, nn, sp.x, r);
    }
    if (!placed) {
      full = 1;
      break;
    }
    rc = esf_fill_grid_add(&g, &sp, err); /* the grid keeps the batch's newborns */
    if (rc) break;
    if (s->led.started) { /* before, e0 counts them */
      double xo[3];       /* the ledger's gravity of v_{n-1/2}: at x_n - v dt/2 */
      v3_copy(xo, sp.x);
      v3_axpy(xo, -0.5 * s->dt, e->fill.velocity);
      s->led.e_inserted +=
          0.5 * m * v3_norm2(e->fill.velocity) - m * v3_dot(s->cfg.gravity, xo);
    }
    if (nmat == capmat) {
      capmat = capmat ? 2 * capmat : 64;
      int32_t *mm = realloc(mat, capmat * sizeof *mat);
      if (!mm) {
        rc = esf_fail(err, ESF_ENOMEM, "out of memory");
        break;
      }
      mat = mm;
    }
    mat[nmat++] = e->m_next;
    e->inserted++;
    e->mass_in += m;
    e->pending = 0;
    (*added)++;
  }
  /* the newborns, appended in placement order (the grid's spheres from nold on) */
  const size_t nnew = (size_t)(e->inserted - before), n0 = p->n, nold = g.nsp - nnew;
  if (!rc && nnew) rc = esf_particles_append(p, nnew, err);
  for (size_t j = 0; !rc && j < nnew; j++) {
    const size_t i = n0 + j;
    const esf_fill_sphere *sp = &g.sp[nold + j];
    v3_copy(p->x + 3 * i, sp->x);
    v3_copy(p->v + 3 * i, e->fill.velocity);
    p->radius[i] = sp->r;
    p->material[i] = mat[j];
    esf_particle_mass(dim, sp->r, s->mats.m[mat[j]].density, s->cfg.disk_thickness,
                      &p->mass[i], &p->inertia[i]);
    p->inv_mass[i] = 1.0 / p->mass[i];
    p->inv_inertia[i] = 1.0 / p->inertia[i];
    p->id[i] = s->insert->next_id++;
  }
  esf_fill_grid_release(&g);
  free(near);
  free(mat);
  if (!rc && full) {
    e->short_batches++;
    if (!e->logged) {
      const double el = (t < e->stop ? t : e->stop) - e->start;
      esf_sim_log(s,
                  "t = %.6g s (step %ld): insert (%s) placed %lld particles in this "
                  "batch, fewer than due: %lld inserted in all (%.6g kg) against %.6g "
                  "due after %.6g s at %s %.6g%s; no free place found in %d attempts "
                  "(region too full): the rest wait for later batches (told once)",
                  t, s->step, e->where, (long long)(e->inserted - before),
                  (long long)e->inserted, e->mass_in,
                  e->mass_rate > 0 ? e->mass_rate * el : e->rate * el, el,
                  e->mass_rate > 0 ? "mass_rate" : "rate",
                  e->mass_rate > 0 ? e->mass_rate : e->rate,
                  e->mass_rate > 0 ? " kg/s" : " /s", ATTEMPTS);
      e->logged = 1;
    }
  }
  return rc;
}

int esf_inserts_apply(esf_sim *s, size_t *added, esf_error *err) {
  esf_inserts *L = s->insert;
  *added = 0;
  for (int k = 0; L && k < L->n; k++) {
    esf_insert *e = &L->e[k];
    if (s->step % e->every_steps != 0 || !active(s, e, s->step)) continue;
    if (s->t + 0.5 * s->dt < e->start) continue;
    int rc = esf_sim_forces_sync(s, err); /* p.f, p.t move with p */
    if (!rc) rc = batch(s, e, added, err);
    if (rc) return rc;
  }
  return ESF_OK;
}

/* INSERT section, per entry: rr, rm, rp (12 uint64), int64 inserted, double mass_in,
 * int32 pending, int32 m_next, double r_next, int32 logged, int64 short_batches;
 * after the entries int64 next_id. Its fields, in that order, for save and restore: */
enum { NFIELDS = 10 };
static void state_fields(esf_insert *e, void *at[NFIELDS], size_t len[NFIELDS]) {
  void *const a[NFIELDS] = {e->rr.s,     e->rm.s,          e->rp.s,    &e->inserted,
                            &e->mass_in, &e->pending,      &e->m_next, &e->r_next,
                            &e->logged,  &e->short_batches};
  const size_t l[NFIELDS] = {
      sizeof e->rr.s, sizeof e->rm.s, sizeof e->rp.s, 8, 8, 4, 4, 8, 4, 8};
  memcpy(at, a, sizeof a);
  memcpy(len, l, sizeof l);
}

void esf_inserts_save(const esf_sim *s, esf_blob *b) {
  const esf_inserts *L = s->insert;
  int32_t n = L ? L->n : 0;
  esf_blob_put(b, &n, 4);
  for (int k = 0; k < n; k++) {
    void *at[NFIELDS];
    size_t len[NFIELDS];
    state_fields(&L->e[k], at, len);
    for (int f = 0; f < NFIELDS; f++) esf_blob_put(b, at[f], len[f]);
  }
  int64_t next = L ? L->next_id : 0;
  esf_blob_put(b, &next, 8);
}

int esf_inserts_restore(esf_sim *s, esf_blob_in *in) {
  esf_inserts *L = s->insert;
  int32_t n = -1;
  esf_blob_get(in, &n, 4);
  if (n != (L ? L->n : 0)) return -1;
  for (int k = 0; k < n; k++) {
    esf_insert *e = &L->e[k];
    void *at[NFIELDS];
    size_t len[NFIELDS];
    state_fields(e, at, len);
    for (int f = 0; f < NFIELDS; f++) esf_blob_get(in, at[f], len[f]);
    if (e->inserted < 0 || !isfinite(e->mass_in) || (e->pending != 0 && e->pending != 1))
      return -1;
    if (e->pending) {
      int ok = 0;
      for (size_t j = 0; j < e->fill.mix.n; j++)
        ok |= e->fill.mix.material[j] == e->m_next;
      if (!ok || !(e->r_next > 0) || !isfinite(e->r_next)) return -1;
    }
  }
  int64_t next = -1;
  esf_blob_get(in, &next, 8);
  if (L) L->next_id = next;
  return in->short_read || in->pos != in->n || (L && next < 0) ? -1 : 0;
}
