/* fused_pairs.c — step 2's pair pass of the fused step (fused.c) for one range: its
 * accumulators set to f = m g, t = 0, the incoming boundary slots (b in the range), its
 * interior pairs in batches of eight (pair_batch.h; a chunk of CH batches has its first
 * halves, the gathers and geometry, computed before its laws) and its outgoing
 * boundary slots' A sides, all in ascending pair index k, so that each particle
 * receives its pair forces in the order of the serial scatter of model/forces.c
 * whatever the ranges.
 * Physics: the linear law of contact/contact_linear.c as pair_batch.c computes it.
 * Entry: the range's lists merged (fused_lists.c) and the lower ranges' boundary slots
 * of this step written (their ready flags seen, fused_sync.c). Units: SI. */
#include "fused/fused_impl.h"

#include "util/vec4.h"

#define PF  32 /* history prefetch distance, pairs */
#define APF 24 /* accumulator prefetch distance, particles */
#define CH  4  /* batches a chunk: their geometry, then their laws */

/* Adds the A side of outgoing boundary pair j (its pair's a is in range), and its
 * ledger rows to A's (rows not NULL). */
static inline void outgoing(const esf_fused *f, const esf_candidates *c, size_t j,
                            double *rows, size_t lr, unsigned set) {
  const size_t a = c->a[f->bk[j]];
  double *fa = f->acc + ESF_FUSED_ACC * a;
  const double *sl = f->slot_a + ESF_FUSED_SLOT_A * j;
  v4_acc(fa, sl);
  v4_acc(fa + 4, sl + 4);
  if (rows) esf_ledger_side_add(rows + lr * a, f->lslot_a + ESF_FUSED_LSLOT * j, set);
}

/* Sets the accumulators of particles [from, to) to f = m g, t = 0, and their ledger rows
 * to zero (rows not NULL): those of the rows `set` (esf_ledger_side_add's), and the
 * wall's row W unless ESF_LEDGER_NO_W (none with ESF_LEDGER_ZEROED); returns the new
 * frontier (max(from, to)). */
static inline size_t acc_set(const esf_particles *p, const double *g, double *acc,
                             double *rows, size_t lr, unsigned set, size_t from,
                             size_t to) {
  const esf_v4 gv = {g[0], g[1], g[2], 0.0}, zero = {0.0, 0.0, 0.0, 0.0};
  const int light = set & ESF_LEDGER_LIGHT, t = !(set & ESF_LEDGER_NO_T);
  for (size_t i = from; i < to; i++) { /* four-wide stores: the adds' four-wide loads */
    __builtin_prefetch(acc + ESF_FUSED_ACC * (i + APF), 1, 3); /* (past the end: none) */
    v4_st(acc + ESF_FUSED_ACC * i,
          p->mass[i] * gv); /* are then forwarded from the store buffer */
    v4_st(acc + ESF_FUSED_ACC * i + 4, zero);
    if (rows && !(set & ESF_LEDGER_ZEROED)) {
      double *r = rows + lr * i;
      v4_st(r + ESF_LR_DN, zero);
      if (!(set & ESF_LEDGER_NO_W)) v4_st(r + ESF_LR_W, zero);
      if (t) {
        v4_st(r + ESF_LR_DT, zero);
        v4_st(r + ESF_LR_MDT, zero);
      }
      if (!light)
        for (int j = ESF_LR_DISS; j < ESF_LR_PLAIN; j += 4) v4_st(r + j, zero);
      if (lr == ESF_LR) {
        v4_st(r + ESF_LR_RD, zero);
        if (!light) v4_st(r + ESF_LR_RE, zero);
      }
    }
  }
  return from > to ? from : to;
}

/* After a batch of list[q0 .. q0 + nl): its pairs whose bit is set in apart go to
 * ended[*ng ..], the others to list[w ..] (w <= q0: in place). Returns the new w. */
static inline size_t compact(uint32_t *list, size_t q0, int nl, unsigned apart, size_t w,
                             uint32_t *ended, size_t *ng) {
  if (!apart && w == q0) return w + (size_t)nl; /* nothing ended yet: in place already */
  for (int l = 0; l < nl; l++) {
    const uint32_t k = list[q0 + l];
    if (apart >> l & 1u)
      ended[(*ng)++] = k;
    else
      list[w++] = k;
  }
  return w;
}

/* The pair pass of range t, its interior contacts and new contacts in
 * list[0 .. cnt) (ascending): forces of all pairs touching its particles, in ascending
 * k per particle. The contacts that ended (the batch finds them) leave list, which is
 * compacted in place to *kept pairs, and go to ended[0 .. *ne). Needs the lower
 * ranges' boundary pairs of this step done (the incoming slots). Returns the lowest
 * failing pair index or SIZE_MAX. Kept out of line: inlined into run_range, the step
 * ran slower (docs/performance.md#tried-and-not-kept). */
__attribute__((noinline)) size_t esf_fused_pairs(esf_sim *s, esf_fused *f,
                                                 const esf_pair_batch_ctx *bc, size_t t,
                                                 size_t lo, size_t hi, uint32_t *list,
                                                 size_t cnt, uint32_t *ended, size_t *ne,
                                                 size_t *kept) {
  esf_particles *p = &s->p;
  const esf_candidates *c = &s->nb.pp;
  const double *g = s->cfg.gravity;
  double *acc = f->acc, *rows = bc->rows;       /* rows: the ledger's, or NULL */
  const unsigned set = esf_pair_batch_lset(bc); /* ledger rows: esf_ledger_side_add's */
  const size_t lr = bc->lr;
  size_t bad = SIZE_MAX;
  /* The accumulators are set (f = m g, t = 0) just ahead of their first use, not in a
   * pass of their own: a pair's b lies a few thousand particles ahead of its a, and a
   * separate pass would leave its line to be fetched again from memory at the add. */
  size_t fr = lo; /* acc[lo .. fr) are set */
  size_t bmax = lo;
  for (size_t q = f->binstart[t]; q < f->binstart[t + 1]; q++) {
    const size_t b = c->b[f->bk[f->bin[q]]];
    if (b >= bmax) bmax = b + 1;
  }
  fr = acc_set(p, g, acc, rows, lr, set, fr, bmax);
  for (size_t q = f->binstart[t]; q < f->binstart[t + 1]; q++) { /* incoming */
    const size_t j = f->bin[q], b = c->b[f->bk[j]];
    double *ab = acc + ESF_FUSED_ACC * b;
    const double *sl = f->slot + ESF_FUSED_SLOT * j;
    v4_dec(ab, sl);
    v4_acc(ab + 4, sl + 4);
    if (rows) esf_ledger_side_add(rows + lr * b, f->lslot + ESF_FUSED_LSLOT * j, set);
  }
  size_t jo = f->bout[t];
  const size_t jo1 = f->bout[t + 1];
  double out[ESF_BATCH][ESF_BATCH_OUT], lout[ESF_BATCH][ESF_BATCH_LOUT];
  const char *hist = (const char *)c->h;
  size_t w = 0, ng = 0; /* list[0 .. w) kept, ended[0 .. ng) */
  esf_pair_geo G[CH];
  for (size_t q0 = 0; q0 < cnt; q0 += CH * ESF_BATCH) {
    const size_t qe = cnt - q0 < CH * ESF_BATCH ? cnt : q0 + CH * ESF_BATCH;
    /* the chunk's geometry first: its batches' loads and square roots overlap */
    int nb = 0;
    for (size_t qb = q0; qb < qe; qb += ESF_BATCH, nb++)
      esf_pair_batch_geometry(bc, list + qb,
                              qe - qb < ESF_BATCH ? (int)(qe - qb) : ESF_BATCH, &G[nb]);
    for (int u = 0; u < nb; u++) /* b > a: covers the a sides and outgoing slots too */
      for (int l = 0; l < ESF_BATCH; l++) /* (lanes past nl repeat lane 0) */
        if (G[u].ib[l] >= bmax) bmax = G[u].ib[l] + 1;
    fr = acc_set(p, g, acc, rows, lr, set, fr, bmax);
    for (int u = 0; u < nb; u++) {
      const esf_pair_geo *gb = &G[u];
      const size_t qb = q0 + (size_t)u * ESF_BATCH;
      const int nl = gb->nl;
      /* the histories of the pairs PF ahead (sparse in memory, so the hardware's
       * stream prefetch does not see them coming), both ends of each record: half the
       * 48-byte records straddle two lines; a batch's worth at a time (a chunk's at
       * once queued more misses than the core holds). Not b's velocity, spin and
       * accumulator: that cost time and gained nothing
       * (docs/performance.md#the-pair-batches). */
      for (size_t q = qb + PF; q < qb + PF + ESF_BATCH && q < cnt; q++) {
        const char *hq = hist + (size_t)list[q] * sizeof(esf_contact_hist);
        __builtin_prefetch(hq, 1, 3);
        __builtin_prefetch(hq + sizeof(esf_contact_hist) - 1, 1, 3);
      }
      unsigned apart;
      if (jo == jo1 || f->bk[jo] > gb->kk[nl - 1]) {
        /* no outgoing slot falls among these pairs: the batch adds its results itself,
           as the loop below does (esf_pair_batch_acc_add) */
        const unsigned fail = esf_pair_batch_law(bc, gb, NULL, NULL, acc, &apart);
        for (int l = 0; fail && l < nl; l++)
          if ((fail >> l & 1u) && gb->kk[l] < bad) bad = gb->kk[l];
        w = compact(list, qb, nl, apart, w, ended, &ng);
        continue;
      }
      const unsigned fail = esf_pair_batch_law(bc, gb, out, lout, NULL, &apart);
      for (int l = 0; l < nl; l++) {
        const size_t k = gb->kk[l], a = gb->ia[l], b = gb->ib[l];
        for (; jo < jo1 && f->bk[jo] < k; jo++) outgoing(f, c, jo, rows, lr, set);
        if (apart >> l & 1u) { /* nothing, but a broken bond's energy (ledger) */
          if (rows) esf_pair_batch_led_add(rows, lr, a, b, lout[l], set);
          continue;
        }
        if (fail >> l & 1u) {
          if (k < bad) bad = k;
          continue;
        }
        esf_pair_batch_acc_add(acc, a, b, v4_ld(out[l]), v4_ld(out[l] + 4),
                               v4_ld(out[l] + 8));
        if (rows) esf_pair_batch_led_add(rows, lr, a, b, lout[l], set);
      }
      w = compact(list, qb, nl, apart, w, ended, &ng);
    }
  }
  acc_set(p, g, acc, rows, lr, set, fr, hi);
  for (; jo < jo1; jo++) outgoing(f, c, jo, rows, lr, set);
  *kept = w;
  *ne = ng;
  return bad;
}
