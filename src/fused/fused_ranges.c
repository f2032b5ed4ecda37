/* fused_ranges.c — the fused step's step 0 (fused.c): indices made once per list build
 * and particle ranges cut for the threads, and the balance that re-cuts them.
 *
 * esf_fused_index, for the current candidate lists and T ranges: each particle's pair
 * block (the pair list is sorted by (a, b), a < b) and wall candidates, each pair's
 * sqrt(m*) for the dashpots, whether all particles have one material (its parameters
 * are then broadcast to the batches' lanes); the ranges, cut where the estimated work
 * is shared equally (scaled by the measured time per unit of work of the old ranges
 * when re-cut); the boundary pairs (a in range t, b in a higher range) with their
 * slots, listed by the range of a (outgoing) and of b (incoming), ascending in k.
 * esf_fused_balance, every 32 steps on one cut: a re-cut when the slowest range took
 * more than 2% longer than the mean. Any cut gives the same results; only the time
 * depends on it. */
#include "fused/fused_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

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

static size_t work_of(const esf_fused *f, const esf_candidates *c, size_t i) {
  size_t w = W_PART + W_WALL * (f->wstart[i + 1] - f->wstart[i]);
  for (size_t k = f->astart[i]; k < f->astart[i + 1]; k++)
    w += W_CAND + W_TOUCH * c->touch[k];
  return w;
}

/* The particle ranges, rlo[t] .. rlo[t + 1] for thread t, cut where the estimated
 * work of steps 1-2 (wt, per particle) is shared equally, so threads finish together
 * although a bed's bottom has more contacts than its surface. Any cut gives the same
 * results. */
static void cut_once(esf_fused *f, const size_t *wt, size_t n, size_t T, size_t align,
                     size_t base) {
  size_t total = 0;
  for (size_t i = 0; i < n; i++) total += wt[i];
  size_t i = 0, acc = 0;
  f->rlo[0] = 0;
  for (size_t t = 1; t < T; t++) {
    const size_t goal = total / T * t + total % T * t / T;
    while (i < n && acc < goal) acc += wt[i++];
    size_t cut = i; /* the ledger's blocks, from base on, stay whole */
    if (i > base) cut = base + (i - base + align / 2) / align * align;
    if (cut < f->rlo[t - 1]) cut = f->rlo[t - 1];
    f->rlo[t] = cut < n ? cut : n;
  }
  f->rlo[T] = n;
}

/* With f->recut (same particles and lists, ranges measured unequal), each particle's
 * work is scaled by its old range's measured seconds per unit (rounded to 1/64).
 * wt: n of scratch, the weights cut by (each particle's work, scaled). */
static void cut_ranges(esf_fused *f, const esf_candidates *c, size_t *wt, size_t n,
                       size_t T, size_t align, size_t base) {
  for (size_t i = 0; i < n; i++) wt[i] = work_of(f, c, i);
  if (f->recut) {
    double mean = 0.0;
    for (size_t t = 0; t < T; t++) mean += f->rate[t] / (double)T;
    for (size_t t = 0; t < T && mean > 0; t++) {
      const size_t q = (size_t)(64.0 * f->rate[t] / mean + 0.5);
      for (size_t i = f->rlo[t]; i < f->rlo[t + 1]; i++) wt[i] *= q;
    }
  }
  cut_once(f, wt, n, T, align, base);
  for (size_t t = 0; t < T; t++) { /* unscaled: the next rates are the ranges' own */
    f->work[t] = 0.0;
    for (size_t i = f->rlo[t]; i < f->rlo[t + 1]; i++) /* again: no second array */
      f->work[t] += (double)work_of(f, c, i);
    f->busy[t] = f->waits[t] = 0.0;
  }
  f->busy_steps = 0;
  f->recut = 0;
}

/* After every 32 steps on the same cut: when the slowest range took more than 2%
 * longer than the mean, the next step cuts again with the measured rates. Range 0's
 * time includes the serial work between steps (the driver's, the list check): its
 * thread, the master, does that work while the others wait. */
void esf_fused_balance(esf_fused *f, size_t T) {
  if (T < 2 || ++f->busy_steps < 32) return;
  double mean = 0.0, worst = 0.0;
  for (size_t t = 0; t < T; t++) {
    mean += f->busy[t] / (double)T;
    worst = f->busy[t] > worst ? f->busy[t] : worst;
  }
  /* The threads' efficiency over the window: the time they worked against the time
   * they worked or waited for each other. Below ESF_FUSED_MIN_EFF they waited more than
   * they worked (other programs on the cores): one thread fewer for ESF_FUSED_BACKOFF
   * seconds, then all again (the results do not change). */
  double busy = 0.0, waited = 0.0;
  for (size_t t = 0; t < T; t++) {
    busy += f->busy[t];
    waited += f->waits[t];
  }
  if (busy + waited > 0 && busy / (busy + waited) < ESF_FUSED_MIN_EFF) {
#ifdef _OPENMP
    if (!(f->backoff >= ESF_FUSED_BACKOFF)) f->backoff = ESF_FUSED_BACKOFF;
    f->cap = (int)T - 1;
    f->cap_until = omp_get_wtime() + f->backoff;
    f->backoff = f->backoff < 64.0 ? 2.0 * f->backoff : 64.0; /* the load persists */
#endif
    f->cap_eff = busy / (busy + waited);
    f->recut = 1;
    if (!f->cap_logged) f->cap_logged = 1;
    return;
  }
  if (worst > 1.02 * mean && mean > 0) {
    for (size_t t = 0; t < T; t++)
      f->rate[t] = f->work[t] > 0 ? f->busy[t] / f->work[t] : 0.0;
    f->recut = 1;
  } else {
    for (size_t t = 0; t < T; t++) f->busy[t] = f->waits[t] = 0.0;
    f->busy_steps = 0;
    if (f->nth == f->want) f->backoff = ESF_FUSED_BACKOFF; /* all threads work well */
  }
}

/* Step 0's part that depends on the lists only (not redone for a re-cut): each
 * particle's pair block and wall candidates, and the one material. */
static void index_pairs(esf_sim *s, esf_fused *f) {
  const esf_particles *p = &s->p;
  const esf_candidates *c = &s->nb.pp, *cw = &s->nb.pw;
  const size_t n = p->n, m = c->n;
  memset(f->astart, 0, (n + 1) * sizeof(size_t));
  memset(f->wstart, 0, (n + 1) * sizeof(size_t));
  for (size_t k = 0; k < m; k++) f->astart[c->a[k] + 1]++;
  for (size_t k = 0; k < cw->n; k++) f->wstart[cw->a[k] + 1]++;
  for (size_t i = 0; i < n; i++) {
    f->astart[i + 1] += f->astart[i];
    f->wstart[i + 1] += f->wstart[i];
  }
  f->m0 = n ? p->material[0] : -1;
  for (size_t i = 1; i < n && f->m0 >= 0; i++)
    if (p->material[i] != f->m0) f->m0 = -1;
}

/* Each pair's sqrt(m*), m* = ma mb / (ma + mb), for the dashpots: once per build
 * rather than per step (the operations pair_batch.c's lanes did, so the same bits). */
static void reduced_masses(esf_sim *s, esf_fused *f, int nth) {
  const esf_particles *p = &s->p;
  const esf_candidates *c = &s->nb.pp;
  const long mm = (long)c->n;
#pragma omp parallel for num_threads(nth) schedule(static)
  for (long k = 0; k < mm; k++) {
    const double ma = p->mass[c->a[k]], mb = p->mass[c->b[k]];
    f->sm[k] = sqrt(ma * mb / (ma + mb));
  }
}

/* The ranges worth running for `want` threads: one per ESF_FUSED_MIN_WORK (or
 * cfg.range_work) units of
 * the step's estimated work, at least one, at most want (a small scene would lose more
 * to the ranges' handoffs than the threads gain). */
static int ranges_for(const esf_sim *s, const esf_fused *f, size_t n, int want) {
  const esf_candidates *c = &s->nb.pp;
  const size_t least =
      s->cfg.range_work > 0 ? (size_t)s->cfg.range_work : ESF_FUSED_MIN_WORK;
  size_t total = 0;
  for (size_t i = 0; i < n; i++) total += work_of(f, c, i);
  size_t r = total / least;
  if ((s->led.on || s->cfg.autod.on || s->walls.gforce) && r > esf_ledger_nblocks(n))
    r = esf_ledger_nblocks(n); /* whole blocks */
  return r < 1 ? 1 : r < (size_t)want ? (int)r : want;
}

/* Step 0: indices for the current lists, and the ranges for up to `want` threads. */
int esf_fused_index(esf_sim *s, esf_fused *f, int want, esf_error *err) {
  const esf_particles *p = &s->p;
  const esf_candidates *c = &s->nb.pp;
  const size_t n = p->n, m = c->n;
  if (m > f->cap_k) {
    if (!grow((void **)&f->list[0], m, sizeof(uint32_t)) ||
        !grow((void **)&f->list[1], m, sizeof(uint32_t)) ||
        !grow((void **)&f->idle, m, sizeof(uint32_t)) ||
        !grow((void **)&f->sm, m, sizeof(double)))
      return esf_fail(err, ESF_ENOMEM, "out of memory for %zu contact candidates", m);
    f->cap_k = m;
  }
  if (n + 1 > f->cap_n) { /* acc: one line per particle (its contents were synced) */
    double *acc = esf_lines_realloc(f->acc, 0, (n + 1) * ESF_FUSED_ACC * sizeof(double));
    if (acc) f->acc = acc;
    if (!acc || !grow((void **)&f->astart, n + 1, sizeof(size_t)) ||
        !grow((void **)&f->wstart, n + 1, sizeof(size_t)))
      return esf_fail(err, ESF_ENOMEM, "out of memory for %zu particle ranges", n);
    f->cap_n = n + 1;
  }
  /* new lists (else the same lists re-cut, or cut for another T) */
  const int fresh = f->np != n || f->built != s->nb.builds;
  if (fresh) index_pairs(s, f);
  const int nth = ranges_for(s, f, n, want);
  if (fresh) reduced_masses(s, f, nth);
  const size_t T = (size_t)nth;
  if (f->nth != nth || fresh) f->recut = 0;
  if (!grow((void **)&f->bout, T + 1, sizeof(size_t)) ||
      !grow((void **)&f->binstart, T + 1, sizeof(size_t)) ||
      !grow((void **)&f->rlo, T + 1, sizeof(size_t)) ||
      !grow((void **)&f->busy, T, sizeof(double)) ||
      !grow((void **)&f->waits, T, sizeof(double)) ||
      !grow((void **)&f->work, T, sizeof(double)) ||
      !grow((void **)&f->rate, T, sizeof(double)))
    return esf_fail(err, ESF_ENOMEM, "out of memory");
  if (f->nth != nth || !f->rr) {
    esf_fused_range *rr = esf_lines_realloc(f->rr, 0, T * sizeof *rr);
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
  size_t *wt = calloc(n ? n : 1, sizeof *wt); /* cut_ranges' weights */
  if (!wt) return esf_fail(err, ESF_ENOMEM, "out of memory for %zu particle ranges", n);
  const size_t align =
      (s->led.on || s->cfg.autod.on || s->walls.gforce) && ESF_FUSED_FEATURES
          ? ESF_LEDGER_BLOCK
          : 1;
  cut_ranges(f, c, wt, n, T, align, esf_sim_own_lo(s));
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
        !grow((void **)&f->slot_a, nb, ESF_FUSED_SLOT_A * sizeof(double)))
      return esf_fail(err, ESF_ENOMEM, "out of memory for %zu boundary pairs", nb);
    double *sl =
        esf_lines_realloc(f->slot, 0, nb * ESF_FUSED_SLOT * sizeof(double)); /* aligned */
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
  const int led = s->led.on && ESF_FUSED_FEATURES;
  if (led && nb > f->cap_lb) {
    double *l0 = esf_lines_realloc(f->lslot, 0, nb * ESF_FUSED_LSLOT * sizeof(double));
    if (l0) f->lslot = l0;
    double *l1 =
        l0 ? esf_lines_realloc(f->lslot_a, 0, nb * ESF_FUSED_LSLOT * sizeof(double))
           : NULL;
    if (l1) f->lslot_a = l1;
    if (!l1) return esf_fail(err, ESF_ENOMEM, "out of memory for %zu boundary pairs", nb);
    f->cap_lb = nb;
  } else if (!led) {
    free(f->lslot);
    free(f->lslot_a);
    f->lslot = f->lslot_a = NULL;
    f->cap_lb = 0;
  }
  for (size_t j = 0; j < nb; j++) esf_fused_slot_clear(f, j); /* zero unless touching */
  f->built = s->nb.builds;
  f->np = n;
  f->nth = nth;
  f->want = want;
  return ESF_OK;
}
