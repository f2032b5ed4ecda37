/* contact_hertz.c — the Hertz-Mindlin law (docs/physics.md#hertz-mindlin-law): Hertz's
 * normal force (4/3) E* sqrt(R*) u^(3/2) (Johnson 1985, 4.22), Mindlin's tangential
 * stiffness 8 G* sqrt(R* u) applied to force increments (Mindlin 1949; the no-slip
 * limit of Mindlin & Deresiewicz 1953, as in Di Renzo & Di Maio 2004), the Coulomb cap
 * of the linear law, dashpots 2 gamma sqrt(m* S) (Tsuji et al. 1992) with gamma the
 * exact map of the restitution (hertz_map.c). No tension: the total normal force is cut
 * at zero, as the linear law's.
 * Elastic energy: (8/15) E* sqrt(R*) u^(5/2) and |F_t|^2 / (2 S_t).
 * Units: SI. Forces are those on A. The law ignores a bond state (no bonds: scene
 * reading and esf_materials_mix refuse adhesion with it).
 * The evaluation itself is the inline esf_contact_hertz_eval (contact_hertz.h). */
#include "contact/contact_hertz.h"

static void hertz_eval(const esf_pair_params *pp, double beta, int tframe,
                       const esf_contact_in *in, const esf_contact_hist *hist,
                       const esf_contact_bond *bond, int first,
                       esf_contact_hist *hist_out, esf_contact_out *out) {
  (void)bond;
  esf_contact_hertz_eval(pp, beta, tframe, in, hist, first, hist_out, out);
}

static double hertz_energy_n(const esf_pair_params *pp, const esf_contact_bond *bond,
                             double un, double rstar, double *fel) {
  (void)bond;
  double ks, sn, st, qa;
  esf_law_hertz_springs_s(pp->hn, pp->ht, rstar, un, &ks, &sn, &st, &qa);
  *fel = ks * un;
  return esf_law_hertz_energy_s(ks, un);
}

const esf_contact_law esf_contact_hertz = {
    .name = "hertz",
    .flags = ESF_LAW_HISTORY | ESF_LAW_FUSED,
    .eval = hertz_eval,
    .energy_n = hertz_energy_n,
};
