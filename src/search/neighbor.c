/* neighbor.c — Verlet candidate lists over the linked cells, with history transfer.
 *
 * Build: (1) find the particle pairs within skin by the cells (each once) and, for
 * every particle, the wall elements within skin (among those the wall index,
 * wall_index.h, reports near it); then, for each list: (2) copy the old list's touching
 * contacts (b, history, carried velocity) aside, grouped by particle a; (3) fill the
 * list in its own storage from the new keys, ordered by (a, b), each new candidate
 * taking the history and touching flag of the old contact with its key, found among the
 * few of its a. Contacts no longer candidates lose their history, as they can only be
 * out of contact (their gap exceeds the skin). Only the touching contacts are held
 * twice, not the whole list (a rebuild's peak memory).
 * Entry: positions finite. Exit: lists sorted by (a, b); xref = current positions. */
#include "search/neighbor.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "bodies/wall_index.h"
#include "util/lines.h"
#include "util/vec3.h"

static void contacts_release(esf_candidates *c) {
  free(c->a);
  free(c->b);
  free(c->h);
  free(c->bond);
  free(c->roll);
  free(c->touch);
  free(c->led);
  free(c->vc0);
  free(c->wr0);
  free(c->img);
  memset(c, 0, sizeof *c);
}

/* Room for n candidates in c, with the optional arrays: ledger scratch, carried
 * velocities (carry), bond states (bonds), rolling states (roll). */
static int contacts_reserve(esf_candidates *c, size_t n, int ledger, int carry, int bonds,
                            int roll, int img, esf_error *err) {
  if (n <= c->cap) return ESF_OK;
  const size_t cap = n + n / 4 + 64; /* a quarter of room: the lists grow and shrink */
  uint32_t *a = realloc(c->a, cap * sizeof *a);
  if (a) c->a = a;
  uint32_t *b = realloc(c->b, cap * sizeof *b);
  if (b) c->b = b;
  esf_contact_hist *h = esf_lines_realloc(c->h, c->n * sizeof *h, cap * sizeof *h);
  if (h) c->h = h;
  esf_contact_bond *bd = c->bond;
  if (bonds) {
    bd = realloc(c->bond, cap * sizeof *bd);
    if (bd) c->bond = bd;
  }
  esf_contact_roll *rl = c->roll;
  if (roll) {
    rl = realloc(c->roll, cap * sizeof *rl);
    if (rl) c->roll = rl;
  }
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
  double *w0 = c->wr0;
  if (carry && roll) {
    w0 = realloc(c->wr0, cap * 3 * sizeof *w0);
    if (w0) c->wr0 = w0;
  }
  int8_t *im = c->img;
  if (img) {
    im = realloc(c->img, cap * 3 * sizeof *im);
    if (im) c->img = im;
  }
  if (!a || !b || !h || !t || (ledger && !l) || (carry && !v0) || (bonds && !bd) ||
      (roll && !rl) || (carry && roll && !w0) || (img && !im))
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
  contacts_release(&nb->kept);
  free(nb->ws_start);
  free(nb->ws_ostart);
  free(nb->ws_ok);
  esf_cells_free(&nb->cells);
  esf_pairbuf_release(&nb->buf);
  free(nb->pimg);
  for (size_t t = 0; t < nb->nwbuf; t++) esf_pairbuf_release(&nb->wbuf[t]);
  free(nb->wbuf);
  free(nb->wscratch);
  esf_wall_index_free(&nb->widx);
  free(nb->wall_hits);
  free(nb->wall_un);
  free(nb->wall_keep);
  free(nb->xref);
  memset(nb, 0, sizeof *nb);
}

double esf_neighbor_limit2(const esf_neighbor *nb) { return 0.25 * nb->skin * nb->skin; }

int esf_neighbor_check(const esf_neighbor *nb, const esf_particles *p, double wall_moved,
                       int *rebuild, esf_error *err) {
  *rebuild = nb->xref == NULL || nb->nref != p->n;
  double lim2 = esf_neighbor_limit2(nb), max2 = 0.0;
  if (!*rebuild && nb->disp_valid) { /* measured during the drift, all finite */
    max2 = nb->max_disp2;
    if (max2 > lim2 || nb->escaped) *rebuild = 1;
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
    if (nb->dom_lo && v3_outside(x, nb->dom_lo, nb->dom_hi)) {
      *rebuild = 1; /* esf_sim_remove_escaped's test */
      continue;
    }
    const double *r = nb->xref + 3 * i;
    double dx = x[0] - r[0], dy = x[1] - r[1], dz = x[2] - r[2];
    double d2 = dx * dx + dy * dy + dz * dz;
    if (d2 > max2) max2 = d2;
  }
  if (max2 > lim2) *rebuild = 1;
  if (wall_moved > 0 && sqrt(max2) + wall_moved > 0.5 * nb->skin) *rebuild = 1;
  return ESF_OK;
}

/* ---- the build's history transfer --------------------------------------------------
 * Both lists are kept by particle: the new keys are ordered by a counting sort on a and
 * an insertion sort of each particle's few b; the old list's touching contacts are
 * copied aside grouped the same way (nb->kept, ostart), so each new candidate
 * finds its old history by a scan of the few old contacts of its a. No comparison sort,
 * no hashing: O(n + m). The per-particle passes run on nb->threads threads; each entry's
 * output has a fixed place, so the lists do not depend on the thread count. */

/* Counting sort of entries k < m by their particle ka[k] (only those with keep[k], or
 * all when keep is NULL): start[a] .. start[a + 1] are particle a's slots, in entry
 * order; each slot receives the entry's kb[k] in bs (when bs is not NULL) or its
 * position k in pos. start needs n + 2 entries. */
static void count_by_a(size_t n, const uint32_t *ka, const uint32_t *kb,
                       const uint8_t *keep, size_t m, size_t *start, uint32_t *bs,
                       uint32_t *pos) {
  memset(start, 0, (n + 2) * sizeof *start);
  for (size_t k = 0; k < m; k++)
    if (!keep || keep[k]) start[ka[k] + 2]++;
  for (size_t i = 2; i < n + 2; i++) start[i] += start[i - 1];
  for (size_t k = 0; k < m; k++) { /* start[a + 1] runs from a's first slot to its end */
    if (keep && !keep[k]) continue;
    const size_t q = start[ka[k] + 1]++;
    if (bs)
      bs[q] = kb[k];
    else if (pos)
      pos[q] = (uint32_t)k;
  }
}

/* The build's scratch: n + 2 particle offsets, m contact entries. */
static int scratch_reserve(esf_neighbor *nb, size_t n, size_t m, esf_error *err) {
  if (n + 2 <= nb->ws_n && m <= nb->ws_m) return ESF_OK;
  const size_t cn = n + 2 > nb->ws_n ? n + 2 : nb->ws_n;
  const size_t cm = m > nb->ws_m ? m : nb->ws_m;
  size_t *st = realloc(nb->ws_start, cn * sizeof *st);
  if (st) nb->ws_start = st;
  size_t *os = realloc(nb->ws_ostart, cn * sizeof *os);
  if (os) nb->ws_ostart = os;
  uint32_t *ok = realloc(nb->ws_ok, (cm ? cm : 1) * sizeof *ok);
  if (ok) nb->ws_ok = ok;
  if (!st || !os || !ok)
    return esf_fail(err, ESF_ENOMEM, "out of memory for %zu contact candidates", m);
  nb->ws_n = cn;
  nb->ws_m = cm;
  return ESF_OK;
}

/* Step (2): the touching contacts of list (every a < n: the lists were renumbered) into
 * kc, particle a's at ws_ostart[a] .. ws_ostart[a + 1], in list order; *carry: their
 * carried velocities were copied too. Their bond states are, when the list has them. */
static int keep_touching(esf_neighbor *nb, const esf_candidates *list, esf_candidates *kc,
                         size_t n, int *carry, esf_error *err) {
  int rc = scratch_reserve(nb, n, list->n, err);
  if (rc) return rc;
  size_t *ostart = nb->ws_ostart;
  uint32_t *okk = nb->ws_ok;
  count_by_a(n, list->a, NULL, list->touch, list->n, ostart, NULL, okk);
  const size_t nk = ostart[n];
  *carry = nb->carry && list->vc0 != NULL;
  kc->n = 0; /* empty: released after each build (rebuild_list) */
  const int cb = list->bond != NULL, cr = list->roll != NULL;
  rc = contacts_reserve(kc, nk, 0, *carry, cb, cr, 0, err);
  if (rc) return rc;
  const long nn = (long)nk;
  const int cv = *carry;
#pragma omp parallel for num_threads(nb->threads > 0 ? nb->threads : 1) schedule(static)
  for (long jj = 0; jj < nn; jj++) {
    const size_t j = (size_t)jj, f = okk[j];
    kc->b[j] = list->b[f];
    kc->h[j] = list->h[f];
    if (cv) memcpy(kc->vc0 + 3 * j, list->vc0 + 3 * f, 3 * sizeof(double));
    if (cv && cr) memcpy(kc->wr0 + 3 * j, list->wr0 + 3 * f, 3 * sizeof(double));
    if (cb) kc->bond[j] = list->bond[f];
    if (cr) kc->roll[j] = list->roll[f];
  }
  kc->n = nk;
  free(nb->ws_ok); /* the positions are read: not held through the refill */
  nb->ws_ok = NULL;
  nb->ws_m = 0;
  return ESF_OK;
}

/* Step (3): list filled, in its own storage, from the keys (a, b) (m of them, a < n),
 * with the history of the kept contacts kc (keep_touching, which sized the scratch for
 * these n particles); bonds: the list keeps bond states. */
static int fill_list(esf_neighbor *nb, esf_candidates *list, const esf_candidates *kc,
                     size_t n, const uint32_t *ka, const uint32_t *kb, size_t m,
                     int carry, int bonds, esf_error *err) {
  const int own_keys = ka == nb->buf.i; /* released once read (the build's peak) */
  list->n = 0;                          /* nothing to keep: the storage is refilled */
  list->xs = NULL; /* the ODE methods bind the state again before evaluating */
  list->xsdot = NULL;
  if (list->cap > 2 * m + 1024) /* the old list was much longer (a larger skin, a */
    contacts_release(list);     /* denser state): drop its storage */
  const int img = list == &nb->pp && nb->per && nb->per->any;
  int rc = contacts_reserve(list, m, nb->ledger, nb->carry, bonds, nb->rolling, img, err);
  if (rc) return rc;
  size_t *start = nb->ws_start;
  const size_t *ostart = nb->ws_ostart;
  count_by_a(n, ka, kb, NULL, m, start, list->b, NULL); /* the new keys' b by a */
  if (own_keys) esf_pairbuf_release(&nb->buf);
  const long nn = (long)n;
  const esf_contact_hist zero = {0}; /* all bits zero */
#pragma omp parallel for num_threads(nb->threads > 0 ? nb->threads : 1) schedule(static)
  for (long ia = 0; ia < nn; ia++) {
    const size_t a = (size_t)ia, k0 = start[a], k1 = start[a + 1];
    uint32_t *b = list->b;
    for (size_t k = k0 + 1; k < k1; k++) { /* insertion sort of a's few b */
      const uint32_t v = b[k];
      size_t j = k;
      for (; j > k0 && b[j - 1] > v; j--) b[j] = b[j - 1];
      b[j] = v;
    }
    for (size_t k = k0; k < k1; k++) {
      list->a[k] = (uint32_t)a;
      size_t f = SIZE_MAX;
      for (size_t j = ostart[a]; j < ostart[a + 1]; j++)
        if (kc->b[j] == b[k]) {
          f = j;
          break;
        }
      if (f != SIZE_MAX) {
        list->h[k] = kc->h[f];
        list->touch[k] = 1;
        if (carry && list->vc0)
          memcpy(list->vc0 + 3 * k, kc->vc0 + 3 * f, 3 * sizeof(double));
        if (carry && list->wr0 && kc->wr0)
          memcpy(list->wr0 + 3 * k, kc->wr0 + 3 * f, 3 * sizeof(double));
        const esf_contact_bond *kb = esf_candidates_bond(kc, f);
        if (bonds) list->bond[k] = kb ? *kb : (esf_contact_bond){0};
        if (list->roll)
          list->roll[k] = kc->roll ? kc->roll[f] : (esf_contact_roll){{0, 0, 0}, 0};
      } else {
        if (memcmp(&list->h[k], &zero, sizeof zero)) /* only when not zero already: */
          list->h[k] = zero; /* a fresh list's pages stay untouched until its contacts */
        list->touch[k] = 0;
        if (list->vc0) memset(list->vc0 + 3 * k, 0, 3 * sizeof(double));
        if (list->wr0) memset(list->wr0 + 3 * k, 0, 3 * sizeof(double));
        if (bonds) list->bond[k] = (esf_contact_bond){0};
        if (list->roll) list->roll[k] = (esf_contact_roll){{0, 0, 0}, 0};
      }
    }
  }
  list->n = m;
  return ESF_OK;
}

/* Rebuilds *list from the keys in its own storage, the old touching contacts' history
 * carried over through nb->kept, which lives only for the build: kept between builds,
 * it stayed resident beside the next reorder's two copies of the particles and raised
 * the peak memory; faulting its pages in at each build costs no measurable time
 * (docs/performance.md#lists-and-rebuilds). */
static int rebuild_list(esf_neighbor *nb, esf_candidates *list, size_t n,
                        const uint32_t *ka, const uint32_t *kb, size_t m, int bonds,
                        esf_error *err) {
  int carry;
  int rc = keep_touching(nb, list, &nb->kept, n, &carry, err);
  if (!rc) rc = fill_list(nb, list, &nb->kept, n, ka, kb, m, carry, bonds, err);
  contacts_release(&nb->kept);
  return rc;
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

/* The wall candidates of particles [i0, i1) into b, in particle order; q: the wall
 * index queries' scratch. */
static int wall_candidates_range(const esf_neighbor *nb, const esf_particles *p,
                                 const esf_walls *w, size_t i0, size_t i1, uint32_t *q,
                                 esf_pairbuf *b) {
  for (size_t i = i0; i < i1; i++) {
    const uint32_t *cand = NULL;
    size_t ncand = 0;
    const double *x = p->x + 3 * i, reach = p->radius[i] + nb->skin;
    esf_wall_index_query(nb->widx, w, x, reach, q, &cand, &ncand);
    for (size_t c = 0; c < ncand; c++) {
      const size_t e = cand[c];
      const esf_wall_elem *el = &w->e[e];
      if (w->g[el->group].absent) continue; /* removed by an event (events.c) */
      if (el->kind == ESF_WALL_POLYGON) {   /* cheap rejects: bounding sphere, plane */
        double d[3];
        v3_sub(d, x, el->p);
        double lim = el->bound_r + reach;
        if (v3_norm2(d) > lim * lim) continue;
        if (esf_wall_out_of_reach(el, x, esf_wall_height(el, x), reach)) continue;
      }
      esf_wall_hit hit;
      esf_wall_nearest(el, x, &hit);
      if (hit.dist >= reach) continue;
      const int rc = esf_pairbuf_push(b, (uint32_t)i, (uint32_t)e, NULL);
      if (rc) return rc;
    }
  }
  return ESF_OK;
}

/* The particle-wall candidates into nb->buf, in particle order: each of nb->threads
 * threads takes one contiguous range of particles into its own buffer, with its own
 * query scratch, and the buffers are joined in range order, so the list is the serial
 * pass's whatever the thread count. */
static int wall_candidates(esf_neighbor *nb, const esf_particles *p, const esf_walls *w,
                           esf_error *err) {
  int rc = esf_wall_index_sync(&nb->widx, w, err);
  if (rc) return rc;
  /* below a thousand particles the pass is too short to share */
  size_t T = nb->threads > 1 && p->n >= 1024 ? (size_t)nb->threads : 1;
  if (T > ESF_CELLS_MAX_THREADS) T = ESF_CELLS_MAX_THREADS;
  const size_t ns = esf_wall_index_scratch(nb->widx);
  if (T > nb->nwbuf) {
    esf_pairbuf *b = realloc(nb->wbuf, T * sizeof *b);
    if (!b) return esf_fail(err, ESF_ENOMEM, "out of memory for wall candidates");
    memset(b + nb->nwbuf, 0, (T - nb->nwbuf) * sizeof *b);
    nb->wbuf = b;
    nb->nwbuf = T;
    nb->wscratch_n = 0; /* the scratch is per buffer */
  }
  if (ns > nb->wscratch_n) {
    uint32_t *q = realloc(nb->wscratch, nb->nwbuf * ns * sizeof *q);
    if (!q) return esf_fail(err, ESF_ENOMEM, "out of memory for wall candidates");
    nb->wscratch = q;
    nb->wscratch_n = ns;
  }
  int trc[ESF_CELLS_MAX_THREADS] = {0};
  const long n = (long)p->n, nt = (long)T;
#pragma omp parallel for num_threads((int)T) schedule(static, 1)
  for (long t = 0; t < nt; t++) {
    esf_pairbuf b = nb->wbuf[t]; /* a copy: the buffers share cache lines (cells.c) */
    b.n = 0;
    trc[t] =
        wall_candidates_range(nb, p, w, (size_t)(n * t / nt), (size_t)(n * (t + 1) / nt),
                              nb->wscratch + (size_t)t * nb->wscratch_n, &b);
    nb->wbuf[t] = b;
  }
  nb->buf.n = 0;
  for (size_t t = 0; t < T; t++) {
    rc = trc[t] ? esf_fail(err, trc[t], "out of memory for wall candidates")
                : esf_pairbuf_append(&nb->buf, &nb->wbuf[t], err);
    if (rc) return rc;
  }
  return ESF_OK;
}

/* The images of the pairs the periodic search found (nb->pimg, in the keys' order:
 * sorted by (a, b), the order fill_list keeps) into list. */
static int periodic_images(esf_neighbor *nb, esf_candidates *list, esf_error *err) {
  if (!list->img) {
    list->img = malloc((list->cap ? list->cap : 1) * 3 * sizeof *list->img);
    if (!list->img) return esf_fail(err, ESF_ENOMEM, "out of memory for pair images");
  }
  if (list->n) memcpy(list->img, nb->pimg, 3 * list->n * sizeof *list->img);
  for (int q = 0; q < 3; q++) list->plen[q] = nb->per->len[q];
  list->per = nb->per;
  return ESF_OK;
}

/* The build's scratch, not held between builds (about 100 bytes a particle: the cells,
 * the pair buffers, the history transfer's offsets; faulting its pages in again costs
 * a build well under 1%: docs/performance.md#memory). */
static void release_scratch(esf_neighbor *nb) {
  esf_pairbuf_release(&nb->buf);
  for (size_t t = 0; t < nb->nwbuf; t++) esf_pairbuf_release(&nb->wbuf[t]);
  free(nb->ws_start);
  free(nb->ws_ostart);
  free(nb->ws_ok);
  nb->ws_start = nb->ws_ostart = NULL;
  nb->ws_ok = NULL;
  nb->ws_n = nb->ws_m = 0;
}

int esf_neighbor_build(esf_neighbor *nb, const esf_particles *p, const esf_walls *w,
                       esf_error *err) {
  esf_cells_threads(nb->cells, nb->threads);
  free(nb->xref); /* written again at the end */
  nb->xref = NULL;
  nb->nref = 0;
  const int per = nb->per && nb->per->any;
  double le_ref = 0, off = 0;
  if (per && nb->per->le) off = esf_periodic_le_offset(nb->per, nb->le_t, &le_ref);
  int rc =
      per ? esf_periodic_pairs(nb->per, nb->cells, p->n, p->x, p->radius, nb->skin, off,
                               &nb->buf, &nb->pimg, &nb->pimg_cap, err)
          : esf_cells_pairs(nb->cells, p->n, p->x, p->radius, nb->skin, &nb->buf, err);
  esf_cells_trim(nb->cells); /* its pair buffers: not beside the lists' refill */
  if (rc) return rc;
  /* the search stores each pair as (min, max) */
  rc = rebuild_list(nb, &nb->pp, p->n, nb->buf.i, nb->buf.j, nb->buf.n, nb->bonds, err);
  if (!rc && per) rc = periodic_images(nb, &nb->pp, err);
  if (!rc && per) { /* Lees-Edwards: the offset's reference for this list */
    nb->pp.le_ref = le_ref;
    nb->pp.le_tb = nb->le_t;
    nb->pp.le_off = off;
  }
  if (rc) return rc;

  rc = wall_candidates(nb, p, w, err);
  if (rc) return rc;
  rc = rebuild_list(nb, &nb->pw, p->n, nb->buf.i, nb->buf.j, nb->buf.n, 0, err);
  if (rc) return rc;
  rc = wall_scratch_reserve(nb, err);
  if (rc) return rc;

  if (!nb->xref) {
    nb->xref = malloc((p->n ? p->n : 1) * 3 * sizeof(double));
    if (!nb->xref) return esf_fail(err, ESF_ENOMEM, "out of memory");
    nb->nref = p->n;
  }
  memcpy(nb->xref, p->x, p->n * 3 * sizeof(double));
  release_scratch(nb);
  nb->builds++;
  nb->disp_valid = 0;
  return ESF_OK;
}

/* Entry m of a particle list turned round (A and B swap): the history's tangential
 * displacement (force on A = kt xi), its normal (A to B) and the carried relative
 * velocity (B - A) change sign. */
static void turn(esf_candidates *c, size_t m) {

  const uint32_t t = c->a[m];
  c->a[m] = c->b[m];
  c->b[m] = t;
  esf_contact_hist *h = &c->h[m];
  for (int q = 0; q < 3; q++) {
    h->xi[q] = -h->xi[q];
    h->n[q] = -h->n[q];
    if (c->vc0) c->vc0[3 * m + q] = -c->vc0[3 * m + q];
    if (c->wr0) c->wr0[3 * m + q] = -c->wr0[3 * m + q];
    if (c->roll) c->roll[m].m[q] = -c->roll[m].m[q];            /* torque on the new A */
    if (c->img) c->img[3 * m + q] = (int8_t)-c->img[3 * m + q]; /* A's image of B */
  } /* the twisting torque t n keeps its sign: n turned round too */
}

/* Renumbers a list through remap (dropping removed particles). A particle pair whose
 * new numbers come in the other order is turned round to keep a < b: A and B swap,
 * so the history's tangential displacement (force on A = kt xi), its normal (A to B)
 * and the carried relative velocity (B - A) change sign. */
static void remap_list(esf_candidates *c, const size_t *remap, size_t n_old, int walls) {
  size_t m = 0;
  for (size_t k = 0; k < c->n; k++) {
    uint32_t a = c->a[k], b = c->b[k];
    if (a >= n_old || remap[a] == SIZE_MAX) continue;
    if (!walls && (b >= n_old || remap[b] == SIZE_MAX)) continue;
    c->a[m] = (uint32_t)remap[a];
    c->b[m] = walls ? b : (uint32_t)remap[b];
    if (m != k) { /* entries move only after a removed particle's (a reordering: never) */
      c->h[m] = c->h[k];
      c->touch[m] = c->touch[k];
      if (c->vc0) memcpy(c->vc0 + 3 * m, c->vc0 + 3 * k, 3 * sizeof(double));
      if (c->wr0) memcpy(c->wr0 + 3 * m, c->wr0 + 3 * k, 3 * sizeof(double));
      if (c->bond) c->bond[m] = c->bond[k]; /* its offset is the pair's: no sign */
      if (c->roll) c->roll[m] = c->roll[k];
      if (c->img) memcpy(c->img + 3 * m, c->img + 3 * k, 3);
    }
    if (!walls && c->a[m] > c->b[m]) turn(c, m);
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

int esf_neighbor_inject(esf_neighbor *nb, int walls, size_t m, const uint32_t *a,
                        const uint32_t *b, const esf_contact_hist *h,
                        const esf_contact_roll *roll, const esf_contact_bond *bond,
                        esf_error *err) {
  esf_candidates *c = walls ? &nb->pw : &nb->pp;
  const int img = !walls && nb->per && nb->per->any;
  int rc = contacts_reserve(c, c->n + m, nb->ledger, nb->carry, walls ? 0 : nb->bonds,
                            nb->rolling, img, err);
  if (rc) return rc;
  for (size_t j = 0; j < m; j++) {
    const size_t k = c->n++;
    c->a[k] = a[j];
    c->b[k] = b[j];
    c->h[k] = h[j];
    c->touch[k] = 1;
    if (c->vc0) memset(c->vc0 + 3 * k, 0, 3 * sizeof(double));
    if (c->wr0) memset(c->wr0 + 3 * k, 0, 3 * sizeof(double));
    if (c->bond) c->bond[k] = bond ? bond[j] : (esf_contact_bond){0};
    if (c->roll) c->roll[k] = roll ? roll[j] : (esf_contact_roll){{0, 0, 0}, 0};
    if (c->img) memset(c->img + 3 * k, 0, 3);
    if (!walls && c->a[k] > c->b[k]) turn(c, k);
  }
  return ESF_OK;
}

void esf_neighbor_skin_range(esf_neighbor *nb, double lo, double hi) {
  nb->skin_lo = lo;
  nb->skin_hi = hi;
}

void esf_neighbor_skin_tune(esf_neighbor *nb, size_t n, long step) {
  if (!(nb->skin_hi > 0) || !nb->xref || nb->nref != n || n == 0 || nb->builds == 0)
    return;
  esf_neighbor_skin_tune_with(nb, esf_neighbor_idle(nb, 0, n), n, step);
}

size_t esf_neighbor_idle(const esf_neighbor *nb, size_t lo, size_t hi) {
  size_t shell = 0; /* candidates not touching at the last evaluation */
  for (size_t k = 0; k < nb->pp.n; k++)
    shell += !nb->pp.touch[k] & (nb->pp.a[k] >= lo) & (nb->pp.a[k] < hi);
  return shell;
}

void esf_neighbor_skin_tune_with(esf_neighbor *nb, size_t shell, size_t n, long step) {
  const long I = step - nb->built_step > 1 ? step - nb->built_step : 1;
  const double ms = (double)shell / (double)n;
  double f = ms > 0 ? sqrt(ESF_SKIN_BUILD_COST / (ms * (double)I)) : 2.0;
  f = f < 0.5 ? 0.5 : f > 2.0 ? 2.0 : f;
  double s = nb->skin * f;
  s = s < nb->skin_lo ? nb->skin_lo : s > nb->skin_hi ? nb->skin_hi : s;
  nb->skin = s;
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
  const int img = nb->per && nb->per->any;
  int rc = contacts_reserve(&nb->pp, npp, nb->ledger, nb->carry, nb->bonds, nb->rolling,
                            img, err);
  if (!rc)
    rc = contacts_reserve(&nb->pw, npw, nb->ledger, nb->carry, 0, nb->rolling, 0, err);
  if (!rc && img) {
    for (int q = 0; q < 3; q++) nb->pp.plen[q] = nb->per->len[q];
    nb->pp.per = nb->per;
  }
  if (rc) return rc;
  return wall_scratch_reserve(nb, err);
}
