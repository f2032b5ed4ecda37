#!/usr/bin/python3
"""check_chung_ooi.py ESFERA REPO -- impacts of Chung & Ooi (2011) tests 4-7 with the
Hertz-Mindlin law (studies/chung_ooi.py's scenes: leapfrog, 400 steps per contact):

- gross sliding (test 4 at 60 and 80 deg and the alloy at 70 deg, test 5 steel at
  Psi_in = 14, test 6 at Psi_in = 10.5) against the rigid-body closed forms with the
  measured normal restitution: v_t' = v_t - mu (1 + e) v_n, R w' = 5/2 mu (1 + e) v_n
  (test 6 from -w0), within 1 % (the torque's lever arm R - u takes up to 0.5 % here);
- the normal restitution: 1 when undamped (within 1e-6), the Tsuji dashpot's e = 0.98
  (test 4) and 0.5 (test 6) within 1e-3;
- test 7 (two spheres with opposite spins, their contact points moving together):
  nothing slides, w' = w0 within 1e-9 and |v_t'| below 1e-12 m/s;
- the sticking regime of test 5 (steel and polyethylene at Psi_in = 1 and 2, where
  the contact point's motion reverses) and test 6 (Psi_in = 0.5) against the law
  integrated independently (chung_ooi.model_reference, the same equations, 4000
  steps per contact): recoil angle and spin within 0.015 (they differ by 0.006 at
  most over the study's 150 impacts, the leapfrog's step);
- the sticking regime of test 4 (aluminium oxide at 15-30 deg) against the paper's
  digitised curves (chung_ooi_published.py): e_t within 0.03 and w' within 25 rad/s
  (4 % of its 610 rad/s peak; measured 0.009 and 21). Test 5's published sticking
  branch is not checked: esfera differs from it by up to 1.4 (studies/results/
  chung_ooi/report.md), and so does the law's independent integration.
A few seconds."""
import os
import sys
import tempfile

from pycheck import check, finish

esfera, repo = sys.argv[1], sys.argv[2]
sys.path.insert(0, os.path.join(repo, "studies"))
import chung_ooi as co  # noqa: E402

ALIAS = {"recoil5": "recoil", "recoil6": "recoil"}


def rel(a, b):
    return abs(a - b) / abs(b)


with tempfile.TemporaryDirectory() as tmp:
    os.makedirs(os.path.join(tmp, "runs"))

    def impact(test, mat, p):
        return co.impact(esfera, tmp, test, mat, p)

    sliding = [(4, "al_oxide", 60.0, ("e_t", "omega")),
               (4, "al_oxide", 80.0, ("e_t", "omega")),
               (4, "al_alloy", 70.0, ("e_t", "omega")),
               (5, "steel", 21.0, ("recoil5", "spin")),
               (6, "al_alloy", 21.0, ("beta", "recoil6"))]
    for test, mat, p, keys in sliding:
        r = impact(test, mat, p)
        cf = co.closed_form(r)
        check(cf is not None, f"test {test} {mat} {p}: slides throughout")
        for k in keys:
            ours = r[ALIAS.get(k, k)]
            check(cf is not None and rel(ours, cf[k]) < 0.01,
                  f"test {test} {mat} {p}: {k} {ours:.6g} vs sliding "
                  f"{cf[k] if cf else float('nan'):.6g}")
        e_want = co.TESTS[test]["e"]
        tol = 1e-6 if e_want == 1 else 1e-3
        check(abs(r["e_n"] / e_want - 1) < tol,
              f"test {test} {mat} {p}: normal restitution {r['e_n']:.8f} vs {e_want}")

    for mat in ("al_alloy", "copper"):
        r = impact(7, mat, 4.0)
        check(abs(r["w_ratio"] - 1) < 1e-9, f"test 7 {mat}: w'/w0 = {r['w_ratio']!r}")
        check(abs(r["vt_after"]) < 1e-12, f"test 7 {mat}: v_t' = {r['vt_after']!r}")

    sticking = [(5, "steel", 1.5), (5, "steel", 3.0), (5, "polyethylene", 1.5),
                (5, "polyethylene", 3.0), (6, "al_alloy", 1.0), (6, "nylon", 1.0)]
    for test, mat, p in sticking:
        r = impact(test, mat, p)
        m = co.observables(test, mat, p, *co.model_reference(test, mat, p))
        for k in ("recoil", "spin", "beta"):
            if k in r:
                check(abs(r[k] - m[k]) < 0.015,
                      f"test {test} {mat} Psi {r['x']:.3g}: {k} {r[k]:.5f} vs the law "
                      f"integrated on its own {m[k]:.5f}")

    pub = co.published(4, "al_oxide")
    for angle in (15.0, 20.0, 25.0, 30.0):
        r = impact(4, "al_oxide", angle)
        p = co.published_at(pub["e_t"], angle)
        check(abs(r["e_t"] - p) < 0.03,
              f"test 4 al_oxide {angle} deg: e_t {r['e_t']:.4f} vs published {p:.4f}")
        p = co.published_at(pub["omega"], angle)
        check(abs(r["omega"] - p) < 25.0,
              f"test 4 al_oxide {angle} deg: w' {r['omega']:.1f} vs published {p:.1f}")

sys.exit(finish("chung_ooi"))
