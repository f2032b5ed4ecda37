#!/usr/bin/python3
"""check_info.py ESFERA — `esfera info FILE.h5` against the file as h5py reads it: on
a run where one particle leaves the domain, the scene, version (= esfera --version),
frame count, time span, particle counts of the first and last frames (41 and 40),
energy rows and the datasets of the first frame with their types and shapes; exit 0.
Bad files exit 2 with a message naming the file and the cause: missing, not HDF5
(energy.csv), truncated frames.h5, a foreign HDF5 file, an esfera file of an unknown
kind; no argument gives the usage (exit 2). A result written before the `kind`
attribute existed is still recognised."""
import os
import re
import subprocess
import sys
import tempfile

import h5py

from pycheck import check, finish, run_scene

SCENE = """name: info-check
domain: {min: [-0.01, -0.01, -0.01], max: [0.04, 0.04, 0.1]}
materials:
  g: {density: 2500, kn: 1.0e4, restitution: 0.5, friction: 0.4}
particles:
  - {generate: lattice, region: {min: [0.003, 0.003, 0.003], max: [0.027, 0.027, 0.03]},
     count: 40, radius: 0.0015, material: g, seed: 1}
  - {material: g, radius: 0.001, position: [0.035, 0.02, 0.05], velocity: [3, 0, 0]}
walls:
  - {box: {min: [0, 0, 0], max: [0.03, 0.03, 0.06]}, open: [top], material: g}
integrator: {method: leapfrog, dt: auto, frac: 0.2}
run: {duration: 0.02}
output: {every: 0.005, energy_every: 5.0e-4}
"""



def info(esfera, *args):
    r = subprocess.run([esfera, "info", *args], capture_output=True, text=True)
    return r.returncode, r.stdout, r.stderr


def expect_error(esfera, path, pattern, what):
    rc, out, err = info(esfera, path)
    check(rc == 2, f"{what}: exit {rc}, expected 2")
    check(re.search(pattern, err) is not None, f"{what}: message {err!r} !~ /{pattern}/")
    check(out == "", f"{what}: nothing on stdout ({out!r})")


def main():
    esfera = sys.argv[1]
    with tempfile.TemporaryDirectory() as tmp:
        out = run_scene(esfera, tmp, SCENE)
        h5 = os.path.join(out, "frames.h5")
        rc, text, err = info(esfera, h5)
        check(rc == 0 and err == "", f"info on a result: exit {rc}, stderr {err!r}")
        print(text, end="")
        kv = dict(re.findall(r"^([a-z ]+): (.*)$", text, re.M))
        version = subprocess.run([esfera, "--version"], capture_output=True,
                                 text=True).stdout.split()[-1]
        with h5py.File(h5, "r") as f:
            names = sorted(f["frames"])
            t0, t1 = (float(f["frames"][n].attrs["time"]) for n in (names[0], names[-1]))
            n0, n1 = (len(f["frames"][n]["id"]) for n in (names[0], names[-1]))
            rows = len(f["energy/time"])
            datasets = {}
            f["frames"][names[0]].visititems(
                lambda k, o: datasets.__setitem__(k, o) if isinstance(o, h5py.Dataset)
                else None)
            listing = {}
            for k, d in datasets.items():
                dims = " x ".join(str(s) for s in d.shape)
                listing[k] = f"{'float' if d.dtype.kind == 'f' else 'int'}" \
                             f"{8 * d.dtype.itemsize} [{dims}]"
        check(kv.get("kind") == "frames", "kind: frames")
        check(kv.get("scene") == "info-check", f"scene {kv.get('scene')}")
        check(kv.get("esfera version") == version, f"version {kv.get('esfera version')}")
        check(kv.get("frames") == str(len(names)), f"frames {kv.get('frames')} vs {len(names)}")
        m = re.match(r"(\S+) \.\. (\S+) s$", kv.get("time", ""))
        check(m and abs(float(m.group(1)) - t0) <= 1e-8 * max(t1, 1e-30)
              and abs(float(m.group(2)) - t1) <= 1e-8 * t1, f"time {kv.get('time')}")
        check(n0 == 41 and n1 == 40, f"h5py: {n0} then {n1} particles (one leaves)")
        check(kv.get("particles") == f"{n0} (first frame), {n1} (last frame)",
              f"particles {kv.get('particles')}")
        check(kv.get("energy rows", "").startswith(f"{rows} (24 columns"),
              f"energy rows {kv.get('energy rows')} vs {rows}")
        shown = dict(re.findall(r"^  (\S+): (.*)$", text, re.M))
        check(shown == listing, f"datasets {shown} vs {listing}")
        check("walls/triangles" in shown and "position" in shown, "walls and particles listed")

        # an older result without the `kind` attribute
        old = os.path.join(tmp, "old.h5")
        with open(h5, "rb") as a, open(old, "wb") as b:
            b.write(a.read())
        with h5py.File(old, "a") as f:
            del f.attrs["kind"]
        rc, text2, err = info(esfera, old)
        check(rc == 0 and "kind: frames" in text2, f"file without kind: exit {rc} {err!r}")

        expect_error(esfera, os.path.join(tmp, "nope.h5"), r"cannot open '.*nope\.h5'",
                     "missing file")
        expect_error(esfera, os.path.join(out, "energy.csv"),
                     r"'.*energy\.csv' is not an HDF5 file", "CSV file")
        trunc = os.path.join(tmp, "trunc.h5")
        with open(h5, "rb") as a, open(trunc, "wb") as b:
            b.write(a.read(3000))
        expect_error(esfera, trunc, r"trunc\.h5", "truncated file")
        foreign = os.path.join(tmp, "foreign.h5")
        with h5py.File(foreign, "w") as f:
            f["data"] = [1, 2, 3]
        expect_error(esfera, foreign, r"'.*foreign\.h5' is an HDF5 file but not an esfera",
                     "foreign HDF5 file")
        other = os.path.join(tmp, "ckpt.h5")
        with h5py.File(other, "w") as f:
            f.attrs["esfera_version"] = "9.9"
            f.attrs["kind"] = "checkpoint"
        expect_error(esfera, other, r"kind 'checkpoint'", "unknown kind")
        rc, _, err = info(esfera)
        check(rc == 2 and "usage: esfera info FILE.h5" in err, f"no argument: {rc} {err!r}")
    return finish("check_info")


if __name__ == "__main__":
    sys.exit(main())
