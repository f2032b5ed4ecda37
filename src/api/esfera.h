/* esfera.h — the public C API of esfera (docs/library.md).
 *
 * One opaque handle, esf_handle, is one simulation: a scene loaded and set up. Drive it
 * with the scene's own integrator (esf_handle_step), or as an ODE y' = f(t, y) with a
 * method of your own (esf_handle_y0, esf_handle_rhs, esf_handle_commit). Read its state
 * (esf_handle_array) and its energy ledger (esf_handle_energies) between calls.
 *
 * Conventions: every function that can fail returns an int status, ESF_OK (0) or a
 * negative ESF_E* code, and leaves the message (for scene input located as
 * file:line:column) in the handle: esf_handle_message. The library never exits, prints
 * nothing and keeps no global state; handles are independent (one thread per handle at
 * a time). Units are SI. Vectors are stored xyz-interleaved per particle (x[3i + k]).
 *
 * Names and meanings below are stable within ESF_API_VERSION; a program compiled
 * against one header may compare ESF_API_VERSION with esf_api_version() at run time.
 * Only the names declared here are exported by the shared library. */
#ifndef ESFERA_H
#define ESFERA_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define ESF_API_VERSION 1 /* raised when a declaration here changes meaning */

/* Status codes (the same values as the library's internal ones). */
#ifndef ESF_ERROR_H
enum {
  ESF_OK = 0,
  ESF_EINPUT = -1,   /* bad input: scene, --set override, call out of order */
  ESF_EIO = -2,      /* a file could not be read */
  ESF_ENOMEM = -3,   /* out of memory */
  ESF_ENUMERIC = -4, /* the simulation failed: instability, non-finite state, overlap */
  ESF_EINTERNAL = -5 /* a bug in esfera */
};
#endif

typedef struct esf_handle esf_handle;

/* The library's version ("0.1.0") and API version (ESF_API_VERSION it was built with). */
const char *esf_version(void);
int esf_api_version(void);

/* Loads the scene file `scene`, applies the overrides sets[0..nsets) ("dotted.key=VALUE",
 * as the program's --set) and sets the simulation up. *out receives a handle even when
 * loading fails (except when memory for the handle itself is lacking: then *out is NULL
 * and the status ESF_ENOMEM): read the message with esf_handle_message, then close it.
 * A failed handle refuses every other call. */
int esf_handle_open(esf_handle **out, const char *scene, const char *const *sets,
                    int nsets);

/* Releases everything; sets *h to NULL. Accepts NULL and an already closed handle. */
void esf_handle_close(esf_handle **h);

/* The status and message of the last failed call ("" and ESF_OK after a success). */
int esf_handle_status(const esf_handle *h);
const char *esf_handle_message(const esf_handle *h);

/* Particle count, simulated time (s), step size (s; the initial one for adaptive
 * methods), steps (or commits) taken, the scene's end time (run.duration, or run.steps
 * x dt; s), its integrator (integrator.method) and its dimension (3, or 2 for disks). */
size_t esf_handle_count(const esf_handle *h);
double esf_handle_time(const esf_handle *h);
double esf_handle_dt(const esf_handle *h);
long esf_handle_steps(const esf_handle *h);
double esf_handle_end_time(const esf_handle *h);
const char *esf_handle_method(const esf_handle *h);
int esf_handle_dim(const esf_handle *h);

/* Worker threads of the handle's steps (default: every core the process may use);
 * results do not depend on it. Only before the first step or ODE call (ESF_EINPUT
 * after), n from 1 to 1024. */
int esf_handle_set_threads(esf_handle *h, int n);

/* Per-particle arrays. */
enum {
  ESF_ARRAY_POSITION, /* 3n, m */
  ESF_ARRAY_VELOCITY, /* 3n, m/s (the leapfrog's are at the half step before t) */
  ESF_ARRAY_SPIN,     /* 3n, angular velocity, rad/s */
  ESF_ARRAY_FORCE,    /* 3n, contact, wall and body forces of the last evaluation, N */
  ESF_ARRAY_TORQUE,   /* 3n, their torques, N m */
  ESF_ARRAY_RADIUS,   /* n, m */
  ESF_ARRAY_MASS,     /* n, kg */
  ESF_ARRAY_INERTIA,  /* n, moment of inertia, kg m^2 */
  ESF_ARRAY_COUNT
};

/* A pointer to the library's own array `which` (ESF_ARRAY_*), *len set to its length;
 * NULL (and *len 0) for an unknown name or a failed handle. Read only. Valid until the
 * next call of esf_handle_step, esf_handle_commit or esf_handle_close (particles that
 * leave the domain are removed, and the arrays move). */
const double *esf_handle_array(esf_handle *h, int which, size_t *len);

/* The particles' stable identifiers (n; the order the scene defined them in), valid as
 * esf_handle_array's. */
const int64_t *esf_handle_ids(const esf_handle *h);

/* The energy ledger (docs/output.md#energycsv): ESF_ENERGY_COLUMNS values in the
 * columns of energy.csv (time, kinetic_translational, ..., total_error), named by
 * esf_energy_column. The ledger is on when the scene sets output.energy_every > 0
 * (ESF_EINPUT otherwise). Values refer to the time in row[0]. */
/* This version's count: later versions add columns at the end (a program built
 * against an older header reads a prefix of the row; a binding counts them with
 * esf_energy_column). */
#define ESF_ENERGY_COLUMNS 24
const char *esf_energy_column(int k); /* NULL outside 0..ESF_ENERGY_COLUMNS-1 */
int esf_handle_energies(esf_handle *h, double row[ESF_ENERGY_COLUMNS]);

/* Takes k steps with the scene's integrator (integrator.method). Adaptive methods
 * stop at the scene's end time (fewer than k steps then; ESF_EINPUT when already
 * there at the call). The first call fixes the handle to this use: the ODE calls
 * below then refuse, and the other way round. */
int esf_handle_step(esf_handle *h, long k);

/* The DEM as an ODE (docs/library.md#the-ode-view):
 *   y = [ x (3n) | v (3n) | w (3n) | Q (nq) | XI (3 per candidate contact) ]
 * Q the ledger's quadratures, J, named by esf_ode_quadrature(0..nq-1) (energy
 * dissipated by normal and tangential dashpots, global and local damping, the work of
 * walls, the power into tangential springs, the work of the fluid, the Hertz
 * tangential springs' stiffness changes, ...; new ones are added at the end); nq is
 * the scene's (esf_handle_ode_nq): the rolling resistance's quadrature,
 * "dissipated_rolling", only in scenes with some rolling or twisting friction; XI only
 * with integrator.history: state (the live tangential displacements, m). f = [ v | a |
 * dw/dt | powers | dXI/dt ]. Contact history is frozen at the last commit
 * (integrator.history: frozen, the default): f(t, y) carries each contact's committed
 * tangential displacement to t; esf_handle_commit(t, y) accepts a step: it commits the
 * histories over it, updates the ledger and refreshes the contact lists. Particles
 * leaving the domain fail the commit. With history as state, a commit rebuilds XI from
 * the committed histories and a list rebuild changes its length: continue from
 * esf_handle_y0 (of esf_handle_ode_size entries) after every commit. With frozen history
 * y0 after a commit is the committed y itself. The first ODE call builds the contact
 * lists and starts the ledger. */
size_t esf_handle_ode_size(esf_handle *h);   /* length of y; 0 on failure */
size_t esf_handle_ode_nq(esf_handle *h);     /* nq, Q's length in y; 0 on failure */
const char *esf_ode_quadrature(int k);       /* Q's names; NULL past the last */
int esf_handle_y0(esf_handle *h, double *y); /* the state to continue from */
int esf_handle_rhs(esf_handle *h, double t, const double *y, double *ydot);
int esf_handle_commit(esf_handle *h, double t, const double *y);

#ifdef __cplusplus
}
#endif

#endif
