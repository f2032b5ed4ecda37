#!/usr/bin/python3
"""MPI runs give the one-process results bit for bit (docs/mpi.md, issue 31).

usage: check_mpi.py ESFERA_MPI SCENES_DIR [PLAIN_ESFERA]  (or $ESFERA_PLAIN)

Each case runs a scene without mpirun (one process: the plain code path, s->par NULL)
and on 2 and 3 MPI processes (oversubscribed on a small machine), and compares
energy.csv byte for byte and every dataset and attribute of frames.h5 with memcmp
semantics (bytes, shape, type). With PLAIN_ESFERA (the README's build, no MPI) its run
is the reference instead. Then what MPI runs refuse gives exit status 2 with the key's
place. Cases are small: a few thousand steps each.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile

import h5py
import numpy as np

ESF, SCENES = sys.argv[1], sys.argv[2]
PLAIN = sys.argv[3] if len(sys.argv) > 3 else os.environ.get("ESFERA_PLAIN") or None
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
           OMPI_MCA_rmaps_base_oversubscribe="1", OMP_NUM_THREADS="1")
checks = failed = 0


def check(ok, what):
    global checks, failed
    checks += 1
    if not ok:
        failed += 1
        print("FAILED:", what)


def walk(path):
    out = {}

    def visit(prefix, obj):
        for k, v in obj.attrs.items():
            out[prefix + "@" + k] = np.asarray(v)
        if isinstance(obj, h5py.Dataset):
            out[prefix] = np.asarray(obj[()])
            return
        for k in obj.keys():
            visit(prefix + "/" + k, obj[k])

    with h5py.File(path, "r") as f:
        visit("", f)
    return out


def same_frames(a, b):
    x, y = walk(a), walk(b)
    if set(x) != set(y):
        return "datasets differ: %s" % sorted(set(x) ^ set(y))[:4]
    for k in sorted(x):
        u, v = x[k], y[k]
        if u.dtype == object or v.dtype == object:
            if u.tolist() != v.tolist():
                return k
        elif u.shape != v.shape or u.dtype != v.dtype or u.tobytes() != v.tobytes():
            return k
    return None


def run(ranks, scene, out, sets, exe=None):
    cmd = [exe or ESF, "run", scene, "--out", out, "--overwrite", "--quiet",
           "--threads", "1"]
    for s in sets:
        cmd += ["--set", s]
    if ranks:
        cmd = ["mpirun", "--oversubscribe", "-np", str(ranks)] + cmd
    return subprocess.run(cmd, env=ENV, capture_output=True, text=True, timeout=900)


def case(tmp, name, scene, sets, ranks=(2, 3), want_migrations=0):
    scene = os.path.join(SCENES, scene) if not os.path.isabs(scene) else scene
    ref = os.path.join(tmp, name + "-1")
    r = run(0, scene, ref, sets, PLAIN)
    check(r.returncode == 0, "%s: one process: %s" % (name, r.stderr[-400:]))
    if r.returncode:
        return
    m = re.search(r"steps=(\d+) particles=(\d+) contacts_mean=([0-9.]+)", r.stdout)
    print("%s: %s steps, %s particles, %s contacts on average" % ((name,) + m.groups()))
    for k in ranks:
        out = os.path.join(tmp, "%s-%d" % (name, k))
        r = run(k, scene, out, sets)
        check(r.returncode == 0, "%s: %d ranks: %s" % (name, k, r.stderr[-600:]))
        if r.returncode:
            continue
        check("ranks=%d" % k in r.stdout, "%s: the summary says ranks=%d" % (name, k))
        e1, ek = (os.path.join(d, "energy.csv") for d in (ref, out))
        if os.path.exists(e1):
            check(open(e1, "rb").read() == open(ek, "rb").read(),
                  "%s: %d ranks: energy.csv differs" % (name, k))
        d = same_frames(os.path.join(ref, "frames.h5"), os.path.join(out, "frames.h5"))
        check(d is None, "%s: %d ranks: frames.h5 differs at %s" % (name, k, d))
        log = open(os.path.join(out, "log.txt")).read()
        mig = re.search(r"mpi: .* (\d+) particles migrated", log)
        check(mig is not None, "%s: %d ranks: the log's mpi line" % (name, k))
        if mig:
            print("  %d ranks: same bits; %s particles migrated" % (k, mig.group(1)))
            check(int(mig.group(1)) >= want_migrations,
                  "%s: %d ranks: %s migrations, expected at least %d" %
                  (name, k, mig.group(1), want_migrations))


def resume(ranks, out, exe=None):
    cmd = [exe or ESF, "run", "--resume", out, "--quiet", "--threads", "1"]
    if ranks:
        cmd = ["mpirun", "--oversubscribe", "-np", str(ranks)] + cmd
    return subprocess.run(cmd, env=ENV, capture_output=True, text=True, timeout=900)


def checkpoints(tmp):
    """A checkpoint written by 2 processes is the one process's, byte for byte; resumed
    on 3 processes and on one, the run ends as the uninterrupted one."""
    scene = os.path.join(SCENES, "settle.yaml")
    sets = ["run.duration=0.06", "output.every=0.02", "output.energy_every=5e-4",
            "output.checkpoint_every=0.02"]
    ref, two = os.path.join(tmp, "ck-1"), os.path.join(tmp, "ck-2")
    r1, r2 = run(0, scene, ref, sets, PLAIN), run(2, scene, two, sets)
    check(r1.returncode == 0 and r2.returncode == 0, "checkpoints: the runs: %s %s" %
          (r1.stderr[-300:], r2.stderr[-300:]))
    if r1.returncode or r2.returncode:
        return
    ck = [open(os.path.join(d, "checkpoint.esf"), "rb").read() for d in (ref, two)]
    check(ck[0] == ck[1], "checkpoints: 2 processes wrote another checkpoint")
    for k, exe in ((3, None), (0, PLAIN)):
        d = os.path.join(tmp, "ck-resumed-%d" % k)
        shutil.copytree(two, d)
        r = resume(k, d, exe)
        check(r.returncode == 0 and "resumed at step" in r.stdout,
              "checkpoints: resumed on %d: %s" % (k, r.stderr[-300:]))
        if r.returncode:
            continue
        same_e = open(os.path.join(ref, "energy.csv"), "rb").read() == \
            open(os.path.join(d, "energy.csv"), "rb").read()
        check(same_e, "checkpoints: resumed on %d: energy.csv differs" % k)
        f = same_frames(os.path.join(ref, "frames.h5"), os.path.join(d, "frames.h5"))
        check(f is None, "checkpoints: resumed on %d: frames.h5 differs at %s" % (k, f))
        where = "%d processes" % k if k else \
            "one process (%s)" % ("the plain build" if PLAIN else "the MPI build")
        print("checkpoint of 2 processes resumed on %s: the uninterrupted run's bits" %
              where)


def refused(tmp, name, scene, sets, key):
    scene = os.path.join(SCENES, scene)
    r = run(2, scene, os.path.join(tmp, name), sets)
    print("%s: %s" % (name, r.stderr.strip().splitlines()[0] if r.stderr.strip() else ""))
    check(r.returncode == 2 and key in r.stderr and "MPI" in r.stderr,
          "%s: refused with exit 2 naming %s: %d %s" % (name, key, r.returncode,
                                                        r.stderr[-300:]))


def main():
    tmp = tempfile.mkdtemp(prefix="esfera-mpi-")
    try:
        # S1's bed: friction, the energy ledger every 50 steps, a box, gravity
        case(tmp, "settle", "settle.yaml",
             ["run.duration=0.1", "output.every=0.025", "output.energy_every=5e-4"])
        # adaptive global damping (its rate from the kinetic energies' exact sums)
        case(tmp, "settle_adaptive", "settle.yaml",
             ["run.duration=0.05", "output.every=0.025", "output.energy_every=5e-4",
              "damping.global.translation=5", "damping.global.auto=true"], ranks=(2,))
        # moving walls (a vibrated box) and a moving mesh (a screw)
        case(tmp, "vibrated_bed", "vibrated_bed-quick.yaml", ["run.duration=0.05"])
        # (strong gravity: the columns reach the screw within the case's 0.1 s)
        case(tmp, "helical_screw", "helical_screw-quick.yaml",
             ["run.duration=0.1", "gravity=[0,0,-150]"])
        # servo walls, the fluid force with its porosity grid, an event deleting grains
        case(tmp, "sand_production", "sand_production-quick.yaml",
             ["run.duration=0.03", "events.0.at=0.01", "fluid.start=0.02",
              "output.every=0.005"])
        # bonds (the adhesive law): a bonded block hit by a ball, bonds breaking
        case(tmp, "block_impact", "block_impact-quick.yaml",
             ["run.duration=0.02", "output.every=0.005"])
        # particles crossing the processes' slabs many times: a gas in a long box
        case(tmp, "gas", os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                      "mpi_gas.yaml"), [],
             want_migrations=2000)
        # periodic boundaries across the processes (the slabs' axis periodic), then
        # Lees-Edwards shear with its flow along the slabs
        here = os.path.dirname(os.path.abspath(__file__))
        case(tmp, "periodic", os.path.join(here, "mpi_periodic.yaml"), [],
             want_migrations=2000)
        case(tmp, "lees_edwards", os.path.join(here, "mpi_periodic.yaml"),
             ["domain.shear={rate: 50, flow: x, gradient: y}", "output.energy_every=0"])
        checkpoints(tmp)
        # what MPI runs do not support yet: refused, with the key's place
        refused(tmp, "silo-insertion", "silo-quick.yaml", [], "silo-quick.yaml:")
        refused(tmp, "settle-rk4", "settle.yaml", ["integrator.method=rk4"],
                "integrator.method")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print("mpi: %d checks, %d failed" % (checks, failed))
    sys.exit(1 if failed else 0)


main()
