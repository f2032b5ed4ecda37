/* par.c — an MPI run's processes (par.h): attaching a sim, the ghosts' exchange every
 * step, agreement on failures, and the sums across processes in a fixed order.
 *
 * Ghosts: at each rebuild (par_cut.c) every process lists, per peer, the owned
 * particles the peer holds as ghosts and where the peer's ghosts land; each step
 * sends x, v, w of the first and receives those of the second (9 doubles a ghost).
 * Sums: the ledger's and the servo walls' blocks are whole on every process and
 * summed exactly (util/xsum.h), so each process's accumulators, added limb by limb by
 * MPI_Allreduce and rounded once, give one process's bits. Folds that one process
 * takes in order (the porosity grid's cells; the esf_reduce chain of the modules
 * below) are taken rank after rank: rank r continues the running value rank r - 1
 * passes on; the last rank's goes to every process. Counts are integers (exact in
 * any order). Failures: the lowest failing rank's status and message go to
 * every process, so all stop together with the same message. Without ESF_MPI every
 * function is the one-process case. */
#include "par/par.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/ledger.h"
#include "loads/drag.h"
#include "loads/porosity.h"
#include "loads/servo.h"
#include "util/xsum.h"
#include "par/par_impl.h"

void esf_par_world(int *rank, int *size) {
  *rank = 0;
  *size = 1;
#ifdef ESF_MPI
  int on = 0;
  MPI_Initialized(&on);
  if (on) {
    MPI_Comm_rank(MPI_COMM_WORLD, rank);
    MPI_Comm_size(MPI_COMM_WORLD, size);
  }
#endif
}

/* The places of what MPI runs refuse (docs/mpi.md#what-mpi-runs-support). */
const char *esf_par_refusal(const esf_sim *s, const char **key) {
  const esf_config *c = &s->cfg;
  struct {
    int on;
    const char *key, *why;
  } const no[] = {
      {strcmp(c->method, "leapfrog") != 0, "integrator.method",
       "the leapfrog only (the ODE methods and Verlet run on one process)"},
      {!c->fused, "integrator.fused", "the fused step only (integrator.fused: false)"},
      {!c->reorder, "search.reorder", "the renumbering is the global order's"},
      {s->insert != NULL, "particles", "insertion during the run"},
      {c->out_contacts, "output.contacts", "the contact network output"},
      {c->out_walls || c->n_stress > 0, "output.walls", "walls.csv and stress.csv"},
  };
  for (size_t k = 0; k < sizeof no / sizeof no[0]; k++)
    if (no[k].on) {
      *key = no[k].key;
      return no[k].why;
    }
  return NULL;
}

#ifndef ESF_MPI

int esf_par_attach(esf_sim *s, esf_error *err) {
  (void)err;
  s->par = NULL;
  return ESF_OK;
}
void esf_par_detach(esf_sim *s) { s->par = NULL; }
int esf_par_rank(const esf_sim *s) { return (void)s, 0; }
void esf_par_busy(esf_sim *s, int end) { (void)s, (void)end; }
int esf_par_size(const esf_sim *s) { return (void)s, 1; }
size_t esf_par_count(const esf_sim *s) { return s->p.n; }
int esf_par_ghosts(esf_sim *s, esf_error *err) { return (void)s, (void)err, ESF_OK; }
int esf_par_agree(esf_sim *s, int rc, esf_error *err) { return (void)s, (void)err, rc; }
int esf_par_any(const esf_sim *s, int flag) { return (void)s, flag != 0; }
long long esf_par_sum(const esf_sim *s, long long v) { return (void)s, v; }
void esf_par_ledger_step(esf_sim *s, const double *blocks, size_t nb) {
  esf_ledger_step(&s->led, blocks, nb);
}
void esf_par_servo(esf_sim *s) { esf_servo_update(s); }
void esf_par_adapt_damping(esf_sim *s, const double *blocks, size_t nb) {
  esf_sim_adapt_damping(s, blocks, nb);
}
size_t esf_par_touching(const esf_sim *s, size_t local) { return (void)s, local; }
int esf_par_agree_flag(esf_sim *s, int rc, int *flag, esf_error *err) {
  return (void)s, (void)flag, (void)err, rc;
}
int esf_par_bcast_status(const esf_sim *s, int rc, esf_error *err) {
  return (void)s, (void)err, rc;
}
void esf_par_stats(const esf_sim *s, esf_par_stat *st) {
  (void)s;
  memset(st, 0, sizeof *st);
}

#else

static int porosity(esf_sim *s, const double *x, esf_error *err);
static const esf_reduce reduce_ops;

int esf_par_attach(esf_sim *s, esf_error *err) {
  s->par = NULL;
  int rank, size;
  esf_par_world(&rank, &size);
  if (size < 2) return ESF_OK;
  const char *key = NULL, *why = esf_par_refusal(s, &key);
  if (why)
    return esf_fail(err, ESF_EINPUT,
                    "%s: not supported on several MPI processes yet: %s (run it on one "
                    "process, or without mpirun)",
                    esf_config_where(&s->cfg, key), why);
  esf_par *P = calloc(1, sizeof *P);
  int *st = calloc((size_t)size + 1, sizeof *st),
      *rt = calloc((size_t)size + 1, sizeof *rt);
  MPI_Request *rq = calloc(2 * (size_t)size, sizeof *rq);
  if (!P || !st || !rt || !rq) {
    free(P);
    free(st);
    free(rt);
    free(rq);
    return esf_fail(err, ESF_ENOMEM, "out of memory");
  }
  MPI_Comm_dup(MPI_COMM_WORLD, &P->comm);
  P->rank = rank;
  P->size = size;
  P->sstart = st;
  P->rstart = rt;
  P->req = rq;
  P->ntot = s->p.n;
  P->rate = 1.0;
  s->par = P;
  if (s->drag) s->drag->update_porosity = porosity;
  s->red = &reduce_ops;
  s->own_lo = 0; /* until the first rebuild: rank 0 owns every particle, the others */
  s->own_hi = rank == 0 ? s->p.n : 0; /* hold theirs only for the set-up's sake */
  return ESF_OK;
}

void esf_par_detach(esf_sim *s) {
  esf_par *P = s->par;
  s->red = NULL;
  if (!P) return;
  MPI_Comm_free(&P->comm);
  free(P->gid);
  free(P->sstart);
  free(P->rstart);
  free(P->sidx);
  free(P->ridx);
  free(P->sbuf);
  free(P->rbuf);
  free(P->req);
  free(P);
  s->par = NULL;
}

/* The reductions of core/sim.h's esf_reduce for the modules below par. */
static double chain_in(const esf_sim *s, double start) {
  const esf_par *P = s->par;
  double v = start;
  if (P->rank > 0)
    MPI_Recv(&v, 1, MPI_DOUBLE, P->rank - 1, 15, P->comm, MPI_STATUS_IGNORE);
  return v;
}

static double chain_out(const esf_sim *s, double v) {
  const esf_par *P = s->par;
  if (P->rank + 1 < P->size) MPI_Send(&v, 1, MPI_DOUBLE, P->rank + 1, 15, P->comm);
  MPI_Bcast(&v, 1, MPI_DOUBLE, P->size - 1, P->comm);
  return v;
}

static long long sum_ll(const esf_sim *s, long long v) { return esf_par_sum(s, v); }

/* Particles leaving the local arrays (an event's deletion): the own range and the
 * global indices follow; the ghosts' plan is remade at the rebuild that follows. */
static void compact(esf_sim *s, const unsigned char *keep) {
  esf_par *P = s->par;
  size_t m = 0, lo = 0, own = 0;
  for (size_t i = 0; i < s->p.n; i++) {
    if (!keep[i]) continue;
    if (i < s->own_lo) lo++;
    if (i >= s->own_lo && i < s->own_hi) own++;
    if (P->gid) P->gid[m] = P->gid[i];
    m++;
  }
  s->own_lo = lo;
  s->own_hi = lo + own;
}

static const esf_reduce reduce_ops = {chain_in, chain_out, sum_ll, compact};

int esf_par_rank(const esf_sim *s) { return s->par ? s->par->rank : 0; }

void esf_par_busy(esf_sim *s, int end) {
  esf_par *P = s->par;
  if (!P) return;
  if (!end) {
    P->busy_t0 = esf_par_now();
    P->busy_c0 = P->seconds;
  } else {
    P->busy += (esf_par_now() - P->busy_t0) - (P->seconds - P->busy_c0);
  }
}
int esf_par_size(const esf_sim *s) { return s->par ? s->par->size : 1; }
size_t esf_par_count(const esf_sim *s) { return s->par ? s->par->ntot : s->p.n; }

static int grow_d(double **p, size_t *cap, size_t n) {
  if (n <= *cap) return 1;
  double *q = realloc(*p, (n ? n : 1) * sizeof *q);
  if (!q) return 0;
  *p = q;
  *cap = n;
  return 1;
}

int esf_par_ghosts(esf_sim *s, esf_error *err) {
  esf_par *P = s->par;
  if (!P || !P->decomposed) return ESF_OK;
  const double t0 = esf_par_now();
  const size_t ns = (size_t)P->sstart[P->size], nr = (size_t)P->rstart[P->size];
  if (!grow_d(&P->sbuf, &P->sbuf_cap, 9 * ns) || !grow_d(&P->rbuf, &P->rbuf_cap, 9 * nr))
    return esf_fail(err, ESF_ENOMEM, "out of memory for the ghosts' exchange");
  const esf_particles *p = &s->p;
  for (size_t j = 0; j < ns; j++) {
    const size_t i = P->sidx[j];
    memcpy(P->sbuf + 9 * j, p->x + 3 * i, 3 * sizeof(double));
    memcpy(P->sbuf + 9 * j + 3, p->v + 3 * i, 3 * sizeof(double));
    memcpy(P->sbuf + 9 * j + 6, p->w + 3 * i, 3 * sizeof(double));
  }
  int nq = 0;
  for (int q = 0; q < P->size; q++) {
    const int c = P->rstart[q + 1] - P->rstart[q];
    if (c > 0)
      MPI_Irecv(P->rbuf + 9 * (size_t)P->rstart[q], 9 * c, MPI_DOUBLE, q, 11, P->comm,
                &P->req[nq++]);
  }
  for (int q = 0; q < P->size; q++) {
    const int c = P->sstart[q + 1] - P->sstart[q];
    if (c > 0)
      MPI_Isend(P->sbuf + 9 * (size_t)P->sstart[q], 9 * c, MPI_DOUBLE, q, 11, P->comm,
                &P->req[nq++]);
  }
  MPI_Waitall(nq, P->req, MPI_STATUSES_IGNORE);
  for (size_t j = 0; j < nr; j++) {
    const size_t i = P->ridx[j];
    memcpy(p->x + 3 * i, P->rbuf + 9 * j, 3 * sizeof(double));
    memcpy(p->v + 3 * i, P->rbuf + 9 * j + 3, 3 * sizeof(double));
    memcpy(p->w + 3 * i, P->rbuf + 9 * j + 6, 3 * sizeof(double));
  }
  P->bytes += 72.0 * (double)ns;
  P->seconds += esf_par_now() - t0;
  return ESF_OK;
}

/* The failing process's status and message to every process, the message prefixed
 * with its rank (out of memory, say, happens on one). */
static int share_failure(const esf_par *P, int first, int rc, esf_error *err) {
  int code = rc;
  MPI_Bcast(&code, 1, MPI_INT, first, P->comm);
  if (P->rank == first) esf_error_prefix(err, "(MPI process %d of %d) ", first, P->size);
  MPI_Bcast(err->msg, (int)sizeof err->msg, MPI_CHAR, first, P->comm);
  err->code = code;
  return code;
}

int esf_par_agree(esf_sim *s, int rc, esf_error *err) {
  const esf_par *P = s->par;
  if (!P) return rc;
  int mine = rc ? P->rank : P->size, first = P->size;
  MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, P->comm);
  if (first == P->size) return ESF_OK;
  return share_failure(P, first, rc, err);
}

int esf_par_bcast_status(const esf_sim *s, int rc, esf_error *err) {
  const esf_par *P = s->par;
  if (!P) return rc;
  MPI_Bcast(&rc, 1, MPI_INT, 0, P->comm);
  if (rc) {
    MPI_Bcast(err->msg, (int)sizeof err->msg, MPI_CHAR, 0, P->comm);
    err->code = rc;
  }
  return rc;
}

int esf_par_any(const esf_sim *s, int flag) {
  if (!s->par) return flag != 0;
  int in = flag != 0, out = 0;
  MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LOR, s->par->comm);
  return out;
}

long long esf_par_sum(const esf_sim *s, long long v) {
  if (!s->par) return v;
  long long out = 0;
  MPI_Allreduce(&v, &out, 1, MPI_LONG_LONG, MPI_SUM, s->par->comm);
  return out;
}

/* t[0 .. m) = the exact sums of m accumulators over every process (util/xsum.h:
 * normalised, their integer limbs added by MPI, rounded once): one process's bits. */
static void exact_sums(esf_par *P, esf_xsum *acc, double *t, int m) {
  const double t0 = esf_par_now();
  for (int c = 0; c < m; c++) esf_xsum_normalize(&acc[c]);
  MPI_Allreduce(MPI_IN_PLACE, acc, m * ESF_XSUM_WORDS, MPI_INT64_T, MPI_SUM, P->comm);
  for (int c = 0; c < m; c++) t[c] = esf_xsum_value(&acc[c]);
  P->bytes += (double)m * sizeof *acc;
  P->seconds += esf_par_now() - t0;
}

void esf_par_ledger_step(esf_sim *s, const double *blocks, size_t nb) {
  esf_par *P = s->par;
  if (!P) {
    esf_ledger_step(&s->led, blocks, nb);
    return;
  }
  esf_xsum acc[ESF_LB_N];
  double t[ESF_LB_N];
  for (int c = 0; c < ESF_LB_N; c++) esf_xsum_zero(&acc[c]);
  esf_ledger_block_sums(blocks, nb, acc); /* this process's blocks */
  exact_sums(P, acc, t, ESF_LB_N);
  esf_ledger_step_sums(&s->led, t);
}

/* The fluid force's porosity grid (loads/porosity.h) over every process: the global
 * box; the cells' solid volumes added in the global order (rank after rank, as one
 * process's loop); the fractions. */
static int porosity(esf_sim *s, const double *x, esf_error *err) {
  esf_par *P = s->par;
  esf_porosity_grid *g = &s->drag->pg;
  const esf_particles *p = &s->p;
  double lh[6], gl[6];
  esf_porosity_box(p, x, s->own_lo, s->own_hi, lh, lh + 3);
  for (int k = 3; k < 6; k++) lh[k] = -lh[k];
  MPI_Allreduce(lh, gl, 6, MPI_DOUBLE, MPI_MIN, P->comm);
  const double hi[3] = {-gl[3], -gl[4], -gl[5]};
  const int rc =
      esf_porosity_cells(g, gl, hi, P->ntot > 0, s->cfg.dim, s->cfg.disk_thickness, err);
  if (esf_par_agree(s, rc, err)) return err->code;
  const double t0 = esf_par_now();
  const int m = (int)g->ncell;
  if (P->rank > 0)
    MPI_Recv(g->eps, m, MPI_DOUBLE, P->rank - 1, 14, P->comm, MPI_STATUS_IGNORE);
  esf_porosity_add(g, p, x, s->own_lo, s->own_hi, s->cfg.dim, s->cfg.disk_thickness);
  if (P->rank + 1 < P->size) MPI_Send(g->eps, m, MPI_DOUBLE, P->rank + 1, 14, P->comm);
  MPI_Bcast(g->eps, m, MPI_DOUBLE, P->size - 1, P->comm);
  P->seconds += esf_par_now() - t0;
  esf_porosity_finish(g);
  return ESF_OK;
}

void esf_par_adapt_damping(esf_sim *s, const double *blocks, size_t nb) {
  esf_par *P = s->par;
  if (!P) {
    esf_sim_adapt_damping(s, blocks, nb);
    return;
  }
  esf_xsum acc[2];
  double ke[2];
  esf_xsum_zero(&acc[0]);
  esf_xsum_zero(&acc[1]);
  esf_sim_damping_sums(blocks, nb, acc);
  exact_sums(P, acc, ke, 2);
  esf_sim_damping_apply(s, ke[0], ke[1]);
}

void esf_par_servo(esf_sim *s) {
  esf_par *P = s->par;
  if (!P) {
    esf_servo_update(s);
    return;
  }
  esf_walls *w = &s->walls;
  const int m = 4 * w->ngroups;
  esf_xsum *acc = malloc((size_t)m * sizeof *acc);
  int ok = acc != NULL, all = 0;
  MPI_Allreduce(&ok, &all, 1, MPI_INT, MPI_LAND, P->comm);
  if (all) {
    for (int q = 0; q < m; q++) esf_xsum_zero(&acc[q]);
    esf_servo_block_sums(s, acc); /* this process's blocks */
    exact_sums(P, acc, w->gforce, m);
  } else { /* (a few KB): the non-finite forces stop every process at the next check */
    for (int q = 0; q < m; q++) w->gforce[q] = NAN;
  }
  free(acc);
  esf_servo_control(s);
}

/* The first entry of a list sorted by a whose a is at least i. */
static size_t first_a(const esf_candidates *c, size_t i) {
  size_t lo = 0, hi = c->n;
  while (lo < hi) {
    const size_t m = lo + (hi - lo) / 2;
    if (c->a[m] < i)
      lo = m + 1;
    else
      hi = m;
  }
  return lo;
}

size_t esf_par_touching(const esf_sim *s, size_t local) {
  if (!s->par) return local;
  size_t m = 0;
  const esf_candidates *lists[2] = {&s->nb.pp, &s->nb.pw};
  for (int l = 0; l < 2; l++) {
    const esf_candidates *c = lists[l];
    const size_t k1 = first_a(c, s->own_hi);
    for (size_t k = first_a(c, s->own_lo); k < k1; k++) m += c->touch[k];
  }
  return m;
}

int esf_par_agree_flag(esf_sim *s, int rc, int *flag, esf_error *err) {
  const esf_par *P = s->par;
  if (!P) return rc;
  int mine[2] = {rc ? P->rank : P->size, *flag ? 0 : 1}, all[2];
  MPI_Allreduce(mine, all, 2, MPI_INT, MPI_MIN, P->comm);
  *flag = all[1] == 0;
  if (all[0] == P->size) return ESF_OK;
  return share_failure(P, all[0], rc, err);
}

void esf_par_stats(const esf_sim *s, esf_par_stat *st) {
  memset(st, 0, sizeof *st);
  const esf_par *P = s->par;
  if (!P) return;
  double mine[2] = {P->bytes, P->seconds}, most[2];
  MPI_Allreduce(mine, most, 2, MPI_DOUBLE, MPI_MAX, P->comm);
  st->bytes = P->bytes;
  st->bytes_max = most[0];
  st->seconds_max = most[1];
  st->rebuilds = P->rebuilds;
  st->migrated = esf_par_sum(s, P->migrated);
  long long mine2[2] = {(long long)(s->own_hi - s->own_lo),
                        (long long)(s->p.n - (s->own_hi - s->own_lo))},
            max2[2];
  MPI_Allreduce(mine2, max2, 2, MPI_LONG_LONG, MPI_MAX, P->comm);
  st->own_max = max2[0];
  st->ghosts_max = max2[1];
}

#endif
