"""check_restart.py -- restart identity (issue 5): N steps in one run against N/2, a
checkpoint, `esfera run --resume` and N/2 more, compared bit for bit (every frame
dataset, /energy, energy.csv), for the leapfrog with friction, global and local damping
and a moving wall (general path with the ledger, and the fused step without it,
checkpointed on two threads and resumed on one; and so with the Hertz-Mindlin law), for
adaptive Dormand-Prince (ARKODE, rtol 1e-5) and adaptive Bogacki-Shampine typed in as
the scene's Butcher table, for spheres
leaving the domain (the count changes either side of the checkpoint), for rolling and
twisting resistance (epsd: its spring torques ride in the checkpoint; general path with
the ledger, fused step on two threads resumed on one, adaptive Dormand-Prince with its
carried spins and plastic work; and with the Hertz-Mindlin law, fused with the ledger on
two threads resumed on one), and for bonded
blocks (the bond states ride in the checkpoint: bonds break on both sides); a run stopped
by SIGTERM resumes to the same output; esfera info on the checkpoint names the resume
command. Usage: check_restart.py ESFERA"""
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import h5py

from ckpt_common import DROP, ERK, ERK_TABLE, esfera, identical, run_ok, write_scene
from pycheck import check, finish


def halves(exe, tmp, scene, name, half, *extra):
    """Reference run with one checkpoint at the half; its copy resumed from there."""
    ref, res = os.path.join(tmp, name + "_ref"), os.path.join(tmp, name + "_res")
    run_ok(exe, "run", scene, "--out", ref, "--quiet", "--checkpoint-every", half, *extra)
    shutil.copytree(ref, res)
    r = run_ok(exe, "info", os.path.join(res, "checkpoint.esf"))
    check(f"resume: esfera run --resume {res}" in r.stdout, f"{name}: info: {r.stdout}")
    check("checkpoint_number: 1\n" in r.stdout, f"{name}: one checkpoint: {r.stdout}")
    step = [ln for ln in r.stdout.splitlines() if ln.startswith("step: ")]
    r = run_ok(exe, "run", "--resume", res, "--quiet")
    n, diffs = identical(ref, res)
    check(n > 5 and not diffs, f"{name}: resumed run differs: {diffs[:5]}")
    print(f"{name}: {n} frames identical after resuming at {step[0] if step else '?'}")
    return ref


def main():
    exe = sys.argv[1]
    os.environ["ESF_RANGE_WORK"] = "1"  # the fused step: one range per thread, small as
    # the scenes are, so that "checkpoint on 2 threads, resume on 1" crosses ranges
    tmp = tempfile.mkdtemp(prefix="esf_restart_")
    try:
        scene = write_scene(tmp)
        # 0.0201 s: one checkpoint, at step 16259 of 32355 (whole steps of dt)
        ref = halves(exe, tmp, scene, "leapfrog", "0.0201")
        # the leapfrog's checkpoints do not touch its state: same as a plain run
        plain = os.path.join(tmp, "plain")
        run_ok(exe, "run", scene, "--out", plain, "--quiet")
        n, diffs = identical(ref, plain)
        check(not diffs, f"leapfrog: a run with checkpoints differs from one without: "
              f"{diffs[:3]}")
        # the fused threaded step (no ledger): checkpoint on 2 threads, resume on 1
        halves(exe, tmp, scene, "leapfrog_fused", "0.0201", "--set",
               "output.energy_every=0", "--threads", "2")
        # the Hertz-Mindlin law (its tangential force record in the histories), with the
        # ledger (work_tangential_stiffness) on the general path, and on the fused step
        hz = ("--set", "materials.glass={density: 2500, youngs_modulus: 1.0e7, "
              "poisson_ratio: 0.3, restitution: 0.7, friction: 0.3}")
        halves(exe, tmp, scene, "hertz", "0.0201", *hz)
        halves(exe, tmp, scene, "hertz_fused", "0.0201", *hz, "--set",
               "output.energy_every=0", "--threads", "2")
        halves(exe, tmp, scene, "erk_dp5", "0.003", *ERK)
        halves(exe, tmp, scene, "erk_table", "0.003", *ERK_TABLE)
        roll = ["--set", "materials.glass.rolling_friction=0.2", "--set",
                "materials.glass.rolling_damping=0.3", "--set",
                "materials.glass.twisting_friction=0.05"]
        halves(exe, tmp, scene, "rolling", "0.0201", *roll)
        halves(exe, tmp, scene, "rolling_fused", "0.0201", *roll, "--set",
               "output.energy_every=0", "--threads", "2")
        halves(exe, tmp, scene, "rolling_erk_dp5", "0.003", *ERK, *roll)
        # both: the Hertz law's S_n in the rolling springs, fused on two threads with
        # the ledger, resumed on one
        halves(exe, tmp, scene, "hertz_rolling_fused", "0.0201", *hz, *roll, "--threads",
               "2")
        drop = halves(exe, tmp, write_scene(tmp, DROP, "drop.yaml"), "domain_exit", "0.031")
        with h5py.File(os.path.join(drop, "frames.h5"), "r") as f:
            n = [len(f["frames"][k]["id"]) for k in sorted(f["frames"])]
        check(n[0] == 120 and 60 < n[len(n) // 2] < 120 and n[-1] < 60,
              f"domain_exit: particle counts {n}")
        # bonds: the quick block impact, checkpointed while its bonds are breaking
        impact = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes",
                              "block_impact-quick.yaml")
        bonded = halves(exe, tmp, impact, "bonds", "0.009", "--set", "run.duration=0.018",
                        "--set", "output.every=0.003")
        broken = []  # (t, broken) per frame, from the log
        with open(os.path.join(bonded, "log.txt")) as fh:
            for ln in fh:
                if " bonds intact, " in ln and ln.startswith("frame t = "):
                    broken.append((float(ln.split()[3]), int(ln.split()[-2])))
        t_ck = round(0.009 / 6.43e-6) * 6.43e-6  # the checkpoint's step (the scene's dt)
        before = [b for t, b in broken if t <= t_ck]
        after = [b for t, b in broken if t > t_ck]
        check(len(broken) == 6 and before and before[-1] > 0 and after[-1] > after[0],
              f"bonds: none broken before the checkpoint, or after the frame after it: "
              f"{broken}")
        print(f"bonds: {before[-1] if before else '?'} broken before the checkpoint, "
              f"{after[0] if after else '?'} just after, {broken[-1][1]} at the end")

        # SIGTERM: finish the step, checkpoint, exit 128 + 15 with the resume command
        term = os.path.join(tmp, "term")
        p = subprocess.Popen([exe, "run", scene, "--out", term, "--quiet"],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        fr = os.path.join(term, "frames.xdmf")
        for _ in range(600):  # until the first frame is out (handlers are installed)
            if os.path.exists(fr):
                break
            time.sleep(0.01)
        time.sleep(0.05)  # (the whole run takes about 0.4 s on this machine's native
        p.send_signal(signal.SIGTERM)  # build since the moving walls' fast pass)
        out, errt = p.communicate(timeout=60)
        check(p.returncode == 128 + signal.SIGTERM, f"SIGTERM: exit {p.returncode} {errt}")
        check(f"esfera run --resume {term}" in errt, f"SIGTERM: message: {errt}")
        r = run_ok(exe, "run", "--resume", term, "--quiet")
        n, diffs = identical(plain, term)
        check(not diffs, f"SIGTERM + resume differs from the plain run: {diffs[:5]}")
        print(f"SIGTERM 0.05 s after the first frame, resumed: {n} frames identical; "
              f"{errt.strip()}")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return finish("restart")


if __name__ == "__main__":
    sys.exit(main())
