"""shear_cell_pack.py -- the packing of the Lees-Edwards shear cell (scenes/shear_cell*.yaml):
n x n x n FCC cells (4 n^3 spheres) in a cubic periodic box whose side sets the solid
fraction phi, diameters uniform in [0.9, 1.1] d (drawn with a seeded generator), the
diameters of touching lattice neighbours swapped until no two spheres overlap (the
lattice's nearest distance must exceed the mean of the two diameters), and small random
velocities (0.01 of d per unit time scale, zero mean) so that the shear melts the
lattice. Usage: shear_cell_pack.py N_CELLS PHI OUT.csv [SEED]; prints the box side (m)."""
import math
import random
import sys

D = 2.0e-3  # mean diameter, m


def pack(ncell, phi, seed=1):
    rnd = random.Random(seed)
    n = 4 * ncell**3
    dia = [D * rnd.uniform(0.9, 1.1) for _ in range(n)]
    vol = sum(math.pi / 6 * x**3 for x in dia)
    side = (vol / phi) ** (1 / 3)
    a = side / ncell
    basis = [(0, 0, 0), (0.5, 0.5, 0), (0.5, 0, 0.5), (0, 0.5, 0.5)]
    pos = [((i + b[0]) * a, (j + b[1]) * a, (k + b[2]) * a)
           for i in range(ncell) for j in range(ncell) for k in range(ncell) for b in basis]
    dnn = a / math.sqrt(2)
    nbr = [[] for _ in range(n)]
    for p in range(n):
        for q in range(p + 1, n):
            d2 = 0.0
            for c in range(3):
                u = abs(pos[p][c] - pos[q][c])
                u = min(u, side - u)
                d2 += u * u
            if d2 < (1.01 * dnn) ** 2:
                nbr[p].append(q)
                nbr[q].append(p)

    def bad(p):
        return any(0.5 * (dia[p] + dia[q]) > 0.999 * dnn for q in nbr[p])

    for _ in range(200 * n):
        over = [p for p in range(n) if bad(p)]
        if not over:
            break
        p = rnd.choice(over)
        q = rnd.randrange(n)
        dia[p], dia[q] = dia[q], dia[p]
        if bad(p) or bad(q):
            dia[p], dia[q] = dia[q], dia[p]
    else:
        raise SystemExit("no overlap-free assignment found: lower phi")
    rows = []
    for p in range(n):
        v = [rnd.gauss(0, 1e-3) for _ in range(3)]
        rows.append((pos[p], 0.5 * dia[p], v))
    mean = [sum(r[2][c] for r in rows) / n for c in range(3)]
    return side, [(x, r, [v[c] - mean[c] for c in range(3)]) for x, r, v in rows]


def write(path, rows):
    with open(path, "w") as f:
        f.write("x,y,z,radius,vx,vy,vz,wx,wy,wz\n")
        for x, r, v in rows:
            f.write(",".join(repr(float(t)) for t in (*x, r, *v, 0, 0, 0)) + "\n")


if __name__ == "__main__":
    nc, phi, out = int(sys.argv[1]), float(sys.argv[2]), sys.argv[3]
    side, rows = pack(nc, phi, int(sys.argv[4]) if len(sys.argv) > 4 else 1)
    write(out, rows)
    print(repr(side))
