#!/usr/bin/python3
"""check_silo.py ESFERA SOURCE_ROOT -- scenes/silo-quick.yaml (issue 29): 2445 glass
beads inserted at run time into a cylindrical silo whose round orifice (D = 5 d, an STL
annulus for a floor) a gate closes; an event removes the gate at t_open = 0.56 s and the
beads drain out of the domain. Checked, with studies/silo.py's measures:
  - the fill: every bead is in (the frame at t_open holds all 2445) and at rest
    (kinetic energy below KE_OPEN of m g d per bead) before the gate opens;
  - no bead passes the floor before the gate goes: every centre stays above the floor
    by at least 1 - FLOOR of its radius in every frame (the first beads hit the bare
    floor at up to 1.8 m/s: a wall contact's peak overlap v sqrt(m/kn) is then 0.21
    of a 2.7 mm radius), nobody removed before t_open (log.txt);
  - the discharge is steady: the discharged mass against time is a line over the
    window (R^2 above R2), its two halves' slopes agree within HALVES, and W lies
    within BEV of Beverloo's law with C 0.58, k 1.5 and the bulk density measured at
    the opening (the quick silo is only 2 D + 4 d wide and the bed one width tall,
    so the band is wide; studies/results/silo/report.md has the full-size study);
  - the particle count closes: inserted = in the run at the end + removed;
  - the energy ledger closes: |total_error| below LEDGER of the energy dissipated over
    the run (the fill's impacts at up to 1.8 m/s carry the leapfrog's O(dt) error of
    the dashpot), and below LEDGER_FLOW of the energy dissipated during the discharge.
Measured (2026-11-27): KE at opening 7e-5 of m g d summed; the lowest centre 0.86
radii above the floor; R^2 0.993; halves
0.138 / 0.164 kg/s; W 0.142 kg/s against Beverloo 0.177 (0.80); ledger 1.1 % of the
whole run's dissipation, 0.3 % of the discharge's."""
import math
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..",
                                "studies"))
import numpy as np  # noqa: E402

import silo  # noqa: E402
import silo_scene  # noqa: E402
from esfera_h5 import load_energy  # noqa: E402
from pycheck import check, finish  # noqa: E402

KE_OPEN = 1e-2
FLOOR = 0.25
R2 = 0.98
HALVES = 0.25
BEV = (0.70, 1.15)
LEDGER = 0.02
LEDGER_FLOW = 0.01


def dissipated(e, k):
    return sum(e[c][k] for c in ("dissipated_contact", "dissipated_friction",
                                 "dissipated_damping"))


def main():
    esfera, root = sys.argv[1], sys.argv[2]
    scene = os.path.join(root, "scenes", "silo-quick.yaml")
    s = silo_scene.scene(5.0, quick=True)
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "out")
        r = subprocess.run([esfera, "run", scene, "--out", out, "--quiet", "--overwrite"],
                           capture_output=True, text=True)
        check(r.returncode == 0, f"run: exit {r.returncode} {r.stderr[-500:]}")
        summ = dict(kv.split("=", 1) for kv in
                    [ln for ln in r.stdout.splitlines() if ln.startswith("summary:")][-1]
                    .split()[1:])
        fr, frames = silo.opening_frame(out, s["t_open"])
        d = fr.data
        m = silo.DENSITY * 4 / 3 * math.pi * d["radius"]**3
        ke = 0.5 * np.sum(m * np.sum(d["velocity"]**2, axis=1))
        ke_ref = np.sum(m) * 9.81 * s["d"]
        print(f"fill: {len(m)} beads at t = {fr.time:.3f} s (opening {s['t_open']} s), "
              f"KE / (sum m g d) = {ke / ke_ref:.2e}")
        check(len(m) == s["count"] == int(summ["inserted"]),
              f"all {s['count']} beads inserted before the gate opens ({len(m)}, "
              f"summary {summ['inserted']})")
        check(ke < KE_OPEN * ke_ref, f"the fill rests at the opening: {ke / ke_ref:.2e}")
        low = min((f.data["position"][:, 2] / f.data["radius"]).min() for f in frames
                  if f.time <= s["t_open"] + 1e-9 and len(f.data["radius"]))
        print(f"before the opening: the lowest centre lies {low:.3f} radii above the floor")
        check(low > 1 - FLOOR, f"no bead passes the closed floor: {low:.3f} radii")
        res = silo.discharge(out, s)
        check(res["early"] == 0, f"nobody leaves before the opening: {res['early']}")
        Wb = silo.beverloo(res["rho_b"], s["D_eff"], s["d"])
        print(f"discharge: {res['n_out']} beads out, rho_b {res['rho_b']:.0f} kg/m^3, "
              f"W {res['W']:.4f} kg/s (R^2 {res['r2']:.4f}; halves {res['W1']:.4f} / "
              f"{res['W2']:.4f}), Beverloo {Wb:.4f} kg/s, ratio {res['W'] / Wb:.3f}")
        check(res["r2"] > R2, f"the discharged mass grows linearly: R^2 {res['r2']:.4f}")
        check(abs(res["W2"] - res["W1"]) < HALVES * res["W"],
              f"steady: halves {res['W1']:.4f}, {res['W2']:.4f}")
        check(BEV[0] < res["W"] / Wb < BEV[1], f"W / Beverloo {res['W'] / Wb:.3f} in {BEV}")
        check(int(summ["inserted"]) == int(summ["n_end"]) + int(summ["removed"])
              and int(summ["removed"]) == res["n_out"],
              f"count: inserted {summ['inserted']} = {summ['n_end']} + {summ['removed']}"
              f" (log {res['n_out']})")
        e = load_energy(out)
        t = e["time"]
        k0 = int(np.searchsorted(t, s["t_open"]))
        err, diss = e["total_error"][-1], dissipated(e, -1)
        derr, ddiss = err - e["total_error"][k0], diss - dissipated(e, k0)
        print(f"ledger: total_error {err:.3e} J of {diss:.3e} J dissipated; during the "
              f"discharge {derr:.3e} J of {ddiss:.3e} J")
        check(abs(err) < LEDGER * diss, f"the ledger closes: {err:.3e} of {diss:.3e} J")
        check(abs(derr) < LEDGER_FLOW * ddiss,
              f"the ledger closes in the discharge: {derr:.3e} of {ddiss:.3e} J")
    return finish("check_silo")


if __name__ == "__main__":
    sys.exit(main())
