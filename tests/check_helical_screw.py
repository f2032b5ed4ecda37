#!/usr/bin/python3
"""check_helical_screw.py ESFERA SOURCE_ROOT — what scenes/helical_screw-quick.yaml is
about: the turning screw lifts the grains inside its radius, and lifts them faster when
it turns faster. The quick scene runs at 95 and 190 rpm (--set); after the fill has
fallen in (t >= T0), every frame gives the axial mass flux through the screw's cross-
section averaged over the slab Z0 < z < Z1 of the bed, Q = sum(m v_z) / (Z1 - Z0) over
the grains with centres inside the flight radius (the slab integral of the flux through
horizontal planes), and the grains' mass-weighted mean axial velocity u.
Checks, with the standard error of the time means from block averages (blocks of
BLOCK s, longer than a grain's passage over one flight segment):
  * Q > 0 at both speeds, by more than 3 standard errors;
  * Q(190 rpm) - Q(95 rpm) > 3 standard errors of the difference;
  * 0 < u <= pitch rpm / 60 at both speeds: a grain resting on the flight cannot rise
    faster than the flight under a grain that does not turn (the lifting efficiency
    u / (pitch rpm / 60) lies in (0, 1]).
The frames' wall mesh holds the screw's triangles (shaft quads as two, the caps' fans,
the flight's) and at each frame's time it is frame 0's turned by -omega t about the
axis (1e-9 m)."""
import math
import os
import sys
import tempfile

import numpy as np

from pycheck import check, finish, run_sets

AXIS_XY = (0.15, 0.15)
RADIUS, PITCH, SEGMENTS, TURNS = 0.1, 0.1, 36, 4
RHO = 3500.0
T0, Z0, Z1, BLOCK = 0.4, 0.03, 0.15, 0.1


def measure(esfera_h5, out):
    frames = esfera_h5.load_frames(out)
    ts, qs, us = [], [], []
    for t, d in frames:
        if t < T0 - 1e-9:
            continue
        x, v, r = d["position"], d["velocity"], d["radius"]
        m = RHO * 4.0 / 3.0 * math.pi * r ** 3
        inside = (np.hypot(x[:, 0] - AXIS_XY[0], x[:, 1] - AXIS_XY[1]) < RADIUS) & \
                 (x[:, 2] > Z0) & (x[:, 2] < Z1)
        ts.append(t)
        qs.append(float((m[inside] * v[inside, 2]).sum()) / (Z1 - Z0))
        us.append(float((m[inside] * v[inside, 2]).sum() / max(m[inside].sum(), 1e-300)))
    ts, qs, us = np.array(ts), np.array(qs), np.array(us)
    blocks = np.floor((ts - T0) / BLOCK + 1e-9)
    full = max((blocks == b).sum() for b in np.unique(blocks))  # drop a partial block
    means = [qs[blocks == b].mean() for b in np.unique(blocks) if (blocks == b).sum() == full]
    se = float(np.std(means, ddof=1) / math.sqrt(len(means)))
    return float(qs.mean()), se, float(us.mean()), len(means), frames


def check_walls(frames, rpm):
    t0, d0 = frames[0]
    g = d0["walls/group"]
    nt = int((g == 1).sum())
    want = 2 * SEGMENTS + 2 * SEGMENTS + 2 * SEGMENTS * TURNS
    check(nt == want, f"{rpm} rpm: the frames hold {nt} screw triangles, want {want}")
    tri0 = d0["walls/triangles"][g == 1]
    worst = 0.0
    for t, d in frames[:: max(1, len(frames) // 7)]:
        w = -rpm * 2 * math.pi / 60.0 * (t - t0)  # about +z (the scene turns about -z)
        p0 = d0["walls/points"][tri0.ravel()]
        p = d["walls/points"][d["walls/triangles"][d["walls/group"] == 1].ravel()]
        dx, dy = p0[:, 0] - AXIS_XY[0], p0[:, 1] - AXIS_XY[1]
        want_p = np.stack([AXIS_XY[0] + math.cos(w) * dx - math.sin(w) * dy,
                           AXIS_XY[1] + math.sin(w) * dx + math.cos(w) * dy, p0[:, 2]], 1)
        worst = max(worst, float(np.abs(p - want_p).max()))
    check(worst < 1e-9, f"{rpm} rpm: the screw in the frames is off its rotation by {worst:.3g} m")


def main():
    esfera, root = sys.argv[1], sys.argv[2]
    sys.path.insert(0, os.path.join(root, "studies"))
    import esfera_h5
    scene = os.path.join(root, "scenes", "helical_screw-quick.yaml")
    res = {}
    with tempfile.TemporaryDirectory() as tmp:
        for rpm in (95, 190):
            out = os.path.join(tmp, f"rpm{rpm}")
            r = run_sets(esfera, scene, out, f"walls.1.motion.rotate.rpm={rpm}")
            if r.returncode:
                return finish("helical_screw")
            q, se, u, nb, frames = measure(esfera_h5, out)
            res[rpm] = (q, se, u)
            lift = PITCH * rpm / 60.0
            print(f"{rpm} rpm: Q = {q:.3f} +- {se:.3f} kg/s ({nb} blocks), mean axial "
                  f"velocity {u:.4f} m/s = {u / lift:.2f} x pitch rpm/60 ({lift:.4f} m/s)")
            check(q - 3 * se > 0, f"{rpm} rpm: flux {q:.3g} +- {se:.2g} kg/s is not > 0")
            check(0 < u <= lift, f"{rpm} rpm: mean axial velocity {u:.4g} m/s outside "
                                 f"(0, pitch rpm/60 = {lift:.4g}]")
            check_walls(frames, rpm)
    (q1, s1, _), (q2, s2, _) = res[95], res[190]
    diff, sd = q2 - q1, math.sqrt(s1 * s1 + s2 * s2)
    print(f"Q(190) - Q(95) = {diff:.3f} +- {sd:.3f} kg/s; ratio {q2 / q1:.2f}")
    check(diff > 3 * sd, f"flux does not grow with rpm: {q1:.3g} -> {q2:.3g} (+- {sd:.2g})")
    return finish("helical_screw")


if __name__ == "__main__":
    sys.exit(main())
