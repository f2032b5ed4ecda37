/* modes.h — the highest natural frequency of the assembled contact system, for the
 * critical-time-step study (issue 7): omega_max^2 is the largest eigenvalue of
 * M^{-1/2} K M^{-1/2}, K the stiffness of the touching contacts' normal and tangential
 * springs about the current configuration, M the masses and moments of inertia. */
#ifndef ESF_MODES_H
#define ESF_MODES_H

#include "core/sim.h"

typedef struct esf_modes {
  size_t dofs;        /* degrees of freedom assembled (6 per sphere, 3 per disk) */
  size_t contacts;    /* touching contacts (pairs and walls) */
  double omega_max;   /* rad/s (0 without contacts) */
  double xi_max;      /* the largest contact damping ratio among the touching ones */
  double dt_undamped; /* 2 / omega_max, s */
  double dt_damped;   /* 2 / omega_max (sqrt(1 + xi^2) - xi) with xi_max, s */
  double xi_mode;     /* the top mode's own damping ratio (the dashpots in its shape) */
  double dt_mode;     /* 2 / omega_max (sqrt(1 + xi^2) - xi) with xi_mode, s */
  size_t argmax_dof;  /* the degree of freedom with the largest share in that mode */
  double lambda;      /* largest eigenvalue of dt^2 A + 2 dt B at the scene's dt, dense
                         (model/stability.h: the leapfrog is stable below 4) */
  double lambda_live; /* the same from the live check's Lanczos (stability.c) */
  double dt_live;     /* the live check's limit: the dt where lambda reaches 4, s */
} esf_modes;

/* Largest dense problem accepted (degrees of freedom): the eigenproblem is O(dofs^3). */
#define ESF_MODES_MAX_DOFS 6000

/* Evaluates the contacts at the sim's state (after esf_sim_setup; builds the candidate
 * lists if needed) and solves the eigenproblem with GSL. Errors:
 * ESF_EINPUT when the system is larger than ESF_MODES_MAX_DOFS, ESF_ENOMEM. */
int esf_modes_compute(esf_sim *s, esf_modes *out, esf_error *err);

#endif
