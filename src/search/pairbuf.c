/* pairbuf.c — the pair buffer (pairbuf.h): grown by doubling from 1024 pairs. */
#include "search/pairbuf.h"

#include <stdlib.h>
#include <string.h>

int esf_pairbuf_grow(esf_pairbuf *b, esf_error *err) {
  size_t cap = b->cap ? 2 * b->cap : 1024;
  if (cap <= b->cap || cap > SIZE_MAX / sizeof(uint32_t))
    return esf_fail(err, ESF_ENOMEM, "too many contact-candidate pairs (%zu)", b->cap);
  uint32_t *i = realloc(b->i, cap * sizeof *i);
  if (!i) return esf_fail(err, ESF_ENOMEM, "out of memory for %zu candidate pairs", cap);
  b->i = i;
  uint32_t *j = realloc(b->j, cap * sizeof *j);
  if (!j) return esf_fail(err, ESF_ENOMEM, "out of memory for %zu candidate pairs", cap);
  b->j = j;
  b->cap = cap;
  return ESF_OK;
}

int esf_pairbuf_push(esf_pairbuf *b, uint32_t i, uint32_t j, esf_error *err) {
  if (b->n == b->cap) {
    int rc = esf_pairbuf_grow(b, err);
    if (rc) return rc;
  }
  b->i[b->n] = i;
  b->j[b->n] = j;
  b->n++;
  return ESF_OK;
}

int esf_pairbuf_append(esf_pairbuf *out, const esf_pairbuf *b, esf_error *err) {
  if (b->n == 0) return ESF_OK; /* its arrays may not exist */
  while (out->cap < out->n + b->n) {
    const int rc = esf_pairbuf_grow(out, err);
    if (rc) return rc;
  }
  memcpy(out->i + out->n, b->i, b->n * sizeof *b->i);
  memcpy(out->j + out->n, b->j, b->n * sizeof *b->j);
  out->n += b->n;
  return ESF_OK;
}

void esf_pairbuf_release(esf_pairbuf *b) {
  if (!b) return;
  free(b->i);
  free(b->j);
  memset(b, 0, sizeof *b);
}
