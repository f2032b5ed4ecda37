/* pairbuf.h — a growable list of candidate pairs (i, j), the output of every pair
 * search (cells.c, cells_grid.c, the brute-force reference). */
#ifndef ESF_PAIRBUF_H
#define ESF_PAIRBUF_H

#include <stddef.h>
#include <stdint.h>

#include "util/esf_error.h"

/* A list of candidate pairs (i, j), i != j, each unordered pair once. */
typedef struct esf_pairbuf {
  size_t n, cap;
  uint32_t *i, *j;
} esf_pairbuf;

/* Stores (i, j) as given. */
int esf_pairbuf_push(esf_pairbuf *b, uint32_t i, uint32_t j, esf_error *err);
/* Appends b's pairs to out, in b's order. */
int esf_pairbuf_append(esf_pairbuf *out, const esf_pairbuf *b, esf_error *err);
void esf_pairbuf_release(esf_pairbuf *b);

/* Grows the pair buffer (doubling). */
int esf_pairbuf_grow(esf_pairbuf *b, esf_error *err);

/* Stores the pair (min, max) when near is 1, without a branch on it (the test is as
 * often true as not in a packed bed, which no branch predictor guesses): the slot is
 * always written, the count advances by near. */
static inline int esf_pairbuf_push_if(esf_pairbuf *b, uint32_t i, uint32_t j, int near,
                                      esf_error *err) {
  if (b->n == b->cap) {
    int rc = esf_pairbuf_grow(b, err);
    if (rc) return rc;
  }
  b->i[b->n] = i < j ? i : j;
  b->j[b->n] = i < j ? j : i;
  b->n += (size_t)near;
  return ESF_OK;
}

/* Stores the pair as (min, max); the fast path is a bounds check and two stores. */
static inline int esf_pairbuf_push_ordered(esf_pairbuf *b, uint32_t i, uint32_t j,
                                           esf_error *err) {
  return esf_pairbuf_push_if(b, i, j, 1, err);
}

#endif
