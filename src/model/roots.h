/* roots.h — event functions that locate contact onset and separation in time,
 * for the ODE methods' optional rootfinding (integrator.roots). */
#ifndef ESF_ROOTS_H
#define ESF_ROOTS_H

#include "core/sim.h"

/* Number of event functions: one per candidate contact (pair list, then wall list). */
size_t esf_roots_count(const esf_sim *s);

/* g[k] > 0 exactly when candidate k carries a normal force at state (x, v) under the
 * no-tension linear law: g = min(un, un - (c_n/k_n) vn) with un the overlap and vn the
 * normal approach rate (negative approaching), so g crosses zero at onset (un = 0) and
 * at separation (k_n un + c_n (-vn) = 0, before the overlap closes when damped). Both
 * terms are lengths, m. Writes esf_roots_count(s) values. */
void esf_roots_eval(const esf_sim *s, const double *x, const double *v, double *g);

#endif
