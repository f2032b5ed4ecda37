/* blob.h — a growing byte buffer and a bounds-checked reader over one: how checkpoint
 * sections (checkpoint.h) and the integrators' saved states (integrator.h save/restore)
 * are serialised. Values are stored in native byte order and layout; the checkpoint
 * records the build's layout and refuses another. */
#ifndef ESF_BLOB_H
#define ESF_BLOB_H

#include <stddef.h>

typedef struct esf_blob {
  unsigned char *d;
  size_t n, cap;
  int nomem; /* an append failed for lack of memory (later appends are ignored) */
} esf_blob;

/* Appends len bytes (ignored once nomem is set). */
void esf_blob_put(esf_blob *b, const void *data, size_t len);
void esf_blob_release(esf_blob *b);

typedef struct esf_blob_in {
  const unsigned char *d;
  size_t n, pos;
  int short_read; /* a get asked for more than was left */
} esf_blob_in;

/* Copies len bytes out (zeros and short_read set when fewer are left); 0 ok, -1 short. */
int esf_blob_get(esf_blob_in *in, void *out, size_t len);
/* A pointer to the next len bytes (NULL and short_read when fewer are left). */
const void *esf_blob_take(esf_blob_in *in, size_t len);

#endif
