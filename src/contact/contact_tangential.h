/* contact_tangential.h — the general path's tangential force (law_body.h's, for one
 * contact: docs/physics.md#tangential-force-and-the-mohr-coulomb-cap) and the assembly
 * of the total contact force, in the strategy table's terms (contact_law.h); static
 * inline so that each law compiles them into its own evaluation. A contact that was not
 * touching (first) starts from xi = 0; tension = 1 for a law that may pull (the shear
 * strength vanishes once fn < -tensile_limit). Units: SI. Forces are those on A. */
#ifndef ESF_CONTACT_TANGENTIAL_H
#define ESF_CONTACT_TANGENTIAL_H

#include "contact/contact_law.h"
#include "contact/lane_scalar.h"
#include "util/vec3.h"

/* st > 0: the Hertz-Mindlin force record (law_body.h), stiffness st now and st0 at the
 * last commit's overlap (0: unknown); st = 0: the linear spring kt. */
static inline __attribute__((always_inline)) void
esf_contact_tangential(const esf_pair_params *pp, double ct, int tframe, int tension,
                       const esf_contact_in *in, const esf_contact_hist *hist, int first,
                       double vn, double fn, double st, double st0, double xi_new[3],
                       esf_contact_out *out) {
  const esf_law_tpar_s P = {.kt = st > 0 ? 1.0 : pp->kt,
                            .hertz = st > 0,
                            .st = st,
                            .st0 = st0,
                            .ct = ct,
                            .mu = pp->mu,
                            .coh = pp->cohesion,
                            .tl = pp->tensile_limit,
                            .rotate = tframe == ESF_TFRAME_ROTATE,
                            .tension = tension,
                            .ledger = 1,
                            .vi = in->vinc};
  esf_law_tout_s T;
  esf_law_tangential_s(&P, in->dt, in->n, in->spin_n, in->vc, vn, fn, hist->xi, hist->n,
                       !first, &T);
  v3_copy(out->ft, T.ft);
  v3_copy(out->fd_t, T.fdt);
  v3_copy(xi_new, T.xi);
  out->sliding = T.slide != 0;
  out->slip_work = T.slip;
  out->e_el_t = T.e_el;
  out->w_st = T.w_st;
}

/* A contact that does not overlap (un <= 0): no force, the history restarts from
 * xi = 0 in the current normal. Returns 1 then (the law is done), else 0. */
static inline int esf_contact_apart(const esf_contact_in *in, esf_contact_hist *hist_out,
                                    esf_contact_out *out) {
  if (in->un > 0.0) return 0;
  const double *n = in->n;
  *out = (esf_contact_out){0};
  if (hist_out) *hist_out = (esf_contact_hist){{0, 0, 0}, {n[0], n[1], n[2]}};
  return 1;
}

static inline void esf_contact_finish(const esf_contact_in *in, double fn, double fd_n,
                                      const double xi[3], esf_contact_hist *hist_out,
                                      esf_contact_out *out) {
  double m[3];
  out->fn = fn;
  out->fd_n = fd_n;
  esf_law_force_s(in->n, fn, out->ft, out->f, m); /* on A: ft - fn n */
  out->touching = 1;
  out->broke = 0;
  out->e_break = 0.0;
  if (hist_out) {
    v3_copy(hist_out->xi, xi);
    v3_copy(hist_out->n, in->n);
  }
}

#endif
