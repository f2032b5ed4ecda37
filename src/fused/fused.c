/* step_fast.c — the fused, threaded leapfrog step (step_fast.h).
 *
 * Physics: exactly the leapfrog of integrators/leapfrog.c (000 3-6..3-8, 004 2.38–2.47,
 * 001 3.50–3.54) with the linear law of contact_linear.c (PHYSICS.md §3.1–3.2: normal
 * spring and dashpot without tension, incremental tangential spring carried into the
 * new contact plane, tangential dashpot while sticking, Mohr-Coulomb cap with radial
 * return), written out for the pair loop without the ledger's by-products, eight pairs
 * at a time in vector lanes (pair_batch.c).
 *
 * Order of operations in one step (state on entry: x_n, v_{n-1/2}, w_{n-1/2}, lists
 * valid for x_n, history at t_{n-1}). The particles are split into T contiguous
 * ranges, one per thread; as the pair list is sorted by (a, b) with a < b, the pairs
 * whose a lies in range t form one block of k. A pair whose b lies in a higher range
 * is a boundary pair. Steps are numbered by an epoch (f->epoch counts them).
 *   0. at a call's start, after a list rebuild (or a new T, or when the ranges'
 *      measured times came out unequal: balance_check): the ranges (cut by estimated
 *      work, scaled by the measured time per unit of work of the old ranges when
 *      re-cut), their pair blocks, the wall candidates of each particle, the boundary
 *      pairs, each pair's sqrt(m*) for the dashpots, and whether all particles have
 *      one material (its pair parameters are then broadcast to the batches' lanes
 *      instead of gathered);
 *   1. each thread, for its own range t (at a call's first step it sorts its interior
 *      pairs, both ends in the range, into contacts and idle candidates by their touch
 *      flags, range_lists; ranges above 0 screen first, step 2's screening: it reads
 *      only the range's own particles and writes nothing shared):
 *      from a call's second step on, waits for its word: range 0 waits until every
 *      range has finished the step before (done flags), gathers their results and
 *      decides, as the driver would between calls, whether this step is taken
 *      (burst_decide: not after a failure, a non-finite position or a particle out of
 *      the domain, nor when the lists need a rebuild or the ranges a re-cut); the
 *      others wait for that word and for the higher ranges' done flags (their
 *      particles have drifted). Then it computes the touching boundary pairs whose a is
 *      in the range, in batches, into their slots (force on A and torque on B for b's
 *      range, by non-temporal stores, fenced; force and torque on A kept apart for its
 *      own; zeroed when the contact ends), committing their history, and raises its
 *      ready flag: range t no longer reads the higher ranges' particles;
 *   2. then: screens its idle candidates for overlapping spheres (range 0; the others
 *      did it in step 1) into a list of new contacts; waits for the lower ranges' ready
 *      flags (this one-way handoff replaces a barrier of all threads); merges the new
 *      contacts into the contacts of the step before (ascending k); sets its
 *      four-wide accumulators to f = m g,
 *      t = 0 (each just ahead of its first use, in ascending particle order, so that
 *      the add into a pair's b finds the line in cache); subtracts the incoming
 *      boundary slots (pairs whose b is its particle) in ascending k; computes the
 *      merged pairs in batches of eight, in ascending k, adding their forces to both
 *      particles and, between them in k order, the A side of its outgoing boundary
 *      slots (a contact whose spheres no longer overlap, by the screening's own test,
 *      adds nothing: the batch clears its flag, and it goes back to the idle
 *      candidates, as the new contacts leave them); then the wall contacts of its
 * particles that have wall candidates, in ascending order (the pass of wall_fast.h: each
 * reads and adds to its own particle only, so doing them all before the kicks changes no
 * operation); then, particle by particle: the 2D projection (the accumulators then hold
 * F_n, M_n: they stay there, s->ft_lazy, for esf_sim_forces_sync), local damping, kick
 * with global damping (1 -+ alpha dt/2), drift x += v dt, the squared displacement since
 * the last build and whether it left the domain (without damping, in 3D, a loop the
 * compiler vectorises over particles); last, its results and its done flag. A wall
 * overlap failure leaves the range unkicked, as a pair failure does. Once the lower ready
 * flags are up no thread reads range t's particles (an interior pair has both ends in one
 * range; the boundary pairs were done before the flags), so it drifts its range as soon
 * as it is done. A call takes up to nmax steps this way in one parallel region: no
 * barrier of all threads between steps, and a range that finished early screens its next
 * step while the others catch up. After the region the master gathers the last step's
 * results. Every particle receives its pair forces in ascending k, the order of the
 * serial scatter in forces.c, whatever T: the results are the same bit for bit on any
 * thread count (and T = 1 is a plain serial scatter without slots). Failures (overlap
 * beyond the limit) are reported for the lowest pair or particle index, also independent
 * of threads (every range computes all its pairs, failing or not); the failing pair's
 * particles keep x_n, so the message reports the overlap the step saw: a range with a
 * failing pair does not move, nor does any range above a failing boundary pair
 * (bfail, seen with the lower flags). Units: SI.
 */
#include "fused/fused.h"

#include <math.h>
#include <sched.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif
#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "model/forces.h"
#include "util/lines.h"
#include "fused/pair_batch.h"
#include "util/vec4.h"
#include "util/vec3.h"
#include "fused/wall_fast.h"

#define ACC ESF_FT_STRIDE /* the accumulators' stride: four-wide force and torque */
/* A boundary pair's results, twice: what b's range reads (force on A, torque on B),
 * one line per pair in `slot`, and what a's range reads (force and torque on A) in
 * `slot_a`, which stays in a's core. Four doubles each, the last zero. */
#define SLOT   8  /* per pair in slot: force on A, torque on B */
#define SLOT_A 8  /* per pair in slot_a: force on A, torque on A */
#define PF     32 /* history prefetch distance, pairs */
/* idle candidates range 0 screens between looks at the others */
#define SCREEN_CHUNK 256

_Static_assert(ACC == ESF_BATCH_ACC, "pair_batch.h adds into the accumulators' layout");
_Static_assert(
    SLOT * sizeof(double) == ESF_LINE && ESF_BATCH_OUT == 12,
    "slot_put stores a slot as one line: the rows 0-3 and 8-11 of the batch's");

/* One range's results of a step. */
typedef struct step_out {
  size_t nt; /* touching contacts: pairs whose a is in it, wall contacts */
  size_t bad_pair, bad_part; /* lowest failing pair, particle, or SIZE_MAX */
  double max2;               /* largest squared displacement since the build, m^2 */
  int nonfinite, escaped;
} step_out;

/* One range's flags and the results of its latest step, a cache line of its own:
 * written by its thread, read by the others once the flag they wait for is up. */
typedef struct range_rec {
  _Alignas(ESF_LINE) _Atomic long ready; /* boundary pairs done for this step (epoch) */
  _Atomic long done;                     /* the whole step done, out written */
  step_out out;
} range_rec;

struct esf_step_fast {
  long built;        /* nb.builds the indices below belong to (-1: none) */
  size_t np;         /* particles the indices were made for */
  int nth;           /* ranges (threads) the split was made for */
  size_t cap_k;      /* pair capacity */
  size_t cap_n;      /* particle capacity */
  double *acc;       /* ACC per particle: force (3, N), 0, torque (3, N m), 0 */
  uint32_t *list[2]; /* per pair, two buffers (range_lists): in each block, the
                        touching interior pairs, the batches' sequence, the new
                        contacts and the ended ones */
  uint32_t *idle;    /* per pair: each block's interior pairs not touching */
  double *sm;        /* per pair: sqrt(m*), kg^1/2 (dashpots c = factor sqrt(m*)) */
  size_t *astart;    /* n+1: pairs k in [astart[i], astart[i+1]) have a == i */
  size_t *wstart;    /* n+1: wall candidates of particle i */
  size_t nb, cap_b;  /* boundary pairs */
  uint32_t *bk;      /* their pair indices, ascending */
  double *slot;      /* SLOT per boundary pair, zero when not touching; line-aligned */
  double *slot_a;    /* SLOT_A per boundary pair, zero when not touching */
  size_t *bout;      /* nth+1: bk[bout[t] .. bout[t+1]) have a in range t */
  uint32_t *bin;     /* boundary ordinals by the range of b, ascending within */
  size_t *binstart;  /* nth+1 */
  size_t *rlo;       /* nth+1: the particle ranges (cut_ranges) */
  int32_t m0;        /* the material every particle has, or -1 (pair_batch.h's one) */
  /* balance (balance_check): step 2's seconds per range since the cut, the estimated
   * work of each range, and, when a re-cut is due, seconds per unit of work */
  double *busy, *work, *rate;
  long busy_steps;
  range_rec *rr; /* nth, line-aligned */
  long epoch;    /* steps run by esf_step_fast_run */
  double t_left; /* when the last call's threads finished (omp_get_wtime), or 0 */
  double t_step; /* how long its parallel part took per step, s */
  int recut;
  /* a burst's outcome, written by range 0 (burst_decide) */
  long taken;    /* steps completed */
  int decided;   /* the last one's results were gathered (the burst stopped early) */
  size_t nt_sum; /* touching contacts summed over the gathered steps */
  /* range 0's word to the others, a line apart from the fields above: go = 2 e to take
   * step e, 2 e + 1 to stop before it; bfail = e: a boundary pair failed in step e */
  _Alignas(ESF_LINE) _Atomic long go;
  _Atomic long bfail;
};

int esf_step_fast_create(esf_step_fast **out, esf_error *err) {
  *out = esf_lines_realloc(NULL, 0, sizeof **out); /* go: a line of its own */
  if (!*out) return esf_fail(err, ESF_ENOMEM, "out of memory");
  memset(*out, 0, sizeof **out);
  (*out)->built = -1;
  return ESF_OK;
}

void esf_step_fast_free(esf_step_fast **f) {
  if (!f || !*f) return;
  esf_step_fast *q = *f;
  free(q->list[0]);
  free(q->list[1]);
  free(q->idle);
  free(q->sm);
  free(q->astart);
  free(q->wstart);
  free(q->acc);
  free(q->bk);
  free(q->slot);
  free(q->slot_a);
  free(q->bout);
  free(q->bin);
  free(q->binstart);
  free(q->rlo);
  free(q->busy);
  free(q->work);
  free(q->rate);
  free(q->rr);
  free(q);
  *f = NULL;
}

/* The features a scene may switch on, compiled in or (ESF_MINIMAL: meson -Dfeatures=
 * minimal) out of the fused step; a build without them sends the scenes that use them
 * to the general path. */
#ifdef ESF_MINIMAL
#define HAS_FEATURES 0
#else
#define HAS_FEATURES 1
#endif

static int minimal_ok(const esf_sim *s) {
  return !s->mats.any_cohesion && s->cfg.tframe == ESF_TFRAME_ROTATE && s->cfg.dim == 3 &&
         !s->local && s->alpha_r == 0.0 && s->alpha_t == 0.0 && !s->walls.moving;
}

int esf_step_fast_eligible(const esf_sim *s) {
  return s->cfg.fused && !s->led.on && !s->cfg.autod.on && !s->tally &&
         s->mats.particles_linear && !s->nb.pp.vc0 && !s->nb.pp.xs && !s->nb.pw.xs &&
         (HAS_FEATURES || minimal_ok(s)) && !s->walls.gforce &&
         !s->drag; /* servo walls, fluid force: general path */
}

static int grow(void **p, size_t n, size_t size) {
  void *q = realloc(*p, (n ? n : 1) * size);
  if (!q) return 0;
  *p = q;
  return 1;
}

/* Estimated work of the step per particle, in units of one screened candidate (about
 * 33 instructions): 2 for the kick, 1 per candidate pair, 5 more per touching one
 * (computing and adding it), 6 per wall candidate. */
enum { W_PART = 2, W_CAND = 1, W_TOUCH = 5, W_WALL = 6 };

static size_t work_of(const esf_step_fast *f, const esf_contacts *c, size_t i) {
  size_t w = W_PART + W_WALL * (f->wstart[i + 1] - f->wstart[i]);
  for (size_t k = f->astart[i]; k < f->astart[i + 1]; k++)
    w += W_CAND + W_TOUCH * c->touch[k];
  return w;
}

/* The particle ranges, rlo[t] .. rlo[t + 1] for thread t, cut where the estimated
 * work of steps 1-2 (wt, per particle) is shared equally, so threads finish together
 * although a bed's bottom has more contacts than its surface. Any cut gives the same
 * results. */
static void cut_once(esf_step_fast *f, const size_t *wt, size_t n, size_t T) {
  size_t total = 0;
  for (size_t i = 0; i < n; i++) total += wt[i];
  size_t i = 0, acc = 0;
  f->rlo[0] = 0;
  for (size_t t = 1; t < T; t++) {
    const size_t goal = total / T * t + total % T * t / T;
    while (i < n && acc < goal) acc += wt[i++];
    f->rlo[t] = i;
  }
  f->rlo[T] = n;
}

/* With f->recut (same particles and lists, ranges measured unequal), each particle's
 * work is scaled by its old range's measured seconds per unit (rounded to 1/64).
 * wt: 2n of scratch, the weights cut by, then each particle's unscaled work. */
static void cut_ranges(esf_step_fast *f, const esf_contacts *c, size_t *wt, size_t n,
                       size_t T) {
  size_t *base = wt + n;
  for (size_t i = 0; i < n; i++) wt[i] = base[i] = work_of(f, c, i);
  if (f->recut) {
    double mean = 0.0;
    for (size_t t = 0; t < T; t++) mean += f->rate[t] / (double)T;
    for (size_t t = 0; t < T && mean > 0; t++) {
      const size_t q = (size_t)(64.0 * f->rate[t] / mean + 0.5);
      for (size_t i = f->rlo[t]; i < f->rlo[t + 1]; i++) wt[i] *= q;
    }
  }
  cut_once(f, wt, n, T);
  for (size_t t = 0; t < T; t++) { /* unscaled: the next rates are the ranges' own */
    f->work[t] = 0.0;
    for (size_t i = f->rlo[t]; i < f->rlo[t + 1]; i++) f->work[t] += (double)base[i];
    f->busy[t] = 0.0;
  }
  f->busy_steps = 0;
  f->recut = 0;
}

/* After every 32 steps on the same cut: when the slowest range took more than 2%
 * longer than the mean, the next step cuts again with the measured rates. Range 0's
 * time includes the serial work between steps (the driver's, the list check): its
 * thread, the master, does that work while the others wait. */
static void balance_check(esf_step_fast *f, size_t T) {
  if (T < 2 || ++f->busy_steps < 32) return;
  double mean = 0.0, worst = 0.0;
  for (size_t t = 0; t < T; t++) {
    mean += f->busy[t] / (double)T;
    worst = f->busy[t] > worst ? f->busy[t] : worst;
  }
  if (worst > 1.02 * mean && mean > 0) {
    for (size_t t = 0; t < T; t++)
      f->rate[t] = f->work[t] > 0 ? f->busy[t] / f->work[t] : 0.0;
    f->recut = 1;
  } else {
    for (size_t t = 0; t < T; t++) f->busy[t] = 0.0;
    f->busy_steps = 0;
  }
}

/* Step 0's part that depends on the lists only (not redone for a re-cut): each
 * particle's pair block and wall candidates, each pair's sqrt(m*), the one material. */
static void index_pairs(esf_sim *s, esf_step_fast *f, int nth) {
  const esf_particles *p = &s->p;
  const esf_contacts *c = &s->nb.pp, *cw = &s->nb.pw;
  const size_t n = p->n, m = c->n;
  memset(f->astart, 0, (n + 1) * sizeof(size_t));
  memset(f->wstart, 0, (n + 1) * sizeof(size_t));
  for (size_t k = 0; k < m; k++) f->astart[c->a[k] + 1]++;
  for (size_t k = 0; k < cw->n; k++) f->wstart[cw->a[k] + 1]++;
  for (size_t i = 0; i < n; i++) {
    f->astart[i + 1] += f->astart[i];
    f->wstart[i + 1] += f->wstart[i];
  }
  /* the dashpots' sqrt(m*), m* = ma mb / (ma + mb), once per build rather than per
     step (the operations pair_batch.c's lanes did, so the same bits) */
  const long mm = (long)m;
#pragma omp parallel for num_threads(nth) schedule(static)
  for (long k = 0; k < mm; k++) {
    const double ma = p->mass[c->a[k]], mb = p->mass[c->b[k]];
    f->sm[k] = sqrt(ma * mb / (ma + mb));
  }
  f->m0 = n ? p->material[0] : -1;
  for (size_t i = 1; i < n && f->m0 >= 0; i++)
    if (p->material[i] != f->m0) f->m0 = -1;
}

/* Step 0: indices for the current lists and T ranges. */
static int index_lists(esf_sim *s, esf_step_fast *f, int nth, esf_error *err) {
  const esf_particles *p = &s->p;
  const esf_contacts *c = &s->nb.pp;
  const size_t n = p->n, m = c->n, T = (size_t)nth;
  if (m > f->cap_k) {
    if (!grow((void **)&f->list[0], m, sizeof(uint32_t)) ||
        !grow((void **)&f->list[1], m, sizeof(uint32_t)) ||
        !grow((void **)&f->idle, m, sizeof(uint32_t)) ||
        !grow((void **)&f->sm, m, sizeof(double)))
      return esf_fail(err, ESF_ENOMEM, "out of memory for %zu contact candidates", m);
    f->cap_k = m;
  }
  if (n + 1 > f->cap_n) { /* acc: one line per particle (its contents were synced) */
    double *acc = esf_lines_realloc(f->acc, 0, (n + 1) * ACC * sizeof(double));
    if (acc) f->acc = acc;
    if (!acc || !grow((void **)&f->astart, n + 1, sizeof(size_t)) ||
        !grow((void **)&f->wstart, n + 1, sizeof(size_t)))
      return esf_fail(err, ESF_ENOMEM, "out of memory for %zu particle ranges", n);
    f->cap_n = n + 1;
  }
  /* new lists (else the same lists re-cut, or cut for another T) */
  const int fresh = f->np != n || f->built != s->nb.builds;
  if (f->nth != nth || fresh) f->recut = 0;
  if (!grow((void **)&f->bout, T + 1, sizeof(size_t)) ||
      !grow((void **)&f->binstart, T + 1, sizeof(size_t)) ||
      !grow((void **)&f->rlo, T + 1, sizeof(size_t)) ||
      !grow((void **)&f->busy, T, sizeof(double)) ||
      !grow((void **)&f->work, T, sizeof(double)) ||
      !grow((void **)&f->rate, T, sizeof(double)))
    return esf_fail(err, ESF_ENOMEM, "out of memory");
  if (f->nth != nth || !f->rr) {
    range_rec *rr = esf_lines_realloc(f->rr, 0, T * sizeof *rr);
    if (!rr) return esf_fail(err, ESF_ENOMEM, "out of memory");
    f->rr = rr;
  }
  for (size_t t = 0; t < T; t++) {
    atomic_init(&f->rr[t].ready, 0);
    atomic_init(&f->rr[t].done, 0);
  }
  atomic_init(&f->go, 0);
  atomic_init(&f->bfail, 0);
  f->epoch = 0;
  if (fresh) index_pairs(s, f, nth);
  size_t *wt = calloc(n ? 2 * n : 1, sizeof *wt); /* cut_ranges' weights and work */
  if (!wt) return esf_fail(err, ESF_ENOMEM, "out of memory for %zu particle ranges", n);
  cut_ranges(f, c, wt, n, T);
  free(wt);
  /* boundary pairs: a in range t, b in a higher range (b > a) */
  size_t nb = 0;
  memset(f->bout, 0, (T + 1) * sizeof(size_t));
  memset(f->binstart, 0, (T + 1) * sizeof(size_t));
  for (size_t t = 0; t < T; t++) {
    const size_t hi = f->rlo[t + 1];
    for (size_t k = f->astart[f->rlo[t]]; k < f->astart[hi]; k++)
      if (c->b[k] >= hi) nb++;
  }
  if (nb > f->cap_b) {
    if (!grow((void **)&f->bk, nb, sizeof(uint32_t)) ||
        !grow((void **)&f->bin, nb, sizeof(uint32_t)) ||
        !grow((void **)&f->slot_a, nb, SLOT_A * sizeof(double)))
      return esf_fail(err, ESF_ENOMEM, "out of memory for %zu boundary pairs", nb);
    double *sl = esf_lines_realloc(f->slot, 0, nb * SLOT * sizeof(double)); /* aligned */
    if (!sl) return esf_fail(err, ESF_ENOMEM, "out of memory for %zu boundary pairs", nb);
    f->slot = sl;
    f->cap_b = nb;
  }
  f->nb = nb;
  nb = 0;
  for (size_t t = 0; t < T; t++) {
    const size_t hi = f->rlo[t + 1];
    f->bout[t] = nb;
    for (size_t k = f->astart[f->rlo[t]]; k < f->astart[hi]; k++)
      if (c->b[k] >= hi) {
        f->bk[nb++] = (uint32_t)k;
        size_t tb = t + 1; /* the range of b */
        while (tb + 1 < T && c->b[k] >= f->rlo[tb + 1]) tb++;
        f->binstart[tb + 1]++;
      }
  }
  f->bout[T] = nb;
  for (size_t t = 0; t < T; t++) f->binstart[t + 1] += f->binstart[t];
  size_t cur[64], *cu = T <= 64 ? cur : malloc(T * sizeof *cu);
  if (!cu) return esf_fail(err, ESF_ENOMEM, "out of memory");
  memcpy(cu, f->binstart, T * sizeof *cu);
  for (size_t j = 0; j < nb; j++) { /* ascending k within each range of b */
    size_t tb = 0;
    while (tb + 1 < T && c->b[f->bk[j]] >= f->rlo[tb + 1]) tb++;
    f->bin[cu[tb]++] = (uint32_t)j;
  }
  if (cu != cur) free(cu);
  if (nb) { /* zero unless touching */
    memset(f->slot, 0, nb * SLOT * sizeof(double));
    memset(f->slot_a, 0, nb * SLOT_A * sizeof(double));
  }
  f->built = s->nb.builds;
  f->np = n;
  f->nth = nth;
  return ESF_OK;
}

/* A range's interior pairs (both particles in it) as two lists, each ascending in k:
 * the contacts, which go to the batches without a test (the batch finds those that
 * ended: pair_batch.h), and the idle candidates, which are screened for new contacts.
 * Made from the touch flags at a call's first step (whatever ran between calls), then
 * carried from step to step. Within the range's block of each buffer (blk pairs):
 *   tl[0 .. nt)        the contacts of the step before;
 *   tl[blk - nn .. blk) this step's new contacts, written downward (tl[blk - 1] is the
 *                      first), by the screening, which writes nothing else (a step not
 *                      taken leaves the lists as they were);
 *   sq[0 .. nt + nn)   the batches' sequence, the two merged; the batches compact it
 *                      in place to the contacts that remain (the next step's tl) and
 *                      write the ended ones to tl[0 ..), free by then;
 *   il[0 .. ni)        the idle candidates; after the batches, less the new contacts,
 *                      plus the ended ones.
 * No two of these overlap: nt + ni <= blk, and the ended ones are among tl's. */
typedef struct range_lists {
  uint32_t *tl, *sq, *il;
  size_t blk, nt, ni;
} range_lists;

static void lists_from_flags(const esf_sim *s, size_t k0, size_t k1, size_t end,
                             range_lists *L) {
  const uint32_t *cb = s->nb.pp.b;
  const uint8_t *touch = s->nb.pp.touch;
  size_t nt = 0, ni = 0;
  for (size_t k = k0; k < k1; k++) {
    if (cb[k] >= end) continue; /* a boundary pair: step 1's */
    const size_t on = touch[k] != 0;
    L->tl[nt] = (uint32_t)k; /* both written, one kept: no branch on the flag */
    L->il[ni] = (uint32_t)k;
    nt += on;
    ni += 1 - on;
  }
  L->nt = nt;
  L->ni = ni;
}

/* Whether the spheres of pair (a, b) overlap: |x_b - x_a|^2 < (r_a + r_b)^2, the step's
 * one test (pair_batch.c's lanes compute it for the contacts in the same order). */
static inline int spheres_overlap(const double *x, const double *r, size_t a, size_t b) {
  double d[3];
  v3_sub(d, x + 3 * b, x + 3 * a);
  const double R = r[a] + r[b];
  return v3_norm2(d) < R * R;
}

/* Step 2's screening of the idle candidates il[j0 .. j1) for overlapping spheres,
 * |x_b - x_a|^2 < (r_a + r_b)^2 (the batch applies the same test, in the same order, to
 * the contacts): the new contacts go to top[-(nn + 1)], top[-(nn + 2)], ...; returns
 * how many. Branch-free: every candidate is written, the count advances on a hit (the
 * write stays in the free part of tl: see range_lists). Reads only the range's own
 * particles. */
static size_t screen_idle(const esf_sim *s, const uint32_t *il, size_t j0, size_t j1,
                          uint32_t *top, size_t nn) {
  const double *x = s->p.x, *r = s->p.radius;
  const uint32_t *ca = s->nb.pp.a, *cb = s->nb.pp.b;
  size_t cnt = nn;
  for (size_t j = j0; j < j1; j++) {
    const size_t k = il[j];
    top[-(ptrdiff_t)(cnt + 1)] = (uint32_t)k;
    cnt += (size_t)spheres_overlap(x, r, ca[k], cb[k]);
  }
  return cnt - nn;
}

/* The batches' sequence: the contacts tl[0 .. nt) and the nn new ones at top[-1],
 * top[-2], ..., merged in ascending k into sq. Returns its length. */
static size_t merge_new(uint32_t *sq, const uint32_t *tl, size_t nt, const uint32_t *top,
                        size_t nn) {
  size_t i = 0, p = 0;
  for (size_t j = 1; j <= nn; j++) {
    const uint32_t k = top[-(ptrdiff_t)j];
    while (i < nt && tl[i] < k) sq[p++] = tl[i++];
    sq[p++] = k;
  }
  if (i < nt) memcpy(sq + p, tl + i, (nt - i) * sizeof *sq); /* tl may be NULL if empty */
  return p + nt - i;
}

/* The idle list after a step: il[0 .. ni) less the nn new contacts at top[-1], ...
 * (a subsequence of it, in the same order), plus the ne ended contacts ended[0 .. ne)
 * (ascending), merged in from the back. Returns the new length. */
static size_t idle_update(uint32_t *il, size_t ni, const uint32_t *top, size_t nn,
                          const uint32_t *ended, size_t ne) {
  size_t w = ni;
  if (nn) {
    size_t j = 1;
    w = 0;
    for (size_t q = 0; q < ni; q++) {
      if (j <= nn && il[q] == top[-(ptrdiff_t)j]) {
        j++;
        continue;
      }
      il[w++] = il[q];
    }
  }
  size_t p = w + ne, i = w;
  for (size_t q = ne; q > 0; q--) {
    const uint32_t k = ended[q - 1];
    while (i > 0 && il[i - 1] > k) il[--p] = il[--i];
    il[--p] = k;
  }
  return w + ne;
}

/* A computed boundary pair's force on A and torque on B (row[0..3], row[8..11] of the
 * batch's) to its slot, one line, by non-temporal stores, which do not take the line
 * from the core of b's range, where the last step's read of it left a copy
 * (slot_fence before the ready flag makes them visible). With two threads at 10 000
 * spheres, in the runs where lines travel slowly between the cores (docs/performance.md,
 * two modes), ordinary stores made range 0's boundary pass take 0.30-0.35 s of 11 000
 * steps, these 0.13-0.17; elsewhere both 0.11-0.12 s. */
static inline void slot_put(double *slot, const double *row) {
#if defined(__AVX__)
  _mm256_stream_pd(slot, _mm256_loadu_pd(row));
  _mm256_stream_pd(slot + 4, _mm256_loadu_pd(row + 8));
#elif defined(__SSE2__)
  for (int q = 0; q < 4; q += 2) {
    _mm_stream_pd(slot + q, _mm_loadu_pd(row + q));
    _mm_stream_pd(slot + 4 + q, _mm_loadu_pd(row + 8 + q));
  }
#else
  memcpy(slot, row, 4 * sizeof(double));
  memcpy(slot + 4, row + 8, 4 * sizeof(double));
#endif
}

/* Orders slot_put's stores before the stores that follow (boundary_pairs' caller's
 * ready flag). */
static inline void slot_fence(void) {
#if defined(__SSE2__)
  _mm_sfence();
#endif
}

/* Step 1 for the boundary pairs bk[j0 .. j1): each one's slot, zero when not touching,
 * the touching ones computed in batches, the stores fenced (slot_fence) before the
 * caller raises its ready flag; no fence for a range without such pairs. Returns the
 * lowest pair index whose overlap exceeds the limit (its slot unwritten), or SIZE_MAX;
 * adds the touching ones to *nt. */
static size_t boundary_pairs(esf_sim *s, esf_step_fast *f, const esf_pair_batch_ctx *bc,
                             size_t j0, size_t j1, size_t *nt) {
  const esf_particles *p = &s->p;
  esf_contacts *c = &s->nb.pp;
  uint32_t kb[ESF_BATCH];
  size_t jb[ESF_BATCH], bad = SIZE_MAX;
  int m = 0;
  double out[ESF_BATCH][ESF_BATCH_OUT];
  for (size_t j = j0; j < j1 || m > 0;) {
    if (j < j1) {
      const size_t k = f->bk[j], a = c->a[k], b = c->b[k];
      if (!spheres_overlap(p->x, p->radius, a, b)) {
        if (c->touch[k]) {
          c->touch[k] = 0;
          memset(f->slot + SLOT * j, 0, SLOT * sizeof(double));
          memset(f->slot_a + SLOT_A * j, 0, SLOT_A * sizeof(double));
        }
        j++;
        continue;
      }
      (*nt)++;
      kb[m] = (uint32_t)k;
      jb[m++] = j++;
      if (m < ESF_BATCH) continue;
    }
    unsigned apart; /* none: screened above by the same test */
    const unsigned fail = esf_pair_batch_linear(bc, kb, m, out, &apart);
    for (int l = 0; l < m; l++) {
      if (fail >> l & 1u) {
        if (kb[l] < bad) bad = kb[l];
        continue;
      }
      slot_put(f->slot + SLOT * jb[l], out[l]);
      memcpy(f->slot_a + SLOT_A * jb[l], out[l], SLOT_A * sizeof(double));
    }
    m = 0;
  }
  if (j1 > j0) slot_fence();
  return bad;
}

/* What step 2's particle pass needs: walls, 2D, local damping, kick, drift. */
typedef struct kick_ctx {
  double dt, cr0, cr1, ct0, ct1, lc;
  int dim2;
  int plain;                  /* 1: no damping of either form, 3D (kick_plain_loop) */
  esf_wall_pass_fn wall_pass; /* wall_fast.h, chosen once per step */
  const esf_local_damping *loc;
  const double *xref;
  const double *dom_lo, *dom_hi; /* the domain, or NULL */
} kick_ctx;

/* Step 2's wall contacts of range [lo, hi), particle by particle in ascending order
 * (each adds to its own particle's accumulator only, at the state before any kick).
 * Returns 1 when an overlap exceeds the limit (*bad_part: the first such particle). */
static int walls_range(esf_sim *s, const esf_step_fast *f, const kick_ctx *K, size_t lo,
                       size_t hi, size_t *nt_pw, size_t *bad_part) {
  const esf_contacts *pw = &s->nb.pw;
  const esf_wall_pass_fn wall_pass = K->wall_pass;
  int fail = 0;
  for (size_t k = f->wstart[lo], k1; k < f->wstart[hi]; k = k1) {
    const size_t i = pw->a[k];
    k1 = f->wstart[i + 1];
    double *fi = f->acc + ACC * i;
    if (wall_pass(s, k, k1, K->dt, nt_pw, fi, fi + 4)) {
      if (i < *bad_part) *bad_part = i;
      fail = 1;
    }
  }
  return fail;
}

/* The kick and drift of range [lo, hi) with neither damping form, in 3D: a loop of
 * its own, without calls or branches, that the compiler vectorises across particles
 * (each lane the same operations as the scalar loop, so the same bits). The largest
 * squared displacement since the lists' build goes to *max2 (a NaN sets *nonfinite),
 * and a position outside [lo3, hi3] (the domain, or infinite bounds: never) sets
 * *escaped. */
static void kick_plain_loop(size_t lo, size_t hi, double dt, double *restrict x,
                            double *restrict v, double *restrict w,
                            const double *restrict acc, const double *restrict im_,
                            const double *restrict ii_, const double *restrict xref,
                            const double *lo3, const double *hi3, double *max2,
                            int *nonfinite, int *escaped) {
  /* the largest d2 through its bits: d2 >= +0 or NaN, and the bits of non-negative
     doubles order as integers do (an integer maximum vectorises, a double one with
     NaN semantics does not); a NaN counts as 0 here, as the scalar test skips it */
  int64_t mb = 0;
  int nan = 0, out = 0;
  /* the new position is tested from registers, not read back: a vector load of what
     the loop has just stored piecewise cannot be forwarded from the store buffer and
     waits for the stores to retire (that load drew 2.7% of a two-thread run's samples) */
  const double bl[3] = {lo3[0], lo3[1], lo3[2]}, bh[3] = {hi3[0], hi3[1], hi3[2]};
  for (size_t i = lo; i < hi; i++) {
    const double *fi = acc + ACC * i, *ti = fi + 4;
    const double im = im_[i] * dt, ii = ii_[i] * dt;
    double d2 = 0.0, xn[3];
    for (int q = 0; q < 3; q++) {
      const double vn = v[3 * i + q] + fi[q] * im;
      v[3 * i + q] = vn;
      w[3 * i + q] += ti[q] * ii;
      xn[q] = x[3 * i + q] + vn * dt;
      x[3 * i + q] = xn[q];
      const double d = xn[q] - xref[3 * i + q];
      d2 += d * d;
    }
    const int isnan_ = !(d2 == d2);
    int64_t b;
    memcpy(&b, &d2, sizeof b);
    b = isnan_ ? 0 : b;
    nan |= isnan_;
    mb = b > mb ? b : mb;
    out |= v3_outside(xn, bl, bh); /* as sim.c's */
  }
  double m2;
  memcpy(&m2, &mb, sizeof m2);
  if (m2 > *max2) *max2 = m2;
  *nonfinite |= nan;
  *escaped |= out;
}

/* The kick and drift of particle i from its totals fi, ti (F_n, M_n; left as they
 * are), with the damping forms and 2D: the displacement since the lists' build and
 * the domain check. */
static inline void kick_one(esf_particles *p, const kick_ctx *K, size_t i, double *fi,
                            double *ti, double *max2, int *nonfinite, int *escaped) {
  const double dt = K->dt;
  if (HAS_FEATURES && K->dim2) {
    fi[1] = 0.0;
    ti[0] = 0.0;
    ti[2] = 0.0;
  }
  double *v = p->v + 3 * i, *w = p->w + 3 * i, *x = p->x + 3 * i;
  double fk[3], tk[3]; /* fi, ti stay: F_n, M_n for p.f, p.t (s->ft_lazy) */
  v3_copy(fk, fi);
  v3_copy(tk, ti);
  if (HAS_FEATURES && K->loc) {
    double fd[3], md[3];
    K->loc->force(K->lc, fk, v, fd);
    K->loc->force(K->lc, tk, w, md);
    v3_add(fk, fk, fd);
    v3_add(tk, tk, md);
  }
  const double im = p->inv_mass[i] * dt, ii = p->inv_inertia[i] * dt;
  double d2 = 0.0;
  for (int q = 0; q < 3; q++) {
    if (HAS_FEATURES) {
      v[q] = (K->cr0 * v[q] + fk[q] * im) * K->cr1;
      w[q] = (K->ct0 * w[q] + tk[q] * ii) * K->ct1;
    } else {
      v[q] += fk[q] * im;
      w[q] += tk[q] * ii;
    }
    x[q] += v[q] * dt;
    if (K->xref) {
      const double d = x[q] - K->xref[3 * i + q];
      d2 += d * d;
    }
  }
  if (!(d2 <= *max2)) {
    if (d2 > *max2)
      *max2 = d2;
    else
      *nonfinite = 1; /* NaN */
  }
  if (K->dom_lo) *escaped |= v3_outside(x, K->dom_lo, K->dom_hi); /* as sim.c's */
}

/* Step 2's particle pass for range [lo, hi): the wall contacts of every particle first,
 * then the kicks (a particle's walls read only its own state, so the order of
 * operations per particle is that of one loop doing both). A wall overlap failure
 * leaves the range unkicked, as a pair failure does: the step is not taken. */
static void kick_range(esf_sim *s, const esf_step_fast *f, const kick_ctx *K, size_t lo,
                       size_t hi, size_t *nt_pw, size_t *bad_part, double *max2,
                       int *nonfinite, int *escaped) {
  if (walls_range(s, f, K, lo, hi, nt_pw, bad_part)) return;
  if (K->plain && K->xref) {
    const double inf3[2][3] = {{-INFINITY, -INFINITY, -INFINITY},
                               {INFINITY, INFINITY, INFINITY}};
    esf_particles *p = &s->p;
    kick_plain_loop(lo, hi, K->dt, p->x, p->v, p->w, f->acc, p->inv_mass, p->inv_inertia,
                    K->xref, K->dom_lo ? K->dom_lo : inf3[0],
                    K->dom_lo ? K->dom_hi : inf3[1], max2, nonfinite, escaped);
    return;
  }
  for (size_t i = lo; i < hi; i++) {
    double *fi = f->acc + ACC * i;
    kick_one(&s->p, K, i, fi, fi + 4, max2, nonfinite, escaped);
  }
}

/* Step 2: adds the A side of outgoing boundary pair j (its pair's a is in range). */
static inline void outgoing(const esf_step_fast *f, const esf_contacts *c, size_t j) {
  double *fa = f->acc + ACC * c->a[f->bk[j]];
  const double *sl = f->slot_a + SLOT_A * j;
  v4_acc(fa, sl);
  v4_acc(fa + 4, sl + 4);
}

/* Sets the accumulators of particles [from, to) to f = m g, t = 0; returns the new
 * frontier (max(from, to)). */
static inline size_t acc_set(const esf_particles *p, const double *g, double *acc,
                             size_t from, size_t to) {
  const esf_v4 gv = {g[0], g[1], g[2], 0.0}, zero = {0.0, 0.0, 0.0, 0.0};
  for (size_t i = from; i < to; i++) { /* four-wide stores: the adds' four-wide loads */
    v4_st(acc + ACC * i, p->mass[i] * gv); /* are then forwarded from the store buffer */
    v4_st(acc + ACC * i + 4, zero);
  }
  return from > to ? from : to;
}

/* A spinning thread's hint to the core (x86 pause: fewer wasted issue slots, and no
 * memory-order flush when the flag changes). */
static inline void cpu_relax(void) {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

/* Spins before a waiting thread yields its core: a wait between two steps is a few
 * microseconds, and a yield is a system call of about one (measured: yielding after 64
 * spins put 4% of a two-thread run's samples in the kernel's scheduler). */
#define SPIN 4096

/* Spins until *flag reaches epoch e (flags only grow); returns the seconds waited, 0
 * when the flag was already up. */
static double wait_flag(_Atomic long *flag, long e) {
  if (atomic_load_explicit(flag, memory_order_acquire) >= e) return 0.0;
#ifdef _OPENMP
  const double t0 = omp_get_wtime();
#endif
  for (unsigned spin = 0; atomic_load_explicit(flag, memory_order_acquire) < e; spin++)
    if (spin < SPIN)
      cpu_relax();
    else
      sched_yield(); /* more threads than cores */
#ifdef _OPENMP
  return omp_get_wtime() - t0;
#else
  return 0.0;
#endif
}

/* After a batch of list[q0 .. q0 + nl): its pairs whose bit is set in apart go to
 * ended[*ng ..], the others to list[w ..] (w <= q0: in place). Returns the new w. */
static inline size_t compact(uint32_t *list, size_t q0, int nl, unsigned apart, size_t w,
                             uint32_t *ended, size_t *ng) {
  if (!apart && w == q0) return w + (size_t)nl; /* nothing ended yet: in place already */
  for (int l = 0; l < nl; l++) {
    const uint32_t k = list[q0 + l];
    if (apart >> l & 1u)
      ended[(*ng)++] = k;
    else
      list[w++] = k;
  }
  return w;
}

/* Step 2's pair pass for range t, its interior contacts and new contacts in
 * list[0 .. cnt) (ascending): forces of all pairs touching its particles, in ascending
 * k per particle. The contacts that ended (the batch finds them) leave list, which is
 * compacted in place to *kept pairs, and go to ended[0 .. *ne). Needs the lower
 * ranges' boundary pairs of this step done (the incoming slots). Returns the lowest
 * failing pair index or SIZE_MAX. Kept out of line: inlined into run_range
 * (GCC 12 does when run_range is a little smaller) the one-thread step at 10k ran 2.5%
 * slower. */
__attribute__((noinline)) static size_t
pairs_range(esf_sim *s, esf_step_fast *f, const esf_pair_batch_ctx *bc, size_t t,
            size_t lo, size_t hi, uint32_t *list, size_t cnt, uint32_t *ended, size_t *ne,
            size_t *kept) {
  esf_particles *p = &s->p;
  const esf_contacts *c = &s->nb.pp;
  const double *g = s->cfg.gravity;
  double *acc = f->acc;
  size_t bad = SIZE_MAX;
  /* The accumulators are set (f = m g, t = 0) just ahead of their first use, not in a
   * pass of their own: a pair's b lies a few thousand particles ahead of its a, and a
   * separate pass would leave its line to be fetched again from memory at the add. */
  size_t fr = lo; /* acc[lo .. fr) are set */
  size_t bmax = lo;
  for (size_t q = f->binstart[t]; q < f->binstart[t + 1]; q++) {
    const size_t b = c->b[f->bk[f->bin[q]]];
    if (b >= bmax) bmax = b + 1;
  }
  fr = acc_set(p, g, acc, fr, bmax);
  for (size_t q = f->binstart[t]; q < f->binstart[t + 1]; q++) { /* incoming */
    const size_t j = f->bin[q];
    double *ab = acc + ACC * c->b[f->bk[j]];
    const double *sl = f->slot + SLOT * j;
    v4_dec(ab, sl);
    v4_acc(ab + 4, sl + 4);
  }
  size_t jo = f->bout[t];
  const size_t jo1 = f->bout[t + 1];
  double out[ESF_BATCH][ESF_BATCH_OUT];
  const char *hist = (const char *)c->h;
  size_t w = 0, ng = 0; /* list[0 .. w) kept, ended[0 .. ng) */
  for (size_t q0 = 0; q0 < cnt; q0 += ESF_BATCH) {
    const int nl = cnt - q0 < ESF_BATCH ? (int)(cnt - q0) : ESF_BATCH;
    /* the histories of the pairs PF ahead (sparse in memory, so the hardware's
     * stream prefetch does not see them coming; worth x1.38 at 50 000), both ends of
     * each record: half the 48-byte records straddle two lines (the first end alone
     * took 1/0.943 as long at 200 000 on one thread, 1/0.970 on two). Prefetching
     * b's velocity, spin and accumulator too, as until 2026-11-24, cost 5-7% at
     * 10 000 and gained nothing at 200 000 (paired runs, one and two threads). */
    for (size_t q = q0 + PF; q < q0 + PF + ESF_BATCH && q < cnt; q++) {
      const char *hq = hist + (size_t)list[q] * sizeof(esf_contact_hist);
      __builtin_prefetch(hq, 1, 3);
      __builtin_prefetch(hq + sizeof(esf_contact_hist) - 1, 1, 3);
    }
    for (int l = 0; l < nl; l++) /* b > a: covers the a sides and outgoing slots too */
      if (c->b[list[q0 + l]] >= bmax) bmax = c->b[list[q0 + l]] + 1;
    fr = acc_set(p, g, acc, fr, bmax);
    if (jo == jo1 || f->bk[jo] > list[q0 + nl - 1]) {
      /* no outgoing slot falls among these pairs: the batch adds its results itself,
         as the loop below does (esf_pair_batch_acc_add) */
      unsigned apart;
      const unsigned fail = esf_pair_batch_linear_add(bc, list + q0, nl, acc, &apart);
      for (int l = 0; fail && l < nl; l++)
        if ((fail >> l & 1u) && list[q0 + l] < bad) bad = list[q0 + l];
      w = compact(list, q0, nl, apart, w, ended, &ng);
      continue;
    }
    unsigned apart;
    const unsigned fail = esf_pair_batch_linear(bc, list + q0, nl, out, &apart);
    for (int l = 0; l < nl; l++) {
      const size_t k = list[q0 + l];
      for (; jo < jo1 && f->bk[jo] < k; jo++) outgoing(f, c, jo);
      if (apart >> l & 1u) continue;
      if (fail >> l & 1u) {
        if (k < bad) bad = k;
        continue;
      }
      esf_pair_batch_acc_add(acc, c->a[k], c->b[k], v4_ld(out[l]), v4_ld(out[l] + 4),
                             v4_ld(out[l] + 8));
    }
    w = compact(list, q0, nl, apart, w, ended, &ng);
  }
  acc_set(p, g, acc, fr, hi);
  for (; jo < jo1; jo++) outgoing(f, c, jo);
  *kept = w;
  *ne = ng;
  return bad;
}

/* What every range's steps share in one call. */
typedef struct burst {
  const esf_pair_batch_ctx *bc;
  const kick_ctx *K;
  long e0;     /* the epoch of the call's first step */
  long steps;  /* steps at most */
  double lim2; /* the lists need a rebuild past this squared displacement, m^2 */
} burst;

/* 1 when the ranges above 0 have all finished step e. */
static int all_done(esf_step_fast *f, long e) {
  for (int u = 1; u < f->nth; u++)
    if (atomic_load_explicit(&f->rr[u].done, memory_order_acquire) < e) return 0;
  return 1;
}

/* The latest step's results of all ranges, in *r. Returns 1 when one failed. */
static int gather(const esf_step_fast *f, step_out *r) {
  *r = (step_out){0, SIZE_MAX, SIZE_MAX, 0.0, 0, 0};
  for (int u = 0; u < f->nth; u++) {
    const step_out *o = &f->rr[u].out;
    r->nt += o->nt;
    r->bad_pair = o->bad_pair < r->bad_pair ? o->bad_pair : r->bad_pair;
    r->bad_part = o->bad_part < r->bad_part ? o->bad_part : r->bad_part;
    r->max2 = o->max2 > r->max2 ? o->max2 : r->max2;
    r->nonfinite |= o->nonfinite;
    r->escaped |= o->escaped;
  }
  return r->bad_pair != SIZE_MAX || r->bad_part != SIZE_MAX;
}

/* Range 0, before step e of a burst (not its first): waits for every range to finish
 * step e - 1, gathers their results and checks the balance, as the driver would
 * between two calls, and tells the others whether to take step e: not when a contact
 * failed, a position is not finite, a particle left the domain, the lists need a
 * rebuild (esf_neighbor_check's test on the same numbers) or the ranges a re-cut.
 * Returns 1 to stop. */
static int burst_decide(esf_step_fast *f, const burst *B, long e, double *waited) {
  const size_t T = (size_t)f->nth;
  for (size_t u = 1; u < T; u++) *waited += wait_flag(&f->rr[u].done, e - 1);
  step_out r;
  const int fail = gather(f, &r);
  if (!fail) f->nt_sum += r.nt;
  balance_check(f, T);
  const int stop = fail || r.nonfinite || r.escaped || r.max2 > B->lim2 || f->recut;
  atomic_store_explicit(&f->go, 2 * e + stop, memory_order_release);
  return stop;
}

/* Range t's steps of one call (the order of operations in the prologue). From the
 * burst's second step on, a range waits, before its boundary pairs, for range 0's word
 * and for the higher ranges to have drifted (their particles are read); range 0 gives
 * the word once all have finished the step before. The screening, which reads only
 * the range's own particles and writes nothing shared, goes ahead of the wait in
 * ranges above 0, so a range that finished early has work while the others catch up. */
static void run_range(esf_sim *s, esf_step_fast *f, const burst *B, size_t t) {
  range_rec *me = f->rr + t;
  const size_t T = (size_t)f->nth, lo = f->rlo[t], hi = f->rlo[t + 1];
  const size_t k0 = f->astart[lo], k1 = f->astart[hi];
  range_lists L = {f->list[0] + k0, f->list[1] + k0, f->idle + k0, k1 - k0, 0, 0};
  lists_from_flags(s, k0, k1, hi, &L);
  long i = 0;
  for (; i < B->steps; i++) {
    const long e = B->e0 + i;
#ifdef _OPENMP
    const double t0 = omp_get_wtime();
#endif
    double waited = 0.0;
    size_t nn = 0, nt_pp = 0, nt_pw = 0;
    uint32_t *top = L.tl + L.blk; /* the new contacts, downward */
    size_t j = 0;                 /* idle candidates screened: il[0 .. j) */
    if (t > 0) {                  /* ahead of the word from the burst's second step on */
      nn = screen_idle(s, L.il, 0, L.ni, top, 0);
      j = L.ni;
    }
    if (i > 0 && t == 0) { /* screens while the others finish the step before */
      while (j < L.ni && !all_done(f, e - 1)) {
        const size_t j1 = L.ni - j > SCREEN_CHUNK ? j + SCREEN_CHUNK : L.ni;
        nn += screen_idle(s, L.il, j, j1, top, nn);
        j = j1;
      }
      if (burst_decide(f, B, e, &waited)) break;
    }
    if (i > 0 && t > 0) {
      waited += wait_flag(&f->go, 2 * e);
      if (atomic_load_explicit(&f->go, memory_order_relaxed) & 1) break;
      for (size_t u = t + 1; u < T; u++) waited += wait_flag(&f->rr[u].done, e - 1);
    }
    step_out o = {0, SIZE_MAX, SIZE_MAX, 0.0, 0, 0};
    o.bad_pair = boundary_pairs(s, f, B->bc, f->bout[t], f->bout[t + 1], &nt_pp);
    if (o.bad_pair != SIZE_MAX) atomic_store_explicit(&f->bfail, e, memory_order_relaxed);
    atomic_store_explicit(&me->ready, e, memory_order_release);
    if (j < L.ni) nn += screen_idle(s, L.il, j, L.ni, top, nn); /* range 0: the rest */
    for (size_t u = 0; u < t; u++) /* their slots written, our particles no longer read */
      waited += wait_flag(&f->rr[u].ready, e);
    const size_t cnt = merge_new(L.sq, L.tl, L.nt, top, nn);
    size_t ne, kept;
    const size_t bad = pairs_range(s, f, B->bc, t, lo, hi, L.sq, cnt, L.tl, &ne, &kept);
    L.ni = idle_update(L.il, L.ni, top, nn, L.tl, ne); /* ended: in tl, free now */
    uint32_t *const tl = L.tl;
    L.tl = L.sq; /* the contacts that remain */
    L.sq = tl;
    L.nt = kept;
    nt_pp += kept;
    if (bad < o.bad_pair) o.bad_pair = bad;
    if (o.bad_pair == SIZE_MAX &&
        atomic_load_explicit(&f->bfail, memory_order_relaxed) != e)
      kick_range(s, f, B->K, lo, hi, &nt_pw, &o.bad_part, &o.max2, &o.nonfinite,
                 &o.escaped);
    o.nt = nt_pp + nt_pw;
    me->out = o;
#ifdef _OPENMP
    f->busy[t] += omp_get_wtime() - t0 - waited; /* range t is this thread's alone */
#endif
    atomic_store_explicit(&me->done, e, memory_order_release);
  }
  if (t == 0) {
    f->taken = i;
    f->decided = i < B->steps;
  }
}

int esf_step_fast_run(esf_sim *s, esf_step_fast *f, long nmax, long *taken,
                      esf_error *err) {
  esf_particles *p = &s->p;
  int rc;
  *taken = 0;
  const int nth = s->cfg.threads > 0 ? s->cfg.threads : 1;
  if (f->built != s->nb.builds || f->np != p->n || f->nth != nth || f->recut) {
    esf_sim_forces_sync(s); /* acc may move */
    rc = index_lists(s, f, nth, err);
    if (rc) return rc;
  }
  const size_t T = (size_t)nth;
  const double dt = s->dt, h = 0.5 * dt;
  const esf_contacts *cp = &s->nb.pp;
  const esf_pair_batch_ctx bc = {p->x,
                                 p->v,
                                 p->w,
                                 p->radius,
                                 p->material,
                                 &s->mats,
                                 f->m0 >= 0 ? s->mats.pair + f->m0 * (s->mats.n + 1)
                                            : NULL,
                                 cp->a,
                                 cp->b,
                                 cp->h,
                                 cp->touch,
                                 f->sm,
                                 s->beta,
                                 dt,
                                 s->cfg.max_overlap,
                                 !HAS_FEATURES || s->cfg.tframe == ESF_TFRAME_ROTATE,
                                 HAS_FEATURES && s->mats.any_cohesion};
  const double cr0 = 1.0 - s->alpha_r * h, cr1 = 1.0 / (1.0 + s->alpha_r * h),
               ct0 = 1.0 - s->alpha_t * h, ct1 = 1.0 / (1.0 + s->alpha_t * h);
  const kick_ctx K = {dt,
                      cr0,
                      cr1,
                      ct0,
                      ct1,
                      s->cfg.local_coef,
                      s->cfg.dim == 2,
                      cr0 == 1.0 && cr1 == 1.0 && ct0 == 1.0 && ct1 == 1.0 && !s->local &&
                          s->cfg.dim == 3,
                      esf_wall_pass_select(s),
                      s->local,
                      s->nb.xref,
                      s->nb.dom_lo,
                      s->nb.dom_hi};
  /* more than one step only when the lists' check between steps needs nothing but
     the displacements (esf_neighbor_check) and nothing else happens between them */
  const int many = s->nb.xref && s->nb.nref == p->n && !s->walls.moving && !s->events;
  const burst B = {&bc, &K, f->epoch + 1, many && nmax > 1 ? nmax : 1,
                   esf_neighbor_limit2(&s->nb)};
  f->nt_sum = 0;
  f->taken = 0;
  f->decided = 0;

#ifdef _OPENMP
  const double t_start = omp_get_wtime(), gap = t_start - f->t_left;
  if (f->t_left > 0 && nth > 1 && gap < 0.5 * f->t_step) /* not a frame write */
    f->busy[0] += gap;
#endif
#pragma omp parallel num_threads(nth)
  {
#ifdef _OPENMP
    const size_t me = (size_t)omp_get_thread_num(), got = (size_t)omp_get_num_threads();
#else
    const size_t me = 0, got = 1;
#endif
    if (got == T) {
      run_range(s, f, &B, me);
    } else { /* fewer threads than ranges: one step, the ranges in ascending order */
      burst B1 = B;
      B1.steps = 1;
      for (size_t t = me; t < T; t += got) run_range(s, f, &B1, t);
    }
  }
  const long n = f->taken;
  f->epoch += n;
  /* the last step's results (a failure stops the burst with the failing step) */
  step_out r;
  const int fail = gather(f, &r);
  if (!f->decided) {
    if (!fail) f->nt_sum += r.nt;
    balance_check(f, T);
  }
  const long ok = fail ? n - 1 : n; /* steps completed without failure */
  s->step += ok;
  s->t = (double)s->step * s->dt;
  s->rhs_evals += ok;
  s->contacts_sum += (double)f->nt_sum;
  *taken = ok;
  /* the accumulators hold F_n, M_n; on failure they are partly overwritten, and p.f,
   * p.t keep what the last sync left */
  s->ft_lazy = fail ? NULL : f->acc;
  if (r.bad_pair != SIZE_MAX) {
    const esf_contacts *c = &s->nb.pp;
    uint32_t a = c->a[r.bad_pair], b = c->b[r.bad_pair];
    double d[3];
    v3_sub(d, p->x + 3 * (size_t)b, p->x + 3 * (size_t)a);
    double un = p->radius[a] + p->radius[b] - v3_norm(d);
    return esf_forces_overlap_failure(s, (long long)p->id[a], (long long)p->id[b], 0, un,
                                      fmin(p->radius[a], p->radius[b]), err);
  }
  if (r.bad_part != SIZE_MAX) { /* the same evaluation again, serially, for the message */
    size_t nt = 0;
    double fi[3] = {0, 0, 0}, ti[3] = {0, 0, 0};
    const size_t i = r.bad_part;
    rc = esf_forces_wall_particle(s, f->wstart[i], f->wstart[i + 1], p->x, p->v, p->w, dt,
                                  ESF_FORCES_TRIAL, NULL, NULL, &nt, fi, ti, err);
    return rc ? rc : esf_fail(err, ESF_EINTERNAL, "wall contact failure not reproduced");
  }
  s->nb.max_disp2 = r.max2;
  s->nb.escaped = r.escaped;
  s->nb.disp_valid = K.xref && !r.nonfinite;
#ifdef _OPENMP
  f->t_left = omp_get_wtime();
  f->t_step = (f->t_left - t_start) / (double)(n > 0 ? n : 1);
#endif
  return ESF_OK;
}
