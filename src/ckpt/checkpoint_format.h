/* checkpoint_format.h — what checkpoint.c (writing, verifying) and
 * checkpoint_restore.c (restoring, describing) share: the loaded file with its section
 * table and the record of the sim's scalars. Internal to those two files. */
#ifndef ESF_CHECKPOINT_FORMAT_H
#define ESF_CHECKPOINT_FORMAT_H

#include <stdint.h>

#include "ckpt/checkpoint.h"
#include "util/blob.h"

/* Scalars of the sim between steps. */
typedef struct ck_sim {
  double t, dt, led_time, alpha_r, alpha_t, contacts_sum, walls_t;
  int64_t step, removed, rhs_evals, builds;
  uint64_t rng[4];
  int64_t bonds_formed, bonds_broken; /* esf_bonds counters (adhesive law) */
} ck_sim;

struct esf_ckpt {
  char *data;
  size_t len;
  char path[1200];
  int nsec;
  const char *sets[256]; /* the stored overrides */
  int nsets;
  struct {
    char tag[9];
    const unsigned char *p;
    size_t len;
  } sec[32];
};

/* Section `tag` of a loaded checkpoint as a reader (short_read set when missing). */
esf_blob_in esf_ckpt_sec(const esf_ckpt *c, const char *tag);

#endif
