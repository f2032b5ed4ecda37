"""ckpt_common.py -- what the checkpoint tests share: a small vibrated bed with friction,
global and local damping and an oscillating box (every kind of state a checkpoint must
carry), running esfera, and a bitwise comparison of two result directories."""
import os
import subprocess

import h5py

from pycheck import check

BED = """name: ckpt_bed
dimension: 3
gravity: [0, 0, -9.81]
domain: {min: [-0.01, -0.01, -0.02], max: [0.026, 0.0111, 0.12]}
materials:
  glass: {density: 2500, kn: 5.0e4, kt: 4.0e4, restitution: 0.7, friction: 0.3}
particles:
  - generate: random
    region: {min: [0, 0, 0.0005], max: [0.016, 0.0011, 0.03]}
    count: 160
    radius: {uniform_diameter: [0.0009, 0.0011]}
    material: glass
    seed: 3
walls:
  - box: {min: [0, 0, 0], max: [0.016, 0.0011, 0.1]}
    material: glass
    motion: {oscillate: {direction: [0, 0, 1], frequency: 25, acceleration: 6}}
integrator: {method: leapfrog, dt: auto, dt_rule: hart, frac: 0.2}
damping:
  global: {translation: 2.0, rotation: 1.0}
  local: {coefficient: 0.1, form: component}
run: {duration: 0.04}
output: {every: 0.002, energy_every: 1.0e-4}
"""

# spheres falling out of the domain: the particle count changes before and after the
# checkpoint (117 at it, 58 at the end)
DROP = """name: ckpt_drop
dimension: 3
gravity: [0, 0, -9.81]
domain: {min: [-0.1, -0.1, -0.002], max: [0.1, 0.1, 0.2]}
materials:
  glass: {density: 2500, kn: 5.0e4, kt: 4.0e4, restitution: 0.7, friction: 0.3}
particles:
  - generate: random
    region: {min: [0, 0, 0.0005], max: [0.016, 0.004, 0.03]}
    count: 120
    radius: {uniform_diameter: [0.0009, 0.0011]}
    material: glass
    seed: 4
integrator: {method: leapfrog, dt: auto, dt_rule: hart, frac: 0.2}
run: {duration: 0.06}
output: {every: 0.003, energy_every: 1.0e-4}
"""

# adaptive Dormand-Prince on the same bed (local damping off: its sign switches make
# the error controller crawl)
ERK = ["--set", "integrator.method=erk:ARKODE_DORMAND_PRINCE_7_4_5",
       "--set", "integrator.rtol=1e-5", "--set", "run.duration=0.006",
       "--set", "damping.local.coefficient=0", "--set", "output.every=0.0005"]

# the same run with Bogacki-Shampine 3(2) typed in as the scene's table (method erk)
BS_TABLE = ("integrator.table={c: [0, 1/2, 3/4, 1], A: [[], [1/2], [0, 3/4], "
            "[2/9, 1/3, 4/9]], b: [2/9, 1/3, 4/9, 0], b_embedded: [7/24, 1/4, 1/3, 1/8], "
            "order: 3, embedded_order: 2}")
ERK_TABLE = ["--set", "integrator.method=erk", "--set", BS_TABLE] + ERK[2:]


def write_scene(tmp, text=BED, name="bed.yaml"):
    path = os.path.join(tmp, name)
    with open(path, "w") as fh:
        fh.write(text)
    return path


def esfera(exe, *args, **kw):
    return subprocess.run([exe, *args], capture_output=True, text=True, **kw)


def run_ok(exe, *args):
    r = esfera(exe, *args)
    check(r.returncode == 0, f"esfera {' '.join(args)}: exit {r.returncode} {r.stderr}")
    return r


def _cmp_group(ga, gb, path, diffs):
    if sorted(ga.keys()) != sorted(gb.keys()):
        diffs.append(f"{path}: members differ")
        return 0
    n = 0
    for k in ga:
        if isinstance(ga[k], h5py.Group):
            n += _cmp_group(ga[k], gb[k], path + "/" + k, diffs)
        else:
            x, y = ga[k][()], gb[k][()]
            if x.shape != y.shape or x.dtype != y.dtype or x.tobytes() != y.tobytes():
                diffs.append(f"{path}/{k} differs")
            n += 1
    return n


def identical(a, b):
    """Compares result directories a and b: every frame (time attribute and every
    dataset, bit for bit), the /energy table and energy.csv byte for byte. Returns
    (number of frames, list of differences)."""
    diffs = []
    with h5py.File(os.path.join(a, "frames.h5"), "r") as fa, \
            h5py.File(os.path.join(b, "frames.h5"), "r") as fb:
        ka, kb = sorted(fa["frames"]), sorted(fb["frames"])
        if ka != kb:
            return len(ka), [f"frame lists differ: {len(ka)} and {len(kb)} frames"]
        for k in ka:
            if fa["frames"][k].attrs["time"] != fb["frames"][k].attrs["time"]:
                diffs.append(f"frame {k}: time differs")
            _cmp_group(fa["frames"][k], fb["frames"][k], k, diffs)
        if ("energy" in fa) != ("energy" in fb):
            diffs.append("/energy present in one only")
        elif "energy" in fa:
            _cmp_group(fa["energy"], fb["energy"], "energy", diffs)
    ea, eb = os.path.join(a, "energy.csv"), os.path.join(b, "energy.csv")
    if os.path.exists(ea) or os.path.exists(eb):
        with open(ea, "rb") as fa, open(eb, "rb") as fb:
            if fa.read() != fb.read():
                diffs.append("energy.csv differs")
    return len(ka), diffs
