#!/usr/bin/python3
"""scipy_head_on.py -- integrate scenes/head_on.yaml with SciPy's DOP853 and Radau
through esfera's ODE view, and print the normal restitution against the closed form.

    PYTHONPATH=python /usr/bin/python3 examples/scipy_head_on.py [SCENE] [--rtol R]

Two equal spheres meet head-on at 1 m/s each. The linear spring-dashpot law with
restitution e sets the damping ratio zeta = -ln e / sqrt(pi^2 + ln^2 e) (docs/physics.md);
the force kn u + cn du/dt is cut at zero (no tension), so the spheres part when it
vanishes, before the overlap closes, with a restitution above e (0.550283 for e = 0.5):
with s = sqrt(1 - zeta^2) the force vanishes at s tau = pi - atan(2 zeta s / (1 -
2 zeta^2)) (tau = omega_n t), and the restitution is
  e_nt = -exp(-zeta tau) (cos(s tau) - zeta / s sin(s tau)).
Each solver takes its own steps (solver.step()), at most ten of the scene's; every
accepted step is committed to esfera (sim.commit), which keeps the contact history
frozen within a step.
"""
import argparse
import math
import os
import sys

import numpy as np
from scipy.integrate import DOP853, Radau

import esfera

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def closed_form(e):
    """The restitution of the linear spring-dashpot with restitution e, force cut at
    zero (no tension)."""
    le = math.log(e)
    zeta = -le / math.sqrt(math.pi ** 2 + le ** 2)
    s = math.sqrt(1 - zeta ** 2)
    st = math.pi - math.atan(2 * zeta * s / (1 - 2 * zeta ** 2))
    tau = st / s
    return -math.exp(-zeta * tau) * (math.cos(st) - zeta / s * math.sin(st))


def integrate(scene, solver_cls, rtol, atol):
    """Runs the scene to its end time with the SciPy solver, committing every accepted
    step; returns (restitution, steps, rhs evaluations, ledger total_error)."""
    sim = esfera.Sim(scene)
    n = sim.n
    y0 = sim.y0()
    rel0 = y0[3 * n + 3] - y0[3 * n]  # x-velocity of sphere 2 relative to sphere 1
    nfev = [0]

    def f(t, y):
        nfev[0] += 1
        return sim.rhs(t, y)

    # steps no longer than ten of the scene's (its critical step's tenth): a first
    # trial step chosen from the free flight alone would drive the spheres through
    # each other, which esfera reports as an error rather than a rejected step
    sol = solver_cls(f, sim.time, y0, sim.end_time, rtol=rtol, atol=atol,
                     first_step=sim.dt, max_step=10 * sim.dt)
    while sol.status == "running":
        msg = sol.step()
        if sol.status == "failed":
            sys.exit(f"{solver_cls.__name__}: {msg}")
        sim.commit(sol.t, sol.y)
    v = sim.velocities
    e = -(v[1, 0] - v[0, 0]) / rel0
    return e, sim.steps, nfev[0], sim.energies["total_error"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    ap.add_argument("scene", nargs="?", default=os.path.join(ROOT, "scenes", "head_on.yaml"))
    ap.add_argument("--rtol", type=float, default=1e-8)
    ap.add_argument("--atol", type=float, default=1e-12)
    a = ap.parse_args()
    exact = closed_form(0.5)
    print(f"closed form (restitution 0.5, no tension): {exact:.6f}")
    worst = 0.0
    for cls in (DOP853, Radau):
        e, steps, nfev, err = integrate(a.scene, cls, a.rtol, a.atol)
        worst = max(worst, abs(e - exact))
        print(f"{cls.__name__:7s} restitution {e:.6f}  error {e - exact:+.2e}  "
              f"({steps} steps, {nfev} rhs evaluations, ledger total_error {err:.2e} J)")
    return 0 if worst < 1e-3 else 1


if __name__ == "__main__":
    sys.exit(main())
