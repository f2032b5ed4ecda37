#!/usr/bin/python3
"""heap.py — the angle of repose of a poured heap against rolling resistance, friction
and the contact law (scenes/heap.yaml's set-up).

    /usr/bin/python3 studies/heap.py [--esfera build/esfera] [--out studies/results/heap]
                                     [--quick] [--only LAW] [--report-only]

A cylinder-lift test: spheres (diameters 4-5 mm, density 2500) released at random in
a cylinder standing on a square plate settle while the cylinder rises at 5 cm/s, and
slump out under its rim into a heap; spheres that roll off the plate leave the domain.
The heap's angle of repose is read from the last frame by repose.py (the median surface profile around the heap, fitted between 20% and 80% of
its height). The cases cross rolling friction mu_r in {0, 0.05, 0.1, 0.2} with sliding
friction mu in {0.3, 0.5}, for the linear law (kn = 2e4 N/m, kt = 2/7 kn) and for
Hertz-Mindlin (E = 5e7 Pa, nu = 0.25: contacts of similar stiffness at these overlaps),
restitution 0.5, the elastic-plastic rolling model (contact.rolling: epsd). The Hertz
case at mu = 0.5, mu_r = 0.1 is scenes/heap.yaml (heap-quick.yaml with --quick).
--quick runs 1000 spheres (as the scene heap-quick.yaml) instead of 2000 (heap.yaml).
Writes OUT/cases.csv and OUT/report.md (the table, the runs' costs)."""
import argparse
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
import repose  # noqa: E402

import numpy as np  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def material(law, mu, mu_r, density=None):
    m = {} if density is None else {"density": density}
    if law == "hertz":
        m.update({"youngs_modulus": 5.0e7, "poisson_ratio": 0.25})
    else:
        m.update({"kn": 2.0e4, "kt": 2.0e4 * 2 / 7})
    m.update({"restitution": 0.5, "tangential_restitution": 0.5, "friction": mu})
    if mu_r > 0:
        m["rolling_friction"] = mu_r
    return m


def heap_scene(law="hertz", mu=0.5, mu_r=0.1, count=2000, seed=3, duration=1.2):
    """The heap: `count` spheres released at random in a box inscribed in a cylinder
    (radius 3 cm, or 1.8 cm for fewer than 1000 spheres) standing on a 40 x 40 cm
    plate; the cylinder rises at 5 cm/s from the start (the spheres settle in it while
    its rim clears the plate) and the heap slumps out under it; run 1.2 s (the heap
    has stopped by 0.8 s)."""
    rc = 0.03 if count >= 1000 else 0.018
    half = round(rc / np.sqrt(2) - 0.001, 4)  # the box inside the cylinder
    vol = count * 4 / 3 * np.pi * (0.00225 ** 3 + 0.0025 ** 3) / 2
    top = round(0.003 + vol / 0.3 / (2 * half) ** 2, 3)  # a third solid, at random
    scene = {
        "name": f"heap-{law}-mu{mu:g}-mur{mu_r:g}",
        "dimension": 3,
        "gravity": [0, 0, -9.81],
        "domain": {"min": [-0.25, -0.25, -0.05], "max": [0.25, 0.25, round(top + 0.4, 2)]},
        "materials": {"glass": material(law, mu, mu_r, 2500),
                      "plate": material(law, mu, mu_r)},
        "particles": [{"generate": "random",
                       "region": {"min": [-half, -half, 0.003], "max": [half, half, top]},
                       "count": count, "radius": {"uniform_diameter": [0.004, 0.005]},
                       "material": "glass", "seed": seed}],
        "walls": [{"polygon": [[-0.2, -0.2, 0], [0.2, -0.2, 0], [0.2, 0.2, 0],
                               [-0.2, 0.2, 0]], "material": "plate"},
                  {"cylinder": {"base": [0, 0, 0], "radius": rc, "height": round(top + 0.05, 2),
                                "segments": 32},
                   "material": "plate", "motion": {"translate": {"velocity": [0, 0, 0.05]}}}],
        "contact": {"rolling": "epsd"} if mu_r > 0 else {},
        "integrator": {"method": "leapfrog", "dt": "auto", "frac": 0.2},
        "run": {"duration": duration},
        "output": {"every": 0.1, "energy_every": 0.01},
    }
    if not scene["contact"]:
        del scene["contact"]
    if law == "hertz":  # the time-step rule's stiffness at the fall's impact speed
        scene["integrator"]["impact_speed"] = round(float(np.sqrt(2 * 9.81 * top)), 1)
    return scene


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--esfera", default=os.path.join(ROOT, "build", "esfera"))
    ap.add_argument("--out", default=os.path.join(ROOT, "studies", "results", "heap"))
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--only", default=None, help="one law: linear or hertz")
    ap.add_argument("--report-only", action="store_true",
                    help="rewrite report.md and heap.png from OUT/cases.csv")
    a = ap.parse_args(argv)
    if a.report_only:
        report_only(a.out)
        return 0
    os.makedirs(a.out, exist_ok=True)
    count = 1000 if a.quick else 2000
    rows = []
    laws = [a.only] if a.only else ["linear", "hertz"]
    for law in laws:
        for mu in (0.3, 0.5):
            for mu_r in (0.0, 0.05, 0.1, 0.2):
                sc = heap_scene(law, mu, mu_r, count)
                d = os.path.join(a.out, "tmp", sc["name"])  # not committed
                os.makedirs(d, exist_ok=True)
                path = common.write_scene(os.path.join(d, "scene.yaml"), sc,
                                          "heap.py case")
                t0 = time.monotonic()
                r = common.run(a.esfera, path, os.path.join(d, "out"))
                wall = time.monotonic() - t0
                row = {"law": law, "mu": mu, "mu_r": mu_r, "particles": count,
                       "exit": r.returncode, "seconds": round(wall, 1)}
                if r.returncode == 0:
                    f = common.last_frame(os.path.join(d, "out"))
                    x, rad = np.asarray(f.data["position"]), np.asarray(f.data["radius"])
                    g = repose.repose_angle(x, rad)
                    row.update({"angle": round(g["angle"], 2), "err": round(g["err"], 2),
                                "flat": g["flat"],
                                "height": g["height"], "radius": g["radius"],
                                "on_plate": int((x[:, 2] > 0).sum())})
                rows.append(row)
                print(row, flush=True)
                common.write_csv(os.path.join(a.out, "cases.csv"), rows)
    write_report(a.out, rows, count)
    return 0


def report_only(out):
    """Rewrites report.md and heap.png from OUT/cases.csv."""
    rows = common.read_csv(os.path.join(out, "cases.csv"))
    write_report(out, rows, int(rows[0]["particles"]))


def write_report(out, rows, count):
    plot(out, rows)
    lines = ["# Angle of repose: the cylinder-lift heap", "",
             f"{count} spheres (diameters 4-5 mm) let out of a cylinder lifted at 5 cm/s "
             "onto a 40 x 40 cm plate; `studies/heap.py`"
             + (" --quick" if count < 2000 else "") + ". Angle from the last frame "
             "(studies/repose.py: median surface profile, fitted between 20% and 80% of "
             "the heap's height; err is the fit's standard error).", "",
             "| law | mu | mu_r | angle (deg) | err | height (mm) | spheres on plate "
             "| run (s) |", "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if r.get("exit") != 0:
            lines.append(f"| {r['law']} | {r['mu']} | {r['mu_r']} | exit {r['exit']} "
                         "| | | | |")
            continue
        ang = "flat (a layer)" if r["flat"] else f"{r['angle']:.1f}"
        err = "" if r["flat"] else f"{r['err']:.1f}"
        lines.append(f"| {r['law']} | {r['mu']} | {r['mu_r']} | {ang} | {err} | "
                     f"{1000 * r['height']:.1f} | {r['on_plate']} | {r['seconds']} |")
    lines += ["", "A flat entry is a layer: the heap's profile is lower than two mean "
              "diameters (no flank to fit).", "", "![angle against mu_r](heap.png)"]
    with open(os.path.join(out, "report.md"), "w") as fh:
        fh.write("\n".join(lines) + "\n")


def plot(out, rows):
    """heap.png: the angle against mu_r, one line per law and mu (a layer as 0)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(5, 3.6))
    for law, mark in (("linear", "o-"), ("hertz", "s--")):
        for mu in sorted({r["mu"] for r in rows}):
            sel = [r for r in rows if r["law"] == law and r["mu"] == mu and r["exit"] == 0]
            if not sel:
                continue
            ax.errorbar([r["mu_r"] for r in sel],
                        [0.0 if r["flat"] else r["angle"] for r in sel],
                        yerr=[0.0 if r["flat"] else r["err"] for r in sel], fmt=mark,
                        capsize=2, label=f"{law}, mu {mu}")
    ax.set_xlabel("rolling friction mu_r")
    ax.set_ylabel("angle of repose (deg; 0: a layer)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "heap.png"), dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
