/* fused_slots.c — step 1 of the fused step (fused.c): the boundary pairs of a range
 * (a in it, b in a higher range) computed before its interior, into per-pair slots.
 *
 * A boundary pair's force and torques are computed once, by a's range, committing its
 * history: the force on A and the torque on B go to `slot` (one cache line per pair,
 * read by b's range, which subtracts the force and adds the torque in ascending k
 * among its incoming pairs), the force and torque on A to `slot_a` (added by a's range
 * between its interior pairs in k order, fused_pairs.c). A pair whose spheres no longer
 * overlap clears its flag and its slots, so an absent contact adds zeros. The slots are
 * written by non-temporal stores and fenced before the range raises its ready flag
 * (fused_sync.c), so they are visible to b's range once it sees the flag; the stores
 * do not pull the line back from b's core
 * (docs/performance.md#two-threads-at-10-000-two-modes). Units: N, N m. */
#include "fused/fused_impl.h"

#include <string.h>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

_Static_assert(
    ESF_FUSED_SLOT * sizeof(double) == ESF_LINE && ESF_BATCH_OUT == 12,
    "slot_put stores a slot as one line: the rows 0-3 and 8-11 of the batch's");

/* A computed boundary pair's force on A and torque on B (row[0..3], row[8..11] of the
 * batch's) to its slot, one line, by non-temporal stores, which do not take the line
 * from the core of b's range, where the last step's read of it left a copy
 * (slot_fence before the ready flag makes them visible). They pay when lines travel
 * slowly between the cores (docs/performance.md#two-threads-at-10-000-two-modes). */
static inline void slot_put(double *slot, const double *row) {
#if defined(__AVX__)
  _mm256_stream_pd(slot, _mm256_loadu_pd(row));
  _mm256_stream_pd(slot + 4, _mm256_loadu_pd(row + 8));
#elif defined(__SSE2__)
  for (int q = 0; q < 4; q += 2) {
    _mm_stream_pd(slot + q, _mm_loadu_pd(row + q));
    _mm_stream_pd(slot + 4 + q, _mm_loadu_pd(row + 8 + q));
  }
#else
  memcpy(slot, row, 4 * sizeof(double));
  memcpy(slot + 4, row + 8, 4 * sizeof(double));
#endif
}

/* Orders slot_put's stores before the stores that follow (esf_fused_boundary' caller's
 * ready flag). */
static inline void slot_fence(void) {
#if defined(__SSE2__)
  _mm_sfence();
#endif
}

/* The boundary pairs bk[j0 .. j1): each one's slot, zero when not touching,
 * the touching ones computed in batches, the stores fenced (slot_fence) before the
 * caller raises its ready flag; no fence for a range without such pairs. Returns the
 * lowest pair index whose overlap exceeds the limit (its slot unwritten), or SIZE_MAX;
 * adds the touching ones to *nt. */
size_t esf_fused_boundary(esf_sim *s, esf_fused *f, const esf_pair_batch_ctx *bc,
                          size_t j0, size_t j1, size_t *nt) {
  const esf_particles *p = &s->p;
  esf_candidates *c = &s->nb.pp;
  uint32_t kb[ESF_BATCH];
  const int per = c->img != NULL; /* periodic images: tested once, not per pair */
  size_t jb[ESF_BATCH], bad = SIZE_MAX;
  int m = 0;
  double out[ESF_BATCH][ESF_BATCH_OUT], lout[ESF_BATCH][ESF_BATCH_LOUT];
  /* the ledger rows a side carries: a light step without tangential dashpots' the
     first row alone (its others unread, core/ledger.h) */
  const size_t lb =
      (bc->light && bc->no_t && !bc->roll ? (size_t)4
                                          : (size_t)ESF_PAIR_BATCH_LROWS(bc)) *
      sizeof(double);
  for (size_t j = j0; j < j1 || m > 0;) {
    if (j < j1) {
      const size_t k = f->bk[j];
      if (!(per ? esf_fused_overlap_k(p->x, p->radius, c, k)
                : esf_fused_overlap(p->x, p->radius, c->a[k], c->b[k])) &&
          !(c->touch[k] && esf_candidates_bonded(c, k))) { /* bonds pull */
        if (c->touch[k] || bc->vc0 || bc->trial) {         /* the ODE methods: a trial may
                                                               have filled a flagless slot */
          if (!bc->trial) c->touch[k] = 0;
          esf_fused_slot_clear(f, j);
        }
        if (bc->rows) /* a bond that broke last step left its energy here */
          f->lslot_a[ESF_FUSED_LSLOT * j + ESF_LS_BOND] = -0.0;
        j++;
        continue;
      }
      (*nt)++;
      kb[m] = (uint32_t)k;
      jb[m++] = j++;
      if (m < ESF_BATCH) continue;
    }
    unsigned apart; /* only broken bonds: screened above by the same test */
    const unsigned fail = esf_pair_batch_linear(bc, kb, m, out, lout, &apart);
    if (m > ESF_BATCH) __builtin_unreachable(); /* kb, jb hold ESF_BATCH */
    for (int l = 0; l < m; l++) {
      if (fail >> l & 1u) {
        if (kb[l] < bad) bad = kb[l];
        continue;
      }
      if (apart >> l & 1u) { /* a bond broke: no force, its energy in the ledger */
        (*nt)--;
        esf_fused_slot_clear(f, jb[l]);
        if (bc->rows) memcpy(f->lslot_a + ESF_FUSED_LSLOT * jb[l], lout[l], lb);
        continue;
      }
      slot_put(f->slot + ESF_FUSED_SLOT * jb[l], out[l]);
      memcpy(f->slot_a + ESF_FUSED_SLOT_A * jb[l], out[l],
             ESF_FUSED_SLOT_A * sizeof(double));
      if (bc->rows) { /* the ledger's rows: A's, B's */
        memcpy(f->lslot_a + ESF_FUSED_LSLOT * jb[l], lout[l], lb);
        memcpy(f->lslot + ESF_FUSED_LSLOT * jb[l], lout[l] + ESF_BATCH_LSIDE, lb);
      }
    }
    m = 0;
  }
  if (j1 > j0) slot_fence();
  return bad;
}
