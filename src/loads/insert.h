/* insert.h — particles inserted while the run goes on (a `particles:` entry
 * `{insert: {...}}`, docs/scene.md#insert): batches of new particles at random,
 * non-overlapping places of a box region, at a number rate or a mass rate, drawn from
 * a size distribution and a material mix (bodies/fill.h), reproducible from a seed.
 * Leapfrog only (both of its paths); the state is checkpointed (ckpt). */
#ifndef ESF_INSERT_H
#define ESF_INSERT_H

#include "bodies/fill.h"
#include "core/sim.h"
#include "util/blob.h"

/* One insert entry: the scene's spec and the run's state. */
typedef struct esf_insert {
  esf_fill_spec fill; /* region, size, mix, seed, dim, velocity; fill.count: the most
                         particles it inserts (0: no limit) */
  double rate;        /* particles/s, or 0 with mass_rate */
  double mass_rate;   /* kg/s, or 0 with rate */
  double start, stop; /* s; stop INFINITY: to the run's end */
  double every;       /* s between batches (0: set-up takes 100 steps) */
  char where[300];    /* the entry's place in the scene, for messages */
  double *sbuf;       /* owned: the size distribution's values and fractions */
  int32_t *mats;      /* owned: the mix's materials */
  double *fr;         /* owned: the mix's fractions */
  double rmax, rmin;  /* the largest and smallest radius it can draw, m */
  long every_steps;   /* set-up: steps between batches (>= 1) */
  /* state (checkpointed) */
  esf_rng rr, rm, rp;    /* radius, material and position streams */
  int64_t inserted;      /* particles it inserted */
  double mass_in;        /* their mass, kg */
  int32_t pending;       /* the next particle is drawn: r_next, m_next */
  int32_t m_next;        /* its material */
  double r_next;         /* its radius, m */
  int32_t logged;        /* it told that the rate could not be met */
  int64_t short_batches; /* batches that placed fewer than were due */
} esf_insert;

typedef struct esf_inserts {
  int n;
  esf_insert *e;
  int64_t next_id; /* the id of the next newborn */
} esf_inserts;

/* Appends an entry (its owned buffers pass to the list; the rng streams are seeded
 * from fill.seed here). */
int esf_inserts_add(esf_inserts **list, const esf_insert *in, esf_error *err);

/* At set-up, before the step is chosen: refuses integrators other than the leapfrog
 * and a region outside the domain; sets the batches' step count, the first id; the
 * critical step's m_min and k_max include the particles the entries may insert. */
int esf_inserts_setup(esf_sim *s, esf_error *err);

/* The smallest mass and the materials an entry may insert, for the critical step: a
 * copy of the particles, grown by one probe particle per material of every entry at its
 * smallest radius and one at its largest (the caller releases it). */
int esf_inserts_probes(const esf_sim *s, esf_particles *probes, esf_error *err);

/* The batch due at the current step (step a multiple of every_steps, start <= t <=
 * stop + every): new particles appended at the end of s->p, placed at random in the
 * region clear of every particle and wall element (touching allowed); *added their
 * count. Their kinetic and gravitational energy goes to the ledger's energy_inserted.
 * A batch that cannot place all that is due logs it once (the numbers); the rest wait
 * for later batches. */
int esf_inserts_apply(esf_sim *s, size_t *added, esf_error *err);

/* Steps until the next batch (>= 1; LONG_MAX when no entry has any left). */
long esf_inserts_steps_left(const esf_sim *s);

/* Checkpoint section INSERT: the entries' states. restore returns -1 on a mismatch
 * with the scene's entries. */
void esf_inserts_save(const esf_sim *s, esf_blob *b);
int esf_inserts_restore(esf_sim *s, esf_blob_in *in);

/* Particles inserted so far by all entries. */
long long esf_inserts_total(const esf_sim *s);

void esf_inserts_free(esf_inserts **list);

#endif
