"""check_shear_cell.py -- the Lees-Edwards shear cell (scenes/shear_cell-quick.yaml; issue
29): 108 frictional spheres at solid fraction 0.59 sheared at 20 /s to a strain of 2.
Checks: the mean flow velocity is linear in the gradient coordinate at the imposed rate
(least-squares slope over the frames past strain 2 within 10 % of the rate, and the
residual profile's rms, in bins of the height, below 0.1 of rate L); stress.csv has one
row every output.stress_every steps (rounded to whole steps) and one at the end with a positive pressure, the shear stress
opposing the flow (sxy < 0) and mu = -sxy / p past strain 2 between 0.2 and 0.6 (the
dense frictional range); stress.csv and the frames are the same bytes on 1 and 2
threads and on the general path; a run checkpointed at strain 5 and resumed gives the
same stress.csv; output.stress_every <= 0, or without output.stress, is refused with
its position (exit 2).
Usage: check_shear_cell.py ESFERA SCENES_DIR"""
import os
import shutil
import sys
import tempfile

import h5py
import numpy as np

from ckpt_common import esfera, identical, run_ok
from pycheck import check, finish

RATE = 20.0


def frames(out):
    with h5py.File(os.path.join(out, "frames.h5"), "r") as f:
        return [(f["frames"][k].attrs["time"], f["frames"][k]["position"][()],
                 f["frames"][k]["velocity"][()]) for k in sorted(f["frames"])]


def same(a, b, what):
    with open(os.path.join(a, "stress.csv"), "rb") as fa, \
            open(os.path.join(b, "stress.csv"), "rb") as fb:
        check(fa.read() == fb.read(), f"{what}: stress.csv differs")


def main():
    exe, scenes = sys.argv[1], sys.argv[2]
    tmp = tempfile.mkdtemp(prefix="esf_shear_")
    try:
        src = os.path.join(scenes, "shear_cell-quick.yaml")
        scene = os.path.join(tmp, "shear_cell-quick.yaml")
        shutil.copy(src, scene)
        shutil.copy(os.path.join(scenes, "shear_cell-quick.csv"), tmp)
        every = ["--set", "output.every=0.005"]
        o1, o2, og = (os.path.join(tmp, n) for n in ("t1", "t2", "gen"))
        r1 = run_ok(exe, "run", scene, "--out", o1, "--quiet", "--threads", "1", *every)
        run_ok(exe, "run", scene, "--out", o2, "--quiet", "--threads", "2", *every)
        run_ok(exe, "run", scene, "--out", og, "--quiet", "--threads", "1", *every,
               "--set", "integrator.fused=false")
        for o in (o2, og):
            nf, diffs = identical(o1, o)
            check(nf > 10 and not diffs, f"{o}: frames against 1 thread: {diffs[:3]}")
            same(o1, o, o)
        # the velocity profile
        fr = frames(o1)
        L = 0.0
        with open(src) as fh:
            for line in fh:
                if line.strip().startswith("max: ["):
                    L = float(line.split("[")[1].split(",")[0])
        ys, vs = [], []
        for t, x, v in fr:
            if t * RATE >= 2.0:
                ys.append(x[:, 1])
                vs.append(v[:, 0])
        y, vx = np.concatenate(ys), np.concatenate(vs)
        b, a = np.polyfit(y, vx, 1)
        edges = np.linspace(0, L, 7)
        idx = np.clip(np.digitize(y, edges) - 1, 0, 5)
        res = [vx[idx == k].mean() - (a + b * 0.5 * (edges[k] + edges[k + 1]))
               for k in range(6)]
        rms = float(np.sqrt(np.mean(np.square(res))) / (RATE * L))
        print(f"profile: slope {b:.4g} /s against the rate {RATE} ({b / RATE - 1:+.2%}), "
              f"binned residual rms {rms:.3g} rate L, {len(ys)} frames")
        check(abs(b / RATE - 1) < 0.10, f"slope {b:.4g} within 10 % of {RATE}")
        check(rms < 0.1, f"binned profile residual {rms:.3g} below 0.1 rate L")
        # stress.csv
        s = np.genfromtxt(os.path.join(o1, "stress.csv"), delimiter=",", names=True)
        summ = [ln for ln in r1.stdout.splitlines() if ln.startswith("summary:")][0].split()
        kv = dict(w.split("=", 1) for w in summ[1:])
        nsteps, dt = int(kv["steps"]), float(kv["dt"])
        ns = int(np.floor(0.005 / dt + 0.5))
        want = nsteps // ns + (nsteps % ns != 0)
        check(len(s) == want, f"{want} stress rows ({nsteps} steps, every {ns}), got {len(s)}")
        check(np.allclose(s["time"][:-1], dt * ns * np.arange(1, want)),
              "the rows' times are the multiples of the interval")
        check(np.all(s["p"] > 0), "positive pressure in every row")
        k = s["time"] * RATE >= 2.0
        mu = -s["sxy"][k].mean() / s["p"][k].mean()
        print(f"stress: p {s['p'][k].mean():.4g} Pa, mu {mu:.4f} past strain 2")
        check(np.all(s["sxy"][k] < 0), "the shear stress opposes the flow past strain 2")
        check(0.2 < mu < 0.6, f"mu {mu:.4f} in the dense frictional range (0.2, 0.6)")
        # checkpoint at strain 1, resumed
        ref, rsm = os.path.join(tmp, "ref"), os.path.join(tmp, "res")
        run_ok(exe, "run", scene, "--out", ref, "--quiet", "--threads", "2", *every,
               "--checkpoint-every", "0.25")
        shutil.copytree(ref, rsm)
        run_ok(exe, "run", "--resume", rsm, "--quiet", "--threads", "1")
        same(ref, rsm, "resumed")
        same(ref, o1, "checkpointed against plain")
        # bad input
        for val, want in (("0", "positive interval"), ("-1", "positive interval")):
            r = esfera(exe, "run", scene, "--out", os.path.join(tmp, "bad"), "--quiet",
                       "--set", f"output.stress_every={val}")
            check(r.returncode == 2 and want in r.stderr and "stress_every" in r.stderr,
                  f"stress_every {val}: exit {r.returncode} {r.stderr.strip()}")
        text = open(scene).read()
        cut = text[:text.index("  stress:\n")]
        bad = os.path.join(tmp, "nostress.yaml")
        with open(bad, "w") as fh:
            fh.write(cut)
        r = esfera(exe, "run", bad, "--out", os.path.join(tmp, "bad2"), "--quiet")
        check(r.returncode == 2 and "needs output.stress" in r.stderr
              and "nostress.yaml:" in r.stderr, f"no stress: {r.stderr.strip()}")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return finish("shear_cell")


if __name__ == "__main__":
    sys.exit(main())
