/* contact_linear.c — the linear spring-dashpot law with incremental tangential force
 * (Cundall & Strack; docs/physics.md#linear-springdashpot-law).
 *
 * Normal (004 2.19): fn = kn un + cn dun/dt with dun/dt = -vc.n; no tension: when the
 * sum is negative the force is zero (the dashpot's applied share is then -kn un).
 * Tangential: esf_contact_tangential (contact_tangential.h), capped by the Coulomb /
 * Mohr-Coulomb surface of the normal force.
 * Dashpots: c = 2 gamma sqrt(m* k) (Tsuji, 004 2.27–2.29), or c = beta k (Rayleigh).
 * Elastic energy: (1/2) kn un^2 and (1/2) kt |xi|^2.
 * Units: SI. Forces are those on A. The law ignores a bond state.
 * The evaluation itself is the inline esf_contact_linear_eval (contact_linear.h), which
 * the fast wall pass (wall_fast.c) shares. */
#include "contact/contact_law.h"
#include "contact/contact_linear.h"

#include <math.h>

#include "util/vec3.h"

static void linear_eval(const esf_pair_params *pp, double beta, int tframe,
                        const esf_contact_in *in, const esf_contact_hist *hist,
                        const esf_contact_bond *bond, int first,
                        esf_contact_hist *hist_out, esf_contact_out *out) {
  (void)bond; /* no bonded term */
  esf_contact_linear_eval(pp, beta, tframe, in, hist, first, hist_out, out); /* .h */
}

static double linear_energy_n(const esf_pair_params *pp, const esf_contact_bond *bond,
                              double un, double rstar, double *fel) {
  (void)bond;
  (void)rstar;
  *fel = pp->kn * un;
  return 0.5 * pp->kn * un * un;
}

const esf_contact_law esf_contact_linear = {
    .name = "linear",
    .flags = ESF_LAW_HISTORY | ESF_LAW_FUSED,
    .eval = linear_eval,
    .energy_n = linear_energy_n,
};
