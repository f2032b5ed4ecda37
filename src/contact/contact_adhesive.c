/* contact_adhesive.c — the nonlinear adhesive normal law with the bond rule Phi
 * (docs/physics.md#adhesive-normal-law-and-bonds; 004 eqs. 2.22–2.25).
 *
 * Law. With u the overlap (> 0 interpenetrating, < 0 a gap) and forces compressive
 * positive (the seed's 2.22 with its sign flipped), the elastic normal force of a bond is
 *   f(u) = kn [u - (1 - e^{-alpha u}) delta] = kn [u + delta expm1(-alpha u)],
 * negative (tension) between the two roots of f; delta and alpha follow from the user's
 * peak tension F and eps (2.23, 2.24; esf_adhesion_derive: the two regimes either side
 * of eps = 1/e, the rest state, the rupture point, the largest stiffness). Past the
 * rupture point the formula turns compressive again (e^{-x} grows without bound); it is
 * never applied there: a bonded contact with u < u_rupture breaks.
 *
 * Bond rule (2.25). bond->on is Phi (contact_law.h, esf_contact_bond): set for the
 * contacts that exist at the start (bonds.c), with an overlap offset bond->s (u = un +
 * s in the law; 0 unless the scene's bond_gap bonds pairs at a gap). A bonded contact
 * carries force at any u >= u_rupture, gap or not; below, the bond breaks for good
 * (adhesive_eval). A contact without a bond (every later contact of the pair) is the
 * linear law: compression and friction only. Tangential: esf_contact_tangential with
 * the total normal force (tension negative). Units: SI. Forces are those on A. */
#include "contact/contact_law.h"
#include "contact/contact_linear.h"
#include "contact/contact_tangential.h"

#include <math.h>

#include "util/vec3.h"

double esf_adhesion_force(double kn, const esf_adhesion *a, double u) {
  return kn * (u + a->delta * expm1(-a->alpha * u));
}

/* The spring's potential, closed form: W(u) = integral_0^u f(s) ds
 *   = kn [u^2/2 - delta (u + expm1(-x)/alpha)], x = alpha u, W(0) = 0; W(u_r) > 0 for
 *   eps > 1/e is the work needed to open a bond from rest to rupture. */
double esf_adhesion_energy(double kn, const esf_adhesion *a, double u) {
  if (!(a->alpha > 0)) return 0.5 * kn * u * u;
  return kn * (0.5 * u * u - a->delta * (u + expm1(-a->alpha * u) / a->alpha));
}

/* The root of g(x) = x - L (1 - e^{-x}) other than 0: g is convex, so Newton from a
 * point beyond the root on its far side (where g > 0) converges monotonically. */
static double other_root(double L) {
  double x = L > 1 ? L : -1.0; /* L > 1: g(L) = L e^{-L} > 0, right of the root */
  if (L < 1)
    while (x - L * (1 - exp(-x)) <= 0) x *= 2; /* step left until g > 0 */
  for (int it = 0; it < 200; it++) {
    double e = exp(-x);
    double g = x - L * (1 - e), dg = 1 - L * e;
    double dx = g / dg;
    x -= dx;
    if (fabs(dx) <= 1e-15 * fabs(x)) break;
  }
  return x;
}

/* The law's constants from the user's F and eps. With L = alpha delta = -ln eps and
 * x = alpha u: f'(u) = kn (1 - L e^{-x}) vanishes at x* = ln L, where the tension is
 *   -f(u*) = kn delta (L - 1 - ln L) / L.
 * Setting it to the user's F gives delta = F L / (kn (L - 1 - ln L)) (= 2.23; the seed
 * prints the opposite overall sign because its F is negative) and alpha = L / delta
 * (2.24). L = 1 (eps = 1/e) makes delta infinite: rejected.
 *   eps < 1/e (L > 1): the peak is in overlap (x* > 0); f is tensile on (0, u_eq) with
 *     u_eq the positive root of x = L (1 - e^{-x}) (u_eq -> delta for small eps), the
 *     stable rest state; the bond opens (ruptures) at u = 0, where f returns to zero.
 *   eps > 1/e (L < 1): the peak is in the gap (x* < 0); f is compressive for u > 0 and
 *     tensile on (u_r, 0), u_r the negative root (x_r = -L exactly for eps = 1/2);
 *     the rest state is u = 0; the bond opens at u_r.
 * Tangent stiffness: df/du = kn (1 - L e^{-x}) rises monotonically with u, so over the
 * bonded range u >= u_r its largest magnitude is k_max = kn max(1, |1 - L e^{-x_r}|):
 * kn (L - 1) for eps < 1/e when L > 2 (17.4 kn at eps = 1e-8), kn for eps = 1/2. */
int esf_adhesion_derive(double F, double eps, double kn, esf_adhesion *a,
                        esf_error *err) {
  *a = (esf_adhesion){0};
  a->F = F;
  a->eps = eps;
  a->k_max = kn;
  if (!(F >= 0) || !isfinite(F))
    return esf_fail(err, ESF_EINPUT,
                    "the adhesive force F must be a non-negative number of newtons, "
                    "got %g",
                    F);
  if (!(eps > 0 && eps < 1))
    return esf_fail(err, ESF_EINPUT,
                    "epsilon must lie in (0, 1) (004 2.23 takes ln(-ln epsilon)), got %g",
                    eps);
  double L = -log(eps);
  if (fabs(L - 1.0) < 1e-3)
    return esf_fail(err, ESF_EINPUT,
                    "epsilon = %.17g is 1/e or too close to it (|ln epsilon + 1| < "
                    "1e-3): delta = F ln eps / (kn (1 + ln eps + ln(-ln eps))) diverges "
                    "there; pick epsilon away from 0.3679",
                    eps);
  if (F == 0) return ESF_OK; /* delta = 0: the linear law */
  a->delta = F * L / (kn * (L - 1.0 - log(L)));
  a->alpha = L / a->delta;
  a->u_peak = log(L) / a->alpha;
  double xr = other_root(L);
  if (L > 1) {
    a->u_eq = xr / a->alpha;
    a->u_rupture = 0.0;
    xr = 0.0;
  } else {
    a->u_eq = 0.0;
    a->u_rupture = xr / a->alpha;
  }
  a->k_max = kn * fmax(1.0, fabs(1.0 - L * exp(-xr)));
  return ESF_OK;
}

/* Bond rule (2.25): a bonded contact carries force at any u >= u_rupture, gap or not
 * (touching stays 1), with the normal dashpot unclipped. When u < u_rupture the bond
 * breaks: Phi = 0 for good; the evaluation then follows the linear law (no tension,
 * u < 0 so no force, history reset), out->broke = 1 and out->e_break = W(u) + (1/2) kt
 * |xi|^2, the energy the bond held, which the caller books as dissipated, clearing the
 * bond state when it commits. A trial evaluation (hist_out NULL) that finds
 * u < u_rupture evaluates the broken law too, without committing. Without a bond:
 * the linear law. */
static void adhesive_eval(const esf_pair_params *pp, double beta, int tframe,
                          const esf_contact_in *in, const esf_contact_hist *hist,
                          const esf_contact_bond *bond, int first,
                          esf_contact_hist *hist_out, esf_contact_out *out) {
  if (first || !bond || !bond->on) { /* Phi = 0: compression and friction only */
    esf_contact_linear_eval(pp, beta, tframe, in, hist, first, hist_out, out);
    return;
  }
  const esf_adhesion *A = &pp->adh;
  double u = in->un + bond->s;
  if (u < A->u_rupture) { /* the bond opens past rupture: Phi = 0 for good */
    double e = esf_adhesion_energy(pp->kn, A, u) + 0.5 * pp->kt * v3_norm2(hist->xi);
    esf_contact_linear_eval(pp, beta, tframe, in, hist, 1, hist_out, out);
    out->broke = 1;
    out->e_break = e;
    return;
  }
  double sm = sqrt(in->mstar);
  double cn = beta > 0 ? beta * pp->kn : pp->cn_factor * sm;
  double ct = beta > 0 ? beta * pp->kt : pp->ct_factor * sm;
  double vn = v3_dot(in->vc, in->n);
  double fd = -cn * vn;
  const double fel = esf_adhesion_force(pp->kn, A, u);
  double fn = fel + fd; /* tension negative, unclipped */
  double xi[3];
  esf_contact_tangential(pp, ct, tframe, 1, in, hist, 0, vn, fn, 0.0, 0.0, xi, out);
  esf_contact_finish(in, fn, fd, xi, hist_out, out);
  out->fel = fel;
  out->e_el_n = esf_adhesion_energy(pp->kn, A, u);
}

static double adhesive_energy_n(const esf_pair_params *pp, const esf_contact_bond *bond,
                                double un, double rstar, double *fel) {
  (void)rstar;
  if (!bond || !bond->on) {
    *fel = pp->kn * un;
    return 0.5 * pp->kn * un * un;
  }
  double u = un + bond->s;
  *fel = esf_adhesion_force(pp->kn, &pp->adh, u);
  return esf_adhesion_energy(pp->kn, &pp->adh, u);
}

const esf_contact_law esf_contact_adhesive = {
    .name = "adhesive",
    .flags = ESF_LAW_HISTORY | ESF_LAW_TENSION | ESF_LAW_FUSED,
    .eval = adhesive_eval,
    .energy_n = adhesive_energy_n,
};
