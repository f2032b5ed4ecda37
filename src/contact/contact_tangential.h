/* contact_tangential.h — the tangential force every contact law shares
 * (docs/physics.md#tangential-force-and-the-mohr-coulomb-cap), and the assembly of the
 * total contact force; static inline so that each law compiles them into its own
 * evaluation (no call in the per-contact path).
 *
 * Per evaluation (000 3-17..3-26, 004 2.16, 2.26):
 *   1. bring xi into the current contact plane: xi1 = xi + (n_old x n) x xi, then
 *      xi2 = xi1 + (spin_n dt n) x xi1 (the seed prints 3-18 without dt; the angle is
 *      spin dt); or, with ESF_TFRAME_PROJECT, project on the plane and rescale;
 *   2. xi_trial = xi2 + vct dt, vct = vc - (vc.n) n (or the tangential part of a
 *      caller-given mean velocity over dt: ODE methods carry the history with the
 *      mean of the velocities at the commit and now, a trapezoidal increment);
 *   3. trial force on A: ft = kt xi_trial + ct vct (dashpot while sticking);
 *   4. failure surface (Mohr-Coulomb with tension cut-off, 004 Fig. 2.13):
 *      tau = max(0, c + mu fn), and tau = 0 when fn < -tensile_limit; fn is the total
 *      normal force, compressive positive, so a bond in tension (fn < 0, adhesive law)
 *      keeps the shear strength c - mu |fn| and none once that reaches zero;
 *   5. if |ft| > tau: sliding; radial return ft = tau ft/|ft|, no dashpot, and the
 *      elastic displacement is reset to xi = ft/kt (2.16); the friction work is the
 *      slip xi_trial - xi times the mean elastic force kt (xi2 + xi)/2.
 * A contact that was not touching (first) starts from xi = 0.
 * Units: SI. Forces are those on A. */
#ifndef ESF_CONTACT_TANGENTIAL_H
#define ESF_CONTACT_TANGENTIAL_H

#include <math.h>

#include "contact/contact_law.h"
#include "util/vec3.h"

static inline void esf_contact_tangential(const esf_pair_params *pp, double ct,
                                          int tframe, const esf_contact_in *in,
                                          const esf_contact_hist *hist, int first,
                                          double vn, double fn, double xi_new[3],
                                          esf_contact_out *out) {
  const double *n = in->n;
  double xi[3] = {0, 0, 0};
  if (!first) {
    if (tframe == ESF_TFRAME_ROTATE) {
      double a[3], b[3];
      v3_cross(a, hist->n, n); /* n_old x n */
      v3_cross(b, a, hist->xi);
      v3_add(xi, hist->xi, b);
      double s[3] = {in->spin_n * in->dt * n[0], in->spin_n * in->dt * n[1],
                     in->spin_n * in->dt * n[2]};
      v3_cross(b, s, xi);
      v3_add(xi, xi, b);
    } else {
      double m0 = v3_norm(hist->xi);
      v3_copy(xi, hist->xi);
      v3_axpy(xi, -v3_dot(xi, n), n);
      double m1 = v3_norm(xi);
      if (m1 > 0) v3_scale(xi, m0 / m1, xi);
    }
  }
  double vct[3];
  v3_copy(vct, in->vc);
  v3_axpy(vct, -vn, n);
  double xi_rot[3];
  v3_copy(xi_rot, xi);
  if (in->vinc) { /* a caller-given mean velocity over dt (ODE methods' carry) */
    double vi[3];
    v3_copy(vi, in->vinc);
    v3_axpy(vi, -v3_dot(vi, n), n);
    v3_axpy(xi, in->dt, vi);
  } else {
    v3_axpy(xi, in->dt, vct); /* trial elastic displacement */
  }

  double ft[3], fdt[3];
  v3_scale(fdt, ct, vct);
  v3_scale(ft, pp->kt, xi);
  v3_add(ft, ft, fdt);

  double tau = fn < -pp->tensile_limit ? 0.0 : pp->cohesion + pp->mu * fn;
  if (tau < 0.0) tau = 0.0;
  double ftm2 = v3_norm2(ft);
  out->sliding = 0;
  out->slip_work = 0.0;
  if (ftm2 > tau * tau) {
    double ftm = sqrt(ftm2);
    v3_scale(ft, tau / ftm, ft);
    double xn[3];
    v3_scale(xn, pp->kt > 0 ? 1.0 / pp->kt : 0.0, ft);
    /* slip s = xi_trial - xi_new, the relative motion not stored elastically. Its work
       is taken with the mean elastic force across the return, kt (xi_rot + xi_new)/2:
       with the stored energy measured as (1/2) kt xi_n . xi_{n+1} (forces.c) this is
       the energy the return removes exactly (for the seed's force increments, too) */
    double slip[3], fmean[3];
    v3_sub(slip, xi, xn);
    v3_add(fmean, xi_rot, xn);
    out->slip_work = 0.5 * pp->kt * v3_dot(fmean, slip);
    v3_copy(xi, xn);
    v3_set(fdt, 0, 0, 0);
    out->sliding = 1;
  }
  v3_copy(out->ft, ft);
  v3_copy(out->fd_t, fdt);
  out->e_el_t = 0.5 * pp->kt * v3_norm2(xi);
  v3_copy(xi_new, xi);
}

static inline void esf_contact_finish(const esf_contact_in *in, double fn, double fd_n,
                                      const double xi[3], esf_contact_hist *hist_out,
                                      esf_contact_out *out) {
  const double *n = in->n;
  out->fn = fn;
  out->fd_n = fd_n;
  /* on A: -fn n (pushed away from B) plus the tangential force */
  out->f[0] = -fn * n[0] + out->ft[0];
  out->f[1] = -fn * n[1] + out->ft[1];
  out->f[2] = -fn * n[2] + out->ft[2];
  out->touching = 1;
  out->broke = 0;
  out->e_break = 0.0;
  if (hist_out) {
    v3_copy(hist_out->xi, xi);
    v3_copy(hist_out->n, n);
  }
}

#endif
