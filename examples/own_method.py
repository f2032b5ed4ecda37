#!/usr/bin/python3
"""own_method.py -- a time integrator of your own against esfera's leapfrog, on a
small pack (examples/small_pack.yaml: 60 spheres dropped into a box).

    PYTHONPATH=python /usr/bin/python3 examples/own_method.py [SCENE] [--h-factor F]

The method here is the classical fourth-order Runge-Kutta, written in numpy over
esfera's ODE view: each step evaluates sim.rhs four times (the contact histories stay
frozen at the last commit) and commits the step (sim.commit), which carries the
tangential springs over it, updates the ledger and refreshes the contact lists.
Replace rk4_step with your own. The leapfrog runs the same scene on a second Sim with
sim.step(). Every fifth of the run both print the pack's centre-of-mass height, their kinetic
energies and their energy ledgers' residuals (total_error: energy not accounted for by
the stored, dissipated and wall energies; 0 for an exact integration).
"""
import argparse
import os
import sys

import numpy as np

import esfera

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def rk4_step(f, t, y, h):
    """One classical Runge-Kutta step of y' = f(t, y)."""
    k1 = f(t, y)
    k2 = f(t + h / 2, y + h / 2 * k1)
    k3 = f(t + h / 2, y + h / 2 * k2)
    k4 = f(t + h, y + h * k3)
    return y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)


def report(name, sim):
    m = sim.masses
    z = float(m @ sim.positions[:, 2] / m.sum())
    e = sim.energies
    ke = e["kinetic_translational"] + e["kinetic_rotational"]
    print(f"  {name:9s} t = {sim.time * 1e3:6.2f} ms  z_cm = {z * 1e3:8.4f} mm  "
          f"kinetic = {ke:.4e} J  total_error = {e['total_error']:+.2e} J")
    return z, ke


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    ap.add_argument("scene", nargs="?", default=os.path.join(ROOT, "examples",
                                                             "small_pack.yaml"))
    ap.add_argument("--h-factor", type=float, default=1.0,
                    help="the Runge-Kutta step as a multiple of the scene's dt")
    a = ap.parse_args()
    own, ref = esfera.Sim(a.scene), esfera.Sim(a.scene)
    h = a.h_factor * own.dt
    print(f"{a.scene}: {own.n} particles, leapfrog dt = {ref.dt:.4g} s, rk4 h = {h:.4g} s,"
          f" to t = {own.end_time:.4g} s")
    y, t, nrhs = own.y0(), own.time, 0

    def f(t, y):
        nonlocal nrhs
        nrhs += 1
        return own.rhs(t, y)

    worst = 0.0
    for k in range(1, 6):
        t_out = own.end_time * k / 5
        while own.steps < round(t_out / h):
            y = rk4_step(f, t, y, h)
            t = (own.steps + 1) * h
            own.commit(t, y)
            y = own.y0()  # the committed state (the same y with frozen history)
        ref.step(max(0, round(t_out / ref.dt) - ref.steps))
        print(f"after {t_out * 1e3:.0f} ms:")
        (z1, _), (z2, _) = report("own rk4", own), report("leapfrog", ref)
        worst = max(worst, abs(z1 - z2))
    print(f"{own.steps} rk4 steps ({nrhs} right-hand sides), {ref.steps} leapfrog steps;"
          f" largest centre-of-mass height difference {worst * 1e3:.3g} mm")
    return 0


if __name__ == "__main__":
    sys.exit(main())
