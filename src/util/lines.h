/* lines.h — arrays aligned to the 64-byte cache line, for records of 64 bytes (the fused
 * step's accumulators) that must each sit in one line, and of 48 bytes (contact
 * history: four records to three lines) that should straddle as few as they can: a
 * record straddling two lines costs two fetches from memory instead of one. */
#ifndef ESF_LINES_H
#define ESF_LINES_H

#include <stdlib.h>
#include <string.h>

#define ESF_LINE 64

/* Like realloc, but the block is line-aligned: a new block of at least `bytes` (a
 * multiple of the line), the first `keep` bytes copied from p, p freed. NULL (and p
 * untouched) when out of memory. Free the result with free(). */
static inline void *esf_lines_realloc(void *p, size_t keep, size_t bytes) {
  const size_t size = (bytes + ESF_LINE - 1) / ESF_LINE * ESF_LINE;
  void *q = aligned_alloc(ESF_LINE, size ? size : ESF_LINE);
  if (!q) return NULL;
  if (p && keep) memcpy(q, p, keep < size ? keep : size);
  free(p);
  return q;
}

#endif
