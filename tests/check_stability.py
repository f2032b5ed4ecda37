#!/usr/bin/env python3
"""check_stability.py ESFERA REPO_ROOT — the live stability check (docs/physics.md#live-
stability-check) on a settled pack (tests/pack300.csv: 300 spheres in a 60 mm box, settled
and kicked by the critical_dt study of 2026-11-25, studies/critical_dt_cases.py), kt = kn,
friction 0.5 and cohesion 1 N (the springs stick), restitution 1 and 0.1:

- `esfera modes` on its lowest 100 spheres: the Lanczos eigenvalue of dt^2 A + 2 dt B
  equals the dense one within 1e-5 and is not above it (a Ritz value);
- the live limit dt_L (the check's own, iterated to its fixed point) lies below half of
  Hart's rule (the rule is unsafe here); with restitution 0.1 below 0.6 of the undamped
  one (the dashpots' damping of the fast modes lowers it);
- at 1.05 dt_L the run stops with exit 1, naming the mode, with the ledger on and off,
  and its summary line says exit=1 with the largest lambda / 4 above 1;
  at 0.95 dt_L it ends with exit 0, its largest lambda / 4 below 1;
- the verdicts are right: with `stability: warn` the run at 1.05 dt_L multiplies its
  kinetic energy by more than 1e4 (measured 3e7 and 4e6), the run at 0.95 dt_L by less
  than 10 (measured 1.2 and 1.0);
- integrator.frac above 1 without allow_unstable is refused (exit 2, located);
- a particle that would travel more than half its radius in a step (500 m/s at dt 16 us,
  r 5 mm: 1.6 radii) stops the run (exit 1, naming it), at 150 m/s (0.49) it runs.
"""
import math
import os
import sys
import tempfile

import subprocess

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..",
                                "studies"))
from esfera_h5 import load_frames  # noqa: E402
from pycheck import check, finish  # noqa: E402

PACK = """name: pack
gravity: [0, 0, -9.81]
materials: {{g: {{density: 2500, kn: 1.0e5, kt: 1.0e5, restitution: {eta}, friction: 0.5,
             cohesion: 1.0}}}}
particles:
  - {{file: {csv}, material: g}}
walls:
  - {{box: {{min: [0, 0, 0], max: [0.06, 0.06, 0.107772]}}, open: [top], material: g}}
contact: {{allow_initial_overlap: true}}
integrator: {{dt: 1.0e-6, allow_unstable: true, stability: stop, stability_every: 500}}
run: {{steps: 4000}}
output: {{energy_every: 1.0e-4, every: 0}}
"""


class Run:
    def __init__(self, p):
        self.returncode, self.stdout, self.stderr = p.returncode, p.stdout, p.stderr
        self.summary = {}
        for ln in p.stdout.splitlines():
            if ln.startswith("summary:"):
                for w in ln.split()[1:]:
                    k, v = w.split("=", 1)
                    try:
                        self.summary[k] = float(v)
                    except ValueError:
                        pass


def run_sets(esfera, scene, out, *sets, command="run"):
    """esfera COMMAND SCENE [--out OUT --quiet --overwrite] --set ...: its exit status
    is for the caller to check."""
    args = [esfera, command, scene]
    if out:
        args += ["--out", out, "--quiet", "--overwrite"]
    for x in sets:
        args += ["--set", x]
    return Run(subprocess.run(args, capture_output=True, text=True))


def modes(esfera, scene):
    r = run_sets(esfera, scene, None, command="modes")
    line = [ln for ln in r.stdout.splitlines() if ln.startswith("modes:")]
    return {k: float(v) for k, v in (w.split("=") for w in line[0].split()[1:])} \
        if line else {}


def kinetic(out):
    rows = [ln.split(",") for ln in open(os.path.join(out, "energy.csv"))
            if not ln.startswith("#")]
    head = rows[0]
    a = np.array([[float(v) for v in r] for r in rows[1:]])
    return a[:, head.index("kinetic_translational")] + a[:, head.index("kinetic_rotational")]


def live_limit(esfera, scene, tmp, dt):
    """The live check's limit: the first check's "stable below dt = X" in log.txt,
    iterated from dt to its fixed point (as esf_stability_limit does)."""
    for _ in range(6):
        out = os.path.join(tmp, "probe")
        run_sets(esfera, scene, out, f"integrator.dt={dt!r}", "run.steps=1",
                 "integrator.stability=warn")
        with open(os.path.join(out, "log.txt")) as fh:
            line = [ln for ln in fh if ln.startswith("stability check at step 0")][0]
        new = float(line.split("stable below dt = ")[1].split()[0])
        if abs(new / dt - 1) < 1e-7:
            break
        dt = new
    return new


def one_pack(esfera, tmp, csv, eta, dt_ref=None):
    scene = os.path.join(tmp, f"pack_{eta:g}.yaml")
    with open(scene, "w") as fh:
        fh.write(PACK.format(eta=eta, csv=csv))
    dl = live_limit(esfera, scene, tmp, 1e-6)
    hart = 2 * math.sqrt(2500 * 4 / 3 * math.pi * 0.0045 ** 3 / 2e5)  # m_min: r 4.5 mm
    print(f"eta {eta:g}: live limit {dl:.6g} s")
    check(dl < 0.5 * hart, f"eta {eta:g}: the live limit {dl:.4g} s is below half "
          f"Hart's rule {hart:.4g} s")
    if dt_ref:
        check(dl < 0.6 * dt_ref, f"damping lowers the limit: {dl:.4g} < 0.6 x {dt_ref:.4g}")
    for led in ("1.0e-4", "0"):
        r = run_sets(esfera, scene, os.path.join(tmp, "above"),
                     f"integrator.dt={1.05 * dl!r}", f"output.energy_every={led}")
        check(r.returncode == 1 and "unstable at dt" in r.stderr and
              r.summary.get("exit") == 1 and r.summary.get("stability", 0) >= 1,
              f"eta {eta:g}, ledger every {led}: 1.05 x the limit stops (exit 1, and "
              f"the summary says so): exit {r.returncode} {r.summary.get('exit')} "
              f"{r.stderr.strip()[:160]}")
    growth = {}
    for f in (1.05, 0.95):
        out = os.path.join(tmp, f"warn{f}")
        r = run_sets(esfera, scene, out, f"integrator.dt={f * dl!r}",
                     "integrator.stability=warn", "run.steps=20000")
        ke = kinetic(out)
        growth[f] = float(ke.max() / ke[0]) if r.returncode == 0 else math.inf
        if f == 0.95:
            check(r.returncode == 0 and r.summary.get("stability", 9) < 1,
                  f"eta {eta:g}: 0.95 x the limit runs to the end: exit {r.returncode}, "
                  f"lambda/4 {r.summary.get('stability')} {r.stderr.strip()[:160]}")
    print(f"eta {eta:g}: kinetic energy growth {growth[1.05]:.3g} at 1.05 x the limit, "
          f"{growth[0.95]:.3g} at 0.95 x (stability: warn)")
    check(growth[1.05] > 1e4, f"eta {eta:g}: the run the check stops is unstable")
    check(growth[0.95] < 10, f"eta {eta:g}: the run it passes is stable")
    r = run_sets(esfera, scene, os.path.join(tmp, "below"), f"integrator.dt={0.95 * dl!r}")
    check(r.returncode == 0, f"eta {eta:g}: 0.95 x the limit, stability: stop: exit "
          f"{r.returncode} {r.stderr.strip()[:160]}")
    return dl


def dense_against_lanczos(esfera, tmp, csv, eta):
    """`esfera modes` on the pack's lowest 100 spheres: Lanczos against the dense
    eigenvalue of dt^2 A + 2 dt B."""
    rows = [ln for ln in open(csv)]
    body = sorted(rows[1:], key=lambda ln: float(ln.split(",")[2]))[:100]
    sub = os.path.join(tmp, "sub.csv")
    with open(sub, "w") as fh:
        fh.writelines([rows[0]] + body)
    scene = os.path.join(tmp, "sub.yaml")
    with open(scene, "w") as fh:
        fh.write(PACK.format(eta=eta, csv=sub).replace("dt: 1.0e-6", "dt: 1.0e-5"))
    m = modes(esfera, scene)
    check(m and abs(m["lambda_live"] / m["lambda"] - 1) < 1e-5 and
          m["lambda_live"] <= m["lambda"] * (1 + 1e-12),
          f"eta {eta:g}: Lanczos lambda {m.get('lambda_live')} against dense "
          f"{m.get('lambda')}")
    print(f"100 spheres, eta {eta:g}: lambda {m.get('lambda_live')} (Lanczos), "
          f"{m.get('lambda')} (dense); live limit {m.get('dt_live')} s")


def main():
    esfera, root = sys.argv[1], sys.argv[2]
    csv = os.path.join(root, "tests", "pack300.csv")
    with tempfile.TemporaryDirectory() as tmp:
        for eta in (1.0, 0.1):
            dense_against_lanczos(esfera, tmp, csv, eta)
        dl = one_pack(esfera, tmp, csv, 1.0)
        one_pack(esfera, tmp, csv, 0.1, dt_ref=dl)
        bad = os.path.join(tmp, "frac.yaml")
        with open(bad, "w") as fh:
            fh.write(PACK.format(eta=1.0, csv=csv).replace(
                "dt: 1.0e-6, allow_unstable: true,", "dt: auto, frac: 1.5,"))
        r = run_sets(esfera, bad, os.path.join(tmp, "frac"))
        check(r.returncode == 2 and "frac.yaml:" in r.stderr and "above 1" in r.stderr,
              f"frac 1.5 refused: exit {r.returncode} {r.stderr.strip()[:200]}")
        for speed, want in ((500.0, 1), (150.0, 0)):
            fast = os.path.join(tmp, "fast.yaml")
            with open(fast, "w") as fh:
                fh.write(FAST.format(v=speed))
            r = run_sets(esfera, fast, os.path.join(tmp, "fast"))
            check(r.returncode == want and (want == 0 or "particle id 0 moves" in r.stderr),
                  f"a particle at {speed} m/s: exit {r.returncode} (want {want}) "
                  f"{r.stderr.strip()[:200]}")
    return finish("check_stability")


FAST = """name: fast
gravity: [0, 0, 0]
materials: {{g: {{density: 2500, kn: 1.0e5, restitution: 0.5, friction: 0.3}}}}
particles:
  - {{material: g, radius: 0.005, position: [0, 0, 0], velocity: [{v}, 0, 0]}}
  - {{material: g, radius: 0.005, position: [0.5, 0, 0]}}
integrator: {{dt: auto, frac: 0.1}}
run: {{steps: 100}}
output: {{energy_every: 0}}
"""


if __name__ == "__main__":
    sys.exit(main())
