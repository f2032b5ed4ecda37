/* events.h — scene events at given times. The one kind so far deletes the particles
 * whose centres lie in a region (drilling a well, seed 004 §4.4: "removing the elements
 * in the drilling region"). Leapfrog only. */
#ifndef ESF_EVENTS_H
#define ESF_EVENTS_H

#include "core/sim.h"

enum { ESF_REGION_CYLINDER = 0, ESF_REGION_BOX = 1 };

typedef struct esf_region {
  int kind;                  /* ESF_REGION_* */
  double center[3], axis[3]; /* cylinder: a point of the axis (m), unit axis */
  double radius;             /* cylinder: m (infinite length) */
  double min[3], max[3];     /* box, m */
} esf_region;

typedef struct esf_event {
  double at; /* s */
  esf_region region;
  int done;      /* applied */
  long deleted;  /* particles it deleted */
  double t_done; /* time it was applied, s */
} esf_event;

typedef struct esf_events {
  int n;
  esf_event *e;
} esf_events;

/* 1 when centre x lies inside region r (on the boundary counts as inside). */
int esf_region_contains(const esf_region *r, const double x[3]);

/* At set-up: refuses integrators other than the leapfrog when events exist. */
int esf_events_setup(esf_sim *s, esf_error *err);

/* Applies the events due at the current step (at <= t + dt/2): deletes the particles
 * inside the region, adds their kinetic and gravitational energy and the elastic
 * energy of their touching contacts to the ledger's energy_removed, logs the count.
 * Candidate lists stay consistent (esf_neighbor_remap). */
int esf_events_apply(esf_sim *s, esf_error *err);

void esf_events_free(esf_events **ev);

#endif
