/* wall_index.c — uniform grids of wall element bounding boxes (wall_index.h).
 *
 * Build, per group of at least ESF_WALL_INDEX_MIN polygons (and no plane): the axis-
 * aligned bounding box of each element in the reference frame, the group's box, a cell
 * edge h = the mean of the elements' largest box extents, grown until the grid has at
 * most 8 n + 64 cells; each element is listed (CSR) in every cell its box touches.
 * Elements of other groups go to a `loose` list reported by every query.
 * Query for (x, r): x_ref = pivot + R(-angle) (x - disp - pivot) for a rotating group
 * (x - disp otherwise: the inverse of wall_motion.c's placement), the cells under the
 * cube [x_ref - r, x_ref + r] (clamped to the grid), each element whose box meets the
 * cube; an element seen in several cells is reported only from the cell whose
 * coordinates are the componentwise max of its box's first cell and the query's first
 * cell, so each once without marks. Rigid motions keep distances, so the reference-
 * frame test is exact. Units: m. Entry: w frozen (esf_walls_freeze) before a moving
 * group is queried. */
#include "bodies/wall_index.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/vec3.h"

typedef struct grid {
  int group;
  double lo[3], h;
  int nc[3];
  uint32_t *start, *items;
} grid;

struct esf_wall_index {
  size_t n;                 /* elements indexed */
  const esf_wall_elem *ref; /* the reference geometry used */
  int ngroups, ngrids;
  grid *g;
  int *grid_of;   /* per group: its grid or -1 */
  double *box;    /* 6 per element: lo, hi (reference frame) */
  int32_t *cell0; /* 3 per element: first cell of its box */
  uint32_t *loose;
  size_t nloose;
};

static const esf_wall_elem *reference(const esf_walls *w) { return w->e0 ? w->e0 : w->e; }

/* clamped before the cast: x may lie any distance from the grid */
static int cell_of(const grid *g, int q, double x) {
  double c = floor((x - g->lo[q]) / g->h);
  return !(c >= 0) ? 0 : c >= g->nc[q] ? g->nc[q] - 1 : (int)c;
}

static int build_grid(esf_wall_index *ix, grid *gr, const uint32_t *el, size_t m,
                      esf_error *err) {
  double hi[3], ext = 0;
  for (int q = 0; q < 3; q++) gr->lo[q] = INFINITY, hi[q] = -INFINITY;
  for (size_t k = 0; k < m; k++) {
    const double *b = ix->box + 6 * el[k];
    double e = 0;
    for (int q = 0; q < 3; q++) {
      gr->lo[q] = fmin(gr->lo[q], b[q]);
      hi[q] = fmax(hi[q], b[3 + q]);
      e = fmax(e, b[3 + q] - b[q]);
    }
    ext += e / (double)m;
  }
  double span = fmax(hi[0] - gr->lo[0], fmax(hi[1] - gr->lo[1], hi[2] - gr->lo[2]));
  gr->h = ext > 0 ? ext : span;
  double ncell, c[3];
  for (;;) {
    ncell = 1;
    for (int q = 0; q < 3; q++) {
      c[q] = floor((hi[q] - gr->lo[q]) / gr->h) + 1;
      ncell *= c[q];
    }
    if (ncell <= 8.0 * (double)m + 64) break;
    gr->h *= 1.25;
  }
  for (int q = 0; q < 3; q++) gr->nc[q] = (int)c[q]; /* each <= ncell: exact */
  size_t nc = (size_t)ncell, total = 0;
  gr->start = calloc(nc + 1, sizeof *gr->start);
  if (!gr->start) return esf_fail(err, ESF_ENOMEM, "out of memory for the wall index");
  for (int pass = 0; pass < 2; pass++) {
    for (size_t k = 0; k < m; k++) {
      const double *b = ix->box + 6 * el[k];
      int c0[3], c1[3];
      for (int q = 0; q < 3; q++) {
        c0[q] = cell_of(gr, q, b[q]);
        c1[q] = cell_of(gr, q, b[3 + q]);
        ix->cell0[3 * el[k] + q] = c0[q];
      }
      for (int i = c0[0]; i <= c1[0]; i++)
        for (int j = c0[1]; j <= c1[1]; j++)
          for (int l = c0[2]; l <= c1[2]; l++) {
            size_t c = ((size_t)l * gr->nc[1] + j) * gr->nc[0] + i;
            if (pass == 0)
              gr->start[c + 1]++;
            else
              gr->items[gr->start[c]++] = el[k];
          }
    }
    if (pass == 0) {
      for (size_t c = 0; c < nc; c++) gr->start[c + 1] += gr->start[c];
      total = gr->start[nc];
      gr->items = malloc((total ? total : 1) * sizeof *gr->items);
      if (!gr->items)
        return esf_fail(err, ESF_ENOMEM, "out of memory for the wall index");
    }
  }
  for (size_t c = nc; c > 0; c--) gr->start[c] = gr->start[c - 1]; /* undo the fill */
  gr->start[0] = 0;
  return ESF_OK;
}

void esf_wall_index_free(esf_wall_index **idx) {
  if (!idx || !*idx) return;
  esf_wall_index *ix = *idx;
  for (int k = 0; k < ix->ngrids; k++) {
    free(ix->g[k].start);
    free(ix->g[k].items);
  }
  free(ix->g);
  free(ix->grid_of);
  free(ix->box);
  free(ix->cell0);
  free(ix->loose);
  free(ix);
  *idx = NULL;
}

static int build(esf_wall_index *ix, const esf_walls *w, esf_error *err) {
  const esf_wall_elem *e = reference(w);
  size_t n = w->n, sz = n ? n : 1;
  ix->n = n;
  ix->ref = e;
  ix->ngroups = w->ngroups;
  ix->box = malloc(6 * sz * sizeof *ix->box);
  ix->cell0 = malloc(3 * sz * sizeof *ix->cell0);
  ix->loose = malloc(sz * sizeof *ix->loose);
  ix->grid_of = malloc((w->ngroups ? w->ngroups : 1) * sizeof *ix->grid_of);
  ix->g = calloc(w->ngroups ? w->ngroups : 1, sizeof *ix->g);
  uint32_t *el = malloc(sz * sizeof *el);
  size_t *count = calloc(w->ngroups ? w->ngroups : 1, sizeof *count);
  int rc = ESF_OK;
  if (!ix->box || !ix->cell0 || !ix->loose || !ix->grid_of || !ix->g || !el || !count)
    rc = esf_fail(err, ESF_ENOMEM, "out of memory for the wall index");
  for (size_t k = 0; k < n && !rc; k++) {
    double *b = ix->box + 6 * k;
    for (int q = 0; q < 3; q++) b[q] = INFINITY, b[3 + q] = -INFINITY;
    for (int j = 0; j < e[k].nv; j++)
      for (int q = 0; q < 3; q++) {
        b[q] = fmin(b[q], e[k].v[j][q]);
        b[3 + q] = fmax(b[3 + q], e[k].v[j][q]);
      }
    count[e[k].group]++;
  }
  for (int g = 0; g < w->ngroups && !rc; g++) ix->grid_of[g] = -1;
  for (size_t k = 0; k < n && !rc; k++) /* a plane leaves its group unindexed */
    if (e[k].kind == ESF_WALL_PLANE) count[e[k].group] = 0;
  for (int g = 0; g < w->ngroups && !rc; g++) {
    if (count[g] < ESF_WALL_INDEX_MIN) continue;
    size_t m = 0;
    for (size_t k = 0; k < n; k++)
      if (e[k].group == g) el[m++] = (uint32_t)k;
    grid *gr = &ix->g[ix->ngrids++];
    gr->group = g;
    ix->grid_of[g] = ix->ngrids - 1;
    rc = build_grid(ix, gr, el, m, err);
  }
  ix->nloose = 0;
  for (size_t k = 0; k < n && !rc; k++)
    if (ix->grid_of[e[k].group] < 0) ix->loose[ix->nloose++] = (uint32_t)k;
  free(el);
  free(count);
  return rc;
}

int esf_wall_index_sync(esf_wall_index **idx, const esf_walls *w, esf_error *err) {
  if (*idx && (*idx)->n == w->n && (*idx)->ref == reference(w) &&
      (*idx)->ngroups == w->ngroups)
    return ESF_OK;
  esf_wall_index_free(idx);
  *idx = calloc(1, sizeof **idx);
  if (!*idx) return esf_fail(err, ESF_ENOMEM, "out of memory for the wall index");
  int rc = build(*idx, w, err);
  if (rc) esf_wall_index_free(idx);
  return rc;
}

int esf_wall_index_grids(const esf_wall_index *idx) { return idx ? idx->ngrids : 0; }

/* x carried into group g's reference frame */
static void to_reference(const esf_wall_group *g, const double x[3], double out[3]) {
  v3_sub(out, x, g->disp);
  const esf_wall_motion *m = &g->motion;
  if (!g->moving || m->kind != ESF_MOTION_ROTATE || g->angle == 0) return;
  double r[3], kxr[3], c = cos(g->angle), s = -sin(g->angle);
  v3_sub(r, out, m->pivot);
  v3_cross(kxr, m->axis, r);
  double kr = v3_dot(m->axis, r) * (1 - c);
  for (int q = 0; q < 3; q++)
    out[q] = m->pivot[q] + r[q] * c + kxr[q] * s + m->axis[q] * kr;
}

size_t esf_wall_index_scratch(const esf_wall_index *ix) { return ix->n ? ix->n : 1; }

void esf_wall_index_query(const esf_wall_index *ix, const esf_walls *w, const double x[3],
                          double r, uint32_t *scratch, const uint32_t **out, size_t *n) {
  if (ix->ngrids == 0) { /* only loose elements: no copy */
    *out = ix->loose;
    *n = ix->nloose;
    return;
  }
  size_t m = ix->nloose;
  memcpy(scratch, ix->loose, m * sizeof *scratch);
  for (int k = 0; k < ix->ngrids; k++) {
    const grid *gr = &ix->g[k];
    double y[3];
    to_reference(&w->g[gr->group], x, y);
    int c0[3], c1[3], outside = 0;
    for (int q = 0; q < 3; q++) {
      double hi = gr->lo[q] + gr->nc[q] * gr->h;
      if (y[q] + r < gr->lo[q] || y[q] - r > hi) outside = 1;
      c0[q] = cell_of(gr, q, y[q] - r);
      c1[q] = cell_of(gr, q, y[q] + r);
    }
    if (outside) continue;
    for (int l = c0[2]; l <= c1[2]; l++)
      for (int j = c0[1]; j <= c1[1]; j++)
        for (int i = c0[0]; i <= c1[0]; i++) {
          size_t c = ((size_t)l * gr->nc[1] + j) * gr->nc[0] + i;
          for (uint32_t s = gr->start[c]; s < gr->start[c + 1]; s++) {
            uint32_t e = gr->items[s];
            const double *b = ix->box + 6 * e;
            const int32_t *e0 = ix->cell0 + 3 * e;
            if (b[0] > y[0] + r || b[3] < y[0] - r || b[1] > y[1] + r ||
                b[4] < y[1] - r || b[2] > y[2] + r || b[5] < y[2] - r)
              continue;
            if (i != (e0[0] > c0[0] ? e0[0] : c0[0]) ||
                j != (e0[1] > c0[1] ? e0[1] : c0[1]) ||
                l != (e0[2] > c0[2] ? e0[2] : c0[2]))
              continue; /* reported from another cell */
            scratch[m++] = e;
          }
        }
  }
  *out = scratch;
  *n = m;
}
