"""check_insert.py -- particles inserted during the run (issue 29; particles entry
{insert: {...}}, docs/scene.md#insert), against numbers:
- the count follows rate x time (+-1) when space allows (3D box, 2D disks);
- no newborn overlaps a particle or a wall: a static scene (no gravity, newborns at
  rest, so every pair is as it was placed) filled past what fits, with an explicit
  particle, a one-sided plane and a rectangle crossing the region, every pair and
  every wall checked in the last frame; the shortfall is logged once, with the numbers;
- the same seed gives the same bits (frames, energy.csv), another seed other places;
- the same bits on 1, 2 and 3 threads (fused step, ranges of one thread each), and on
  the general path;
- a checkpoint taken mid-insertion resumes bit for bit (fused, 2 threads -> default);
- mass_rate: the inserted mass is within one particle below mass_rate x time;
- the ledger closes: free fall with insertion, |total_error| against energy_inserted;
- 2D: disks at y = 0, no overlaps;
- an ODE method (and velocity Verlet) refuses an insert entry with a located error, as
  do the library's ODE view and bad keys and values;
- the Python module steps an insert scene with its ledger closed.
Usage: check_insert.py ESFERA"""
import math
import os
import shutil
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..",
                                "studies"))
import esfera_h5  # noqa: E402
from ckpt_common import esfera, identical, run_ok  # noqa: E402
from pycheck import check, finish  # noqa: E402

BOX = """name: ins
domain: {min: [-0.01, -0.01, -0.01], max: [0.03, 0.03, 0.08]}
materials:
  glass: {density: 2500, kn: 1.0e4, kt: 2857.14, restitution: 0.5, friction: 0.5}
  steel: {density: 7800, kn: 1.0e4, restitution: 0.5, friction: 0.5}
particles:
  - {material: steel, radius: 0.003, position: [0.01, 0.01, 0.003]}
  - insert:
      region: {min: [0, 0, 0.03], max: [0.02, 0.02, 0.06]}
      rate: 5000
      radius: {uniform_diameter: [0.002, 0.003]}
      material: {mix: {glass: 0.7, steel: 0.3}}
      velocity: [0, 0, -1]
      seed: 5
      stop: 0.03
      every: 0.0005
walls:
  - {box: {min: [0, 0, 0], max: [0.02, 0.02, 0.07]}, open: [top], material: steel}
integrator: {method: leapfrog, dt: auto, frac: 0.2}
run: {duration: 0.04}
output: {every: 0.004, energy_every: 0.0005}
"""

# static: newborns at rest without gravity never move; the region is over-full
STATIC = """name: static
gravity: [0, 0, 0]
materials:
  glass: {density: 2500, kn: 1.0e4}
particles:
  - {material: glass, radius: 0.004, position: [0.01, 0.01, 0.01]}
  - insert:
      region: {min: [0, 0, 0], max: [0.02, 0.02, 0.02]}
      rate: 200000
      radius: {values: [0.001, 0.0015], fractions: [0.5, 0.5]}
      material: glass
      seed: 3
      every: 0.0001
walls:
  - {plane: {point: [0, 0, 0.004], normal: [0, 0, 1]}, material: glass}
  - {polygon: [[0, 0, 0.015], [0.02, 0, 0.015], [0.02, 0.008, 0.015], [0, 0.008, 0.015]],
     material: glass}
integrator: {method: leapfrog, dt: 1.0e-5}
run: {duration: 0.005}
output: {every: 0.001, energy_every: 0.001}
"""

FALL = """name: fall
materials:
  glass: {density: 2500, kn: 1.0e4}
particles:
  - insert:
      region: {min: [0, 0, 0], max: [0.05, 0.05, 0.05]}
      RATE
      radius: {uniform: [0.001, 0.002]}
      material: glass
      velocity: [0.1, 0, 0.3]
      stop: 0.02
      every: 0.00002
integrator: {method: leapfrog, dt: 1.0e-5}
run: {duration: 0.025}
output: {every: 0.005, energy_every: 0.0001}
"""


def write(tmp, name, text):
    path = os.path.join(tmp, name)
    with open(path, "w") as fh:
        fh.write(text)
    return path


def summary(stdout):
    line = [ln for ln in stdout.splitlines() if ln.startswith("summary:")]
    return dict(kv.split("=", 1) for kv in line[-1].split()[1:] if "=" in kv) if line \
        else {}


def last_frame(out):
    return esfera_h5.load_frames(out)[-1].data


def overlaps(x, r, slack=1e-12):
    """Pairs (i, j) with |x_i - x_j| < r_i + r_j (all pairs)."""
    bad = []
    for i in range(len(r)):
        d = np.linalg.norm(x[i + 1:] - x[i], axis=1)
        for j in np.nonzero(d < (r[i + 1:] + r[i]) * (1 - slack))[0]:
            bad.append((i, i + 1 + j, d[j], r[i] + r[i + 1 + j]))
    return bad


def rect_dist(p):
    """Distance from p to the rectangle [0, 0.02] x [0, 0.008] at z = 0.015."""
    q = np.array([min(max(p[0], 0.0), 0.02), min(max(p[1], 0.0), 0.008), 0.015])
    return float(np.linalg.norm(p - q))


def check_static(exe, tmp):
    scene = write(tmp, "static.yaml", STATIC)
    out = os.path.join(tmp, "static")
    r = run_ok(exe, "run", scene, "--out", out, "--quiet")
    s = summary(r.stdout)
    f = last_frame(out)
    x, rad = np.asarray(f["position"]), np.asarray(f["radius"])
    bad = overlaps(x, rad)
    check(not bad, f"static: {len(bad)} overlapping pairs, first {bad[:2]}")
    below = [i for i in range(len(rad)) if x[i, 2] - 0.004 < rad[i] * (1 - 1e-12)]
    check(not below, f"static: {len(below)} particles overlap (or lie behind) the plane")
    near = [i for i in range(len(rad)) if rect_dist(x[i]) < rad[i] * (1 - 1e-12)]
    check(not near, f"static: {len(near)} particles overlap the rectangle")
    inside = all((x[i, k] - rad[i] >= -1e-15 and x[i, k] + rad[i] <= 0.02 + 1e-15)
                 for i in range(1, len(rad)) for k in range(3))
    check(inside, "static: newborns lie inside the region")
    with open(os.path.join(out, "log.txt")) as fh:
        log = fh.read()
    told = log.count("fewer than due")
    check(told == 1, f"static: the shortfall told once, {told} times")
    line = [ln for ln in log.splitlines() if "fewer than due" in ln]
    check(bool(line) and "rate 200000" in line[0] and "attempts" in line[0],
          f"static: the message gives the numbers: {line[:1]}")
    n_in = int(s.get("inserted", -1))
    check(n_in == len(rad) - 1 and n_in > 100,
          f"static: {n_in} inserted, {len(rad)} particles in the frame")
    print(f"static: {n_in} newborns of {int(200000 * 0.005)} due, solid fraction "
          f"{sum(4 / 3 * math.pi * rad[1:] ** 3) / 0.02 ** 3:.3f}; no overlap among "
          f"{len(rad) * (len(rad) - 1) // 2} pairs, none with the plane or rectangle")


def check_box(exe, tmp):
    scene = write(tmp, "box.yaml", BOX)
    a, b = os.path.join(tmp, "box_a"), os.path.join(tmp, "box_b")
    ra = run_ok(exe, "run", scene, "--out", a, "--quiet", "--threads", "1")
    n_in = int(summary(ra.stdout).get("inserted", -1))
    check(abs(n_in - 5000 * 0.03) <= 1, f"box: {n_in} inserted, rate x time = 150")
    run_ok(exe, "run", scene, "--out", b, "--quiet", "--threads", "1")
    n, diffs = identical(a, b)
    check(n > 5 and not diffs, f"box: same seed, other bits: {diffs[:3]}")
    c = os.path.join(tmp, "box_seed")
    run_ok(exe, "run", scene, "--out", c, "--quiet", "--threads", "1", "--set",
           "particles.1.insert.seed=6")
    xa, xc = last_frame(a)["position"], last_frame(c)["position"]
    check(len(xa) != len(xc) or not np.array_equal(xa, xc), "box: another seed, same places")
    env = dict(os.environ, ESF_RANGE_WORK="1")
    for th in ("2", "3"):
        d = os.path.join(tmp, "box_t" + th)
        r = subprocess.run([exe, "run", scene, "--out", d, "--quiet", "--threads", th],
                           capture_output=True, text=True, env=env)
        check(r.returncode == 0, f"box: {th} threads: exit {r.returncode} {r.stderr}")
        n, diffs = identical(a, d)
        check(not diffs, f"box: {th} threads differ from 1: {diffs[:3]}")
    g = os.path.join(tmp, "box_general")
    run_ok(exe, "run", scene, "--out", g, "--quiet", "--set", "integrator.fused=false")
    n, diffs = identical(a, g)
    check(not diffs, f"box: the general path differs from the fused step: {diffs[:3]}")
    # a checkpoint mid-insertion (t = 0.0151 s of 0.03), resumed
    ref, res = os.path.join(tmp, "box_ref"), os.path.join(tmp, "box_res")
    run_ok(exe, "run", scene, "--out", ref, "--quiet", "--threads", "2",
           "--checkpoint-every", "0.0151", "--set", "run.duration=0.03")
    shutil.copytree(ref, res)
    run_ok(exe, "run", "--resume", res, "--quiet")
    n, diffs = identical(ref, res)
    check(n > 5 and not diffs, f"box: resumed mid-insertion differs: {diffs[:3]}")
    e = esfera_h5.load_energy(a)
    err, ins = abs(e["total_error"][-1]), e["energy_inserted"][-1]
    print(f"box: {n_in} inserted (rate x time 150); same bits on 1, 2, 3 threads, the "
          f"general path, after a resume at 0.0151 s; total_error {err:.3g} J against "
          f"energy_inserted {ins:.4g} J (collisions, dt = 0.2 critical)")
    check(ins > 0 and err < 1e-2 * ins, f"box: the ledger: {err} J against {ins} J")


def check_fall(exe, tmp):
    """Free fall: the balance is the integrator's rounding only."""
    scene = write(tmp, "fall.yaml", FALL.replace("RATE", "rate: 5000"))
    out = os.path.join(tmp, "fall")
    r = run_ok(exe, "run", scene, "--out", out, "--quiet")
    n_in = int(summary(r.stdout).get("inserted", -1))
    check(abs(n_in - 100) <= 1, f"fall: {n_in} inserted, rate x time = 100")
    e = esfera_h5.load_energy(out)
    err = max(abs(v) for v in e["total_error"])
    ins = e["energy_inserted"][-1]
    check(ins > 0 and err < 1e-9 * ins,
          f"fall: |total_error| {err:.3g} J against energy_inserted {ins:.4g} J")
    print(f"fall: {n_in} inserted, max |total_error| {err:.3g} J, energy_inserted "
          f"{ins:.6g} J")
    # mass_rate: 0.1 kg/s for 0.02 s, radii 1-2 mm of glass
    scene = write(tmp, "mass.yaml", FALL.replace("RATE", "mass_rate: 0.1"))
    out = os.path.join(tmp, "mass")
    run_ok(exe, "run", scene, "--out", out, "--quiet")
    rad = np.asarray(last_frame(out)["radius"])
    m = sum(4 / 3 * math.pi * rad ** 3 * 2500)
    m_max = 4 / 3 * math.pi * 0.002 ** 3 * 2500
    check(0 <= 0.1 * 0.02 - m < m_max,
          f"mass_rate: {m:.6g} kg inserted, {0.1 * 0.02:.6g} kg due, one particle "
          f"{m_max:.3g} kg")
    print(f"mass_rate: {len(rad)} particles, {m:.6g} kg of {0.1 * 0.02:.6g} kg due "
          f"(largest particle {m_max:.3g} kg)")


def check_2d(exe, tmp):
    text = STATIC.replace("name: static", "name: disks\ndimension: 2") \
        .replace("[0.01, 0.01, 0.01]", "[0.01, 0, 0.01]") \
        .replace("rate: 200000", "rate: 2000")
    text = text[:text.index("  - {polygon")] + text[text.index("integrator:"):]
    scene = write(tmp, "disks.yaml", text)
    out = os.path.join(tmp, "disks")
    r = run_ok(exe, "run", scene, "--out", out, "--quiet")
    n_in = int(summary(r.stdout).get("inserted", -1))
    f = last_frame(out)
    x, rad = np.asarray(f["position"]), np.asarray(f["radius"])
    check(abs(n_in - 10) <= 1, f"2D: {n_in} inserted, rate x time = 10")
    check(not np.any(x[:, 1]), "2D: disks at y = 0")
    check(not overlaps(x, rad), "2D: overlapping disks")
    check(all(x[i, 2] - 0.004 >= rad[i] * (1 - 1e-12) for i in range(len(rad))),
          "2D: a disk overlaps the plane")
    print(f"2D: {n_in} disks inserted, none overlapping")


def check_refused(exe, tmp):
    scene = write(tmp, "box.yaml", BOX)
    for method in ("rk4", "verlet"):
        r = esfera(exe, "run", scene, "--out", os.path.join(tmp, "refused"), "--quiet",
                   "--overwrite", "--set", "integrator.method=" + method)
        check(r.returncode == 2 and "box.yaml:9:" in r.stderr and "leapfrog" in
              r.stderr, f"{method}: exit {r.returncode}: {r.stderr}")
    bad = BOX.replace("rate: 5000", "rate: 5000\n      mass_rate: 1")
    r = esfera(exe, "run", write(tmp, "bad.yaml", bad), "--out",
               os.path.join(tmp, "bad"), "--quiet")
    check(r.returncode == 2 and "bad.yaml:9:" in r.stderr and "mass_rate" in r.stderr,
          f"rate and mass_rate: exit {r.returncode}: {r.stderr}")
    gen = BOX.replace("integrator:", "generate: {box: {min: [0, 0, 0], max: [0.02, 0.02, "
                      "0.07]}, copies: [2, 1, 1], material: steel}\nintegrator:")
    r = esfera(exe, "generate", write(tmp, "gen.yaml", gen), "--out",
               os.path.join(tmp, "gen.csv"))
    check(r.returncode == 2 and "gen.yaml:9:" in r.stderr and "generate" in r.stderr,
          f"esfera generate: exit {r.returncode}: {r.stderr}")
    for what, old, new, where in (
            ("unknown key", "seed: 5", "sead: 5", "bad.yaml:14:7"),
            ("stop before start", "stop: 0.03", "stop: 0.03\n      start: 0.05",
             "bad.yaml:15:13"),
            ("region outside the domain", "max: [0.02, 0.02, 0.06]",
             "max: [0.02, 0.02, 0.09]", "bad.yaml:9:")):
        r = esfera(exe, "run", write(tmp, "bad.yaml", BOX.replace(old, new)), "--out",
                   os.path.join(tmp, "bad"), "--quiet")
        check(r.returncode == 2 and where in r.stderr,
              f"{what}: exit {r.returncode}, expected {where}: {r.stderr}")


def check_module(tmp):
    """The Python module (the library's handle): steps insert, the ODE view refuses."""
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
    sys.path.insert(0, os.path.join(root, "python"))
    try:
        import esfera
    except Exception as e:  # the library not found: say so, as a failure
        check(False, f"module: import esfera: {e}")
        return
    scene = write(tmp, "fall_mod.yaml", FALL.replace("RATE", "rate: 5000"))
    sim = esfera.Sim(scene)
    sim.step(1001)
    row = sim.energies
    check(row["energy_inserted"] > 0 and abs(row["total_error"]) < 1e-9 *
          row["energy_inserted"], f"module: ledger {row}")
    try:
        esfera.Sim(scene).y0()
        check(False, "module: the ODE view accepted an insert entry")
    except esfera.Error as e:
        check("fall_mod.yaml:" in str(e) and "fixed" in str(e), f"module: {e}")
    print(f"module: energy_inserted {row['energy_inserted']:.4g} J after 1001 steps; "
          "the ODE view refuses")


def main():
    exe = sys.argv[1]
    tmp = tempfile.mkdtemp(prefix="esf_insert_")
    try:
        check_static(exe, tmp)
        check_box(exe, tmp)
        check_fall(exe, tmp)
        check_2d(exe, tmp)
        check_refused(exe, tmp)
        check_module(tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return finish("insert")


if __name__ == "__main__":
    sys.exit(main())
