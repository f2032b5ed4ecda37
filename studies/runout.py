#!/usr/bin/python3
"""runout.py — the front of a granular mass along a direction, frame by frame: the
runout distance and front speed of a debris flow, an avalanche or a dam break.

    /usr/bin/python3 studies/runout.py RESULT [--direction 1,0,0] [--origin 0,0,0]
                                       [--percentiles 50,95,99] [--width W | --2d]
                                       [--min-layers F] [--out CSV]

For every frame of RESULT (a result directory or frames.h5) each particle's distance
s = (x - origin) . n along the unit direction n is taken, and the front is given as
percentiles of s (the 95th and 99th are robust to a few runaway spheres, the maximum is
not) and the maximum. Percentiles are fractions of the particles, so they do not
compare masses of different sizes: a small mass's few strays are a larger fraction of
it. With --width W (the channel's width, m; 3D) or --2d (disks) the deposit front is
also given the way one measures a deposit with a ruler: the farthest s at which the
solid thickness (the particles' volume 4/3 pi r^3 in the window [s - 2 d, s] along n,
over W 2 d; in 2D their area pi r^2 over 2 d; d the mean diameter) is at least
--min-layers (default 0.6) of a monolayer's (square packing: pi d / 6 in 3D,
pi d / 4 in 2D, so that in 2D one stray disk, 0.5 of a monolayer in the window, does
not count), column front_deposit. Front speed: the central difference of the 95th percentile over
the frame times (one-sided at the ends), m/s. Kinetic energy (translational plus
rotational, J) comes from the run's energy table at the frame's time when the run kept
one. Particles that left the domain are no longer in the frames: the count column says
how many remain. Writes RESULT/runout.csv (or --out) with the columns
time, particles, front_pXX..., front_max, front_speed, kinetic and prints one summary
line: final front, its peak speed, the kinetic energy at the end against its peak.

As a module: front_table(frames, direction, origin, percentiles, width, disks) -> dict
of arrays; deposit_front(s, radius, width) for one frame (width None: disks)."""
import argparse
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from esfera_h5 import frames_path, load_energy, load_frames  # noqa: E402


def deposit_front(s, radius, width=None, min_layers=0.6):
    """The farthest s* where the solid thickness in [s* - 2d, s*] is at least
    min_layers of a square monolayer's; width None means disks (2D)."""
    if len(s) == 0:
        return np.nan
    d = 2 * radius.mean()
    hmin = min_layers * np.pi * d / (4 if width is None else 6)
    step = d / 8
    edges = np.arange(s.min() - step, s.max() + 2 * step, step)
    w = np.pi * radius ** 2 if width is None else 4 / 3 * np.pi * radius ** 3 / width
    vol, _ = np.histogram(s, bins=edges, weights=w)
    k = 16  # 2 d = 16 steps
    run = np.convolve(vol, np.ones(k))[: len(vol)] / (k * step)
    ok = np.flatnonzero(run >= hmin)
    return edges[ok[-1] + 1] if len(ok) else np.nan


def front_table(frames, direction=(1, 0, 0), origin=(0, 0, 0), percentiles=(50, 95, 99),
                width=None, disks=False, min_layers=0.6):
    n = np.asarray(direction, float)
    n /= np.linalg.norm(n)
    o = np.asarray(origin, float)
    t = np.array([f.time for f in frames])
    out = {"time": t, "particles": np.array([len(f.data["id"]) for f in frames])}
    s = [(f.data["position"] - o) @ n for f in frames]
    for p in percentiles:
        out[f"front_p{p:g}"] = np.array([np.percentile(x, p) if len(x) else np.nan
                                         for x in s])
    out["front_max"] = np.array([x.max() if len(x) else np.nan for x in s])
    if width or disks:
        out["front_deposit"] = np.array([deposit_front(x, f.data["radius"],
                                                       None if disks else width, min_layers)
                                         for x, f in zip(s, frames)])
    key = f"front_p{95 if 95 in percentiles else percentiles[-1]:g}"
    out["front_speed"] = np.gradient(out[key], t) if len(t) > 1 else np.zeros_like(t)
    return out


def add_kinetic(table, result):
    try:
        e = load_energy(result)
    except (OSError, KeyError):
        return
    ke = e["kinetic_translational"] + e["kinetic_rotational"]
    idx = np.clip(np.searchsorted(e["time"], table["time"] - 1e-12), 0, len(ke) - 1)
    table["kinetic"] = ke[idx]


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("result")
    ap.add_argument("--direction", default="1,0,0")
    ap.add_argument("--origin", default="0,0,0")
    ap.add_argument("--percentiles", default="50,95,99")
    ap.add_argument("--width", type=float, help="channel width, m (3D deposit front)")
    ap.add_argument("--2d", dest="disks", action="store_true", help="disks (2D scenes)")
    ap.add_argument("--min-layers", type=float, default=0.6,
                    help="deposit front threshold, fraction of a monolayer")
    ap.add_argument("--out")
    a = ap.parse_args(argv[1:])
    try:
        vec = lambda s: [float(v) for v in s.split(",")]  # noqa: E731
        d, o, ps = vec(a.direction), vec(a.origin), vec(a.percentiles)
        if len(d) != 3 or len(o) != 3 or not np.linalg.norm(d) > 0:
            raise ValueError("--direction and --origin take three numbers, the direction "
                             "non-zero")
        frames = load_frames(a.result)
    except (OSError, KeyError, ValueError) as e:
        print(f"runout: {a.result}: {e}", file=sys.stderr)
        return 2
    table = front_table(frames, d, o, ps, a.width, a.disks, a.min_layers)
    add_kinetic(table, a.result)
    res = os.path.dirname(frames_path(a.result)) or "."
    out = a.out or os.path.join(res, "runout.csv")
    cols = list(table)
    np.savetxt(out, np.column_stack([table[c] for c in cols]), delimiter=",",
               header=",".join(cols), comments="", fmt="%.10g")
    key = f"front_p{95 if 95 in ps else ps[-1]:g}"
    k = int(np.argmax(table["front_speed"]))
    line = (f"runout: frames={len(frames)} {key}={table[key][-1]:.6g} "
            f"front_max={table['front_max'][-1]:.6g} "
            + (f"front_deposit={table['front_deposit'][-1]:.6g} "
               if "front_deposit" in table else "") +
            f"peak_front_speed={table['front_speed'][k]:.6g} at_t={table['time'][k]:.6g} "
            f"particles={table['particles'][0]}->{table['particles'][-1]}")
    if "kinetic" in table:
        ke = table["kinetic"]
        line += (f" kinetic_end={ke[-1]:.6g} kinetic_peak={ke.max():.6g} "
                 f"kinetic_ratio={ke[-1] / ke.max() if ke.max() > 0 else 0:.4g}")
    print(line + f" csv={out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
