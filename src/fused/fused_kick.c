/* fused_kick.c — step 2's particle pass of the fused step (fused.c): the wall
 * contacts of a range's particles, then, particle by particle, the 2D projection, local
 * damping, the kick with global damping and the drift, with the displacement since the
 * lists' build and the domain check.
 *
 * Physics: the leapfrog of integrators/leapfrog.c (000 3-6..3-8, 004 2.38-2.47, 001
 * 3.50-3.54): v_{n+1/2} = [(1 - alpha h) v_{n-1/2} + (F_n + F_local) dt / m] /
 * (1 + alpha h), h = dt/2, the same for w with the moment and the inertia, and
 * x_{n+1} = x_n + v_{n+1/2} dt. The wall pass (wall_fast.h) reads and adds to its own
 * particle only, so doing all of a range's walls before its kicks changes no operation.
 * The accumulators keep F_n, M_n (s->ft_lazy, for esf_sim_forces_sync). An evaluation
 * (esf_fused_forces, K->forces_only) stops after the walls: the totals to p.f, p.t,
 * and with K->acc the accelerations (model/accel.h).
 * Entry: the range's pair forces summed (fused_pairs.c). Units: SI. */
#include "fused/fused_impl.h"

#include <float.h>

#include <math.h>
#include <string.h>

#include "loads/drag.h"
#include "model/accel.h"

#define WPF 8 /* wall pass prefetch distance, candidates */

/* The wall contacts of range [lo, hi), particle by particle in ascending order
 * (each adds to its own particle's accumulator only, at the state before any kick).
 * Returns 1 when an overlap exceeds the limit (*bad_part: the first such particle). */
static int walls_range(esf_sim *s, const esf_fused *f, const esf_fused_kick *K, size_t lo,
                       size_t hi, size_t *nt_pw, size_t *bad_part) {
  const esf_candidates *pw = &s->nb.pw;
  const esf_wall_pass_fn wall_pass = K->wall_pass;
  int fail = 0;
  if (s->walls.gforce && hi > lo) { /* servo walls: this range's blocks (whole) zeroed */
    const size_t per = 4 * (size_t)s->walls.ngroups;
    const size_t b0 = (lo - K->kbase) / ESF_LEDGER_BLOCK,
                 b1 = (hi - 1 - K->kbase) / ESF_LEDGER_BLOCK + 1;
    memset(s->walls.gforce_blk + per * b0, 0, (b1 - b0) * per * sizeof(double));
  }
  const size_t kend = f->wstart[hi];
  const esf_particles *p = &s->p;
  for (size_t k = f->wstart[lo], k1; k < kend; k = k1) {
    const size_t i = pw->a[k];
    k1 = f->wstart[i + 1];
    if (k + WPF < kend) { /* the state of the particle WPF candidates ahead */
      const size_t kp = k + WPF, ip = pw->a[kp];
      __builtin_prefetch(f->acc + ESF_FUSED_ACC * ip, 1, 3);
      __builtin_prefetch(p->x + 3 * ip, 0, 3);
      __builtin_prefetch(p->v + 3 * ip, 0, 3);
      __builtin_prefetch(p->w + 3 * ip, 0, 3);
      __builtin_prefetch(pw->h + kp, 1, 3);
    }
    double *fi = f->acc + ESF_FUSED_ACC * i;
    if (wall_pass(s, k, k1, K->dt, nt_pw, fi, fi + 4,
                  K->rows ? K->rows + K->lr * i : NULL)) {
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
     waits for the stores to retire (docs/performance.md#wall-contacts-and-the-kick) */
  const double bl[3] = {lo3[0], lo3[1], lo3[2]}, bh[3] = {hi3[0], hi3[1], hi3[2]};
  for (size_t i = lo; i < hi; i++) {
    const double *fi = acc + ESF_FUSED_ACC * i, *ti = fi + 4;
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

/* No domain: bounds nothing passes (the kicks' domain test then never fires). */
static const double inf3[2][3] = {{-INFINITY, -INFINITY, -INFINITY},
                                  {INFINITY, INFINITY, INFINITY}};

/* esf_accel_one's accelerations without local damping (its zero terms added, as
 * there) of particles [lo, hi) from their accumulators acc, and with pf the totals
 * copied to pf, pt: a loop without calls or branches, vectorised (each lane the scalar
 * operations). */
static inline __attribute__((always_inline)) void
accel_loop(size_t lo, size_t hi, const double *restrict acc, const double *restrict im_,
           const double *restrict ii_, const double *restrict v, const double *restrict w,
           double ar, double at, double *restrict pf, double *restrict pt,
           double *restrict a, double *restrict dw, const int keep) {
  for (size_t i = lo; i < hi; i++) {
    const double *fi = acc + ESF_FUSED_ACC * i, *ti = fi + 4;
    const double im = im_[i], ii = ii_[i];
    for (size_t q = 0; q < 3; q++) {
      const size_t j = 3 * i + q;
      if (keep) {
        pf[j] = fi[q];
        pt[j] = ti[q];
      }
      a[j] = esf_accel_entry(fi[q], 0.0, im, ar, v[j]);
      dw[j] = esf_accel_entry(ti[q], 0.0, ii, at, w[j]);
    }
  }
}

static void accel_plain_loop(size_t lo, size_t hi, const double *acc, const double *im,
                             const double *ii, const double *v, const double *w,
                             double ar, double at, double *pf, double *pt, double *a,
                             double *dw) {
  if (pf)
    accel_loop(lo, hi, acc, im, ii, v, w, ar, at, pf, pt, a, dw, 1);
  else
    accel_loop(lo, hi, acc, im, ii, v, w, ar, at, pf, pt, a, dw, 0);
}

/* A light step's channels of row r (those fused_pairs.c's acc_set zeroes) set to +0,
 * each group of four only when not +0 already (a row no contact touched stays clean in
 * the cache). */
static inline void clear_light_row(const esf_fused_kick *K, double *r) {
  const size_t off[5] = {ESF_LR_DN, ESF_LR_W, ESF_LR_DT, ESF_LR_MDT, ESF_LR_RD};
  const int on[5] = {1, !K->lk.no_w, !K->lk.no_t, !K->lk.no_t, K->lr == ESF_LR};
  for (int g = 0; g < 5; g++) {
    if (!on[g]) continue;
    uint64_t u[4], any = 0;
    memcpy(u, r + off[g], sizeof u);
    for (int q = 0; q < 4; q++) any |= u[q];
    if (any) memset(r + off[g], 0, sizeof u);
  }
}

/* kick_plain_loop's kick and drift of range [lo, hi) with the ledger's cumulative
 * channels of a light step (esf_ledger_kick_particle's, K->lk.light; no rolling
 * resistance, local damping or fluid force): block by block (ESF_LEDGER_BLOCK), the
 * velocities before the kick kept, the block kicked, each particle's terms computed
 * in a loop without branches or calls, then added to the block's channels in
 * particle order, as the scalar path adds them; with K->clear_rows the rows read are
 * left zero for the next light step (whose pair pass then does not zero them). */
static void kick_ledger_light(size_t lo, size_t hi, const esf_fused_kick *K,
                              esf_particles *p, const double *acc, const double *lo3,
                              const double *hi3, double *max2, int *nonfinite,
                              int *escaped, size_t lr) {
  const esf_ledger_kick *k = &K->lk;
  const double dt = K->dt;
  /* channels whose every term is +0 (which adds nothing) left out: global damping at
     alpha 0, the tangential dashpots without their rows and the walls' side */
  const int dg_on = k->alpha_r != 0.0 || k->alpha_t != 0.0, dt_on = !k->no_t || !k->no_w;
  const int spin = dg_on || dt_on; /* the spins' terms wanted */
  double v0[3 * ESF_LEDGER_BLOCK], w0[3 * ESF_LEDGER_BLOCK];
  double tdn[ESF_LEDGER_BLOCK], tdt[ESF_LEDGER_BLOCK], tsl[ESF_LEDGER_BLOCK],
      tww[ESF_LEDGER_BLOCK], tdg[ESF_LEDGER_BLOCK];
  for (size_t b0 = lo, b1; b0 < hi; b0 = b1) { /* blocks from K->kbase (MPI) */
    b1 = K->kbase + ((b0 - K->kbase) / ESF_LEDGER_BLOCK + 1) * ESF_LEDGER_BLOCK;
    if (b1 > hi) b1 = hi;
    const size_t nb = b1 - b0;
    memcpy(v0, p->v + 3 * b0, 3 * nb * sizeof(double));
    if (spin) memcpy(w0, p->w + 3 * b0, 3 * nb * sizeof(double));
    kick_plain_loop(b0, b1, dt, p->x, p->v, p->w, acc, p->inv_mass, p->inv_inertia,
                    K->xref, lo3, hi3, max2, nonfinite, escaped);
    if (!spin) /* the normal dashpots and slip alone */
      for (size_t j = 0; j < nb; j++) {
        const size_t i = b0 + j;
        const double *r = K->rows + lr * i, *v = p->v + 3 * i;
        double vb[3];
        for (int q = 0; q < 3; q++) vb[q] = 0.5 * (v0[3 * j + q] + v[q]);
        tdn[j] = esf_ledger_dn_term(r, vb, dt, k->no_w);
        tsl[j] = r[ESF_LR_DN + 3];
      }
    else
      for (size_t j = 0; j < nb; j++) {
        const size_t i = b0 + j;
        const double *r = K->rows + lr * i, *v = p->v + 3 * i, *w = p->w + 3 * i;
        double vb[3], wb[3], vb2 = 0, wb2 = 0;
        for (int q = 0; q < 3; q++) { /* as esf_ledger_kick_particle */
          vb[q] = 0.5 * (v0[3 * j + q] + v[q]);
          wb[q] = 0.5 * (w0[3 * j + q] + w[q]);
          vb2 += vb[q] * vb[q];
          wb2 += wb[q] * wb[q];
        }
        if (dg_on) tdg[j] = esf_ledger_dg_term(k, p->mass[i], p->inertia[i], vb2, wb2);
        tdn[j] = esf_ledger_dn_term(r, vb, dt, k->no_w);
        tsl[j] = r[ESF_LR_DN + 3];
        if (dt_on) tdt[j] = esf_ledger_dt_term(r, vb, wb, dt, k->no_t, k->no_w);
        if (!k->no_w) tww[j] = r[ESF_LR_WWORK] * dt;
      }
    double *blk = K->blocks + ESF_LB_N * ((b0 - K->kbase) / ESF_LEDGER_BLOCK);
    if ((b0 - K->kbase) % ESF_LEDGER_BLOCK == 0)
      memset(blk, 0, ESF_LB_N * sizeof(double));
    for (size_t j = 0; j < nb; j++) { /* esf_ledger_kick_particle's order per channel */
      blk[ESF_LB_DN] -= tdn[j];
      blk[ESF_LB_SL] += tsl[j];
    }
    if (dg_on)
      for (size_t j = 0; j < nb; j++) blk[ESF_LB_DG] += tdg[j];
    if (dt_on)
      for (size_t j = 0; j < nb; j++) blk[ESF_LB_DT] -= tdt[j];
    if (!k->no_w)
      for (size_t j = 0; j < nb; j++) blk[ESF_LB_WW] += tww[j];
    if (!k->no_t) /* else rows of +0 (and no room for them: ESF_LR_DISS_N) */
      for (size_t j = 0; j < nb; j++) {
        const double *r = K->rows + lr * (b0 + j);
        blk[ESF_LB_BD] += r[ESF_LR_BOND];
        blk[ESF_LB_SW] += r[ESF_LR_STIFF];
      }
    if (K->clear_rows && lr <= ESF_LR_DISS) /* light_rows' own rows: all of them */
      memset(K->rows + lr * b0, 0, lr * nb * sizeof(double));
    else if (K->clear_rows)
      for (size_t j = 0; j < nb; j++) clear_light_row(K, K->rows + lr * (b0 + j));
  }
}

/* The kick and drift of particle i from its totals fi, ti (F_n, M_n; left as they
 * are), with the damping forms and 2D: the displacement since the lists' build and
 * the domain check. */
static inline void kick_one(const esf_sim *s, esf_particles *p, const esf_fused_kick *K,
                            size_t i, double *fi, double *ti, double *max2,
                            int *nonfinite, int *escaped) {
  const double dt = K->dt;
  if (ESF_FUSED_FEATURES && K->drag) { /* the fluid force, after the walls (forces.c) */
    double *F = K->drag->f + 3 * i;
    esf_drag_particle(s, K->drag_on, i, p->x + 3 * i, p->v + 3 * i, F);
    v3_add(fi, fi, F);
  }
  if (ESF_FUSED_FEATURES && K->dim2) {
    fi[1] = 0.0;
    ti[0] = 0.0;
    ti[2] = 0.0;
  }
  double *v = p->v + 3 * i, *w = p->w + 3 * i, *x = p->x + 3 * i;
  double fk[3], tk[3]; /* fi, ti stay: F_n, M_n for p.f, p.t (s->ft_lazy) */
  v3_copy(fk, fi);
  v3_copy(tk, ti);
  double fl[3] = {0, 0, 0}, ml[3] = {0, 0, 0}; /* local damping */
  if (ESF_FUSED_FEATURES && K->loc) {
    K->loc->force(K->lc, fk, v, fl);
    K->loc->force(K->lc, tk, w, ml);
    v3_add(fk, fk, fl);
    v3_add(tk, tk, ml);
  }
  const double im = p->inv_mass[i] * dt, ii = p->inv_inertia[i] * dt;
  double x0[3], v0[3], w0[3];
  if (K->blocks) { /* the ledger's blocks: the state before the kick and drift */
    v3_copy(x0, x);
    v3_copy(v0, v);
    v3_copy(w0, w);
  }
  /* the new state in locals first (K and the arrays may alias as far as the compiler
     knows: stores between loads would reload every factor) */
  const double cr0 = K->cr0, cr1 = K->cr1, ct0 = K->ct0, ct1 = K->ct1;
  double vn[3], wn[3], xn[3], d2 = 0.0;
  for (int q = 0; q < 3; q++) {
    if (ESF_FUSED_FEATURES) {
      vn[q] = (cr0 * v[q] + fk[q] * im) * cr1;
      wn[q] = (ct0 * w[q] + tk[q] * ii) * ct1;
    } else {
      vn[q] = v[q] + fk[q] * im;
      wn[q] = w[q] + tk[q] * ii;
    }
    xn[q] = x[q] + vn[q] * dt;
  }
  if (K->xref)
    for (int q = 0; q < 3; q++) {
      const double d = xn[q] - K->xref[3 * i + q];
      d2 += d * d;
    }
  v3_copy(v, vn);
  v3_copy(w, wn);
  v3_copy(x, xn);
  if (!(d2 <= *max2)) {
    if (d2 > *max2)
      *max2 = d2;
    else
      *nonfinite = 1; /* NaN */
  }
  if (K->dom_lo) *escaped |= v3_outside(x, K->dom_lo, K->dom_hi); /* as sim.c's */
  if (K->blocks) { /* as the general path's kick (esf_ledger_kick_particle) */
    const size_t ib = i - K->kbase;
    double *blk = K->blocks + ESF_LB_N * (ib / ESF_LEDGER_BLOCK);
    if (ib % ESF_LEDGER_BLOCK == 0) memset(blk, 0, ESF_LB_N * sizeof(double));
    esf_ledger_kick_particle(&K->lk, p->mass[i], p->inertia[i], x0, v0, v, w0, w,
                             ESF_FUSED_FEATURES && K->loc ? fl : NULL,
                             ESF_FUSED_FEATURES && K->loc ? ml : NULL,
                             ESF_FUSED_FEATURES && K->drag ? K->drag->f + 3 * i : NULL,
                             K->rows ? K->rows + K->lr * i : NULL, blk);
    if (K->clear_rows && K->lk.light && K->rows) clear_light_row(K, K->rows + K->lr * i);
  }
}

/* The particle pass of range [lo, hi): the wall contacts of every particle first,
 * then the kicks (a particle's walls read only its own state, so the order of
 * operations per particle is that of one loop doing both). A wall overlap failure
 * leaves the range unkicked, as a pair failure does: the step is not taken. */
void esf_fused_kick_range(esf_sim *s, const esf_fused *f, const esf_fused_kick *K,
                          size_t lo, size_t hi, esf_fused_out *o, size_t *nt_pw) {
  if (walls_range(s, f, K, lo, hi, nt_pw, &o->bad_part)) return;
  if (K->forces_only) {  /* an evaluation (esf_fused_forces): the totals to p.f, p.t */
    if (K->lazy) return; /* they stay in acc, the caller's to read */
    esf_particles *p = &s->p;
    const int keep = !K->acc || !K->ft_skip; /* else F, M read here only */
    if (K->acc && !K->loc && !(ESF_FUSED_FEATURES && K->dim2)) {
      accel_plain_loop(lo, hi, f->acc, p->inv_mass, p->inv_inertia, p->v, p->w, K->ar,
                       K->at, keep ? p->f : NULL, keep ? p->t : NULL, K->acc, K->dw);
      return;
    }
    for (size_t i = lo; i < hi; i++) {
      const double *fi = f->acc + ESF_FUSED_ACC * i;
      double fl[3], ml[3];
      double *const fo = keep ? p->f + 3 * i : fl, *const mo = keep ? p->t + 3 * i : ml;
      v3_copy(fo, fi);
      v3_copy(mo, fi + 4);
      if (ESF_FUSED_FEATURES && K->dim2) { /* as forces.c's, at the end */
        fo[1] = 0.0;
        mo[0] = 0.0;
        mo[2] = 0.0;
      }
      if (K->acc) /* as esf_sim_accel's, from the totals (one pass fewer) */
        esf_accel_one(s, i, fo, mo, p->v, p->w, K->acc, K->dw, K->ar, K->at, NULL);
    }
    return;
  }
  const double *lo3 = K->dom_lo ? K->dom_lo : inf3[0],
               *hi3 = K->dom_lo ? K->dom_hi : inf3[1];
  if (K->plain && K->xref) {
    esf_particles *p = &s->p;
    kick_plain_loop(lo, hi, K->dt, p->x, p->v, p->w, f->acc, p->inv_mass, p->inv_inertia,
                    K->xref, lo3, hi3, &o->max2, &o->nonfinite, &o->escaped);
    return;
  }
  if (K->plain_led && K->lk.light && K->xref) {
    kick_ledger_light(lo, hi, K, &s->p, f->acc, lo3, hi3, &o->max2, &o->nonfinite,
                      &o->escaped, K->lr);
    return;
  }
  for (size_t i = lo; i < hi; i++) {
    double *fi = f->acc + ESF_FUSED_ACC * i;
    kick_one(s, &s->p, K, i, fi, fi + 4, &o->max2, &o->nonfinite, &o->escaped);
  }
}

/* esf_vv_pass's operations on particles [lo, hi) (fused.h), without calls or branches:
 * GCC vectorises the loop, each lane the scalar loop's operations (end, drift, dsp and
 * fm known when compiling). fm: the accelerations from the totals F (model/accel.h's
 * operations without local damping) at the velocities on entry, stored to a, dw when
 * st; else read from a, dw. */
static inline __attribute__((always_inline)) void
vv_drift(const esf_vv_pass *c, size_t lo, size_t hi, double *restrict x,
         double *restrict v, double *restrict w, double *restrict a, double *restrict dw,
         const double *restrict F, const double *restrict im_, const double *restrict ii_,
         const double *restrict xref, esf_vv_disp *o, const int end, const int drift,
         const int dsp, const int fm, const int st) {
  const double h = c->h, dt = c->dt, ar = c->ar, at = c->at, cr = c->cr, ct = c->ct;
  const double ar0 = c->ar0, at0 = c->at0;
  const double *lo3 = c->lo3 ? c->lo3 : inf3[0], *hi3 = c->lo3 ? c->hi3 : inf3[1];
  const double bl[3] = {lo3[0], lo3[1], lo3[2]}, bh[3] = {hi3[0], hi3[1], hi3[2]};
  int64_t mb = 0;
  int bad = 0, out = 0;
  for (size_t i = lo; i < hi; i++) {
    double d2 = 0.0, xn[3];
    for (size_t q = 0; q < 3; q++) {
      const size_t j = 3 * i + q;
      double vj = v[j], wj = w[j], aj, dwj;
      if (fm) { /* esf_accel_one's, its local terms +0 */
        aj = esf_accel_entry(F[ESF_FT_STRIDE * i + q], 0.0, im_[i], ar0, vj);
        dwj = esf_accel_entry(F[ESF_FT_STRIDE * i + 4 + q], 0.0, ii_[i], at0, wj);
        if (st) {
          a[j] = aj;
          dw[j] = dwj;
        }
      } else {
        aj = a[j];
        dwj = dw[j];
      }
      if (end) {
        vj = (vj + h * aj) * cr;
        wj = (wj + h * dwj) * ct;
      }
      if (!drift) {
        v[j] = vj;
        w[j] = wj;
        continue;
      }
      vj += h * (aj - ar * vj);
      wj += h * (dwj - at * wj);
      v[j] = vj;
      w[j] = wj;
      xn[q] = x[j] + dt * vj;
      x[j] = xn[q];
      if (dsp) {
        const double d = xn[q] - xref[j];
        d2 += d * d;
      }
    }
    if (!drift || !dsp) continue;
    const int nf = !(d2 <= DBL_MAX); /* inf or NaN */
    int64_t b;
    memcpy(&b, &d2, sizeof b);
    b = nf ? 0 : b;
    bad |= nf;
    mb = b > mb ? b : mb;
    out |= v3_outside(xn, bl, bh);
  }
  if (mb > o->max_bits) o->max_bits = mb;
  o->bad |= bad;
  o->out |= out;
}

void esf_fused_vv_drift_range(const esf_vv_pass *c, size_t lo, size_t hi,
                              esf_vv_disp *o) {
#define VV(e, d, m, f, t)                                                                \
  vv_drift(c, lo, hi, c->x, c->v, c->w, c->a, c->dw, c->F, c->im, c->ii, c->xref, o, e,  \
           d, m, f, t)
  const int dsp = c->xref != NULL;
  if (c->F) { /* a step's end: the accelerations from its totals */
    if (!c->drift)
      VV(1, 0, 0, 1, 1); /* the call's last: kept for the next call's start */
    else if (dsp)
      VV(1, 1, 1, 1, 0);
    else
      VV(1, 1, 0, 1, 0);
  } else if (!c->drift) {
    VV(1, 0, 0, 0, 0);
  } else if (c->end) {
    if (dsp)
      VV(1, 1, 1, 0, 0);
    else
      VV(1, 1, 0, 0, 0);
  } else if (dsp) {
    VV(0, 1, 1, 0, 0);
  } else {
    VV(0, 1, 0, 0, 0);
  }
#undef VV
}
