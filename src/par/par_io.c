/* par_io.c — an MPI run's particles gathered on rank 0 for its frames (par.h).
 *
 * Rank 0 writes frames.h5 alone, through the same writer as one process
 * (output/frames.c, which orders particles by id): every process sends its owned
 * particles (esf_par_rec and F: 184 bytes each) and rank 0 receives them
 * rank after rank, the global order. Parallel HDF5 would spare rank 0 the memory of
 * one frame's particles; docs/mpi.md gives the measured cost of the gather.
 * esf_par_view gathers the same way, with the candidate lists' entries of each
 * process's own particles (their A), for the checkpoint writer (ckpt/checkpoint.c).
 * Entry: p.f current (esf_sim_forces_sync). */
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "core/bonds.h"
#include "par/par.h"

#ifdef ESF_MPI
#include "par/par_impl.h"

typedef struct out_rec { /* a particle of a frame: the record and its force */
  esf_par_rec p;
  double f[3];
} out_rec;

/* Gathers n records of `size` bytes from every process on rank 0, rank after rank:
 * *all (malloc'd on rank 0, NULL elsewhere) and their count *total. A process that
 * failed before (rc) takes part with none; rank 0's failure to allocate is returned
 * there. */
static int gather_recs(esf_par *P, const void *mine, size_t n, size_t size, int rc,
                       void **all, size_t *total, esf_error *err) {
  *all = NULL;
  *total = 0;
  int mn = rc || n > INT_MAX ? 0 : (int)n, *cnt = NULL, *dsp = NULL;
  if (P->rank == 0) {
    cnt = malloc(2 * (size_t)P->size * sizeof *cnt);
    if (!cnt) return esf_fail(err, ESF_ENOMEM, "out of memory");
    dsp = cnt + P->size;
  }
  MPI_Gather(&mn, 1, MPI_INT, cnt, 1, MPI_INT, 0, P->comm);
  if (P->rank == 0) {
    for (int q = 0; q < P->size; q++) {
      dsp[q] = (int)*total;
      *total += (size_t)cnt[q];
    }
    *all = malloc(*total ? *total * size : 1);
  }
  MPI_Datatype rec;
  MPI_Type_contiguous((int)size, MPI_BYTE, &rec);
  MPI_Type_commit(&rec);
  MPI_Gatherv(mine, mn, rec, *all, cnt, dsp, rec, 0, P->comm);
  MPI_Type_free(&rec);
  free(cnt);
  P->bytes += (double)(n * size);
  if (P->rank == 0 && !*all && !rc)
    rc = esf_fail(err, ESF_ENOMEM, "out of memory gathering %zu records", *total);
  return rc;
}

int esf_par_gather(esf_sim *s, esf_particles *all, esf_error *err) {
  memset(all, 0, sizeof *all);
  esf_par *P = s->par;
  if (!P) return esf_fail(err, ESF_EINTERNAL, "esf_par_gather without MPI");
  const double t0 = esf_par_now();
  const esf_particles *p = &s->p;
  const size_t lo = s->own_lo, n = s->own_hi - s->own_lo;
  out_rec *mine = malloc((n ? n : 1) * sizeof *mine);
  int rc = mine ? ESF_OK : esf_fail(err, ESF_ENOMEM, "out of memory");
  for (size_t j = 0; !rc && j < n; j++) {
    const size_t i = lo + j;
    out_rec *r = &mine[j];
    esf_par_rec_of(p, i, 0, 0, &r->p);
    if (p->f)
      memcpy(r->f, p->f + 3 * i, sizeof r->f);
    else
      memset(r->f, 0, sizeof r->f);
  }
  out_rec *got = NULL;
  size_t m = 0;
  rc = gather_recs(P, mine, n, sizeof *mine, rc, (void **)&got, &m, err);
  if (!rc && P->rank == 0) rc = esf_particles_alloc(all, m, err);
  if (!rc && P->rank == 0 && p->img) rc = esf_particles_images(all, err);
  for (size_t k = 0; !rc && P->rank == 0 && k < m; k++) {
    esf_par_rec_to(all, k, &got[k].p);
    memcpy(all->f + 3 * k, got[k].f, sizeof got[k].f);
  }
  free(mine);
  free(got);
  P->seconds += esf_par_now() - t0;
  return rc;
}

typedef struct ck_rec { /* a particle of a checkpoint: the record, F_n, M_n, xref */
  esf_par_rec p;
  double f[3], t[3], xref[3];
} ck_rec;

typedef struct pair_rec {
  int64_t a, b;
  esf_contact_hist h;
  esf_contact_bond bond;
  esf_contact_roll roll;
  uint8_t touch;
  int8_t img[3], spare[4]; /* B's periodic image */
} pair_rec;

/* The entries of list c whose A this process owns, A and B numbered globally (B a wall
 * element for wall lists). */
static pair_rec *own_entries(const esf_sim *s, const esf_candidates *c, int walls,
                             size_t *n) {
  const int64_t *gid = s->par->gid;
  size_t m = 0;
  for (size_t k = 0; k < c->n; k++) m += c->a[k] >= s->own_lo && c->a[k] < s->own_hi;
  pair_rec *r = calloc(m ? m : 1, sizeof *r);
  if (!r) return NULL;
  m = 0;
  for (size_t k = 0; k < c->n; k++) {
    if (!(c->a[k] >= s->own_lo && c->a[k] < s->own_hi)) continue;
    pair_rec *e = &r[m++];
    e->a = gid[c->a[k]];
    e->b = walls ? (int64_t)c->b[k] : gid[c->b[k]];
    e->h = c->h[k];
    if (c->bond) e->bond = c->bond[k];
    if (c->roll) e->roll = c->roll[k];
    if (c->img) memcpy(e->img, c->img + 3 * k, 3);
    e->touch = c->touch[k];
  }
  *n = m;
  return r;
}

/* A gathered list into view's candidates (allocated here, released by
 * esf_par_view_release). */
static int view_list(esf_candidates *dst, const esf_candidates *like, const pair_rec *r,
                     size_t m) {
  memset(dst, 0, sizeof *dst);
  const size_t c = m ? m : 1;
  dst->a = malloc(c * sizeof *dst->a);
  dst->b = malloc(c * sizeof *dst->b);
  dst->h = malloc(c * sizeof *dst->h);
  dst->touch = malloc(c);
  dst->bond = like->bond ? malloc(c * sizeof *dst->bond) : NULL;
  dst->roll = like->roll ? malloc(c * sizeof *dst->roll) : NULL;
  dst->img = like->img ? malloc(3 * c) : NULL;
  if (!dst->a || !dst->b || !dst->h || !dst->touch || (like->bond && !dst->bond) ||
      (like->roll && !dst->roll) || (like->img && !dst->img))
    return 0;
  if (like->img) { /* the periods and Lees-Edwards references: every process's */
    memcpy(dst->plen, like->plen, sizeof dst->plen);
    dst->per = like->per;
    dst->le_off = like->le_off;
    dst->le_ref = like->le_ref;
    dst->le_tb = like->le_tb;
  }
  for (size_t k = 0; k < m; k++) {
    dst->a[k] = (uint32_t)r[k].a;
    dst->b[k] = (uint32_t)r[k].b;
    dst->h[k] = r[k].h;
    dst->touch[k] = r[k].touch;
    if (dst->bond) dst->bond[k] = r[k].bond;
    if (dst->roll) dst->roll[k] = r[k].roll;
    if (dst->img) memcpy(dst->img + 3 * k, r[k].img, 3);
  }
  dst->n = dst->cap = m;
  return 1;
}

static void view_list_free(esf_candidates *c) {
  free(c->a);
  free(c->b);
  free(c->h);
  free(c->touch);
  free(c->bond);
  free(c->roll);
  free(c->img);
  memset(c, 0, sizeof *c);
}

void esf_par_view_release(esf_sim *view) {
  if (!view->p.y && !view->nb.pp.a) return;
  esf_particles_release(&view->p);
  view_list_free(&view->nb.pp);
  view_list_free(&view->nb.pw);
  free(view->nb.xref);
  memset(view, 0, sizeof *view);
}

int esf_par_view(esf_sim *s, esf_sim *view, esf_error *err) {
  memset(view, 0, sizeof *view);
  esf_par *P = s->par;
  if (!P) return esf_fail(err, ESF_EINTERNAL, "esf_par_view without MPI");
  const double t0 = esf_par_now();
  int rc = esf_par_agree(s, esf_sim_forces_sync(s, err), err);
  if (rc) return rc;
  const esf_particles *p = &s->p;
  const size_t lo = s->own_lo, n = s->own_hi - s->own_lo;
  const int ref = s->nb.xref && s->nb.nref == p->n;
  ck_rec *mine = calloc(n ? n : 1, sizeof *mine);
  size_t npp = 0, npw = 0;
  pair_rec *pp = own_entries(s, &s->nb.pp, 0, &npp);
  pair_rec *pw = own_entries(s, &s->nb.pw, 1, &npw);
  rc = mine && pp && pw ? ESF_OK : esf_fail(err, ESF_ENOMEM, "out of memory");
  for (size_t j = 0; !rc && j < n; j++) {
    const size_t i = lo + j;
    ck_rec *r = &mine[j];
    esf_par_rec_of(p, i, 0, 0, &r->p);
    memcpy(r->f, p->f + 3 * i, sizeof r->f);
    memcpy(r->t, p->t + 3 * i, sizeof r->t);
    if (ref) memcpy(r->xref, s->nb.xref + 3 * i, sizeof r->xref);
  }
  rc = esf_par_agree(s, rc, err);
  void *ap = NULL, *app = NULL, *apw = NULL;
  size_t tp = 0, tpp = 0, tpw = 0;
  rc = gather_recs(P, mine, n, sizeof *mine, rc, &ap, &tp, err); /* (collective: */
  rc = gather_recs(P, pp, npp, sizeof *pp, rc, &app, &tpp, err); /*  each one is */
  rc = gather_recs(P, pw, npw, sizeof *pw, rc, &apw, &tpw, err); /*  always made) */
  const long long csum = esf_par_sum(s, (long long)s->contacts_sum);
  const long broken = esf_bonds_broken(s);
  const int allref = esf_par_any(s, !ref) == 0;
  free(mine);
  free(pp);
  free(pw);
  if (!rc && P->rank == 0) {
    *view = *s;
    view->par = NULL;
    view->ft_lazy = NULL;
    view->contacts_sum = (double)csum;
    view->bonds.broken = broken;
    memset(&view->p, 0, sizeof view->p);
    const size_t m = tp;
    rc = esf_particles_alloc(&view->p, m, err);
    if (!rc && p->img) rc = esf_particles_images(&view->p, err);
    const ck_rec *r = ap;
    for (size_t k = 0; !rc && k < m; k++) {
      esf_particles *q = &view->p;
      esf_par_rec_to(q, k, &r[k].p);
      memcpy(q->f + 3 * k, r[k].f, sizeof r[k].f);
      memcpy(q->t + 3 * k, r[k].t, sizeof r[k].t);
    }
    view->nb.xref = NULL;
    view->nb.nref = 0;
    if (!rc && allref) {
      view->nb.xref = malloc((m ? m : 1) * 3 * sizeof(double));
      if (!view->nb.xref) rc = esf_fail(err, ESF_ENOMEM, "out of memory");
      for (size_t k = 0; !rc && k < m; k++)
        memcpy(view->nb.xref + 3 * k, r[k].xref, 3 * sizeof(double));
      view->nb.nref = m;
    }
    if (!rc && (!view_list(&view->nb.pp, &s->nb.pp, app, tpp) ||
                !view_list(&view->nb.pw, &s->nb.pw, apw, tpw)))
      rc = esf_fail(err, ESF_ENOMEM, "out of memory for the checkpoint's lists");
    if (rc) esf_par_view_release(view);
  }
  free(ap);
  free(app);
  free(apw);
  P->seconds += esf_par_now() - t0;
  return esf_par_bcast_status(s, rc, err);
}

#else

int esf_par_view(esf_sim *s, esf_sim *view, esf_error *err) {
  (void)s;
  memset(view, 0, sizeof *view);
  return esf_fail(err, ESF_EINTERNAL, "esf_par_view without MPI");
}
void esf_par_view_release(esf_sim *view) { (void)view; }

int esf_par_gather(esf_sim *s, esf_particles *all, esf_error *err) {
  (void)s;
  memset(all, 0, sizeof *all);
  return esf_fail(err, ESF_EINTERNAL, "esf_par_gather without MPI");
}

#endif
