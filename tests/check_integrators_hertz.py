#!/usr/bin/python3
"""check_integrators_hertz.py ESFERA REPO -- studies/integrators_hertz.py: its --quick
mode (leapfrog and DP5 on the five head-on cases, 16 .. 1024 steps per contact, five
onset phases; about 30 s) into a temporary directory: every case measured, its CSV,
JSON, PNG and section written, the references (closed forms: the adaptive reference
within 1e-9 of them), every curve's error falling at least 15-fold from 16 to 1024 steps
per contact (64-fold at order 1, less the onset phase's scatter), and the clearest
orders even at four step sizes: the leapfrog's 2 on the
undamped cases (linear and Hertz) and 1 on the linear damped one (within 0.35), DP5's
above 2.1 on the undamped Hertz impact. Then the committed full results
(studies/results/integrators/hertz_orders.csv and .json): all five cases, and the
observed orders of the ERK methods (fitted slopes) within the band of the expected
order the force's smoothness allows: 2 linear undamped, 1 linear damped, 2.5 Hertz
undamped, 1.25 Hertz with the Tsuji dashpot, 1 Hertz with the constant dashpot
(+-0.35, +-0.2, +-0.35, +-0.15, +-0.2), and the leapfrog's 2, 1, 2, 1, 1 (+-0.25)."""
import json
import os
import subprocess
import sys
import tempfile

from pycheck import check, finish

esfera, repo = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(repo, "studies"))
import integrators_hertz as ih  # noqa: E402
from common import read_csv  # noqa: E402
from integrators_curves import DP5, orders  # noqa: E402


def slopes(rows, meta):
    """{(case, method): fitted slope} of the rows' curves."""
    out = {}
    for case in ih.CASES:
        for m in ih.METHODS:
            pts = ih.curve([r for r in rows if r["case"] == case and r["method"] == m])
            o = orders(pts, meta[case]["floor"]) if pts and case in meta else None
            if o:
                out[(case, m)] = o["all"]
    return out


with tempfile.TemporaryDirectory() as tmp:
    p = subprocess.run(["/usr/bin/python3", os.path.join(repo, "studies",
                                                         "integrators_hertz.py"),
                        "--quick", "--out", tmp, "--esfera", esfera],
                       capture_output=True, text=True, timeout=600)
    check(p.returncode == 0, f"integrators_hertz.py --quick: exit {p.returncode} "
          f"{p.stderr[-2000:]}")
    for f in ("hertz_orders.csv", "hertz_orders.json", "hertz_orders.png", "hertz.md"):
        check(os.path.getsize(os.path.join(tmp, f)) > 0 if os.path.exists(
            os.path.join(tmp, f)) else False, f"{f} written")
    rows = read_csv(os.path.join(tmp, "hertz_orders.csv"))
    with open(os.path.join(tmp, "hertz_orders.json")) as fh:
        meta = json.load(fh)
    check(sorted(meta) == sorted(ih.CASES), f"every case measured: {sorted(meta)}")
    for case in ("linear_undamped", "linear_damped", "hertz_undamped"):
        note = meta.get(case, {}).get("note", "")
        gap = float(note.split(" lies ")[1].split()[0]) if " lies " in note else 1.0
        check(gap < 1e-9, f"{case}: adaptive reference {gap:.1e} from the closed form")
    for case in ih.CASES:
        for m in ("leapfrog", DP5):
            pts = ih.curve([r for r in rows if r["case"] == case and r["method"] == m])
            drop = pts[0]["error"] / pts[-1]["error"] if len(pts) == 4 else 0.0
            check(drop > 15, f"{case} {m}: error falls {drop:.3g}-fold over 16..1024")
    s = slopes(rows, meta)
    for case, want in (("linear_undamped", 2.0), ("hertz_undamped", 2.0),
                       ("linear_damped", 1.0)):
        got = s.get((case, "leapfrog"), float("nan"))
        check(abs(got - want) < 0.35, f"quick {case} leapfrog order {got:.2f} vs {want}")
    got = s.get(("hertz_undamped", DP5), float("nan"))
    check(got > 2.1, f"quick hertz_undamped DP5 order {got:.2f} above 2.1")

res = os.path.join(repo, "studies", "results", "integrators")
rows = read_csv(os.path.join(res, "hertz_orders.csv"))
with open(os.path.join(res, "hertz_orders.json")) as fh:
    meta = json.load(fh)
check(sorted(c for c in meta if c in ih.CASES) == sorted(ih.CASES),
      "committed results hold every case")
s = slopes(rows, meta)
band = {"linear_undamped": 0.35, "linear_damped": 0.2, "hertz_undamped": 0.35,
        "hertz_tsuji": 0.15, "hertz_constant": 0.2}
lf = {"linear_undamped": 2.0, "linear_damped": 1.0, "hertz_undamped": 2.0,
      "hertz_tsuji": 1.0, "hertz_constant": 1.0}
for case, (_, _, _, k) in ih.CASES.items():
    for m in ih.METHODS:
        got = s.get((case, m), float("nan"))
        want, tol = (lf[case], 0.25) if m == "leapfrog" else (min(k, ih.NOMINAL[m]),
                                                               band[case])
        check(abs(got - want) < tol, f"committed {case} {m}: order {got:.2f} vs {want}")

sys.exit(finish("integrators_hertz"))
