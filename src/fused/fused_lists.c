/* fused_lists.c — a range's interior pairs (both particles in it) as two lists, each
 * ascending in k: the contacts, which go to the batches without a test (the batch finds
 * those that ended: pair_batch.h), and the idle candidates, which are screened for new
 * contacts. Made from the touch flags at a call's first step (whatever ran between
 * calls), then carried from step to step. Within the range's block of each buffer (blk
 * pairs): tl[0 .. nt)        the contacts of the step before; tl[blk - nn .. blk) this
 * step's new contacts, written downward (tl[blk - 1] is the first), by the screening,
 * which writes nothing else (a step not taken leaves the lists as they were); sq[0 .. nt
 * + nn)   the batches' sequence, the two merged; the batches compact it in place to the
 * contacts that remain (the next step's tl) and write the ended ones to tl[0 ..), free by
 * then; il[0 .. ni)        the idle candidates; after the batches, less the new contacts,
 *                      plus the ended ones.
 * No two of these overlap: nt + ni <= blk, and the ended ones are among tl's.
 * Units: none (indices); the screening's test is fused_impl.h's esf_fused_overlap. */
#include "fused/fused_impl.h"

#include <string.h>

/* The two lists from the touch flags of the pairs k0 .. k1 whose b is below end (the
 * range's interior pairs; the others are boundary pairs, fused_slots.c's). */
void esf_fused_lists_from_flags(const esf_sim *s, size_t k0, size_t k1, size_t end,
                                esf_fused_lists *L) {
  const uint32_t *cb = s->nb.pp.b;
  const uint8_t *touch = s->nb.pp.touch;
  size_t nt = 0, ni = 0;
  for (size_t k = k0; k < k1; k++) {
    if (cb[k] >= end) continue; /* a boundary pair: step 1's */
    const size_t on = touch[k] != 0;
    L->tl[nt] = (uint32_t)k; /* both written, one kept: no branch on the flag */
    L->il[ni] = (uint32_t)k;
    nt += on;
    ni += 1 - on;
  }
  L->nt = nt;
  L->ni = ni;
}

/* The screening of the idle candidates il[j0 .. j1) for overlapping spheres,
 * |x_b - x_a|^2 < (r_a + r_b)^2 (the batch applies the same test, in the same order, to
 * the contacts): the new contacts go to top[-(nn + 1)], top[-(nn + 2)], ...; returns
 * how many. Branch-free: every candidate is written, the count advances on a hit (the
 * write stays in the free part of tl: see esf_fused_lists). Reads only the range's own
 * particles. */
size_t esf_fused_screen(const esf_sim *s, const uint32_t *il, size_t j0, size_t j1,
                        uint32_t *top, size_t nn) {
  const double *x = s->p.x, *r = s->p.radius;
  const uint32_t *ca = s->nb.pp.a, *cb = s->nb.pp.b;
  size_t cnt = nn;
  if (s->nb.pp.img) { /* periodic axes: B at its image */
    for (size_t j = j0; j < j1; j++) {
      const size_t k = il[j];
      top[-(ptrdiff_t)(cnt + 1)] = (uint32_t)k;
      cnt += (size_t)esf_fused_overlap_k(x, r, &s->nb.pp, k);
    }
    return cnt - nn;
  }
  for (size_t j = j0; j < j1; j++) {
    const size_t k = il[j];
    top[-(ptrdiff_t)(cnt + 1)] = (uint32_t)k;
    cnt += (size_t)esf_fused_overlap(x, r, ca[k], cb[k]);
  }
  return cnt - nn;
}

/* The batches' sequence: the contacts tl[0 .. nt) and the nn new ones at top[-1],
 * top[-2], ..., merged in ascending k into sq. Returns its length. */
size_t esf_fused_merge_new(uint32_t *sq, const uint32_t *tl, size_t nt,
                           const uint32_t *top, size_t nn) {
  size_t i = 0, p = 0;
  for (size_t j = 1; j <= nn; j++) {
    const uint32_t k = top[-(ptrdiff_t)j];
    while (i < nt && tl[i] < k) sq[p++] = tl[i++];
    sq[p++] = k;
  }
  if (i < nt) memcpy(sq + p, tl + i, (nt - i) * sizeof *sq); /* tl may be NULL if empty */
  return p + nt - i;
}

/* The idle list after a step: il[0 .. ni) less the nn new contacts at top[-1], ...
 * (a subsequence of it, in the same order), plus the ne ended contacts ended[0 .. ne)
 * (ascending), merged in from the back. Returns the new length. */
size_t esf_fused_idle_update(uint32_t *il, size_t ni, const uint32_t *top, size_t nn,
                             const uint32_t *ended, size_t ne) {
  size_t w = ni;
  if (nn) {
    size_t j = 1;
    w = 0;
    for (size_t q = 0; q < ni; q++) {
      if (j <= nn && il[q] == top[-(ptrdiff_t)j]) {
        j++;
        continue;
      }
      il[w++] = il[q];
    }
  }
  size_t p = w + ne, i = w;
  for (size_t q = ne; q > 0; q--) {
    const uint32_t k = ended[q - 1];
    while (i > 0 && il[i - 1] > k) il[--p] = il[--i];
    il[--p] = k;
  }
  return w + ne;
}
