#!/bin/bash
# study_critical_dt.sh ESFERA REPO_ROOT — runs studies/critical_dt.py --quick into a
# temporary directory and checks its outputs: every file is there and not empty, and
# the measurements are sane:
#   - the single undamped normal contact (a sphere resting on a wall) is stable up to
#     within 3 % of 2/omega_max from `esfera modes`;
#   - the free undamped pair's limit is Hart's rule 2 sqrt(m/2k) within 3 %;
#   - every single-contact case's closed form (each mode with its own damping ratio)
#     lies inside the measured stable/unstable bracket (1 % wide);
#   - no run contradicts a single stability boundary.
set -euo pipefail
if [ $# -ne 2 ]; then
  echo "usage: $0 ESFERA REPO_ROOT" >&2
  exit 2
fi
esfera=$1
root=$2
py=/usr/bin/python3
tmp=$(mktemp -d "${TMPDIR:-/tmp}/study_critical_dt.XXXXXX")
trap 'rm -rf "$tmp"' EXIT

start=$(date +%s)
"$py" "$root/studies/critical_dt.py" --quick --out "$tmp/out" --esfera "$esfera"
echo "study_critical_dt: quick study took $(( $(date +%s) - start )) s"

fail=0
for f in limits.csv runs.csv summary.csv pack_particles.csv report.md \
         limit_vs_xi.png margins.png limit_vs_kt.png sweep.png; do
  if [ ! -s "$tmp/out/$f" ]; then
    echo "FAIL: $f missing or empty"
    fail=1
  fi
done

"$py" - "$tmp/out" <<'EOF' || fail=1
import csv, os, sys
out = sys.argv[1]
rows = list(csv.DictReader(open(os.path.join(out, "limits.csv"))))
bad = 0

def check(ok, what):
    global bad
    print(("ok: " if ok else "FAIL: ") + what)
    bad += not ok

def row(case, eta):
    for r in rows:
        if r["case"] == case and float(r["eta"]) == eta:
            return r
    raise SystemExit(f"FAIL: no row for {case} eta {eta}")

w = row("wall_normal", 1.0)
ratio = float(w["dt_limit"]) / float(w["dt_modes"])
check(abs(ratio - 1) < 0.03, f"wall_normal eta 1: limit / (2/omega_max) = {ratio:.4f}")
p = row("pair_normal", 1.0)
ratio = float(p["dt_limit"]) / float(p["dt_hart"])
check(abs(ratio - 1) < 0.03, f"pair_normal eta 1: limit / hart = {ratio:.4f}")
single = [r for r in rows if r["closed_form_in_bracket"] != ""]
inside = [r for r in single if r["closed_form_in_bracket"] == "1"]
check(len(single) >= 4 and len(inside) == len(single),
      f"closed form inside the bracket in {len(inside)} of {len(single)} cases")
n = sum(int(r["inconsistent_runs"]) for r in rows)
check(n == 0, f"{n} runs contradict the stability boundary")
sys.exit(1 if bad else 0)
EOF

if [ $fail -ne 0 ]; then
  echo "study_critical_dt: FAILED"
  exit 1
fi
echo "study_critical_dt: all checks passed"
