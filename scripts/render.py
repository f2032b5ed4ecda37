#!/usr/bin/python3
"""render.py — a picture of one frame of an esfera result (matplotlib, Agg backend).

    /usr/bin/python3 scripts/render.py RESULT [--frame K] [--out PNG] [--elev DEG]
                                       [--azim DEG] [--size INCHES] [--dpi DPI]

RESULT is a result directory or its frames.h5. K is the frame number (negative counts
from the end; default -1, the last frame). The spheres are drawn as a 3D scatter
coloured by speed |v| (m/s) and sized by radius (marker diameter = the sphere's
diameter at the axes' scale), the walls of the frame (frames.h5 walls/points,
walls/triangles) as translucent polygons. Default output: RESULT/frame_K.png.
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "studies"))
import esfera_h5  # noqa: E402


def render(path, frame=-1, out=None, elev=22.0, azim=-60.0, size=7.0, dpi=110):
    nframes = esfera_h5.frame_count(path)
    if nframes == 0:
        raise ValueError(f"{path}: no frames")
    k = range(nframes)[frame]
    fr = esfera_h5.load_frames(path, select=[k])[0]
    d = fr.data
    x, r = d["position"], d["radius"]
    speed = np.linalg.norm(d["velocity"], axis=1) if len(x) else np.zeros(0)

    fig = plt.figure(figsize=(size, size), dpi=dpi)
    ax = fig.add_subplot(projection="3d")
    ax.view_init(elev=elev, azim=azim)
    pts = [x] if len(x) else []
    if "walls/points" in d and len(d["walls/triangles"]):
        wp, tri = d["walls/points"], d["walls/triangles"]
        polys = Poly3DCollection(wp[tri], facecolor=(0.55, 0.6, 0.7, 0.12),
                                 edgecolor=(0.3, 0.3, 0.4, 0.5), linewidth=0.6)
        ax.add_collection3d(polys)
        pts.append(wp)
    allp = np.vstack(pts) if pts else np.zeros((1, 3))
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    mid, half = 0.5 * (lo + hi), 0.5 * max(float(np.max(hi - lo)), 1e-12)
    ax.set_xlim(mid[0] - half, mid[0] + half)
    ax.set_ylim(mid[1] - half, mid[1] + half)
    ax.set_zlim(mid[2] - half, mid[2] + half)
    ax.set_box_aspect((1, 1, 1))
    if len(x):
        # marker diameter in points: the axes span 2*half metres over ~0.55 of the
        # figure width once projected
        pts_per_m = 0.55 * size * 72.0 / (2 * half)
        sc = ax.scatter(x[:, 0], x[:, 1], x[:, 2], c=speed, cmap="viridis",
                        s=(2 * r * pts_per_m) ** 2, edgecolors="none", depthshade=True)
        cb = fig.colorbar(sc, ax=ax, shrink=0.6, pad=0.08)
        cb.set_label("speed |v| (m/s)")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    scene = esfera_h5.summary(path).get("scene") or ""
    ax.set_title(f"{scene}: frame {k}, t = {fr.time:.4g} s, {len(x)} particles")
    if out is None:
        base = path if os.path.isdir(path) else os.path.dirname(path) or "."
        out = os.path.join(base, f"frame_{k:06d}.png")
    fig.savefig(out, dpi=dpi, bbox_inches="tight")
    plt.close(fig)
    return out


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("result", help="result directory or frames.h5")
    ap.add_argument("--frame", type=int, default=-1, help="frame number (default -1: last)")
    ap.add_argument("--out", help="PNG to write (default RESULT/frame_K.png)")
    ap.add_argument("--elev", type=float, default=22.0)
    ap.add_argument("--azim", type=float, default=-60.0)
    ap.add_argument("--size", type=float, default=7.0, help="figure size, inches")
    ap.add_argument("--dpi", type=int, default=110)
    a = ap.parse_args(argv[1:])
    try:
        out = render(a.result, a.frame, a.out, a.elev, a.azim, a.size, a.dpi)
    except (OSError, KeyError, ValueError, IndexError) as e:
        print(f"render.py: {e}", file=sys.stderr)
        return 2
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
