#!/usr/bin/python3
"""check_loads.py ESFERA SOURCE_ROOT -- walls.csv and stress.csv (output.walls,
output.stress; docs/output.md#wallscsv, docs/physics.md#wall-loads-and-region-stress)
against numbers:
  * a simple cubic lattice of N^3 spheres (radius r, lateral spacing 2r' = 2r(1 + 1e-6),
    no gravity) pressed between two planes with the same overlap d at every contact, at
    rest: every contact carries f = kn d; the top plane takes +N^2 f along z, the
    bottom one -N^2 f, their moments about the origin are N^2 f (+-y_mean, -+x_mean, 0);
    the stress of the box over the lattice (from the bottom wall contacts' points to the
    top ones', z = -d/2 and h + d/2 with the seed lever) is szz = f / A, A = (2r')^2 the
    column's cross-section, the other components 0, and so is that of a box cut at the
    contact plane between the first two layers (pairs split at the contact point); all
    to 1e-9, with the leapfrog and with rk4; with the top plane a servo wall holding
    that stress, its row gives target x area (1e-9);
  * a bed of 200 spheres settled in a box: the vertical forces on the walls add up to
    the bed's weight within 1% (mean of the last 5 rows);
  * the helical screw's quick scene (0.2 s, rows every step): the power -M . omega of
    the screw's moment about its axis point, summed over the rows times dt, equals the
    wall work in energy.csv (the ledger's, booked from the same contact forces) to 1e-9
    relative, and is not small (> 0.1 J);
  * walls.csv and stress.csv are the same bytes on 1, 2 and 3 threads and on the
    general path (integrator.fused: false), and a run resumed from its half-way
    checkpoint writes the same bytes as the uninterrupted one."""
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

from pycheck import check, finish, run_sets

N, R, D, KN = 3, 1.0e-3, 1.0e-6, 1.0e4
SP = 2 * R * (1 + 1e-6)  # lateral spacing: the columns do not touch


def lattice_scene(servo=False):
    zs = [(R - D) + k * (2 * R - D) for k in range(N)]  # every overlap d
    h = zs[-1] + R - D  # the top plane
    parts = []
    for i in range(N):
        for j in range(N):
            for k in range(N):
                parts.append(f"  - {{material: g, radius: {R!r}, position: "
                             f"[{(i + 0.5) * SP!r}, {(j + 0.5) * SP!r}, {zs[k]!r}]}}")
    cut = zs[0] + (R - D / 2)  # the contact plane between layers 0 and 1
    lo, hi = -D / 2, h + D / 2  # the wall contacts' points (lever r - d/2)
    box = f"[0, 0, {lo!r}], max: [{N * SP!r}, {N * SP!r}"
    return "\n".join([
        "name: lattice", "gravity: [0, 0, 0]",
        "materials:", f"  g: {{density: 2500, kn: {KN!r}, restitution: 0.5, friction: 0.3}}",
        "particles:", *parts,
        "walls:",
        "  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: g}",
        f"  - {{plane: {{point: [0, 0, {h!r}], normal: [0, 0, -1]}}, material: g"
        + (f", motion: {{servo: {{stress: {N * N * KN * D / (N * SP) ** 2!r}, "
           f"direction: [0, 0, -1], area: {(N * SP) ** 2!r}, max_speed: 0.01}}}}}}"
           if servo else "}"),
        "contact: {allow_initial_overlap: true}",
        "integrator: {method: leapfrog, dt: auto, frac: 0.1}",
        "run: {steps: 20}",
        "output: {energy_every: 0, walls: true, stress: [",
        f"  {{region: {{min: {box}, {hi!r}]}}}},",
        f"  {{region: {{min: {box}, {cut!r}]}}}}]}}", ""]).replace(
            "energy_every: 0", "energy_every: 1.0e-9")


BED = """name: bed
gravity: [0, 0, -9.81]
domain: {min: [-0.01, -0.01, -0.01], max: [0.03, 0.03, 0.1]}
materials:
  glass: {density: 2500, kn: 1.0e4, kt: 2857.142857142857, restitution: 0.3, friction: 0.5}
particles:
  - {generate: random, region: {min: [0, 0, 0.003], max: [0.02, 0.02, 0.04]}, count: 200,
     radius: {uniform_diameter: [0.002, 0.003]}, material: glass, seed: 7}
walls:
  - {box: {min: [0, 0, 0], max: [0.02, 0.02, 0.06]}, open: [top], material: glass}
damping: {global: {translation: 20.0, rotation: 20.0}}
integrator: {method: leapfrog, dt: auto, frac: 0.2}
run: {duration: 0.4}
output: {every: 0.1, energy_every: 0.01, walls: true,
         stress: [{region: {min: [0, 0, 0], max: [0.02, 0.02, 0.06]}},
                  {region: {min: [0, 0, 0], max: [0.02, 0.02, 0.004]}}]}
"""


def load(out, name):
    return np.loadtxt(os.path.join(out, name), delimiter=",", skiprows=1, ndmin=2)


def same_bytes(a, b, what):
    for f in ("walls.csv", "stress.csv"):
        with open(os.path.join(a, f), "rb") as x, open(os.path.join(b, f), "rb") as y:
            check(x.read() == y.read(), f"{what}: {f} differs")


def lattice(exe, tmp):
    scene = os.path.join(tmp, "lattice.yaml")
    with open(scene, "w") as fh:
        fh.write(lattice_scene())
    out = os.path.join(tmp, "lat")
    run_sets(exe, scene, out)
    lattice_rows(out, "leapfrog")
    rk = os.path.join(tmp, "lat_rk4")
    run_sets(exe, scene, rk, "integrator.method=rk4")
    lattice_rows(rk, "rk4")
    gen = os.path.join(tmp, "lat_gen")
    run_sets(exe, scene, gen, "integrator.fused=false")
    same_bytes(out, gen, "lattice: fused vs general path")
    # the top plane as a servo wall holding the lattice's own stress: it stays, and
    # walls.csv gives it the target stress times its area
    with open(scene, "w") as fh:
        fh.write(lattice_scene(servo=True))
    out = os.path.join(tmp, "lat_servo")
    run_sets(exe, scene, out)
    top = load(out, "walls.csv")[-1]
    f = KN * D
    check(int(top[1]) == 1 and abs(top[4] / (N * N * f) - 1) < 1e-9,
          f"lattice, servo lid: fz {top[4]!r} vs target stress x area {N * N * f!r}")
    print(f"lattice, servo lid: fz = {top[4]:.12g} N, target x area {N * N * f:.12g} N")


def lattice_rows(out, how):
    w, s = load(out, "walls.csv"), load(out, "stress.csv")
    f = KN * D
    last = w[-2:]  # the last row's two walls
    xm = ym = N * SP / 2
    want = {0: [0, 0, -N * N * f, -N * N * f * ym, N * N * f * xm, 0],
            1: [0, 0, N * N * f, N * N * f * ym, -N * N * f * xm, 0]}
    for row in last:
        g = int(row[1])
        err = np.abs(row[2:] - want[g]).max() / (N * N * f * xm)
        check(err < 1e-9, f"{how}: lattice wall {g}: {row[2:]} vs {want[g]} (rel {err:.2e})")
        print(f"{how}: lattice wall {g}: F = {row[2:5]}, M = {row[5:]}; closed form {want[g]}")
    a = SP * SP
    for row in s[-2:]:
        r = int(row[1])
        szz, others = row[5], np.abs(np.r_[row[3:5], row[6:9]]).max()
        check(row[2] == (N ** 3 if r == 0 else N * N), f"region {r}: {row[2]} particles")
        check(abs(szz / (f / a) - 1) < 1e-9 and others < 1e-9 * f / a,
              f"{how}: lattice region {r}: szz {szz!r} vs f/A {f / a!r}, others {others:.2e}")
        check(abs(row[9] - szz / 3) < 1e-9 * szz and abs(row[10] - szz) < 1e-9 * szz,
              f"{how}: lattice region {r}: p {row[9]}, q {row[10]} (want szz/3, szz)")
        print(f"{how}: lattice region {r}: szz = {szz:.12g} Pa, f/A = {f / a:.12g} Pa")


def bed(exe, tmp):
    scene = os.path.join(tmp, "bed.yaml")
    with open(scene, "w") as fh:
        fh.write(BED)
    outs = []
    for th in (1, 2, 3):
        out = os.path.join(tmp, f"bed{th}")
        r = subprocess.run([exe, "run", scene, "--out", out, "--quiet", "--overwrite",
                            "--threads", str(th)], capture_output=True, text=True,
                           env=dict(os.environ, ESF_RANGE_WORK="1"))  # a range a thread
        check(r.returncode == 0, f"bed on {th} threads: {r.stderr}")
        outs.append(out)
    for o in outs[1:]:
        same_bytes(outs[0], o, f"bed: 1 thread vs {o[-1]}")
    gen = os.path.join(tmp, "bed_gen")
    run_sets(exe, scene, gen, "integrator.fused=false")
    same_bytes(outs[0], gen, "bed: fused vs general path")
    # the weight
    import h5py
    with h5py.File(os.path.join(outs[0], "frames.h5"), "r") as fh:
        g = fh["frames"][sorted(fh["frames"])[-1]]
        r = g["radius"][:]
    weight = float((2500 * 4 / 3 * np.pi * r ** 3).sum() * 9.81)
    w = load(outs[0], "walls.csv")
    fz = w[:, 4].reshape(-1, 1)[-5:].mean()  # one wall: the box
    check(abs(-fz / weight - 1) < 0.01, f"bed: walls' fz {fz} vs weight {weight}")
    print(f"bed: walls carry {-fz:.6g} N, weight {weight:.6g} N "
          f"({100 * (-fz / weight - 1):+.3f}%)")
    s = load(outs[0], "stress.csv")
    check(s[-2, 2] == 200 and s[-2, 9] > 0, f"bed: whole box: {s[-2, 2]} particles, "
          f"p {s[-2, 9]}")
    # resumed from the half-way checkpoint: the same rows
    ref, res = os.path.join(tmp, "bed_ref"), os.path.join(tmp, "bed_res")
    r = subprocess.run([exe, "run", scene, "--out", ref, "--quiet", "--checkpoint-every",
                        "0.2", "--threads", "2"], capture_output=True, text=True)
    check(r.returncode == 0, f"bed with a checkpoint: {r.stderr}")
    shutil.copytree(ref, res)
    r = subprocess.run([exe, "run", "--resume", res, "--quiet", "--threads", "1"],
                       capture_output=True, text=True)
    check(r.returncode == 0, f"bed resumed: {r.stderr}")
    same_bytes(ref, res, "bed: resumed vs uninterrupted")
    same_bytes(outs[0], res, "bed: resumed vs the plain run")


def screw(exe, root, tmp):
    out = os.path.join(tmp, "screw")
    run_sets(exe, os.path.join(root, "scenes", "helical_screw-quick.yaml"), out,
             "run.duration=0.2", "output.energy_every=1.17e-5", "output.walls=true",
             "output.every=0")
    w = load(out, "walls.csv")
    e = np.genfromtxt(os.path.join(out, "energy.csv"), delimiter=",", names=True)
    s = w[w[:, 1] == 1]
    om = -95 * 2 * np.pi / 60  # about +z (the scene turns about -z at 95 rpm)
    power = -s[:, 7] * om
    work = float((power[:-1] * np.diff(s[:, 0])).sum())
    ledger = float(e["work_walls"][-1] - e["work_walls"][0])
    check(len(s) == len(e), f"screw: {len(s)} rows of the screw, {len(e)} energy rows")
    check(abs(work / ledger - 1) < 1e-9 and ledger > 0.1,
          f"screw: sum -M.omega dt {work!r} J vs ledger wall work {ledger!r} J")
    print(f"screw: sum of -M.omega dt = {work:.12g} J, ledger's wall work "
          f"{ledger:.12g} J")


def main():
    exe, root = sys.argv[1], sys.argv[2]
    with tempfile.TemporaryDirectory() as tmp:
        lattice(exe, tmp)
        bed(exe, tmp)
        screw(exe, root, tmp)
    return finish("check_loads")


if __name__ == "__main__":
    sys.exit(main())
