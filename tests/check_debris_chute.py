#!/usr/bin/python3
"""check_debris_chute.py ESFERA SOURCE_ROOT — scenes/debris_chute-quick.yaml (360
spheres, d 20 mm, released by a gate down a 35-degree chute onto a flat floor) and the
same with a third of the mass (debris_chute-quick-small.csv, 120 spheres), measured
with studies/runout.py along the floor from the toe.

- the mass runs out: the deposit front (farthest point where the deposit is at least
  d/4 of solid thick) lies on the runout floor, s > 0, in both runs;
- it comes to rest: kinetic energy at 2.5 s under 1% of its peak (measured 4e-4 and
  7e-4), and the 95th-percentile front moves at under a tenth of its peak speed
  (measured 5% in the small run: its last spheres still roll, slowing as
  exp(-1.43 t) under the rotational damping, so the fronts creep on by a few cm);
- no particle leaves the domain;
- the peak front speed is below the frictionless slide from the gate to the toe,
  sqrt(2 g sin 35 * 0.8 m) = 3.0 m/s, and the percentiles are ordered;
- runout grows with released volume: the deposit front of the full mass lies at least
  2 d beyond the small one's (measured +0.15 m = 7.5 d; two packings of each size
  generated with other seeds gave +0.19 m, and the spread of one size over seeds is
  about 0.1 m). Percentile fronts do not compare masses of different size (a small
  mass's strays are a larger fraction of it) and are not used for that.
runout.py must also write runout.csv with its summary line."""
import math
import os
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..",
                                "studies"))
from esfera_h5 import load_frames  # noqa: E402
from pycheck import check, finish  # noqa: E402
from runout import add_kinetic, front_table  # noqa: E402

D, W = 0.02, 0.088
DIR = (math.cos(math.radians(35)), 0, math.sin(math.radians(35)))


def run(esfera, scene, out, *sets):
    args = [esfera, "run", scene, "--out", out, "--quiet"]
    for s in sets:
        args += ["--set", s]
    r = subprocess.run(args, capture_output=True, text=True)
    check(r.returncode == 0, f"run {sets}: exit {r.returncode} {r.stderr}")
    check(" removed=0 " in r.stdout, f"no particle leaves the domain {sets}")
    tab = front_table(load_frames(out), DIR, (0, 0, 0), (50, 95, 99), W)
    add_kinetic(tab, out)
    return tab


def main():
    esfera, root = sys.argv[1], sys.argv[2]
    scene = os.path.join(root, "scenes", "debris_chute-quick.yaml")
    runout_py = os.path.join(root, "studies", "runout.py")
    vmax = math.sqrt(2 * 9.81 * math.sin(math.radians(35)) * 0.8)
    with tempfile.TemporaryDirectory() as tmp:
        fronts = {}
        for name, sets in (("full", ()),
                           ("small", ("particles.0.file=debris_chute-quick-small.csv",))):
            out = os.path.join(tmp, name)
            t = run(esfera, scene, out, *sets)
            ke = t["kinetic"]
            v_end = abs(t["front_speed"][-1])
            fronts[name] = t["front_deposit"][-1]
            print(f"{name}: {t['particles'][0]} particles; deposit front "
                  f"{t['front_deposit'][-1]:.4f} m, p95 {t['front_p95'][-1]:.4f} m, p99 "
                  f"{t['front_p99'][-1]:.4f} m, max {t['front_max'][-1]:.4f} m; peak front "
                  f"speed {t['front_speed'].max():.3f} m/s; kinetic end/peak "
                  f"{ke[-1] / ke.max():.3g}; final front speed {v_end:.4f} m/s")
            check(t["front_deposit"][-1] > 0, f"{name}: the deposit reaches the floor")
            check(ke[-1] < 0.01 * ke.max(), f"{name}: at rest, kinetic {ke[-1]} vs {ke.max()}")
            check(v_end < 0.1 * t["front_speed"].max(), f"{name}: front speed {v_end} m/s")
            check(0 < t["front_speed"].max() < vmax,
                  f"{name}: peak front speed {t['front_speed'].max()} vs {vmax}")
            check(np.all(t["front_p95"] <= t["front_p99"] + 1e-12)
                  and np.all(t["front_p99"] <= t["front_max"] + 1e-12), "percentiles ordered")
        gain = fronts["full"] - fronts["small"]
        print(f"runout gain with 3x the volume: {gain:.4f} m = {gain / D:.2f} d")
        check(gain >= 2 * D, f"runout grows with volume: {fronts}")
        r = subprocess.run(["/usr/bin/python3", runout_py, os.path.join(tmp, "full"),
                            "--direction", ",".join(map(str, DIR)), "--width", str(W)],
                           capture_output=True, text=True)
        check(r.returncode == 0 and r.stdout.startswith("runout:")
              and os.path.exists(os.path.join(tmp, "full", "runout.csv")),
              f"runout.py: {r.returncode} {r.stdout} {r.stderr}")
        r = subprocess.run(["/usr/bin/python3", runout_py, os.path.join(tmp, "full"),
                            "--direction", "0,0,0"], capture_output=True, text=True)
        check(r.returncode == 2 and "direction" in r.stderr, f"bad direction: {r.stderr}")
    return finish("debris_chute")


if __name__ == "__main__":
    sys.exit(main())
