/* contact_linear.h — the linear law's evaluation (contact_linear.c,
 * docs/physics.md#linear-springdashpot-law) as a static inline function, so that a
 * specialised caller (the fast wall pass, wall_fast.c) compiles the same arithmetic
 * without the strategy table's call and structs. contact_linear.c's table entry is
 * this function. */
#ifndef ESF_CONTACT_LINEAR_H
#define ESF_CONTACT_LINEAR_H

#include "contact/contact_law.h"
#include "contact/contact_tangential.h"

#include <math.h>

#include "util/vec3.h"

static inline void esf_contact_linear_eval(const esf_pair_params *pp, double beta,
                                           int tframe, const esf_contact_in *in,
                                           const esf_contact_hist *hist, int first,
                                           esf_contact_hist *hist_out,
                                           esf_contact_out *out) {
  const double *n = in->n;
  if (in->un <= 0.0) {
    *out = (esf_contact_out){0};
    if (hist_out) *hist_out = (esf_contact_hist){{0, 0, 0}, {n[0], n[1], n[2]}};
    return;
  }
  double sm = sqrt(in->mstar);
  double cn = beta > 0 ? beta * pp->kn : pp->cn_factor * sm;
  double ct = beta > 0 ? beta * pp->kt : pp->ct_factor * sm;

  double vn = v3_dot(in->vc, n); /* < 0 approaching */
  double fel = pp->kn * in->un;
  double fd = -cn * vn;
  double fn = fel + fd;
  if (fn < 0.0) {
    fn = 0.0;
    fd = -fel;
  }
  double xi[3];
  esf_contact_tangential(pp, ct, tframe, in, hist, first, vn, fn, xi, out);
  esf_contact_finish(in, fn, fd, xi, hist_out, out);
  out->e_el_n = 0.5 * pp->kn * in->un * in->un;
}

#endif
