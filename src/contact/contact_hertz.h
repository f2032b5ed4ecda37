/* contact_hertz.h — the Hertz-Mindlin law's evaluation (contact_hertz.c,
 * docs/physics.md#hertz-mindlin-law) for one contact, from law_body.h's formulas, as a
 * static inline function, so that the fast wall pass (wall_fast.c) compiles it without
 * the strategy table's call, as it does the linear law's (contact_linear.h). */
#ifndef ESF_CONTACT_HERTZ_H
#define ESF_CONTACT_HERTZ_H

#include <math.h>

#include "contact/contact_law.h"
#include "contact/contact_tangential.h"
#include "util/vec3.h"

static inline void esf_contact_hertz_eval(const esf_pair_params *pp, double beta,
                                          int tframe, const esf_contact_in *in,
                                          const esf_contact_hist *hist, int first,
                                          esf_contact_hist *hist_out,
                                          esf_contact_out *out) {
  const double *n = in->n;
  if (esf_contact_apart(in, hist_out, out)) return;
  const double sm = sqrt(in->mstar);
  double ks, sn, st, qa, cn, ct;
  esf_law_hertz_springs_s(pp->hn, pp->ht, in->rstar, in->un, &ks, &sn, &st, &qa);
  if (pp->hertz_constant) qa = esf_law_hertz_qref_s(pp->estar, sm, in->rstar, pp->v_imp);
  esf_law_hertz_dashpots_s(beta, pp->cn_factor, pp->ct_factor, sm, qa, sn, st, &cn, &ct);
  const double vn = v3_dot(in->vc, n); /* < 0 approaching */
  const double st0 = esf_law_hertz_st_s(pp->ht, in->rstar, in->un + in->dt * vn);
  double fd, xi[3];
  const double fn = esf_law_linear_normal_s(ks, cn, in->un, vn, &fd);
  esf_contact_tangential(pp, ct, tframe, 0, in, hist, first, vn, fn, st, st0, xi, out);
  esf_contact_finish(in, fn, fd, xi, hist_out, out);
  out->fel = ks * in->un;
  out->e_el_n = esf_law_hertz_energy_s(ks, in->un);
}

#endif
