#!/usr/bin/python3
"""frame_to_csv.py — one frame of an esfera frames.h5 as a particle CSV (x, y, z, radius,
vx, vy, vz, wx, wy, wz) that a scene reads with `particles: - {file: ..., material: ...}`.

usage: frame_to_csv.py FRAMES.h5 FRAME OUT.csv   (FRAME: index, negative from the end)
Used to make the packings of the polydisperse contact-search benchmark (bench_cells,
docs in tests/meson.build): settle a scene, then start benchmark runs from its frames.
Velocities are the frame's (half-step) ones; the contact history is not carried."""
import sys

import h5py
import numpy as np


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    with h5py.File(sys.argv[1], "r") as f:
        names = sorted(f["frames"].keys())
        g = f["frames"][names[int(sys.argv[2])]]
        x = g["position"][...]
        r = g["radius"][...]
        v = g["velocity"][...]
        w = g["angular_velocity"][...]
        t = g.attrs.get("time", float("nan"))
    data = np.column_stack([x, r, v, w])
    np.savetxt(sys.argv[3], data, delimiter=",", fmt="%.17g",
               header="x,y,z,radius,vx,vy,vz,wx,wy,wz", comments="")
    print("%s: frame %s at t = %g s, %d particles" % (sys.argv[3], names[int(sys.argv[2])],
                                                     t, len(r)))


if __name__ == "__main__":
    main()
