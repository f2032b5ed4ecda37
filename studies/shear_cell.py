"""shear_cell.py -- mu(I) of a dense frictional shear cell (issue 29; scenes/shear_cell.yaml,
docs/examples.md#shear-cell). Each case packs 500 spheres (studies/shear_cell_pack.py) at
solid fraction phi, shears them at rate g (Lees-Edwards, fixed volume) to a strain of
STRAIN, and averages stress.csv's whole-cell rows over strains >= SKIP (the start-up
transient discarded): p = mean p, tau = -mean sxy (compression positive: the shear
stress of flow x / gradient y is -sxy), mu = tau / p, I = g d / sqrt(p / rho). The error
bar of mu is the standard error over 4 blocks of the averaging window; p_drift, the
mean p of the window's second half over its first, says how steady the state is. Fits
mu = mu_s + (mu_2 - mu_s) / (1 + I_0 / I) to the points with I <= IFIT (least squares,
I_0 on a grid), compares with the guide curve of Jop, Forterre & Pouliquen (2006), and
writes studies/results/shear_cell/{cases.csv, report numbers, mu_I.png}.
Usage: /usr/bin/python3 studies/shear_cell.py [ESFERA] [--from-csv]  (--from-csv: the
numbers and plot from the last run's cases.csv)"""
import math
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import shear_cell_pack  # noqa: E402

ROOT = os.path.dirname(HERE)
OUT = os.path.join(HERE, "results", "shear_cell")
RHO, D = 2500.0, shear_cell_pack.D
STRAIN, SKIP = 20.0, 10.0
# (phi, shear rate 1/s): the dense cases sweep the rate (the quasi-static end is set by
# the contact stiffness), the looser ones reach the inertial end.
CASES = [(0.59, 1.0), (0.59, 3.0), (0.59, 10.0), (0.59, 30.0), (0.59, 100.0),
         (0.58, 30.0), (0.57, 30.0), (0.56, 30.0), (0.55, 30.0), (0.52, 30.0),
         (0.48, 30.0), (0.44, 30.0)]
# mu_s = tan 20.9 deg, mu_2 = tan 32.76 deg, I_0 = 0.279: Jop, Forterre & Pouliquen 2006
# (Nature 441, 727), glass beads of 0.5 mm in experiments (see the report)
JOP = (math.tan(math.radians(20.9)), math.tan(math.radians(32.76)), 0.279)
IFIT = 2.0  # the fit uses I <= IFIT (all the cases here)


def scene_text(side, csv, rate, duration, every):
    base = open(os.path.join(ROOT, "scenes", "shear_cell.yaml")).read()
    out = []
    edits = [  # (a stripped line's start, the line that replaces it)
        ("max: [", f"  max: [{side!r}, {side!r}, {side!r}]"),
        ("shear:", f"  shear: {{rate: {rate!r}, flow: x, gradient: y}}"),
        ("- {file:", f"  - {{file: {csv}, material: glass}}"),
        ("run:", f"run: {{duration: {duration!r}}}"),
        ("stress_every:", f"  stress_every: {every!r}"),
        ("every:", f"  every: {duration!r}"),
        ("- {region:", f"    - {{region: {{min: [0, 0, 0], max: [{side!r}, {side!r}, "
                       f"{side!r}]}}}}")]
    for line in base.splitlines():
        s = line.strip()
        line = next((new for start, new in edits if s.startswith(start)), line)
        out.append(line)
    return "\n".join(out) + "\n"


def run_case(exe, phi, rate, work):
    tag = f"phi{phi:.2f}_g{rate:g}"
    d = os.path.join(work, tag)
    os.makedirs(d, exist_ok=True)
    side, rows = shear_cell_pack.pack(5, phi, seed=7)
    shear_cell_pack.write(os.path.join(d, "pack.csv"), rows)
    duration = STRAIN / rate
    with open(os.path.join(d, "scene.yaml"), "w") as f:
        f.write(scene_text(side, "pack.csv", rate, duration, duration / 400))
    subprocess.run([exe, "run", os.path.join(d, "scene.yaml"), "--out", os.path.join(d, "out"),
                    "--overwrite", "--quiet", "--threads", "1"], check=True,
                   stdout=subprocess.DEVNULL)
    s = np.genfromtxt(os.path.join(d, "out", "stress.csv"), delimiter=",", names=True)
    keep = s["time"] * rate >= SKIP
    p, tau = s["p"][keep], -s["sxy"][keep]
    blocks = np.array_split(np.arange(keep.sum()), 4)
    mub = [tau[b].mean() / p[b].mean() for b in blocks]
    P = p.mean()
    h = len(p) // 2
    drift = p[h:].mean() / p[:h].mean()  # the window's second half against its first
    return dict(drift=drift, phi=phi, rate=rate, p=P, mu=tau.mean() / P,
                mu_err=np.std(mub, ddof=1) / 2, I=rate * D / math.sqrt(P / RHO),
                pk=s["p_kinetic"][keep].mean() / P)


def fit(I, mu):
    best = None
    for i0 in np.exp(np.linspace(np.log(1e-3), np.log(3), 300)):
        A = np.stack([np.ones_like(I), 1 / (1 + i0 / I)], axis=1)
        c, *_ = np.linalg.lstsq(A, mu, rcond=None)
        r = float(((A @ c - mu) ** 2).sum())
        if best is None or r < best[0]:
            best = (r, c[0], c[0] + c[1], i0)
    return best[1:]


def main():
    args = [x for x in sys.argv[1:] if x != "--from-csv"]
    exe = args[0] if args else os.path.join(ROOT, "build", "esfera")
    work = os.path.join("/tmp", "esfera_shear_cell")
    if "--from-csv" in sys.argv:  # the figures and plot again from cases.csv, no runs
        import csv
        with open(os.path.join(OUT, "cases.csv")) as f:
            res = [dict(phi=float(r["phi"]), rate=float(r["rate"]), p=float(r["p"]),
                        I=float(r["I"]), mu=float(r["mu"]), mu_err=float(r["mu_err"]),
                        pk=float(r["p_kinetic_over_p"]), drift=float(r["p_drift"]))
                   for r in csv.DictReader(f)]
    else:
        res = [run_case(exe, phi, g, work) for phi, g in CASES]
    os.makedirs(OUT, exist_ok=True)
    with open(os.path.join(OUT, "cases.csv"), "w") as f:
        f.write("phi,rate,p,I,mu,mu_err,p_kinetic_over_p,p_drift\n")
        for r in res:
            f.write(f"{r['phi']},{r['rate']},{r['p']:.6g},{r['I']:.5g},{r['mu']:.4f},"
                    f"{r['mu_err']:.4f},{r['pk']:.4f},{r['drift']:.3f}\n")
            print(f"phi {r['phi']:.2f} rate {r['rate']:6g}: p {r['p']:10.4g} Pa  "
                  f"I {r['I']:.4g}  mu {r['mu']:.4f} +- {r['mu_err']:.4f}  "
                  f"p_kin/p {r['pk']:.3f}  p 2nd/1st half {r['drift']:.3f}")
    I = np.array([r["I"] for r in res])
    mu = np.array([r["mu"] for r in res])
    sel = I <= IFIT
    ms, m2, i0 = fit(I[sel], mu[sel])
    rms = float(np.sqrt(np.mean((ms + (m2 - ms) / (1 + i0 / I[sel]) - mu[sel]) ** 2)))
    print(f"fit rms deviation {rms:.4f} over {int(sel.sum())} points (I <= {IFIT})")
    print(f"fit: mu_s {ms:.3f}  mu_2 {m2:.3f}  I_0 {i0:.3f}")
    ref = JOP[0] + (JOP[1] - JOP[0]) / (1 + JOP[2] / I)
    for lim in (0.03, 0.3, IFIT):
        k = I <= lim
        dev = mu[k] - ref[k]
        print(f"against the reference curve, I <= {lim}: {int(k.sum())} points, rms "
              f"{np.sqrt(np.mean(dev ** 2)):.4f}, largest {dev[np.argmax(np.abs(dev))]:+.4f}")
    with open(os.path.join(OUT, "fit.txt"), "w") as f:
        f.write(f"mu_s {ms:.4f}\nmu_2 {m2:.4f}\nI_0 {i0:.4f}\nrms {rms:.4f}\n")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    for phi in sorted({r["phi"] for r in res}):
        sel = [r for r in res if r["phi"] == phi]
        ax.errorbar([r["I"] for r in sel], [r["mu"] for r in sel],
                    yerr=[r["mu_err"] for r in sel], fmt="o", label=f"esfera, phi = {phi}")
    xs = np.logspace(-3.5, 0.3, 200)
    xf = xs[xs <= IFIT]
    ax.plot(xf, ms + (m2 - ms) / (1 + i0 / xf), "k-",
            label=f"fit: {ms:.2f} + ({m2:.2f} - {ms:.2f}) / (1 + {i0:.3f} / I)")
    ax.plot(xs, JOP[0] + (JOP[1] - JOP[0]) / (1 + JOP[2] / xs), "k:",
            label="Jop et al. 2006, glass beads: tan 20.9°, tan 32.76°, I_0 0.279")
    ax.set_xscale("log")
    ax.set_xlabel("inertial number I = g d / sqrt(p / rho)")
    ax.set_ylabel("mu = shear stress / pressure")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(OUT, "mu_I.png"), dpi=120)


if __name__ == "__main__":
    main()
