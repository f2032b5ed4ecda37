/* wall_mesh.c — triangle mesh of the walls (wall_mesh.h).
 *
 * Polygons: their vertices as stored (m) and fan triangles. Planes: a square patch of
 * side s about c, the projection of the sizing box's centre onto the plane, with
 * in-plane axes u = unit(n x a), a the coordinate axis least aligned with n, and
 * v = n x u, so u x v = n; corners c + (s/2)(-u-v, u-v, u+v, -u+v) and triangles
 * (0,1,2), (0,2,3) face along n. s is the box's diagonal, or 1 m when the box is
 * empty. Moving walls not at time t are placed at t in a copy (esf_walls_set_time on
 * copies of the elements and groups, sharing the read-only reference geometry e0).
 * Entry: walls as the sim holds them; exit: m holds the mesh at t, walls unchanged. */
#include "bodies/wall_mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/vec3.h"

static int reserve(esf_wall_mesh *m, size_t np, size_t nt, esf_error *err) {
  if (np > m->cap_p) {
    double *p = realloc(m->points, 3 * np * sizeof *p);
    if (!p) return esf_fail(err, ESF_ENOMEM, "out of memory for the wall mesh");
    m->points = p;
    m->cap_p = np;
  }
  if (nt > m->cap_t) {
    int32_t *t = realloc(m->tri, 3 * nt * sizeof *t);
    if (t) m->tri = t;
    int32_t *g = t ? realloc(m->group, nt * sizeof *g) : NULL;
    if (g) m->group = g;
    int32_t *mt = g ? realloc(m->material, nt * sizeof *mt) : NULL;
    if (!mt) return esf_fail(err, ESF_ENOMEM, "out of memory for the wall mesh");
    m->material = mt;
    m->cap_t = nt;
  }
  return ESF_OK;
}

/* The sizing box: the given one if not empty, else that of the finite elements.
 * Returns 0 when there is none. */
static int sizing_box(const esf_walls *w, const double *lo, const double *hi,
                      double blo[3], double bhi[3]) {
  if (lo && hi && lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2]) {
    v3_copy(blo, lo);
    v3_copy(bhi, hi);
    return 1;
  }
  int any = 0;
  for (size_t k = 0; k < w->n; k++) {
    const esf_wall_elem *e = &w->e[k];
    for (int j = 0; e->kind == ESF_WALL_POLYGON && j < e->nv; j++, any = 1)
      for (int q = 0; q < 3; q++) {
        blo[q] = any ? fmin(blo[q], e->v[j][q]) : e->v[j][q];
        bhi[q] = any ? fmax(bhi[q], e->v[j][q]) : e->v[j][q];
      }
  }
  return any;
}

static void plane_patch(const esf_wall_elem *e, int have_box, const double blo[3],
                        const double bhi[3], double out[4][3]) {
  const double *n = e->n;
  double c[3], s = 1.0;
  v3_copy(c, e->p);
  if (have_box) {
    double mid[3], diag[3], d[3];
    for (int q = 0; q < 3; q++) {
      mid[q] = 0.5 * (blo[q] + bhi[q]);
      diag[q] = bhi[q] - blo[q];
    }
    v3_sub(d, mid, e->p);
    v3_copy(c, mid);
    v3_axpy(c, -v3_dot(d, n), n);
    if (v3_norm(diag) > 0) s = v3_norm(diag);
  }
  double u[3], v[3];
  v3_basis(u, v, n);
  const double su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
  for (int j = 0; j < 4; j++)
    for (int q = 0; q < 3; q++)
      out[j][q] = c[q] + 0.5 * s * (su[j] * u[q] + sv[j] * v[q]);
}

/* w placed at time t: w itself, or a copy in m's scratch storage. */
static int walls_at(const esf_walls *w, double t, esf_wall_mesh *m, esf_walls *copy,
                    const esf_walls **out, esf_error *err) {
  *out = w;
  if (!w->moving || t == w->t) return ESF_OK;
  if (w->n > m->cap_se) {
    esf_wall_elem *e = realloc(m->scratch_e, w->n * sizeof *e);
    if (!e) return esf_fail(err, ESF_ENOMEM, "out of memory for the wall mesh");
    m->scratch_e = e;
    m->cap_se = w->n;
  }
  if (w->ngroups > m->cap_sg) {
    esf_wall_group *g = realloc(m->scratch_g, (size_t)w->ngroups * sizeof *g);
    if (!g) return esf_fail(err, ESF_ENOMEM, "out of memory for the wall mesh");
    m->scratch_g = g;
    m->cap_sg = w->ngroups;
  }
  *copy = *w;
  copy->e = m->scratch_e;
  copy->g = m->scratch_g;
  copy->cap = w->n;
  memcpy(copy->e, w->e, w->n * sizeof *w->e);
  memcpy(copy->g, w->g, (size_t)w->ngroups * sizeof *w->g);
  esf_walls_set_time(copy, t);
  *out = copy;
  return ESF_OK;
}

int esf_wall_mesh_build(const esf_walls *walls, double t, const double *box_lo,
                        const double *box_hi, esf_wall_mesh *m, esf_error *err) {
  m->np = m->nt = 0;
  esf_walls copy;
  const esf_walls *w = NULL;
  int rc = walls_at(walls, t, m, &copy, &w, err);
  if (rc) return rc;
  size_t np = 0, nt = 0;
  for (size_t k = 0; k < w->n; k++) {
    if (w->g[w->e[k].group].absent) continue; /* removed by an event */
    int nv = w->e[k].kind == ESF_WALL_PLANE ? 4 : w->e[k].nv;
    np += (size_t)nv;
    nt += (size_t)(nv - 2);
  }
  rc = reserve(m, np, nt, err);
  if (rc) return rc;
  double blo[3], bhi[3];
  int have_box = sizing_box(w, box_lo, box_hi, blo, bhi);
  for (size_t k = 0; k < w->n; k++) {
    const esf_wall_elem *e = &w->e[k];
    if (w->g[e->group].absent) continue;
    double quad[4][3];
    int nv = e->nv;
    const double(*verts)[3] = e->v;
    if (e->kind == ESF_WALL_PLANE) {
      plane_patch(e, have_box, blo, bhi, quad);
      nv = 4;
      verts = (const double(*)[3])quad;
    }
    int32_t base = (int32_t)m->np;
    for (int j = 0; j < nv; j++) v3_copy(m->points + 3 * m->np++, verts[j]);
    for (int j = 1; j + 1 < nv; j++) {
      int32_t *t = m->tri + 3 * m->nt;
      t[0] = base;
      t[1] = base + j;
      t[2] = base + j + 1;
      m->group[m->nt] = e->group;
      m->material[m->nt] = e->material;
      m->nt++;
    }
  }
  return ESF_OK;
}

void esf_wall_mesh_release(esf_wall_mesh *m) {
  free(m->points);
  free(m->tri);
  free(m->group);
  free(m->material);
  free(m->scratch_e);
  free(m->scratch_g);
  memset(m, 0, sizeof *m);
}
