"""check_periodic.py -- periodic boundaries through the esfera program (issue 29): a
frictional gas in a fully periodic box (3D) and a 2D gas of disks periodic in x and z
give the same frames (every dataset, the image counters included) and energy.csv byte
for byte on 1, 2 and 3 threads and on the general path; a checkpoint taken halfway
resumes to the same output bit for bit, with particles wrapping on both sides of it;
each frame's `image` rebuilds unwrapped positions that move continuously (less than
v_max dt_frame between frames) while the wrapped ones jump by a period; an oblique
frictional impact across x = L books the mid-domain pair's energy ledger, every column
to 1e-9 of the energy, and gives its stress.csv (branch vectors from the partner's
image on the contact's side) to 1e-9 of the largest stress; particles inserted during
the run into a box periodic in x and y give the same output on 1 and 2 threads and
resumed from a checkpoint taken while they come in. The same for
the 3D gas under Lees-Edwards shear (domain.shear; ledger off; the flow axis left out
of the unwrapped check).
Usage: check_periodic.py ESFERA"""
import os
import random
import shutil
import sys
import tempfile

import h5py
import numpy as np

from ckpt_common import identical, run_ok, write_scene
from pycheck import check, finish

L = 0.04

SCENE = """name: pbc_gas
dimension: {dim}
disk_thickness: 0.002
gravity: [0, 0, 0]
domain: {{min: [0, {ylo}, 0], max: [{L}, {yhi}, {L}], periodic: {axes}{shear}}}
materials:
  glass: {{density: 2500, kn: 2.0e4, restitution: 0.5, friction: 0.4}}
particles:
  - {{file: gas.csv, material: glass}}
integrator: {{method: leapfrog, dt: auto, frac: 0.3}}
run: {{duration: 0.03}}
output: {{every: 0.002, energy_every: {energy}}}
"""


def gas_csv(path, n, dim, seed):
    """n spheres (or disks in x-z) placed without overlap across the periodic faces,
    with Gaussian velocities."""
    rnd = random.Random(seed)
    placed = []
    while len(placed) < n:
        r = rnd.uniform(0.001, 0.002)
        x = [rnd.uniform(0, L), 0.0 if dim == 2 else rnd.uniform(0, L), rnd.uniform(0, L)]
        ok = True
        for y, s in placed:
            d = [min(abs(x[k] - y[k]), L - abs(x[k] - y[k])) for k in range(3)]
            if sum(t * t for t in d) < (r + s + 1e-4) ** 2:
                ok = False
                break
        if ok:
            placed.append((x, r))
    with open(path, "w") as fh:
        fh.write("x,y,z,radius,vx,vy,vz\n")
        for x, r in placed:
            v = [rnd.gauss(0, 0.5), 0.0 if dim == 2 else rnd.gauss(0, 0.5), rnd.gauss(0, 0.5)]
            fh.write("%.9g,%.9g,%.9g,%.9g,%.6f,%.6f,%.6f\n" % (*x, r, *v))


def frames(out):
    with h5py.File(os.path.join(out, "frames.h5"), "r") as f:
        res = []
        for k in sorted(f["frames"]):
            g = f["frames"][k]
            res.append({"t": g.attrs["time"], "id": g["id"][()], "x": g["position"][()],
                        "v": g["velocity"][()], "img": g["image"][()]})
        return res


def check_unwrapped(fr, name, axes, skip=""):
    per = np.array([1.0 if a in axes else 0.0 for a in "xyz"])
    keep = [k for k in range(3) if "xyz"[k] not in skip]
    jumps, worst = 0, 0.0
    for a, b in zip(fr, fr[1:]):
        ia, ib = np.argsort(a["id"]), np.argsort(b["id"])
        ua = a["x"][ia] + a["img"][ia] * L * per
        ub = b["x"][ib] + b["img"][ib] * L * per
        dt = b["t"] - a["t"]
        vmax = max(np.abs(a["v"]).max(), np.abs(b["v"]).max())
        worst = max(worst, float(np.abs(ub - ua)[:, keep].max() / (vmax * dt)))
        jumps += int((np.abs(b["x"][ib] - a["x"][ia])[:, keep] > 0.5 * L).sum())
        check(np.all(a["img"][:, [k for k in range(3) if "xyz"[k] not in axes]] == 0),
              f"{name}: no image on a closed axis")
    print(f"{name}: {jumps} wraps between frames; unwrapped steps <= {worst:.3f} v_max dt")
    check(jumps > 5, f"{name}: particles wrapped between frames ({jumps})")
    check(worst < 1.001, f"{name}: unwrapped positions move continuously ({worst:.3f})")


def case(exe, tmp, dim, axes, n, shear=False):
    name = f"{dim}d" + ("_shear" if shear else "")
    d = os.path.join(tmp, name)
    os.makedirs(d)
    gas_csv(os.path.join(d, "gas.csv"), n, dim, 7 + dim)
    sh = ",\n         shear: {rate: 20, flow: x, gradient: z}" if shear else ""
    scene = write_scene(d, SCENE.format(dim=dim, L=L, ylo=-L if dim == 2 else 0,
                                        yhi=L, axes="[" + ", ".join(axes) + "]", shear=sh,
                                        energy=0 if shear else 0.0005),
                        "gas.yaml")
    outs = {}
    for t in (1, 2, 3):
        outs[t] = os.path.join(d, f"t{t}")
        run_ok(exe, "run", scene, "--out", outs[t], "--quiet", "--threads", str(t))
    gen = os.path.join(d, "gen")
    run_ok(exe, "run", scene, "--out", gen, "--quiet", "--set", "integrator.fused=false")
    for other in (outs[2], outs[3], gen):
        nf, diffs = identical(outs[1], other)
        check(nf > 10 and not diffs, f"{name}: {other} against 1 thread: {diffs[:3]}")
    with open(os.path.join(outs[1], "frames.xdmf")) as fh:
        check('Attribute Name="image"' in fh.read(), f"{name}: frames.xdmf lists image")
    fr = frames(outs[1])
    check_unwrapped(fr, name, axes, "x" if shear else "")
    # checkpoint halfway (2 threads), resumed on one
    ref, res = os.path.join(d, "ref"), os.path.join(d, "res")
    run_ok(exe, "run", scene, "--out", ref, "--quiet", "--threads", "2",
           "--checkpoint-every", "0.015")
    shutil.copytree(ref, res)
    run_ok(exe, "run", "--resume", res, "--quiet", "--threads", "1")
    nf, diffs = identical(ref, res)
    check(nf > 10 and not diffs, f"{name}: resumed run: {diffs[:3]}")
    nf, diffs = identical(ref, outs[1])
    check(not diffs, f"{name}: checkpointed run against the plain one: {diffs[:3]}")
    half = [f for f in fr if f["t"] < 0.5 * fr[-1]["t"]]
    w0, w1 = np.abs(half[-1]["img"]).sum(), np.abs(fr[-1]["img"]).sum()
    print(f"{name}: image counts {w0} at the half, {w1} at the end")
    check(w0 > 0 and w1 > w0, f"{name}: wraps before and after the checkpoint ({w0}, {w1})")


PAIR = """name: pbc_pair
gravity: [0, 0, 0]
domain: {{min: [0, -0.05, -0.05], max: [0.1, 0.05, 0.05]{per}}}
materials: {{glass: {{density: 2500, kn: 1.0e4, restitution: 0.5, friction: 0.3}}}}
particles:
  - {{material: glass, radius: 0.005, position: [{xa}, 0, 0], velocity: [2, 0, 0.3]}}
  - {{material: glass, radius: 0.005, position: [{xb}, 0, 0.002], velocity: [0, 0, -0.3]}}
integrator: {{method: leapfrog, dt: 2.0e-6}}
search: {{skin: 0.0004}}
run: {{steps: 2000}}
output: {{every: 0.001, energy_every: 0.0001,
         stress: [{{region: {{min: [0, -0.05, -0.05], max: [0.1, 0.05, 0.05]}}}}]}}
"""


def ledger(exe, tmp):
    """The energy ledger of an oblique frictional impact across x = L against the same
    pair in mid-domain: every column of the last row to 1e-9 of the energy."""
    rows, stress = [], []
    for per, xa, xb in (("", 0.0396, 0.0498), (", periodic: [x]", 0.0896, 0.0998)):
        d = os.path.join(tmp, "pair" + ("_per" if per else ""))
        os.makedirs(d)
        scene = write_scene(d, PAIR.format(per=per, xa=xa, xb=xb), "pair.yaml")
        run_ok(exe, "run", scene, "--out", os.path.join(d, "out"), "--quiet")
        with open(os.path.join(d, "out", "energy.csv")) as fh:
            lines = fh.read().split()
        head = lines[0].split(",")
        rows.append(dict(zip(head, map(float, lines[-1].split(",")))))
        with open(os.path.join(d, "out", "stress.csv")) as fh:
            st = [ln.split(",") for ln in fh.read().split()]
        stress.append(np.array([[float(v) for v in r[3:9]] for r in st[1:]]))
    e0 = rows[0]["kinetic_translational"] + rows[0]["dissipated_contact"] + \
        rows[0]["dissipated_friction"]
    worst = max(abs(rows[0][k] - rows[1][k]) for k in rows[0] if k != "time")
    print(f"pair ledger: total_error {rows[1]['total_error']:.4g} J periodic, "
          f"{rows[0]['total_error']:.4g} J mid-domain; largest column difference "
          f"{worst:.3g} J of {e0:.4g} J")
    check(worst < 1e-9 * e0, f"pair ledger as in mid-domain ({worst:.3g} J)")
    check(abs(rows[1]["total_error"]) < 1e-5 * e0, "pair ledger closes")
    scale = np.abs(stress[0]).max()
    ds = np.abs(stress[1] - stress[0]).max()
    print(f"pair stress (Love-Weber, the domain as region): largest difference {ds:.3g} Pa "
          f"of {scale:.4g} Pa")
    check(scale > 0 and ds < 1e-9 * scale, f"pair stress as in mid-domain ({ds:.3g} Pa)")


INSERT = """name: pbc_insert
gravity: [0, 0, -9.81]
domain: {min: [0, 0, -0.01], max: [0.04, 0.04, 0.2], periodic: [x, y]}
materials:
  glass: {density: 2500, kn: 1.0e4, restitution: 0.5, friction: 0.5}
particles:
  - insert:
      region: {min: [0.002, 0.002, 0.05], max: [0.038, 0.038, 0.09]}
      rate: 20000
      radius: {uniform_diameter: [0.002, 0.003]}
      material: glass
      velocity: [0.3, -0.2, -0.5]
      seed: 5
      stop: 0.03
      every: 0.002
walls:
  - {polygon: [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], material: glass}
integrator: {method: leapfrog, dt: auto, frac: 0.2}
run: {duration: 0.08}
output: {every: 0.004, energy_every: 0.001}
"""


def insert(exe, tmp):
    """Particles inserted into a box periodic in x and y over a floor: the same output
    on 1 and 2 threads, and resumed from a checkpoint taken while they come in; the
    newcomers' image counters start at zero, and some cross the faces."""
    d = os.path.join(tmp, "insert")
    os.makedirs(d)
    scene = write_scene(d, INSERT, "insert.yaml")
    one, two, ref, res = (os.path.join(d, k) for k in ("t1", "t2", "ref", "res"))
    run_ok(exe, "run", scene, "--out", one, "--quiet", "--threads", "1")
    run_ok(exe, "run", scene, "--out", two, "--quiet", "--threads", "2")
    nf, diffs = identical(one, two)
    check(nf > 10 and not diffs, f"insert: 2 threads against 1: {diffs[:3]}")
    run_ok(exe, "run", scene, "--out", ref, "--quiet", "--checkpoint-every", "0.02")
    shutil.copytree(ref, res)
    run_ok(exe, "run", "--resume", res, "--quiet")
    nf, diffs = identical(ref, res)
    check(nf > 10 and not diffs, f"insert: resumed run: {diffs[:3]}")
    fr = frames(one)
    n0, n1 = len(fr[1]["id"]), len(fr[-1]["id"])
    wraps = int(np.abs(fr[-1]["img"]).sum())
    print(f"insert: {n0} particles in the first frames, {n1} at the end, {wraps} wraps")
    check(n1 > n0 > 0, f"insert: particles came in ({n0}, {n1})")
    check(wraps > 0, "insert: inserted particles crossed the periodic faces")


def main():
    exe = sys.argv[1]
    with tempfile.TemporaryDirectory() as tmp:
        ledger(exe, tmp)
        insert(exe, tmp)
        case(exe, tmp, 3, ["x", "y", "z"], 150)
        case(exe, tmp, 2, ["x", "z"], 60)
        case(exe, tmp, 3, ["x", "y", "z"], 150, shear=True)
    return finish("check_periodic")


if __name__ == "__main__":
    sys.exit(main())
