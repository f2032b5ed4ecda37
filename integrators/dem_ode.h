/* dem_ode.h — the DEM as an ODE right-hand side y' = f(t, y) for the SUNDIALS methods.
 *
 * y = [ x (3n) | v (3n) | w (3n) | Q (ESF_ODE_NQ) ], Q the ledger quadratures
 * (dissipated by normal and tangential dashpots, global and local damping, the work
 * of walls, and with history as state the power into the tangential springs: Coulomb
 * dissipation is then that work less the change of their stored energy), so that an
 * adaptive method integrates the energy balance to its own accuracy. f = [ v | a | dw |
 * powers ] with a, dw the damped accelerations (model/model.h) from the forces at (x, v,
 * w).
 *
 * Contact history, treatment (b) "frozen" (integrator.history: frozen): within a step
 * the tangential displacement is the committed one carried by the trapezoidal rule,
 *   xi(t) = rot(xi_c) + [(vct(t_c) + vct(t))/2] (t - t_c)
 * (vct(t_c) kept per contact at each commit; a contact new within the step uses vct(t));
 * stage evaluations never write it. After each accepted step esf_dem_ode_commit
 * evaluates once more at the step's end and commits (Coulomb return and slip work
 * included), then t_c = t.
 *
 * Treatment (a) "state" (integrator.history: state): y gains a block XI of 3 entries
 * per candidate contact (pair list, then wall list), the live tangential displacement,
 * with rate xi' = vct + spin_n n x xi while touching and 0 otherwise (smooth: within a
 * step xi may pass the Coulomb cap, the force does not); the law tilts xi
 * from the committed normal into the current plane at every evaluation and caps the
 * force at the Coulomb limit, so stages never write history and xi is integrated to
 * the method's own order. At each commit the Coulomb return, the tilt and the reset of
 * ended contacts are applied to the committed history and XI is rebuilt from it
 * (esf_dem_ode_pack); when that changes y or its length (after a list rebuild) the
 * method is resized or reset to the new y, which costs an ARKODE restart.
 *
 * A failure inside f (a non-finite acceleration, an overlap beyond the limit) returns 1
 * (recoverable: adaptive methods retry with a smaller step) and keeps the message. */
#ifndef ESF_DEM_ODE_H
#define ESF_DEM_ODE_H

#include <sundials/sundials_context.h>
#include <sundials/sundials_nvector.h>

#include "core/sim.h"
#include "fused/fused.h"

enum {
  ESF_ODE_QN,
  ESF_ODE_QT,
  ESF_ODE_QG,
  ESF_ODE_QL,
  ESF_ODE_QW,
  ESF_ODE_QF,
  ESF_ODE_QFL, /* work of the fluid force (drag.c) */
  ESF_ODE_QS,  /* Hertz tangential springs' stiffness changes (forces.c p_stiff) */
  ESF_ODE_NQ,
  ESF_ODE_QR = ESF_ODE_NQ /* with rolling resistance only (o->nq = ESF_ODE_NQ + 1): the
                             power its dashpots and constant torques dissipate */
};

/* The force evaluation of velocity Verlet and the ODE methods: the fused step's
 * kernels, threaded (esf_fused_forces), when the sim's settings allow
 * (esf_fused_eval_refusal), else model/forces.c's general path; the same bits either
 * way. The path taken is logged when it changes. */
typedef struct esf_eval_path {
  esf_fused *fast;  /* NULL until the first evaluation */
  const char *name; /* the method, for the log */
  int ode;          /* 1: an ODE method (esf_fused_eval_refusal) */
  int logged;       /* the path last logged: 1 fused, 2 general, 0 none yet */
  int threads;      /* the threads the last evaluation ran on (esf_fused_threads; 1 on
                       the general path): the method's other loops take as many, so
                       that they follow the fused step's back-off on a busy machine */
} esf_eval_path;

/* Where an evaluation also writes the accelerations (esf_sim_accel's, without the
 * damping powers): acc, dw (3n each), global damping with with_global. */
typedef struct esf_eval_accel {
  double *acc, *dw;
  int with_global;
  int lazy; /* committing: F, M may stay in the fused step's accumulators until read,
               and then acc, dw are not written: s->ft_lazy is not NULL after the call
               and holds them (esf_fused_eval's lazy: a scheme whose every evaluation
               commits) */
} esf_eval_accel;

/* As esf_forces_eval(s, x, v, w, dt, mode, touching, err), by the path ep takes; with
 * ea (may be NULL) the accelerations too, on the fused path in its particle pass. */
int esf_eval_forces(esf_eval_path *ep, esf_sim *s, const double *x, const double *v,
                    const double *w, double dt, int mode, size_t *touching,
                    const esf_eval_accel *ea, esf_error *err);

void esf_eval_path_free(esf_eval_path *ep);

typedef struct esf_dem_ode {
  esf_sim *s;
  esf_eval_path path; /* the force evaluation's */
  size_t n;           /* particles in the layout */
  size_t nxi;         /* entries of the XI block (0 for frozen history) */
  size_t nq;          /* quadratures: ESF_ODE_NQ, + 1 with rolling resistance (QR) */
  size_t len;         /* length of y: 9 n + nq + nxi */
  int state;          /* 1: history as ODE state */
  double t_commit;    /* time the committed history refers to, s */
  long nrhs;          /* right-hand-side evaluations */
  long ncommit;       /* commit evaluations */
  long nfail;         /* recoverable failures returned */
  double el_t0;       /* tangential elastic energy at the start, J (history as state) */
  double slip_r;      /* plastic rolling work booked at the commits, J (rolling) */
  esf_error err;      /* the last failure inside f */
} esf_dem_ode;

/* Prepares the ODE view of the sim, for the method `name` (the log); call before the
 * first candidate-list build. esf_dem_ode_free releases it. */
void esf_dem_ode_init(esf_dem_ode *o, esf_sim *s, const char *name);
void esf_dem_ode_free(esf_dem_ode *o);

/* Sets o->n, o->nxi and o->len for the current particles and candidate lists (after
 * each build: the first may have removed particles that start outside the domain);
 * returns o->len. */
size_t esf_dem_ode_layout(esf_dem_ode *o);

/* Writes y (length o->len): x, v, w from the particles, the quadratures from q
 * (o->nq values, NULL: zero) and XI from the committed history (zero where not
 * touching). */
void esf_dem_ode_pack(const esf_dem_ode *o, const double *q, double *y);

/* The stored energy at the start (a trial evaluation at t0 for the elastic energy):
 * sets the ledger's e0. */
int esf_dem_ode_start(esf_dem_ode *o, const double *y, esf_error *err);

/* Absolute tolerance for the ledger quadratures: rtol times the energy scale (the
 * stored energy at the start plus the kinetic energy), so that the energy balance is
 * integrated as accurately as the motion; left out of the error test, a multistep
 * method extrapolates the dashpots' power across whole collisions. */
double esf_dem_ode_qtol(const esf_dem_ode *o, double rtol);

/* Fills the absolute-tolerance vector (length o->len): atol on x, v, w and
 * esf_dem_ode_qtol on the quadratures. */
void esf_dem_ode_atol(const esf_dem_ode *o, double *a, double rtol, double atol);

/* A SUNDIALS vector of length len for the ODE methods' state (ode_vector.c): OpenMP's
 * on *threads threads (read at every operation: the evaluation path's count), fused
 * vector operations on, its linear combinations, sums, scalings and constants blocked for
 * the cache and the same bits on any thread count (SUNDIALS' serial operations block by
 * block), and a serial WRMS norm scaled by the largest weight, without the subnormal
 * products of ARKODE's fixed-step weights (DBL_MIN), vectorised (ARKODE takes the state's
 * norm at every step, even with a fixed step). NULL when out of memory. Clones keep all
 * of it. */
N_Vector esf_dem_ode_vector(size_t len, const int *threads, SUNContext ctx);

/* z = sum c_i X_i over vectors of esf_dem_ode_vector (z none of X, nvec <= 64), the
 * same bits as N_VLinearCombination(nvec, c, X, z) with fewer passes: the terms with
 * c_i = 0 are left out, which changes no entry but a zero's sign (such a term is +-0 for
 * a finite X_i, and adding +-0 to a partial sum changes it only when it is +-0), and the
 * entries that come out zero are summed again with every term. resum_only: z holds the
 * sum of the nonzero terms already (the same nonzero terms, in the same order), only
 * its zeros are summed again. Returns the number of zero entries. */
long esf_dem_ode_lincomb_nz(int nvec, const double *c, N_Vector *X, N_Vector z,
                            int resum_only);

/* A SUNDIALS error handler that prints nothing: failures reach the user through
 * esfera's own messages (ARKErrHandlerFn and CVErrHandlerFn have this signature). */
void esf_sundials_silent(int code, const char *module, const char *function, char *msg,
                         void *data);

/* ESF_EINPUT, located at `domain`, when the scene has periodic axes: the ODE methods
 * refuse them (the wrap into the box would jump their state). */
int esf_dem_ode_periodic(const esf_sim *s, const char *name, esf_error *err);

/* ESF_EINPUT when the configuration asks for what the method (named `name`) cannot do:
 * history as state without state_ok, rootfinding without roots_ok. */
int esf_dem_ode_check(const esf_sim *s, const char *name, int state_ok, int roots_ok,
                      esf_error *err);

/* The right-hand side: 0 ok, 1 recoverable failure (message in o->err). */
int esf_dem_ode_rhs(esf_dem_ode *o, double t, const double *y, double *ydot);

/* The right-hand side at the end of a step already accepted (a fixed step's last stage
 * at t_{n+1}, y_{n+1}) with the commit esf_dem_ode_commit would make there, in one
 * evaluation: a trial and a commit at the same state compute the same forces (the
 * commit also writes histories, touch flags and p.f, p.t), so ydot and the committed
 * state are those of esf_dem_ode_rhs followed by esf_dem_ode_commit, bit for bit. Only
 * where esf_dem_ode_can_merge: without history as state and without the ledger (whose
 * quadratures and tallies the two evaluations take differently). 0 ok, 1 failure
 * (o->err), -1 not allowed. */
int esf_dem_ode_rhs_commit(esf_dem_ode *o, double t, const double *y, double *ydot);
int esf_dem_ode_can_merge(const esf_dem_ode *o);

/* After an accepted step to t with state y: copies x, v, w into the particles, commits
 * the contact history over [t_commit, t], updates the ledger (stored energies,
 * dissipation from the quadratures and the slip work) and sets s->t, s->led_time. */
int esf_dem_ode_commit(esf_dem_ode *o, double t, const double *y, esf_error *err);

#endif
