/* par_io.c — an MPI run's particles gathered on rank 0 for its frames (par.h).
 *
 * Rank 0 writes frames.h5 alone, through the same writer as one process
 * (output/frames.c, which orders particles by id): every process sends its owned
 * particles (id, material, x, v, w, F, radius: 120 bytes each) and rank 0 receives them
 * rank after rank, the global order. Parallel HDF5 would spare rank 0 the memory of
 * one frame's particles; docs/mpi.md gives the measured cost of the gather.
 * Entry: p.f current (esf_sim_forces_sync). */
#include <stdlib.h>
#include <string.h>

#include "par/par.h"

#ifdef ESF_MPI
#include "par/par_impl.h"

typedef struct out_rec {
  int64_t id;
  int32_t material, spare;
  double x[3], v[3], w[3], f[3], radius;
} out_rec;

int esf_par_gather(esf_sim *s, esf_particles *all, esf_error *err) {
  memset(all, 0, sizeof *all);
  esf_par *P = s->par;
  if (!P) return esf_fail(err, ESF_EINTERNAL, "esf_par_gather without MPI");
  const double t0 = esf_par_now();
  const esf_particles *p = &s->p;
  const size_t lo = s->own_lo, n = s->own_hi - s->own_lo;
  out_rec *mine = malloc((n ? n : 1) * sizeof *mine);
  int *cnt = P->rank == 0 ? malloc(2 * (size_t)P->size * sizeof *cnt) : NULL;
  int rc =
      mine && (P->rank != 0 || cnt) ? ESF_OK : esf_fail(err, ESF_ENOMEM, "out of memory");
  for (size_t j = 0; !rc && j < n; j++) {
    const size_t i = lo + j;
    out_rec *r = &mine[j];
    r->id = p->id[i];
    r->material = p->material[i];
    r->spare = 0;
    memcpy(r->x, p->x + 3 * i, sizeof r->x);
    memcpy(r->v, p->v + 3 * i, sizeof r->v);
    memcpy(r->w, p->w + 3 * i, sizeof r->w);
    if (p->f)
      memcpy(r->f, p->f + 3 * i, sizeof r->f);
    else
      memset(r->f, 0, sizeof r->f);
    r->radius = p->radius[i];
  }
  int mb = (int)(n * sizeof *mine);
  MPI_Gather(&mb, 1, MPI_INT, cnt, 1, MPI_INT, 0, P->comm);
  out_rec *got = NULL;
  size_t tot = 0;
  if (P->rank == 0 && cnt) {
    int *dsp = cnt + P->size;
    for (int q = 0; q < P->size; q++) {
      dsp[q] = (int)tot;
      tot += (size_t)cnt[q];
    }
    got = malloc(tot ? tot : 1);
    if (!got && !rc) rc = esf_fail(err, ESF_ENOMEM, "out of memory for a frame");
  }
  /* a process without memory still takes part, sending nothing */
  MPI_Gatherv(mine, rc ? 0 : mb, MPI_BYTE, got, cnt, cnt ? cnt + P->size : NULL, MPI_BYTE,
              0, P->comm);
  const size_t m = tot / sizeof(out_rec);
  if (!rc && P->rank == 0) rc = esf_particles_alloc(all, m, err);
  for (size_t k = 0; !rc && P->rank == 0 && k < m; k++) {
    const out_rec *r = &got[k];
    all->id[k] = r->id;
    all->material[k] = r->material;
    memcpy(all->x + 3 * k, r->x, sizeof r->x);
    memcpy(all->v + 3 * k, r->v, sizeof r->v);
    memcpy(all->w + 3 * k, r->w, sizeof r->w);
    memcpy(all->f + 3 * k, r->f, sizeof r->f);
    all->radius[k] = r->radius;
  }
  free(mine);
  free(cnt);
  free(got);
  P->bytes += (double)n * sizeof(out_rec);
  P->seconds += esf_par_now() - t0;
  return rc;
}

#else

int esf_par_gather(esf_sim *s, esf_particles *all, esf_error *err) {
  (void)s;
  memset(all, 0, sizeof *all);
  return esf_fail(err, ESF_EINTERNAL, "esf_par_gather without MPI");
}

#endif
