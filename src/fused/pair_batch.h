/* pair_batch.h — the linear (or Hertz-Mindlin) contact law of the fused step for
 * ESF_BATCH pairs at once.
 *
 * One function computes the contact of up to ESF_BATCH overlapping particle pairs in
 * the lanes of vectors (GCC vector extensions: AVX-512 when the build targets it, AVX
 * or SSE2 halves otherwise). Every lane goes through the same instructions, so a pair's
 * result does not depend on the batch it lands in nor on its lane: the fused step
 * stays bit for bit independent of the thread count however its ranges cut the
 * batches. The results go either to an array of rows or, added in lane order, straight
 * into the particles' accumulators (no round trip through memory:
 * docs/performance.md#distance-from-the-machines-limit). */
#ifndef ESF_PAIR_BATCH_H
#define ESF_PAIR_BATCH_H

#include <stddef.h>
#include <stdint.h>

#include "contact/contact_law.h"
#include "fused/fused_isa.h"
#include "contact/material.h"
#include "core/ledger.h"
#include "util/vec4.h"

#define ESF_BATCH     8
#define ESF_BATCH_OUT 12 /* force on A, torque on A, torque on B: 3 + a zero each */
/* with the ledger: A's ledger rows (ESF_LR_PAIR of core/ledger.h: six rows of four;
 * ESF_LR_PAIR_ROLL, eight, with rolling resistance), then B's from ESF_BATCH_LSIDE,
 * ready to add */
#define ESF_BATCH_LSIDE 32
#define ESF_BATCH_LOUT  64

/* What the batch reads and commits: the particles, the candidate pairs' ends and
 * history, the reduced masses the dashpots' coefficients come from, and the step's
 * constants. */
typedef struct esf_pair_batch_ctx {
  const double *x, *v, *w;    /* 3n: m, m/s, rad/s */
  const double *radius;       /* n, m */
  const int32_t *material;    /* n */
  const esf_materials *mt;    /* pair parameters (kn, kt, mu, cohesion) */
  const esf_pair_params *one; /* non-NULL: one material, these parameters everywhere */
  const uint32_t *a, *b;      /* per candidate pair k: its particles, a < b */
  esf_contact_hist *h;        /* per pair: tangential history, committed */
  uint8_t *touch;             /* per pair: 1 once committed touching */
  const double *sm;           /* per pair: sqrt(m*), m* = ma mb / (ma + mb), kg^1/2 */
  double beta;                /* > 0: Rayleigh dashpots c = beta k (001 3.47); else c =
                                 factor sqrt(m*) (004 2.28) */
  double dt;                  /* s */
  double max_overlap;         /* the overlap limit, fraction of the smaller radius */
  int rotate;                 /* 1: xi rotated into the new plane (000 3-17, 3-18);
                                 0: projected and rescaled */
  int cohesion;               /* 1: the Coulomb cap includes the pair's cohesion */
  int hertz;                  /* 1: every pair Hertz-Mindlin (contact_hertz.h) */
  int hertz_cst;              /* with hertz: constant dashpots (hertz_damping) */
  double *rows;               /* the ledger's rows (core/ledger.h, ESF_LR a particle;
                                 line-aligned), or NULL: no ledger */
  esf_contact_bond *bond;     /* per pair: the bond state, or NULL: no bonds */
  size_t lr;                  /* with rows: a particle's rows, esf_ledger_lr */
  int light;                  /* with rows: only the rows of the ledger's cumulative
                                 terms (core/ledger.h: ESF_LEDGER_LIGHT) */
  int no_t;                   /* with rows: not DT, MDT (ESF_LEDGER_NO_T) */
  int no_w;                   /* with rows: row W not zeroed (ESF_LEDGER_NO_W) */
  int zeroed;             /* with rows: the rows are zero already (ESF_LEDGER_ZEROED) */
  esf_contact_roll *roll; /* per pair: the rolling resistance state (committed), or
                             NULL: no rolling resistance (contact_rolling.h) */
  const double *mass;     /* n, kg (with roll) */
  const double *inertia;  /* n, kg m^2 (with roll) */
  int roll_cdt;           /* with roll: 1 the cdt model, 0 epsd */
  _Atomic long *broken;   /* bonds broken (with bond) whose A is in [own_lo, own_hi)
                             (an MPI run counts each bond on one process) */
  size_t own_lo, own_hi;
  int trial;             /* 1: nothing committed (history, touch flags, bonds,
                            rolling states): the ODE methods' stage evaluations */
  double *vc0;           /* per pair, 3: the relative contact velocity at the last
                            commit (the ODE methods' trapezoidal carry: a live
                            contact's increment integrates (vc0 + vc)/2 over dt;
                            committing writes vc), or NULL */
  const int8_t *img;     /* per pair: B's periodic image (search/periodic.h), or
                            NULL: no periodic axis (nothing added to the batch) */
  double plen[3];        /* with img: the periods, m */
  int le;                /* with img: Lees-Edwards shear (periodic.h): B's image */
  int le_flow, le_grad;  /* also moves le_off m along the flow axis times its */
  double le_off, le_vel; /* gradient image, at le_vel m/s (esf_candidates_xb, _vb) */
} esf_pair_batch_ctx;

/* The first half of a batch, for pairs k[0 .. nl) (1 <= nl <= ESF_BATCH; lanes past nl
 * repeat lane 0's pair): their particles, positions, radii, velocities and spins
 * gathered, the overlap test, the normal, overlap, lever arms and contact velocity
 * (law_body.h's geometry), as columns of eight lanes. Kept apart from the law so that
 * the batches of a chunk have their loads and square roots in flight together
 * (docs/performance.md#the-pair-batches). */
#define ESF_PAIR_GEO_COLS 21
typedef struct esf_pair_geo {
  double col[ESF_PAIR_GEO_COLS][ESF_BATCH] __attribute__((aligned(64)));
  size_t kk[ESF_BATCH], ia[ESF_BATCH], ib[ESF_BATCH]; /* pair, its A and B per lane */
  int nl;
} esf_pair_geo;

void esf_pair_batch_geometry(const esf_pair_batch_ctx *ctx, const uint32_t *k, int nl,
                             esf_pair_geo *g);

/* The contacts of the pairs of g (esf_pair_batch_geometry's). A pair whose spheres do
 * not overlap (the fused step's screening test: |x_b - x_a|^2 < (r_a + r_b)^2, the
 * same operations) is apart: its touch flag is cleared, nothing else is written, and
 * its lane's bit is set in *apart. For the others, with acc NULL, writes
 * out[lane][0 .. ESF_BATCH_OUT) and, with the ledger (ctx->rows),
 * lout[lane][0 .. ESF_BATCH_LOUT); with acc, adds each lane's results to its particles'
 * accumulators, lane by lane in lane order, as a caller's scatter of out would (force
 * on A to A's force, its opposite to B's, the torques to A's and B's torques, and with
 * the ledger each lane's rows to its particles' rows). Commits each pair's history and
 * touch flag (not in a trial, ctx->trial; with ctx->vc0 also its contact velocity, the
 * increment then integrating the carry). Returns a bit mask of the lanes whose overlap
 * exceeds the limit: nothing is committed nor added for those. The particle arrays x,
 * v, w are read four doubles at a time, so one double past the last w must be readable
 * (esf_particles' y has it). */
unsigned esf_pair_batch_law(const esf_pair_batch_ctx *ctx, const esf_pair_geo *g,
                            double out[ESF_BATCH][ESF_BATCH_OUT],
                            double lout[ESF_BATCH][ESF_BATCH_LOUT], double *acc,
                            unsigned *apart);

/* Both halves for pairs k[0 .. nl), the results to out and lout. */
unsigned esf_pair_batch_linear(const esf_pair_batch_ctx *ctx, const uint32_t *k, int nl,
                               double out[ESF_BATCH][ESF_BATCH_OUT],
                               double lout[ESF_BATCH][ESF_BATCH_LOUT], unsigned *apart);

/* Adds one pair's ledger rows lout (esf_pair_batch_linear's, A's side then B's from
 * ESF_BATCH_LSIDE) to the rows of its particles a and b (lr doubles a particle;
 * esf_ledger_side_add's rows `set`, esf_pair_batch_lset). */
static inline void esf_pair_batch_led_add(double *rows, size_t lr, size_t a, size_t b,
                                          const double *lout, unsigned set) {
  esf_ledger_side_add(rows + lr * a, lout, set);
  esf_ledger_side_add(rows + lr * b, lout + ESF_BATCH_LSIDE, set);
}

/* The ledger rows the batches of ctx write (esf_ledger_side_add's set). */
static inline unsigned esf_pair_batch_lset(const esf_pair_batch_ctx *ctx) {
  return (ctx->light ? ESF_LEDGER_LIGHT : 0u) | (ctx->no_t ? ESF_LEDGER_NO_T : 0u) |
         (ctx->roll ? ESF_LEDGER_ROLL : 0u) | (ctx->no_w ? ESF_LEDGER_NO_W : 0u) |
         (ctx->zeroed ? ESF_LEDGER_ZEROED : 0u);
}

/* The ledger rows a pair writes per side in the batches of ctx. */
#define ESF_PAIR_BATCH_LROWS(ctx) ((ctx)->roll ? ESF_LR_PAIR_ROLL : ESF_LR_PAIR)

/* The accumulators esf_pair_batch_law adds into: per particle i, at
 * acc + ESF_BATCH_ACC * i, the force (x, y, z, unused) then the torque (x, y, z,
 * unused). */
#define ESF_BATCH_ACC 8

/* Adds one pair's results to its particles' accumulators: f (force on A) to A's force,
 * -f to B's, ta and tb to A's and B's torques; the one order both the batch and a
 * caller's scatter of out use. */
static inline void esf_pair_batch_acc_add(double *acc, size_t a, size_t b, esf_v4 f,
                                          esf_v4 ta, esf_v4 tb) {
  double *aa = acc + ESF_BATCH_ACC * a, *ab = acc + ESF_BATCH_ACC * b;
  v4_st(aa, v4_ld(aa) + f);
  v4_st(ab, v4_ld(ab) - f);
  v4_st(aa + 4, v4_ld(aa + 4) + ta);
  v4_st(ab + 4, v4_ld(ab + 4) + tb);
}

#endif
