/* blob.c — byte buffer and checked reader (blob.h). The buffer doubles its capacity,
 * so appending a checkpoint costs amortised O(bytes). */
#include "util/blob.h"

#include <stdlib.h>
#include <string.h>

void esf_blob_put(esf_blob *b, const void *data, size_t len) {
  if (b->nomem || len == 0) return;
  if (b->n + len > b->cap) {
    size_t cap = b->cap ? b->cap : 4096;
    while (cap < b->n + len) cap *= 2;
    unsigned char *d = realloc(b->d, cap);
    if (!d) {
      b->nomem = 1;
      return;
    }
    b->d = d;
    b->cap = cap;
  }
  memcpy(b->d + b->n, data, len);
  b->n += len;
}

void esf_blob_release(esf_blob *b) {
  free(b->d);
  b->d = NULL;
  b->n = b->cap = 0;
  b->nomem = 0;
}

const void *esf_blob_take(esf_blob_in *in, size_t len) {
  if (in->short_read || len > in->n - in->pos) {
    in->short_read = 1;
    return NULL;
  }
  const void *p = in->d + in->pos;
  in->pos += len;
  return p;
}

int esf_blob_get(esf_blob_in *in, void *out, size_t len) {
  const void *p = esf_blob_take(in, len);
  if (!p) {
    if (len) memset(out, 0, len);
    return -1;
  }
  if (len) memcpy(out, p, len); /* out may be NULL for an empty list */
  return 0;
}
