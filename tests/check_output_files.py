"""check_output_files.py -- a run's output is crash-consistent and says what it is
(issue 27, item 7): log.txt reaches the disk line by line (a SIGKILL a few seconds in
leaves its set-up lines, whole); energy.csv holds whole rows only after SIGKILLs at
random moments; Ctrl-C on a terminal (a pty) prints its message on a line of its own
with the program's real path in the resume hint; a resumed run's summary counts the
checkpoints since the run's start (resumed_from_step= and a line saying what wall_s and
the rate cover, the rate being that invocation's own) and the progress ETA after a
resume follows the recent rate; every finished run ends with an `output:` line naming
its folder, `esfera info` and the XDMF file. Usage: check_output_files.py ESFERA"""
import os
import pty
import random
import re
import select
import shutil
import signal
import subprocess
import sys
import tempfile
import time

from ckpt_common import write_scene
from pycheck import check, finish


def summary(stdout):
    line = [ln for ln in stdout.splitlines() if ln.startswith("summary:")]
    return dict(kv.split("=", 1) for kv in line[-1].split()[1:]) if line else {}


def kill_log(exe, tmp, scene):
    """SIGKILL 3.5 s into a run: log.txt has its set-up lines, each one whole."""
    out = os.path.join(tmp, "killed_log")
    p = subprocess.Popen([exe, "run", scene, "--out", out, "--quiet", "--threads", "1",
                          "--set", "run.duration=100"], stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL)
    time.sleep(3.5)
    p.send_signal(signal.SIGKILL)
    p.wait()
    log = open(os.path.join(out, "log.txt"), "rb").read()
    check(len(log) > 0 and log.endswith(b"\n") and b"\nrun: " in log,
          f"log.txt after SIGKILL at 3.5 s: {len(log)} bytes, ends {log[-40:]!r}")
    nl = log.count(b"\n")
    print(f"SIGKILL at 3.5 s: log.txt {len(log)} bytes, {nl} whole lines")


def kill_rows(exe, tmp, scene, rng):
    """SIGKILL at random moments: energy.csv ends with a whole row, all rows whole."""
    bad = 0
    for k in range(6):
        out = os.path.join(tmp, f"killed_rows{k}")
        p = subprocess.Popen([exe, "run", scene, "--out", out, "--quiet", "--threads", "1",
                              "--set", "run.duration=100", "--set",
                              "output.energy_every=2e-5"], stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL)
        time.sleep(rng.uniform(0.6, 1.6))
        p.send_signal(signal.SIGKILL)
        p.wait()
        data = open(os.path.join(out, "energy.csv"), "rb").read()
        lines = data.split(b"\n")
        whole = data.endswith(b"\n") and all(ln.count(b",") == 23 for ln in lines[:-1])
        bad += not whole
        print(f"SIGKILL {k}: energy.csv {len(data)} bytes, {len(lines) - 1} lines, "
              f"{'whole rows' if whole else 'a row cut: ' + repr(lines[-1][-30:])}")
    check(bad == 0, f"energy.csv: {bad} of 6 kills left a part of a row")


def on_pty(args, after, sig):
    """Runs args with stdout and stderr on a pseudo-terminal, sends sig after `after`
    seconds, returns (exit status, everything written)."""
    master, slave = pty.openpty()
    p = subprocess.Popen(args, stdout=slave, stderr=slave, stdin=subprocess.DEVNULL)
    os.close(slave)
    buf, t0, sent = b"", time.monotonic(), False
    while True:
        if not sent and time.monotonic() - t0 >= after:
            p.send_signal(sig)
            sent = True
        r, _, _ = select.select([master], [], [], 0.05)
        if r:
            try:
                chunk = os.read(master, 65536)
            except OSError:
                chunk = b""
            if not chunk:
                break
            buf += chunk
        elif p.poll() is not None and sent:
            # drain what is left
            try:
                while True:
                    chunk = os.read(master, 65536)
                    if not chunk:
                        break
                    buf += chunk
            except OSError:
                pass
            break
    os.close(master)
    return p.wait(), buf


def ctrl_c(exe, tmp, scene):
    """Ctrl-C on a terminal: the message on its own line, the real program path."""
    out = os.path.join(tmp, "ctrl_c")
    rc, buf = on_pty([exe, "run", scene, "--out", out, "--threads", "1", "--set",
                      "run.duration=100", "--checkpoint-every", "1"], 2.0, signal.SIGINT)
    at = buf.find(b"esfera: stopped by signal 2")
    before = buf[max(0, at - 8):at]
    own_line = at >= 0 and (at == 0 or before.endswith(b"\n") or
                            before.endswith(b"\r\x1b[K"))
    check(rc == 130 and own_line, f"Ctrl-C: exit {rc}, message not on its own line: "
          f"{buf[max(0, at - 120):at + 60]!r}")
    m = re.search(rb"resume with: (\S+) run --resume (\S+)", buf)
    prog = m.group(1).decode() if m else ""
    check(m is not None and os.path.isabs(prog) and os.path.samefile(prog, exe),
          f"Ctrl-C: resume hint names {prog!r}, not the program {exe}")
    print(f"Ctrl-C: exit {rc}, the message after {before!r}, resume with {prog}")


def resumed(exe, tmp, scene):
    """A resumed run's summary: checkpoints since the start, its own rate; the ETA of
    its progress follows the recent rate; an output: line at the end."""
    ref = os.path.join(tmp, "resumed_ref")
    args = ["--quiet", "--threads", "1", "--set", "output.energy_every=0"]
    r = subprocess.run([exe, "run", scene, "--out", ref, *args, "--checkpoint-every",
                        "0.01"], capture_output=True, text=True)
    last = r.stdout.strip().splitlines()[-1] if r.stdout.strip() else ""
    check(r.returncode == 0 and last.startswith(f"output: {ref} (") and
          "frames.xdmf" in last and " info " in last,
          f"a finished run ends with its output line: {last!r}")
    print(f"last line: {last}")
    res = os.path.join(tmp, "resumed")
    shutil.copytree(ref, res)
    r = subprocess.run([exe, "run", "--resume", res, "--quiet", "--threads", "1"],
                       capture_output=True, text=True)
    s = summary(r.stdout)
    info = subprocess.run([exe, "info", os.path.join(ref, "checkpoint.esf")],
                          capture_output=True, text=True).stdout
    count = re.search(r"checkpoint_number: (\d+)", info)
    step = re.search(r"^step: (\d+)", info, re.M)
    ok = (r.returncode == 0 and count and step and s.get("checkpoints") == count.group(1)
          and s.get("resumed_from_step") == step.group(1) and
          f"resumed at step {step.group(1)}" in r.stdout)
    check(ok, f"resumed summary: {r.returncode} {s} {r.stdout[-300:]} {r.stderr}")
    if ok:
        done = int(s["steps"]) - int(step.group(1))
        rate = float(s["particle_steps_per_s"]) * float(s["wall_s"])
        check(abs(rate - 160 * done) <= 0.01 * 160 * done + 1,
              f"resumed rate x wall_s = {rate:.6g}, its own particle-steps {160 * done}")
        print(f"resumed at step {step.group(1)}: checkpoints={s['checkpoints']}, "
              f"rate x wall = {rate:.6g} for {done} steps of 160 particles")
    # the ETA after a resume past half of a longer run: from the recent rate, not the
    # time since the resume against the whole run's fraction (the resumed part long
    # enough, a few seconds, for whole-second ETAs)
    long = os.path.join(tmp, "eta")
    r = subprocess.run([exe, "run", scene, "--out", long, *args, "--set",
                        "run.duration=1.0", "--checkpoint-every", "0.55"],
                       capture_output=True, text=True)
    t0 = time.monotonic()
    rc, buf = on_pty([exe, "run", "--resume", long, "--threads", "1"], 1e9, signal.SIGINT)
    took = time.monotonic() - t0
    etas = [float(x) for x in re.findall(rb"ETA (\d+) s", buf)]
    first = etas[0] if etas else -1
    check(r.returncode == 0 and rc == 0 and first >= 0.3 * (took - 0.5),
          f"ETA after a resume at 0.55 of 1: first {first} s, the rest took {took:.1f} s "
          f"({etas[:5]})")
    print(f"ETA after a resume at 0.55 of 1: first {first:.0f} s, the rest took "
          f"{took:.1f} s")


def main():
    exe = os.path.abspath(sys.argv[1])
    rng = random.Random(27)
    tmp = tempfile.mkdtemp(prefix="esf_outfiles_")
    try:
        scene = write_scene(tmp)
        kill_log(exe, tmp, scene)
        kill_rows(exe, tmp, scene, rng)
        ctrl_c(exe, tmp, scene)
        resumed(exe, tmp, scene)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return finish("output_files")


if __name__ == "__main__":
    sys.exit(main())
