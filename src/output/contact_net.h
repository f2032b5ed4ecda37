/* contact_net.h — the contact network of a state, for output: the particle pairs that
 * touch (the contact law gives them a force at the current positions) with their normal
 * force magnitude and tangential force vector, the particle-wall contacts with theirs,
 * and each contact's point and force (walls.csv, stress.csv: wall_loads.h). */
#ifndef ESF_CONTACT_NET_H
#define ESF_CONTACT_NET_H

#include <stddef.h>
#include <stdint.h>

#include "util/esf_error.h"

struct esf_sim;

/* One kind of contact (pairs or particle-wall) as parallel arrays of n entries. */
typedef struct esf_contact_set {
  size_t n, cap;
  int64_t *pair; /* 2n: pairs: rows (from 0) of the two particles, a < b;
                    walls: the particle's row and the wall's index in the scene */
  double *fn;    /* n: normal force magnitude, N (> 0 compressive) */
  double *ft;    /* 3n: tangential force on the first particle, N */
  double *f;     /* 3n: whole contact force on the first particle, N */
  double *pc;    /* 3n: contact point, m */
  double *ta;    /* 3n: torque of the contact on the first particle about its centre,
                    N m (lever arm x ft plus rolling resistance) */
} esf_contact_set;

typedef struct esf_contact_net {
  esf_contact_set pp; /* touching particle pairs */
  esf_contact_set pw; /* touching particle-wall contacts */
} esf_contact_net;

/* Fills net (reusing its storage) from the sim's candidate lists, evaluating the
 * contact law without committing anything (esf_forces_probe): the sim's state is not
 * changed, but for the walls' placement: walls: also the particle-wall contacts (else
 * net->pw.n = 0), with moving walls placed at the state's time s->t first. */
int esf_contact_net_build(struct esf_sim *s, int walls, esf_contact_net *net,
                          esf_error *err);

/* Coordination number of each of the n particles (contacts with particles and walls)
 * into z (n int32). */
void esf_contact_net_coordination(const esf_contact_net *net, size_t n, int32_t *z);

void esf_contact_net_release(esf_contact_net *net);

#endif
