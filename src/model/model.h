/* model.h — the assembled model: a sim set up from a filled scene and torn down
 * (setup.c), its candidate lists kept valid between steps (refresh.c), and the
 * accelerations and stored energies of a state (accel.c). Every integrator and the
 * program's commands drive the model through these and model/forces.h. */
#ifndef ESF_MODEL_H
#define ESF_MODEL_H

#include "core/sim.h"

/* Prepares a sim whose cfg, particles, materials and walls are filled in: mixes the
 * pair table, sets masses and inertias, picks dt (auto or checked), allocates lists. */
int esf_sim_setup(esf_sim *s, esf_error *err);
void esf_sim_release(esf_sim *s);

/* Rebuilds the candidate lists when a particle moved more than skin/2 (removing the
 * particles that left the domain first). *rebuilt is set when it did (may be NULL). */
int esf_sim_refresh(esf_sim *s, int *rebuilt, esf_error *err);

/* Accelerations from the forces and torques in s->p.f, s->p.t at velocities v, w:
 *   a = (F + F_local(F, v) - alpha_r m v) / m,  dw = (M + M_local(M, w) - alpha_t I w) /
 * I (global damping as a force term: the form the Runge-Kutta methods integrate). With
 * with_global = 0 the global term is left out (the caller treats it itself). Writes 3n
 * values to acc and dw, on `threads` threads when p_damp is NULL (else one). When p_damp
 * is not NULL it receives the powers dissipated by global and local damping (W) at this
 * state. */
void esf_sim_accel(const esf_sim *s, const double *v, const double *w, double *acc,
                   double *dw, double p_damp[2], int with_global, int threads);

/* Stored energies of the state (x, v, w): kinetic (translational, rotational) and
 * gravitational potential. */
void esf_sim_energies(const esf_sim *s, const double *x, const double *v, const double *w,
                      double *kin_t, double *kin_r, double *pot);

#endif
