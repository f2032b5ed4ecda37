#!/usr/bin/python3
"""check_xdmf.py ESFERA — frames.xdmf parsed with a real XML parser (xml.etree)
against frames.h5 (h5py): a run with a box, an inclined plane and output.contacts
gives one Temporal collection each of particles, walls and contacts with one Uniform
grid per frame; every DataItem names a dataset that exists in frames.h5 with the
stated dimensions, number type and precision; topologies count their elements,
node attributes have the geometry's rows and cell attributes the elements'; times are
the frames' time attributes exactly; contact pairs index existing particles. Then a
run killed (SIGKILL) in the middle leaves an XDMF that still parses and describes
only frames present in frames.h5, in order."""
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



def validate(xdmf, complete=True):
    """Checks the XDMF against the HDF5 file beside it; returns the frame count."""
    base = os.path.dirname(xdmf)
    root = ET.parse(xdmf).getroot()
    check(root.tag == "Xdmf" and root.get("Version") == "3.0", "root is Xdmf 3.0")
    dom = root.find("Domain")
    colls = {g.get("Name"): g for g in dom.findall("Grid")}
    for g in colls.values():
        check(g.get("GridType") == "Collection" and g.get("CollectionType") == "Temporal",
              f"{g.get('Name')}: a Temporal collection")
    check("particles" in colls, "a particles collection")
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
            if tt == "Polyvertex":
                check(nel == npts, f"{g.get('Name')}: {nel} vertices, {npts} points")
            else:
                td = dataset(topo.find("DataItem"))
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
    if complete:
        check(counts.get("particles") == nframes,
              f"{counts.get('particles')} particle grids for {nframes} frames")
    else:
        check(0 < counts.get("particles", 0) <= nframes,
              f"{counts.get('particles')} particle grids, {nframes} frames in the file")
    names = {a.get("Name") for a in root.iter("Attribute")}
    for want in ("radius", "velocity", "angular_velocity", "force", "material", "id",
                 "normal_force", "group"):
        check(want in names, f"attribute {want} present")
    for f in h5files.values():
        f.close()
    return counts


def run(esfera, tmp, name, duration, every, kill_after=None):
    scene = os.path.join(tmp, name + ".yaml")
    with open(scene, "w") as fh:
        fh.write(SCENE % {"duration": duration, "every": every})
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
        out = run(esfera, tmp, "killed", 5.0, 2.0e-4, kill_after=3)
        counts = validate(os.path.join(out, "frames.xdmf"), complete=False)
        print("killed run:", counts)
    return finish("check_xdmf")


if __name__ == "__main__":
    sys.exit(main())
