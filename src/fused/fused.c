/* fused.c — the fused, threaded leapfrog step (fused.h).
 *
 * Physics: exactly the leapfrog of integrators/leapfrog.c with the linear law of
 * contact/contact_linear.c (docs/physics.md#linear-springdashpot-law), written out
 * for the pair loop without the ledger's by-products, eight pairs at a time in vector
 * lanes (pair_batch.c). State on entry: x_n, v_{n-1/2}, w_{n-1/2}, candidate lists
 * valid for x_n, history at t_{n-1}. The particles are cut into T contiguous ranges,
 * one per thread; as the pair list is sorted by (a, b), a < b, the pairs whose a lies
 * in range t form one block, and a pair whose b lies in a higher range is a boundary
 * pair. One call runs up to nmax steps in one parallel region, after esf_fused_index
 * (fused_ranges.c) when the lists, T or the balance changed; each range's step:
 * boundary pairs into slots, screening, pair forces, walls, kick and drift (run_range).
 * Invariant: every particle receives its pair forces in ascending pair index k, the
 * order of the serial scatter in model/forces.c, whatever T (incoming slots, interior
 * batches and outgoing slots are merged in k), and every other sum is per particle;
 * so the results are the same bits on any thread count. Failures are reported for the
 * lowest pair or particle index, and a range with a failing pair does not move.
 * esf_fused_forces: the same passes for one evaluation at a given state (Verlet, the
 * ODE methods), without kick and drift, committing or as a trial. */
#include "fused/fused_impl.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "loads/drag.h"
#include "loads/events.h"
#include "loads/servo.h"
#include "model/forces.h"
#include "model/model.h"
#include "par/par.h"

/* idle candidates range 0 screens between looks at the others */
#define SCREEN_CHUNK 256

/* The kernels for this CPU: the widest instruction set it has among those built, or
 * the one `want` names (base, avx2, avx512: for tests and comparisons). */
static int pick_kernels(const char *want, const esf_fused_kernels **out, esf_error *err) {
  const esf_fused_kernels *all[3] = {&esf_fused_kernels_base, NULL, NULL};
  int have[3] = {1, 0, 0};
#ifdef ESF_FUSED_X86
  __builtin_cpu_init();
  all[1] = &esf_fused_kernels_avx2;
  all[2] = &esf_fused_kernels_avx512;
  have[1] = __builtin_cpu_supports("avx2");
  have[2] = have[1] && __builtin_cpu_supports("avx512f") &&
            __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512vl") &&
            __builtin_cpu_supports("avx512bw");
#endif
  *out = all[0];
  for (int i = 0; i < 3; i++) {
    if (!all[i]) continue;
    if (want && *want && strcmp(want, all[i]->isa) == 0) {
      if (!have[i])
        return esf_fail(err, ESF_EINPUT,
                        "ESF_ISA=%s: this CPU lacks that instruction set", want);
      *out = all[i];
      return ESF_OK;
    }
    if (have[i]) *out = all[i];
  }
  if (want && *want)
    return esf_fail(err, ESF_EINPUT,
                    "ESF_ISA=%s: not a kernel set of this build (base%s)", want,
                    all[1] ? ", avx2, avx512" : "");
  return ESF_OK;
}

int esf_fused_vv_drift(const char *isa, esf_vv_drift_fn *out, esf_error *err) {
  const esf_fused_kernels *k;
  const int rc = pick_kernels(isa, &k, err);
  *out = rc ? NULL : k->vv_drift;
  return rc;
}

int esf_fused_create(esf_fused **out, const char *isa, esf_error *err) {
  *out = esf_lines_realloc(NULL, 0, sizeof **out); /* go: a line of its own */
  if (!*out) return esf_fail(err, ESF_ENOMEM, "out of memory");
  memset(*out, 0, sizeof **out);
  (*out)->built = -1;
  (*out)->lists_stamp = -1;
  const int rc = pick_kernels(isa, &(*out)->k, err);
  if (rc) esf_fused_free(out);
  return rc;
}

void esf_fused_free(esf_fused **f) {
  if (!f || !*f) return;
  esf_fused *q = *f;
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
  free(q->lslot);
  free(q->lslot_a);
  free(q->lrows);
  free(q->bout);
  free(q->bin);
  free(q->binstart);
  free(q->rlo);
  free(q->busy);
  free(q->waits);
  free(q->work);
  free(q->rate);
  free(q->rr);
  free(q);
  *f = NULL;
}

void esf_fused_trim(esf_sim *s, esf_fused *f) {
  if (!f) return;
  void **big[6] = {(void **)&f->list[0], (void **)&f->list[1], (void **)&f->idle,
                   (void **)&f->sm,      (void **)&f->astart,  (void **)&f->wstart};
  for (int q = 0; q < 6; q++) { /* first: p.f, p.t then come in their place */
    free(*big[q]);
    *big[q] = NULL;
  }
  f->cap_k = f->cap_n = 0;
  f->built = -1; /* esf_fused_run indexes again (syncing first when acc is kept) */
  f->lists_stamp = -1;
  esf_error e;
  if (esf_sim_forces_sync(s, &e)) return; /* acc kept when p.f, p.t cannot come */
  free(f->acc);
  f->acc = NULL;
}

const char *esf_fused_isa(const esf_fused *f) { return f->k->isa; }

static int minimal_ok(const esf_sim *s) {
  return !s->mats.any_cohesion && !s->mats.all_hertz &&
         s->cfg.tframe == ESF_TFRAME_ROTATE && s->cfg.dim == 3 && !s->local &&
         s->alpha_r == 0.0 && s->alpha_t == 0.0 && !s->walls.moving;
}

const char *esf_fused_refusal(const esf_sim *s) {
  if (!s->cfg.fused) return "integrator.fused: false";
  if (s->led.on && !ESF_FUSED_FEATURES) return "the energy ledger (a minimal build)";
  if (s->tally || s->nb.pp.vc0 || s->nb.pp.xs || s->nb.pw.xs)
    return "the integrator's own tallies or history";
  if (!s->mats.particles_fused) return "a contact law the fused step has no kernel for";
  if (s->bonds.on && !ESF_FUSED_FEATURES) return "bonds (a minimal build)";
  if ((s->walls.gforce || s->drag) && !ESF_FUSED_FEATURES)
    return "servo walls or the fluid force (a minimal build)";
  if (!ESF_FUSED_FEATURES && !minimal_ok(s)) return "a feature of a minimal build";
  return NULL;
}

int esf_fused_eligible(const esf_sim *s) { return esf_fused_refusal(s) == NULL; }

/* Range t's steps of one call (esf_fused_run), each step:
 *   0. esf_fused_index (fused_ranges.c), at a call's start when the lists, T or the
 *      balance changed: pair blocks, wall candidates, ranges, boundary pairs (run by
 *      esf_fused_run before the parallel region);
 *   1. from the second step on, waits for range 0's word and the higher ranges' done
 *      flags (fused_sync.c: esf_fused_decide, esf_fused_wait); esf_fused_boundary
 *      (fused_slots.c) computes its boundary pairs into slots, then its ready flag;
 *   2. esf_fused_screen (fused_lists.c) finds its new contacts among the idle
 *      candidates; waits for the lower ranges' ready flags; esf_fused_pairs
 *      (fused_pairs.c) sums its pair forces; esf_fused_kick_range (fused_kick.c) adds
 *      its walls, kicks and drifts; its results and its done flag. */
static void run_range(esf_sim *s, esf_fused *f, const esf_fused_burst *B, size_t t) {
  esf_fused_range *me = f->rr + t;
  const size_t T = (size_t)f->nth, lo = f->rlo[t], hi = f->rlo[t + 1];
  const size_t k0 = f->astart[lo], k1 = f->astart[hi];
  esf_fused_lists L = {
      .tl = f->list[0] + k0, .sq = f->list[1] + k0, .il = f->idle + k0, .blk = k1 - k0};
  if (B->lists_kept) /* the same lists as from the flags, in the same order */
    L = me->L;
  else
    esf_fused_lists_from_flags(s, k0, k1, hi, &L);
#ifdef _OPENMP
  const int timed = T > 1; /* the threads' balance and back-off (one range: neither) */
#endif
  long i = 0;
  for (; i < B->steps; i++) {
    const long e = B->e0 + i;
#ifdef _OPENMP
    const double t0 = timed ? omp_get_wtime() : 0.0;
#endif
    double waited = 0.0;
    size_t nn = 0, nt_pp = 0, nt_pw = 0;
    uint32_t *top = L.tl + L.blk; /* the new contacts, downward */
    size_t j = 0;                 /* idle candidates screened: il[0 .. j) */
    if (t > 0) {                  /* ahead of the word from the burst's second step on */
      nn = esf_fused_screen(s, L.il, 0, L.ni, top, 0);
      j = L.ni;
    }
    if (i > 0 && t == 0) { /* screens while the others finish the step before */
      while (j < L.ni && !esf_fused_all_done(f, e - 1)) {
        const size_t j1 = L.ni - j > SCREEN_CHUNK ? j + SCREEN_CHUNK : L.ni;
        nn += esf_fused_screen(s, L.il, j, j1, top, nn);
        j = j1;
      }
      if (esf_fused_decide(f, B, e, &waited)) break;
    }
    if (i > 0 && t > 0) {
      waited += esf_fused_wait(&f->go, 2 * e);
      if (atomic_load_explicit(&f->go, memory_order_relaxed) & 1) break;
      for (size_t u = t + 1; u < T; u++) waited += esf_fused_wait(&f->rr[u].done, e - 1);
    }
    /* the ledger's stored energies: on the burst's last step (what is read after it)
       and the first one it books */
    const int light = B->bc_light && i + 1 < B->need && (i > 0 || B->started);
    const int after = /* step i - 1 light too, its rows left zero */
        i > 1 || (i > 0 && B->started) || (i == 0 && B->pre_zeroed);
    const esf_pair_batch_ctx *bc = !light                            ? B->bc
                                   : after && B->K_light->clear_rows ? B->bc_light_z
                                                                     : B->bc_light;
    const esf_fused_kick *K = light ? B->K_light : B->K;
    esf_fused_out o = ESF_FUSED_OUT_NONE;
    o.bad_pair = f->k->boundary(s, f, bc, f->bout[t], f->bout[t + 1], &nt_pp);
    if (o.bad_pair != SIZE_MAX) atomic_store_explicit(&f->bfail, e, memory_order_relaxed);
    atomic_store_explicit(&me->ready, e, memory_order_release);
    if (j < L.ni)
      nn += esf_fused_screen(s, L.il, j, L.ni, top, nn); /* range 0: the rest */
    /* their slots written, our particles no longer read: a wait the range has every
       step, counted as its work, so that the balance gives it less of the rest */
    for (size_t u = 0; u < t; u++) esf_fused_wait(&f->rr[u].ready, e);
    const size_t cnt = esf_fused_merge_new(L.sq, L.tl, L.nt, top, nn);
    size_t ne, kept;
    const size_t bad = f->k->pairs(s, f, bc, t, lo, hi, L.sq, cnt, L.tl, &ne, &kept);
    L.ni =
        esf_fused_idle_update(L.il, L.ni, top, nn, L.tl, ne); /* ended: in tl, free now */
    uint32_t *const tl = L.tl;
    L.tl = L.sq; /* the contacts that remain */
    L.sq = tl;
    L.nt = kept;
    nt_pp += kept;
    if (bad < o.bad_pair) o.bad_pair = bad;
    if (o.bad_pair == SIZE_MAX &&
        atomic_load_explicit(&f->bfail, memory_order_relaxed) !=
            e) { /* an MPI run's ghosts are not integrated here (par/par.h) */
      const size_t olo = esf_sim_own_lo(s), ohi = esf_sim_own_hi(s);
      const size_t klo = lo > olo ? lo : olo, khi = hi < ohi ? hi : ohi;
      if (klo < khi) f->k->kick_range(s, f, K, klo, khi, &o, &nt_pw);
    }
    o.nt = nt_pp + nt_pw;
    me->out = o;
#ifdef _OPENMP
    if (timed) {
      const double spent = omp_get_wtime() - t0;
      f->busy[t] += spent - waited; /* range t is this thread's alone */
      f->waits[t] += waited;
      if (t == 0) f->inside += spent;
    }
#endif
    atomic_store_explicit(&me->done, e, memory_order_release);
  }
  me->L = L;
  if (t == 0) {
    f->taken = i;
    f->decided = i < B->steps;
  }
}

/* Thread me of got runs its range, or (fewer threads than ranges) one step of the ranges
 * me, me + got, ... in ascending order. */
static void run_ranges(esf_sim *s, esf_fused *f, const esf_fused_burst *B, size_t me,
                       size_t got, size_t T) {
  if (got == T) {
    run_range(s, f, B, me);
  } else {
    esf_fused_burst B1 = *B;
    B1.steps = 1;
    for (size_t t = me; t < T; t += got) run_range(s, f, &B1, t);
  }
}

/* Whether the ledger's rows DT and MDT stay +0 in the scene (core/ledger.h's
 * ESF_LEDGER_NO_T): no tangential dashpot (beta = 0 and every pair's ct_factor 0, the
 * linear law), no bonds, no Hertz springs' stiffness change. */
static int ledger_no_t(const esf_sim *s) {
  const esf_materials *m = &s->mats;
  if (s->beta > 0 || s->bonds.on || !m->all_linear) return 0;
  for (int i = 0; i < m->n * m->n; i++)
    if (m->pair[i].ct_factor != 0.0) return 0;
  return 1;
}

/* The light steps' rows (esf_fused_burst): when the scene has no rolling resistance
 * and the walls' fast pass, rows of their own with only the rows they use
 * (ESF_LR_DISS doubles a particle, ESF_LR_DISS_N without DT, MDT: the first of
 * core/ledger.h's, at the same offsets; W, +0 at static walls, neither written nor
 * read), which the wall pass's light variant writes; else the full rows. */
static int light_rows(esf_sim *s, esf_fused *f, esf_pair_batch_ctx *bc, esf_fused_kick *K,
                      esf_error *err) {
  if (s->mats.any_rolling || K->wall_pass != esf_wall_fast_particle) return ESF_OK;
  const size_t n = s->p.n;
  if (n > f->cap_lr || !f->lrows) {
    const size_t cap = n > 2 * f->cap_lr ? n : 2 * f->cap_lr;
    double *r = esf_lines_realloc(f->lrows, 0, (cap ? cap : 1) * ESF_LR_DISS * sizeof *r);
    if (!r) return esf_fail(err, ESF_ENOMEM, "out of memory (the ledger's light rows)");
    f->lrows = r;
    f->cap_lr = cap;
  }
  bc->rows = K->rows = f->lrows;
  bc->no_w = K->lk.no_w = 1; /* static walls (the fast pass's): their side +0 */
  bc->lr = K->lr = bc->no_t ? ESF_LR_DISS_N : ESF_LR_DISS;
  K->wall_pass = bc->no_t ? esf_wall_fast_particle_light_n : esf_wall_fast_particle_light;
  K->clear_rows = K->plain_led && K->xref; /* kick_ledger_light's (fused_kick.c) */
  return ESF_OK;
}

/* An evaluation whose F, M stay in the accumulators (esf_fused_eval's lazy). */
static int lazy_eval(const esf_sim *s, const esf_fused_eval *ev) {
  return ev->lazy && ev->acc && !ev->trial && s->cfg.dim == 3 && !s->par && !s->local;
}

/* esf_fused_run's steps, or with ev one force evaluation (esf_fused_forces): ev's
 * interval and mode, the particle pass writing p.f, p.t (no kick, no drift), *nt the
 * touching contacts, none of the step's counters advanced. */

static int run_calls(esf_sim *s, esf_fused *f, long nmax, long *taken,
                     const esf_fused_eval *ev, size_t *nt, esf_error *err) {
  esf_particles *p = &s->p;
  int rc;
  *taken = 0;
  int want = s->cfg.threads > 0 ? s->cfg.threads : 1;
#ifdef _OPENMP
  if (f->cap > 0 && omp_get_wtime() < f->cap_until)
    want = f->cap < want ? f->cap : want; /* the threads waited more than they worked */
  else
    f->cap = 0;
#endif
  /* the ranges' lists as the last call left them, when nothing since has touched the
     flags (another evaluation counts in rhs_evals) nor cut the ranges anew */
  int lists_kept = f->lists_stamp == s->rhs_evals && !s->par;
  f->lists_stamp = -1;
  if (f->built != s->nb.builds || f->np != p->n || f->want != want || f->recut) {
    /* acc moves only when it grows (a re-cut keeps it: no p.f, p.t beside it) */
    rc = p->n + 1 > f->cap_n ? esf_sim_forces_sync(s, err) : ESF_OK;
    if (!rc) rc = esf_fused_index(s, f, want, err);
    if (rc) return rc;
    lists_kept = 0;
  }
  if (ev && !lazy_eval(s, ev)) { /* an evaluation writes p.f, p.t itself (a trial with
                                      accelerations: no) */
    if ((rc = esf_sim_forces_sync(s, err))) return rc;
  } else if (ev) { /* lazy: the last commit's F, M superseded */
    s->ft_lazy = NULL;
  } else if (!s->ft_lazy)      /* the steps write F_n, M_n into acc: not held beside it */
    esf_sim_forces_release(s); /* (docs/performance.md#memory) */
  const int nth = f->nth;      /* the ranges worth running (fused_ranges.c) */
  const int ledger = s->led.on;      /* per-particle rows and blocks (core/ledger.h) */
  const int autod = s->cfg.autod.on; /* adaptive damping: the blocks' kinetic energies */
  int drag_on = 0;
  if (s->drag) { /* the fluid force: its set-up at x_n (porosity grid), then per particle
                  */
    rc = esf_drag_prepare(s, p->x, &drag_on, err);
    if (rc) return rc;
  }
  if (s->walls.gforce) { /* servo walls: per-block sums of their contacts (servo.h) */
    rc = esf_servo_blocks(s, 0, err);
    if (rc) return rc;
  }
  if (ledger || autod) {
    rc = esf_sim_ledger_room(s, 0, err);
    if (rc) return rc;
  }
  const size_t T = (size_t)nth;
  const double dt = ev ? ev->dt : s->dt, h = 0.5 * s->dt;
  const esf_candidates *cp = &s->nb.pp;
  const esf_pair_batch_ctx bc = {
      .x = p->x,
      .v = p->v,
      .w = p->w,
      .radius = p->radius,
      .material = p->material,
      .mt = &s->mats,
      .one = f->m0 >= 0 ? s->mats.pair + f->m0 * (s->mats.n + 1) : NULL,
      .a = cp->a,
      .b = cp->b,
      .h = cp->h,
      .touch = cp->touch,
      .sm = f->sm,
      .beta = s->beta,
      .dt = dt,
      .max_overlap = s->cfg.max_overlap,
      .rotate = !ESF_FUSED_FEATURES || s->cfg.tframe == ESF_TFRAME_ROTATE,
      .cohesion = ESF_FUSED_FEATURES && s->mats.any_cohesion,
      .hertz = ESF_FUSED_FEATURES && s->mats.all_hertz,
      .hertz_cst = s->mats.hertz_constant,
      .rows = ledger ? s->led_rows : NULL,
      .lr = s->led_lr,
      .no_t = ledger && ledger_no_t(s),
      .bond = s->bonds.on ? cp->bond : NULL,
      .roll = cp->roll,
      .mass = p->mass,
      .inertia = p->inertia,
      .roll_cdt = s->mats.rolling_model == ESF_ROLL_CDT,
      .broken = &f->broken,
      .own_lo = esf_sim_own_lo(s),
      .own_hi = esf_sim_own_hi(s),
      .trial = ev && ev->trial,
      .vc0 = ev ? cp->vc0 : NULL,
      .img = cp->img,
      .le = cp->img && s->cfg.per.le,
      .le_flow = s->cfg.per.flow,
      .le_grad = s->cfg.per.grad,
      .le_off = cp->le_off,
      .le_vel = s->cfg.per.le ? esf_periodic_le_speed(&s->cfg.per) : 0,
      .plen = {cp->plen[0], cp->plen[1], cp->plen[2]}};
  const double cr0 = 1.0 - s->alpha_r * h, cr1 = 1.0 / (1.0 + s->alpha_r * h),
               ct0 = 1.0 - s->alpha_t * h, ct1 = 1.0 / (1.0 + s->alpha_t * h);
  esf_fused_kick K = {
      .dt = dt,
      .cr0 = cr0,
      .cr1 = cr1,
      .ct0 = ct0,
      .ct1 = ct1,
      .lc = s->cfg.local_coef,
      .dim2 = s->cfg.dim == 2,
      .plain = cr0 == 1.0 && cr1 == 1.0 && ct0 == 1.0 && ct1 == 1.0 && !s->local &&
               s->cfg.dim == 3 && !ledger && !autod && !s->drag,
      .plain_led = cr0 == 1.0 && cr1 == 1.0 && ct0 == 1.0 && ct1 == 1.0 && !s->local &&
                   s->cfg.dim == 3 && ledger && !autod && !s->drag &&
                   !s->mats.any_rolling,
      .wall_pass = ev ? esf_wall_pass_eval(s, ev->trial) : esf_wall_pass_select(s),
      .forces_only = ev != NULL,
      .acc = ev && !s->par && !lazy_eval(s, ev) ? ev->acc : NULL, /* MPI: after the
                                                  call (own range only); lazy: none */
      .lazy = ev && lazy_eval(s, ev),
      .dw = ev ? ev->dw : NULL,
      .ar = ev && ev->with_global ? s->alpha_r : 0.0,
      .at = ev && ev->with_global ? s->alpha_t : 0.0,
      .ft_skip = ev && (ev->trial || lazy_eval(s, ev)),
      .loc = s->local,
      .xref = s->nb.xref,
      .dom_lo = s->nb.dom_lo,
      .dom_hi = s->nb.dom_hi,
      .rows = ledger ? s->led_rows : NULL,
      .blocks = ledger || autod ? s->led_blocks : NULL,
      .kbase = esf_sim_own_lo(s),
      .lr = s->led_lr,
      .drag = s->drag,
      .drag_on = drag_on,
      .lk = {
          .dt = dt, .alpha_r = s->alpha_r, .alpha_t = s->alpha_t, .g = s->cfg.gravity}};
  K.lk.roll = s->mats.any_rolling; /* the rows carry rolling resistance */
  K.lk.no_t = bc.no_t;
  /* more than one step only when the lists' check between steps needs nothing but
     the displacements (esf_neighbor_check) and nothing else happens between them */
  const int many = s->nb.xref && s->nb.nref == p->n && !s->walls.moving &&
                   !esf_events_pending(s->events) && !autod &&
                   !s->drag;   /* alpha, the porosity: updated after every step */
  esf_pair_batch_ctx bcl = bc; /* the light steps' (esf_fused_burst) */
  esf_fused_kick Kl = K;
  bcl.light = 1;
  Kl.lk.light = 1;
  if (ledger && !autod && (rc = light_rows(s, f, &bcl, &Kl, err))) return rc;
  if (ledger && !autod && !s->par) /* (MPI: the ghosts' rows are not kicked) */
    Kl.clear_rows = 1;
  /* the last call's last step was light and left these rows zero, nothing since */
  const int pre_zeroed = Kl.clear_rows && f->z_rows == Kl.rows && f->z_step == s->step &&
                         f->z_n == p->n && f->z_builds == s->nb.builds && !ev;
  f->z_rows = NULL;
  esf_pair_batch_ctx bclz = bcl;
  bclz.zeroed = 1;
  const esf_fused_burst B = {
      .bc = &bc,
      .K = &K,
      .bc_light = ledger && !autod ? &bcl : NULL,
      .K_light = &Kl,
      .bc_light_z = &bclz,
      .started = s->led.started,
      .pre_zeroed = pre_zeroed,
      .lists_kept = lists_kept,
      .e0 = f->epoch + 1,
      .steps = many && nmax > 1 && !ev && !s->par ? nmax : 1,
      .need = ev ? 1 : nmax,
      .lim2 = esf_neighbor_limit2(&s->nb),
      .led = ledger ? &s->led : NULL,
      .nblocks = esf_ledger_nblocks(esf_sim_own_hi(s) - esf_sim_own_lo(s))};
  f->nt_sum = 0;
  f->inside = 0.0;
  atomic_store_explicit(&f->broken, 0, memory_order_relaxed);
  f->taken = 0;
  f->decided = 0;

#ifdef _OPENMP
  const double t_start = nth > 1 ? omp_get_wtime() : 0.0, gap = t_start - f->t_left;
  if (f->t_left > 0 && nth > 1 && gap < 0.5 * f->t_step) /* not a frame write */
    f->busy[0] += gap;
#endif
  if (nth == 1) { /* no parallel region: its start costs a tiny scene more than a step */
    run_ranges(s, f, &B, 0, 1, T);
  } else {
#pragma omp parallel num_threads(nth)
    {
#ifdef _OPENMP
      const size_t me = (size_t)omp_get_thread_num(), got = (size_t)omp_get_num_threads();
#else
      const size_t me = 0, got = 1;
#endif
      run_ranges(s, f, &B, me, got, T);
    }
  }
  const long n = f->taken;
  f->epoch += n;
  /* the last step's results (a failure stops the burst with the failing step) */
  esf_fused_out r;
  const int fail = esf_fused_gather(f, &r);
  if (!f->decided) {
    if (!fail) f->nt_sum += r.nt;
    if (!fail && ledger && n > 0) esf_par_ledger_step(s, s->led_blocks, B.nblocks);
    esf_fused_balance(f, T);
  }
  const long ok = fail ? n - 1 : n; /* steps completed without failure */
  if (ev) {
    s->rhs_evals++;
    *nt = f->nt_sum;
  } else {
    s->step += ok;
    s->t = (double)s->step * s->dt;
    s->rhs_evals += ok;
    s->contacts_sum += (double)esf_par_touching(s, f->nt_sum);
  }
  /* a trial's batches drop the pairs apart from its lists, not from the flags */
  if (!fail && !(ev && ev->trial) && !s->par) f->lists_stamp = s->rhs_evals;
  s->bonds.broken += atomic_load_explicit(&f->broken, memory_order_relaxed);
  *taken = ok;
  if (!fail && !ev && n > 0 && B.bc_light && Kl.clear_rows && n < B.need &&
      (n > 1 || B.started)) { /* the last step light: its rows left zero */
    f->z_rows = Kl.rows;
    f->z_step = s->step;
    f->z_n = p->n;
    f->z_builds = s->nb.builds;
  }
  /* the accumulators hold F_n, M_n; on failure they are partly overwritten, and p.f,
   * p.t keep what the last sync left (an evaluation wrote p.f, p.t itself) */
  s->ft_lazy = fail || (ev && !lazy_eval(s, ev)) ? NULL : f->acc;
  if (fail && (rc = esf_sim_forces_room(s, err))) /* p.f, p.t zero */
    return rc;
  if (r.bad_pair != SIZE_MAX) {
    const esf_candidates *c = &s->nb.pp;
    uint32_t a = c->a[r.bad_pair], b = c->b[r.bad_pair];
    double d[3], xb[3];
    v3_sub(d, esf_candidates_xb(c, r.bad_pair, p->x, xb), p->x + 3 * (size_t)a);
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
  if (ledger) s->led_time = (double)(s->step - 1) * s->dt; /* the last step's t_n */
  if (f->cap_logged == 1) {                                /* the first time only */
    esf_sim_log(s,
                "t = %.6g s: the fused step's %d threads worked %.0f%% of the time and "
                "waited the rest (other programs on the cores, or too little work a "
                "step): one thread fewer for %.0f s at a time when it happens again "
                "(the results are the same on any thread count)",
                s->t, f->cap + 1, 100.0 * f->cap_eff, ESF_FUSED_BACKOFF);
    f->cap_logged = 2;
  }
  if (autod && n > 0) esf_par_adapt_damping(s, s->led_blocks, B.nblocks);
  if (s->walls.gforce && n > 0) esf_par_servo(s); /* the walls' velocities */
  if (!ev) {                                      /* an evaluation moved nothing */
    s->nb.max_disp2 = r.max2;
    s->nb.escaped = r.escaped;
    s->nb.disp_valid = K.xref && !r.nonfinite;
    const int check =
        s->cfg.stability != ESF_STAB_OFF && s->step % s->cfg.stability_every == 0;
    if ((s->nb.disp_valid && (r.max2 > B.lim2 || r.escaped)) || check)
      esf_fused_trim(s, f); /* a rebuild or a stability check is next */
  }
#ifdef _OPENMP
  f->t_left = 0.0; /* one range: no clock read (a tiny scene's step is a few of them) */
  if (nth > 1) {
    f->t_left = omp_get_wtime();
    f->t_step = (f->t_left - t_start) / (double)(n > 0 ? n : 1);
    if (f->t_left - t_start > f->inside) /* the region's start and end: waits */
      f->waits[0] += f->t_left - t_start - f->inside;
  }
#endif
  return ESF_OK;
}

int esf_fused_run(esf_sim *s, esf_fused *f, long nmax, long *taken, esf_error *err) {
  return run_calls(s, f, nmax, taken, NULL, NULL, err);
}

const char *esf_fused_eval_refusal(const esf_sim *s, int ode) {
  if (!s->cfg.fused) return "integrator.fused: false";
  if (s->led.on) return "the energy ledger (its tallies: the general path's)";
  if (s->cfg.history == ESF_HIST_STATE) return "integrator.history: state";
  if (!s->mats.particles_fused) return "a contact law the fused step has no kernel for";
  if (s->bonds.on || s->walls.gforce || s->drag)
    return "bonds, servo walls or the fluid force";
  if (ode && s->mats.any_rolling) return "rolling resistance (its carry)";
  if (!ESF_FUSED_FEATURES && !minimal_ok(s)) return "a feature of a minimal build";
  return NULL;
}

int esf_fused_forces(esf_sim *s, esf_fused *f, const esf_fused_eval *ev, size_t *touching,
                     esf_error *err) {
  esf_particles *p = &s->p;
  double *const x = p->x, *const v = p->v, *const w = p->w;
  p->x = (double *)ev->x; /* the passes read the state there (restored below) */
  p->v = (double *)ev->v;
  p->w = (double *)ev->w;
  long taken;
  size_t nt = 0;
  const int rc = run_calls(s, f, 1, &taken, ev, &nt, err);
  if (!rc && ev->acc && s->par) /* the pass left them out (fused.c's K.acc) */
    esf_sim_accel(s, ev->v, ev->w, ev->acc, ev->dw, NULL, ev->with_global, 1);
  p->x = x;
  p->v = v;
  p->w = w;
  if (touching) *touching = nt;
  return rc;
}

int esf_fused_threads(const esf_fused *f) { return f->nth > 1 ? f->nth : 1; }
