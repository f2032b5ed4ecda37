#!/usr/bin/python3
"""check_generate.py ESFERA — `esfera generate` (model generation by successive copies,
004 §3.3). 150 monodisperse spheres (r = 1 mm, mu 0.5) settle in a 12 x 12 x 24 mm box,
are copied 2 x 2 x 2 and settle again (1200 spheres). Checks:
- without the second settling (resettle.max_time: 0) copy (i, j, k) is the primary set
  translated by exactly (i L_x, j L_y, k H) with one H for every particle of a layer;
- after it, no pair overlaps more than 1% of a radius (the static overlap under the
  bed's weight is ~ n_layers m g / k_n ~ 1e-3 r here) and no particle leaves the box;
- the bed height h = 2 z_mean: the upper copies start a gap (H - h1, H the primary
  set's highest top, h1 its height) above the lower ones and cannot rise (no energy
  source), so h <= h1 + H; the settling closes that gap and the loose layers the
  primary box's walls left at the copies' interfaces, but the bed cannot pass the
  random close packing, so h >= N V / (A 0.64);
- the porosity of the core (one diameter from the walls and the floor, two below the
  surface) lies in 0.36-0.45, the range of random monodisperse packings (dense random
  0.36, poured frictional ~0.40-0.44);
- the same seed gives a byte-identical file; the file loads in a run scene;
- compaction (copies 2 x 2 x 1, lateral strain 0.1 over 0.1 s, then resettling): every
  particle inside the compacted box, no overlap above 1% of r, and the bulk solid
  fraction N V / (A 2 z_mean) rises (measured 0.520 -> 0.541): a poured pack, looser
  than random close packing, compacts under slow lateral compression;
- `esfera run` on a generate scene and a bad generate key exit 2."""
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

from pycheck import check, finish, run_scene, run_sets

R = 0.001
SCENE = """name: gen-check
materials:
  glass: {density: 2500, kn: 1.0e4, restitution: 0.2, friction: 0.5}
particles:
  - {generate: random, region: {min: [0, 0, 0], max: [0.012, 0.012, 0.024]}, count: 150,
     radius: 0.001, material: glass, seed: 5}
generate:
  box: {min: [0, 0, 0], max: [0.012, 0.012, 0.024]}
  copies: [2, 2, 2]
  material: glass
  settle: {ke_fraction: 1.0e-4, max_time: 0.3, check_every: 0.005}
  resettle: {max_time: 0.15}
integrator: {method: leapfrog, dt: auto, frac: 0.08}
"""


def load(path):
    rows = [ln.strip().split(",") for ln in open(path) if not ln.startswith("#")][1:]
    return np.array([[float(v) for v in r[:4]] for r in rows]), [r[4] for r in rows]


def generate(esfera, scene, out, *sets):
    r = run_sets(esfera, scene, out, *sets, command="generate")
    stages = {m.group(1): dict(kv.split("=") for kv in m.group(2).split() if "=" in kv)
              for m in re.finditer(r"stage=(\w+) (.*)", r.stdout)}
    return stages, r.stdout


def solid_fraction(P, lo, hi, h):
    """Fraction of a grid of spacing h in [lo, hi] inside some sphere."""
    g = [np.arange(lo[k] + h / 2, hi[k], h) for k in range(3)]
    occ = np.zeros([len(a) for a in g], bool)
    for x, y, z, r in P:
        sl, cs = [], []
        for k, c in enumerate((x, y, z)):
            i0, i1 = np.searchsorted(g[k], c - r), np.searchsorted(g[k], c + r)
            sl.append(slice(i0, i1))
            cs.append(g[k][i0:i1] - c)
        d2 = cs[0][:, None, None] ** 2 + cs[1][None, :, None] ** 2 + cs[2][None, None, :] ** 2
        occ[sl[0], sl[1], sl[2]] |= d2 <= r * r
    return occ.mean()


def main():
    esfera = sys.argv[1]
    with tempfile.TemporaryDirectory() as tmp:
        scene = os.path.join(tmp, "g.yaml")
        with open(scene, "w") as fh:
            fh.write(SCENE)
        # the copies before the second settling
        st0, log0 = generate(esfera, scene, os.path.join(tmp, "c.csv"),
                          "generate.resettle.max_time=0")
        C, _ = load(os.path.join(tmp, "c.csv"))
        check(len(C) == 1200, f"1200 particles, got {len(C)}")
        n0, L = 150, 0.012
        P0 = C[:n0]
        H = float(st0["primary"]["top"])
        check(re.search(r"stage=primary .* settled ", log0), f"primary settled: {log0}")
        worst, Hk = 0.0, []
        for c in range(8):
            i, j, k = c % 2, (c // 2) % 2, c // 4
            off = C[c * n0:(c + 1) * n0, :3] - P0[:, :3]
            Hk.append(off[:, 2].mean())
            worst = max(worst, np.abs(off - [i * L, j * L, Hk[-1]]).max())
            check(np.array_equal(C[c * n0:(c + 1) * n0, 3], P0[:, 3]), f"copy {c} radii")
        print(f"copies: periodic-image deviation {worst:.3g} m, layer offsets {Hk[0]:.6g}, "
              f"{Hk[4]:.6g} m (top of the primary set H = {H:.6g} m)")
        check(worst < 1e-15, f"copies are the primary set translated, deviation {worst}")
        check(Hk[:4] == [0.0] * 4 and abs(Hk[4] - H) < 1e-6 * H and Hk[4:] == [Hk[4]] * 4,
              f"layer offsets {Hk} against H = {H}")
        h1 = 2 * P0[:, 2].mean()  # bed height of the primary set (uniform bed: 2 z_mean)

        # the settled packing
        out = os.path.join(tmp, "p.csv")
        st, log = generate(esfera, scene, out)
        print(log.strip())
        P, mats = load(out)
        x, r = P[:, :3], P[:, 3]
        d = 2 * R
        diff = x[:, None, :] - x[None, :, :]
        dist = np.sqrt((diff ** 2).sum(-1)) + np.eye(len(P)) * 1.0
        ov = (r[:, None] + r[None, :] - dist).max()
        print(f"largest pair overlap {ov:.3g} m = {ov / R:.3g} r")
        check(ov < 0.01 * R, f"largest overlap {ov} m >= 1% of r")
        lo = (x - r[:, None]).min(0)
        hi = (x + r[:, None]).max(0)
        check(lo.min() > -0.01 * R and hi[0] < 2 * L + 0.01 * R and hi[1] < 2 * L + 0.01 * R,
              f"particles inside the box: {lo} {hi}")
        h = 2 * x[:, 2].mean()
        print(f"bed height 2 z_mean {h:.6g} m; primary set's h1 = {h1:.6g} m, top H = {H:.6g}")
        h_rcp = (4 / 3 * np.pi * r ** 3).sum() / ((2 * L) ** 2 * 0.64)
        print(f"bounds: random close packing {h_rcp:.6g} m, h1 + H {h1 + H:.6g} m")
        check(h_rcp <= h <= h1 + H, f"bed height {h} outside [{h_rcp}, {h1 + H}]")
        surf = np.percentile(x[:, 2] + r, 95)
        phi = solid_fraction(P, [d, d, d], [2 * L - d, 2 * L - d, surf - 2 * d], d / 20)
        print(f"core porosity {1 - phi:.4f} (solid fraction {phi:.4f})")
        check(0.36 <= 1 - phi <= 0.45, f"porosity {1 - phi} outside 0.36-0.45")

        # reproducible; loadable
        generate(esfera, scene, os.path.join(tmp, "p2.csv"))
        same = open(out, "rb").read() == open(os.path.join(tmp, "p2.csv"), "rb").read()
        check(same, "the same seed gives the same file")
        run_scene(esfera, tmp, f"""name: load
materials:
  glass: {{density: 2500, kn: 1.0e4, restitution: 0.2, friction: 0.5}}
particles:
  - {{file: {out}}}
walls:
  - {{box: {{min: [0, 0, 0], max: [0.024, 0.024, 0.04]}}, open: [top], material: glass}}
integrator: {{method: leapfrog, dt: auto, frac: 0.08}}
run: {{steps: 20}}
output: {{energy_every: 0}}
""")

        # compaction against the same copies without it
        sf = {}
        for name, sets in (("plain", ()),
                           ("compacted", ("generate.compact={strain: 0.1, time: 0.1}",))):
            p = os.path.join(tmp, name + ".csv")
            _, log = generate(esfera, scene, p, "generate.copies=[2,2,1]", *sets)
            Q, _ = load(p)
            lo, hi = (0.0012, 0.0228) if sets else (0.0, 2 * L)
            q, rq = Q[:, :3], Q[:, 3]
            sf[name] = (4 / 3 * np.pi * rq ** 3).sum() / ((hi - lo) ** 2 * 2 * q[:, 2].mean())
            inside = ((q[:, :2] - rq[:, None]).min() >= lo - 0.01 * R
                      and (q[:, :2] + rq[:, None]).max() <= hi + 0.01 * R)
            check(inside, f"{name}: particles inside [{lo}, {hi}]")
            dq = q[:, None, :] - q[None, :, :]
            dd = np.sqrt((dq ** 2).sum(-1)) + np.eye(len(Q))
            ovq = (rq[:, None] + rq[None, :] - dd).max()
            check(ovq < 0.01 * R, f"{name}: largest overlap {ovq} m")
            if sets:
                check("stage=compact " in log and "stage=compacted " in log, log)
        print(f"bulk solid fraction: {sf['plain']:.4f} plain, {sf['compacted']:.4f} "
              f"compacted")
        check(sf["compacted"] > sf["plain"], f"compaction raises the solid fraction {sf}")

        # bad input
        with open(out, "rb") as fh:
            before = fh.read()
        r = subprocess.run([esfera, "run", scene, "--quiet"], capture_output=True, text=True)
        check(r.returncode == 2 and "generate" in r.stderr, f"run a generate scene: {r}")
        r = subprocess.run([esfera, "generate", scene, "--out", out, "--set",
                            "generate.copeis=[1,1,1]"], capture_output=True, text=True)
        check(r.returncode == 2 and "copeis" in r.stderr, f"misspelt key: {r.stderr}")
        r = subprocess.run([esfera, "generate", scene], capture_output=True, text=True)
        check(r.returncode == 2 and "--out" in r.stderr, f"no --out: {r.stderr}")
        with open(out, "rb") as fh:
            check(fh.read() == before, "a failed generate leaves the file intact")
    return finish("generate")


if __name__ == "__main__":
    sys.exit(main())
