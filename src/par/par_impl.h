/* par_impl.h — the MPI decomposition's state, shared by par.c, par_cut.c and par_io.c
 * (private to the module). Built only with ESF_MPI. */
#ifndef ESF_PAR_IMPL_H
#define ESF_PAR_IMPL_H

#ifdef ESF_MPI
#include <mpi.h>

#include "par/par.h"

/* One particle as it travels between processes. */
typedef struct esf_par_rec {
  int64_t id, gid; /* stable id; global index (the previous one while migrating) */
  uint32_t key;    /* cell key of the renumbering's grid */
  int32_t material;
  uint32_t pos, spare; /* a received ghost's place in the arrival order */
  int32_t img[3], spare2; /* periodic image counters (periodic scenes) */
  double x[3], v[3], w[3];
  double radius, mass, inv_mass, inertia, inv_inertia;
} esf_par_rec;

/* One touching contact of a migrating particle: particle pair (id_a, id_b) in the
 * list's orientation, or particle id_a and wall element b (wall = 1). */
typedef struct esf_par_contact {
  int64_t id_a, id_b;
  int32_t wall, has_roll;
  esf_contact_hist h;
  esf_contact_roll roll;
  esf_contact_bond bond; /* zero without bonds */
} esf_par_contact;

struct esf_par {
  MPI_Comm comm;
  int rank, size;
  int decomposed; /* the first rebuild has cut the particles among the processes */
  int empty_said; /* the log said that some process owns no particles */
  int64_t *gid;   /* n: each local particle's global index (owned and ghosts) */
  size_t gid_cap;
  size_t g0, ntot; /* global index of the first owned particle; the run's count */
  /* the ghosts' exchange: per peer, the owned particles sent (sidx[sstart[q] ..]) and
     the ghosts received (ridx[rstart[q] ..]), local indices */
  int *sstart, *rstart; /* size + 1 each */
  uint32_t *sidx, *ridx;
  double *sbuf, *rbuf;
  size_t sbuf_cap, rbuf_cap;
  MPI_Request *req;
  double busy; /* seconds this process computed steps since the last cut (the balance) */
  double rate; /* the work one of its particles counts for at the cut (1 at first) */
  double busy_t0, busy_c0; /* the current step's start, and the exchanges' seconds then */
  /* statistics */
  double bytes, seconds;
  long rebuilds, migrated; /* rebuilds; particles this process sent away */
};

/* The exchange's wall clock. */
static inline double esf_par_now(void) { return MPI_Wtime(); }

#endif
#endif
