/* events.h — scene events at given times: deleting the particles whose centres lie in
 * a region (drilling a well, seed 004 §4.4: "removing the elements in the drilling
 * region"), removing a named wall (a gate that opens) or adding one back. Leapfrog
 * only. */
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

enum { ESF_EVENT_DELETE = 0, ESF_EVENT_REMOVE_WALL = 1, ESF_EVENT_ADD_WALL = 2 };

typedef struct esf_event {
  int kind;  /* ESF_EVENT_* */
  int group; /* REMOVE_WALL, ADD_WALL: the wall group */
  double at; /* s */
  esf_region region;
  int done;      /* applied */
  long deleted;  /* particles it deleted */
  double t_done; /* time it was applied, s */
} esf_event;

typedef struct esf_events {
  int n;
  esf_event *e;
  int walls_changed; /* a wall was removed or added: the lists are rebuilt (refresh.c) */
} esf_events;

/* 1 when centre x lies inside region r (on the boundary counts as inside). */
int esf_region_contains(const esf_region *r, const double x[3]);

/* At set-up: refuses integrators other than the leapfrog when events exist. */
int esf_events_setup(esf_sim *s, esf_error *err);

/* Applies the events due at the current step (at <= t + dt/2): deletes the particles
 * inside the region, adds their kinetic and gravitational energy and the elastic
 * energy of their touching contacts to the ledger's energy_removed, logs the count.
 * Candidate lists stay consistent (esf_neighbor_remap). Removing a wall adds the
 * elastic energy of its touching contacts to energy_removed and sets walls_changed;
 * adding one fails (ESF_ENUMERIC) when a particle overlaps it. */
int esf_events_apply(esf_sim *s, esf_error *err);

/* Sets each named wall's presence (esf_wall_group.absent) from its events: absent
 * when its latest applied event removed it, or, none applied, when its first event
 * adds it. At scene reading and after a checkpoint's event records are restored. */
void esf_events_wall_state(esf_sim *s);

/* 1 when event b comes before event a of the same list in time (ties: list order). */
int esf_event_before(const esf_events *E, int b, int a);

/* 1 when an event is still to come (E may be NULL): the fused step then takes one step
 * a call, so that each step's refresh sees it. */
int esf_events_pending(const esf_events *E);

void esf_events_free(esf_events **ev);

#endif
