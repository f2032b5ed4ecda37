/* contact_net.h — the contact network of a state, for output: the particle pairs that
 * touch (overlap > 0 at the current positions) with the magnitude of the normal force
 * the contact law gives them (N, >= 0). Particle-wall contacts are not included. */
#ifndef ESF_CONTACT_NET_H
#define ESF_CONTACT_NET_H

#include <stddef.h>
#include <stdint.h>

#include "util/esf_error.h"

struct esf_sim;

typedef struct esf_contact_net {
  size_t n;      /* touching pairs */
  int64_t *pair; /* 2n: row indices (from 0) of the two particles in the frame, a < b */
  double *fn;    /* n: normal force magnitude, N */
  size_t cap;
} esf_contact_net;

/* Fills net (reusing its storage) from the sim's particle-particle candidate list,
 * evaluating the contact law without committing anything: the sim is not changed. */
int esf_contact_net_build(const struct esf_sim *s, esf_contact_net *net, esf_error *err);

void esf_contact_net_release(esf_contact_net *net);

#endif
