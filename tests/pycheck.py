"""pycheck.py -- the checks the Python tests share: count every check, remember the
failed ones, print "NAME: N checks, M failed" at the end (as the C tests' check.h)."""

failures = []
counted = [0]


def check(cond, msg):
    """Counts one check; prints and remembers msg when cond is false."""
    counted[0] += 1
    if not cond:
        failures.append(msg)
        print("FAIL:", msg)


def finish(name):
    """Prints the tally; returns the exit status (1 when any check failed)."""
    print(f"{name}: {counted[0]} checks, {len(failures)} failed")
    return 1 if failures else 0


def run_scene(esfera, tmp, text, *extra):
    """Writes the scene text into tmp, runs `esfera run` on it into tmp/out with
    --quiet and --overwrite (tmp/out is reused; and extra arguments); checks the exit
    status; returns the output dir."""
    import os
    import subprocess

    scene = os.path.join(tmp, "s.yaml")
    with open(scene, "w") as fh:
        fh.write(text)
    out = os.path.join(tmp, "out")
    r = subprocess.run([esfera, "run", scene, "--out", out, "--quiet", "--overwrite",
                        *extra],
                       capture_output=True, text=True)
    check(r.returncode == 0, f"run: exit {r.returncode} {r.stderr}")
    return out


def run_sets(esfera, scene, out, *sets, command="run"):
    """Runs `esfera COMMAND SCENE --out OUT` (with --quiet --overwrite for run: callers
    reuse OUT) with each of sets as a --set override; checks the exit status; returns
    the finished process (stdout holds the summary, or generate's stage lines)."""
    import subprocess

    args = [esfera, command, scene, "--out", out] + (
        ["--quiet", "--overwrite"] if command == "run" else [])
    for s in sets:
        args += ["--set", s]
    r = subprocess.run(args, capture_output=True, text=True)
    check(r.returncode == 0, f"{command} {sets}: exit {r.returncode} {r.stderr}")
    return r
