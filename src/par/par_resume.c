/* par_resume.c — a checkpoint's restore cut among an MPI run's processes (par.h:
 * esf_par_resumed).
 *
 * Every process has restored the whole run as one process held it: particles in the
 * global order of the last renumbering, the candidate lists with their histories,
 * the lists' reference positions. The order is cut in place, at multiples of
 * ESF_LEDGER_BLOCK near equal counts (the first rebuild re-cuts on measured time);
 * each process keeps its own particles and, as ghosts, every partner of theirs in the
 * pair list (the particles a candidate pair of its own reaches), compacted in the same
 * order, with the lists renumbered and the reference positions kept, so that the next
 * rebuild comes when one process's would and the run goes on bit for bit. The ghosts'
 * exchange plan: each process asks the owners for its ghosts by global index. */
#include <stdlib.h>
#include <string.h>

#include "par/par.h"

#ifdef ESF_MPI
#include "core/ledger.h"
#include "par/par_impl.h"

int esf_par_resumed(esf_sim *s, esf_error *err) {
  esf_par *P = s->par;
  if (!P) return ESF_OK;
  esf_particles *p = &s->p;
  const int K = P->size, me = P->rank;
  const size_t n = p->n, B = ESF_LEDGER_BLOCK;
  size_t *cut = malloc(((size_t)K + 1) * sizeof *cut);
  unsigned char *need = calloc(n ? n : 1, 1);
  size_t *remap = malloc((n ? n : 1) * sizeof *remap);
  double *xr =
      s->nb.xref && s->nb.nref == n ? malloc((n ? n : 1) * 3 * sizeof *xr) : NULL;
  int *cnt = calloc(4 * (size_t)K, sizeof *cnt);
  int64_t *ask = NULL, *got = NULL;
  int rc = ESF_OK;
  if (!cut || !need || !remap || !cnt || (s->nb.xref && s->nb.nref == n && !xr)) {
    rc = esf_fail(err, ESF_ENOMEM, "out of memory resuming %zu particles", n);
    goto done;
  }
  cut[0] = 0; /* the current order cut at multiples of ESF_LEDGER_BLOCK */
  cut[K] = n;
  for (int r = 1; r < K; r++) {
    const size_t c = ((size_t)r * n / (size_t)K + B / 2) / B * B;
    cut[r] = c < cut[r - 1] ? cut[r - 1] : c > n ? n : c;
  }
  const size_t g0 = cut[me], g1 = cut[me + 1];
  for (size_t i = g0; i < g1; i++) need[i] = 1;
  const esf_candidates *pp = &s->nb.pp;
  for (size_t k = 0; k < pp->n; k++) { /* every partner of an own particle */
    const size_t a = pp->a[k], b = pp->b[k];
    if (a >= g0 && a < g1) need[b] = 1;
    if (b >= g0 && b < g1) need[a] = 1;
  }
  if (xr) memcpy(xr, s->nb.xref, n * 3 * sizeof *xr);
  if ((rc = esf_sim_forces_sync(s, err))) goto done;
  if ((rc = esf_particles_compact(p, need, remap, err))) goto done;
  esf_neighbor_remap(&s->nb, remap, n); /* (drops xref: put back below) */
  free(P->gid);
  P->gid = malloc((p->n ? p->n : 1) * sizeof *P->gid);
  if (!P->gid) {
    rc = esf_fail(err, ESF_ENOMEM, "out of memory");
    goto done;
  }
  size_t below = 0;
  for (size_t i = 0; i < n; i++) {
    if (!need[i]) continue;
    P->gid[remap[i]] = (int64_t)i;
    below += i < g0;
  }
  if (xr) {
    for (size_t i = 0; i < n; i++)
      if (need[i]) memcpy(xr + 3 * remap[i], xr + 3 * i, 3 * sizeof *xr); /* i >= new */
    s->nb.xref = xr;
    s->nb.nref = p->n;
    xr = NULL;
  }
  s->own_lo = below;
  s->own_hi = below + (g1 - g0);
  /* the ghosts' exchange: each asks the owners for its ghosts, by global index */
  int *co = cnt, *ci = cnt + K, *dso = cnt + 2 * K, *dsi = cnt + 3 * K;
  for (size_t i = 0; i < p->n; i++) {
    if (i >= s->own_lo && i < s->own_hi) continue;
    int q = 0;
    while (q + 1 < K && cut[q + 1] <= (size_t)P->gid[i]) q++;
    co[q]++;
  }
  MPI_Alltoall(co, 1, MPI_INT, ci, 1, MPI_INT, P->comm);
  size_t no = 0, ni = 0;
  for (int q = 0; q < K; q++) {
    dso[q] = (int)no;
    dsi[q] = (int)ni;
    no += (size_t)co[q];
    ni += (size_t)ci[q];
  }
  ask = malloc((no ? no : 1) * sizeof *ask);
  got = malloc((ni ? ni : 1) * sizeof *got);
  P->ridx = realloc(P->ridx, (no ? no : 1) * sizeof *P->ridx);
  P->sidx = realloc(P->sidx, (ni ? ni : 1) * sizeof *P->sidx);
  if (!ask || !got || !P->ridx || !P->sidx) {
    rc = esf_fail(err, ESF_ENOMEM, "out of memory for the ghosts' exchange");
    goto done;
  }
  for (size_t i = 0, t = 0; i < p->n; i++) /* ascending: by owner, as the counts */
    if (i < s->own_lo || i >= s->own_hi) {
      ask[t] = P->gid[i];
      P->ridx[t++] = (uint32_t)i;
    }
  MPI_Alltoallv(ask, co, dso, MPI_INT64_T, got, ci, dsi, MPI_INT64_T, P->comm);
  for (size_t j = 0; j < ni; j++)
    P->sidx[j] = (uint32_t)(s->own_lo + (size_t)(got[j] - (int64_t)g0));
  P->sstart[0] = P->rstart[0] = 0;
  for (int q = 0; q < K; q++) {
    P->sstart[q + 1] = P->sstart[q] + ci[q];
    P->rstart[q + 1] = P->rstart[q] + co[q];
  }
  P->g0 = g0;
  P->ntot = n;
  P->decomposed = 1;
  if (me != 0) { /* each process counts its own from here */
    s->contacts_sum = 0.0;
    s->bonds.broken = 0;
  }
done:
  free(cut);
  free(need);
  free(remap);
  free(xr);
  free(cnt);
  free(ask);
  free(got);
  return rc;
}
#else

int esf_par_resumed(esf_sim *s, esf_error *err) { return (void)s, (void)err, ESF_OK; }

#endif
