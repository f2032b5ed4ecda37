"""check_kill.py -- a run killed with SIGKILL at random moments, again and again, and
resumed each time (`esfera run --resume`), ends with output identical bit for bit to an
uninterrupted run (every frame dataset, /energy, energy.csv). Checkpoints come every
1 ms of simulated time (about every 50 ms of wall time); every other kill comes at a
random moment, the others as soon as a checkpoint.esf.tmp appears (a checkpoint being
written, synced or renamed), so kills land before, during and after checkpoint writes
and during the resumes' own rewriting of the frames index; after
every kill the checkpoint must still load (`esfera info` exits 0). Counts the kills
that found a checkpoint.esf.tmp (killed while writing one) or a frames.h5.tmp (killed
while the index frames.h5 was being rewritten, frames.h). Usage: check_kill.py ESFERA"""
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time

from ckpt_common import esfera, identical, run_ok, write_scene
from pycheck import check, finish

KILLS = 25


def main():
    exe = sys.argv[1]
    rng = random.Random(20261121)
    tmp = tempfile.mkdtemp(prefix="esf_kill_")
    try:
        scene = write_scene(tmp)
        ref = os.path.join(tmp, "ref")
        run_ok(exe, "run", scene, "--out", ref, "--quiet")
        out = os.path.join(tmp, "out")
        ck = os.path.join(out, "checkpoint.esf")
        cmd = [exe, "run", scene, "--out", out, "--quiet", "--checkpoint-every", "0.001"]
        kills = mid_ckpt = mid_index = resumes = 0
        done = False
        while not done:
            if os.path.exists(ck + ".tmp"):  # left by a kill: counts only fresh ones
                os.unlink(ck + ".tmp")
            p = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE,
                                 text=True)
            if kills < KILLS:
                if not os.path.exists(ck):  # the first run: wait for a checkpoint
                    while not os.path.exists(ck) and p.poll() is None:
                        time.sleep(0.005)
                if kills % 2:  # at a random moment
                    time.sleep(rng.uniform(0.0, 0.12))
                else:  # as soon as a checkpoint is being written (its .tmp exists)
                    t_end = time.monotonic() + 5
                    while (not os.path.exists(ck + ".tmp") and p.poll() is None
                           and time.monotonic() < t_end):
                        pass
                    time.sleep(rng.uniform(0.0, 0.0005))
                if p.poll() is None:
                    p.send_signal(signal.SIGKILL)
                    kills += 1
                    mid_ckpt += os.path.exists(ck + ".tmp")
                    mid_index += os.path.exists(os.path.join(out, "frames.h5.tmp"))
            _, err = p.communicate(timeout=120)
            if p.returncode == 0:
                done = True
            else:
                check(p.returncode == -signal.SIGKILL,
                      f"run {resumes}: exit {p.returncode}: {err}")
                if p.returncode != -signal.SIGKILL:
                    break
                r = esfera(exe, "info", ck)
                check(r.returncode == 0, f"after kill {kills}: checkpoint unreadable: "
                      f"{r.stderr}")
            cmd = [exe, "run", "--resume", out, "--quiet"]
            resumes += 1
        n, diffs = identical(ref, out)
        check(done and n > 5 and not diffs, f"after {kills} kills: output differs: "
              f"{diffs[:5]}")
        print(f"{kills} SIGKILLs ({mid_ckpt} while a checkpoint was being written, "
              f"{mid_index} while the index was being rewritten), {resumes - 1} resumes: "
              f"{n} frames identical to the uninterrupted run")
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    return finish("kill")


if __name__ == "__main__":
    sys.exit(main())
