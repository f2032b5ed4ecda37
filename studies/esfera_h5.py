#!/usr/bin/python3
"""esfera_h5 — read esfera's results (frames.h5, energy.csv) with h5py and numpy.

    import esfera_h5 as e
    frames = e.load_frames("out/settle")          # or ".../frames.h5"
    t, d = frames[-1]                              # time (s), dict of arrays
    d["position"], d["velocity"], d["walls/points"], d.get("contacts/pairs")
    energy = e.load_energy("out/settle")           # dict column -> 1-D array
    energy = e.load_energy("out/settle/energy.csv")

    /usr/bin/python3 studies/esfera_h5.py FILE.h5  # a summary, like `esfera info`

Layout (docs/output.md, src/output/frames.h): /frames/NNNNNN groups with attribute `time`
and datasets id, position, velocity, angular_velocity, force, radius, material, and
the groups walls/ (points, triangles, group, material) and contacts/ (pairs,
normal_force) when present; /energy holds one 1-D dataset per energy.csv column, in
the order of its attribute `columns`. Needs only h5py and numpy (Debian's
/usr/bin/python3 with python3-h5py and python3-numpy, as scripts/setup installs).
"""
import collections
import os
import sys

import h5py
import numpy as np

Frame = collections.namedtuple("Frame", "time data")


def frames_path(path):
    """frames.h5 of a result directory, or path itself."""
    return os.path.join(path, "frames.h5") if os.path.isdir(path) else path


def _read_group(g, prefix=""):
    out = {}
    for name, obj in g.items():
        if isinstance(obj, h5py.Dataset):
            out[prefix + name] = obj[()]
        else:
            out.update(_read_group(obj, prefix + name + "/"))
    return out


def iter_frames(path, select=None):
    """Yields Frame(time, data) in order; data maps dataset names ("position",
    "walls/points", ...) to numpy arrays. select: frame numbers to read (negative
    from the end), default all."""
    with h5py.File(frames_path(path), "r") as f:
        names = sorted(f["frames"].keys())
        picks = range(len(names)) if select is None else [range(len(names))[k] for k in select]
        for k in picks:
            g = f["frames"][names[k]]
            yield Frame(float(g.attrs["time"]), _read_group(g))


def load_frames(path, select=None):
    """All frames (or those in select) as a list of Frame(time, data)."""
    return list(iter_frames(path, select))


def frame_count(path):
    with h5py.File(frames_path(path), "r") as f:
        return len(f["frames"])


def _energy_h5(path):
    with h5py.File(path, "r") as f:
        if "energy" not in f:
            raise KeyError(f"{path}: no /energy table (the run had the ledger off)")
        g = f["energy"]
        cols = [c.decode() if isinstance(c, bytes) else str(c) for c in g.attrs["columns"]]
        return {c: g[c][()] for c in cols}


def _energy_csv(path):
    with open(path) as fh:
        cols = fh.readline().strip().split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    return {c: data[:, k].copy() for k, c in enumerate(cols)}


def load_energy(path):
    """The energy rows as a dict column -> array, from frames.h5's /energy, from
    energy.csv, or from a result directory (frames.h5 when it has the table, else
    energy.csv)."""
    if os.path.isdir(path):
        h5 = os.path.join(path, "frames.h5")
        if os.path.exists(h5):
            with h5py.File(h5, "r") as f:
                has = "energy" in f
            if has:
                return _energy_h5(h5)
        return _energy_csv(os.path.join(path, "energy.csv"))
    if path.endswith(".csv"):
        return _energy_csv(path)
    return _energy_h5(path)


def summary(path):
    """A dict describing the file (what `esfera info` prints)."""
    path = frames_path(path)
    with h5py.File(path, "r") as f:
        attrs = {k: (v.decode() if isinstance(v, bytes) else v) for k, v in f.attrs.items()}
        names = sorted(f["frames"].keys())
        s = {
            "file": path,
            "kind": attrs.get("kind", "frames"),
            "scene": attrs.get("scene"),
            "esfera_version": attrs.get("esfera_version"),
            "frames": len(names),
            "energy_rows": len(f["energy"]["time"]) if "energy" in f else 0,
        }
        if names:
            first, last = f["frames"][names[0]], f["frames"][names[-1]]
            s["time"] = (float(first.attrs["time"]), float(last.attrs["time"]))
            s["particles"] = (len(first["id"]), len(last["id"]))
            s["datasets"] = sorted(_read_group(first).keys())
            s["walls"] = "walls" in first
            s["contacts"] = "contacts" in first
    return s


def main(argv):
    if len(argv) != 2:
        print("usage: esfera_h5.py FILE.h5 | RESULT_DIR", file=sys.stderr)
        return 2
    try:
        s = summary(argv[1])
    except (OSError, KeyError) as e:
        print(f"esfera_h5: {argv[1]}: {e}", file=sys.stderr)
        return 2
    for k, v in s.items():
        print(f"{k}: {v}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
