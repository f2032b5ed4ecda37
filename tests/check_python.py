#!/usr/bin/python3
"""check_python.py ROOT -- the Python module esfera (python/esfera, docs/python.md) over
the shared library (ESFERA_LIB, set by meson; PYTHONPATH=ROOT/python).

Checks: import without ESFERA_LIB (the build tree's library beside the package);
errors as esfera.Error with the located message (file:line:column) and code; the ODE
view: y0's layout against the state arrays, rhs against the library's own forces and
against central differences of the ledger's elastic energy (commits at t = 0 with the
spheres pressed together: m a = -dE/dx), free fall (a = g), rhs pure (twice the same
bits), commit (time, steps, y0 after it, back in time refused), the two uses refusing
each other; step with the leapfrog (step(k) = k x step(1), threads 1 = 2, bit for
bit) and an adaptive ERK to the scene's end; numpy views read-only and keeping the Sim
alive; the SciPy example (DOP853 and Radau on scenes/head_on.yaml) against the
no-tension closed form 0.550283 to 1e-3; the own-method example runs.
"""
import gc
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pycheck import check, finish  # noqa: E402

ROOT = sys.argv[1]
HEAD_ON = os.path.join(ROOT, "scenes", "head_on.yaml")
PACK = os.path.join(ROOT, "examples", "small_pack.yaml")
sys.path.insert(0, os.path.join(ROOT, "examples"))
import esfera  # noqa: E402


def raises(fn, code=None, pattern=None):
    """The esfera.Error fn raises (checked against code and the message pattern)."""
    try:
        fn()
    except esfera.Error as e:
        check(code is None or e.code == code, f"error code {e.code}, expected {code}")
        check(pattern is None or re.search(pattern, e.message),
              f"message {e.message!r} lacks {pattern!r}")
        return e
    check(False, f"no esfera.Error from {fn}")
    return None


def test_import():
    env = {k: v for k, v in os.environ.items() if k != "ESFERA_LIB"}
    env["PYTHONPATH"] = os.path.join(ROOT, "python")
    r = subprocess.run(["/usr/bin/python3", "-c",
                        "import esfera; print(esfera.library_path(), esfera.version())"],
                       capture_output=True, text=True, env=env, cwd=tempfile.gettempdir())
    check(r.returncode == 0, f"import without ESFERA_LIB: {r.stderr}")
    if os.path.exists(os.path.join(ROOT, "build", "libesfera.so")):
        check(r.stdout.startswith(os.path.join(os.path.realpath(ROOT), "build")) or
              r.stdout.startswith(os.path.join(ROOT, "build")),
              f"the build tree's library: {r.stdout}")
    check(esfera.version() == "0.1.0", f"version {esfera.version()}")


def test_errors(tmp):
    bad = os.path.join(tmp, "bad.yaml")
    with open(bad, "w") as fh:
        fh.write("name: bad\nmaterials:\n  glass: {density: 2500, kn: 1.0e5, frction: 1}\n")
    e = raises(lambda: esfera.Sim(bad), -1, re.escape(bad) + r":3:\d+: .*frction")
    check(e is not None and e.kind == "bad input", "kind")
    raises(lambda: esfera.Sim(HEAD_ON, set={"materials.glass.densty": 3}), -1,
           r"--set materials.glass.densty=3: unknown key 'densty'")
    raises(lambda: esfera.Sim(os.path.join(tmp, "none.yaml")), None, "none.yaml")
    s = esfera.Sim(HEAD_ON, set={"output.energy_every": 0})
    s.step(1)
    raises(lambda: s.energies, -1, r"--set output.energy_every=0: output.energy_every")
    s.close()
    raises(lambda: s.n, -1, "closed")


def test_ode():
    s = esfera.Sim(HEAD_ON)
    n = s.n
    y = s.y0()
    nq = s.ode_nq
    check(nq == len(esfera.Q_NAMES) - 1 and esfera.Q_NAMES[nq] == "dissipated_rolling",
          f"{nq} of the quadratures {esfera.Q_NAMES} without rolling resistance")
    check(y.shape == (9 * n + nq,) and s.ode_size == 9 * n + nq, f"layout {y.shape}")
    r = esfera.Sim(HEAD_ON, set={"materials.glass.rolling_friction": 0.1})
    check(r.ode_nq == len(esfera.Q_NAMES) and r.y0().shape == (9 * n + r.ode_nq,)
          and r.split(r.y0())["xi"].size == 0, "with rolling friction: its quadrature")
    r.close()
    b = s.split(y)
    check(np.array_equal(b["x"], s.positions) and np.array_equal(b["v"], s.velocities)
          and not b["q"].any() and b["xi"].size == 0, "y0 holds x, v, w, Q = 0")
    # pressed together and approaching: rhs against the library's own force array
    b["x"][:, 0] = [-0.0045, 0.0045]
    b["v"][:, 0] = [0.3, -0.3]
    f1 = s.rhs(0.0, y)
    f2 = s.rhs(0.0, y.copy())
    check(np.array_equal(f1, f2), "rhs pure: the same bits twice")
    acc = f1[3 * n:6 * n].reshape(-1, 3)
    check(np.allclose(acc * s.masses[:, None], s.forces, rtol=1e-15, atol=0),
          "m a = the library's force")
    check(acc[0, 0] < 0 and acc[1, 0] == -acc[0, 0], f"repulsion {acc[:, 0]}")
    check(np.array_equal(f1[:3 * n], y[3 * n:6 * n]), "dx/dt = v")
    check(f1[9 * n] > 0, f"dashpot power {f1[9 * n]}")
    raises(lambda: s.step(1), -1, "another")
    raises(lambda: s.commit(-1.0, y), -1, "before")
    # commit: time, steps, y0 continues from the committed y
    s.commit(2e-6, y)
    check(s.time == 2e-6 and s.steps == 1, f"commit: t {s.time} steps {s.steps}")
    check(np.array_equal(s.y0(), y), "y0 after a commit = the committed y")
    check(s.energies["time"] == 2e-6, "ledger at the commit")


def test_energy_gradient():
    """m a = -dE_el/dx by central differences of the ledger's elastic energy (spheres
    at rest pressed together; each commit at t = 0 evaluates it)."""
    s = esfera.Sim(HEAD_ON)
    n = s.n
    y = s.y0()
    y[0], y[3] = -0.0046, 0.0046
    y[3 * n:9 * n] = 0.0  # at rest: no dashpot
    a = s.rhs(0.0, y)[3 * n]

    def elastic(dx):
        z = y.copy()
        z[0] += dx
        s.commit(0.0, z)
        return s.energies["elastic"]

    h = 1e-7
    grad = (elastic(h) - elastic(-h)) / (2 * h)
    m = s.masses[0]
    check(abs(m * a + grad) <= 1e-7 * abs(grad), f"m a {m * a:.12g} vs -dE/dx {-grad:.12g}")


def test_free_fall():
    s = esfera.Sim(PACK)
    n = s.n
    y = s.y0()
    f = s.rhs(0.0, y)
    az = f[3 * n + 2:6 * n:3]
    free = np.isclose(np.abs(s.forces).sum(axis=1), s.masses * 9.81, rtol=1e-14, atol=0)
    check(free.sum() > n // 2, f"free particles {free.sum()} of {n}")
    check(np.allclose(az[free], -9.81, rtol=1e-15, atol=0), f"free fall a_z {az[free][:3]}")


def test_step_and_views():
    s = esfera.Sim(HEAD_ON)
    dt = s.dt
    p = s.positions
    check(not p.flags.writeable and p.shape == (2, 3), "read-only n x 3 view")
    s.step(10)
    check(s.steps == 10 and abs(s.time - 10 * dt) < 1e-18, f"step: {s.steps} {s.time}")
    check(p[0, 0] == s.positions[0, 0] and p[0, 0] > -0.0051, "the view follows the state")
    raises(lambda: s.y0(), -1, "another")
    s.run()
    check(s.time >= s.end_time and s.energies["dissipated_contact"] > 0, "run to the end")
    v = s.velocities
    del s
    gc.collect()
    check(v[1, 0] > 0.5, f"a view keeps its Sim alive: {v[1, 0]}")


def test_step_bits():
    """step(k) takes the fused leapfrog's bursts: the same bits as k calls of step(1);
    an adaptive ERK stops at the scene's end and then refuses."""
    a, b, c = esfera.Sim(PACK, threads=1), esfera.Sim(PACK, threads=1), \
        esfera.Sim(PACK, threads=2)
    a.step(1500)
    c.step(1500)
    for _ in range(1500):
        b.step(1)
    check(np.array_equal(a.positions, b.positions) and
          np.array_equal(a.velocities, b.velocities) and a.energies == b.energies,
          "step(k) = k x step(1), bit for bit")
    check(np.array_equal(a.positions, c.positions) and a.energies == c.energies,
          "threads 1 and 2: the same bits")
    raises(lambda: esfera.Sim(PACK, threads=0), -1, "1 to 1024")
    c = esfera.Sim(HEAD_ON, set={"integrator.method": "erk:ARKODE_DORMAND_PRINCE_7_4_5",
                                 "integrator.rtol": 1e-8})
    c.step(10 ** 6)
    v = c.velocities[:, 0]
    check(c.time == c.end_time and abs((v[1] - v[0]) / 2 - 0.550283) < 1e-3,
          f"adaptive ERK to the end: t {c.time}, restitution {(v[1] - v[0]) / 2}")
    raises(lambda: c.step(1), -1, r"head_on.yaml:\d+:\d+: run.duration: .*end time")


def test_scipy():
    import scipy_head_on as ex
    from scipy.integrate import DOP853, Radau
    exact = ex.closed_form(0.5)
    check(abs(exact - 0.550283) < 5e-7, f"closed form {exact}")
    for cls in (DOP853, Radau):
        e, steps, nfev, err = ex.integrate(HEAD_ON, cls, 1e-8, 1e-12)
        print(f"{cls.__name__}: restitution {e:.6f} ({steps} steps, {nfev} rhs), "
              f"ledger error {err:.2e} J")
        check(abs(e - 0.550283) < 1e-3, f"{cls.__name__}: restitution {e}")
        check(abs(err) < 1e-8, f"{cls.__name__}: ledger error {err}")
    r = subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "examples", "own_method.py")],
                       capture_output=True, text=True)
    check(r.returncode == 0 and "leapfrog" in r.stdout, f"own_method.py: {r.stderr}")
    print(r.stdout.splitlines()[-1] if r.stdout else "")


with tempfile.TemporaryDirectory() as tmp:
    test_import()
    test_errors(tmp)
    test_ode()
    test_energy_gradient()
    test_free_fall()
    test_step_and_views()
    test_step_bits()
    test_scipy()
sys.exit(finish("python"))
