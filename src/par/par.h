/* par.h — one run on several MPI processes (docs/mpi.md): the particles cut among
 * them in the global order, ghosts, migration with the contacts' state, and every sum
 * across particles taken so that the results do not depend on the process count.
 *
 * The global order is the renumbering's (core/reorder.h): cells ranked with the axis of
 * most cells slowest, ties in the previous global order. Each process owns one
 * contiguous piece of it, cut where the count before the cut is a multiple of
 * ESF_LEDGER_BLOCK, so that the ledger's blocks are whole on every process; as the
 * slowest axis varies slowest, a piece is a slab of the domain. Its particles are
 * stored in the global order, between the ghosts that come before it in that order
 * and those after; a process's pair forces, histories and sums per particle are then
 * those one process computes, bit for bit. Without -Dmpi=true every function here is
 * the one-process case (s->par is NULL). */
#ifndef ESF_PAR_H
#define ESF_PAR_H

#include <stddef.h>
#include <stdint.h>

#include "core/sim.h"

typedef struct esf_par esf_par;

/* Takes sim s (every process read the same scene and set it up) onto MPI_COMM_WORLD
 * when it has more than one process; refuses, with the key's place, what MPI runs do
 * not support. One process: s->par stays NULL and nothing changes. */
int esf_par_attach(esf_sim *s, esf_error *err);
void esf_par_detach(esf_sim *s);

/* This process's rank (0 without MPI), the process count (1). */
int esf_par_rank(const esf_sim *s);
int esf_par_size(const esf_sim *s);

/* MPI's rank and size of MPI_COMM_WORLD (0 and 1 without MPI, or before MPI_Init). */
void esf_par_world(int *rank, int *size);

/* The run's particle count over every process. */
size_t esf_par_count(const esf_sim *s);

/* What an MPI run refuses in this scene (NULL: nothing); *key its scene key. */
const char *esf_par_refusal(const esf_sim *s, const char **key);

/* At a list rebuild, in place of esf_sim_remove_escaped and esf_reorder_particles:
 * particles that left the domain removed (their energy booked in the global order),
 * the cut, particles migrated with their contacts' histories, renumbered in the global
 * order, ghosts received; the lists renumbered, a build must follow. */
int esf_par_rebuild(esf_sim *s, esf_error *err);

/* Ghosts' x, v, w from their owners (every step, before the forces). */
int esf_par_ghosts(esf_sim *s, esf_error *err);

/* Around a step's computation (end 0, then 1): its time less the exchanges' within
 * it is added to this process's busy time, the next cut's balance. */
void esf_par_busy(esf_sim *s, int end);

/* Every process learns whether any failed: returns the lowest failing rank's status
 * with its message (rc on the process itself when it failed). */
int esf_par_agree(esf_sim *s, int rc, esf_error *err);

/* Logical or of flag over the processes; sum of counts. */
int esf_par_any(const esf_sim *s, int flag);
long long esf_par_sum(const esf_sim *s, long long v);

/* Books a step of the ledger from this process's nb blocks (esf_ledger_step over
 * all processes' blocks in the global order). */
void esf_par_ledger_step(esf_sim *s, const double *blocks, size_t nb);

/* Adaptive global damping from the kinetic energies in nb blocks of this process's
 * (esf_sim_adapt_damping over every process's blocks). */
void esf_par_adapt_damping(esf_sim *s, const double *blocks, size_t nb);

/* The servo walls' velocities from their contacts' sums (loads/servo.h), the blocks
 * summed over every process in the global order. */
void esf_par_servo(esf_sim *s);

/* The touching contacts of the last step whose particle A this process owns (each
 * contact of the run counted once when summed over the processes; `local` without
 * MPI). */
size_t esf_par_touching(const esf_sim *s, size_t local);

/* esf_par_agree, and *flag becomes the logical or of every process's flag: one
 * exchange. */
int esf_par_agree_flag(esf_sim *s, int rc, int *flag, esf_error *err);

/* The run's particles gathered on rank 0 in the global order into *all (positions,
 * velocities, spins, forces, radii, materials, ids; the others get none); *all is
 * NULL-safe to release. Collective. */
int esf_par_gather(esf_sim *s, esf_particles *all, esf_error *err);

/* A checkpoint of an MPI run (collective): on rank 0, *view becomes the run as one
 * process holds it (a shallow copy of *s with every particle, both candidate lists in
 * the global numbering, the lists' reference positions and the contact count
 * gathered), which the checkpoint writer takes as it is; the other processes get
 * nothing. esf_par_view_release frees what the gather allocated. */
int esf_par_view(esf_sim *s, esf_sim *view, esf_error *err);
void esf_par_view_release(esf_sim *view);

/* After a checkpoint's restore on every process (each holds the whole run as one
 * process did): the particles cut in their current order, without renumbering or a
 * rebuild, so the run goes on as one process's would; each keeps its own, the ghosts
 * its contacts reach, and the lists' entries that touch its own. */
int esf_par_resumed(esf_sim *s, esf_error *err);

/* Broadcasts rank 0's status and message to every process (after a step only rank 0
 * takes, as a file's write). */
int esf_par_bcast_status(const esf_sim *s, int rc, esf_error *err);

/* Exchange statistics since the start (collective). */
typedef struct esf_par_stat {
  double bytes, bytes_max; /* bytes this process sent; the most any process sent */
  double seconds_max;      /* the most seconds any process spent exchanging or waiting */
  long rebuilds;           /* rebuilds (cuts) */
  long long migrated;      /* particles that changed process, over all processes */
  long long own_max, ghosts_max; /* now: the most particles and ghosts a process holds */
} esf_par_stat;
void esf_par_stats(const esf_sim *s, esf_par_stat *st);

#endif
