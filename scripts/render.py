#!/usr/bin/python3
"""render.py — a picture of one frame of an esfera result (matplotlib, Agg backend).

    /usr/bin/python3 scripts/render.py RESULT [--frame K] [--out PNG] [--elev DEG]
                     [--azim DEG] [--size INCHES] [--dpi DPI] [--full]

RESULT is a result directory or its frames.h5. K is the frame number (negative counts
from the end; default -1, the last frame). Default output: RESULT/frame_K.png.

The spheres are a 3D scatter coloured by speed |v| (m/s; logarithmic between the 1st
and 99.5th percentiles when those differ by more than a decade, as in a settled pack,
else linear from 0) and sized by radius: each marker's diameter is the sphere's
projected diameter in the picture, measured through the axes' own projection. The
walls of the frame (frames.h5 walls/points, walls/triangles) are translucent polygons
with their outlines (edges of one triangle only, so the diagonals splitting a polygon
are not drawn). The view box is the particles' bounding box (centres +- radii) grown
by 10% of its largest side on every side, in true proportions, with the walls clipped
to it; --full shows the walls whole instead.
"""
import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import LogNorm, Normalize  # noqa: E402
from mpl_toolkits.mplot3d import proj3d  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "studies"))
import esfera_h5  # noqa: E402


def outline(tri):
    """Edges used by one triangle only: index pairs into the points."""
    e = np.sort(np.concatenate([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
    uniq, count = np.unique(e, axis=0, return_counts=True)
    return uniq[count == 1]


def clip_polygon(poly, lo, hi):
    """Sutherland-Hodgman clipping of a planar polygon (k x 3) to the box lo..hi."""
    out = [np.asarray(p, float) for p in poly]
    for axis in range(3):
        for bound, sign in ((lo[axis], 1.0), (hi[axis], -1.0)):
            src, out = out, []
            for i, p in enumerate(src):
                q = src[i - 1]
                pin, qin = sign * (p[axis] - bound) >= 0, sign * (q[axis] - bound) >= 0
                if pin != qin:
                    s = (bound - q[axis]) / (p[axis] - q[axis])
                    out.append(q + s * (p - q))
                if pin:
                    out.append(p)
            if not out:
                return None
    return np.array(out) if len(out) >= 2 else None


def speed_norm(speed):
    pos = speed[speed > 0]
    if len(pos) > 1:
        lo, hi = np.percentile(pos, [1, 99.5])
        if hi > 10 * lo > 0:
            return LogNorm(vmin=lo, vmax=hi, clip=True)
    top = float(speed.max()) if len(speed) else 0.0
    return Normalize(vmin=0, vmax=top if top > 0 else 1.0)


def view_box(x, r, walls, full):
    if len(x) and not full:
        lo, hi = (x - r[:, None]).min(axis=0), (x + r[:, None]).max(axis=0)
        pad = 0.1 * float(np.max(hi - lo))
        return lo - pad, hi + pad
    pts = [walls] if walls is not None and len(walls) else []
    if len(x):
        pts += [x - r[:, None], x + r[:, None]]
    allp = np.vstack(pts) if pts else np.zeros((1, 3))
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    pad = 1e-3 * max(float(np.max(hi - lo)), 1e-9)
    return lo - pad, hi + pad


def marker_sizes(ax, fig, x, r):
    """Marker areas (points^2) with the spheres' projected diameters."""
    fig.canvas.draw()
    M = ax.get_proj()
    px = lambda p: ax.transData.transform(  # noqa: E731
        np.column_stack(proj3d.proj_transform(p[:, 0], p[:, 1], p[:, 2], M)[:2]))
    c = px(x)
    rad = np.zeros(len(x))
    for k in range(3):
        off = x.copy()
        off[:, k] += r
        rad = np.maximum(rad, np.linalg.norm(px(off) - c, axis=1))
    return (2 * rad * 72.0 / fig.dpi) ** 2


def render(path, frame=-1, out=None, elev=22.0, azim=-60.0, size=7.0, dpi=110,
           full=False):
    nframes = esfera_h5.frame_count(path)
    if nframes == 0:
        raise ValueError(f"{path}: no frames")
    k = range(nframes)[frame]
    fr = esfera_h5.load_frames(path, select=[k])[0]
    d = fr.data
    x, r = d["position"], d["radius"]
    speed = np.linalg.norm(d["velocity"], axis=1) if len(x) else np.zeros(0)
    wp, tri = d.get("walls/points"), d.get("walls/triangles")
    lo, hi = view_box(x, r, wp, full)

    fig = plt.figure(figsize=(size, size), dpi=dpi)
    ax = fig.add_subplot(projection="3d")
    ax.view_init(elev=elev, azim=azim)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(hi - lo)  # true proportions
    if tri is not None and len(tri):
        faces = [c for c in (clip_polygon(wp[t], lo, hi) for t in tri)
                 if c is not None and len(c) >= 3]
        edges = [c for c in (clip_polygon(wp[e], lo, hi) for e in outline(tri))
                 if c is not None]
        ax.add_collection3d(Poly3DCollection(faces, facecolor=(0.55, 0.6, 0.7, 0.15),
                                             edgecolor="none"))
        ax.add_collection3d(Line3DCollection([e[[0, -1]] for e in edges],
                                             colors=[(0.25, 0.25, 0.35, 0.7)],
                                             linewidths=0.8))
    if len(x):
        sc = ax.scatter(x[:, 0], x[:, 1], x[:, 2], c=speed, cmap="viridis",
                        norm=speed_norm(speed), s=1.0, edgecolors="none",
                        depthshade=True)
        cb = fig.colorbar(sc, ax=ax, shrink=0.55, pad=0.12)
        cb.set_label("speed |v| (m/s)")
        sc.set_sizes(marker_sizes(ax, fig, x, r))
    ax.set_xlabel("x (m)", labelpad=8)
    ax.set_ylabel("y (m)", labelpad=8)
    ax.set_zlabel("z (m)", labelpad=8)
    ax.tick_params(labelsize=7)
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
    ap.add_argument("--elev", type=float, default=22.0, help="view elevation, degrees")
    ap.add_argument("--azim", type=float, default=-60.0, help="view azimuth, degrees")
    ap.add_argument("--size", type=float, default=7.0, help="figure size, inches")
    ap.add_argument("--dpi", type=int, default=110)
    ap.add_argument("--full", action="store_true", help="show the walls whole")
    a = ap.parse_args(argv[1:])
    try:
        out = render(a.result, a.frame, a.out, a.elev, a.azim, a.size, a.dpi, a.full)
    except (OSError, KeyError, ValueError, IndexError) as e:
        print(f"render.py: {e}", file=sys.stderr)
        return 2
    print(out)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
