#!/usr/bin/python3
"""check_reader.py ESFERA SOURCE_ROOT — the Python reader studies/esfera_h5.py and
scripts/render.py on a real run: load_frames gives every frame in order with the
frames' times and every dataset (shapes N x 3 and N, walls, contacts), select=[-1]
the last one; load_energy from frames.h5's /energy, from energy.csv and from the
result directory give the same 24 columns and rows, equal within the CSV's printed
precision (relative 1e-9: time has 10 significant digits, energies 13);
the CLI summary exits 0 and names the frame count, a missing file exits 2; render.py
writes a PNG of the last frame that is not blank (hundreds of distinct colours); the
walls in the frames of a run with an oscillating box are displaced by A sin(2 pi f t)
at each frame's time (1e-12 m)."""
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

from pycheck import check, finish, run_scene

SCENE = """name: reader-check
materials:
  g: {density: 2500, kn: 1.0e4, restitution: 0.5, friction: 0.4}
particles:
  - {generate: random, region: {min: [0.002, 0.002, 0.004], max: [0.028, 0.028, 0.05]},
     count: 120, radius: {uniform: [0.0012, 0.0018]}, material: g, seed: 5}
walls:
  - {box: {min: [0, 0, 0], max: [0.03, 0.03, 0.06]}, open: [top], material: g}
integrator: {method: leapfrog, dt: auto, frac: 0.2}
run: {duration: 0.3}
output: {every: 0.05, energy_every: 2.0e-3, contacts: true}
"""

MOVING = """name: move
materials:
  g: {density: 2500, kn: 1.0e4, restitution: 0.5, friction: 0.4}
particles:
  - {generate: random, region: {min: [0.003, 0.003, 0.004], max: [0.027, 0.027, 0.03]},
     count: 50, radius: 0.0015, material: g, seed: 1}
walls:
  - {box: {min: [0, 0, 0], max: [0.03, 0.03, 0.06]}, open: [top], material: g,
     motion: {oscillate: {direction: [1, 0, 0], frequency: 20, amplitude: 0.002}}}
integrator: {method: leapfrog, dt: auto, frac: 0.2}
run: {duration: 0.05}
output: {every: 0.01, energy_every: 0}
"""



def main():
    esfera, root = sys.argv[1], sys.argv[2]
    sys.path.insert(0, os.path.join(root, "studies"))
    import esfera_h5

    with tempfile.TemporaryDirectory() as tmp:
        out = run_scene(esfera, tmp, SCENE)
        h5 = os.path.join(out, "frames.h5")
        frames = esfera_h5.load_frames(out)
        with h5py.File(h5, "r") as f:
            names = sorted(f["frames"])
            times = [float(f["frames"][n].attrs["time"]) for n in names]
            last_pos = f["frames"][names[-1]]["position"][()]
        check(len(frames) == len(names) >= 5, f"{len(frames)} frames, file has {len(names)}")
        check([fr.time for fr in frames] == times, "frame times")
        for fr in frames:
            d = fr.data
            n = len(d["id"])
            check(n == 120, f"t={fr.time}: {n} particles")
            for k in ("position", "velocity", "angular_velocity", "force"):
                check(d[k].shape == (n, 3) and d[k].dtype == np.float64, f"{k} shape")
            check(d["radius"].shape == (n,) and d["material"].dtype == np.int32,
                  "radius, material")
            check(d["walls/points"].shape == (20, 3) and d["walls/triangles"].shape == (10, 3),
                  "walls mesh")
            check(d["contacts/pairs"].shape[1:] == (2,), "contact pairs")
        check(np.array_equal(frames[-1].data["position"], last_pos), "last frame's positions")
        only = esfera_h5.load_frames(h5, select=[-1])
        check(len(only) == 1 and only[0].time == times[-1], "select=[-1]")
        # settled by 0.3 s (about 120 contacts); at 0.15 s it still bounces
        check(len(frames[-1].data["contacts/pairs"]) > 60, "the pack has contacts")

        e_h5 = esfera_h5.load_energy(h5)
        e_csv = esfera_h5.load_energy(os.path.join(out, "energy.csv"))
        e_dir = esfera_h5.load_energy(out)
        check(list(e_h5) == list(e_csv) and len(e_h5) == 24, f"columns {list(e_h5)}")
        check(len(e_h5["time"]) == len(e_csv["time"]) >= 140, "row counts")
        worst = 0.0
        for k in e_h5:
            a, b = e_h5[k], e_csv[k]
            scale = np.maximum(np.abs(a), 1e-300)
            worst = max(worst, float(np.max(np.abs(a - b) / scale)))
        print(f"largest relative difference /energy vs energy.csv: {worst:.3g}")
        check(worst < 1e-9, f"HDF5 and CSV energy differ by {worst:.3g} (relative)")
        check(all(np.array_equal(e_dir[k], e_h5[k]) for k in e_h5), "directory -> frames.h5")

        py = sys.executable
        r = subprocess.run([py, os.path.join(root, "studies", "esfera_h5.py"), h5],
                           capture_output=True, text=True)
        check(r.returncode == 0 and f"frames: {len(names)}" in r.stdout,
              f"CLI summary: {r.returncode} {r.stdout!r} {r.stderr!r}")
        r = subprocess.run([py, os.path.join(root, "studies", "esfera_h5.py"),
                            os.path.join(tmp, "none.h5")], capture_output=True, text=True)
        check(r.returncode == 2 and "none.h5" in r.stderr, f"CLI on a missing file: {r}")

        png = os.path.join(tmp, "last.png")
        r = subprocess.run([py, os.path.join(root, "scripts", "render.py"), out, "--out",
                            png, "--size", "4", "--dpi", "60"], capture_output=True, text=True)
        check(r.returncode == 0 and os.path.exists(png), f"render.py: {r.stderr}")
        if os.path.exists(png):
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.image as mpimg
            img = mpimg.imread(png)
            colours = len(np.unique((img[..., :3] * 255).astype(np.uint8).reshape(-1, 3),
                                    axis=0))
            print(f"render: {img.shape[1]} x {img.shape[0]} px, {colours} colours")
            check(img.shape[0] > 150 and img.shape[1] > 150, "picture size")
            check(colours > 200, f"the picture looks blank ({colours} colours)")
        # walls are written at each frame's time: an oscillating box
        scene = os.path.join(tmp, "move.yaml")
        with open(scene, "w") as fh:
            fh.write(MOVING)
        out = os.path.join(tmp, "move")
        r = subprocess.run([esfera, "run", scene, "--out", out, "--quiet"],
                           capture_output=True, text=True)
        check(r.returncode == 0, f"moving-wall run: exit {r.returncode} {r.stderr}")
        worst, seen = 0.0, set()
        for fr in esfera_h5.load_frames(out):
            x0 = fr.data["walls/points"][:, 0].min()
            worst = max(worst, abs(x0 - 0.002 * np.sin(2 * np.pi * 20 * fr.time)))
            seen.add(round(x0, 6))
        print(f"moving box: wall x in the frames off the motion by at most {worst:.3g} m")
        check(worst < 1e-12 and len(seen) >= 4, f"moving walls in frames ({worst}, {seen})")
    return finish("check_reader")


if __name__ == "__main__":
    sys.exit(main())
