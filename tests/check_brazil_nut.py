#!/usr/bin/python3
"""check_brazil_nut.py ESFERA SOURCE_ROOT — scenes/brazil_nut-quick.yaml: a 24 mm
sphere (id 0) under 500 spheres of 8 mm in a box shaken at 20 Hz, 3 g, against the
same scene unshaken (--set walls.0.motion.oscillate.acceleration=0); the shaken run
goes to 4 s (the scene's duration), the control to 2 s.

Measure: the intruder's height minus the mean height of the small spheres, in small
diameters d, from t = 0.5 s (the poured bed has settled) to the end (4 s, 70 cycles
later), with frames taken once per cycle at the same phase. The shaken bed convects
(walls drag the outer spheres down, the centre rises) and carries the intruder up,
while the shaking compacts the bed (its mean height drops ~0.4 d; the relative
measure is immune to that). Measured rises by 4 s for three random fills of the bed:
2.49 d (seed 2004, the scene's), 1.71 d (seed 7), 1.27 d (seed 11); the fraction of
small spheres above the intruder dropped by 0.25, 0.18, 0.12. Passing needs a rise of
at least 1 d and a drop of at least 0.05: below every fill's, and four times the
control's limit. Unshaken, nothing drives motion after settling: over 0.5-2 s the
control moves under 0.25 d (measured 0.05 d, creep) and its bed's mean height under
0.1 d, while the shaken intruder rises at least three times as much (0.88-1.27 d over
the three fills). The bed must stay in the box (no particle removed) in both runs."""
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..",
                                "studies"))
from esfera_h5 import load_frames  # noqa: E402
from pycheck import check, finish, run_sets  # noqa: E402

D = 0.008


def measure(esfera, scene, out, *sets):
    r = run_sets(esfera, scene, out, *sets)
    print(r.stdout.strip())
    check(" removed=0 " in r.stdout, f"no particle leaves the box {sets}")
    rows = []
    for f in load_frames(out):
        ids, z = f.data["id"], f.data["position"][:, 2]
        i = np.flatnonzero(ids == 0)[0]
        zs = z[ids != 0]
        rows.append((f.time, (z[i] - zs.mean()) / D, (zs > z[i]).mean(), zs.mean() / D))
    return np.array(rows)


def window(rows, t0):
    a = rows[np.argmin(abs(rows[:, 0] - t0))]
    return a, rows[-1]


def main():
    esfera, root = sys.argv[1], sys.argv[2]
    scene = os.path.join(root, "scenes", "brazil_nut-quick.yaml")
    with tempfile.TemporaryDirectory() as tmp:
        res = {}
        for name, sets in (("shaken", ()),
                           ("control", ("walls.0.motion.oscillate.acceleration=0",
                                        "run.duration=2.0"))):
            rows = measure(esfera, scene, os.path.join(tmp, name), *sets)
            for t1 in (2.0, 4.0):
                if rows[-1, 0] < t1 - 1e-6:
                    continue
                a, b = window(rows, 0.5)[0], window(rows, t1)[0]
                res[name, t1] = (b[1] - a[1], a[2] - b[2], b[3] - a[3])
                print(f"{name}: t {a[0]:.2f} -> {b[0]:.2f} s: intruder - bed mean "
                      f"{a[1]:+.2f} d -> {b[1]:+.2f} d (rise {b[1] - a[1]:+.2f} d); "
                      f"fraction of small spheres above it {a[2]:.3f} -> {b[2]:.3f}; "
                      f"bed mean {a[3]:.2f} d -> {b[3]:.2f} d")
        rise, drop, _ = res["shaken", 4.0]
        check(rise >= 1.0, f"shaken: the intruder rises {rise:.2f} d by 4 s (>= 1 d)")
        check(drop >= 0.05, f"shaken: the fraction above it drops by {drop:.3f} (>= 0.05)")
        rise2 = res["shaken", 2.0][0]
        rise, drop, bed = res["control", 2.0]
        check(abs(rise) < 0.25, f"control: the intruder moves {rise:.2f} d (< 0.25 d)")
        check(abs(drop) <= 0.02, f"control: the fraction above it changes by {drop:.3f}")
        check(abs(bed) < 0.1, f"control: the bed had settled by 0.5 s ({bed:+.3f} d)")
        check(rise2 >= 3 * max(abs(rise), 0.1),
              f"0.5-2 s: shaken rise {rise2:.2f} d vs control {rise:.2f} d")
    return finish("brazil_nut")


if __name__ == "__main__":
    sys.exit(main())
