/* periodic.c — periodic boundaries: the wrap into the box and the candidate search
 * across its periodic faces (periodic.h; docs/physics.md#periodic-boundaries).
 *
 * Search by image copies: with reach s = 2 r_max + skin (the cell search's largest
 * cutoff) and every period L > 2 s, a particle within s of the lower face of periodic
 * axis k gets a copy shifted by +L_k, one within s of the upper face a copy shifted by
 * -L_k, and a particle near faces of several axes a copy for each combination (at
 * most 7). The linked cells (cells.c) search particles and copies together with the
 * unchanged criterion; a pair of two particles is kept with image 0, a particle-copy
 * pair (i, copy of j shifted by m L) becomes (i, j) with image m, turned to (min, max)
 * (the image negated when turned), and a copy-copy pair is dropped (it repeats one of
 * the others, shifted). A pair across a face is found from both sides: the sorted list
 * keeps it once. Lees-Edwards shear (#lees-edwards-shear): a copy across the gradient
 * faces is also shifted along the flow axis by the offset, and its flow copies follow
 * from there; the wrap moves flow coordinate and velocity. Cost: the search over n +
 * (copies) particles and a sort of the pairs, only in scenes with periodic axes.
 * Units: m. Entry: positions wrapped into the box (esf_periodic_wrap), finite. Exit:
 * out sorted by (a, b), a < b, each pair once, img 3 per pair. */
#include "search/periodic.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Wraps coordinate *xq into [lo, lo + L); returns the periods it moved by. */
static int32_t wrap_axis(double *xq, double lo, double L) {
  const double hi = lo + L;
  if (*xq >= lo && *xq < hi) return 0;
  const double f = floor((*xq - lo) / L);
  *xq -= f * L;
  int32_t m = (int32_t)f;
  if (*xq < lo) { /* rounding at the faces */
    *xq += L;
    m--;
  }
  if (*xq >= hi) {
    *xq -= L;
    m++;
  }
  return m;
}

double esf_periodic_le_offset(const esf_periodic *pb, double t, double *ref) {
  const double D = pb->rate * pb->len[pb->grad] * t, L = pb->len[pb->flow];
  const double r = L * floor(D / L);
  if (ref) *ref = r;
  return D - r;
}

size_t esf_periodic_wrap(const esf_periodic *pb, size_t n, double *x, double *v, double t,
                         int32_t *img) {
  size_t moved = 0;
  const double off = pb->le ? esf_periodic_le_offset(pb, t, NULL) : 0;
  const double u = pb->le ? pb->rate * pb->len[pb->grad] : 0;
  for (size_t i = 0; i < n; i++) {
    int hit = 0;
    if (pb->le) { /* the gradient axis first: it moves the flow coordinate */
      const int g = pb->grad, f = pb->flow;
      const int32_t m = wrap_axis(x + 3 * i + g, pb->lo[g], pb->len[g]);
      if (m) {
        x[3 * i + f] -= (double)m * off;
        v[3 * i + f] -= (double)m * u;
        img[3 * i + g] += m;
        hit = 1;
      }
    }
    for (int q = 0; q < 3; q++) {
      if (!pb->on[q] || (pb->le && q == pb->grad)) continue;
      const int32_t m = wrap_axis(x + 3 * i + q, pb->lo[q], pb->len[q]);
      img[3 * i + q] += m;
      hit |= m != 0;
    }
    moved += (size_t)hit;
  }
  return moved;
}

double esf_periodic_reach(const esf_periodic *pb) {
  double r = INFINITY;
  for (int q = 0; q < 3; q++)
    if (pb->on[q] && 0.5 * pb->len[q] < r) r = 0.5 * pb->len[q];
  return r;
}

typedef struct ppair {
  uint32_t a, b;
  int8_t m[3];
} ppair;

static int ppair_cmp(const void *u, const void *v) {
  const ppair *p = u, *q = v;
  if (p->a != q->a) return p->a < q->a ? -1 : 1;
  if (p->b != q->b) return p->b < q->b ? -1 : 1;
  return memcmp(p->m, q->m, 3);
}

/* The near-face option of coordinate v on axis q: +1 within s of the lower face (a
 * copy beyond the upper one), -1 within s of the upper face, else 0. */
static int8_t near_face(const esf_periodic *pb, int q, double v, double s) {
  if (v - pb->lo[q] < s) return 1;
  if (pb->lo[q] + pb->len[q] - v < s) return -1;
  return 0;
}

/* The image copies of the particle at xi: each combination of the faces it is within s
 * of, but none, into m (3 each); off: the Lees-Edwards offset. Returns the count. */
static size_t copies_of(const esf_periodic *pb, const double *xi, double s, double off,
                        int8_t *m) {
  int8_t opt[3] = {0, 0, 0};
  for (int q = 0; q < 3; q++)
    if (pb->on[q]) opt[q] = near_face(pb, q, xi[q], s);
  size_t k = 0;
  for (int c = 1 - (pb->le != 0); c < 8; c++) { /* bit q of c: shift along q */
    int8_t mm[3] = {0, 0, 0};
    int ok = 1;
    for (int q = 0; q < 3; q++) {
      if (pb->le && q == pb->flow) continue;
      if (c >> q & 1) {
        ok &= opt[q] != 0;
        mm[q] = opt[q];
      }
    }
    if (pb->le && ok) { /* the flow axis from the copy's shifted flow coordinate */
      const int f = pb->flow;
      const double uf = xi[f] + (double)mm[pb->grad] * off;
      const double kb = -floor((uf - pb->lo[f]) / pb->len[f]);
      const int8_t of = near_face(pb, f, uf + kb * pb->len[f], s);
      if ((c >> f & 1) && !of) ok = 0;
      mm[f] = (int8_t)(kb + ((c >> f & 1) ? of : 0));
    }
    if (!ok || (!mm[0] && !mm[1] && !mm[2])) continue;
    memcpy(m + 3 * k++, mm, 3);
  }
  return k;
}

typedef struct scratch {
  double *x, *r;
  uint32_t *src;
  int8_t *m;
  ppair *pp;
  esf_pairbuf buf;
} scratch;

static void scratch_free(scratch *w) {
  free(w->x);
  free(w->r);
  free(w->src);
  free(w->m);
  free(w->pp);
  esf_pairbuf_release(&w->buf);
}

/* Particles and their copies into w (x, r of n + *g; src, m of *g). */
static int with_copies(const esf_periodic *pb, size_t n, const double *x,
                       const double *radius, double s, double off, scratch *w, size_t *g,
                       esf_error *err) {
  size_t cap = n + n / 2 + 16, ng = 0;
  w->x = malloc(3 * cap * sizeof *w->x);
  w->r = malloc(cap * sizeof *w->r);
  w->src = malloc(cap * sizeof *w->src);
  w->m = malloc(3 * cap * sizeof *w->m);
  if (!w->x || !w->r || !w->src || !w->m) goto oom;
  memcpy(w->x, x, 3 * n * sizeof *x);
  memcpy(w->r, radius, n * sizeof *radius);
  for (size_t i = 0; i < n; i++) {
    int8_t m[24];
    const size_t k = copies_of(pb, x + 3 * i, s, off, m);
    if (n + ng + k > cap) {
      cap = 2 * (n + ng + k);
      double *nx = realloc(w->x, 3 * cap * sizeof *nx);
      if (nx) w->x = nx;
      double *nr = realloc(w->r, cap * sizeof *nr);
      if (nr) w->r = nr;
      uint32_t *ns = realloc(w->src, cap * sizeof *ns);
      if (ns) w->src = ns;
      int8_t *nm = realloc(w->m, 3 * cap * sizeof *nm);
      if (nm) w->m = nm;
      if (!nx || !nr || !ns || !nm) goto oom;
    }
    for (size_t j = 0; j < k; j++, ng++) {
      esf_periodic_image(x + 3 * i, m + 3 * j, pb->len, w->x + 3 * (n + ng));
      if (pb->le) esf_periodic_le_image(pb, m + 3 * j, off, w->x + 3 * (n + ng));
      w->r[n + ng] = radius[i];
      w->src[ng] = (uint32_t)i;
      memcpy(w->m + 3 * ng, m + 3 * j, 3);
    }
  }
  *g = ng;
  return ESF_OK;
oom:
  return esf_fail(err, ESF_ENOMEM,
                  "out of memory for the periodic images of %zu particles", n);
}

int esf_periodic_pairs(const esf_periodic *pb, esf_cells *c, size_t n, const double *x,
                       const double *radius, double skin, double off, esf_pairbuf *out,
                       int8_t **img, size_t *img_cap, esf_error *err) {
  out->n = 0;
  double rmax = 0;
  for (size_t i = 0; i < n; i++)
    if (radius[i] > rmax) rmax = radius[i];
  const double s = 2 * rmax + skin, half = esf_periodic_reach(pb);
  if (!(s < half))
    return esf_fail(err, ESF_EINPUT,
                    "the periodic box is too small: a period must exceed twice the "
                    "largest diameter plus the skin, 2 x %g m, but the shortest is %g m",
                    s, 2 * half);
  scratch w = {0};
  size_t g = 0;
  int rc = with_copies(pb, n, x, radius, s, off, &w, &g, err);
  if (!rc) rc = esf_cells_pairs(c, n + g, w.x, w.r, skin, &w.buf, err);
  if (!rc) {
    w.pp = malloc((w.buf.n ? w.buf.n : 1) * sizeof *w.pp);
    if (!w.pp) rc = esf_fail(err, ESF_ENOMEM, "out of memory for periodic pairs");
  }
  size_t np = 0;
  for (size_t k = 0; !rc && k < w.buf.n; k++) {
    const uint32_t i = w.buf.i[k], j = w.buf.j[k]; /* i < j */
    if (i >= n) continue;                          /* two copies */
    ppair *p = &w.pp[np++];
    if (j < n) {
      *p = (ppair){i, j, {0, 0, 0}};
      continue;
    }
    const uint32_t q = w.src[j - n];
    const int8_t *m = w.m + 3 * (size_t)(j - n);
    if (i < q)
      *p = (ppair){i, q, {m[0], m[1], m[2]}};
    else
      *p = (ppair){q, i, {(int8_t)-m[0], (int8_t)-m[1], (int8_t)-m[2]}};
  }
  if (!rc) qsort(w.pp, np, sizeof *w.pp, ppair_cmp);
  if (!rc && np > *img_cap) {
    int8_t *nm = realloc(*img, 3 * np * sizeof *nm);
    if (!nm)
      rc = esf_fail(err, ESF_ENOMEM, "out of memory for periodic pairs");
    else {
      *img = nm;
      *img_cap = np;
    }
  }
  for (size_t k = 0; !rc && k < np; k++) {
    const ppair *p = &w.pp[k];
    if (out->n && out->i[out->n - 1] == p->a && out->j[out->n - 1] == p->b) {
      if (memcmp(*img + 3 * (out->n - 1), p->m, 3))
        rc = esf_fail(err, ESF_EINTERNAL, "periodic pair (%u, %u) found at two images",
                      p->a, p->b);
      continue; /* found from both sides */
    }
    rc = esf_pairbuf_push(out, p->a, p->b, err);
    if (!rc) memcpy(*img + 3 * (out->n - 1), p->m, 3);
  }
  scratch_free(&w);
  if (rc) out->n = 0;
  return rc;
}
