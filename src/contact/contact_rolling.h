/* contact_rolling.h — rolling and twisting resistance for one contact at a time
 * (docs/physics.md#rolling-resistance): law_body.h's esf_law_rolling_par_s and
 * esf_law_rolling_s from a pair's mixed parameters, shared by the general path's pairs
 * and walls (model/forces.c); the fused step's batches run the same formulas
 * (fused/pair_batch.c). Ai, Chen, Rotter & Ooi 2011, Powder Technol. 206, 269-282:
 * type C (epsd) k_r = 2.25 kn mu_r^2 R*^2 (Hertz-Mindlin: kn = S_n at the overlap), limit
 * mu_r R* fn, dashpot C_r = eta_r 2 sqrt(I_r k_r) off at the limit; type A (cdt) the
 * constant torque mu_r R* fn against the rolling spin. Twisting: the same forms with
 * mu_tw about the normal. Units: SI; torques on A. */
#ifndef ESF_CONTACT_ROLLING_H
#define ESF_CONTACT_ROLLING_H

#include "contact/contact_law.h"
#include "contact/lane_scalar.h"

/* The normal stiffness kn of k_r = 2.25 kn mu_r^2 R*^2 for a touching contact at
 * overlap un with reduced radius rstar: the linear law's kn, or for a Hertz-Mindlin
 * pair (hn > 0) the normal tangent stiffness S_n = 2 E* sqrt(R* un) at that overlap
 * (esf_law_hertz_springs's sn: the same operations as the fused step's batches). */
static inline double esf_contact_rolling_kn(const esf_pair_params *pp, double rstar,
                                            double un) {
  return pp->hn > 0 ? esf_law_hertz_sn_s(pp->hn, rstar, un) : pp->kn;
}

/* The rolling resistance of a touching contact: pair parameters pp, model
 * (ESF_ROLL_*), normal stiffness kn, R* and the inertias ir, itw
 * (esf_law_rolling_pair_s), normal force fn, relative spin wrel = wA - wB (a wall: its
 * angular velocity), wi NULL or the spin the increments integrate over dt (the ODE
 * methods' trapezoidal carry), the stored state h (live: touching at the last
 * commit). stiff: o->w_k books the springs' stiffness change from kn0, the normal
 * stiffness at the last commit's overlap (Hertz pairs with the ledger). */
static inline void esf_contact_rolling(const esf_pair_params *pp, int model, double kn,
                                       int stiff, double kn0, double rstar, double ir,
                                       double itw, double fn, double dt,
                                       const double n[3], const double wrel[3],
                                       const double *wi, const esf_contact_roll *h,
                                       int live, esf_law_rout_s *o) {
  esf_law_rpar_s P;
  esf_law_rolling_par_s(kn, pp->mu_r, pp->mu_tw, pp->eta_r, rstar, ir, itw, fn,
                        model == ESF_ROLL_CDT, &P);
  P.wi = wi;
  if (stiff) {
    P.stiff = 1;
    P.kr0 = esf_law_rolling_stiffness_s(kn0, pp->mu_r, rstar);
    P.ktw0 = esf_law_rolling_stiffness_s(kn0, pp->mu_tw, rstar);
  }
  esf_law_rolling_s(&P, dt, n, wrel, h->m, h->t, live, o);
}

#endif
