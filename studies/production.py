#!/usr/bin/python3
"""production.py — the seed scenes at full size, run to their ends: wall time against the
seeds' and each scene's outcome against what the seed shows.

    /usr/bin/python3 studies/production.py RUNS [--out DIR] [--scenes a,b,...]

RUNS holds one result directory per scene (`esfera run scenes/NAME.yaml --out
RUNS/NAME`, with its standard output in RUNS/NAME.out and, when the run was timed with
/usr/bin/time -v, its report in RUNS/NAME.err). For each scene found, the summary line
gives steps, particles, wall time, rate and threads; one function per scene measures
its outcome from the frames and the energy table; a picture of the last frame (side
view, spheres as discs to scale, coloured by material or height) goes to
DIR/NAME.png; DIR/production.csv and DIR/report.md collect the table (default DIR:
studies/results/production).

Outcomes (the seed's figure or statement in brackets):
- brazil_nut: the large sphere's height above the small spheres' mean, in small
  diameters, and the fraction of small spheres above it [it rises to the surface];
- block_impact: bonds broken, the projectile's mean position against the slab's back
  face [the projectile perforates the block];
- debris_chute, debris_chute_3d: the deposit front past the toe (studies/runout.py);
- vibrated_bed: the bed's centre of mass against time: its dominant frequency over the
  last second against the drive's [period doubling: the bed lands every other cycle];
- helical_screw: the mass flux up the screw and the grains' mean rise speed against
  the flight's pitch x rpm/60 [the screw lifts the grains];
- sand_production: grains inside the well's radius at the end, and their mass [sand is
  produced once the fluid flows];
- damping_demo: the run's rebound peaks [restitution 0.5: peaks shrink by 0.5].
"""
import argparse
import math
import os
import re
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from esfera_h5 import load_energy, load_frames  # noqa: E402
from runout import front_table  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# what the seeds report: CPU time of the full run and its machine
SEED = {"vibrated_bed": "61 h (Pentium 4 2.4 GHz)", "brazil_nut": "36 h (Pentium 4)",
        "helical_screw": "58 h (Cray SV1)", "block_impact": "50 min (Pentium 4)",
        "sand_production": "123 h (Pentium 4)", "damping_demo": "-",
        "debris_chute": "- (geometry chosen here)",
        "debris_chute_3d": "- (geometry chosen here)"}
ORDER = ["damping_demo", "brazil_nut", "block_impact", "debris_chute", "debris_chute_3d",
         "vibrated_bed", "helical_screw", "sand_production"]


def summary(runs, name):
    """The run's summary line as a dict, and its peak RSS (kB) when timed."""
    out = {}
    try:
        for ln in open(os.path.join(runs, name + ".out")):
            if ln.startswith("summary:"):
                out = dict(w.split("=", 1) for w in ln.split()[1:])
    except OSError:
        pass
    try:
        m = re.search(r"Maximum resident set size \(kbytes\): (\d+)",
                      open(os.path.join(runs, name + ".err")).read())
        out["rss_kb"] = m.group(1) if m else ""
    except OSError:
        out["rss_kb"] = ""
    return out


def last(d):
    return load_frames(d, [-1])[0]


# ------------------------------------------------------------------------ outcomes
def brazil_nut(d, t0=0.6, box=0.1):
    """The large sphere's rise from t0 (the pour settled) to the end, and the small
    spheres' vertical displacement over that time in the central column (within 25 mm
    of the axis) and along the side walls (within 15 mm): the seed's Fig. 4.15 shows
    convection, up in the centre and down at the walls."""
    frames = load_frames(d)
    a = [f for f in frames if f.time >= t0 - 1e-9][0]
    b = frames[-1]

    def rise(f):
        ids, z, r = f.data["id"], f.data["position"][:, 2], f.data["radius"]
        i, small = np.flatnonzero(ids == 0)[0], ids != 0
        ds = 2 * float(np.median(r[small]))
        return (z[i] - z[small].mean()) / ds, float((z[small] > z[i]).mean())

    (ra, fa), (rb, fb) = rise(a), rise(b)
    row = dict(zip(a.data["id"], range(len(a.data["id"]))))
    k = np.array([row[i] for i in b.data["id"]])
    xa, xb = a.data["position"][k], b.data["position"]
    dz = xb[:, 2] - xa[:, 2]
    centre = np.hypot(xa[:, 0] - box / 2, xa[:, 1] - box / 2) < 0.025
    wall = np.minimum.reduce([xa[:, 0], box - xa[:, 0], xa[:, 1], box - xa[:, 1]]) < 0.015
    return (f"from t = {a.time:.1f} to {b.time:.2f} s the large sphere rises from "
            f"{ra:.1f} to {rb:.1f} small diameters about the bed's mean height (small "
            f"spheres above it: {100 * fa:.0f}% to {100 * fb:.0f}%); convection: the "
            f"central column moves {1e3 * dz[centre].mean():+.1f} mm, the spheres along "
            f"the walls {1e3 * dz[wall].mean():+.1f} mm")


def block_impact(d, out):
    """The projectile is the material whose spheres are all of one size (the rod)."""
    f0, f = load_frames(d, [0])[0], last(d)
    mats = np.unique(f0.data["material"])
    rod = [m for m in mats if np.ptp(f0.data["radius"][f0.data["material"] == m]) < 1e-12][0]
    back = f0.data["position"][f0.data["material"] != rod, 0].max()
    x = f.data["position"][f.data["material"] == rod, 0]
    return (f"t = {f.time:.3f} s: {out.get('bonds_broken', '?')} of {out.get('bonds', '?')} "
            f"bonds broken; the projectile's mean x {x.mean() - back:+.3f} m from the "
            f"slab's back face (95th percentile {np.percentile(x, 95) - back:+.3f} m): "
            f"{'through' if x.mean() > back else 'not through'}")


def runout(d, direction, width, disks):
    frames = load_frames(d)
    t = front_table(frames, direction=direction, width=width, disks=disks)
    return (f"t = {t['time'][-1]:.2f} s: deposit front {t['front_deposit'][-1]:.2f} m past "
            f"the toe, 95th percentile {t['front_p95'][-1]:.2f} m")


def vibrated_bed(d, freq=25.0):
    e = load_energy(os.path.join(d, "energy.csv"))
    t, pe = e["time"], e["potential_gravity"]
    keep = t >= t[-1] - 1.0
    y = pe[keep] - pe[keep].mean()
    dt = float(np.median(np.diff(t[keep])))
    spec = np.abs(np.fft.rfft(y * np.hanning(len(y))))
    fr = np.fft.rfftfreq(len(y), dt)
    top = fr[1:][np.argmax(spec[1:])]
    return (f"the bed's height oscillates at {top:.2f} Hz over the last second "
            f"({top / freq:.2f} of the {freq:g} Hz drive"
            f"{': period doubling' if abs(top / freq - 0.5) < 0.05 else ''})")


def helical_screw(d, axis=(0.6, 0.6), radius=0.3, pitch=0.3, rpm=95.0, rho=3500.0,
                  z0=0.1, z1=0.4, t0=0.8):
    qs, us = [], []
    for f in load_frames(d):
        if f.time < t0:
            continue
        x, v, r = f.data["position"], f.data["velocity"], f.data["radius"]
        m = rho * 4.0 / 3.0 * math.pi * r ** 3
        ins = (np.hypot(x[:, 0] - axis[0], x[:, 1] - axis[1]) < radius) & \
              (x[:, 2] > z0) & (x[:, 2] < z1)
        qs.append(float((m[ins] * v[ins, 2]).sum()) / (z1 - z0))
        us.append(float((m[ins] * v[ins, 2]).sum() / max(m[ins].sum(), 1e-300)))
    flight = pitch * rpm / 60.0
    return (f"after {t0} s: mass flux up the screw {np.mean(qs):.1f} kg/s, grains rising "
            f"at {np.mean(us):.3f} m/s = {np.mean(us) / flight:.2f} of the flight's "
            f"{flight:.2f} m/s")


def sand_production(d, center=(0.67, 0.67), radius=0.09, rho=3000.0):
    f = last(d)
    x, r = f.data["position"], f.data["radius"]
    ins = np.hypot(x[:, 0] - center[0], x[:, 2] - center[1]) < radius
    m = rho * 4.0 / 3.0 * math.pi * r[ins] ** 3
    return (f"t = {f.time * 1e3:.1f} ms: {int(ins.sum())} grains ({m.sum():.3f} kg) inside "
            f"the well's radius")


def damping_demo(d):
    """Sphere A's (id 0) vertical speed: the ratio of successive peaks of |v_z| (half
    cycles of the oscillation on the plane) [the penetration rate halves]."""
    frames = load_frames(d)
    v = np.array([f.data["velocity"][np.flatnonzero(f.data["id"] == 0)[0], 2]
                  for f in frames])
    a = np.abs(v)
    pk = [a[i] for i in range(1, len(a) - 1) if a[i] >= a[i - 1] and a[i] > a[i + 1]]
    ratios = [pk[i + 1] / pk[i] for i in range(len(pk) - 1) if pk[i] > 0]
    if not ratios:
        return "no oscillation found in the frames"
    return (f"sphere A's speed peaks shrink by {np.median(ratios):.3f} per half cycle "
            f"({len(pk)} peaks; frames every 0.1 ms, so the peaks are sampled)")


def outcome(name, d, out):
    if name == "brazil_nut":
        return brazil_nut(d)
    if name == "block_impact":
        return block_impact(d, out)
    if name == "debris_chute":
        return runout(d, (0.819152, 0.0, 0.573576), None, True)
    if name == "debris_chute_3d":
        return runout(d, (0.819152, 0.0, 0.573576), 0.2, False)
    if name == "vibrated_bed":
        return vibrated_bed(d)
    if name == "helical_screw":
        return helical_screw(d)
    if name == "sand_production":
        return sand_production(d)
    return damping_demo(d)


# ------------------------------------------------------------------------ pictures
def picture(name, d, path):
    """The last frame seen along y: the spheres of a slice through the middle (within
    1.5 median radii of the median y, when the scene is deeper than that), discs to
    scale, coloured by height (brazil_nut: by vertical displacement since 0.6 s, the
    large sphere outlined in red; block_impact: by material)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import EllipseCollection

    f = last(d)
    x, r = f.data["position"].copy(), f.data["radius"]
    if name.startswith("debris_chute"):  # into the true frame: gravity down
        a = math.radians(35.0)
        h, g = np.array([math.cos(a), 0, math.sin(a)]), np.array([math.sin(a), 0, -math.cos(a)])
        x = np.c_[x @ h, x[:, 1], -(x @ g)]
    rm = float(np.median(r))
    sl = np.abs(x[:, 1] - np.median(x[:, 1])) < 1.5 * rm
    if np.ptp(x[:, 1]) < 3 * rm or sl.sum() < 10:
        sl = np.ones(len(r), bool)
    col, label = x[:, 2], "height (m)"
    if name == "block_impact":
        col, label = f.data["material"].astype(float), "material"
    if name == "brazil_nut":
        a = [g for g in load_frames(d) if g.time >= 0.6 - 1e-9][0]
        row = dict(zip(a.data["id"], range(len(a.data["id"]))))
        col = 1e3 * (x[:, 2] - a.data["position"][[row[i] for i in f.data["id"]], 2])
        label = "vertical displacement since 0.6 s (mm)"
    if name == "sand_production":  # the seed's Figs. 4.12-4.13: the production phase
        a = [g for g in load_frames(d) if g.time >= 0.02 - 1e-9][0]
        row = dict(zip(a.data["id"], range(len(a.data["id"]))))
        x0 = a.data["position"][[row[i] for i in f.data["id"]]]
        col = 1e3 * np.linalg.norm(x - x0, axis=1)
        label = "displacement since the fluid's start, 0.02 s (mm)"
    fig, ax = plt.subplots(figsize=(6.5, 5.5))
    ec = EllipseCollection(2 * r[sl], 2 * r[sl], 0, units="xy",
                           offsets=np.c_[x[sl, 0], x[sl, 2]], transOffset=ax.transData,
                           cmap="coolwarm" if name == "brazil_nut" else "viridis")
    ec.set_array(np.asarray(col[sl], float))
    ax.add_collection(ec)
    fig.colorbar(ec, ax=ax, label=label, shrink=0.8)
    if name == "brazil_nut":
        i = np.flatnonzero(f.data["id"] == 0)[0]
        ax.add_patch(plt.Circle((x[i, 0], x[i, 2]), r[i], fill=False, color="red", lw=2))
    ax.set_xlim(x[:, 0].min() - r.max(), x[:, 0].max() + r.max())
    ax.set_ylim(x[:, 2].min() - r.max(), x[:, 2].max() + r.max())
    flat = np.ptp(x[:, 2]) < 0.15 * np.ptp(x[:, 0])
    ax.set_aspect(5.0 if flat else "equal")  # a thin deposit: heights exaggerated 5 x
    ax.set_xlabel("x (m)")
    ax.set_ylabel("z (m)" + (", exaggerated 5 x" if flat else ""))
    ax.set_title(f"{name}, t = {f.time:.3g} s" + (", middle slice" if not sl.all() else ""))
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def hms(sec):
    sec = float(sec)
    return f"{sec:.0f} s" if sec < 120 else (f"{sec / 60:.1f} min" if sec < 7200 else
                                             f"{sec / 3600:.2f} h")


def write_report(out, rows, note=""):
    L = ["# The seed scenes at full size",
         "",
         "Generated by `studies/production.py` from full runs of `scenes/NAME.yaml` "
         "(the README's build; threads as listed). Each picture is the last frame, "
         "a slice through the middle.",
         ""] + ([note, ""] if note else []) + [
         "| scene | particles | steps | threads | wall time | particle-steps/s | "
         "peak RSS | the seed's run | outcome |",
         "|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        L.append(f"| `{r['scene']}` | {float(r['particles']):.0f} | {r['steps']} | "
                 f"{r['threads']} | {hms(r['wall_s'])} | "
                 f"{float(r['particle_steps_per_s']) / 1e6:.1f} M | "
                 f"{r['peak_rss_mb']} MB | {r['seed']} | {r['outcome']} |")
    L += [""] + [f"![{r['scene']}]({r['scene']}.png)" for r in rows]
    with open(os.path.join(out, "report.md"), "w") as fh:
        fh.write("\n".join(L) + "\n")


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("runs")
    ap.add_argument("--out", default=os.path.join(REPO, "studies", "results",
                                                  "production"))
    ap.add_argument("--scenes", default=",".join(ORDER))
    ap.add_argument("--note", default="", help="a paragraph for report.md (conditions)")
    a = ap.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    rows = []
    for name in a.scenes.split(","):
        d = os.path.join(a.runs, name)
        s = summary(a.runs, name)
        if not s or not os.path.exists(os.path.join(d, "frames.h5")):
            print(f"{name}: no finished run in {d}")
            continue
        res = outcome(name, d, s)
        picture(name, d, os.path.join(a.out, name + ".png"))
        wall = float(s["wall_s"])
        rows.append({"scene": name, "particles": s["particles"], "steps": s["steps"],
                     "threads": s["threads"], "wall_s": f"{wall:.1f}",
                     "particle_steps_per_s": s["particle_steps_per_s"],
                     "peak_rss_mb": f"{int(s['rss_kb']) / 1024:.0f}" if s["rss_kb"] else "",
                     "seed": SEED.get(name, ""), "outcome": res})
        print(f"{name}: {wall:.1f} s, {res}")
    write_report(a.out, rows, a.note)
    with open(os.path.join(a.out, "production.csv"), "w") as fh:
        keys = list(rows[0]) if rows else []
        fh.write(",".join(keys) + "\n")
        for r in rows:
            fh.write(",".join(f'"{r[k]}"' if "," in str(r[k]) else str(r[k]) for k in keys)
                     + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
