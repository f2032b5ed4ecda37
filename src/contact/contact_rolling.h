/* contact_rolling.h — rolling and twisting resistance for one contact at a time
 * (docs/physics.md#rolling-resistance): the pair's rolling stiffness, damping and
 * limits from the mixed parameters, and the evaluation (law_body.h's
 * esf_law_rolling_s), shared by the general path's pairs and walls (model/forces.c).
 * Ai, Chen, Rotter & Ooi 2011, Powder Technol. 206, 269-282: type C (epsd)
 * k_r = 2.25 kn mu_r^2 R*^2, limit mu_r R* fn, dashpot C_r = eta_r 2 sqrt(I_r k_r);
 * type A (cdt) the constant torque mu_r R* fn against the rolling spin. Twisting:
 * the same forms with mu_tw about the normal. Units: SI; torques on A. */
#ifndef ESF_CONTACT_ROLLING_H
#define ESF_CONTACT_ROLLING_H

#include <math.h>

#include "contact/contact_law.h"
#include "contact/lane_scalar.h"

/* The rolling spring of a contact whose normal stiffness is kn (the linear law's kn;
 * the Hertz law passes its tangent stiffness at the current overlap), N m/rad:
 * 2.25 kn mu^2 R*^2 (Ai et al. 2011 eq. 17; also the twisting spring with mu_tw). */
static inline double esf_rolling_stiffness(double kn, double mu, double rstar) {
  return 2.25 * kn * mu * mu * rstar * rstar;
}

/* The rolling resistance of a touching contact: pair parameters pp, model
 * (ESF_ROLL_*), normal stiffness kn (esf_rolling_stiffness), effective radius rstar
 * (rA rB/(rA + rB); a wall: rA), the equivalent inertias for rolling ir
 * (1/(1/(IA + mA rA^2) + 1/(IB + mB rB^2)), Ai eq. 21; a wall: IA + mA rA^2) and
 * twisting itw (1/(1/IA + 1/IB); a wall: IA), normal force fn (a tension gives no
 * resistance), relative spin wrel = wA - wB (a wall: its angular velocity), the
 * stored state h (live: touching at the last commit). */
static inline void esf_contact_rolling(const esf_pair_params *pp, int model, double kn,
                                       double rstar, double ir, double itw, double fn,
                                       double dt, const double n[3], const double wrel[3],
                                       const esf_contact_roll *h, int live,
                                       esf_law_rout_s *o) {
  const double f = fn > 0 ? fn : 0.0;
  esf_law_rpar_s P = {.mr = pp->mu_r * rstar * f,
                      .mtw = pp->mu_tw * rstar * f,
                      .cdt = model == ESF_ROLL_CDT};
  if (!P.cdt) {
    P.kr = esf_rolling_stiffness(kn, pp->mu_r, rstar);
    P.ktw = esf_rolling_stiffness(kn, pp->mu_tw, rstar);
    P.cr = 2.0 * pp->eta_r * sqrt(ir * P.kr);
    P.ctw = 2.0 * pp->eta_r * sqrt(itw * P.ktw);
  }
  esf_law_rolling_s(&P, dt, n, wrel, h->m, h->t, live, o);
}

#endif
