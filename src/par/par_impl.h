/* par_impl.h — the MPI decomposition's state, shared by par.c, par_cut.c and par_io.c
 * (private to the module). Built only with ESF_MPI. */
#ifndef ESF_PAR_IMPL_H
#define ESF_PAR_IMPL_H

#ifdef ESF_MPI
#include <mpi.h>
#include <string.h>

#include "par/par.h"

/* One particle as it travels between processes. */
typedef struct esf_par_rec {
  int64_t id, gid; /* stable id; global index (the previous one while migrating) */
  uint32_t key;    /* cell key of the renumbering's grid */
  int32_t material;
  uint32_t pos, spare;    /* a received ghost's place in the arrival order */
  int32_t img[3], spare2; /* periodic image counters (periodic scenes) */
  double x[3], v[3], w[3];
  double radius, mass, inv_mass, inertia, inv_inertia;
} esf_par_rec;

/* Particle i of p into a record (global index gid, cell key), and a record into
 * particle i of p (its image counters when p has them): migration, ghosts, frames and
 * checkpoints all carry particles this way. */
static inline void esf_par_rec_of(const esf_particles *p, size_t i, int64_t gid,
                                  uint32_t key, esf_par_rec *r) {
  r->id = p->id[i];
  r->gid = gid;
  r->key = key;
  r->material = p->material[i];
  memcpy(r->x, p->x + 3 * i, sizeof r->x);
  memcpy(r->v, p->v + 3 * i, sizeof r->v);
  memcpy(r->w, p->w + 3 * i, sizeof r->w);
  r->radius = p->radius[i];
  r->mass = p->mass[i];
  r->inv_mass = p->inv_mass[i];
  r->inertia = p->inertia[i];
  r->inv_inertia = p->inv_inertia[i];
  if (p->img)
    memcpy(r->img, p->img + 3 * i, sizeof r->img);
  else
    memset(r->img, 0, sizeof r->img);
}

static inline void esf_par_rec_to(esf_particles *p, size_t i, const esf_par_rec *r) {
  if (p->img) memcpy(p->img + 3 * i, r->img, sizeof r->img);
  p->id[i] = r->id;
  p->material[i] = r->material;
  memcpy(p->x + 3 * i, r->x, sizeof r->x);
  memcpy(p->v + 3 * i, r->v, sizeof r->v);
  memcpy(p->w + 3 * i, r->w, sizeof r->w);
  p->radius[i] = r->radius;
  p->mass[i] = r->mass;
  p->inv_mass[i] = r->inv_mass;
  p->inertia[i] = r->inertia;
  p->inv_inertia[i] = r->inv_inertia;
}

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
