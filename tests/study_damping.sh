#!/bin/bash
# study_damping.sh ESFERA REPO_ROOT — runs studies/damping.py --quick into a temporary
# directory and checks that its outputs exist and make sense:
#  - every CSV, PNG and report.md is written;
#  - impact restitution within 2% of the cut-oscillator closed form for eta 0.1-0.9
#    at the finest time step of the quick run;
#  - the resting sphere's log decrement: global damping within 1% of
#    2 pi zeta / sqrt(1 - zeta^2) with zeta = alpha / (2 omega), local damping (both
#    forms) within 2% of ln((1 + c)/(1 - c)), the contact dashpot within 2% for
#    eta >= 0.5;
#  - Rayleigh damping of the contact mode within 3% of zeta_R (f_R/f + f/f_R);
#  - load step: local damping (component 0.7) converges in fewer steps than no damping;
#  - bouncing sphere under local damping 0.7: first apex within 10% of ((1-c)/(1+c))^2;
#  - the chain pulse under local damping 0.7 arrives weaker than undamped;
#  - the vibrated bed under local damping 0.7 flies lower than the seed bed (or, with an
#    esfera without moving walls, the report says the bed is not available).
# Exit 77 (skipped) when Debian's python3 lacks numpy, matplotlib or h5py.
set -u
esfera=$(readlink -f "$1")
root=$(readlink -f "$2")
py=/usr/bin/python3
if ! $py -c 'import numpy, matplotlib, h5py' 2>/dev/null; then
  echo "study_damping: $py lacks numpy/matplotlib/h5py; skipped"
  exit 77
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
start=$(date +%s)
if ! $py "$root/studies/damping.py" --quick --out "$out" --esfera "$esfera"; then
  echo "FAIL: studies/damping.py --quick exited with an error"
  exit 1
fi
echo "quick study: $(( $(date +%s) - start )) s"
fail=0
for f in report.md restitution.csv decay.csv rayleigh.csv settling_pour.csv \
         settling_load.csv bounce.csv chain.csv restitution_decay.png decay_series.png \
         rayleigh.png settling.png dynamics.png; do
  if [ ! -s "$out/$f" ]; then
    echo "FAIL: $f missing or empty"
    fail=1
  fi
done
[ $fail = 0 ] || exit 1

$py - "$out" <<'EOF'
import csv, math, os, sys

out = sys.argv[1]
bad = []


def rows(name):
    with open(os.path.join(out, name)) as fh:
        return list(csv.DictReader(fh))


def num(x):
    return float(x) if x not in ("", None) else float("nan")


def check(ok, msg):
    print(("ok   " if ok else "FAIL ") + msg)
    if not ok:
        bad.append(msg)


rest = rows("restitution.csv")
fmin = min(num(r["frac"]) for r in rest)
mod = [r for r in rest if num(r["frac"]) == fmin and 0.1 <= num(r["eta_requested"]) <= 0.9]
worst = max(abs(num(r["rel_error"])) for r in mod)
check(len(mod) >= 6 and worst < 0.02,
      f"restitution within 2% of the closed form for eta 0.1-0.9 ({len(mod)} cases, "
      f"worst {100 * worst:.2f}%)")
check(all(num(r["e_measured"]) > num(r["eta_requested"]) for r in mod),
      "measured restitution exceeds the requested eta (no-tension cut)")

for r in rows("decay.csv"):
    kind, p = r["damping"], num(r["parameter"])
    exp_, got = num(r["decrement_expected"]), num(r["decrement_measured"])
    err = abs(got / exp_ - 1)
    tol = {"global": 0.01, "component": 0.02, "vector": 0.02, "contact": 0.02}[kind]
    if kind == "contact" and p < 0.5:
        continue
    check(err < tol, f"decay {kind} {p:g}: decrement {got:.4g} vs {exp_:.4g} ({100 * err:.2f}%)")

for r in rows("rayleigh.csv"):
    e, m = num(r["zeta_mode_wall_expected"]), num(r["zeta_mode_wall_measured"])
    check(abs(m / e - 1) < 0.03,
          f"Rayleigh f_R/f_c {num(r['f_R_over_f_wall']):g}: mode zeta {m:.4g} vs {e:.4g}")

load = {r["damping"]: r for r in rows("settling_load.csv")}
steps = lambda lab: num(load[lab]["steps_to_force_tolerance"])  # noqa: E731
none, loc = steps("none (eta 1, friction only)"), steps("local component 0.7")
check(math.isfinite(loc) and not (loc >= none),
      f"load step: local damping converges in fewer steps than none ({loc:g} vs {none:g})")

b = {r["damping"]: r for r in rows("bounce.csv")}["local component 0.7"]
a1, pr = num(b["apex1_over_h0"]), num(b["apex1_predicted"])
check(abs(a1 / pr - 1) < 0.1, f"bounce, local 0.7: first apex {a1:.4g} h0 vs {pr:.4g}")

ch = {r["damping"]: r for r in rows("chain.csv")}
amp = num(ch["local component 0.7"]["amplitude_vs_undamped"])
check(amp < 0.5, f"chain, local 0.7: pulse amplitude {amp:.3g} of the undamped one")

with open(os.path.join(out, "report.md")) as fh:
    rep = fh.read()
if os.path.exists(os.path.join(out, "vibrated_bed.csv")):
    bed = {r["damping"]: r for r in rows("vibrated_bed.csv")}
    seed, loc = (num(bed[k]["max_lift_mm"]) for k in ("contact eta 0.7 (seed)",
                                                       "local component 0.7"))
    check(0 < loc < seed, f"vibrated bed: local 0.7 lifts {loc:.2f} mm, seed bed {seed:.2f} mm")
    png = os.path.join(out, "vibrated_bed.png")
    check(os.path.exists(png) and os.path.getsize(png) > 0, "vibrated_bed.png written")
else:
    check("Vibrated bed: not available" in rep and "motion" in rep,
          "no moving walls: the report says the vibrated bed is not available")
sys.exit(1 if bad else 0)
EOF
