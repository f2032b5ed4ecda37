#!/bin/bash
# study_integrators.sh ESFERA REPO_ROOT - runs studies/integrators.py --quick into a
# temporary directory and checks its outputs: the CSVs with their columns, the PNGs, the
# report, and basic sanity (the leapfrog's error falls as frac falls, the adaptive
# Dormand-Prince's falls as rtol falls, the head-on errors are against the closed form
# and small at the finest settings, the report names a cheapest method per error level);
# then --replot (the report rebuilt from the CSV and JSON files alone must be the same)
# and --scenes oblique (one scene measured again, the other kept). Finally the committed
# full-mode results hold every scene, the vibrated bed (moving wall) included.
# Exit 77 (skipped) when Debian's python lacks numpy, matplotlib or h5py.
set -u
esfera=${1:?usage: study_integrators.sh ESFERA REPO_ROOT}
root=${2:?usage: study_integrators.sh ESFERA REPO_ROOT}
py=/usr/bin/python3

if ! "$py" -c 'import numpy, h5py, matplotlib' 2>/dev/null; then
  echo "study_integrators: $py lacks numpy/h5py/matplotlib: skipped"
  exit 77
fi

out=$(mktemp -d "${TMPDIR:-/tmp}/study_integrators.XXXXXX")
trap 'rm -rf "$out"' EXIT
fail=0
check() { # check CONDITION-EXIT-STATUS MESSAGE
  if [ "$1" -ne 0 ]; then
    echo "FAIL: $2"
    fail=$((fail + 1))
  else
    echo "ok: $2"
  fi
}

start=$(date +%s)
"$py" "$root/studies/integrators.py" --quick --out "$out" --esfera "$esfera" \
  >"$out/stdout.txt" 2>"$out/stderr.txt"
rc=$?
took=$(($(date +%s) - start))
check $rc "integrators.py --quick exits 0 (took ${took} s)"
[ $rc -ne 0 ] && tail -20 "$out/stderr.txt"
[ "$took" -le 60 ]
check $? "--quick finishes within 60 s (${took} s)"

for f in head_on.csv oblique.csv head_on.json oblique.json report.md; do
  [ -s "$out/$f" ]
  check $? "$f written"
done
for f in head_on_rhs.png head_on_wall.png oblique_rhs.png oblique_wall.png; do
  [ "$(head -c 4 "$out/$f" 2>/dev/null | tail -c 3)" = "PNG" ]
  check $? "$f is a PNG"
done
[ ! -e "$out/tmp/runs" ] || [ -z "$(ls -A "$out/tmp/runs")" ]
check $? "run directories cleaned up"

"$py" - "$out" <<'EOF'
import csv, math, os, sys

out = sys.argv[1]
bad = []


def rows(name):
    with open(os.path.join(out, name)) as fh:
        r = csv.DictReader(fh)
        need = ["method", "history", "roots", "setting", "error", "rhs_evals", "wall_s",
                "steps", "rejected"]
        missing = [c for c in need if c not in r.fieldnames]
        if missing:
            bad.append(f"{name}: missing columns {missing}")
        return list(r)


def curve(rs, method, history="-", roots="false", mode=None):
    sel = [r for r in rs if r["method"] == method and r["history"] == history
           and r["roots"] == roots and (mode is None or r["mode"] == mode)]
    return [(float(r["setting"]), float(r["error"]), int(r["rhs_evals"]))
            for r in sel if r["status"] == "ok"]


for name in ("head_on.csv", "oblique.csv"):
    rs = rows(name)
    okr = [r for r in rs if r["status"] == "ok"]
    if len(okr) < 15:
        bad.append(f"{name}: only {len(okr)} measured runs")
    for r in okr:
        e, n, w = float(r["error"]), int(r["rhs_evals"]), float(r["wall_s"])
        if not (math.isfinite(e) and e >= 0 and n > 0 and w >= 0):
            bad.append(f"{name}: bad row {r}")
    lf = sorted(curve(rs, "leapfrog"), reverse=True)  # coarse to fine
    if len(lf) < 3 or not lf[-1][1] < 0.5 * lf[0][1]:
        bad.append(f"{name}: leapfrog error does not fall with frac: {lf}")
    if len(lf) >= 2 and not lf[-1][2] > lf[0][2]:
        bad.append(f"{name}: leapfrog rhs evaluations do not grow as frac falls")
    dp = sorted(curve(rs, "erk:ARKODE_DORMAND_PRINCE_7_4_5", "state", "false",
                      "adaptive"), reverse=True)
    if len(dp) < 2 or not dp[-1][1] < 0.1 * dp[0][1]:
        bad.append(f"{name}: DP5 adaptive state error does not fall tenfold: {dp}")

ho = rows("head_on.csv")
lf = sorted(curve(ho, "leapfrog"), reverse=True)
if lf and not 1e-3 < lf[0][1] < 0.1:  # first order: a few % at frac 0.1
    bad.append(f"head_on: leapfrog error at frac {lf[0][0]:.3g} is {lf[0][1]:.3g}")
best = min(float(r["error"]) for r in ho if r["status"] == "ok")
if not best < 1e-5:
    bad.append(f"head_on: best error {best:.3g} not below 1e-5 (closed form broken?)")

with open(os.path.join(out, "report.md")) as fh:
    rep = fh.read()
for key in ("## Headline", "Head-on collision", "Oblique frictional impact",
            "Vibrated bed", "Observed orders", "Frozen vs state", "matched accuracy"):
    if key not in rep:
        bad.append(f"report.md lacks '{key}'")
head = [l for l in rep.splitlines() if l.startswith("| Head-on collision | 0.01 |")]
if not head or "not reached" in head[0] or not any(
        m in head[0] for m in ("leapfrog", "verlet", "RK4", "DP5", "CVODE")):
    bad.append(f"report.md: no cheapest method named for head-on at 1e-2: {head}")
for b in bad:
    print("FAIL:", b)
print(f"csv/report sanity: {len(bad)} problems")
sys.exit(1 if bad else 0)
EOF
check $? "CSV and report sanity"

cp "$out/report.md" "$out/report.first"
"$py" "$root/studies/integrators.py" --quick --replot --out "$out" --esfera /nonexistent \
  >"$out/stdout.txt" 2>"$out/stderr.txt"
check $? "--replot exits 0 (no esfera needed)"
cmp -s "$out/report.md" "$out/report.first"
check $? "--replot rebuilds the same report from the CSV and JSON files"

head_sum=$(md5sum <"$out/head_on.csv")
"$py" "$root/studies/integrators.py" --quick --scenes oblique --out "$out" \
  --esfera "$esfera" >"$out/stdout.txt" 2>"$out/stderr.txt"
rc=$?
check $rc "--scenes oblique exits 0"
[ $rc -eq 0 ] && [ "$(md5sum <"$out/head_on.csv")" = "$head_sum" ] &&
  grep -q "^## Head-on collision" "$out/report.md" &&
  grep -q "^## Oblique frictional impact" "$out/report.md"
check $? "--scenes oblique keeps head_on.csv and reports both scenes"
"$py" "$root/studies/integrators.py" --quick --scenes nosuch --out "$out" \
  --esfera "$esfera" >/dev/null 2>&1
[ $? -eq 2 ]
check $? "--scenes with an unknown scene exits 2"

# The committed full-mode results (studies/results/integrators): every scene, the
# vibrated bed with its methods and reference floor, and its rows in the report.
"$py" - "$root/studies/results/integrators" <<'EOF'
import csv, json, os, sys

res = sys.argv[1]
bad = []
for name in ("head_on", "oblique", "pack", "vibrated_bed"):
    for ext in (".csv", ".json", "_rhs.png", "_wall.png"):
        if not os.path.exists(os.path.join(res, name + ext)):
            bad.append(f"committed results lack {name}{ext}")
try:
    with open(os.path.join(res, "vibrated_bed.csv")) as fh:
        ok = [r for r in csv.DictReader(fh) if r["status"] == "ok"]
    with open(os.path.join(res, "vibrated_bed.json")) as fh:
        meta = json.load(fh)
    methods = {r["method"] for r in ok}
    for m in ("leapfrog", "verlet", "rk4", "cvode-adams",
              "erk:ARKODE_DORMAND_PRINCE_7_4_5", "erk:ARKODE_BOGACKI_SHAMPINE_4_2_3"):
        if m not in methods:
            bad.append(f"vibrated_bed.csv: no measured {m} run")
    if not {r["history"] for r in ok} >= {"frozen", "state"}:
        bad.append("vibrated_bed.csv: not both histories")
    if not 0 < meta["floor"] < 1e-5:
        bad.append(f"vibrated_bed.json: reference floor {meta['floor']}")
    with open(os.path.join(res, "report.md")) as fh:
        rep = fh.read()
    row = [l for l in rep.splitlines()
           if l.startswith("| Vibrated bed (moving wall) | 0.01 |")]
    if "## Vibrated bed (moving wall)" not in rep or not row or "not reached" in row[0]:
        bad.append(f"report.md: no vibrated-bed section or headline row: {row}")
except (OSError, KeyError, ValueError) as e:
    bad.append(f"committed vibrated-bed results unreadable: {e}")
for b in bad:
    print("FAIL:", b)
sys.exit(1 if bad else 0)
EOF
check $? "committed full-mode results hold every scene, the vibrated bed included"

echo "study_integrators: $fail failed"
[ $fail -eq 0 ]
