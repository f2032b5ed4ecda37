#!/usr/bin/python3
"""heap.py — the angle of repose of a poured heap against rolling resistance, friction
and the contact law (scenes/heap.yaml's set-up).

    /usr/bin/python3 studies/heap.py [--esfera build/esfera] [--out studies/results/heap]
                                     [--quick] [--only LAW]

A column of spheres (diameters 4-5 mm, density 2500) released at random positions in a
narrow tall box falls onto a square plate and piles up; spheres that roll off the plate
leave the domain. After the pour the heap's angle of repose is read from the last frame
by repose.py (the median surface profile around the heap, fitted between 20% and 80% of
its height). The cases cross rolling friction mu_r in {0, 0.05, 0.1, 0.2} with sliding
friction mu in {0.3, 0.5}, for the linear law (kn = 2e4 N/m, kt = 2/7 kn) and for
Hertz-Mindlin (E = 5e7 Pa, nu = 0.25: contacts of similar stiffness at these overlaps),
restitution 0.5, the elastic-plastic rolling model (contact.rolling: epsd). The Hertz
case at mu = 0.5, mu_r = 0.1 is scenes/heap.yaml (heap-quick.yaml with --quick).
--quick runs 400 spheres (the scene heap-quick.yaml) instead of 2000 (heap.yaml).
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


def heap_scene(law="hertz", mu=0.5, mu_r=0.1, count=2000, seed=3):
    """The heap: `count` spheres in a column of 3 x 3 cm section, as tall as a quarter
    solid fraction needs, 2 cm above a 30 x 30 cm plate; run until the last sphere has
    fallen and the heap has had about 0.6 s to come to rest."""
    vol = count * 4 / 3 * np.pi * (0.00225 ** 3 + 0.0025 ** 3) / 2
    top = 0.02 + vol / 0.25 / 0.03 ** 2
    fall = np.sqrt(2 * top / 9.81)
    scene = {
        "name": f"heap-{law}-mu{mu:g}-mur{mu_r:g}",
        "dimension": 3,
        "gravity": [0, 0, -9.81],
        "domain": {"min": [-0.2, -0.2, -0.05], "max": [0.2, 0.2, round(top + 0.05, 3)]},
        "materials": {"glass": material(law, mu, mu_r, 2500),
                      "plate": material(law, mu, mu_r)},
        "particles": [{"generate": "random",
                       "region": {"min": [-0.015, -0.015, 0.02],
                                  "max": [0.015, 0.015, round(top, 4)]},
                       "count": count, "radius": {"uniform_diameter": [0.004, 0.005]},
                       "material": "glass", "seed": seed}],
        "walls": [{"polygon": [[-0.15, -0.15, 0], [0.15, -0.15, 0], [0.15, 0.15, 0],
                               [-0.15, 0.15, 0]], "material": "plate"}],
        "contact": {"rolling": "epsd"} if mu_r > 0 else {},
        "integrator": {"method": "leapfrog", "dt": "auto", "frac": 0.2},
        "run": {"duration": round(fall + 0.6, 2)},
        "output": {"every": 0.05, "energy_every": 0.01},
    }
    if not scene["contact"]:
        del scene["contact"]
    if law == "hertz":  # the time-step rule's stiffness at the pour's impact speed
        scene["integrator"]["impact_speed"] = round(float(np.sqrt(2 * 9.81 * top)), 1)
    return scene


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--esfera", default=os.path.join(ROOT, "build", "esfera"))
    ap.add_argument("--out", default=os.path.join(ROOT, "studies", "results", "heap"))
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--only", default=None, help="one law: linear or hertz")
    a = ap.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    count = 400 if a.quick else 2000
    rows = []
    laws = [a.only] if a.only else ["linear", "hertz"]
    for law in laws:
        for mu in (0.3, 0.5):
            for mu_r in (0.0, 0.05, 0.1, 0.2):
                sc = heap_scene(law, mu, mu_r, count)
                d = os.path.join(a.out, "runs", sc["name"])
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


def write_report(out, rows, count):
    lines = ["# Angle of repose of a poured heap", "",
             f"{count} spheres (diameters 4-5 mm) poured from a 3 x 3 cm column onto a "
             "30 x 30 cm plate; `studies/heap.py`"
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
    with open(os.path.join(out, "report.md"), "w") as fh:
        fh.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
