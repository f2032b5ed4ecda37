/* scene_overlap.c — overlaps at the start (scene_parts.h): a particle that starts inside
 * a wall, or two particles that start overlapping by more than the contact law's limit,
 * is bad input, told with the particle's id, the wall element or other particle, the
 * overlap and where the scene defines them (file:line:column), instead of a failure of
 * the first step. Overlaps with walls are measured as the force evaluation does
 * (model/forces.c): un = r - dist to the element's nearest point (a plane's distance is
 * signed), against the walls placed at t = 0 (moving walls frozen on a copy); the
 * element candidates come from the wall index (bodies/wall_index.h), the particle pairs
 * from the cell search (search/cells.h; across periodic faces search/periodic.h, on the
 * positions wrapped into the box). Particles outside the domain are skipped (the first
 * list build removes them). Units: m. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bodies/wall_index.h"
#include "scene/scene_parts.h"
#include "search/cells.h"
#include "search/periodic.h"
#include "util/vec3.h"

/* Where particle i comes from: its entry of the particles list, and for a file the
 * file's own key. */
static void particle_place(const esf_ynode *seq, const uint32_t *entry, size_t i,
                           char *buf, size_t len) {
  const esf_ynode *e = seq->items[entry[i]];
  const esf_ynode *f = esf_ymap_get(e, "file");
  char w[600];
  esf_ynode_where(f ? f : e, w, sizeof w);
  snprintf(buf, len, "%s (particles.%u%s)", w, entry[i],
           f                             ? ", a row of its file"
           : esf_ymap_get(e, "generate") ? ", generated"
                                         : "");
}

/* A copy of the walls placed at t = 0 (a moving wall's phase may displace it). */
static int walls_at_start(const esf_walls *w, esf_walls *c, esf_error *err) {
  memset(c, 0, sizeof *c);
  c->g = malloc((w->ngroups ? (size_t)w->ngroups : 1) * sizeof *c->g);
  c->e = malloc((w->n ? w->n : 1) * sizeof *c->e);
  if (!c->g || !c->e) {
    esf_walls_release(c);
    return esf_fail(err, ESF_ENOMEM, "out of memory");
  }
  memcpy(c->g, w->g, (size_t)w->ngroups * sizeof *c->g);
  memcpy(c->e, w->e, w->n * sizeof *c->e);
  c->ngroups = w->ngroups;
  c->n = c->cap = w->n;
  int rc = esf_walls_freeze(c, 0.0, err);
  if (rc) esf_walls_release(c);
  return rc;
}

static int outside(const esf_sim *s, const double *x) { /* periodic axes: never */
  return s->cfg.has_domain && v3_outside(x, s->cfg.keep_lo, s->cfg.keep_hi);
}

/* The pairs with periodic axes: the positions x (m of them, a copy) wrapped into the
 * box, the pairs across the faces with their images (search/periodic.h) into pb, img. */
static int periodic_pairs(const esf_sim *s, size_t m, double *x, const double *r,
                          esf_cells *cells, esf_pairbuf *pb, int8_t **img,
                          esf_error *err) {
  double *v = calloc(3 * m + 1, sizeof *v);    /* the wrap's velocities: unused */
  int32_t *im = calloc(3 * m + 1, sizeof *im); /* and image counters */
  size_t cap = 0;
  int rc = v && im ? ESF_OK : esf_fail(err, ESF_ENOMEM, "out of memory");
  if (!rc) esf_periodic_wrap(&s->cfg.per, m, x, v, 0.0, im);
  if (!rc)
    rc = esf_periodic_pairs(&s->cfg.per, cells, m, x, r, 0.0, 0.0, pb, img, &cap, err);
  if (rc == ESF_EINPUT)
    esf_error_prefix(err, "%s: domain.periodic: ", esf_config_where(&s->cfg, "domain"));
  free(v);
  free(im);
  return rc;
}

static int check_walls(const esf_ynode *seq, const esf_ynode *walls, const esf_sim *s,
                       const uint32_t *entry, esf_error *err) {
  esf_walls w;
  int rc = walls_at_start(&s->walls, &w, err);
  if (rc) return rc;
  esf_wall_index *idx = NULL;
  rc = esf_wall_index_sync(&idx, &w, err);
  uint32_t *scratch = rc ? NULL : malloc(esf_wall_index_scratch(idx) * sizeof *scratch);
  if (!rc && !scratch) rc = esf_fail(err, ESF_ENOMEM, "out of memory");
  const esf_particles *p = &s->p;
  const double lim = s->cfg.max_overlap;
  for (size_t i = 0; i < p->n && !rc; i++) {
    const double *x = p->x + 3 * i, r = p->radius[i];
    if (outside(s, x)) continue;
    const esf_ynode *e = seq->items[entry[i]];
    const int explicit_ = !esf_ymap_get(e, "file") && !esf_ymap_get(e, "generate");
    const uint32_t *el = NULL;
    size_t ne = 0;
    esf_wall_index_query(idx, &w, x, r, scratch, &el, &ne);
    for (size_t q = 0; q < ne && !rc; q++) {
      if (w.g[w.e[el[q]].group].absent) continue; /* added later by an event */
      esf_wall_hit hit;
      esf_wall_nearest(&w.e[el[q]], x, &hit);
      const double un = r - hit.dist;
      const int beyond = un > lim * r;
      if (!(un > 0) || (!beyond && (!explicit_ || s->cfg.allow_initial_overlap)))
        continue;
      const int g = w.e[el[q]].group;
      char pp[700], wp[600] = "";
      particle_place(seq, entry, i, pp, sizeof pp);
      if (walls && g < (int)walls->n) esf_ynode_where(walls->items[g], wp, sizeof wp);
      rc = esf_fail(err, ESF_EINPUT,
                    "%s: particle id %lld at (%g, %g, %g) m, radius %g m, starts "
                    "overlapping wall element %u of walls.%d ('%s' at %s) by %.4g m, "
                    "%.3g%% of its radius (limit %.3g%%)%s. Move the particle or the "
                    "wall%s",
                    pp, (long long)p->id[i], x[0], x[1], x[2], r, el[q], g, w.g[g].label,
                    wp, un, 100.0 * un / r, 100.0 * lim,
                    beyond ? ", more than contact.max_overlap allows (the first step "
                             "would fail)"
                           : "",
                    beyond ? "" : ", or set contact.allow_initial_overlap: true");
    }
  }
  free(scratch);
  esf_wall_index_free(&idx);
  esf_walls_release(&w);
  return rc;
}

/* Particles outside the domain are left out of the pair search (they are skipped, and
 * one far away would stretch the search's cell grid over all the space between, making
 * it slow): in[k] is the particle of search index k, x and r their positions and radii
 * (p's own arrays when no particle is left out). */
static int check_pairs(const esf_ynode *seq, const esf_sim *s, const uint32_t *entry,
                       esf_error *err) {
  const esf_particles *p = &s->p;
  esf_cells *cells = NULL;
  esf_pairbuf pb = {0};
  size_t m = 0;
  for (size_t i = 0; i < p->n; i++) m += !outside(s, p->x + 3 * i);
  const int per = s->cfg.per.any, subset = m < p->n || per; /* per: x is wrapped */
  int8_t *img = NULL;
  uint32_t *in = NULL;
  double *x = p->x, *r = p->radius;
  int rc = ESF_OK;
  if (subset) {
    in = malloc(m * sizeof *in + 1);
    x = malloc(3 * m * sizeof *x + 1);
    r = malloc(m * sizeof *r + 1);
    if (!in || !x || !r) rc = esf_fail(err, ESF_ENOMEM, "out of memory");
  }
  for (size_t i = 0, k = 0; subset && !rc && i < p->n; i++) {
    if (outside(s, p->x + 3 * i)) continue;
    in[k] = (uint32_t)i;
    memcpy(x + 3 * k, p->x + 3 * i, 3 * sizeof *x);
    r[k++] = p->radius[i];
  }
  if (!rc) rc = esf_cells_create(&cells, err);
  if (!rc && per) rc = periodic_pairs(s, m, x, r, cells, &pb, &img, err);
  if (!rc && !per) rc = esf_cells_pairs(cells, m, x, r, 0.0, &pb, err);
  for (size_t k = 0; k < pb.n && !rc; k++) {
    const uint32_t a = subset ? in[pb.i[k]] : pb.i[k], b = subset ? in[pb.j[k]] : pb.j[k];
    const double rmin = p->radius[a] < p->radius[b] ? p->radius[a] : p->radius[b];
    double dx[3], xb[3];
    memcpy(xb, x + 3 * (size_t)pb.j[k], sizeof xb);
    if (per) esf_periodic_image(x + 3 * (size_t)pb.j[k], img + 3 * k, s->cfg.per.len, xb);
    v3_sub(dx, xb, x + 3 * (size_t)pb.i[k]);
    const double d = v3_norm(dx);
    const double un = p->radius[a] + p->radius[b] - d;
    if (!(un > s->cfg.max_overlap * rmin)) continue;
    char pa[700], pbp[700];
    particle_place(seq, entry, a, pa, sizeof pa);
    particle_place(seq, entry, b, pbp, sizeof pbp);
    rc = esf_fail(err, ESF_EINPUT,
                  "%s: particle id %lld and particle id %lld (%s) start overlapping by "
                  "%.4g m, %.3g%% of the smaller radius, more than contact.max_overlap "
                  "(%.3g%%) allows: the first step would fail. Move them apart",
                  pa, (long long)p->id[a], (long long)p->id[b],
                  strcmp(pa, pbp) ? pbp : "the same entry", un, 100.0 * un / rmin,
                  100.0 * s->cfg.max_overlap);
  }
  esf_pairbuf_release(&pb);
  esf_cells_free(&cells);
  free(img);
  if (subset) {
    free(in);
    free(x);
    free(r);
  }
  return rc;
}

int esf_scene_check_overlaps(const esf_ynode *seq, const esf_ynode *walls,
                             const esf_sim *s, const uint32_t *entry, esf_error *err) {
  int rc = s->walls.n ? check_walls(seq, walls, s, entry, err) : ESF_OK;
  if (!rc) rc = check_pairs(seq, s, entry, err);
  return rc;
}
