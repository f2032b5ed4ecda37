/* neighbor.c — Verlet candidate lists over the linked cells, with history transfer.
 *
 * Build: (1) index the old lists' touching contacts by key (a, b) in a sorted array;
 * (2) find the particle pairs within skin by the cells (each once) and, for every
 * particle, the wall elements within skin (among those the wall index, wall_index.h,
 * reports near it); (3) for every new candidate, binary-search its key in the old
 * index and copy the history and the touching flag. Contacts no longer candidates lose
 * their history, as they can only be out of contact (their gap exceeds the skin).
 * Entry: positions finite. Exit: lists sorted by (a, b); xref = current positions. */
#include "neighbor.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "lines.h"
#include "vec3.h"
#include "wall_index.h"

static void contacts_release(esf_contacts *c) {
  free(c->a);
  free(c->b);
  free(c->h);
  free(c->touch);
  free(c->led);
  free(c->vc0);
  memset(c, 0, sizeof *c);
}

static int contacts_reserve(esf_contacts *c, size_t n, int ledger, int carry,
                            esf_error *err) {
  if (n <= c->cap) return ESF_OK;
  size_t cap = c->cap ? c->cap : 64;
  while (cap < n) cap *= 2;
  uint32_t *a = realloc(c->a, cap * sizeof *a);
  if (a) c->a = a;
  uint32_t *b = realloc(c->b, cap * sizeof *b);
  if (b) c->b = b;
  esf_contact_hist *h = esf_lines_realloc(c->h, c->n * sizeof *h, cap * sizeof *h);
  if (h) c->h = h;
  uint8_t *t = realloc(c->touch, cap * sizeof *t);
  if (t) c->touch = t;
  double *l = c->led;
  if (ledger) {
    l = realloc(c->led, cap * ESF_LED_STRIDE * sizeof *l);
    if (l) c->led = l;
  }
  double *v0 = c->vc0;
  if (carry) {
    v0 = realloc(c->vc0, cap * 3 * sizeof *v0);
    if (v0) c->vc0 = v0;
  }
  if (!a || !b || !h || !t || (ledger && !l) || (carry && !v0))
    return esf_fail(err, ESF_ENOMEM, "out of memory for %zu contact candidates", cap);
  c->cap = cap;
  return ESF_OK;
}

int esf_neighbor_init(esf_neighbor *nb, double skin, int ledger, esf_error *err) {
  memset(nb, 0, sizeof *nb);
  nb->skin = skin;
  nb->ledger = ledger;
  return esf_cells_create(&nb->cells, err);
}

void esf_neighbor_release(esf_neighbor *nb) {
  contacts_release(&nb->pp);
  contacts_release(&nb->pw);
  esf_cells_free(&nb->cells);
  esf_pairbuf_release(&nb->buf);
  esf_wall_index_free(&nb->widx);
  free(nb->wall_hits);
  free(nb->wall_un);
  free(nb->wall_keep);
  free(nb->xref);
  memset(nb, 0, sizeof *nb);
}

int esf_neighbor_check(const esf_neighbor *nb, const esf_particles *p, double wall_moved,
                       int *rebuild, esf_error *err) {
  *rebuild = nb->xref == NULL || nb->nref != p->n;
  double lim2 = 0.25 * nb->skin * nb->skin, max2 = 0.0;
  if (!*rebuild && nb->disp_valid) { /* measured during the drift, all finite */
    max2 = nb->max_disp2;
    if (max2 > lim2) *rebuild = 1;
    if (wall_moved > 0 && sqrt(max2) + wall_moved > 0.5 * nb->skin) *rebuild = 1;
    return ESF_OK;
  }
  for (size_t i = 0; i < p->n; i++) {
    const double *x = p->x + 3 * i;
    if (!isfinite(x[0]) || !isfinite(x[1]) || !isfinite(x[2]))
      return esf_fail(err, ESF_ENUMERIC,
                      "particle id %lld has a non-finite position (%g, %g, %g)",
                      (long long)p->id[i], x[0], x[1], x[2]);
    if (*rebuild) continue;
    const double *r = nb->xref + 3 * i;
    double dx = x[0] - r[0], dy = x[1] - r[1], dz = x[2] - r[2];
    double d2 = dx * dx + dy * dy + dz * dz;
    if (d2 > max2) max2 = d2;
  }
  if (max2 > lim2) *rebuild = 1;
  if (wall_moved > 0 && sqrt(max2) + wall_moved > 0.5 * nb->skin) *rebuild = 1;
  return ESF_OK;
}

/* sorted index of the touching contacts of a list: key (a, b) -> position */
typedef struct hkey {
  uint32_t a, b;
  size_t k;
} hkey;

static int hkey_cmp(const void *x, const void *y) {
  const hkey *p = x, *q = y;
  if (p->a != q->a) return p->a < q->a ? -1 : 1;
  if (p->b != q->b) return p->b < q->b ? -1 : 1;
  return 0;
}

static int index_touching(const esf_contacts *c, hkey **out, size_t *nout,
                          esf_error *err) {
  size_t m = 0;
  for (size_t k = 0; k < c->n; k++) m += c->touch[k];
  *nout = m;
  *out = NULL;
  if (!m) return ESF_OK;
  hkey *h = malloc(m * sizeof *h);
  if (!h) return esf_fail(err, ESF_ENOMEM, "out of memory for the contact index");
  m = 0;
  for (size_t k = 0; k < c->n; k++)
    if (c->touch[k]) h[m++] = (hkey){c->a[k], c->b[k], k};
  qsort(h, m, sizeof *h, hkey_cmp);
  *out = h;
  return ESF_OK;
}

static const hkey *index_find(const hkey *h, size_t m, uint32_t a, uint32_t b) {
  hkey key = {a, b, 0};
  return m ? bsearch(&key, h, m, sizeof *h, hkey_cmp) : NULL;
}

static int cand_cmp(const void *x, const void *y) {
  const uint32_t *p = x, *q = y;
  if (p[0] != q[0]) return p[0] < q[0] ? -1 : 1;
  return (p[1] > q[1]) - (p[1] < q[1]);
}

/* Fills dst from candidate keys (pairs of uint32), copying history from the old list. */
static int fill_from(esf_contacts *dst, const uint32_t *keys, size_t m,
                     const esf_contacts *old, const hkey *idx, size_t nidx, int ledger,
                     int carry, esf_error *err) {
  int rc = contacts_reserve(dst, m, ledger, carry, err);
  if (rc) return rc;
  for (size_t k = 0; k < m; k++) {
    uint32_t a = keys[2 * k], b = keys[2 * k + 1];
    dst->a[k] = a;
    dst->b[k] = b;
    const hkey *f = index_find(idx, nidx, a, b);
    if (f) {
      dst->h[k] = old->h[f->k];
      dst->touch[k] = 1;
      if (carry && old->vc0)
        memcpy(dst->vc0 + 3 * k, old->vc0 + 3 * f->k, 3 * sizeof(double));
    } else {
      memset(&dst->h[k], 0, sizeof dst->h[k]);
      dst->touch[k] = 0;
    }
  }
  dst->n = m;
  return ESF_OK;
}

/* Swaps the contents of two contact lists. */
static void contacts_swap(esf_contacts *x, esf_contacts *y) {
  esf_contacts t = *x;
  *x = *y;
  *y = t;
}

static int rebuild_list(esf_contacts *list, uint32_t *keys, size_t m, int ledger,
                        int carry, esf_error *err) {
  hkey *idx = NULL;
  size_t nidx = 0;
  int rc = index_touching(list, &idx, &nidx, err);
  if (rc) return rc;
  qsort(keys, m, 2 * sizeof(uint32_t), cand_cmp);
  esf_contacts fresh = {0};
  rc = fill_from(&fresh, keys, m, list, idx, nidx, ledger, carry, err);
  free(idx);
  if (rc) {
    contacts_release(&fresh);
    return rc;
  }
  contacts_swap(list, &fresh);
  contacts_release(&fresh);
  return ESF_OK;
}

/* The wall loop's scratch (forces.c), one entry per wall candidate. */
static int wall_scratch_reserve(esf_neighbor *nb, esf_error *err) {
  size_t ws = nb->pw.cap ? nb->pw.cap : 1;
  esf_wall_hit *wh = realloc(nb->wall_hits, ws * sizeof *wh);
  if (wh) nb->wall_hits = wh;
  double *wu = realloc(nb->wall_un, ws * sizeof *wu);
  if (wu) nb->wall_un = wu;
  unsigned char *wk = realloc(nb->wall_keep, ws);
  if (wk) nb->wall_keep = wk;
  if (!wh || !wu || !wk)
    return esf_fail(err, ESF_ENOMEM, "out of memory for wall contacts");
  return ESF_OK;
}

int esf_neighbor_build(esf_neighbor *nb, const esf_particles *p, const esf_walls *w,
                       esf_error *err) {
  int rc = esf_cells_pairs(nb->cells, p->n, p->x, p->radius, nb->skin, &nb->buf, err);
  if (rc) return rc;
  size_t m = nb->buf.n;
  uint32_t *keys = malloc((m ? m : 1) * 2 * sizeof *keys);
  if (!keys) return esf_fail(err, ESF_ENOMEM, "out of memory for contact candidates");
  for (size_t k = 0; k < m; k++) {
    uint32_t a = nb->buf.i[k], b = nb->buf.j[k];
    keys[2 * k] = a < b ? a : b;
    keys[2 * k + 1] = a < b ? b : a;
  }
  rc = rebuild_list(&nb->pp, keys, m, nb->ledger, nb->carry, err);
  free(keys);
  if (rc) return rc;

  /* particle-wall candidates */
  rc = esf_wall_index_sync(&nb->widx, w, err);
  if (rc) return rc;
  size_t cap = 64, mw = 0;
  keys = malloc(cap * 2 * sizeof *keys);
  if (!keys) return esf_fail(err, ESF_ENOMEM, "out of memory for wall candidates");
  for (size_t i = 0; i < p->n; i++) {
    const uint32_t *cand = NULL;
    size_t ncand = 0;
    esf_wall_index_query(nb->widx, w, p->x + 3 * i, p->radius[i] + nb->skin, &cand,
                         &ncand);
    for (size_t c = 0; c < ncand; c++) {
      size_t e = cand[c];
      const esf_wall_elem *el = &w->e[e];
      const double *x = p->x + 3 * i;
      double reach = p->radius[i] + nb->skin;
      if (el->kind == ESF_WALL_POLYGON) { /* cheap bounding-sphere reject */
        double d[3];
        v3_sub(d, x, el->p);
        double lim = el->bound_r + reach;
        if (v3_norm2(d) > lim * lim) continue;
      }
      esf_wall_hit hit;
      esf_wall_nearest(el, x, &hit);
      if (hit.dist >= reach) continue;
      if (mw == cap) {
        cap *= 2;
        uint32_t *nk = realloc(keys, cap * 2 * sizeof *nk);
        if (!nk) {
          free(keys);
          return esf_fail(err, ESF_ENOMEM, "out of memory for wall candidates");
        }
        keys = nk;
      }
      keys[2 * mw] = (uint32_t)i;
      keys[2 * mw + 1] = (uint32_t)e;
      mw++;
    }
  }
  rc = rebuild_list(&nb->pw, keys, mw, nb->ledger, nb->carry, err);
  free(keys);
  if (rc) return rc;
  rc = wall_scratch_reserve(nb, err);
  if (rc) return rc;

  if (nb->nref != p->n || !nb->xref) {
    free(nb->xref);
    nb->xref = malloc((p->n ? p->n : 1) * 3 * sizeof(double));
    if (!nb->xref) return esf_fail(err, ESF_ENOMEM, "out of memory");
    nb->nref = p->n;
  }
  memcpy(nb->xref, p->x, p->n * 3 * sizeof(double));
  nb->builds++;
  nb->disp_valid = 0;
  return ESF_OK;
}

/* Renumbers a list through remap (dropping removed particles). A particle pair whose
 * new numbers come in the other order is turned round to keep a < b: A and B swap,
 * so the history's tangential displacement (force on A = kt xi), its normal (A to B)
 * and the carried relative velocity (B - A) change sign. */
static void remap_list(esf_contacts *c, const size_t *remap, size_t n_old, int walls) {
  size_t m = 0;
  for (size_t k = 0; k < c->n; k++) {
    uint32_t a = c->a[k], b = c->b[k];
    if (a >= n_old || remap[a] == SIZE_MAX) continue;
    if (!walls && (b >= n_old || remap[b] == SIZE_MAX)) continue;
    c->a[m] = (uint32_t)remap[a];
    c->b[m] = walls ? b : (uint32_t)remap[b];
    c->h[m] = c->h[k];
    c->touch[m] = c->touch[k];
    if (c->vc0) memcpy(c->vc0 + 3 * m, c->vc0 + 3 * k, 3 * sizeof(double));
    if (!walls && c->a[m] > c->b[m]) {
      const uint32_t t = c->a[m];
      c->a[m] = c->b[m];
      c->b[m] = t;
      esf_contact_hist *h = &c->h[m];
      for (int q = 0; q < 3; q++) {
        h->xi[q] = -h->xi[q];
        h->n[q] = -h->n[q];
        if (c->vc0) c->vc0[3 * m + q] = -c->vc0[3 * m + q];
      }
    }
    m++;
  }
  c->n = m;
}

void esf_neighbor_remap(esf_neighbor *nb, const size_t *remap, size_t n_old) {
  remap_list(&nb->pp, remap, n_old, 0);
  remap_list(&nb->pw, remap, n_old, 1);
  free(nb->xref); /* force a rebuild at the next check */
  nb->xref = NULL;
  nb->nref = 0;
}

size_t esf_neighbor_touching(const esf_neighbor *nb) {
  size_t m = 0;
  for (size_t k = 0; k < nb->pp.n; k++) m += nb->pp.touch[k];
  for (size_t k = 0; k < nb->pw.n; k++) m += nb->pw.touch[k];
  return m;
}

/* Checkpoint restore (checkpoint.c): room for npp and npw candidates, scratch
 * included. */
int esf_neighbor_reserve(esf_neighbor *nb, size_t npp, size_t npw, esf_error *err) {
  int rc = contacts_reserve(&nb->pp, npp, nb->ledger, nb->carry, err);
  if (!rc) rc = contacts_reserve(&nb->pw, npw, nb->ledger, nb->carry, err);
  if (rc) return rc;
  return wall_scratch_reserve(nb, err);
}
