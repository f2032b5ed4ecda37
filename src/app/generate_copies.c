/* generate_copies.c — model generation by successive copies (004 §3.3;
 * docs/physics.md#model-generation-by-successive-copies), the Sandia technique the
 * seed adopts:
 *  1. The scene's particles are the primary set (typically a `generate: random` fill of
 *     the primary box, radii in [r_min, r_max], a material mix). Walls: the five faces
 *     of generate.box (open at the top), of generate.material.
 *  2. Settle under gravity with the scene's integrator, damping and contact law until
 *     E_k < ke_fraction · E_ref, checked every check_every seconds, or until max_time
 *     (E_k, E_ref: settle).
 *  3. Copy: copy (i, j, k) is the settled set translated by (i L_x, j L_y, k H), L the
 *     box's edges and H the settled height (highest top minus box floor), so the
 *     copies are exact periodic images; the box grows to n_x L_x × n_y L_y with
 *     walls n_z L_z high (open top).
 *  4. Settle again (generate.resettle, default the settle values; max_time 0 skips
 *     it), write the CSV in id order with velocities dropped.
 *  5. Optionally compact (generate.compact: strain, time; compact).
 * Units: SI. State: each stage builds its own esf_sim from the same parsed scene
 * (materials, damping, integrator), so nothing of a stage leaks into the next but the
 * particle positions, radii and materials. The library never prints except to `log`. */
#include "app/generate_copies.h"
#include "util/clock.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "integrators/integrator.h"
#include "loads/insert.h"
#include "model/model.h"
#include "scene/scene.h"
#include "util/atomic_file.h"
#include "util/vec3.h"

typedef struct settle_spec {
  double ke_fraction; /* stop when E_k < ke_fraction E_ref */
  double max_time;    /* s; 0: no settling */
  double check_every; /* s between checks */
} settle_spec;

typedef struct gen_spec {
  double min[3], max[3]; /* primary box, m */
  long copies[3];
  int32_t material; /* wall material */
  settle_spec settle, resettle;
  double strain, compact_time; /* compaction: lateral strain, its duration (s); 0: off */
} gen_spec;

static int read_settle(const esf_ynode *g, const char *key, settle_spec *sp,
                       esf_error *err) {
  static const char *const keys[] = {"ke_fraction", "max_time", "check_every", NULL};
  const esf_ynode *n = esf_ymap_get(g, key);
  if (!n) return ESF_OK;
  int rc = esf_ynode_require_map(n, err);
  if (!rc) rc = esf_ymap_check_keys(n, keys, err);
  if (!rc) rc = esf_yget_double(n, "ke_fraction", 0, &sp->ke_fraction, err);
  if (!rc && !(sp->ke_fraction > 0 && sp->ke_fraction < 1))
    return esf_ynode_fail(esf_ymap_get(n, "ke_fraction"), err, "must be in (0, 1)");
  if (!rc) rc = esf_yget_double(n, "max_time", 0, &sp->max_time, err);
  if (!rc && !(sp->max_time >= 0))
    return esf_ynode_fail(esf_ymap_get(n, "max_time"), err, "must be >= 0 s");
  if (!rc) rc = esf_yget_double(n, "check_every", 0, &sp->check_every, err);
  if (!rc && !(sp->check_every > 0))
    return esf_ynode_fail(esf_ymap_get(n, "check_every"), err, "must be positive");
  return rc;
}

static int read_spec(const esf_ynode *root, const esf_sim *s, gen_spec *gs,
                     esf_error *err) {
  static const char *const keys[] = {"box",      "copies",  "material", "settle",
                                     "resettle", "compact", NULL};
  static const char *const bkeys[] = {"min", "max", NULL};
  const esf_ynode *g = esf_ymap_get(root, "generate");
  if (!g)
    return esf_ynode_fail(root, err,
                          "missing key 'generate' (box, copies, material, settle): "
                          "esfera generate needs it");
  int rc = esf_ynode_require_map(g, err);
  if (!rc) rc = esf_ymap_check_keys(g, keys, err);
  const esf_ynode *b = esf_ymap_get(g, "box");
  if (!rc && !b) return esf_ynode_fail(g, err, "missing key 'box' ({min, max}, m)");
  if (!rc) rc = esf_ymap_check_keys(b, bkeys, err);
  if (!rc) rc = esf_yget_doubles(b, "min", 1, gs->min, 3, err);
  if (!rc) rc = esf_yget_doubles(b, "max", 1, gs->max, 3, err);
  for (int k = 0; k < 3 && !rc; k++)
    if (!(gs->min[k] < gs->max[k]))
      return esf_ynode_fail(b, err, "min must be below max in every direction");
  const esf_ynode *cp = esf_ymap_get(g, "copies");
  if (!rc && !cp) return esf_ynode_fail(g, err, "missing key 'copies' ([nx, ny, nz])");
  if (!rc) rc = esf_ynode_require_seq(cp, err);
  if (!rc && cp->n != 3)
    return esf_ynode_fail(cp, err, "copies takes three whole numbers [nx, ny, nz]");
  for (int k = 0; k < 3 && !rc; k++) {
    rc = esf_ynode_long(cp->items[k], &gs->copies[k], err);
    if (!rc && !(gs->copies[k] >= 1 && gs->copies[k] <= 1000))
      return esf_ynode_fail(cp->items[k], err, "must be in [1, 1000], got %ld",
                            gs->copies[k]);
  }
  const esf_ynode *m = esf_ymap_get(g, "material");
  if (!rc && !m) return esf_ynode_fail(g, err, "missing key 'material' (of the walls)");
  if (!rc) rc = esf_scene_material(m, &s->mats, &gs->material, err);
  gs->settle = (settle_spec){1e-4, 1.0, 0.0};
  if (!rc) rc = read_settle(g, "settle", &gs->settle, err);
  gs->resettle = gs->settle;
  if (!rc) rc = read_settle(g, "resettle", &gs->resettle, err);
  static const char *const ckeys[] = {"strain", "time", NULL};
  const esf_ynode *c = esf_ymap_get(g, "compact");
  gs->strain = gs->compact_time = 0;
  if (!rc && c) rc = esf_ymap_check_keys(c, ckeys, err);
  if (!rc && c) rc = esf_yget_double(c, "strain", 1, &gs->strain, err);
  if (!rc && c && !(gs->strain > 0 && gs->strain < 0.5))
    return esf_ynode_fail(esf_ymap_get(c, "strain"), err, "must be in (0, 0.5)");
  if (!rc && c) rc = esf_yget_double(c, "time", 1, &gs->compact_time, err);
  if (!rc && c && !(gs->compact_time > 0))
    return esf_ynode_fail(esf_ymap_get(c, "time"), err, "must be positive (s)");
  if (!rc && esf_ymap_get(root, "walls"))
    return esf_ynode_fail(esf_ymap_get(root, "walls"), err,
                          "a generate scene takes its walls from generate.box; remove "
                          "'walls'");
  return rc;
}

/* Faces of a box as one group (faces: wall_geom.h's bits of the faces kept), moving at
 * vel (m/s) when it is not NULL. */
static int add_faces(esf_sim *s, const double min[3], const double max[3], unsigned faces,
                     int32_t mat, const double *vel, esf_error *err) {
  int group = 0, count = 0;
  esf_wall_elem e[6];
  int rc = esf_walls_add_group(&s->walls, "box", &group, err);
  if (!rc) rc = esf_wall_box(min, max, 63u & ~faces, mat, group, e, &count, err);
  for (int k = 0; k < count && !rc; k++) rc = esf_walls_add_elem(&s->walls, &e[k], err);
  if (!rc && vel) {
    s->walls.g[group].motion.kind = ESF_MOTION_TRANSLATE;
    v3_copy(s->walls.g[group].motion.vel, vel);
  }
  return rc;
}

/* The box walls, open at the top, as one static group. */
static int add_box(esf_sim *s, const double min[3], const double max[3], int32_t mat,
                   esf_error *err) {
  return add_faces(s, min, max, 31u, mat, NULL, err);
}

/* Kinetic (translational + rotational) and gravitational energy, J. */
static void energies(const esf_sim *s, double *ek, double *ep) {
  double kt, kr;
  esf_sim_energies(s, s->p.x, s->p.v, s->p.w, &kt, &kr, ep);
  *ek = kt + kr;
}

/* Settles the set-up sim under gravity until E_k < ke_fraction · E_ref, checked every
 * check_every seconds, or until max_time; fills rep. E_k = Σ ½ m v² + ½ I ω² (J);
 * E_ref = max(|ΔE_p|, Σ m |g| r) (J), ΔE_p the change of gravitational potential energy
 * over the stage: the energy released by the settling; the floor Σ m|g|r (lifting every
 * particle by its radius) keeps a scale for a stage that barely moves. */
static int settle(esf_sim *s, const settle_spec *sp, esf_settle_report *rep,
                  esf_error *err) {
  const esf_integrator_type *it = esf_integrator_find(s->cfg.method);
  if (!it) return esf_fail(err, ESF_EINPUT, "unknown integrator '%s'", s->cfg.method);
  memset(rep, 0, sizeof *rep);
  double g = v3_norm(s->cfg.gravity), floor_e = 0, ek = 0, ep0 = 0, ep = 0;
  for (size_t i = 0; i < s->p.n; i++) floor_e += s->p.mass[i] * g * s->p.radius[i];
  energies(s, &ek, &ep0);
  void *ist = NULL;
  double t0 = s->t, w0 = esf_now_s();
  double check = sp->check_every > 0 ? sp->check_every : sp->max_time / 100.0;
  long every = (long)fmax(1.0, floor(check / s->dt + 0.5));
  long nmax = (long)ceil(sp->max_time / s->dt - 1e-9);
  int rc = sp->max_time > 0 ? it->create(s, &ist, err) : ESF_OK;
  for (long n = 1; n <= nmax && !rc; n++) {
    rc = it->step(s, ist, t0 + sp->max_time, err);
    if (rc || (n % every && n < nmax)) continue;
    energies(s, &ek, &ep);
    rep->e_ref = fmax(fabs(ep - ep0), floor_e);
    if (ek < sp->ke_fraction * rep->e_ref) {
      rep->settled = 1;
      break;
    }
  }
  if (ist) it->destroy(&ist);
  if (rc) return rc;
  energies(s, &ek, &ep);
  rep->particles = s->p.n;
  rep->steps = s->step;
  rep->time = s->t - t0;
  rep->ke = ek;
  rep->e_ref = fmax(fabs(ep - ep0), floor_e);
  if (sp->max_time <= 0) rep->settled = ek < sp->ke_fraction * rep->e_ref;
  rep->top = -INFINITY;
  for (size_t i = 0; i < s->p.n; i++)
    rep->top = fmax(rep->top, s->p.x[3 * i + 2] + s->p.radius[i]);
  rep->wall_s = esf_now_s() - w0;
  return ESF_OK;
}

static void log_stage(FILE *log, const char *name, const esf_settle_report *r,
                      double ke_fraction) {
  if (!log) return;
  fprintf(log,
          "generate: stage=%s particles=%zu steps=%ld time=%.6g ke=%.6g e_ref=%.6g "
          "ke_ratio=%.4g target=%.4g %s top=%.6g wall_s=%.3f\n",
          name, r->particles, r->steps, r->time, r->ke, r->e_ref,
          r->e_ref > 0 ? r->ke / r->e_ref : 0.0, ke_fraction,
          r->steps == 0 ? "skipped"
          : r->settled  ? "settled"
                        : "time_limit",
          r->top, r->wall_s);
}

/* Positions (3n), radii and materials of a sim's particles in id order. */
static int by_id(const esf_particles *p, double *x, double *r, int32_t *mat,
                 esf_error *err) {
  for (size_t i = 0; i < p->n; i++) {
    int64_t id = p->id[i];
    if (id < 0 || (size_t)id >= p->n)
      return esf_fail(err, ESF_EINTERNAL, "particle id %lld out of range", (long long)id);
    memcpy(x + 3 * id, p->x + 3 * i, 3 * sizeof *x);
    r[id] = p->radius[i];
    mat[id] = p->material[i];
  }
  return ESF_OK;
}

/* The packing as CSV text, written with esf_atomic_write (PATH.tmp, fsync, rename):
 * an earlier file survives any failure. */
static int write_csv(const char *path, const esf_sim *s, esf_error *err) {
  size_t n = s->p.n, len = 0;
  double *x = malloc(3 * n * sizeof *x), *r = malloc(n * sizeof *r);
  int32_t *mat = malloc(n * sizeof *mat);
  char *text = NULL;
  FILE *f = NULL;
  int rc = x && r && mat ? by_id(&s->p, x, r, mat, err)
                         : esf_fail(err, ESF_ENOMEM, "out of memory");
  if (!rc && !(f = open_memstream(&text, &len)))
    rc = esf_fail(err, ESF_ENOMEM, "out of memory for the packing's text");
  if (!rc) {
    fprintf(f, "# esfera generate: %s (%s), %zu particles\nx,y,z,radius,material\n",
            s->cfg.name, s->cfg.source, n);
    for (size_t i = 0; i < n; i++)
      fprintf(f, "%.17g,%.17g,%.17g,%.17g,%s\n", x[3 * i], x[3 * i + 1], x[3 * i + 2],
              r[i], s->mats.m[mat[i]].name);
    if (fclose(f) != 0) rc = esf_fail(err, ESF_ENOMEM, "out of memory for the packing");
  }
  if (!rc) rc = esf_atomic_write(path, text, len, err);
  free(text);
  free(x);
  free(r);
  free(mat);
  return rc;
}

/* Replaces b's particles by n[0] x n[1] x n[2] copies of a's (copy (i, j, k) moved by
 * (i L_x, j L_y, k (top - box floor)), L the edges of gs->box), in id order. */
static int make_copies(const esf_sim *a, const gen_spec *gs, const long n[3], esf_sim *b,
                       double top, esf_error *err) {
  size_t n0 = a->p.n, nc = (size_t)(n[0] * n[1] * n[2]);
  double *x = malloc(3 * n0 * sizeof *x), *r = malloc(n0 * sizeof *r);
  int32_t *mat = malloc(n0 * sizeof *mat);
  int rc = x && r && mat ? by_id(&a->p, x, r, mat, err)
                         : esf_fail(err, ESF_ENOMEM, "out of memory");
  esf_particles_release(&b->p);
  if (!rc) rc = esf_particles_alloc(&b->p, n0 * nc, err);
  double L[3] = {gs->max[0] - gs->min[0], gs->max[1] - gs->min[1], top - gs->min[2]};
  for (size_t c = 0; c < nc && !rc; c++) {
    size_t i = c % (size_t)n[0], j = (c / (size_t)n[0]) % (size_t)n[1],
           k = c / (size_t)(n[0] * n[1]);
    double off[3] = {(double)i * L[0], (double)j * L[1], (double)k * L[2]};
    for (size_t q = 0; q < n0; q++) {
      size_t d = c * n0 + q;
      for (int e = 0; e < 3; e++) b->p.x[3 * d + e] = x[3 * q + e] + off[e];
      b->p.radius[d] = r[q];
      b->p.material[d] = mat[q];
      b->p.id[d] = (int64_t)d;
    }
  }
  free(x);
  free(r);
  free(mat);
  return rc;
}

/* A stage's sim from the parsed scene: materials, damping, integrator; no ledger. */
static int stage_sim(esf_ydoc *doc, const char *path, esf_sim *s, esf_error *err) {
  memset(s, 0, sizeof *s);
  esf_config_default(&s->cfg);
  snprintf(s->cfg.source, sizeof s->cfg.source, "%s", path);
  int rc = esf_scene_read(doc, s, err);
  if (!rc && s->insert) /* the copies would each insert */
    rc = esf_fail(err, ESF_EINPUT,
                  "%s: esfera generate builds its packing from the scene's particles at "
                  "t = 0: an insert entry (particles added during a run) has no place "
                  "in it; give the primary set as a generator",
                  s->insert->e[0].where);
  return rc;
}

static int check_inside(const esf_sim *s, const gen_spec *gs, esf_error *err) {
  for (size_t i = 0; i < s->p.n; i++)
    for (int k = 0; k < 3; k++) {
      double c = s->p.x[3 * i + k], r = s->p.radius[i];
      if (c - r < gs->min[k] || c + r > gs->max[k])
        return esf_fail(err, ESF_EINPUT,
                        "%s: particle id %lld (centre %g %g %g, radius %g) is not "
                        "inside generate.box: the primary set must lie in the box",
                        s->cfg.source, (long long)s->p.id[i], s->p.x[3 * i],
                        s->p.x[3 * i + 1], s->p.x[3 * i + 2], r);
    }
  return ESF_OK;
}

/* Compaction (optional, generate.compact: strain, time): the four lateral walls of the
 * box [min, max] move inward at constant speed by strain L / 2 each over compact_time
 * (the floor stays), then a static box of the compacted size holds the particles while
 * they settle (resettle values). Replaces *b by the result. */
static int compact(esf_ydoc *doc, const char *path, const gen_spec *gs, double min[3],
                   double max[3], esf_sim *b, FILE *log, esf_error *err) {
  static const long one[3] = {1, 1, 1};
  static const unsigned face[4] = {1u, 2u, 4u, 8u}; /* xmin, xmax, ymin, ymax */
  esf_sim c, d;
  memset(&c, 0, sizeof c);
  memset(&d, 0, sizeof d);
  esf_settle_report r;
  settle_spec push = {0, gs->compact_time, gs->compact_time};
  int rc = stage_sim(doc, path, &c, err);
  if (!rc) rc = make_copies(b, gs, one, &c, max[2], err);
  if (!rc) rc = add_faces(&c, min, max, 16u, gs->material, NULL, err); /* the floor */
  for (int k = 0; k < 4 && !rc; k++) {
    double v[3] = {0, 0, 0}, L = max[k / 2] - min[k / 2];
    v[k / 2] = (k % 2 ? -1 : 1) * gs->strain * L / (2 * gs->compact_time);
    rc = add_faces(&c, min, max, face[k], gs->material, v, err);
  }
  c.cfg.energy_every = 0;
  if (!rc) rc = esf_sim_setup(&c, err);
  if (!rc) rc = settle(&c, &push, &r, err);
  if (!rc) log_stage(log, "compact", &r, 0.0);
  for (int k = 0; k < 2; k++) {
    double dl = 0.5 * gs->strain * (max[k] - min[k]);
    min[k] += dl;
    max[k] -= dl;
  }
  if (!rc) rc = stage_sim(doc, path, &d, err);
  if (!rc) rc = make_copies(&c, gs, one, &d, max[2], err);
  if (!rc) rc = add_box(&d, min, max, gs->material, err);
  d.cfg.energy_every = 0;
  if (!rc) rc = esf_sim_setup(&d, err);
  if (!rc) rc = settle(&d, &gs->resettle, &r, err);
  if (!rc) log_stage(log, "compacted", &r, gs->resettle.ke_fraction);
  esf_sim_release(&c);
  esf_sim_release(b);
  *b = d;
  return rc;
}

int esf_generate_copies(const char *path, const char *const *sets, int nsets,
                        const char *out_csv, FILE *log, esf_error *err) {
  esf_ydoc *doc = NULL;
  esf_sim a, b;
  memset(&a, 0, sizeof a);
  memset(&b, 0, sizeof b);
  gen_spec gs;
  esf_settle_report r1, r2;
  memset(&gs, 0, sizeof gs);
  memset(&r1, 0, sizeof r1);
  memset(&r2, 0, sizeof r2);
  int rc = esf_ydoc_load(path, &doc, err);
  for (int k = 0; k < nsets && !rc; k++) rc = esf_ydoc_override(doc, sets[k], err);
  if (!rc) rc = stage_sim(doc, path, &a, err);
  if (!rc) rc = read_spec(esf_ydoc_root(doc), &a, &gs, err);
  if (!rc && a.cfg.dim != 3)
    rc = esf_fail(err, ESF_EINPUT, "%s: esfera generate builds 3D packings only", path);
  if (!rc) rc = check_inside(&a, &gs, err);
  if (!rc) rc = add_box(&a, gs.min, gs.max, gs.material, err);
  a.cfg.energy_every = 0;
  if (!rc) rc = esf_sim_setup(&a, err);
  if (!rc) rc = settle(&a, &gs.settle, &r1, err);
  if (!rc) log_stage(log, "primary", &r1, gs.settle.ke_fraction);
  if (!rc) rc = stage_sim(doc, path, &b, err);
  double H = r1.top - gs.min[2];
  if (!rc) rc = make_copies(&a, &gs, gs.copies, &b, r1.top, err);
  double bmin[3] = {gs.min[0], gs.min[1], gs.min[2]}, bmax[3];
  for (int k = 0; k < 3; k++)
    bmax[k] = gs.min[k] + (double)gs.copies[k] * (gs.max[k] - gs.min[k]);
  bmax[2] = gs.min[2] + (double)gs.copies[2] * fmax(H, gs.max[2] - gs.min[2]);
  if (!rc) rc = add_box(&b, bmin, bmax, gs.material, err);
  b.cfg.energy_every = 0;
  if (!rc) rc = esf_sim_setup(&b, err);
  if (!rc) rc = settle(&b, &gs.resettle, &r2, err);
  if (!rc) log_stage(log, "copies", &r2, gs.resettle.ke_fraction);
  if (!rc && gs.strain > 0) rc = compact(doc, path, &gs, bmin, bmax, &b, log, err);
  if (!rc) rc = write_csv(out_csv, &b, err);
  if (!rc && log)
    fprintf(log, "generate: wrote %s: %zu particles (%ld x %ld x %ld copies of %zu)\n",
            out_csv, b.p.n, gs.copies[0], gs.copies[1], gs.copies[2], a.p.n);
  esf_sim_release(&a);
  esf_sim_release(&b);
  esf_ydoc_free(&doc);
  return rc;
}
