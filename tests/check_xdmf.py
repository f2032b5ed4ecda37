#!/usr/bin/python3
"""check_xdmf.py ESFERA — frames.xdmf parsed with a real XML parser (xml.etree)
against frames.h5 (h5py): a run with a box, an inclined plane and output.contacts
gives one Temporal collection each of particles, walls and contacts with one Uniform
grid per frame; every DataItem names a dataset that exists in frames.h5 with the
stated dimensions, number type and precision; topologies count their elements,
node attributes have the geometry's rows and cell attributes the elements'; times are
the frames' time attributes exactly; contact pairs index existing particles; the
particles are N vertex cells 0..N-1 (/vertex_index, whole or as a hyperslab); an empty
set has a topology without data or cell attributes. The files of one kind each
(frames_particles.xdmf, frames_walls.xdmf, frames_contacts.xdmf) hold that kind alone,
and meshio's time series reader reads the particles' file: the first frame's vertex
cells, every frame's positions and radii as in frames.h5 and, with contacts, the
coordination number (its sum: two per pair plus the wall contacts). A run whose particles leave
the domain (hyperslabs, empty contact sets) passes the same checks. Then a run killed
(SIGKILL) in the middle leaves XDMF files that still parse and describe only frames
present in frames.h5, in order."""
import os
import signal
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET

import h5py
import numpy as np

from pycheck import check, finish

SCENE = """name: xdmf-check
materials:
  g: {density: 2500, kn: 1.0e4, restitution: 0.5, friction: 0.4}
particles:
  - {generate: random, region: {min: [0.002, 0.002, 0.004], max: [0.028, 0.028, 0.05]},
     count: 150, radius: {uniform: [0.0012, 0.0018]}, material: g, seed: 3}
walls:
  - {box: {min: [0, 0, 0], max: [0.03, 0.03, 0.06]}, open: [top, xmax], material: g}
  - {plane: {point: [0.03, 0, 0], normal: [-1, 0, 0.2]}, material: g}
integrator: {method: leapfrog, dt: auto, frac: 0.2}
run: {duration: %(duration)s}
output: {every: %(every)s, energy_every: 1.0e-3, contacts: true}
"""

# Spheres falling out of the domain through an open floor: the frames hold fewer and
# fewer particles (the vertex cells become a hyperslab of /vertex_index), and the first
# frames have no contacts (empty contact sets).
LEAVING = """name: xdmf-leaving
domain: {min: [-0.01, -0.01, -0.02], max: [0.04, 0.04, 0.06]}
materials:
  g: {density: 2500, kn: 1.0e4, restitution: 0.5, friction: 0.4}
particles:
  - {generate: random, region: {min: [0.002, 0.002, 0.004], max: [0.028, 0.028, 0.05]},
     count: 60, radius: {uniform: [0.0012, 0.0018]}, material: g, seed: 3}
walls:
  - {box: {min: [0, 0, 0], max: [0.03, 0.03, 0.06]}, open: [top, bottom], material: g}
integrator: {method: leapfrog, dt: auto, frac: 0.2}
run: {duration: 0.12}
output: {every: 0.01, energy_every: 1.0e-3, contacts: true}
"""


def check_meshio(out):
    """meshio's time series reader on the particles' own file: the vertex cells of the
    first frame, and each frame's positions and radii as point data."""
    import meshio
    xdmf = os.path.join(out, "frames_particles.xdmf")
    with meshio.xdmf.TimeSeriesReader(xdmf) as r, \
            h5py.File(os.path.join(out, "frames.h5"), "r") as f:
        pts, cells = r.read_points_cells()
        n0 = len(f["frames/000000/position"])
        check(pts.shape == (n0, 3) and [(c.type, len(c.data)) for c in cells]
              == [("vertex", n0)], f"meshio: {pts.shape} points, cells "
              f"{[(c.type, len(c.data)) for c in cells]}")
        check(r.num_steps == len(f["frames"]), f"meshio: {r.num_steps} steps")
        for k in range(r.num_steps):
            t, pd, _ = r.read_data(k)
            g = f["frames/%06d" % k]
            check(t == float(g.attrs["time"]), f"meshio step {k}: time {t}")
            if len(g["position"]) == 0:  # every particle gone: no point data
                check(pd == {}, f"meshio step {k}: no data for no particles")
                continue
            check(np.array_equal(pd["position"], g["position"][()]) and
                  np.array_equal(pd["radius"], g["radius"][()]),
                  f"meshio step {k}: positions and radii as in frames.h5")
            if "contacts" in g:  # the coordination number: each contact's ends
                z = g["coordination"][()]
                want = 2 * len(g["contacts/pairs"]) + len(g["contacts/wall_pairs"])
                check(np.array_equal(pd.get("coordination"), z) and int(z.sum()) == want,
                      f"meshio step {k}: coordination as in frames.h5, sum {z.sum()} "
                      f"(2 pairs + wall contacts {want})")
        return r.num_steps



def vertex_cells(topo, dataset):
    """The Polyvertex connectivity: /vertex_index whole, or a HyperSlab of it (start 0,
    stride 1, count N)."""
    items = topo.findall("DataItem")
    if len(items) != 1:
        check(False, "one DataItem in a Polyvertex topology")
        return None
    it = items[0]
    if it.get("ItemType") == "HyperSlab":
        sub = it.findall("DataItem")
        check(len(sub) == 2 and sub[0].get("Format") == "XML", "HyperSlab: XML + HDF")
        start, stride, count = (int(v) for v in sub[0].text.split())
        n = int(it.get("Dimensions"))
        check(count == n, f"HyperSlab count {count}, Dimensions {n}")
        d = dataset(sub[1])
        return None if d is None else d[()][start:start + stride * count:stride]
    d = dataset(it)
    return None if d is None else d[()]


def validate(xdmf, complete=True, kinds=("particles", "walls", "contacts"), forces=True):
    """Checks the XDMF against the HDF5 file beside it; returns the frame count."""
    base = os.path.dirname(xdmf)
    root = ET.parse(xdmf).getroot()
    check(root.tag == "Xdmf" and root.get("Version") == "3.0", "root is Xdmf 3.0")
    dom = root.find("Domain")
    colls = {g.get("Name"): g for g in dom.findall("Grid")}
    for g in colls.values():
        check(g.get("GridType") == "Collection" and g.get("CollectionType") == "Temporal",
              f"{g.get('Name')}: a Temporal collection")
    check(set(colls) <= set(kinds), f"{sorted(colls)}: only {kinds}")
    check(kinds[0] in colls, f"a {kinds[0]} collection")
    h5files = {}

    def dataset(item):
        fname, _, dpath = item.text.strip().partition(":")
        check(not os.path.isabs(fname), f"{fname}: relative path")
        if fname not in h5files:
            h5files[fname] = h5py.File(os.path.join(base, fname), "r")
        f = h5files[fname]
        check(dpath in f, f"{dpath} referenced but absent")
        if dpath not in f:
            return None
        d = f[dpath]
        dims = tuple(int(v) for v in item.get("Dimensions").split())
        check(d.shape == dims, f"{dpath}: shape {d.shape}, XDMF says {dims}")
        kind = {"Float": "f", "Int": "i"}[item.get("NumberType")]
        check(d.dtype.kind == kind and d.dtype.itemsize == int(item.get("Precision")),
              f"{dpath}: dtype {d.dtype}, XDMF says {item.get('NumberType')}"
              f"{item.get('Precision')}")
        check(item.get("Format") == "HDF", f"{dpath}: Format HDF")
        return d

    counts = {}
    for name, coll in colls.items():
        grids = coll.findall("Grid")
        counts[name] = len(grids)
        times = []
        for g in grids:
            check(g.get("GridType") == "Uniform", f"{g.get('Name')}: Uniform")
            frame = g.get("Name").rsplit("_", 1)[1]
            t = float(g.find("Time").get("Value"))
            times.append(t)
            geo = g.find("Geometry")
            check(geo.get("GeometryType") == "XYZ", "geometry XYZ")
            gd = dataset(geo.find("DataItem"))
            npts = gd.shape[0] if gd is not None else -1
            h5 = next(iter(h5files.values()))
            check(float(h5[f"/frames/{frame}"].attrs["time"]) == t,
                  f"{g.get('Name')}: time {t!r} differs from the frame's")
            topo = g.find("Topology")
            nel = int(topo.get("NumberOfElements"))
            tt = topo.get("TopologyType")
            items = topo.findall("DataItem")
            if nel == 0:  # no cells: no data, no cell attributes (the XDMF 2 reader)
                check(not items, f"{g.get('Name')}: an empty topology has no DataItem")
                check(all(a.get("Center") != "Cell" for a in g.findall("Attribute")),
                      f"{g.get('Name')}: no cell attributes without cells")
            elif tt == "Polyvertex":
                check(nel == npts, f"{g.get('Name')}: {nel} vertices, {npts} points")
                conn = vertex_cells(topo, dataset)
                check(conn is not None and np.array_equal(conn, np.arange(npts)),
                      f"{g.get('Name')}: vertex cells 0..{npts - 1}")
            else:
                td = dataset(items[0])
                per = {"Triangle": 3, "Polyline": 2}[tt]
                if tt == "Polyline":
                    check(topo.get("NodesPerElement") == "2", "Polyline of 2 nodes")
                if td is not None:
                    check(td.shape == (nel, per), f"{g.get('Name')}: topology {td.shape}")
                    a = td[()]
                    check(a.size == 0 or (a.min() >= 0 and a.max() < npts),
                          f"{g.get('Name')}: connectivity outside the points")
            for at in g.findall("Attribute"):
                ad = dataset(at.find("DataItem"))
                rows = npts if at.get("Center") == "Node" else nel
                if ad is not None:
                    check(ad.shape[0] == rows, f"{g.get('Name')}/{at.get('Name')}: "
                          f"{ad.shape[0]} rows, expected {rows}")
                    want = 3 if at.get("AttributeType") == "Vector" else 1
                    check((ad.shape[1] if ad.ndim == 2 else 1) == want,
                          f"{at.get('Name')}: {want} components")
        check(times == sorted(times), f"{name}: times in order")
    h5 = next(iter(h5files.values()))
    nframes = len(h5["frames"])
    if "particles" in kinds and complete:
        check(counts.get("particles") == nframes,
              f"{counts.get('particles')} particle grids for {nframes} frames")
    elif "particles" in kinds:
        check(0 < counts.get("particles", 0) <= nframes,
              f"{counts.get('particles')} particle grids, {nframes} frames in the file")
    names = {a.get("Name") for a in root.iter("Attribute")}
    wanted = {"particles": ("radius", "velocity", "angular_velocity", "force",
                            "material", "id"),
              "walls": ("group", "material"),
              "contacts": ("normal_force", "tangential_force") if forces else ()}
    for k in kinds:
        for want in wanted[k]:
            check(want in names, f"attribute {want} present")
    check(("position" in names) == (kinds == ("particles",)),
          "a position attribute in the particles' own file only")
    for f in h5files.values():
        f.close()
    return counts


def run(esfera, tmp, name, duration, every, kill_after=None, text=None):
    scene = os.path.join(tmp, name + ".yaml")
    with open(scene, "w") as fh:
        fh.write(text or SCENE % {"duration": duration, "every": every})
    out = os.path.join(tmp, name)
    args = [esfera, "run", scene, "--out", out, "--quiet"]
    if kill_after is None:
        r = subprocess.run(args, capture_output=True, text=True)
        check(r.returncode == 0, f"run exit {r.returncode}: {r.stderr}")
        return out
    p = subprocess.Popen(args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    xdmf = os.path.join(out, "frames.xdmf")
    t0 = time.time()
    while time.time() - t0 < 60:
        try:
            with open(xdmf) as fh:
                if fh.read().count("<Grid Name=\"particles_") >= kill_after:
                    break
        except OSError:
            pass
        time.sleep(0.01)
    p.send_signal(signal.SIGKILL)
    p.wait()
    check(p.returncode == -signal.SIGKILL, f"the run was killed ({p.returncode})")
    return out


def main():
    esfera = sys.argv[1]
    with tempfile.TemporaryDirectory() as tmp:
        out = run(esfera, tmp, "full", 0.15, 0.025)
        counts = validate(os.path.join(out, "frames.xdmf"))
        print("complete run:", counts)
        check(counts.get("walls") == counts.get("particles") == counts.get("contacts") >= 7,
              f"7 or more frames of particles, walls and contacts: {counts}")
        check(not os.path.exists(os.path.join(out, "frames.xdmf.tmp")), "no temp file left")
        with h5py.File(os.path.join(out, "frames.h5"), "r") as f:
            pairs = f["frames/%06d/contacts/pairs" % (len(f["frames"]) - 1)][()]
            check(len(pairs) > 50, f"a settling pack has contacts ({len(pairs)})")
        for k in ("particles", "walls", "contacts"):
            c1 = validate(os.path.join(out, f"frames_{k}.xdmf"), kinds=(k,))
            check(c1 == {k: counts[k]}, f"frames_{k}.xdmf: {c1}")
        print("meshio steps:", check_meshio(out))
        out = run(esfera, tmp, "leaving", 0, 0, text=LEAVING)
        counts = validate(os.path.join(out, "frames.xdmf"), forces=False)
        with open(os.path.join(out, "frames.xdmf")) as fh:
            text = fh.read()
        check('ItemType="HyperSlab"' in text, "particles left: vertex cells as hyperslabs")
        check('TopologyType="Polyline" NumberOfElements="0"' in text,
              "frames without contacts: empty contact topologies")
        check('TopologyType="Polyvertex" NumberOfElements="0"' in text,
              "every particle gone: an empty particle grid")
        check('TopologyType="Polyvertex" NumberOfElements="0"' in text,
              "every particle gone: an empty particle grid")
        validate(os.path.join(out, "frames_particles.xdmf"), kinds=("particles",))
        print("leaving run:", counts, "meshio steps:", check_meshio(out))
        out = run(esfera, tmp, "killed", 5.0, 2.0e-4, kill_after=3)
        counts = validate(os.path.join(out, "frames.xdmf"), complete=False, forces=False)
        validate(os.path.join(out, "frames_particles.xdmf"), complete=False,
                 kinds=("particles",))
        print("killed run:", counts)
    return finish("check_xdmf")


if __name__ == "__main__":
    sys.exit(main())
