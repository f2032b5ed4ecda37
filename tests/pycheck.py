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
