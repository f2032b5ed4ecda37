/* test_damping_demo.c — scenes/damping_demo-quick.yaml (004 §2.4, Table 1): a sphere
 * released just touching a plane oscillates on its contact spring about the static
 * overlap m g / k_n.
 *
 * The seed's claim for restitution 0.5 is "the penetration rate halves every cycle".
 * With Tsuji's dashpot (004 2.27-2.28), zeta = -ln eta / sqrt(pi^2 + ln^2 eta), the
 * contact is a linear damped oscillator whose velocity extrema are half a damped
 * period apart and shrink by exp(-pi zeta / sqrt(1 - zeta^2)) = eta each: so the ratio
 * of successive (opposite-sign) velocity peaks must be 0.5. Measured on the leapfrog's
 * half-step velocities at every step, each peak refined by a parabola through its
 * three samples. Two checks on each ratio: (1) against the leapfrog's discrete closed
 * form (the decay of the recurrence's complex root over half a discrete period), within
 * 3e-5 (measured: at most 9.1e-6); (2) against the seed's 0.5 within 1% (0.005): at
 * omega dt = 0.0707 ((omega dt)^2 = 5e-3) the discrete ratio is 0.497268, 0.55% below
 * 0.5.
 *
 * Restitution 1e-7 gives zeta = 0.98: the closed form's first rebound is 1e-7 of the
 * approach peak. The check: after its downward peak the velocity of sphere B never
 * reverses by more than 1e-5 of that peak (no visible oscillation; the margin over 1e-7
 * covers the discrete scheme), and the overlap approaches m g / k_n from below, never
 * overshooting it by more than 1e-5 of itself. The scene path comes from argv[1]. */
#include <stdlib.h>

#include "simtest.h"

enum { NMAX = 4096 };

int main(int argc, char **argv) {
  const char *sets[] = {"output.energy_every=0"};
  simtest T;
  int rc =
      simtest_open_scene(&T, argc > 1 ? argv[1] : ".", "damping_demo-quick", sets, 1);
  CHECK(rc == 0, "damping demo opens");
  if (rc) return check_finish("test_damping_demo");
  static double va[NMAX], vb[NMAX], zb[NMAX];
  size_t ia = 0, ib = 0, n = 0;
  for (size_t i = 0; i < T.s.p.n; i++) {
    if (T.s.p.id[i] == 0)
      ia = i;
    else
      ib = i;
  }
  /* the contact stiffnesses of each sphere with the floor, as the scene mixes them */
  const esf_materials *M = &T.s.mats;
  int32_t fl = esf_materials_find(M, "floor");
  CHECK(fl >= 0, "the scene has a floor material");
  if (fl < 0) return check_finish("test_damping_demo");
  double ka = M->pair[T.s.p.material[ia] * M->n + fl].kn;
  double k = M->pair[T.s.p.material[ib] * M->n + fl].kn;
  double r = T.s.p.radius[ib], m = T.s.p.mass[ib];
  while (!rc && T.s.t < 0.006 && n < NMAX) {
    rc = simtest_step(&T);
    va[n] = T.s.p.v[3 * ia + 2];
    vb[n] = T.s.p.v[3 * ib + 2];
    zb[n++] = T.s.p.x[3 * ib + 2];
  }
  CHECK(rc == 0, "the run completes (%zu steps)", n);
  /* sphere A: extrema of v_z, refined by a parabola */
  double peak[64];
  int np = 0;
  for (size_t i = 1; i + 1 < n && np < 64; i++) {
    double a = va[i - 1], b = va[i], c = va[i + 1];
    if (!((b > a && b >= c) || (b < a && b <= c))) continue;
    double den = a - 2 * b + c;
    peak[np++] = den != 0 ? b - 0.125 * (c - a) * (c - a) / den : b;
  }
  double zeta = esf_restitution_gamma(0.5), h = sqrt(ka / T.s.p.mass[ia]) * T.s.dt;
  double zr = sqrt(1 - 2 * zeta * h), th = acos((2 - h * h - 2 * zeta * h) / (2 * zr));
  double want = pow(zr, ESF_PI / th);
  printf("damping demo, eta 0.5: zeta %.5f, omega dt %.5f, discrete closed form %.6f; "
         "%d velocity peaks; ratios:",
         zeta, h, want, np);
  int checked = 0;
  double dev = 0;
  for (int j = 1; j < np; j++) {
    double ratio = -peak[j] / peak[j - 1];
    printf(" %.5f", ratio);
    if (fabs(peak[j]) >= 1e-3 * fabs(peak[0])) dev = fmax(dev, fabs(ratio - want));
    if (fabs(peak[j]) < 1e-3 * fabs(peak[0])) continue; /* drowned in round-off */
    CHECK(fabs(ratio - want) < 3e-5,
          "peak %d / peak %d = %.6f (discrete closed form %.6f)", j, j - 1, ratio, want);
    CHECK(fabs(ratio - 0.5) < 0.005, "peak %d / peak %d = %.6f (seed: 0.5)", j, j - 1,
          ratio);
    checked++;
  }
  printf("; largest |ratio - closed form| %.2e\n", dev);
  CHECK(checked >= 6, "at least six peak ratios measured (%d)", checked);
  /* sphere B: no rebound */
  size_t imin = 0;
  for (size_t i = 0; i < n; i++)
    if (vb[i] < vb[imin]) imin = i;
  double vmax_after = 0, over = 0, ustat = m * 9.81 / k;
  for (size_t i = imin; i < n; i++) vmax_after = fmax(vmax_after, vb[i]);
  for (size_t i = 0; i < n; i++) over = fmax(over, (r - zb[i]) - ustat);
  printf("damping demo, eta 1e-7: approach peak %.6g m/s, largest reverse velocity "
         "%.3g m/s (%.3g of it), overlap overshoot %.3g of m g / k_n\n",
         vb[imin], vmax_after, vmax_after / -vb[imin], over / ustat);
  CHECK(vb[imin] < 0, "sphere B moves down (%g)", vb[imin]);
  CHECK(vmax_after <= 1e-5 * -vb[imin], "sphere B rebounds: %g m/s after %g m/s",
        vmax_after, vb[imin]);
  CHECK(over <= 1e-5 * ustat, "sphere B overshoots the static overlap by %g m", over);
  simtest_close(&T);
  return check_finish("test_damping_demo");
}
