/* hertz_map.c — the exact map from the restitution e to the Hertz-Mindlin law's damping
 * ratio gamma (docs/physics.md#hertz-mindlin-law, the restitution map).
 *
 * The normal impact m u'' = -k u^(3/2) - 2 gamma sqrt(m (3/2) k u^(1/2)) u' (k =
 * (4/3) E* sqrt(R*), no tension: the force is cut at zero) is, in u = L x, t = T s with
 * T^2 = m/(k L^(1/2)) and L chosen so that the impact speed is 1,
 *   x'' = -max(0, x^(3/2) + c x^(1/4) x'),  c = 2 sqrt(3/2) gamma,  x(0) = 0, x'(0) = 1,
 * free of m, k and the speed (Tsuji et al. 1992): e = -x' once x is back at 0 (after the
 * cut the force stays zero: x^(3/2) falls faster than x^(1/4)). The ODE is integrated
 * with Dormand-Prince 5(4) under a tight error control (its step shrinks where x^(1/4)
 * is not smooth: the first touch and the cut) and e(gamma), decreasing, is inverted by
 * the Illinois (regula falsi) method in a bracket doubled from [0, 1/2]. Costs about a
 * millisecond a pair of materials; runs at each mixing (esf_materials_mix). The same for
 * the constant dashpot (contact.hertz_damping: constant), c = 2 gamma sqrt(m* S_n(u_p)),
 * u_p the undamped peak overlap at the impact speed: x'' = -max(0, x^(3/2) + c' x'),
 * c' = 2 sqrt(3/2) gamma (5/4)^(1/10), exact at that speed only.
 * Units: none (gamma, e dimensionless). */
#include "contact/material.h"

#include <math.h>

/* x'' for the state (x, v); cst: the constant dashpot's c v instead of c x^(1/4) v. */
static double accel(double c, int cst, double x, double v) {
  if (!(x > 0)) return 0.0;
  const double f = x * sqrt(x) + c * (cst ? 1.0 : sqrt(sqrt(x))) * v;
  return f > 0 ? -f : 0.0;
}

/* e(gamma) of the tsuji dashpot (cst = 0) or of the constant one (cst = 1: c =
 * 2 gamma sqrt(m* S_n(u_p)), u_p the undamped peak overlap at the impact speed, which
 * is x_p = (5/4)^(2/5) here: c = 2 sqrt(3/2) gamma x_p^(1/4)). */
static double restitution(double gamma, int cst) {
  static const double a21 = 1.0 / 5, a31 = 3.0 / 40, a32 = 9.0 / 40, a41 = 44.0 / 45,
                      a42 = -56.0 / 15, a43 = 32.0 / 9, a51 = 19372.0 / 6561,
                      a52 = -25360.0 / 2187, a53 = 64448.0 / 6561, a54 = -212.0 / 729,
                      a61 = 9017.0 / 3168, a62 = -355.0 / 33, a63 = 46732.0 / 5247,
                      a64 = 49.0 / 176, a65 = -5103.0 / 18656, b1 = 35.0 / 384,
                      b3 = 500.0 / 1113, b4 = 125.0 / 192, b5 = -2187.0 / 6784,
                      b6 = 11.0 / 84, e1 = 71.0 / 57600, e3 = -71.0 / 16695,
                      e4 = 71.0 / 1920, e5 = -17253.0 / 339200, e6 = 22.0 / 525,
                      e7 = -1.0 / 40;
  const double c = 2.0 * sqrt(1.5) * gamma * (cst ? pow(1.25, 0.1) : 1.0), tol = 1e-12;
  double x = 0.0, v = 1.0, h = 1e-4;
  for (int it = 0; it < 1000000; it++) {
    /* stages: (x, v)' = (v, a(x, v)) */
    const double k1x = v, k1v = accel(c, cst, x, v);
    const double x2 = x + h * a21 * k1x, v2 = v + h * a21 * k1v;
    const double k2x = v2, k2v = accel(c, cst, x2, v2);
    const double x3 = x + h * (a31 * k1x + a32 * k2x),
                 v3 = v + h * (a31 * k1v + a32 * k2v);
    const double k3x = v3, k3v = accel(c, cst, x3, v3);
    const double x4 = x + h * (a41 * k1x + a42 * k2x + a43 * k3x),
                 v4 = v + h * (a41 * k1v + a42 * k2v + a43 * k3v);
    const double k4x = v4, k4v = accel(c, cst, x4, v4);
    const double x5 = x + h * (a51 * k1x + a52 * k2x + a53 * k3x + a54 * k4x),
                 v5 = v + h * (a51 * k1v + a52 * k2v + a53 * k3v + a54 * k4v);
    const double k5x = v5, k5v = accel(c, cst, x5, v5);
    const double x6 = x + h * (a61 * k1x + a62 * k2x + a63 * k3x + a64 * k4x + a65 * k5x),
                 v6 = v + h * (a61 * k1v + a62 * k2v + a63 * k3v + a64 * k4v + a65 * k5v);
    const double k6x = v6, k6v = accel(c, cst, x6, v6);
    const double xn = x + h * (b1 * k1x + b3 * k3x + b4 * k4x + b5 * k5x + b6 * k6x),
                 vn = v + h * (b1 * k1v + b3 * k3v + b4 * k4v + b5 * k5v + b6 * k6v);
    const double k7x = vn, k7v = accel(c, cst, xn, vn);
    const double ex = h *
                      (e1 * k1x + e3 * k3x + e4 * k4x + e5 * k5x + e6 * k6x + e7 * k7x),
                 ev = h *
                      (e1 * k1v + e3 * k3v + e4 * k4v + e5 * k5v + e6 * k6v + e7 * k7v);
    const double err = fmax(fabs(ex), fabs(ev)) / tol;
    if (err <= 1.0) {
      x = xn;
      v = vn;
      if (x < 0) return -v; /* back at the surface: no force since */
    }
    /* the usual step-size control, safety 0.9, growth within [0.2, 5] */
    double fac = err > 0 ? 0.9 * pow(err, -0.2) : 5.0;
    h *= fmin(5.0, fmax(0.2, fac));
  }
  return NAN; /* not reached for gamma >= 0 */
}

double esf_hertz_restitution(double gamma) { return restitution(gamma, 0); }

double esf_hertz_gamma_form(double eta, int cst) {
  if (eta >= 1.0) return 0.0;
  double lo = 0.0, hi = 0.5, flo = 1.0 - eta, fhi = restitution(hi, cst) - eta;
  while (fhi > 0 && hi < 1e3) { /* e falls with gamma: widen until it is below eta */
    lo = hi;
    flo = fhi;
    hi *= 2.0;
    fhi = restitution(hi, cst) - eta;
  }
  int side = 0;
  double g = hi;
  for (int it = 0; it < 200 && hi - lo > 1e-13 * hi; it++) {
    g = (lo * fhi - hi * flo) / (fhi - flo);
    const double fg = restitution(g, cst) - eta;
    if (fabs(fg) < 1e-12) break;
    if ((fg > 0) == (flo > 0)) {
      lo = g;
      flo = fg;
      if (side == -1) fhi *= 0.5; /* Illinois: halve the end that stays */
      side = -1;
    } else {
      hi = g;
      fhi = fg;
      if (side == 1) flo *= 0.5;
      side = 1;
    }
  }
  return g;
}

double esf_hertz_gamma(double eta) { return esf_hertz_gamma_form(eta, 0); }
