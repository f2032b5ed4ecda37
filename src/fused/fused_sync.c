/* fused_sync.c — the flags by which the fused step's ranges hand work to each other
 * without a barrier of all threads (fused.c's order of operations).
 *
 * Each range t owns one cache line (esf_fused_range) with two flags that only grow and
 * hold step numbers (epochs): `ready` = e once its boundary pairs of step e are in their
 * slots (fused_slots.c), `done` = e once step e is finished and its results (out) are
 * written. Range 0 owns one more word, `go` = 2 e to let step e be taken, 2 e + 1 to
 * stop before it; `bfail` = e when a boundary pair failed in step e. A flag is stored
 * with release order after the data it announces and loaded with acquire order before
 * that data is read, so what a flag announces is visible to whoever saw it up:
 *   - range t, before adding the incoming boundary slots, waits for `ready` of every
 *     lower range (their slots written; they no longer read range t's particles);
 *   - from a burst's second step on, range 0 waits for `done` of every range (step
 *     e - 1 finished), gathers their results and decides (esf_fused_decide); the other
 *     ranges wait for `go` and for `done` of the higher ranges, whose particles their
 *     boundary pairs read and which must have drifted first.
 * Units: seconds for the waits. */
#include "fused/fused_impl.h"

#include "util/threads.h"

/* Spins until *flag reaches epoch e (flags only grow), then yields (util/threads.h);
 * returns the seconds waited, 0 when the flag was already up. */
double esf_fused_wait(_Atomic long *flag, long e) { return esf_threads_wait(flag, e); }

/* 1 when the ranges above 0 have all finished step e. */
int esf_fused_all_done(esf_fused *f, long e) {
  for (int u = 1; u < f->nth; u++)
    if (atomic_load_explicit(&f->rr[u].done, memory_order_acquire) < e) return 0;
  return 1;
}

/* The latest step's results of all ranges, in *r. Returns 1 when one failed. */
int esf_fused_gather(const esf_fused *f, esf_fused_out *r) {
  *r = ESF_FUSED_OUT_NONE;
  for (int u = 0; u < f->nth; u++) {
    const esf_fused_out *o = &f->rr[u].out;
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
int esf_fused_decide(esf_fused *f, const esf_fused_burst *B, long e, double *waited) {
  const size_t T = (size_t)f->nth;
  for (size_t u = 1; u < T; u++) *waited += esf_fused_wait(&f->rr[u].done, e - 1);
  esf_fused_out r;
  const int fail = esf_fused_gather(f, &r);
  if (!fail) f->nt_sum += r.nt;
  if (!fail && B->led) esf_ledger_step(B->led, B->K->blocks, B->nblocks); /* step e-1 */
  esf_fused_balance(f, T);
  const int stop = fail || r.nonfinite || r.escaped || r.max2 > B->lim2 || f->recut;
  atomic_store_explicit(&f->go, 2 * e + stop, memory_order_release);
  return stop;
}
