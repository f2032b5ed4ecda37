#!/usr/bin/python3
"""check_paraview.py ESFERA — frames.xdmf in ParaView's own readers (pvbatch), when
ParaView is installed (otherwise the test is skipped: exit 77).

A run of spheres poured into a box with an open floor, contacts written: its first
frame has no contacts and its later frames fewer particles than the first (the
vertex cells become hyperslabs). tests/paraview_readers.py opens frames.xdmf with
Xdmf3ReaderT, Xdmf3ReaderS and XDMFReader and frames_particles.xdmf with
Xdmf3ReaderS, at the first and the last time. Each must give the particles as N
vertex cells on N points (N from frames.h5) with their arrays (radius, velocity,
angular_velocity, force, material, id), the walls as the mesh's triangles, and the
contacts as many lines as frames.h5 has pairs, none failing on the empty first set;
the times are the frames' times; XDMFReader keeps the block names. The particles are
then rendered as Point Gaussian scaled by radius (docs/output.md#paraview), under
xvfb-run when there is no display (neither: no image; the readers need no display),
with up to three attempts (a virtual X server can fail to start on a loaded machine),
and the image must show them: at least 5% of its pixels differ from the white
background."""
import json
import os
import shutil
import subprocess
import sys
import tempfile

import h5py

from pycheck import check, finish, run_scene

SCENE = """name: paraview-check
domain: {min: [-0.01, -0.01, -0.005], max: [0.04, 0.04, 0.06]}
materials:
  g: {density: 2500, kn: 1.0e4, restitution: 0.5, friction: 0.4}
particles:
  - {generate: random, region: {min: [0.002, 0.002, 0.004], max: [0.028, 0.028, 0.05]},
     count: 80, radius: {uniform: [0.0012, 0.0018]}, material: g, seed: 3}
walls:
  - {box: {min: [0, 0, 0], max: [0.03, 0.03, 0.06]}, open: [top], material: g}
  - {polygon: [[0, 0, 0], [0.015, 0, 0], [0.015, 0.03, 0], [0, 0.03, 0]], material: g}
integrator: {method: leapfrog, dt: auto, frac: 0.2}
run: {duration: 0.12}
output: {every: 0.02, energy_every: 1.0e-3, contacts: true}
"""

PARTICLE_ARRAYS = {"radius", "velocity", "angular_velocity", "force", "material", "id"}


def main():
    esfera = sys.argv[1]
    pvbatch = shutil.which("pvbatch")
    if not pvbatch:
        print("check_paraview: skipped (no pvbatch: ParaView is not installed)")
        return 77
    render = [pvbatch]
    if not os.environ.get("DISPLAY"):  # reading needs no display; rendering does
        xvfb = shutil.which("xvfb-run")
        render = [xvfb, "-a", pvbatch] if xvfb else None
        if not xvfb:
            print("check_paraview: no display and no xvfb-run: the readers only, no image")
    here = os.path.dirname(os.path.abspath(__file__))
    script = os.path.join(here, "paraview_readers.py")
    with tempfile.TemporaryDirectory() as tmp:
        # half the floor is missing: spheres fall out while others settle on the rest
        out = run_scene(esfera, tmp, SCENE.replace("open: [top]", "open: [top, bottom]"))
        js, png = os.path.join(tmp, "r.json"), os.path.join(tmp, "p.png")
        r = subprocess.run([pvbatch, script, out, js], capture_output=True, text=True,
                           timeout=600)
        check(r.returncode == 0 and os.path.exists(js),
              f"pvbatch exit {r.returncode}: {r.stderr[-2000:]}")
        # the image: a virtual X server may fail to come up on a loaded machine (the
        # render then aborts on "bad X server connection"): up to three attempts
        for attempt in range(3 if render else 0):
            rr = subprocess.run(render + [script, out, js + ".render", png],
                                capture_output=True, text=True, timeout=600)
            if rr.returncode == 0 and os.path.exists(png):
                break
            print(f"render attempt {attempt + 1}: exit {rr.returncode}: "
                  f"{rr.stderr.strip().splitlines()[-1:] if rr.stderr.strip() else ''}")
        if not os.path.exists(js):
            return finish("check_paraview")
        with open(js) as fh:
            rep = json.load(fh)
        with h5py.File(os.path.join(out, "frames.h5"), "r") as f:
            keys = sorted(f["frames"].keys())
            first, last = f["frames"][keys[0]], f["frames"][keys[-1]]
            want = [(float(g.attrs["time"]), len(g["position"]), len(g["contacts/pairs"]),
                     len(g["walls/triangles"])) for g in (first, last)]
            times = [float(f["frames"][k].attrs["time"]) for k in keys]
        check(want[0][2] == 0 and want[1][1] < want[0][1] and want[1][2] > 0,
              f"the run has an empty first contact set and loses particles: {want}")
        for name, got in rep.items():
            check(got["times"] == times, f"{name}: times {got['times']} against {times}")
            solo = name.endswith("particles")
            for (t, n, nc, ntri), at in zip(want, got["at"]):
                blocks = at["blocks"]
                check(len(blocks) == (1 if solo else 3), f"{name} t={t}: {len(blocks)} blocks")
                if len(blocks) < (1 if solo else 3):
                    continue
                p = blocks[0][1]
                check(p is not None and p["points"] == n and p["cells"] == n,
                      f"{name} t={t}: particles {p and (p['points'], p['cells'])}, want {n}")
                check(p is not None and PARTICLE_ARRAYS <= set(p["point_arrays"]),
                      f"{name} t={t}: particle arrays {p and p['point_arrays']}")
                if solo:
                    continue
                w, c = blocks[1][1], blocks[2][1]
                check(w is not None and w["cells"] == ntri,
                      f"{name} t={t}: {w and w['cells']} wall cells, want {ntri}")
                check(c is not None and c["cells"] == nc,
                      f"{name} t={t}: {c and c['cells']} contact lines, want {nc}")
                if name == "XDMFReader":
                    check([b[0] for b in blocks] == ["particles", "walls", "contacts"],
                          f"XDMFReader keeps the names: {[b[0] for b in blocks]}")
        if os.path.exists(png):
            import matplotlib.image
            a = matplotlib.image.imread(png)[..., :3]
            frac = float((abs(a - 1.0).sum(-1) > 0.1).mean())
            check(frac > 0.05, f"Point Gaussian image: {frac:.3f} of its pixels drawn")
            print(f"Point Gaussian image: {frac:.3f} of the pixels show particles")
        elif render:
            check(False, "no image rendered in three attempts")
        print("readers:", ", ".join(rep))
    return finish("check_paraview")


if __name__ == "__main__":
    sys.exit(main())
