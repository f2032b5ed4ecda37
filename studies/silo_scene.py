#!/usr/bin/python3
"""silo_scene.py -- writes a flat-bottomed cylindrical silo scene (issue 29's Beverloo
validation): the floor is an STL annulus with a round orifice of diameter D, a named
gate (an STL disc sharing the orifice's vertices) closes it while particles inserted
at run time fill the silo, and an event removes the gate so that fill and discharge
are one run. The domain's floor lies a few diameters below the orifice: particles
that fall through leave the run.

Geometry from D and the mean diameter d: silo diameter 2.5 D + 6 d (three d between
the wall and a 2.5 D zone around the orifice), fill height 1.2 silo diameters (above
the silo width, so W does not depend on the height: Janssen), the orifice and the silo
faceted with SEG vertices on their radii.

    /usr/bin/python3 studies/silo_scene.py OUTDIR NAME --D-over-d 8 [--quick]
writes OUTDIR/NAME.yaml, OUTDIR/NAME-floor.stl, OUTDIR/NAME-gate.stl; scene() returns
the numbers the study needs (t_open, count, D, d, ...).
"""
import argparse
import math
import os

SEG = 48  # facets around the orifice and the silo

# glass beads: mean diameter 4 mm, +-10 %; the quick scene: 6 mm
# (the quick scene: 6 mm, a narrower silo, 2 D + 4 d, filled to one silo diameter)
FULL = dict(d=0.004, kn=2000.0, t_settle=0.15, discharge=0.40, every=0.01, wide=2.5,
            gap=6.0, tall=1.2)
QUICK = dict(d=0.006, kn=2000.0, t_settle=0.12, discharge=0.25, every=0.01, wide=2.0,
             gap=4.0, tall=1.0)


def mean_d3(d):
    """E[diam^3] for diameters uniform on [0.9 d, 1.1 d]."""
    a, b = 0.9 * d, 1.1 * d
    return (b**4 - a**4) / (4 * (b - a))


def stl(path, tris):
    with open(path, "w") as fh:
        fh.write("solid silo\n")
        for t in tris:
            fh.write(" facet normal 0 0 1\n  outer loop\n")
            for v in t:
                fh.write(f"   vertex {v[0]:.9g} {v[1]:.9g} {v[2]:.9g}\n")
            fh.write("  endloop\n endfacet\n")
        fh.write("endsolid silo\n")


def ring(r):
    return [(r * math.cos(2 * math.pi * i / SEG), r * math.sin(2 * math.pi * i / SEG), 0.0)
            for i in range(SEG)]


def floor_and_gate(D, R_out):
    """Triangles of the annulus D/2 < r < R_out and of the disc r < D/2 (the gate),
    sharing the orifice's vertices."""
    inner, outer = ring(D / 2), ring(R_out)
    floor, gate = [], []
    for i in range(SEG):
        j = (i + 1) % SEG
        floor += [(inner[i], outer[i], outer[j]), (inner[i], outer[j], inner[j])]
        gate.append(((0.0, 0.0, 0.0), inner[i], inner[j]))
    return floor, gate


def scene(D_over_d, quick=False):
    """The scene's numbers (SI)."""
    p = dict(QUICK if quick else FULL)
    d = p["d"]
    D = D_over_d * d
    Ds = p["wide"] * D + p["gap"] * d
    R = Ds / 2
    H = p["tall"] * Ds  # fill height
    phi = 0.60  # the poured bed's solid fraction, to size the count
    count = int(phi * math.pi * R * R * H / (math.pi / 6 * mean_d3(d)))
    # the insertion box: inscribed in the faceted cylinder, above the bed's top
    a = 0.97 * R * math.cos(math.pi / SEG) / math.sqrt(2)
    z0, z1 = 1.1 * H, 1.1 * H + 0.5 * Ds
    v0 = 1.0
    # the fill's time: inserted at `rate` (the region's room may slow it), then the
    # fall from the region's top and the settling
    rate = count / 0.35
    fall = (-v0 + math.sqrt(v0 * v0 + 2 * 9.81 * z1)) / 9.81
    t_open = round(count / rate + fall + p["t_settle"], 2)
    # D_eff: the diameter of the circle with the faceted orifice's area
    D_eff = D * math.sqrt(SEG * math.sin(2 * math.pi / SEG) / (2 * math.pi))
    return dict(p, D=D, D_eff=D_eff, D_over_d=D_over_d, Ds=Ds, R=R, H=H, count=count,
                a=a, z0=z0, z1=z1, v0=v0, rate=rate, t_open=t_open,
                t_end=round(t_open + p["discharge"], 2), wall_top=z1 + d)


def yaml_text(s, name, floor_file, gate_file, quick):
    d = s["d"]
    kn = s["kn"]
    m = 4.0  # margin of the domain, diameters
    lo = [-s["R"] - m * d, -s["R"] - m * d, -m * d]
    hi = [s["R"] + m * d, s["R"] + m * d, s["wall_top"] + m * d]
    f = lambda v: "[" + ", ".join(f"{x:.6g}" for x in v) + "]"
    cmd = f"studies/silo_scene.py scenes {name} {'--quick ' if quick else ''}--D-over-d {s['D_over_d']:g}"
    return f"""# Silo discharge through a round orifice (issue 29; docs/examples.md#silo),
# written by {cmd}.
# A flat-bottomed cylindrical silo, diameter {s['Ds']*1e3:.1f} mm = {s['wide']:g} D + {s['gap']:g} d ({SEG} facets),
# is filled by run-time insertion with {s['count']} glass beads (diameters
# {0.9*d*1e3:.2f}-{1.1*d*1e3:.2f} mm, mean d = {d*1e3:g} mm) to about {s['H']*1e3:.0f} mm while a gate
# (an STL disc) closes the orifice, D = {s['D']*1e3:.1f} mm = {s['D_over_d']:g} d, in the floor (an STL
# annulus). At {s['t_open']:g} s an event removes the gate and the beads drain; they leave
# the run below the domain's floor, {m:g} d under the orifice. studies/silo.py measures
# the mass flow rate and compares it with Beverloo's law.
# Materials: a moderate kn (overlaps below 1 % of d in the bed) keeps the step large;
# kt = kn/3.5 gives the tangential oscillation (with rolling) the normal one's period;
# friction 0.5, restitution 0.5, no rolling resistance (smooth spheres).
name: {name}
dimension: 3
gravity: [0, 0, -9.81]
domain: {{min: {f(lo)}, max: {f(hi)}}}
materials:
  glass: {{density: 2500, kn: {kn:g}, kt: {kn/3.5:.10g}, restitution: 0.5,
          tangential_restitution: 0.5, friction: 0.5}}
particles:
  - insert:
      region: {{min: {f([-s['a'], -s['a'], s['z0']])}, max: {f([s['a'], s['a'], s['z1']])}}}
      rate: {s['rate']:.6g}
      count: {s['count']}
      radius: {{uniform_diameter: [{0.9*d:.6g}, {1.1*d:.6g}]}}
      material: glass
      velocity: [0, 0, {-s['v0']:g}]
      seed: 7
      every: 0.01
walls:
  - cylinder: {{base: [0, 0, 0], axis: [0, 0, 1], radius: {s['R']:.6g}, height: {s['wall_top']:.6g},
               segments: {SEG}}}
    material: glass
  - {{name: floor, mesh: {{file: {floor_file}}}, material: glass}}
  - {{name: gate, mesh: {{file: {gate_file}}}, material: glass}}
events:
  - {{at: {s['t_open']:g}, remove_wall: gate}}
integrator: {{method: leapfrog, dt: auto, frac: 0.2}}
run: {{duration: {s['t_end']:g}}}
output: {{every: {s['every']:g}, energy_every: 1.0e-3}}
"""


def write(outdir, name, D_over_d, quick=False):
    """Writes NAME.yaml and its two STL files into outdir; returns scene()."""
    s = scene(D_over_d, quick)
    floor, gate = floor_and_gate(s["D"], s["R"] + s["d"])
    ff, gf = f"{name}-floor.stl", f"{name}-gate.stl"
    stl(os.path.join(outdir, ff), floor)
    stl(os.path.join(outdir, gf), gate)
    with open(os.path.join(outdir, f"{name}.yaml"), "w") as fh:
        fh.write(yaml_text(s, name, ff, gf, quick))
    return s


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("outdir")
    ap.add_argument("name")
    ap.add_argument("--D-over-d", type=float, default=8.0)
    ap.add_argument("--quick", action="store_true")
    a = ap.parse_args()
    s = write(a.outdir, a.name, a.D_over_d, a.quick)
    print(f"{a.name}: count={s['count']} D={s['D']:.4g} Ds={s['Ds']:.4g} "
          f"t_open={s['t_open']} t_end={s['t_end']}")


if __name__ == "__main__":
    main()
