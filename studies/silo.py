#!/usr/bin/python3
"""silo.py -- the silo discharge against Beverloo's law (issue 29).

For each orifice size D/d the study writes the scene (studies/silo_scene.py: a
cylindrical silo filled by run-time insertion, a gate removed by an event), runs it,
and measures:
  - the bulk density rho_b at the gate's opening: the particles' mass whose centres lie
    in the bed's core (r < R - 2 d, 2 d < z < 0.8 of the bed height) over its volume;
  - the discharged mass M(t): every particle leaving the domain (its floor lies 4 d
    below the orifice) is logged with its time and id (log.txt); its mass follows from
    its radius in the frame at the opening;
  - the steady mass flow rate W: the slope of a least-squares line through M(t) over
    the window from 0.05 s after the first particle left to the run's end (the first
    0.05 s hold the flow's start; the bed stays above one silo diameter throughout,
    so the rate does not depend on the height); R^2 and the slopes of the window's two
    halves say how steady it was.
Beverloo, Leniger & van de Velde (1961): W = C rho_b sqrt(g) (D - k d)^(5/2), C = 0.58,
k = 1.5. The report gives the ratio measured/Beverloo, C fitted with k = 1.5 per size,
and C and k fitted over all sizes (W^(2/5) is linear in D).

    /usr/bin/python3 studies/silo.py [--esfera build/esfera] [--out out/silo]
        [--sizes 5 6.5 8] [--quick] [--report studies/results/silo] [--set K=V]...
        [--no-run]
"""
import argparse
import math
import os
import re
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import esfera_h5  # noqa: E402
import silo_scene  # noqa: E402

G = 9.81
C_BEV, K_BEV = 0.58, 1.5
DENSITY = 2500.0
WINDOW_DELAY = 0.05  # s after the first particle left


def removals(out):
    """(times, ids) of the particles that left the domain, from log.txt."""
    pat = re.compile(r"^t = (\S+) s: particle id (\d+) left the domain")
    ts, ids = [], []
    with open(os.path.join(out, "log.txt")) as fh:
        for line in fh:
            m = pat.match(line)
            if m:
                ts.append(float(m.group(1)))
                ids.append(int(m.group(2)))
    return np.array(ts), np.array(ids, dtype=int)


def opening_frame(out, t_open):
    """The last frame at or before the gate's opening."""
    frames = esfera_h5.load_frames(out)
    best = None
    for fr in frames:
        if fr.time <= t_open + 1e-9:
            best = fr
    return best, frames


def bulk_density(data, s):
    p, r = data["position"], data["radius"]
    m = DENSITY * 4.0 / 3.0 * math.pi * r**3
    rad = np.hypot(p[:, 0], p[:, 1])
    top = np.percentile(p[:, 2], 99.5)
    lo, hi, rc = 2 * s["d"], 0.8 * top, s["R"] - 2 * s["d"]
    sel = (rad < rc) & (p[:, 2] > lo) & (p[:, 2] < hi)
    return m[sel].sum() / (math.pi * rc * rc * (hi - lo)), top


def discharge(out, s):
    """Everything measured in one run (a dict)."""
    fr, frames = opening_frame(out, s["t_open"])
    d = fr.data
    rho_b, top = bulk_density(d, s)
    mass = dict(zip(d["id"].tolist(), (DENSITY * 4 / 3 * math.pi * d["radius"]**3).tolist()))
    ts, ids = removals(out)
    early = int(np.sum(ts < s["t_open"]))
    ms = np.array([mass[i] for i in ids])
    M = np.cumsum(ms)
    t0 = ts[0] + WINDOW_DELAY if len(ts) else s["t_open"]
    t1 = frames[-1].time
    w = ts >= t0
    if w.sum() < 8:  # no flow to fit (a clogged orifice): W 0, R^2 0
        return dict(rho_b=rho_b, phi=rho_b / DENSITY, top=top, top_end=top, n_open=len(d["id"]),
                    early=early, n_out=len(ts), W=0.0, r2=0.0, W1=0.0, W2=0.0, t0=t0, t1=t1,
                    ts=ts, M=M, fit=np.zeros(2))
    fit = np.polyfit(ts[w], M[w], 1)
    resid = M[w] - np.polyval(fit, ts[w])
    r2 = 1 - np.sum(resid**2) / np.sum((M[w] - M[w].mean())**2)
    half = 0.5 * (t0 + t1)
    a, b = w & (ts < half), w & (ts >= half)
    W1, W2 = np.polyfit(ts[a], M[a], 1)[0], np.polyfit(ts[b], M[b], 1)[0]
    last = frames[-1].data["position"]
    top_end = np.percentile(last[last[:, 2] > 0, 2], 99.5)
    return dict(rho_b=rho_b, phi=rho_b / DENSITY, top=top, top_end=top_end,
                n_open=len(d["id"]), early=early, n_out=len(ts), W=fit[0], r2=r2,
                W1=W1, W2=W2, t0=t0, t1=t1, ts=ts, M=M, fit=fit)


def beverloo(rho_b, D, d, C=C_BEV, k=K_BEV):
    return C * rho_b * math.sqrt(G) * (D - k * d)**2.5


def run(esfera, outdir, name, ratio, quick, threads, sets=()):
    os.makedirs(outdir, exist_ok=True)
    s = silo_scene.write(outdir, name, ratio, quick)
    res = os.path.join(outdir, name)
    extra = [x for kv in sets for x in ("--set", kv)]
    r = subprocess.run([esfera, "run", os.path.join(outdir, name + ".yaml"), "--out", res,
                        "--quiet", "--overwrite", "--threads", str(threads), *extra],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"{name}: exit {r.returncode}: {r.stderr}")
    summary = dict(kv.split("=", 1) for kv in
                   [ln for ln in r.stdout.splitlines() if ln.startswith("summary:")][-1]
                   .split()[1:])
    return s, res, summary


def fit_ck(rows):
    """C and k over the sizes: W^(2/5) = (C rho_b sqrt g)^(2/5) (D - k d)."""
    D = np.array([r["D_eff"] for r in rows])
    y = np.array([(r["W"] / (r["rho_b"] * math.sqrt(G)))**0.4 for r in rows])
    slope, icpt = np.polyfit(D, y, 1)
    d = rows[0]["d"]
    return slope**2.5, -icpt / (slope * d)


def report(rows, C, k, path, quick, sets=()):
    os.makedirs(path, exist_ok=True)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
    for r in rows:
        ax[0].plot(r["ts"] - r["t_open"], r["M"] * 1e3, lw=1,
                   label=f"D/d = {r['D_over_d']:g}")
        tt = np.array([r["t0"], r["t1"]])
        ax[0].plot(tt - r["t_open"], np.polyval(r["fit"], tt) * 1e3, "k--", lw=0.8)
    ax[0].set_xlabel("time since the gate opened (s)")
    ax[0].set_ylabel("discharged mass (g)")
    ax[0].legend()
    ax[0].set_title("discharged mass; dashed: fits over the steady window")
    Dd = np.linspace(min(r["D_over_d"] for r in rows) * 0.8,
                     max(r["D_over_d"] for r in rows) * 1.15, 50)
    d, rho = rows[0]["d"], np.mean([r["rho_b"] for r in rows])
    ax[1].plot(Dd, [beverloo(rho, x * d, d) * 1e3 for x in Dd], "b-",
               label="Beverloo C 0.58, k 1.5")
    ax[1].plot(Dd, [beverloo(rho, x * d, d, C, k) * 1e3 if x > k else 0 for x in Dd], "g:",
               label=f"fit C {C:.3f}, k {k:.2f}")
    ax[1].plot([r["D_eff"] / d for r in rows], [r["W"] * 1e3 for r in rows], "ko",
               label="esfera")
    ax[1].set_xlabel("D/d")
    ax[1].set_ylabel("W (g/s)")
    ax[1].legend()
    ax[1].set_title("steady mass flow rate")
    fig.tight_layout()
    fig.savefig(os.path.join(path, "silo.png"), dpi=110)
    lines = ["# Silo discharge against Beverloo's law", "",
             "Written by `studies/silo.py" + (" --quick" if quick else "")
             + "".join(f" --set {x}" for x in sets) + "`. "
             "Scenes from `studies/silo_scene.py` (docs/examples.md#silo); W is the slope "
             "of the discharged mass against time, fitted from 0.05 s after the first "
             "particle left the domain to the run's end. rho_b is the bulk density of "
             "the bed's core at the opening. Beverloo: W = C rho_b sqrt(g) (D - k d)^(5/2), "
             "C 0.58, k 1.5. D is the faceted orifice's area-equivalent diameter.", "",
             "| D (mm) | D/d | silo (mm) | particles | rho_b (kg/m^3) | bed at open / end (mm) "
             "| W (g/s) | Beverloo (g/s) | ratio | C (k = 1.5) | R^2 | W 1st/2nd half (g/s) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        Wb = beverloo(r["rho_b"], r["D_eff"], r["d"])
        Cf = r["W"] / (r["rho_b"] * math.sqrt(G) * (r["D_eff"] - K_BEV * r["d"])**2.5)
        lines.append(
            f"| {r['D_eff']*1e3:.2f} | {r['D_eff']/r['d']:.2f} | {r['Ds']*1e3:.1f} | "
            f"{r['n_open']} | {r['rho_b']:.0f} | {r['top']*1e3:.0f} / {r['top_end']*1e3:.0f} "
            f"| {r['W']*1e3:.1f} | {Wb*1e3:.1f} | {r['W']/Wb:.3f} | {Cf:.3f} | "
            f"{r['r2']:.4f} | {r['W1']*1e3:.1f} / {r['W2']*1e3:.1f} |")
    lines += ["", f"C and k fitted over the sizes (W^(2/5) linear in D): C = {C:.3f}, "
              f"k = {k:.2f}.", "", "![discharge](silo.png)", ""]
    with open(os.path.join(path, "report.md"), "w") as fh:
        fh.write("\n".join(lines))
    print("\n".join(lines))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    ap.add_argument("--esfera", default=os.path.join(here, "build", "esfera"))
    ap.add_argument("--out", default="out/silo")
    ap.add_argument("--sizes", type=float, nargs="+", default=[5.0, 6.5, 8.0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--report", default=os.path.join(here, "studies", "results", "silo"))
    ap.add_argument("--no-run", action="store_true", help="analyse existing results")
    ap.add_argument("--set", action="append", default=[],
                    help="KEY=VALUE passed to every run (e.g. materials.glass.friction=0.3)")
    a = ap.parse_args()
    rows = []
    for ratio in a.sizes:
        name = f"silo-{ratio:g}"
        if a.no_run:
            s, res = silo_scene.scene(ratio, a.quick), os.path.join(a.out, name)
        else:
            s, res, summ = run(a.esfera, a.out, name, ratio, a.quick, a.threads, a.set)
            print(f"{name}: wall_s={summ['wall_s']} inserted={summ['inserted']} "
                  f"removed={summ['removed']}", flush=True)
        rows.append(dict(s, **discharge(res, s)))
    C, k = fit_ck(rows) if len(rows) > 1 else (float("nan"), float("nan"))
    report(rows, C, k, a.report, a.quick, a.set)


if __name__ == "__main__":
    main()
