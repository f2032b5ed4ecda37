"""check_wall_events.py -- wall motion in time through the esfera program (issue 29):
a silo whose gate (a named wall) is removed at t1 = 0.05 s while a side plate follows a
velocity table, in 3D and in 2D: a run checkpointed at 0.045 s and resumed gives every
frame and energy.csv bit for bit (the fused step checkpointed on 2 threads, resumed on
1); the frames' wall mesh loses the gate's triangles after t1 and the fill falls below
it; the log names the removal. Bad input (table times out of order, a stop before its
start, an unknown wall name, a wall removed twice, a table's row count, rotations
about two axes, a servo in a sequence, a servo wall removed, events under an ODE
method) exits 2 with
file:line:column. Usage: check_wall_events.py ESFERA"""
import os
import shutil
import sys
import tempfile

import h5py

from check_restart import halves
from ckpt_common import esfera, write_scene
from pycheck import check, finish

SILO = """name: silo
dimension: 3
gravity: [0, 0, -9.81]
materials: {g: {density: 2500, kn: 1.0e5, restitution: 0.5, friction: 0.3}}
particles:
  - generate: random
    region: {min: [0.0005, 0.0005, 0.0005], max: [0.0265, 0.0295, 0.06]}
    count: 60
    radius: 0.0025
    material: g
    seed: 5
walls:
  - {box: {min: [0, 0, 0], max: [0.03, 0.03, 0.1]}, open: [bottom, top], material: g}
  - {name: gate, polygon: [[0,0,0], [0.03,0,0], [0.03,0.03,0], [0,0.03,0]],
     material: g}
  - polygon: [[0.027,0,0.005], [0.027,0.03,0.005], [0.027,0.03,0.03], [0.027,0,0.03]]
    material: g
    motion: {table: {time: [0, 0.03, 0.06], velocity: [[-0.05, 0, 0], [0.05, 0, 0],
                                                        [0, 0, 0]]}}
events: [{at: 0.05, remove_wall: gate}]
damping: {global: {translation: 2.0}}
integrator: {method: leapfrog, dt: auto, frac: 0.2}
run: {duration: 0.08}
output: {every: 0.005, energy_every: 1.0e-4}
"""

SILO_2D = (SILO.replace("dimension: 3", "dimension: 2\ndisk_thickness: 0.005")
           .replace("[0.0265, 0.0295, 0.06]", "[0.0265, 0, 0.06]")
           .replace("min: [0.0005, 0.0005, 0.0005]", "min: [0.0005, 0, 0.0005]")
           .replace("count: 60", "count: 30"))


def gate_opened(out, t1):
    """The wall mesh's triangle count before and after t1, the lowest centre after."""
    before, after, zmin = set(), set(), 1.0
    with h5py.File(os.path.join(out, "frames.h5"), "r") as f:
        for k in sorted(f["frames"]):
            fr = f["frames"][k]
            t = fr.attrs["time"]
            tri = [v for v in fr.keys() if "wall" in v]
            ntri = sum(fr[v]["triangles"].shape[0] for v in tri
                       if isinstance(fr[v], h5py.Group) and "triangles" in fr[v])
            (after if t > t1 else before).add(ntri)
            if t > t1 + 0.02:
                zmin = min(zmin, float(fr["position"][:, 2].min()))
    return before, after, zmin


def resume_case(exe, tmp, text, name):
    scene = write_scene(tmp, text, name + ".yaml")
    ref = halves(exe, tmp, scene, name, "0.045")
    fused = halves(exe, tmp, scene, name + "_fused2", "0.045", "--threads", "2")
    check(os.path.isdir(fused), f"{name}: fused run on 2 threads")
    with open(os.path.join(ref, "log.txt")) as fh:
        log = fh.read()
    check("removed wall 'gate'" in log, f"{name}: the log names the removal")
    return ref


def bad(exe, tmp, name, text, pattern):
    path = write_scene(tmp, text, name + ".yaml")
    r = esfera(exe, "run", path, "--out", os.path.join(tmp, "bad_" + name), "--quiet")
    ok = r.returncode == 2 and pattern in r.stderr and f"{name}.yaml:" in r.stderr
    check(ok, f"{name}: exit {r.returncode}, want 2 with '{pattern}' at file:line:col; "
          f"stderr: {r.stderr.strip()}")


def main():
    exe = sys.argv[1]
    os.environ["ESF_RANGE_WORK"] = "1"
    tmp = tempfile.mkdtemp(prefix="esf_wall_events_")
    try:
        for text, name in ((SILO, "silo"), (SILO_2D, "silo2d")):
            ref = resume_case(exe, tmp, text, name)
            before, after, zmin = gate_opened(ref, 0.05)
            print(f"{name}: wall triangles {sorted(before)} before t1, {sorted(after)} "
                  f"after; lowest centre {zmin:.4f} m 0.02 s after t1")
            check(len(before) == 1 and len(after) == 1 and
                  min(before) - min(after) == 2,
                  f"{name}: the gate's two triangles leave the wall mesh at t1")
            check(zmin < -0.003, f"{name}: the fill falls through the opened gate")
        bad(exe, tmp, "unsorted", SILO.replace("time: [0, 0.03, 0.06]",
                                               "time: [0, 0.06, 0.03]"),
            "table times must increase")
        bad(exe, tmp, "rows", SILO.replace("time: [0, 0.03, 0.06]", "time: [0, 0.03]"),
            "3 rows for 2 times")
        bad(exe, tmp, "stop", SILO.replace(
            "time: [0, 0.03, 0.06]", "start: 0.02, stop: 0.01, time: [0, 0.03, 0.06]"),
            "must come after start")
        bad(exe, tmp, "unknown", SILO.replace("remove_wall: gate", "remove_wall: gat"),
            "no wall is named 'gat'")
        bad(exe, tmp, "twice", SILO.replace(
            "events: [{at: 0.05, remove_wall: gate}]",
            "events: [{at: 0.05, remove_wall: gate}, {at: 0.06, remove_wall: gate}]"),
            "removed twice in a row")
        motion = SILO[SILO.index("    motion: {table:"):SILO.index("events:")]
        bad(exe, tmp, "axes", SILO.replace(motion, (
            "    motion: [{rotate: {axis: [0, 0, 1], omega: 1}},\n"
            "             {rotate: {axis: [1, 0, 0], omega: 1}}]\n")), "share one axis")
        bad(exe, tmp, "servo", SILO.replace(motion, (
            "    motion: [{servo: {stress: 1, direction: [1, 0, 0], max_speed: 1}},\n"
            "             {translate: {velocity: [0, 0, 1]}}]\n")),
            "cannot be part of a sequence")
        bad(exe, tmp, "servo_gate", SILO.replace("{name: gate, polygon:", (
            "{name: gate, motion: {servo: {stress: 1, direction: [0, 0, 1], "
            "max_speed: 1, area: 0.01}}, polygon:")), "cannot be removed or added")
        bad(exe, tmp, "ode", SILO.replace("method: leapfrog", "method: erk:rk4"),
            "supported by the leapfrog only")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return finish("wall_events")


if __name__ == "__main__":
    sys.exit(main())
