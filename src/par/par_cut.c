/* par_cut.c — an MPI run's rebuild (par.h: esf_par_rebuild): what one process does at
 * a list rebuild (esf_sim_remove_escaped, then esf_reorder_particles), done across
 * the processes with the same result.
 *
 * 1. Owned particles outside the domain are removed; their energies are booked in
 *    the global order (gathered, sorted by global index), as one process books them.
 * 2. The renumbering's grid from the global box, count and exact sum of radii.
 * 3. The cut: work per plane of cells (the slowest axis; a particle's work is its
 *    process's measured time per particle), then per cell in the plane where each
 *    cut's target falls; each cut is a key boundary whose count before it is a
 *    multiple of ESF_LEDGER_BLOCK, nearest its share of the work.
 * 4. Owned particles whose cell lies in another process's keys migrate there with
 *    their touching contacts (histories and rolling states, keyed by particle ids).
 * 5. The owned particles are ordered by (key, previous global index) — one process's
 *    stable counting sort — and numbered from the count on lower ranks.
 * 6. Ghosts: each process's owned particles within m planes of another's keys, m
 *    planes covering 2 r_max + skin (the farthest a candidate pair reaches).
 * 7. The local arrays: ghosts before the owned ones in the global order, the owned,
 *    ghosts after; the old lists renumbered by id (a contact's history is kept only
 *    where its process owned one of its particles: ghosts' own contacts are not
 *    computed in full), the migrants' contacts added; a build follows. */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "par/par.h"

#ifdef ESF_MPI
#include "core/ledger.h"
#include "core/reorder.h"
#include "par/par_impl.h"
#include "util/vec3.h"
#include "util/xsum.h"

typedef struct idx_pair {
  int64_t id;
  size_t i;
} idx_pair;

static int by_id(const void *x, const void *y) {
  const int64_t a = ((const idx_pair *)x)->id, b = ((const idx_pair *)y)->id;
  return (a > b) - (a < b);
}

static int rec_by_gid(const void *x, const void *y) {
  const int64_t a = ((const esf_par_rec *)x)->gid, b = ((const esf_par_rec *)y)->gid;
  return (a > b) - (a < b);
}

static size_t find_id(const idx_pair *t, size_t n, int64_t id) {
  size_t lo = 0, hi = n;
  while (lo < hi) {
    const size_t m = lo + (hi - lo) / 2;
    if (t[m].id < id)
      lo = m + 1;
    else
      hi = m;
  }
  return lo < n && t[lo].id == id ? t[lo].i : SIZE_MAX;
}

/* Counts in, displacements out, in bytes of `size` each; the total. */
static size_t displs(const int *cnt, int *dsp, int K) {
  size_t t = 0;
  for (int q = 0; q < K; q++) {
    dsp[q] = (int)t;
    t += (size_t)cnt[q];
  }
  return t;
}

/* All-to-all of records of `size` bytes: out[cnt_out[q]] to q; *in (malloc'd) gets
 * *nin records, rank by rank. */
static int exchange(esf_par *P, const void *out, const int *cnt_out, size_t size,
                    void **in, size_t *nin, esf_error *err) {
  const int K = P->size;
  int *co = malloc(4 * (size_t)K * sizeof *co);
  if (!co) return esf_fail(err, ESF_ENOMEM, "out of memory");
  int *ci = co + K, *dout = co + 2 * K, *din = co + 3 * K;
  MPI_Alltoall(cnt_out, 1, MPI_INT, ci, 1, MPI_INT, P->comm);
  size_t no = 0, ni = 0;
  for (int q = 0; q < K; q++) { /* counts and offsets in records (a record type) */
    dout[q] = (int)no;
    no += (size_t)cnt_out[q];
    din[q] = (int)ni;
    ni += (size_t)ci[q];
  }
  *in = malloc(ni ? ni * size : 1);
  if (!*in || no > INT_MAX || ni > INT_MAX) {
    free(co);
    return esf_fail(err, ESF_ENOMEM, "out of memory for %zu migrating records", ni);
  }
  MPI_Datatype rec;
  MPI_Type_contiguous((int)size, MPI_BYTE, &rec);
  MPI_Type_commit(&rec);
  MPI_Alltoallv(out, cnt_out, dout, rec, *in, ci, din, rec, P->comm);
  MPI_Type_free(&rec);
  P->bytes += (double)(no * size);
  *nin = ni;
  free(co);
  return ESF_OK;
}

typedef struct removed_rec {
  int64_t gid, id;
  double e, x[3];
} removed_rec;

static int rem_by_gid(const void *x, const void *y) {
  const int64_t a = ((const removed_rec *)x)->gid, b = ((const removed_rec *)y)->gid;
  return (a > b) - (a < b);
}

/* Step 1: keep[i] for the owned particles; the removed ones booked and logged. */
static int remove_escaped(esf_sim *s, const int64_t *gid, unsigned char *keep,
                          esf_error *err) {
  esf_par *P = s->par;
  const esf_particles *p = &s->p;
  const size_t lo = s->own_lo, hi = s->own_hi;
  size_t out = 0;
  for (size_t i = lo; i < hi; i++) {
    keep[i - lo] =
        !s->cfg.has_domain || !v3_outside(p->x + 3 * i, s->cfg.keep_lo, s->cfg.keep_hi);
    out += !keep[i - lo];
  }
  if (!s->cfg.has_domain || !esf_par_any(s, out > 0)) return ESF_OK;
  removed_rec *mine = malloc((out ? out : 1) * sizeof *mine);
  int *cnt = malloc(2 * (size_t)P->size * sizeof *cnt);
  if (!mine || !cnt) {
    free(mine);
    free(cnt);
    return esf_fail(err, ESF_ENOMEM, "out of memory");
  }
  size_t m = 0;
  for (size_t i = lo; i < hi; i++) {
    if (keep[i - lo]) continue;
    const double *x = p->x + 3 * i, *v = p->v + 3 * i, *w = p->w + 3 * i;
    removed_rec *r = &mine[m++];
    r->gid = gid[i];
    r->id = p->id[i];
    const double ek = 0.5 * p->mass[i] * v3_norm2(v) + 0.5 * p->inertia[i] * v3_norm2(w);
    const double ep = -p->mass[i] * v3_dot(s->cfg.gravity, x);
    r->e = ek + ep; /* as sim.c books it */
    memcpy(r->x, x, sizeof r->x);
  }
  int mb = (int)(out * sizeof *mine), *dsp = cnt + P->size;
  MPI_Allgather(&mb, 1, MPI_INT, cnt, 1, MPI_INT, P->comm);
  const size_t tot = displs(cnt, dsp, P->size);
  removed_rec *all = malloc(tot ? tot : 1);
  if (!all) {
    free(mine);
    free(cnt);
    return esf_fail(err, ESF_ENOMEM, "out of memory");
  }
  MPI_Allgatherv(mine, mb, MPI_BYTE, all, cnt, dsp, MPI_BYTE, P->comm);
  const size_t nall = tot / sizeof *all;
  qsort(all, nall, sizeof *all, rem_by_gid);
  for (size_t k = 0; k < nall; k++) {
    const removed_rec *r = &all[k];
    if (s->led.started) s->led.e_removed += r->e;
    esf_sim_log(s,
                "t = %.6g s: particle id %lld left the domain at (%g, %g, %g); removed",
                s->t, (long long)r->id, r->x[0], r->x[1], r->x[2]);
  }
  s->removed += (long)nall;
  free(all);
  free(mine);
  free(cnt);
  return ESF_OK;
}

/* Step 2: the global box, count, largest radius and sum of radii of the kept owned
 * particles; the grid. Returns the run's count. */
static size_t global_grid(esf_sim *s, const unsigned char *keep, esf_reorder_grid *g,
                          double *rmax_out) {
  esf_par *P = s->par;
  const esf_particles *p = &s->p;
  double lo[3] = {INFINITY, INFINITY, INFINITY},
         hi[3] = {-INFINITY, -INFINITY, -INFINITY};
  double rmax = 0.0;
  unsigned long long nk = 0, ntot = 0;
  for (size_t i = s->own_lo; i < s->own_hi; i++) {
    if (!keep[i - s->own_lo]) continue;
    for (int q = 0; q < 3; q++) {
      const double v = p->x[3 * i + q];
      lo[q] = v < lo[q] ? v : lo[q];
      hi[q] = v > hi[q] ? v : hi[q];
    }
    rmax = p->radius[i] > rmax ? p->radius[i] : rmax;
    nk++;
  }
  double lh[7] = {lo[0], lo[1], lo[2], -hi[0], -hi[1], -hi[2], -rmax}, gl[7];
  MPI_Allreduce(lh, gl, 7, MPI_DOUBLE, MPI_MIN, P->comm);
  MPI_Allreduce(&nk, &ntot, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, P->comm);
  /* the sum of radii, exact (as esf_reorder_particles takes it) */
  esf_xsum rs;
  esf_xsum_zero(&rs);
  for (size_t i = s->own_lo; i < s->own_hi; i++)
    if (keep[i - s->own_lo]) esf_xsum_add(&rs, p->radius[i]);
  esf_xsum_normalize(&rs);
  MPI_Allreduce(MPI_IN_PLACE, &rs, ESF_XSUM_WORDS, MPI_INT64_T, MPI_SUM, P->comm);
  const double rsum = esf_xsum_value(&rs);
  *rmax_out = -gl[6];
  if (ntot < 3) { /* one process does not renumber so few: one cell, the order kept */
    memset(g, 0, sizeof *g);
    g->h = INFINITY;
    g->dims[0] = g->dims[1] = g->dims[2] = 1.0;
    g->ax[0] = 0;
    g->ax[1] = 1;
    g->ax[2] = 2;
    g->d1 = g->d2 = g->ncell = 1;
    return (size_t)ntot;
  }
  const double glo[3] = {gl[0], gl[1], gl[2]}, ghi[3] = {-gl[3], -gl[4], -gl[5]};
  esf_reorder_grid_make(g, glo, ghi, 2.0 * rsum / (double)ntot + s->nb.skin,
                        (size_t)ntot);
  return (size_t)ntot;
}

/* Step 3: kcut[0 .. K], each process's keys [kcut[r], kcut[r + 1]). The work a
 * particle costs is its process's measured seconds per particle since the last cut
 * (relative to the mean, within [1/2, 2]; 1 before any measurement); each cut is
 * the key boundary, with a count before it that is a multiple of ESF_LEDGER_BLOCK,
 * whose work before it is nearest r / K of the total (the plane it falls in and its
 * neighbours, more of them until one is found, are searched cell by cell, the other
 * planes at their starts). Any cut gives
 * the same results; only the time depends on it. */
static int make_cut(esf_sim *s, const esf_reorder_grid *g, const uint32_t *key,
                    const unsigned char *keep, size_t *kcut, esf_error *err) {
  esf_par *P = s->par;
  const int K = P->size;
  const size_t nown = s->own_hi - s->own_lo, d12 = g->d1 * g->d2, np = g->ncell / d12;
  { /* this process's cost per particle relative to the mean, smoothed over cuts */
    double in[2] = {P->busy > 0 && nown > 0 ? P->busy / (double)nown : 0.0, 0.0}, sum[2];
    in[1] = in[0] > 0;
    MPI_Allreduce(in, sum, 2, MPI_DOUBLE, MPI_SUM, P->comm);
    if (in[0] > 0 && sum[1] == K && sum[0] > 0) {
      double r = in[0] / (sum[0] / K);
      r = r < 0.5 ? 0.5 : r > 2.0 ? 2.0 : r;
      P->rate = 0.5 * P->rate + 0.5 * r;
    }
    P->busy = 0.0;
  }
  const double rate = P->rate;
  double *pw = calloc(2 * (np + 1), sizeof *pw), *cwb = NULL;
  if (!pw) return esf_fail(err, ESF_ENOMEM, "out of memory for the cut");
  double *pc = pw + np; /* work and counts per plane */
  for (size_t j = 0; j < nown; j++)
    if (keep[j]) {
      pw[key[j] / d12] += rate;
      pc[key[j] / d12] += 1.0;
    }
  MPI_Allreduce(MPI_IN_PLACE, pw, 2 * (int)np, MPI_DOUBLE, MPI_SUM, P->comm);
  double wtot = 0.0;
  for (size_t q = 0; q < np; q++) wtot += pw[q];
  kcut[0] = 0;
  kcut[K] = g->ncell;
  const size_t B = ESF_LEDGER_BLOCK;
  for (int r = 1; r < K; r++) {
    const double target = wtot * r / K;
    size_t pl = 0; /* the plane the target falls in; its work and count before it */
    double w0 = 0.0, c0 = 0.0;
    while (pl + 1 < np && w0 + pw[pl] <= target) {
      w0 += pw[pl];
      c0 += pc[pl];
      pl++;
    }
    /* the cells of that plane and its neighbours, W planes either side (a plane of
       few, crowded cells may hold no boundary at a multiple of the block): W doubles
       until one is found or every plane was searched */
    size_t best = 0;
    double bd = target; /* key 0: no work before it */
    for (size_t W = 1;; W *= 2) {
      const size_t p0 = pl > W ? pl - W : 0, p1 = pl + W + 1 < np ? pl + W + 1 : np;
      const size_t nc = (p1 - p0) * d12;
      double *cw = realloc(cwb, 2 * (nc ? nc : 1) * sizeof *cw);
      if (!cw) {
        free(pw);
        free(cwb);
        return esf_fail(err, ESF_ENOMEM, "out of memory for the cut");
      }
      cwb = cw;
      double *cc = cw + nc; /* the cells' counts */
      memset(cw, 0, 2 * nc * sizeof *cw);
      for (size_t j = 0; j < nown; j++)
        if (keep[j] && key[j] / d12 >= p0 && key[j] / d12 < p1) {
          cw[key[j] - p0 * d12] += rate;
          cc[key[j] - p0 * d12] += 1.0;
        }
      MPI_Allreduce(MPI_IN_PLACE, cw, 2 * (int)nc, MPI_DOUBLE, MPI_SUM, P->comm);
      double w = w0, c = c0;
      for (size_t q = pl; q > p0; q--) { /* the start of the first plane searched */
        w -= pw[q - 1];
        c -= pc[q - 1];
      }
      for (size_t j = 0; j <= nc; j++) { /* boundaries inside the planes */
        if (fmod(c, (double)B) == 0.0 && fabs(w - target) < bd) {
          bd = fabs(w - target);
          best = p0 * d12 + j;
        }
        if (j < nc) {
          w += cw[j];
          c += cc[j];
        }
      }
      if (best > 0 || (p0 == 0 && p1 == np)) break;
    }
    double w = 0.0, c = 0.0;
    for (size_t q = 0; q <= np; q++) { /* or a plane's start */
      if (fmod(c, (double)B) == 0.0 && fabs(w - target) < bd) {
        bd = fabs(w - target);
        best = q * d12;
      }
      if (q < np) {
        w += pw[q];
        c += pc[q];
      }
    }
    kcut[r] = best > kcut[r - 1] ? best : kcut[r - 1];
  }
  free(pw);
  free(cwb);
  return ESF_OK;
}

/* The process whose keys hold key. */
static int owner_of(const size_t *kcut, int K, uint32_t key) {
  int lo = 0, hi = K; /* the last r with kcut[r] <= key */
  while (hi - lo > 1) {
    const int m = (lo + hi) / 2;
    if (kcut[m] <= key)
      lo = m;
    else
      hi = m;
  }
  return lo;
}

/* Step 5: the owned records ordered by (key, previous global index): sorted by the
 * index, then a stable counting sort on the key (keys in [k0, k1)). */
static int order_owned(esf_par_rec *r, size_t n, size_t nstay, size_t k0, size_t k1,
                       esf_error *err) {
  /* r[0 .. nstay) stayed, in the previous global order already; the arrivals are
     sorted, then both runs merged: no sort of the whole */
  qsort(r + nstay, n - nstay, sizeof *r, rec_by_gid);
  const size_t R = k1 - k0;
  size_t *start = calloc(R + 1, sizeof *start);
  esf_par_rec *t = malloc((n ? n : 1) * sizeof *t);
  size_t *src = malloc((n ? n : 1) * sizeof *src);
  if (!start || !t || !src) {
    free(start);
    free(t);
    free(src);
    return esf_fail(err, ESF_ENOMEM, "out of memory for ordering %zu particles", n);
  }
  for (size_t i = 0, j = nstay, m = 0; m < n; m++) /* the merge, as indices */
    src[m] = j >= n || (i < nstay && r[i].gid < r[j].gid) ? i++ : j++;
  for (size_t j = 0; j < n; j++) start[r[j].key - k0 + 1]++;
  for (size_t c = 0; c < R; c++) start[c + 1] += start[c];
  for (size_t m = 0; m < n; m++) t[start[r[src[m]].key - k0]++] = r[src[m]];
  memcpy(r, t, n * sizeof *r);
  free(t);
  free(start);
  free(src);
  return ESF_OK;
}

/* The first of the n records (sorted by key) whose plane is at least pl. */
static size_t first_plane(const esf_par_rec *r, size_t n, size_t d12, size_t pl) {
  size_t lo = 0, hi = n;
  while (lo < hi) {
    const size_t m = lo + (hi - lo) / 2;
    if (r[m].key / d12 < pl)
      lo = m + 1;
    else
      hi = m;
  }
  return lo;
}

/* Step 4's contacts: the touching contacts of the kept owned particles that migrate,
 * for their new process (dest[i - own_lo], -1 for removed); *out (malloc'd) by
 * process, cnt[q] of them for q. */
static int pack_contacts(esf_sim *s, const int *dest, int me, int K, int *cnt,
                         esf_par_contact **out, esf_error *err) {
  const esf_particles *p = &s->p;
  const size_t lo = s->own_lo, hi = s->own_hi;
  memset(cnt, 0, (size_t)K * sizeof *cnt);
  esf_par_contact *c = NULL;
  size_t *at = NULL;
  for (int pass = 0; pass < 2; pass++) {
    for (int l = 0; l < 2; l++) {
      const esf_candidates *L = l ? &s->nb.pw : &s->nb.pp;
      for (size_t k = 0; k < L->n; k++) {
        if (!L->touch[k]) continue;
        const size_t a = L->a[k], b = L->b[k];
        const int da = a >= lo && a < hi ? dest[a - lo] : -1;
        const int db = !l && b >= lo && b < hi ? dest[b - lo] : -1;
        int to[2] = {da >= 0 && da != me ? da : -1,
                     db >= 0 && db != me && db != da ? db : -1};
        for (int e = 0; e < 2; e++) {
          if (to[e] < 0) continue;
          if (!pass) {
            cnt[to[e]]++;
            continue;
          }
          esf_par_contact *x = &c[at[to[e]]++];
          memset(x, 0, sizeof *x);
          x->id_a = p->id[a];
          x->id_b = l ? (int64_t)b : p->id[b];
          x->wall = l;
          x->h = L->h[k];
          x->has_roll = L->roll != NULL;
          if (L->roll) x->roll = L->roll[k];
          if (!l && L->bond) x->bond = L->bond[k];
        }
      }
    }
    if (pass) break;
    size_t tot = 0;
    at = malloc((size_t)K * sizeof *at);
    for (int q = 0; at && q < K; q++) {
      at[q] = tot;
      tot += (size_t)cnt[q];
    }
    c = malloc((tot ? tot : 1) * sizeof *c);
    if (!c || !at) {
      free(c);
      free(at);
      return esf_fail(err, ESF_ENOMEM, "out of memory for migrating contacts");
    }
  }
  free(at);
  *out = c;
  return ESF_OK;
}

/* Step 7's contacts: the received ones added to the lists (ids through t). */
static int inject(esf_sim *s, const esf_par_contact *c, size_t n, const idx_pair *t,
                  size_t nt, esf_error *err) {
  uint32_t *a = malloc((n ? n : 1) * 2 * sizeof *a);
  esf_contact_hist *h = malloc((n ? n : 1) * sizeof *h);
  esf_contact_roll *r = malloc((n ? n : 1) * sizeof *r);
  esf_contact_bond *bd = malloc((n ? n : 1) * sizeof *bd);
  int rc = a && h && r && bd ? ESF_OK : esf_fail(err, ESF_ENOMEM, "out of memory");
  for (int wall = 0; !rc && wall < 2; wall++) {
    size_t m = 0;
    int roll = 0;
    for (size_t k = 0; k < n; k++) {
      if (c[k].wall != wall) continue;
      const size_t ia = find_id(t, nt, c[k].id_a);
      const size_t ib = wall ? (size_t)c[k].id_b : find_id(t, nt, c[k].id_b);
      if (ia == SIZE_MAX || ib == SIZE_MAX) continue; /* (not within reach here) */
      a[m] = (uint32_t)ia;
      a[n + m] = (uint32_t)ib;
      h[m] = c[k].h;
      r[m] = c[k].roll;
      bd[m] = c[k].bond;
      roll |= c[k].has_roll;
      m++;
    }
    rc = esf_neighbor_inject(&s->nb, wall, m, a, a + n, h, roll ? r : NULL, bd, err);
  }
  free(a);
  free(h);
  free(r);
  free(bd);
  return rc;
}

int esf_par_rebuild(esf_sim *s, esf_error *err) {
  esf_par *P = s->par;
  if (!P) return ESF_OK;
  const double t0 = esf_par_now();
  esf_particles *p = &s->p;
  const int K = P->size, me = P->rank;
  const size_t n_old = p->n, olo = s->own_lo, ohi = s->own_hi, nown = ohi - olo;
  s->ft_lazy = NULL; /* the forces are evaluated again after the rebuild */
  esf_sim_forces_release(s);
  int rc = ESF_OK;
  int64_t *gid = P->gid; /* the previous global indices; first: the scene's order */
  unsigned char *keep = malloc(nown ? nown : 1);
  uint32_t *key = malloc((nown ? nown : 1) * sizeof *key);
  int *dest = malloc((nown ? nown : 1) * sizeof *dest);
  int *cnt = calloc(3 * (size_t)K, sizeof *cnt);
  size_t *kcut = malloc(((size_t)K + 1) * sizeof *kcut);
  esf_par_rec *out = NULL, *in = NULL, *own = NULL, *gout = NULL, *gin = NULL;
  esf_par_contact *cout = NULL, *cin = NULL;
  idx_pair *tab = NULL;
  size_t *remap = NULL;
  int64_t *ngid = NULL;
  esf_particles q = {0};
  if (!P->decomposed) {
    gid = malloc((n_old ? n_old : 1) * sizeof *gid);
    for (size_t i = 0; gid && i < n_old; i++) gid[i] = (int64_t)i;
  }
  if (!keep || !key || !dest || !cnt || !kcut || !gid) {
    rc = esf_fail(err, ESF_ENOMEM, "out of memory for the rebuild of %zu particles",
                  n_old);
    goto done;
  }
  if ((rc = remove_escaped(s, gid, keep, err))) goto done;
  esf_reorder_grid g;
  double rmax = 0.0;
  const size_t ntot = global_grid(s, keep, &g, &rmax);
  for (size_t j = 0; j < nown; j++)
    key[j] = keep[j] && g.ncell > 1 ? esf_reorder_key(&g, p->x + 3 * (olo + j)) : 0;
  if ((rc = make_cut(s, &g, key, keep, kcut, err))) goto done;
  /* step 4: the migrants and their contacts */
  int *co = cnt, *cc = cnt + K;
  size_t nstay = 0;
  for (size_t j = 0; j < nown; j++) {
    dest[j] = keep[j] ? owner_of(kcut, K, key[j]) : -1;
    if (dest[j] == me) nstay++;
    if (dest[j] >= 0 && dest[j] != me) co[dest[j]]++;
  }
  size_t nmig = 0;
  for (int r = 0; r < K; r++) nmig += (size_t)co[r];
  out = malloc((nmig ? nmig : 1) * sizeof *out);
  if (!out) {
    rc = esf_fail(err, ESF_ENOMEM, "out of memory for %zu migrating particles", nmig);
    goto done;
  }
  {
    size_t at[K];
    size_t t = 0;
    for (int r = 0; r < K; r++) {
      at[r] = t;
      t += (size_t)co[r];
    }
    for (size_t j = 0; j < nown; j++)
      if (dest[j] >= 0 && dest[j] != me)
        esf_par_rec_of(p, olo + j, gid[olo + j], key[j], &out[at[dest[j]]++]);
  }
  if ((rc = pack_contacts(s, dest, me, K, cc, &cout, err))) goto done;
  size_t nin = 0, ncin = 0;
  if ((rc = exchange(P, out, co, sizeof *out, (void **)&in, &nin, err))) goto done;
  if ((rc = exchange(P, cout, cc, sizeof *cout, (void **)&cin, &ncin, err))) goto done;
  /* step 5: the new owned particles, in the global order */
  const size_t no = nstay + nin;
  own = malloc((no ? no : 1) * sizeof *own);
  if (!own) {
    rc = esf_fail(err, ESF_ENOMEM, "out of memory for %zu particles", no);
    goto done;
  }
  {
    size_t m = 0;
    for (size_t j = 0; j < nown; j++)
      if (dest[j] == me) esf_par_rec_of(p, olo + j, gid[olo + j], key[j], &own[m++]);
    memcpy(own + m, in, nin * sizeof *in);
  }
  if ((rc = order_owned(own, no, nstay, kcut[me], kcut[me + 1], err))) goto done;
  unsigned long long nol = no, g0 = 0;
  MPI_Exscan(&nol, &g0, 1, MPI_UNSIGNED_LONG_LONG, MPI_SUM, P->comm);
  if (me == 0) g0 = 0;
  for (size_t j = 0; j < no; j++) own[j].gid = (int64_t)(g0 + j);
  /* step 6: ghosts, within m planes of another process's keys (and, when the slabs'
     axis is periodic, within reach of its slab through the periodic faces) */
  const size_t d12 = g.d1 * g.d2, np = g.ncell / d12;
  const double reach = 2.0 * rmax + s->nb.skin;
  const size_t mpl = isfinite(g.h) ? (size_t)ceil(reach / g.h) : 0;
  const esf_periodic *pb = &s->cfg.per;
  const int ks = g.ax[0], wrap = pb->on[ks] && isfinite(g.h);
  const double per = wrap ? pb->len[ks] : 0.0;
  /* Lees-Edwards with the flow along the slabs' axis: the images across the gradient
     faces are shifted along the slabs by the offset, so the particles within reach of
     those faces are every other process's ghosts */
  const int le_all = pb->le && pb->flow == ks;
  const double ge_lo = pb->lo[pb->grad] + reach,
               ge_hi = pb->lo[pb->grad] + pb->len[pb->grad] - reach;
  int *cg = cnt + 2 * K;
  for (int pass = 0; pass < 2; pass++) {
    size_t t = 0;
    for (int r = 0; r < K; r++) {
      const size_t tr = t;
      if (r != me && kcut[r + 1] > kcut[r]) {
        const size_t plo = kcut[r] / d12, phi = (kcut[r + 1] - 1) / d12;
        const size_t j0 = first_plane(own, no, d12, plo > mpl ? plo - mpl : 0),
                     j1 = first_plane(own, no, d12, phi + mpl + 1);
        for (size_t j = j0; j < j1; j++) { /* own is in key order: planes in order */
          if (pass) gout[t] = own[j];
          t++;
        }
        if (wrap ||
            le_all) { /* r's slab, widened by the reach, against x -+ the period */
          const double elo = plo == 0 ? -INFINITY : g.lo[ks] + (double)plo * g.h - reach,
                       ehi = phi + 1 >= np ? INFINITY
                                           : g.lo[ks] + (double)(phi + 1) * g.h + reach;
          for (size_t j = 0; j < no; j++) {
            if (j == j0) j = j1; /* (those are sent already) */
            if (j >= no) break;
            const double xu = own[j].x[ks] + per, xd = own[j].x[ks] - per;
            const double xg = own[j].x[pb->grad];
            if ((wrap && ((xu >= elo && xu <= ehi) || (xd >= elo && xd <= ehi))) ||
                (le_all && (xg < ge_lo || xg > ge_hi))) {
              if (pass) gout[t] = own[j];
              t++;
            }
          }
        }
      }
      if (!pass) cg[r] = (int)(t - tr);
    }
    if (!pass) {
      gout = malloc((t ? t : 1) * sizeof *gout);
      P->sidx = realloc(P->sidx, (t ? t : 1) * sizeof *P->sidx);
      if (!gout || !P->sidx) {
        rc = esf_fail(err, ESF_ENOMEM, "out of memory for %zu ghosts", t);
        goto done;
      }
    }
  }
  size_t ngin = 0;
  if ((rc = exchange(P, gout, cg, sizeof *gout, (void **)&gin, &ngin, err))) goto done;
  {
    int rin[K]; /* ghosts received from each process, for the exchange's plan */
    MPI_Alltoall(cg, 1, MPI_INT, rin, 1, MPI_INT, P->comm);
    P->rstart[0] = P->sstart[0] = 0;
    for (int r = 0; r < K; r++) {
      P->sstart[r + 1] = P->sstart[r] + cg[r];
      P->rstart[r + 1] = P->rstart[r] + rin[r];
    }
  }
  for (size_t j = 0; j < ngin; j++) gin[j].pos = (uint32_t)j;
  qsort(gin, ngin, sizeof *gin, rec_by_gid);
  size_t nbelow = 0;
  while (nbelow < ngin && gin[nbelow].gid < (int64_t)g0) nbelow++;
  /* step 7: the local arrays, the lists renumbered, the migrants' contacts */
  const size_t n_new = ngin + no;
  if ((rc = esf_particles_alloc(&q, n_new, err))) goto done;
  if (p->img && (rc = esf_particles_images(&q, err))) goto done;
  ngid = malloc((n_new ? n_new : 1) * sizeof *ngid);
  tab = malloc((n_new ? n_new : 1) * sizeof *tab);
  remap = malloc((n_old ? n_old : 1) * sizeof *remap);
  P->ridx = realloc(P->ridx, (ngin ? ngin : 1) * sizeof *P->ridx);
  if (!ngid || !tab || !remap || !P->ridx) {
    rc = esf_fail(err, ESF_ENOMEM, "out of memory for %zu particles", n_new);
    goto done;
  }
  for (size_t i = 0; i < n_new; i++) {
    const esf_par_rec *r = i < nbelow        ? &gin[i]
                           : i < nbelow + no ? &own[i - nbelow]
                                             : &gin[i - no];
    esf_par_rec_to(&q, i, r);
    ngid[i] = r->gid;
    tab[i].id = r->id;
    tab[i].i = i;
    if (i < nbelow || i >= nbelow + no) P->ridx[r->pos] = (uint32_t)i;
  }
  { /* the owned particles sent as ghosts, by their new local index */
    size_t t = 0;
    for (int r = 0; r < K; r++)
      for (size_t j = 0; j < (size_t)cg[r]; j++, t++) {
        P->sidx[t] = (uint32_t)(nbelow + (size_t)(gout[t].gid - (int64_t)g0));
      }
  }
  qsort(tab, n_new, sizeof *tab, by_id);
  /* a contact's history is right only where its process owned one of its particles */
  for (size_t k = 0; k < s->nb.pp.n; k++)
    if (!((s->nb.pp.a[k] >= olo && s->nb.pp.a[k] < ohi) ||
          (s->nb.pp.b[k] >= olo && s->nb.pp.b[k] < ohi)))
      s->nb.pp.touch[k] = 0;
  for (size_t k = 0; k < s->nb.pw.n; k++)
    if (!(s->nb.pw.a[k] >= olo && s->nb.pw.a[k] < ohi)) s->nb.pw.touch[k] = 0;
  for (size_t i = 0; i < n_old; i++) {
    const int removed = i >= olo && i < ohi && !keep[i - olo];
    remap[i] = removed ? SIZE_MAX : find_id(tab, n_new, p->id[i]);
  }
  esf_neighbor_remap(&s->nb, remap, n_old);
  if ((rc = inject(s, cin, ncin, tab, n_new, err))) goto done;
  esf_particles_release(&s->p);
  s->p = q;
  memset(&q, 0, sizeof q);
  esf_sim_forces_release(s);
  s->own_lo = nbelow;
  s->own_hi = nbelow + no;
  P->gid = ngid; /* the old one is freed below */
  ngid = NULL;
  P->g0 = (size_t)g0;
  P->ntot = ntot;
  P->decomposed = 1;
  P->rebuilds++;
  P->migrated += (long)nmig;
  { /* processes left without particles: said once (they wait at every exchange) */
    const long long empty = esf_par_sum(s, no == 0);
    if (empty > 0 && !P->empty_said) {
      esf_sim_log(s,
                  "mpi: t = %.6g s: %lld of %d processes own no particles (%zu particles "
                  "in %zu planes of cells along the longest axis): fewer processes would "
                  "run as fast",
                  s->t, empty, K, ntot, g.ncell / d12);
      P->empty_said = 1;
    }
  }
done:
  if (gid != P->gid) free(gid);
  esf_particles_release(&q);
  free(keep);
  free(key);
  free(dest);
  free(cnt);
  free(kcut);
  free(out);
  free(in);
  free(own);
  free(gout);
  free(gin);
  free(cout);
  free(cin);
  free(tab);
  free(remap);
  free(ngid);
  P->seconds += esf_par_now() - t0;
  return rc;
}

#endif

#ifndef ESF_MPI
int esf_par_rebuild(esf_sim *s, esf_error *err) { return (void)s, (void)err, ESF_OK; }
#endif
