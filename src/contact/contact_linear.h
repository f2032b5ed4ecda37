/* contact_linear.h — the linear law's evaluation (contact_linear.c,
 * docs/physics.md#linear-springdashpot-law) for one contact, from law_body.h's
 * formulas, as a static inline function, so that a specialised caller (the fast wall
 * pass, wall_fast.c) compiles it without the strategy table's call. contact_linear.c's
 * table entry is this function. */
#ifndef ESF_CONTACT_LINEAR_H
#define ESF_CONTACT_LINEAR_H

#include <math.h>

#include "contact/contact_law.h"
#include "contact/contact_tangential.h"
#include "util/vec3.h"

static inline void esf_contact_linear_eval(const esf_pair_params *pp, double beta,
                                           int tframe, const esf_contact_in *in,
                                           const esf_contact_hist *hist, int first,
                                           esf_contact_hist *hist_out,
                                           esf_contact_out *out) {
  const double *n = in->n;
  if (esf_contact_apart(in, hist_out, out)) return;
  const double sm = sqrt(in->mstar);
  const double cn = beta > 0 ? beta * pp->kn : pp->cn_factor * sm;
  const double ct = beta > 0 ? beta * pp->kt : pp->ct_factor * sm;
  const double vn = v3_dot(in->vc, n); /* < 0 approaching */
  double fd, xi[3];
  const double fn = esf_law_linear_normal_s(pp->kn, cn, in->un, vn, &fd);
  esf_contact_tangential(pp, ct, tframe, 0, in, hist, first, vn, fn, 0.0, 0.0, xi, out);
  esf_contact_finish(in, fn, fd, xi, hist_out, out);
  out->fel = pp->kn * in->un;
  out->e_el_n = 0.5 * pp->kn * in->un * in->un;
}

#endif
