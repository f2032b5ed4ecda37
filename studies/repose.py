#!/usr/bin/python3
"""repose.py — the angle of repose of a heap of spheres on a horizontal plate, from a
frame.

    /usr/bin/python3 studies/repose.py RESULT [--frame K] [--axis x,y] [--plate Z]

The heap's free surface is read the way one reads a photograph's profile, all around
the heap: about the axis (default the particles' centroid in x, y), the plane is cut
into 16 sectors and radial rings one mean diameter wide; in each ring and sector the
surface height is the highest sphere top, z + r, above the plate (height --plate, default
z = 0); the ring's height h(rho) is the median over the sectors that hold
particles (a lone sphere perched on the surface moves one sector's value, not the
median). The flank is the part of the profile between 20% and 80% of the heap's height
H = h at the innermost ring (a profile lower than two mean diameters, or with fewer
than three rings in the flank, is a layer, not a heap: angle nan, flat 1); the angle is the arctangent of minus the least-squares
slope of h against rho there, with the standard error of the slope turned into degrees.
Spheres whose bottom is below the plate (fallen off) are ignored. Prints one line
`repose: angle=... err=... height=... radius=... flank_rings=... particles=...`.

As a module: repose_angle(x, radius, axis=None, plate=None) -> dict with angle (deg),
err (deg), height (m), radius (m, where h falls below 20% of H), rings (used), profile
(rho, h arrays)."""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from esfera_h5 import load_frames  # noqa: E402

SECTORS = 16


def profile(x, radius, axis=None, plate=None):
    """Radial surface profile (rho, h) of a heap: ring centres and median heights."""
    if plate is None:
        plate = 0.0
    keep = x[:, 2] - radius >= plate - 0.5 * radius.mean()
    x, radius = x[keep], radius[keep]
    if axis is None:
        axis = x[:, :2].mean(axis=0)
    d = 2 * radius.mean()
    rel = x[:, :2] - np.asarray(axis, float)
    rho = np.hypot(rel[:, 0], rel[:, 1])
    sector = ((np.arctan2(rel[:, 1], rel[:, 0]) + np.pi) / (2 * np.pi) * SECTORS).astype(int)
    sector = np.minimum(sector, SECTORS - 1)
    ring = (rho / d).astype(int)
    top = x[:, 2] + radius - plate
    nring = int(ring.max()) + 1 if len(ring) else 0
    tops = np.full((nring, SECTORS), np.nan)
    for r, s, t in zip(ring, sector, top):
        if not (t <= tops[r, s]):  # nan or lower
            tops[r, s] = t
    rings, heights = [], []
    for r in range(nring):
        v = tops[r][np.isfinite(tops[r])]
        if len(v) * 2 >= SECTORS:  # at least half the sectors hold particles
            rings.append((r + 0.5) * d)
            heights.append(float(np.median(v)))
    return np.array(rings), np.array(heights), len(x)


def repose_angle(x, radius, axis=None, plate=None):
    rho, h, n = profile(x, radius, axis, plate)
    out = {"angle": np.nan, "err": np.nan, "height": np.nan, "radius": np.nan,
           "rings": 0, "particles": n, "profile": (rho, h), "flat": 1}
    if len(h) == 0:
        return out
    H = h[0]
    out["height"] = H
    if len(h) < 3 or H < 4 * radius.mean():
        return out
    below = np.flatnonzero(h < 0.2 * H)
    out["radius"] = rho[below[0]] if len(below) else rho[-1]
    flank = (h >= 0.2 * H) & (h <= 0.8 * H)
    out["rings"] = int(flank.sum())
    if flank.sum() < 3:
        return out
    A = np.vstack([rho[flank], np.ones(flank.sum())]).T
    coef, res, _, _ = np.linalg.lstsq(A, h[flank], rcond=None)
    slope = coef[0]
    m = flank.sum()
    resid = h[flank] - A @ coef
    sxx = np.sum((rho[flank] - rho[flank].mean()) ** 2)
    se = np.sqrt(np.sum(resid ** 2) / max(m - 2, 1) / sxx) if sxx > 0 else np.nan
    out["flat"] = 0
    out["angle"] = float(np.degrees(np.arctan(-slope)))
    out["err"] = float(np.degrees(se / (1 + slope * slope)))
    return out


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("result")
    ap.add_argument("--frame", type=int, default=-1)
    ap.add_argument("--axis", default=None)
    ap.add_argument("--plate", type=float, default=None)
    a = ap.parse_args(argv)
    f = load_frames(a.result, select=[a.frame])[0]
    axis = [float(v) for v in a.axis.split(",")] if a.axis else None
    r = repose_angle(np.asarray(f.data["position"]), np.asarray(f.data["radius"]), axis,
                     a.plate)
    print(f"repose: angle={r['angle']:.2f} err={r['err']:.2f} height={r['height']:.5g} "
          f"radius={r['radius']:.5g} flank_rings={r['rings']} particles={r['particles']} flat={r['flat']}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
