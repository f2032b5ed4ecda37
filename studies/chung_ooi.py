#!/usr/bin/python3
"""chung_ooi.py -- the oblique impacts of Chung & Ooi (2011), tests 4-7, with esfera's
Hertz-Mindlin law, against the paper's published curves (digitised:
chung_ooi_published.py) and the rigid-body closed forms of gross sliding.

Chung Y.C., Ooi J.Y., Granular Matter 13 (2011) 643-656. The tests' definitions and
data, as the peer codes' inputs for these tests give them (the paper itself was not
available here): Yade's Chung & Ooi scripts (test 4), LIGGGHTS-PFM's
examples/LIGGGHTS/PFM/tests/contact_models/chung/test04..test07, and the PySPH fork
github.com/dineshadepu/pysph (tests 4, 5); they agree where they overlap. One sphere and
a rigid plane, or two spheres; no gravity:
  test4  R = 2.5 mm, |v| = 3.9 m/s at 5-85 deg from the normal, no spin, e = 0.98,
         mu = 0.092; aluminium oxide (E 380 GPa, nu 0.23, rho 4000) and aluminium alloy
         (70 GPa, 0.33, 2700). Observed: e_t = v_t'/v_t and the spin w' (rad/s).
  test5  R = 10 um, v_n = 5 m/s, v_t = 0.1-21 m/s, e = 1, mu = 0.3; steel (208 GPa, 0.3,
         7850) and polyethylene (1 GPa, 0.4, 1400). Observed against
         Psi_in = v_t/(mu v_n): the recoil angle Psi_out = v_c'/(mu v_n') (v_c the
         contact point's tangential velocity) and the spin R w'/(mu v_n).
  test6  R = 0.1 m, v_n = 0.2 m/s, no v_t, spin w0 = 0.175-21 rad/s, e = 0.5, mu = 0.4;
         aluminium alloy and nylon (2.5 GPa, 0.4, 1000). Observed against
         Psi_in = R w0/v_n: the contact point's tangential restitution
         beta = -v_c'/v_c0 and Psi_out = v_c'/v_n'.
  test7  two identical spheres, R = 0.1 m, +-0.2 m/s, spins +w0 and -w0 (their contact
         points move together), e = 0.5, mu = 0.4; aluminium alloy and copper (120 GPa,
         0.35, 8900). Exact: nothing slides, w' = w0 and v_t' = 0.
The plane is rigid: sphere and wall both get 2E and the sphere's nu, which makes
E* = E/(1 - nu^2) and G* = G/(2 - nu) exactly those of a rigid plane. No tangential
dashpot (tangential_restitution 1), the normal one from e (contact.hertz_damping
default, tsuji). The wall contact acts on the plane's surface, lever R - u
(contact.wall_lever: surface; the default, the seed's R - u/2, puts it halfway through
the overlap). Leapfrog at dt = t_H/400 (t_H the elastic Hertz contact time).

The law's own solution ("model"): each wall impact is also integrated by
model_reference, independently of esfera (semi-implicit Euler at t_H/4000, the dashpot's
gamma found by bisection so that the normal restitution is e): esfera's distance from it
is the implementation's and the step's error; the distance between the model and the
published curves is the law's.

Closed forms (solid sphere, I = 2/5 m R^2, wall): sliding throughout, when
v_c0 >= 7/2 mu (1 + e) v_n: v_t' = v_t - mu (1 + e) v_n, R w' = 5/2 mu (1 + e) v_n
(from w0 = 0), v_c' = v_c0 - 7/2 mu (1 + e) v_n; rigid sticking (no compliance):
v_c' = 0, hence e_t = 5/7 from rest.

Run: /usr/bin/python3 studies/chung_ooi.py [--out DIR] [--esfera PATH] [--tests 4,5]
Writes DIR (default studies/results/chung_ooi/): chung_ooi.csv (every impact), test4.png
.. test7.png and report.md (chung_ooi_report.py). About 10 s.
"""
import argparse
import math
import os
import shutil
import sys

import numpy as np

import chung_ooi_published as pub
from common import last_frame, run, write_csv, write_scene

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

MATERIALS = {  # E (Pa), nu, rho (kg/m^3): Chung & Ooi's materials (see the docstring)
    "al_oxide": (3.8e11, 0.23, 4000.0), "al_alloy": (7.0e10, 0.33, 2700.0),
    "steel": (2.08e11, 0.30, 7850.0), "polyethylene": (1.0e9, 0.40, 1400.0),
    "nylon": (2.5e9, 0.40, 1000.0), "copper": (1.2e11, 0.35, 8900.0)}
NAMES = {"al_oxide": "aluminium oxide", "al_alloy": "aluminium alloy", "steel": "steel",
         "polyethylene": "polyethylene", "nylon": "nylon", "copper": "copper"}

TESTS = {
    4: dict(R=2.5e-3, e=0.98, mu=0.092, materials=("al_oxide", "al_alloy"), speed=3.9,
            params=[5.0 * k for k in range(1, 18)]),  # angle (deg)
    5: dict(R=1.0e-5, e=1.0, mu=0.3, materials=("steel", "polyethylene"), vn=5.0,
            params=[0.1, 0.3, 0.45, 0.6, 0.9, 1.2, 1.5, 1.8, 2.25, 2.7, 3.0, 3.75, 4.5,
                    5.25, 6.0, 7.5, 9.0, 12.0, 15.0, 18.0, 21.0]),  # v_t (m/s)
    6: dict(R=0.1, e=0.5, mu=0.4, materials=("al_alloy", "nylon"), vn=0.2,
            params=[0.175, 0.3, 0.42, 0.6, 0.8, 1.0, 1.2, 1.5, 2.0, 2.4, 2.8, 3.0, 3.5,
                    4.0, 6.0, 8.0, 10.0, 12.0, 14.0, 21.0]),  # w0 (rad/s)
    7: dict(R=0.1, e=0.5, mu=0.4, materials=("al_alloy", "copper"), vn=0.2,
            params=[0.175, 0.3, 0.6, 1.0, 2.0, 4.0, 8.0, 14.0, 21.0])}  # w0 (rad/s)
STEPS_PER_CONTACT = 400
OBSERVABLES = ("e_n", "e_t", "omega", "recoil", "spin", "beta")


def mass(mat, R):
    return MATERIALS[mat][2] * 4.0 / 3.0 * math.pi * R ** 3


def hertz_time(m_eff, r_eff, e_eff, v):
    """Elastic Hertz contact time 2 (u_max/v) int_0^1 dx/sqrt(1 - x^(5/2)), with
    u_max = (15 m v^2 / (16 E* sqrt(R*)))^(2/5); the integral is (2/5) B(2/5, 1/2)."""
    u_max = (15.0 * m_eff * v * v / (16.0 * e_eff * math.sqrt(r_eff))) ** 0.4
    integral = 0.4 * math.gamma(0.4) * math.gamma(0.5) / math.gamma(0.9)
    return 2.0 * u_max / v * integral


def case(test, mat, p):
    """Initial (v_t, v_n, w0) of one impact: v_n > 0 toward the wall, v_t along +x, the
    spin -w0 about y (scene_yaml), so that the contact point slides at v_t + R w0."""
    t = TESTS[test]
    if test == 4:
        th = math.radians(p)
        return t["speed"] * math.sin(th), t["speed"] * math.cos(th), 0.0
    if test == 5:
        return p, t["vn"], 0.0
    return 0.0, t["vn"], p


def scene_yaml(test, mat, p, steps=STEPS_PER_CONTACT):
    """The scene of one impact and its end time. Sphere above the plane z = 0 (or two
    spheres meeting at z = 0), moving down at v_n, along +x at v_t, spinning about y at
    -w0 (test 6), so that the contact point slides along +x at v_c0 = v_t + R w0."""
    t = TESTS[test]
    E, nu, rho = MATERIALS[mat]
    R, e, mu = t["R"], t["e"], t["mu"]
    vt, vn, w0 = case(test, mat, p)
    m = mass(mat, R)
    two = test == 7
    estar = E / (2 * (1 - nu * nu)) if two else E / (1 - nu * nu)
    t_h = hertz_time(m / 2 if two else m, R / 2 if two else R, estar, 2 * vn if two else vn)
    gap = 0.05 * vn * t_h  # reached after 5 % of a contact time
    dt = t_h / steps
    n = math.ceil((gap / vn + 2.0 * t_h) / dt)
    props = (f"youngs_modulus: {E if two else 2 * E!r}, poisson_ratio: {nu}, "
             f"restitution: {e}, tangential_restitution: 1, friction: {mu}")
    lines = ["name: chung_ooi", "gravity: [0, 0, 0]", "materials:",
             f"  ball: {{density: {rho}, {props}}}"]
    if two:
        z = R + gap / 4
        lines += ["particles:",
                  f"  - {{material: ball, radius: {R}, position: [0, 0, {z!r}], "
                  f"velocity: [0, 0, {-vn}], angular_velocity: [0, {w0}, 0]}}",
                  f"  - {{material: ball, radius: {R}, position: [0, 0, {-z!r}], "
                  f"velocity: [0, 0, {vn}], angular_velocity: [0, {-w0}, 0]}}"]
    else:
        lines += [f"  rigid: {{{props}}}", "particles:",
                  f"  - {{material: ball, radius: {R}, position: [0, 0, {R + gap!r}], "
                  f"velocity: [{vt!r}, 0, {-vn!r}], angular_velocity: [0, {-w0}, 0]}}",
                  "walls:", "  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, "
                  "material: rigid}", "contact: {wall_lever: surface}"]
    speed = 2 * vn if two else vn  # the approach speed
    lines += [f"integrator: {{method: leapfrog, dt: {dt!r}, impact_speed: {speed!r}}}",
              f"run: {{steps: {n}}}", "output: {every: 0, energy_every: 0}"]
    return "\n".join(lines) + "\n", t_h


def observe(test, mat, p, frame):
    """The test's observables from the last frame (particle 0, the upper sphere)."""
    R = TESTS[test]["R"]
    _, d = frame
    i = int(np.argmin(d["id"]))
    row = observables(test, mat, p, float(d["velocity"][i, 0]),
                      float(d["velocity"][i, 2]), float(d["angular_velocity"][i, 1]))
    row["left"] = bool(d["position"][i, 2] - R > 0 and row["vz"] > 0)
    return row


def observables(test, mat, p, vx, vz, wy):
    """The row of one impact from the sphere's velocity and spin after it."""
    t = TESTS[test]
    R, mu = t["R"], t["mu"]
    vt, vn, w0 = case(test, mat, p)
    vc = vx - R * wy  # the contact point's tangential velocity after the impact
    row = dict(test=test, material=mat, param=p, vt0=vt, vn0=vn, w0=w0, vx=vx, vz=vz,
               wy=wy, e_n=vz / vn, vc=vc)
    if test == 4:
        row.update(x=p, e_t=vx / vt, omega=-wy)
    elif test == 5:
        row.update(x=vt / (mu * vn), recoil=vc / (mu * vz), spin=-R * wy / (mu * vn))
    elif test == 6:
        row.update(x=R * w0 / vn, beta=-vc / (R * w0), recoil=vc / vz)
    else:
        row.update(x=w0, w_ratio=wy / w0, vt_after=vx)
    return row


def _wall_impact(m, R, es, gs, mu, gamma, vt, vn, w0, dt, tangential=True):
    """The law's impact of a sphere on a rigid plane, integrated on its own (semi-
    implicit Euler at step dt): F_n = (4/3) E* sqrt(R) u^(3/2) + c u', c = 2 gamma
    sqrt(m S_n), S_n = 2 E* a, a = sqrt(R u), no tension; the tangential force grows
    by 8 G* a v_c dt (Mindlin's incremental stiffness), capped at mu F_n; the contact
    point at R - u from the centre. Returns (vx, vz, wy) after the impact."""
    inertia = 0.4 * m * R * R
    z, vz, vx, wy, ft, touched = 0.0, -vn, vt, -w0, 0.0, False
    kh = 4.0 / 3.0 * es * math.sqrt(R)
    while True:
        u = -z
        if u > 0:
            touched = True
            a = math.sqrt(R * u)
            fn = max(0.0, kh * u * math.sqrt(u) - 2 * gamma * math.sqrt(2 * m * es * a) * vz)
            if tangential:
                lever = R - u
                ft += 8 * gs * a * (vx - lever * wy) * dt
                cap = mu * fn
                ft = max(-cap, min(cap, ft))
                vx -= ft / m * dt
                wy += lever * ft / inertia * dt
        else:
            fn, ft = 0.0, 0.0
            if touched:
                return vx, vz, wy
        vz += fn / m * dt
        z += vz * dt


_GAMMA = {}


def model_reference(test, mat, p, steps=4000):
    """(vx, vz, wy) of a wall impact (tests 4-6) by _wall_impact at t_H/steps: the law
    integrated independently of esfera, its dashpot's gamma found by bisection so that
    the normal restitution is e."""
    t = TESTS[test]
    E, nu, _ = MATERIALS[mat]
    R, e, mu = t["R"], t["e"], t["mu"]
    vt, vn, w0 = case(test, mat, p)
    m = mass(mat, R)
    es, gs = E / (1 - nu * nu), E / (2 * (1 + nu)) / (2 - nu)
    dt = hertz_time(m, R, es, vn) / steps
    key = (test, mat, steps)
    if key not in _GAMMA:
        lo, hi = 0.0, 0.0 if e >= 1 else 4.0
        for _ in range(0 if e >= 1 else 40):
            mid = 0.5 * (lo + hi)
            _, vz, _ = _wall_impact(m, R, es, gs, mu, mid, 0.0, vn, 0.0, dt, False)
            lo, hi = (mid, hi) if vz / vn > e else (lo, mid)
        _GAMMA[key] = 0.5 * (lo + hi)
    return _wall_impact(m, R, es, gs, mu, _GAMMA[key], vt, vn, w0, dt)


def closed_form(row):
    """Rigid-body gross sliding with the measured normal restitution; None when the
    impact does not slide throughout (v_c0 < 7/2 mu (1 + e_n) v_n)."""
    t = TESTS[row["test"]]
    R, mu, en = t["R"], t["mu"], row["e_n"]
    vt, vn, w0 = row["vt0"], row["vn0"], row["w0"]
    jump = mu * (1 + en) * vn
    if row["test"] == 7 or vt + R * w0 < 3.5 * jump:
        return None
    vx, wy = vt - jump, -w0 + 2.5 * jump / R
    vc, vz = vx - R * wy, en * vn
    return dict(e_t=vx / vt if vt else None, omega=-wy, recoil5=vc / (mu * vz),
                spin=-R * wy / (mu * vn), beta=-vc / (R * w0) if w0 else None,
                recoil6=vc / vz)


def impact(esfera, tmp, test, mat, p, steps=STEPS_PER_CONTACT):
    """Runs one impact: its row (observables), or RuntimeError."""
    text, t_h = scene_yaml(test, mat, p, steps)
    tag = f"t{test}_{mat}_{p:g}_{steps}"
    path = write_scene(os.path.join(tmp, tag + ".yaml"), text)
    out = os.path.join(tmp, "runs", tag)
    r = run(esfera, path, out).check()
    row = observe(test, mat, p, last_frame(r.out))
    shutil.rmtree(out, ignore_errors=True)
    row.update(t_hertz=t_h, steps_per_contact=steps)
    if not row["left"]:
        raise RuntimeError(f"{tag}: the sphere has not left the wall at the end")
    return row


def published(test, mat):
    """{observable: [(x, y)]} of the digitised curves for a test and material."""
    table = {(4, "al_oxide"): dict(e_t=pub.T4_ET_AL_OXIDE, omega=pub.T4_OMEGA_AL_OXIDE),
             (4, "al_alloy"): dict(e_t=pub.T4_ET_AL_ALLOY),
             (5, "steel"): dict(recoil=pub.T5_RECOIL_STEEL, spin=pub.T5_SPIN_STEEL),
             (5, "polyethylene"): dict(recoil=pub.T5_RECOIL_PE, spin=pub.T5_SPIN_PE),
             (7, "copper"): dict(vt_after=pub.T7_VT_COPPER)}
    return table.get((test, mat), {})


def published_at(points, x):
    """The digitised curve at x (linear between points; the end value within 3 % of
    the x range beyond an end: digitised points sit off the exact abscissa), None
    further out."""
    pts = sorted(points)
    xs, ys = [a for a, _ in pts], [b for _, b in pts]
    slack = 0.03 * (xs[-1] - xs[0]) if xs else 0.0
    if not xs or x < xs[0] - slack or x > xs[-1] + slack:
        return None
    return float(np.interp(x, xs, ys))


def parse_args(argv):
    ap = argparse.ArgumentParser(description="Chung & Ooi (2011) tests 4-7.")
    ap.add_argument("--out", default=os.path.join(REPO, "studies", "results", "chung_ooi"))
    ap.add_argument("--esfera", default=os.path.join(REPO, "build", "esfera"))
    ap.add_argument("--tests", default="4,5,6,7")
    return ap.parse_args(argv)


def main(argv):
    args = parse_args(argv)
    from chung_ooi_report import write_outputs  # matplotlib only when writing
    tests = [int(s) for s in args.tests.split(",")]
    out = os.path.abspath(args.out)
    tmp = os.path.join(out, "tmp")
    os.makedirs(os.path.join(tmp, "runs"), exist_ok=True)
    esf = os.path.abspath(args.esfera)
    rows = []
    for test in tests:
        for mat in TESTS[test]["materials"]:
            for p in TESTS[test]["params"]:
                row = impact(esf, tmp, test, mat, p)
                if test != 7:  # the law integrated on its own, for every wall impact
                    ref = observables(test, mat, p, *model_reference(test, mat, p))
                    for k in OBSERVABLES:
                        if k in ref:
                            row["model_" + k] = ref[k]
                rows.append(row)
            print(f"test {test} {mat}: {len(TESTS[test]['params'])} impacts",
                  file=sys.stderr)
    fields = ["test", "material", "param", "x", "vt0", "vn0", "w0", "vx", "vz", "wy",
              "e_n", "vc", "e_t", "omega", "recoil", "spin", "beta", "w_ratio",
              "vt_after", "t_hertz", "steps_per_contact"] + [
                  "model_" + k for k in OBSERVABLES]
    write_csv(os.path.join(out, "chung_ooi.csv"), rows, fields)
    write_outputs(out, rows)
    shutil.rmtree(tmp, ignore_errors=True)
    print(f"done: {out}/report.md", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
