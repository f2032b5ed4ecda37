/* fused_impl.h — the fused step's own state and the functions its files share (not
 * part of the library's interface: fused.h is). The order of one step and the
 * invariant that makes it thread-independent are in fused.c's prologue. */
#ifndef ESF_FUSED_IMPL_H
#define ESF_FUSED_IMPL_H

#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>

#include "core/sim.h"
#include "fused/fused_isa.h"
#include "fused/fused.h"
#include "fused/pair_batch.h"
#include "fused/wall_fast.h"
#include "util/lines.h"
#include "util/vec3.h"

/* The features a scene may switch on, compiled in or (ESF_MINIMAL: meson -Dfeatures=
 * minimal) out of the fused step; a build without them sends the scenes that use them
 * to the general path. */
#ifdef ESF_MINIMAL
#define ESF_FUSED_FEATURES 0
#else
#define ESF_FUSED_FEATURES 1
#endif

/* Estimated work a range must have to be worth a thread, in units of one screened
 * candidate (fused_ranges.c's work_of): below it a thread's handoffs cost more than
 * its share saves (docs/performance.md#threads-on-small-scenes). */
#define ESF_FUSED_MIN_WORK 1000
/* Below this efficiency (time worked over time worked or waited) the step drops a
 * thread for ESF_FUSED_BACKOFF seconds (esf_fused_balance;
 * docs/performance.md#threads-on-small-scenes) */
#define ESF_FUSED_MIN_EFF 0.5
#define ESF_FUSED_BACKOFF 2.0

/* the accumulators' stride: four-wide force, four-wide torque */
#define ESF_FUSED_ACC ESF_FT_STRIDE
/* A boundary pair's results, twice: what b's range reads (force on A, torque on B), one
 * line per pair in `slot`, and what a's range reads (force and torque on A) in
 * `slot_a`, which stays in a's core. Four doubles each, the last zero. */
#define ESF_FUSED_SLOT   8 /* per pair in slot: force on A, torque on B */
#define ESF_FUSED_SLOT_A 8 /* per pair in slot_a: force on A, torque on A */
#define ESF_FUSED_LSLOT                                                                  \
  32 /* with the ledger, per pair in lslot (B's) and lslot_a (A's): six ledger rows      \
        (core/ledger.h), eight with rolling resistance (ESF_PAIR_BATCH_LROWS) */

/* One range's results of a step. */
typedef struct esf_fused_out {
  size_t nt;                 /* touching contacts: pairs whose a is in it, wall ones */
  size_t bad_pair, bad_part; /* lowest failing pair, particle, or SIZE_MAX */
  double max2;               /* largest squared displacement since the build, m^2 */
  int nonfinite, escaped;
} esf_fused_out;

#define ESF_FUSED_OUT_NONE ((esf_fused_out){.bad_pair = SIZE_MAX, .bad_part = SIZE_MAX})

/* A range's interior pairs as two lists, contacts and idle candidates (fused_lists.c
 * describes the layout). */
typedef struct esf_fused_lists {
  uint32_t *tl, *sq, *il;
  size_t blk, nt, ni;
} esf_fused_lists;

/* One range's flags and the results of its latest step, a cache line of its own:
 * written by its thread, read by the others once the flag they wait for is up
 * (fused_sync.c). */
typedef struct esf_fused_range {
  _Alignas(ESF_LINE) _Atomic long ready; /* boundary pairs done for this step (epoch) */
  _Atomic long done;                     /* the whole step done, out written */
  esf_fused_out out;
  esf_fused_lists L; /* its lists at the end of the last call (esf_fused.lists_stamp) */
} esf_fused_range;

struct esf_fused_kick;

/* One instruction set's copy of the kernels (fused_isa.h, fused_kernels.c). */
typedef struct esf_fused_kernels {
  const char *isa; /* "base", "avx2", "avx512" */
  size_t (*boundary)(esf_sim *s, esf_fused *f, const esf_pair_batch_ctx *bc, size_t j0,
                     size_t j1, size_t *nt);
  size_t (*pairs)(esf_sim *s, esf_fused *f, const esf_pair_batch_ctx *bc, size_t t,
                  size_t lo, size_t hi, uint32_t *list, size_t cnt, uint32_t *ended,
                  size_t *ne, size_t *kept);
  void (*kick_range)(esf_sim *s, const esf_fused *f, const struct esf_fused_kick *K,
                     size_t lo, size_t hi, esf_fused_out *o, size_t *nt_pw);
  unsigned (*batch)(const esf_pair_batch_ctx *ctx, const uint32_t *k, int nl,
                    double out[ESF_BATCH][ESF_BATCH_OUT],
                    double lout[ESF_BATCH][ESF_BATCH_LOUT], unsigned *apart); /* tests */
  esf_vv_drift_fn vv_drift; /* velocity Verlet's particle pass (fused.h) */
} esf_fused_kernels;

extern const esf_fused_kernels esf_fused_kernels_base;
#ifdef ESF_FUSED_X86
extern const esf_fused_kernels esf_fused_kernels_avx2, esf_fused_kernels_avx512;
#endif

struct esf_fused {
  const esf_fused_kernels *k; /* the kernels for this CPU (esf_fused_create) */
  long built;                 /* nb.builds the indices below belong to (-1: none) */
  size_t np;                  /* particles the indices were made for */
  int nth;                    /* ranges (threads) the split was made for */
  int want;                   /* the threads asked for when it was made (nth <= want) */
  size_t cap_k;               /* pair capacity */
  size_t cap_n;               /* particle capacity */
  double *acc;       /* ESF_FUSED_ACC per particle: force (3, N), 0, torque (3, N m), 0 */
  uint32_t *list[2]; /* per pair, two buffers (esf_fused_lists): in each block, the
                        touching interior pairs, the batches' sequence, the new contacts
                        and the ended ones */
  uint32_t *idle;    /* per pair: each block's interior pairs not touching */
  double *sm;        /* per pair: sqrt(m*), kg^1/2 (dashpots c = factor sqrt(m*)) */
  size_t *astart;    /* n+1: pairs k in [astart[i], astart[i+1]) have a == i */
  size_t *wstart;    /* n+1: wall candidates of particle i */
  size_t nb, cap_b;  /* boundary pairs */
  uint32_t *bk;      /* their pair indices, ascending */
  double *slot;      /* ESF_FUSED_SLOT per boundary pair, zero when not touching;
                        line-aligned */
  double *slot_a;    /* ESF_FUSED_SLOT_A per boundary pair, zero when not touching */
  double *lslot, *lslot_a; /* with the ledger: ESF_FUSED_LSLOT per boundary pair, B's and
                              A's ledger rows, zero when not touching; else NULL */
  double *lrows;           /* with the ledger: the light steps' rows, ESF_LR_DISS a
                              particle (fused.c's light_rows), line-aligned, or NULL */
  size_t cap_lr;           /* particles lrows has room for */
  /* the rows a call's last (light) step left zero, and the step, particle count and
     list build they hold for (the next call's first light step skips zeroing them),
     or z_rows NULL */
  const double *z_rows;
  long z_step, z_builds;
  size_t z_n;
  size_t cap_lb;    /* boundary pairs they have room for */
  size_t *bout;     /* nth+1: bk[bout[t] .. bout[t+1]) have a in range t */
  uint32_t *bin;    /* boundary ordinals by the range of b, ascending within */
  size_t *binstart; /* nth+1 */
  size_t *rlo;      /* nth+1: the particle ranges (fused_ranges.c) */
  int32_t m0;       /* the material every particle has, or -1 (pair_batch.h's one) */
  /* balance (esf_fused_balance): the pair and kick pass's seconds per range since the
   * cut, the estimated work of each range, and, when a re-cut is due, seconds per unit
   * of work */
  double *busy, *work, *rate;
  long busy_steps;
  double *waits;             /* per range: seconds waited for the others */
  double inside;             /* a call's seconds range 0 spent in its steps */
  double backoff;            /* s: the next cap's length (doubles while it lasts) */
  int cap;                   /* > 0: at most this many ranges until cap_until */
  double cap_until, cap_eff; /* s (omp_get_wtime); the efficiency that set it */
  int cap_logged;            /* 1: a cap to log, 2: logged */
  esf_fused_range *rr;       /* nth, line-aligned */
  long epoch;                /* steps run by esf_fused_run */
  long lists_stamp;    /* s->rhs_evals when the ranges' lists (rr[t].L) last matched the
                          touch flags (after a call that committed, with no failure, on
                          the same index), or -1: the next call makes them from the flags */
  _Atomic long broken; /* bonds the batches broke (esf_fused_run books them) */
  double t_left;       /* when the last call's threads finished (omp_get_wtime), or 0 */
  double t_step;       /* how long its parallel part took per step, s */
  int recut;
  /* a burst's outcome, written by range 0 (esf_fused_decide) */
  long taken;    /* steps completed */
  int decided;   /* the last one's results were gathered (the burst stopped early) */
  size_t nt_sum; /* touching contacts summed over the gathered steps */
  /* range 0's word to the others, a line apart from the fields above: go = 2 e to take
   * step e, 2 e + 1 to stop before it; bfail = e: a boundary pair failed in step e */
  _Alignas(ESF_LINE) _Atomic long go;
  _Atomic long bfail;
};

/* Boundary pair j's slots when it does not touch: what adding (or, for the force on A
 * in `slot`, subtracting) leaves every double as it was, -0 and +0 (a zero slot must
 * not turn a -0 into +0, which the general path, adding nothing, keeps). */
static inline void esf_fused_slot_clear(esf_fused *f, size_t j) {
  double *s = f->slot + ESF_FUSED_SLOT * j, *sa = f->slot_a + ESF_FUSED_SLOT_A * j;
  for (int q = 0; q < 4; q++) {
    s[q] = 0.0;      /* subtracted from B's force */
    s[4 + q] = -0.0; /* added to B's torque */
    sa[q] = -0.0;
    sa[4 + q] = -0.0;
  }
  if (f->lslot)
    for (int q = 0; q < ESF_FUSED_LSLOT; q++) {
      f->lslot[ESF_FUSED_LSLOT * j + q] = -0.0;
      f->lslot_a[ESF_FUSED_LSLOT * j + q] = -0.0;
    }
}

/* What the particle pass needs: walls, 2D, local damping, kick, drift (fused_kick.c). */
typedef struct esf_fused_kick {
  double dt, cr0, cr1, ct0, ct1, lc; /* s; (1 -+ alpha h) factors; local coefficient */
  int dim2;
  int plain;                  /* 1: no damping of either form, 3D (a vectorised loop) */
  int plain_led;              /* 1: the same with the ledger on, without rolling
                                 resistance (its light steps: a loop of their own) */
  esf_wall_pass_fn wall_pass; /* wall_fast.h, chosen once per call */
  int forces_only;            /* 1: walls, then F, M to p.f, p.t (esf_fused_forces) */
  double *acc, *dw, ar, at;   /* forces_only: the accelerations too (esf_fused_eval), or
                                 NULL; the global damping they take, 1/s */
  int ft_skip;                /* with acc: F, M not written to p.f, p.t (a trial) */
  int lazy; /* an evaluation whose F, M stay in acc, no accelerations (esf_fused_eval) */
  const esf_local_damping *loc;
  const double *xref;            /* positions at the lists' build, or NULL */
  const double *dom_lo, *dom_hi; /* the domain, or NULL */
  /* the ledger (core/ledger.h), or rows NULL: the particles' rows (lr doubles a
     particle), their blocks */
  double *rows, *blocks;
  size_t kbase; /* the particle of the first block's start (MPI: the first owned one) */
  size_t lr;
  int clear_rows; /* 1: a light step leaves the rows it read zero (kick_ledger_light,
                     kick_one; the next light step's pair pass then skips zeroing) */
  esf_ledger_kick lk;
  struct esf_drag *drag; /* the fluid force (loads/drag.h), or NULL */
  int drag_on;           /* it acts at this step's time */
} esf_fused_kick;

/* What every range's steps share in one call (fused.c). */
typedef struct esf_fused_burst {
  const esf_pair_batch_ctx *bc;
  const esf_fused_kick *K;
  /* with the ledger, the same for the steps whose stored energies nobody reads (all
     but the last of the caller's `need`, and the first when the ledger has not
     started: core/ledger.h's light rows and kick), or NULL */
  const esf_pair_batch_ctx *bc_light;
  const esf_fused_kick *K_light;
  const esf_pair_batch_ctx *bc_light_z; /* bc_light with rows already zero, for a light
                                           step after one that cleared them */
  int started; /* the ledger had booked a step before the call (its first step: full) */
  int pre_zeroed;  /* the step before the call left the light rows zero (esf_fused.z_rows)
                    */
  int lists_kept;  /* the ranges' lists of the last call hold (esf_fused.lists_stamp) */
  long e0;         /* the epoch of the call's first step */
  long steps;      /* steps at most */
  long need;       /* the caller's steps up to a read of the stored energies (its burst:
                      an energy row, a check, the end), >= steps; a call of fewer steps
                      (moving walls, servo, fluid: one) ends on a light step before it */
  double lim2;     /* the lists need a rebuild past this squared displacement, m^2 */
  esf_ledger *led; /* the ledger, booked step by step from K->blocks; NULL: off */
  size_t nblocks;  /* its blocks */
} esf_fused_burst;

/* Whether the spheres of pair (a, b) overlap: |x_b - x_a|^2 < (r_a + r_b)^2, the step's
 * one test (pair_batch.c's lanes compute it for the contacts in the same order). */
static inline int esf_fused_overlap(const double *x, const double *r, size_t a,
                                    size_t b) {
  double d[3];
  v3_sub(d, x + 3 * b, x + 3 * a);
  const double R = r[a] + r[b];
  return v3_norm2(d) < R * R;
}

/* The same test for candidate k of the list c, B at its periodic image when c has
 * images (search/periodic.h; pair_batch.c's lanes add it the same way). */
static inline int esf_fused_overlap_k(const double *x, const double *r,
                                      const esf_candidates *c, size_t k) {
  double d[3], xb[3];
  const size_t a = c->a[k], b = c->b[k];
  v3_sub(d, esf_candidates_xb(c, k, x, xb), x + 3 * a);
  const double R = r[a] + r[b];
  return v3_norm2(d) < R * R;
}

/* fused_ranges.c: step 0, the indices for the current lists and nth ranges, and the
 * balance of the ranges. */
int esf_fused_index(esf_sim *s, esf_fused *f, int want, esf_error *err);
void esf_fused_balance(esf_fused *f, size_t T);

/* fused_lists.c: a range's contacts and idle candidates from step to step. */
void esf_fused_lists_from_flags(const esf_sim *s, size_t k0, size_t k1, size_t end,
                                esf_fused_lists *L);
size_t esf_fused_screen(const esf_sim *s, const uint32_t *il, size_t j0, size_t j1,
                        uint32_t *top, size_t nn);
size_t esf_fused_merge_new(uint32_t *sq, const uint32_t *tl, size_t nt,
                           const uint32_t *top, size_t nn);
size_t esf_fused_idle_update(uint32_t *il, size_t ni, const uint32_t *top, size_t nn,
                             const uint32_t *ended, size_t ne);

/* fused_slots.c: step 1, the boundary pairs into their slots. */
size_t esf_fused_boundary(esf_sim *s, esf_fused *f, const esf_pair_batch_ctx *bc,
                          size_t j0, size_t j1, size_t *nt);

/* fused_pairs.c: step 2's pair pass of one range. */
size_t esf_fused_pairs(esf_sim *s, esf_fused *f, const esf_pair_batch_ctx *bc, size_t t,
                       size_t lo, size_t hi, uint32_t *list, size_t cnt, uint32_t *ended,
                       size_t *ne, size_t *kept);

/* fused_kick.c: step 2's particle pass of one range: walls, kick, drift. */
void esf_fused_vv_drift_range(const esf_vv_pass *c, size_t lo, size_t hi, esf_vv_disp *o);
void esf_fused_kick_range(esf_sim *s, const esf_fused *f, const esf_fused_kick *K,
                          size_t lo, size_t hi, esf_fused_out *o, size_t *nt_pw);

/* fused_sync.c: the flags between the ranges. */
double esf_fused_wait(_Atomic long *flag, long e);
int esf_fused_all_done(esf_fused *f, long e);
int esf_fused_gather(const esf_fused *f, esf_fused_out *r);
int esf_fused_decide(esf_fused *f, const esf_fused_burst *B, long e, double *waited);

#endif
