"""check_odd_runs.py -- runs at the edges of what a scene may ask (issue 27, no crash and
no hang on any input; run it in the sanitizer build too):
a particle that starts outside the domain with every integrator, ledger on (it is
removed before the balance starts: no heap overflow in the ODE methods' packing, no
energy from nothing in the leapfrog's ledger); adaptive ERK and CVODE runs with tiny
output, energy-row and checkpoint intervals (1e-300 s: a row or frame every step) end;
SIGTERM stops a long ODE run (erk: with a checkpoint; cvode-adams, which cannot write
one: without, exit 143 all the same); every particle leaving the domain with the ledger
on (and off) ends cleanly with 0 particles. Usage: check_odd_runs.py ESFERA"""
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

from pycheck import check, finish

TWO = """name: outside
domain: {min: [-1, -1, -1], max: [1, 1, 1]}
gravity: [0, 0, -9.81]
materials:
  glass: {density: 2500, kn: 1.0e5, restitution: 0.5, friction: 0.3}
particles:
  - {material: glass, radius: 0.005, position: [0, 0, 0.01], velocity: [0.1, 0, 0]}
  - {material: glass, radius: 0.005, position: [0, 0, 5]}
walls:
  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: glass}
run: {steps: 40}
output: {energy_every: 1.0e-5}
"""

ONE = """name: tiny
materials:
  glass: {density: 2500, kn: 1.0e5, restitution: 0.5, friction: 0.3}
particles:
  - {material: glass, radius: 0.005, position: [0, 0, 0.01]}
integrator: {method: "erk:ARKODE_DORMAND_PRINCE_7_4_5", rtol: 1.0e-6}
run: {steps: 20}
"""

ESCAPE = """name: escape
domain: {min: [-1, -1, -0.001], max: [1, 1, 1]}
materials:
  glass: {density: 2500, kn: 1.0e5, restitution: 0.5, friction: 0.3}
particles:
  - {material: glass, radius: 0.005, position: [0, 0, 0.01]}
  - {material: glass, radius: 0.005, position: [0.05, 0, 0.02], velocity: [0, 0, -1]}
  - {generate: lattice, region: {min: [0.2, -0.05, 0.05], max: [0.3, 0.05, 0.1]},
     radius: 0.005, material: glass}
run: {duration: 0.2}
output: {energy_every: 1.0e-3, every: 0.02}
"""


def scene(tmp, name, text):
    path = os.path.join(tmp, name)
    with open(path, "w") as fh:
        fh.write(text)
    return path


def run(exe, *args, timeout=60):
    try:
        return subprocess.run([exe, "run", *args, "--quiet"], capture_output=True,
                              text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None


def summary(r):
    line = [ln for ln in r.stdout.splitlines() if ln.startswith("summary:")]
    return dict(kv.split("=", 1) for kv in line[-1].split()[1:]) if line else {}


def outside(exe, tmp):
    """A particle that starts outside the domain, every integrator, ledger on."""
    path = scene(tmp, "two.yaml", TWO)
    for m in ["leapfrog", "verlet", "rk4", "erk:ARKODE_BOGACKI_SHAMPINE_4_2_3",
              "erk:ARKODE_DORMAND_PRINCE_7_4_5", "cvode-adams"]:
        sets = ["--set", f"integrator.method={m}"]
        if m == "erk:ARKODE_DORMAND_PRINCE_7_4_5":
            sets += ["--set", "integrator.rtol=1e-7"]
        out = os.path.join(tmp, "two_" + m.replace(":", "_"))
        r = run(exe, path, "--out", out, *sets)
        s = summary(r) if r else {}
        err = abs(float(s.get("energy_error", "nan")))
        lp = os.path.join(out, "log.txt")
        log = open(lp).read() if os.path.exists(lp) else ""
        ok = (r is not None and r.returncode == 0 and s.get("removed") == "1" and
              s.get("particles") == "1" and err < 1e-9 and
              "particle id 1 left the domain" in log)
        check(ok, f"{m}, a particle outside the domain at the start: "
              f"{r.returncode if r else 'timeout'} {r.stderr if r else ''} {s}")
        print(f"outside the domain at the start, {m}: exit {r.returncode if r else '-'}, "
              f"removed {s.get('removed')}, energy error {err:.3g} J")


def tiny_intervals(exe, tmp):
    """Adaptive runs with intervals far below the step end, with a row every step."""
    path = scene(tmp, "one.yaml", ONE)
    cases = [("no output section", []),
             ("cvode-adams", ["--set", "integrator.method=cvode-adams"]),
             ("output.every 1e-300", ["--set", "output.every=1e-300",
                                      "--set", "output.energy_every=0"]),
             ("checkpoint_every 1e-300", ["--checkpoint-every", "1e-300"]),
             ("fixed step, output.every 1e-300",
              ["--set", "integrator.rtol=0", "--set", "output.every=1e-300"])]
    for k, (what, extra) in enumerate(cases):
        out = os.path.join(tmp, f"tiny{k}")
        t0 = time.monotonic()
        r = run(exe, path, "--out", out, *extra, timeout=30)
        dt = time.monotonic() - t0
        s = summary(r) if r else {}
        check(r is not None and r.returncode == 0 and int(s.get("steps", 0)) > 0,
              f"{what}: {'did not end in 30 s' if r is None else r.returncode} "
              f"{r.stderr if r else ''}")
        rows = 0
        if r is not None and os.path.exists(os.path.join(out, "energy.csv")):
            rows = len(open(os.path.join(out, "energy.csv")).read().splitlines()) - 1
        print(f"{what}: {'timeout' if r is None else 'exit %d' % r.returncode} in "
              f"{dt:.2f} s, {s.get('steps')} steps, {rows} energy rows")
        if what == "no output section" and r is not None:
            check(rows == int(s.get("steps", -1)),
                  f"{what}: a row every step: {rows} rows, {s.get('steps')} steps")


def sigterm(exe, tmp):
    """SIGTERM in long ODE runs: erk stops with a checkpoint, cvode-adams without."""
    path = scene(tmp, "long.yaml", ONE.replace("run: {steps: 20}",
                                               "run: {duration: 1.0e6}\n"
                                               "output: {every: 0.1}"))
    for m, ck in [("erk:ARKODE_DORMAND_PRINCE_7_4_5", True), ("cvode-adams", False)]:
        out = os.path.join(tmp, "long_" + m.replace(":", "_"))
        p = subprocess.Popen([exe, "run", path, "--out", out, "--quiet", "--set",
                              f"integrator.method={m}"], stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)
        time.sleep(1.0)
        p.send_signal(signal.SIGTERM)
        try:
            _, err = p.communicate(timeout=10)
        except subprocess.TimeoutExpired:
            p.kill()
            _, err = p.communicate()
            check(False, f"{m}: SIGTERM not honoured within 10 s")
            continue
        has = os.path.exists(os.path.join(out, "checkpoint.esf"))
        words = ["resume with:"] if ck else ["cannot write checkpoints", out]
        check(p.returncode == 128 + signal.SIGTERM and has == ck and
              all(w in err for w in words),
              f"{m}: SIGTERM: exit {p.returncode}, checkpoint {has}, stderr {err!r}")
        print(f"SIGTERM, {m}: exit {p.returncode}, checkpoint {has}: "
              f"{err.strip().splitlines()[0] if err.strip() else ''}")


def escape(exe, tmp):
    """Every particle leaves the domain, ledger on and off (the fused step)."""
    path = scene(tmp, "escape.yaml", ESCAPE)
    for what, extra in [("ledger on", []),
                        ("ledger off", ["--set", "output.energy_every=0"]),
                        ("ledger on, 2 threads", ["--threads", "2"])]:
        out = os.path.join(tmp, "escape_" + what.replace(" ", "_").replace(",", ""))
        r = run(exe, path, "--out", out, *extra)
        s = summary(r) if r else {}
        ok = (r is not None and r.returncode == 0 and s.get("particles") is not None
              and int(s.get("removed", 0)) == 502)
        info = subprocess.run([exe, "info", os.path.join(out, "frames.h5")],
                              capture_output=True, text=True)
        ok = ok and info.returncode == 0 and "0 (last frame)" in info.stdout
        check(ok, f"every particle leaves, {what}: {r.returncode if r else 'timeout'} "
              f"{r.stderr if r else ''} {info.stdout} {info.stderr}")
        print(f"every particle leaves, {what}: exit {r.returncode if r else '-'}, "
              f"{s.get('removed')} removed, energy error {s.get('energy_error')}")


def main():
    exe = sys.argv[1]
    tmp = tempfile.mkdtemp(prefix="esf_odd_")
    try:
        outside(exe, tmp)
        tiny_intervals(exe, tmp)
        sigterm(exe, tmp)
        escape(exe, tmp)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return finish("odd_runs")


if __name__ == "__main__":
    sys.exit(main())
