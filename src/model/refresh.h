/* integ_common.h — pieces every integrator uses: keeping the candidate lists valid and
 * turning forces into accelerations with the damping forms applied as force terms. */
#ifndef ESF_INTEG_COMMON_H
#define ESF_INTEG_COMMON_H

#include "core/sim.h"

/* Rebuilds the candidate lists when a particle moved more than skin/2 (removing the
 * particles that left the domain first). *rebuilt is set when it did (may be NULL). */
int esf_integ_refresh(esf_sim *s, int *rebuilt, esf_error *err);

/* Accelerations from the forces and torques in s->p.f, s->p.t at velocities v, w:
 *   a = (F + F_local(F, v) - alpha_r m v) / m,  dw = (M + M_local(M, w) - alpha_t I w) /
 * I (global damping as a force term: the form the Runge-Kutta methods integrate). With
 * with_global = 0 the global term is left out (the caller treats it itself). Writes 3n
 * values to acc and dw. When p_damp is not NULL it receives the powers dissipated by
 * global and local damping (W) at this state. */
void esf_integ_accel(const esf_sim *s, const double *v, const double *w, double *acc,
                     double *dw, double p_damp[2], int with_global);

/* Stored energies of the state (x, v, w): kinetic (translational, rotational) and
 * gravitational potential. */
void esf_integ_energies(const esf_sim *s, const double *x, const double *v,
                        const double *w, double *kin_t, double *kin_r, double *pot);

#endif
