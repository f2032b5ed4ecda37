/* fused.h — the leapfrog's fused step: force evaluation, kick and drift in one
 * threaded pass whose results do not depend on the thread count, bit for bit, for the
 * runs that need nothing beyond the linear law with tangential history, walls, global
 * and local damping and gravity (esf_fused_eligible says which). How it works: fused.c;
 * every other run takes model/forces.c's general path. */
#ifndef ESF_FUSED_H
#define ESF_FUSED_H

#include "core/sim.h"

typedef struct esf_fused esf_fused;

/* Velocity Verlet's particle pass (integrators/verlet.c), compiled with the kernels for
 * each instruction set: particles [lo, hi) get, entry by entry, with end the second half
 * kick of the step just taken, v = (v + h a) cr, w = (w + h dw) ct, then the first half
 * kick and drift of the next, v += h (a - ar v), w += h (dw - at w), x += dt v; with
 * xref their squared displacement since the lists' build (esf_neighbor_check's
 * operations) and the domain test [lo3, hi3] (NULL: none). Without drift,
 * the second half kick alone (end must be set). The accelerations a, dw are read from
 * a, dw; or, with F (end must be set; the totals of a lazy evaluation, s->ft_lazy:
 * ESF_FT_STRIDE doubles a particle, force then torque), computed from them at the
 * velocities on entry as model/accel.h does without local damping, a = (F + 0) im -
 * ar0 v, and stored to a, dw only without drift (for the next call's first half kick). */
typedef struct esf_vv_pass {
  double h, dt, ar, at, cr, ct;
  double *x, *v, *w;
  double *a, *dw;
  const double *F;         /* or NULL */
  const double *im, *ii;   /* with F: inverse masses and inertias */
  double ar0, at0;         /* with F: the global damping inside the accelerations */
  const double *xref;      /* or NULL: no displacement */
  const double *lo3, *hi3; /* the domain, or NULL: none */
  int end, drift;
} esf_vv_pass;

/* What one pass measured: its largest squared displacement as the bits of a double
 * (an integer maximum vectorises), whether one was not finite (the check's own pass
 * then words it) and whether a particle left the domain. Start from zeros. */
typedef struct esf_vv_disp {
  int64_t max_bits;
  int bad, out;
} esf_vv_disp;

typedef void (*esf_vv_drift_fn)(const esf_vv_pass *c, size_t lo, size_t hi,
                                esf_vv_disp *o);

/* The pass of the kernels for this CPU, or those isa names (as esf_fused_create). */
int esf_fused_vv_drift(const char *isa, esf_vv_drift_fn *out, esf_error *err);

/* isa: the kernels' instruction set (base, avx2, avx512), or NULL or "" for the widest
 * this CPU has. */
int esf_fused_create(esf_fused **out, const char *isa, esf_error *err);
void esf_fused_free(esf_fused **f);

/* The instruction set of the kernels esf_fused_create picked: "base", "avx2" or
 * "avx512". */
const char *esf_fused_isa(const esf_fused *f);

/* 1 when the sim's current settings can use the fused step (checked every step: the
 * ledger or adaptive damping may be switched by the driver). */
int esf_fused_eligible(const esf_sim *s);

/* Why the fused step cannot take the sim's current settings (for the log), or NULL
 * when it can. */
const char *esf_fused_refusal(const esf_sim *s);

/* Up to nmax leapfrog steps from x_n, v_{n-1/2}, w_{n-1/2} (candidate lists valid),
 * each: forces at x_n committing the history, kick with global and local damping,
 * drift. Between two steps of one call the ranges check what the driver would (the
 * lists' displacement limit, particles leaving the domain, non-finite positions, the
 * balance of the ranges) and stop early when a rebuild or re-cut is due; more than one
 * step is taken only with static walls and no scene events, whose checks between steps
 * need more. On exit *taken steps were completed: s->step, s->t, s->contacts_sum and
 * s->rhs_evals advanced by them; x, v, w advanced, F_n and M_n of the last left in the
 * step's accumulators with s->ft_lazy pointing at them (esf_sim_forces_sync copies them
 * to p.f and p.t; not copied every step, as only frames and checkpoints read them), and
 * nb.max_disp2 the largest squared displacement since the last build. A failure
 * (overlap past the limit) is reported for the step it happened in, s->step naming it. */
int esf_fused_run(esf_sim *s, esf_fused *f, long nmax, long *taken, esf_error *err);

/* One force evaluation for velocity Verlet and the ODE methods (the fused step's
 * passes without kick and drift): forces and torques at the state (x, v, w) into p.f,
 * p.t, as model/forces.c's esf_forces_eval gives them bit for bit, threaded, the same
 * bits on any thread count. dt: the interval the tangential increment integrates over;
 * trial: history read, not written (ESF_FORCES_TRIAL), else committed (with the
 * lists' carry vc0 when they keep it). */
typedef struct esf_fused_eval {
  const double *x, *v, *w; /* 3n each; one double past w readable (esf_particles' y, an
                              ODE state with its quadratures) */
  double dt;               /* s */
  int trial;
  double *acc, *dw; /* or NULL; else the accelerations at x, v, w (3n each, model.h's
                       esf_sim_accel, global damping with with_global), written by the
                       particle pass after the totals; a trial then leaves p.f, p.t */
  int with_global;
  int lazy; /* with acc, committing: F, M stay in the accumulators until read
               (s->ft_lazy, as the leapfrog's), the previous evaluation's are not
               copied out first (a scheme whose every evaluation commits: Verlet), and
               the accelerations are not written (esf_vv_pass's F derives them); taken
               in 3D without local damping or MPI (else acc is written and
               s->ft_lazy is NULL) */
} esf_fused_eval;

/* Why esf_fused_forces cannot take the sim's settings (for the log), or NULL; ode: for
 * the ODE methods (their rolling carry is the general path's). */
const char *esf_fused_eval_refusal(const esf_sim *s, int ode);

/* The evaluation: as esf_forces_eval (s->rhs_evals advanced, *touching may be NULL;
 * an overlap past the limit gives its message). */
int esf_fused_forces(esf_sim *s, esf_fused *f, const esf_fused_eval *ev, size_t *touching,
                     esf_error *err);

/* The threads the last call ran on (its ranges: fewer than asked on a small scene, or
 * while other programs kept them waiting, fused.c), >= 1. */
int esf_fused_threads(const esf_fused *f);

/* Releases the indices and accumulators the next call makes again (about 140 bytes a
 * particle: per pair the sequences, idle lists and sqrt(m*), per particle the
 * accumulators and offsets), after copying F_n, M_n to p.f, p.t: so that a list
 * rebuild, a stability check or a frame does not hold its scratch beside them.
 * esf_fused_run calls it when it stops for a rebuild or a stability check; the
 * leapfrog's trim (integrator.h) before the run's frames and final check. */
void esf_fused_trim(esf_sim *s, esf_fused *f);

#endif
