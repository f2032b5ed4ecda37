#!/usr/bin/python3
"""Study 1 (issue 7): the critical time step of esfera's production leapfrog, measured.

Every experiment is an esfera scene in a loaded equilibrium, given a small velocity
perturbation and integrated with `integrator.dt` fixed (`allow_unstable: true`) for a
fixed number of periods of its fastest mode. The largest stable step is bisected and
compared with the seeds' three critical-step rules and with the highest frequency of
the assembled contact system that `esfera modes` computes.

Cases (SI units; glass-like spheres r = 5 mm, rho = 2500 kg/m^3, kn = 1e5 N/m)
-----------------------------------------------------------------------------
wall_normal          one sphere resting on a plane wall under gravity (overlap mg/kn),
                     frictionless, kicked normally: the single normal contact.
pair_normal          a free pair pressed together (no gravity), held only by two soft
                     frictionless undamped walls (k_w = 1e-3 kn), kicked apart: the
                     pair's relative mode sqrt((2 kn + k_w)/m), reduced mass m/2.
wall_tangential_ktX  the resting sphere with a sticking tangential spring kt = X kn
                     (cohesion 1 N, never reached), kicked normally and in its
                     tangential mode (translation and rotation against the spring:
                     omega_t^2 = kt (1/m + l^2/I)).
pair_tangential_ktX  the free pair with a sticking tangential spring, kicked in its
                     normal and shear modes (omega_t^2 = kt (2/m + 2 l^2/I)).
pack_ktX             a dense random pack (N polydisperse spheres, r = 4.5-5.5 mm,
                     poured frictionless into a box and settled to rest: coordination
                     about 6 in the bulk), then sticking tangential springs kt = X kn,
                     random velocities and spins.
Each case is run for restitutions eta from 1 (xi = 0) to 1e-7 (xi = 0.98); the
tangential restitution is the same, so both dashpots follow Tsuji's form.

Definitions
-----------
xi        contact damping ratio from the restitution, xi = -ln eta / sqrt(pi^2 +
          ln^2 eta) (Tsuji; the dashpot c = 2 xi sqrt(m* k)).
f(xi)     sqrt(1 + xi^2) - xi, the central-difference factor for damping.
tau       dt / sqrt(m_min / k_max): the step in units of Cundall's rule (m_min the
          lightest particle, k_max = max(kn, kt)); esfera's own rule values are used.
rules     cundall sqrt(m/k), hart 2 sqrt(m/2k), damped 2 sqrt(m/k) f(xi) (FRAC = 1,
          esfera's values, src/timestep.c); 2/omega_max and (2/omega_max) f(xi_max)
          from `esfera modes` at the initial state (xi_max: the contacts' ratio);
          bound (2/omega_max) f(xi_b), xi_b = xi omega_max sqrt(m_max / k_min): an
          upper bound of the fastest mode's damping ratio, since every dashpot has
          c/k = 2 xi sqrt(m*/k) <= beta = 2 xi sqrt(m_max/k_min), so C <= beta K and
          a mode phi of frequency w has phi.C.phi / (2 w) <= beta w / 2 (m_max the
          heaviest particle, k_min = min(kn, kt) of the damped contacts).
closed form  single-contact cases only: each mode of the contact is a damped
          oscillator x'' + 2 xi_m w x' + w^2 x = 0, and the leapfrog, whose dashpots
          see the half-step velocity v_{n-1/2}, is stable exactly for
          w dt < 2 f(xi_m) (the recurrence's root at -1). xi_m is the mode's own
          damping ratio: for the tangential mode it is xi sqrt(m*/m_eff), m_eff the
          mode's effective mass (m/3.5 on a wall, m/7 for a pair), not xi.
margin    measured limit / rule: the largest FRAC of that rule that is still stable.
          A rule is unsafe in a case when its step itself (FRAC = 1) was measured
          unstable (the bisection's unstable bound <= rule), marginal when the rule
          falls inside the final 1 % bracket, safe otherwise.

Instability criterion
---------------------
A run lasts P periods 2 pi / omega_max of the fastest mode (at least 1000 steps). It is
unstable if esfera stops it (exit status 1: non-finite state, overlap beyond
contact.max_overlap, runaway energy) or if the largest kinetic energy (translational +
rotational, energy.csv, one row per step) at any time of the run exceeds GROWTH = 1e4
times the kick's kinetic energy E_kick (or the first row's, if larger). The kick is
tiny (3e-4 of the static overlap for the single contacts) so that the linear growth of
an unstable mode is seen long before it saturates: beyond the limit the motion does not
always blow up. A normal contact that opens turns into a bouncing limit cycle, a
tangential spring that reaches the Coulomb cap turns into steady sliding and spinning
(energy ~1e9 E_kick, balanced in the ledger, not caught by esfera's runaway check), and
the pack loses the contacts whose modes were unstable and calms down again, which is
why the largest energy of the whole run counts, not that of its end. The kinetic
energy is used rather than the ledger's mechanical energy: the ledger books gravity at
mid-step and elastic energy at the step, which leaves a term linear in the velocity
(m g v dt / 2) that swamps the kick's quadratic energy. Below the limit an undamped
leapfrog's discrete amplitude is 1/cos(theta/2) times the continuous one
(cos(theta/2)^2 = 1 - (w dt/2)^2): a stable run's ratio stays under 1e4 up to 0.005 %
from the limit. The limit is bisected on dt, geometrically,
until the stable and unstable bounds are within 1 %; the reported limit is their
geometric mean. A sweep of dt from 0.5 to 2 times the limit checks that stability
changes only once.

Running
-------
    /usr/bin/python3 studies/critical_dt.py [--quick] [--out DIR] [--esfera PATH]
        [--jobs N] [--replot]

Defaults: --esfera build/esfera and --out studies/results/critical_dt/ (relative to
the repository root). Outputs in DIR: limits.csv (one row per case and restitution),
runs.csv (every run), pack_particles.csv (the settled pack), limit_vs_xi.png,
margins.png, limit_vs_kt.png, sweep.png, summary.csv (pack statistics, run time) and
report.md. Scratch scenes go to DIR/tmp/. --replot redraws the plots and the report
from DIR's CSV files without running esfera.
--quick: two restitutions, one stiffness ratio, a 60-sphere pack (under a minute).
Needs numpy, matplotlib and h5py (Debian's /usr/bin/python3); runs esfera and reads its
results through studies/common.py.
"""
import argparse
import concurrent.futures as cf
import math
import os
import shutil
import subprocess
import sys
import threading
import time

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from common import (energy, kinetic, last_frame, parse_line, read_csv, run,  # noqa: E402
                    tsuji_zeta, write_csv, write_scene)

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

RHO, KN, RADIUS, GRAV = 2500.0, 1.0e5, 0.005, 9.81
K_SOFT = 1.0e-3 * KN      # the pair's holding walls
WALL_PRESS = 0.02         # the pair's wall overlap, fraction of the radius
AMP = 3e-4                # kick amplitude / static overlap (single contacts)
PACK_AMP = 1e-3           # pack velocity scale: PACK_AMP * (m g / kn) * sqrt(kn / m)
COHESION = 1.0            # N: keeps tangential springs sticking
GROWTH = 1.0e4            # kinetic-energy growth over the kick that marks instability
RESOLUTION = 0.01         # bisection stops when unstable / stable bound <= 1 + this
MIN_STEPS, MAX_STEPS = 1000, 40000

FULL = dict(etas=[1.0, 0.9, 0.7, 0.5, 0.3, 0.1, 1e-2, 1e-3, 1e-7],
            kts=[0.1, 0.2, 0.3, 0.5, 0.75, 1.0], pack_kts=[0.25, 1.0], pack_n=300,
            pack_box=0.06, periods=300, sweep_etas=[1.0, 0.5, 1e-7], sweep_points=21)
QUICK = dict(etas=[1.0, 1e-7], kts=[1.0], pack_kts=[1.0], pack_n=60, pack_box=0.03,
             periods=150, sweep_etas=[1.0], sweep_points=7)
SWEEP_SPAN = (0.5, 2.0)
RULES = ["cundall", "hart", "damped", "modes", "modes_damped", "bound"]
RULE_LABEL = {"cundall": "Cundall sqrt(m/k)", "hart": "Hart 2 sqrt(m/2k)",
              "damped": "damped 2 sqrt(m/k) f(xi)", "modes": "2/omega_max",
              "modes_damped": "(2/omega_max) f(xi_max)",
              "bound": "(2/omega_max) f(xi_b)"}


# ----------------------------------------------------------------------------- physics
def damp_factor(xi):
    """The central-difference limit's damping factor sqrt(1 + xi^2) - xi."""
    return math.sqrt(1.0 + xi * xi) - xi


def sphere_mass(r):
    return 4.0 / 3.0 * math.pi * r ** 3 * RHO


def kick_energy(radius, vel, spin):
    """Kinetic energy of the initial velocities and spins (arrays n x 3), J."""
    r = np.asarray(radius, float)
    m = 4.0 / 3.0 * math.pi * r ** 3 * RHO
    v2 = np.sum(np.asarray(vel, float) ** 2, axis=1)
    w2 = np.sum(np.asarray(spin, float) ** 2, axis=1)
    return float(np.sum(0.5 * m * v2 + 0.5 * 0.4 * m * r * r * w2))


def leapfrog_limit(modes):
    """Largest stable dt over (omega, xi) oscillator modes: min (2/w) f(xi)."""
    return min(2.0 / w * damp_factor(x) for w, x in modes)


# -------------------------------------------------------------------------------- YAML
def material(kt_ratio, eta, friction, cohesion):
    return {"density": RHO, "kn": KN, "kt": kt_ratio * KN, "restitution": eta,
            "friction": friction, "cohesion": cohesion}


def base_scene(name, gravity, materials, particles, walls):
    return {"name": name, "gravity": gravity, "materials": materials,
            "particles": particles, "walls": walls,
            "contact": {"allow_initial_overlap": True},
            "integrator": {"method": "leapfrog", "dt": 1e-6, "allow_unstable": True},
            "run": {"steps": 1}}


# ---------------------------------------------------------------------- the cases
def wall_case(eta, kt_ratio, tangential):
    """A sphere resting on the plane z = 0 under gravity, kicked."""
    m = sphere_mass(RADIUS)
    inertia = 0.4 * m * RADIUS ** 2
    delta = m * GRAV / KN
    lever = RADIUS - delta
    xi = tsuji_zeta(eta)
    w_n = math.sqrt(KN / m)
    vel, spin = [0.0, 0.0, AMP * delta * w_n], [0.0, 0.0, 0.0]
    modes = [(w_n, xi)]
    if tangential:
        kt = kt_ratio * KN
        m_eff = 1.0 / (1.0 / m + lever ** 2 / inertia)
        w_t = math.sqrt(kt / m_eff)
        c = AMP * delta * w_t * m_eff          # contact-point speed AMP delta w_t
        vel[0], spin[1] = c / m, -c * lever / inertia
        modes.append((w_t, xi * math.sqrt(m / m_eff)))
    mat = material(kt_ratio, eta, 0.5 if tangential else 0.0,
                   COHESION if tangential else 0.0)
    particle = {"material": "g", "radius": RADIUS, "position": [0.0, 0.0, lever],
                "velocity": vel, "angular_velocity": spin}
    wall = {"plane": {"point": [0.0, 0.0, 0.0], "normal": [0.0, 0.0, 1.0]},
            "material": "g"}
    scene = base_scene("wall", [0.0, 0.0, -GRAV], {"g": mat}, [particle], [wall])
    family = "wall_tangential" if tangential else "wall_normal"
    return {"family": family, "kt_ratio": kt_ratio, "eta": eta, "xi": xi,
            "scene": scene, "closed": modes,
            "kick": kick_energy([RADIUS], [vel], [spin])}


def pair_case(eta, kt_ratio, tangential):
    """Two spheres pressed together along x, held by soft frictionless walls, no
    gravity, kicked in the normal (and shear) relative modes."""
    m = sphere_mass(RADIUS)
    inertia = 0.4 * m * RADIUS ** 2
    u_w = WALL_PRESS * RADIUS
    u_p = K_SOFT * u_w / KN
    lever = RADIUS - 0.5 * u_p
    xi = tsuji_zeta(eta)
    k_rel = 2.0 * KN + K_SOFT
    w_n = math.sqrt(k_rel / m)
    c_rel = 2 * 2 * xi * math.sqrt(0.5 * m * KN)  # the walls are undamped
    modes = [(w_n, c_rel / (2.0 * math.sqrt(k_rel * m)))]
    v_n = 0.5 * AMP * u_p * w_n
    va, vb = [v_n, 0.0, 0.0], [-v_n, 0.0, 0.0]
    wa, wb = [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]
    if tangential:
        kt = kt_ratio * KN
        m_eff = 1.0 / (2.0 / m + 2.0 * lever ** 2 / inertia)
        w_t = math.sqrt(kt / m_eff)
        c = AMP * u_p * w_t * m_eff
        va[1], vb[1] = -c / m, c / m
        wa[2] = wb[2] = -c * lever / inertia
        ct = 2.0 * xi * math.sqrt(0.5 * m * kt)
        modes.append((w_t, ct / (2.0 * math.sqrt(kt * m_eff))))
    mat = material(kt_ratio, eta, 0.5 if tangential else 0.0,
                   COHESION if tangential else 0.0)
    soft = {"kn": K_SOFT, "kt": K_SOFT, "restitution": 1.0, "friction": 0.0}
    xa, xb = -lever, lever
    particles = [
        {"material": "g", "radius": RADIUS, "position": [xa, 0.0, 0.0], "velocity": va,
         "angular_velocity": wa},
        {"material": "g", "radius": RADIUS, "position": [xb, 0.0, 0.0], "velocity": vb,
         "angular_velocity": wb}]
    walls = [{"plane": {"point": [xa - RADIUS + u_w, 0.0, 0.0], "normal": [1.0, 0, 0]},
              "material": "soft"},
             {"plane": {"point": [xb + RADIUS - u_w, 0.0, 0.0], "normal": [-1.0, 0, 0]},
              "material": "soft"}]
    scene = base_scene("pair", [0.0, 0.0, 0.0], {"g": mat, "soft": soft}, particles,
                       walls)
    scene["mixing"] = {"kn": "min", "kt": "min", "restitution": "max",
                       "tangential_restitution": "max"}
    family = "pair_tangential" if tangential else "pair_normal"
    return {"family": family, "kt_ratio": kt_ratio, "eta": eta, "xi": xi,
            "scene": scene, "closed": modes,
            "kick": kick_energy([RADIUS, RADIUS], [va, vb], [wa, wb])}


def pack_case(eta, kt_ratio, pack):
    """The settled pack with sticking tangential springs and random velocities."""
    mat = material(kt_ratio, eta, 0.5, COHESION)
    particles = [{"file": pack["csv"], "material": "g"}]
    scene = base_scene("pack", [0.0, 0.0, -GRAV], {"g": mat}, particles, [pack["box"]])
    return {"family": "pack", "kt_ratio": kt_ratio, "eta": eta, "xi": tsuji_zeta(eta),
            "scene": scene, "closed": None,
            "kick": kick_energy(pack["rad"], pack["vel"], pack["spin"])}


def case_name(case):
    fam, kt = case["family"], case["kt_ratio"]
    if fam in ("wall_normal", "pair_normal"):
        return fam
    return f"{fam}_kt{kt:g}"


# ----------------------------------------------------------------------- esfera calls
def esfera_run(esfera, scene_path, out_dir, sets=()):
    """Runs esfera (exit 0 or 1: stable or stopped); status 2 (bad input) raises."""
    return run(esfera, scene_path, out_dir, sets).check(ok=(0, 1))


def esfera_modes(esfera, scene_path):
    """`esfera modes` as a dict of floats."""
    p = subprocess.run([esfera, "modes", scene_path], capture_output=True, text=True)
    modes = parse_line(p.stdout, "modes:")
    if p.returncode != 0 or not modes:
        raise RuntimeError(f"esfera modes {scene_path}: {p.stderr.strip()}")
    return modes


# ------------------------------------------------------------------------------ pack
def write_pack_csv(path, pos, rad, vel=None, spin=None):
    with open(path, "w") as fh:
        fh.write("x,y,z,radius" + (",vx,vy,vz,wx,wy,wz" if vel is not None else "") + "\n")
        for i in range(len(rad)):
            row = [*pos[i], rad[i]]
            if vel is not None:
                row += [*vel[i], *spin[i]]
            fh.write(",".join(repr(float(v)) for v in row) + "\n")


def settle_pack(esfera, work, n, side):
    """Pours n spheres frictionless into an open box and settles them to rest in two
    runs (free settling, then strong local and global damping); returns the final
    positions, radii and the box wall."""
    height = n * sphere_mass(RADIUS) / RHO / (0.25 * side ** 2)  # solid fraction 0.25
    box = {"box": {"min": [0.0, 0.0, 0.0], "max": [side, side, 1.3 * height]},
           "open": ["top"], "material": "g"}
    mat = {"density": RHO, "kn": KN, "kt": KN, "restitution": 0.1, "friction": 0.0}
    gen = {"generate": "random", "region": {"min": [0, 0, 0], "max": [side, side, height]},
           "count": n, "radius": {"uniform": [0.9 * RADIUS, 1.1 * RADIUS]},
           "material": "g", "seed": 7}
    scene = base_scene("pack_pour", [0.0, 0.0, -GRAV], {"g": mat}, [gen], [box])
    scene["integrator"] = {"dt": "auto", "dt_rule": "hart", "frac": 0.2}
    scene["run"] = {"duration": 0.5}
    scene["output"] = {"energy_every": 0.01}
    pos, rad = run_settle(esfera, work, "pour", scene)
    write_pack_csv(os.path.join(work, "pack_poured.csv"), pos, rad)
    scene["particles"] = [{"file": "pack_poured.csv", "material": "g"}]
    scene["damping"] = {"local": {"coefficient": 0.7}, "global": {"translation": 50.0}}
    scene["run"] = {"duration": 0.5}
    pos, rad = run_settle(esfera, work, "rest", scene)
    return pos, rad, box


def run_settle(esfera, work, tag, scene):
    path = os.path.join(work, f"pack_{tag}.yaml")
    write_scene(path, scene, flow=True)
    out = os.path.join(work, f"pack_{tag}")
    r = esfera_run(esfera, path, out)
    if r.returncode:
        raise RuntimeError(f"settling the pack ({tag}) failed: {r.stderr.strip()}")
    d = last_frame(out).data
    return d["position"], d["radius"]


def coordination(pos, rad, side):
    """Contacts per particle (pairs + walls of the box): all particles, and the bulk
    (centres over 2 diameters from the side walls and the floor and 2 diameters below
    the top particle)."""
    n = len(rad)
    z = np.zeros(n)
    for i in range(n):
        d = np.linalg.norm(pos[i + 1:] - pos[i], axis=1)
        hit = np.nonzero(rad[i + 1:] + rad[i] - d > 0)[0] + i + 1
        z[i] += len(hit)
        z[hit] += 1
    for axis in range(3):
        z += (pos[:, axis] < rad)
        if axis < 2:
            z += (side - pos[:, axis] < rad)
    d4 = 4 * RADIUS
    bulk = ((pos[:, 0] > d4) & (pos[:, 0] < side - d4) & (pos[:, 1] > d4) &
            (pos[:, 1] < side - d4) & (pos[:, 2] > d4) & (pos[:, 2] < pos[:, 2].max() - d4))
    return {"z_all": float(z.mean()), "z_bulk": float(z[bulk].mean()) if bulk.any() else
            float("nan"), "n_bulk": int(bulk.sum()), "rattlers": int((z < 2).sum())}


def prepare_pack(esfera, work, n, side):
    """Settled pack: the CSV with random velocities (seeded) and its statistics."""
    pos, rad, box = settle_pack(esfera, work, n, side)
    rng = np.random.default_rng(11)
    mass = 4.0 / 3.0 * math.pi * rad ** 3 * RHO
    scale = PACK_AMP * (mass * GRAV / KN) * np.sqrt(KN / mass)
    vel = rng.standard_normal((len(rad), 3)) * scale[:, None]
    spin = rng.standard_normal((len(rad), 3)) * (scale / rad)[:, None]
    csv_path = os.path.join(work, "pack_study.csv")
    write_pack_csv(csv_path, pos, rad, vel, spin)
    stats = coordination(pos, rad, side)
    stats.update(n=len(rad), side=side, height=float((pos[:, 2] + rad).max()),
                 solid_fraction=float(np.sum(4 / 3 * math.pi * rad ** 3) /
                                      (side * side * (pos[:, 2] + rad).max())))
    return {"csv": csv_path, "box": box, "pos": pos, "rad": rad, "vel": vel,
            "spin": spin, "stats": stats}


# ------------------------------------------------------------------ one case's runs
class Prober:
    """Runs one case at given steps, classifies stability, remembers every run."""

    def __init__(self, esfera, work, case, omega_max, periods, rules):
        self.esfera, self.case = esfera, case
        self.scene_path = os.path.join(work, f"{case['key']}.yaml")
        write_scene(self.scene_path, case["scene"], flow=True)
        self.run_dir = os.path.join(work, f"{case['key']}_run")
        self.omega, self.periods, self.rules = omega_max, periods, rules
        self.rows = []

    def steps(self, dt):
        n = math.ceil(self.periods * 2.0 * math.pi / (self.omega * dt))
        return int(min(max(n, MIN_STEPS), MAX_STEPS))

    def probe(self, dt, purpose):
        n = self.steps(dt)
        r = esfera_run(self.esfera, self.scene_path, self.run_dir,
                       [f"integrator.dt={dt!r}", f"run.steps={n}"])
        rc = r.returncode
        growth = math.inf
        if rc == 0:
            growth = window_growth(kinetic(energy(self.run_dir)), self.case["kick"])
        shutil.rmtree(self.run_dir, ignore_errors=True)
        unstable = rc != 0 or not growth <= GROWTH
        self.rows.append({"case": self.case["name"], "eta": self.case["eta"],
                          "xi": self.case["xi"], "purpose": purpose, "dt": dt,
                          "tau": dt / self.rules["cundall"],
                          "frac_cundall": dt / self.rules["cundall"],
                          "frac_hart": dt / self.rules["hart"],
                          "frac_damped": dt / self.rules["damped"],
                          "steps": n, "exit": rc,
                          "growth": growth, "unstable": int(unstable),
                          "message": first_line(r.stderr.strip()) if rc else ""})
        return unstable


def first_line(text):
    """esfera's error line (without the program name), for runs.csv."""
    line = text.splitlines()[0] if text else ""
    return line.replace("esfera: ", "", 1).replace(",", ";")[:200]


def window_growth(ke, kick):
    """max KE over the run / the reference: the kick's kinetic energy, or the first
    row's if larger."""
    if len(ke) < 4 or not np.all(np.isfinite(ke)):
        return math.inf
    ref = max(kick, ke[0])
    return float(ke.max() / ref) if ref > 0 else math.inf


def bisect_limit(prober, estimate):
    """(stable dt, unstable dt) within RESOLUTION, starting near the estimate."""
    lo, hi = estimate / 1.05, estimate * 1.07  # no probe exactly at the estimate
    while prober.probe(lo, "bracket"):
        hi, lo = lo, lo / 1.3
    known_hi = hi < estimate
    while not known_hi and not prober.probe(hi, "bracket"):
        lo, hi = hi, hi * 1.3
    while hi / lo > 1.0 + RESOLUTION:
        mid = math.sqrt(lo * hi)
        if prober.probe(mid, "bisect"):
            hi = mid
        else:
            lo = mid
    return lo, hi


def sweep(prober, limit, points):
    for f in np.geomspace(SWEEP_SPAN[0], SWEEP_SPAN[1], points):
        prober.probe(limit * float(f), "sweep")


def consistency(rows, lo, hi):
    """Runs contradicting a single stability boundary (stable above hi or unstable
    below lo)."""
    return sum(1 for r in rows if (r["unstable"] and r["dt"] < lo * (1 - 1e-12)) or
               (not r["unstable"] and r["dt"] > hi * (1 + 1e-12)))


def bound_xi(xi, omega_max, m_max, k_min):
    """Upper bound of the fastest mode's damping ratio when every dashpot is
    c = 2 xi sqrt(m* k): then C <= beta K with beta = max c/k = 2 xi sqrt(m*_max/k_min),
    and a mode of frequency w has a ratio phi.C.phi / (2 w) <= beta w / 2."""
    return xi * omega_max * math.sqrt(m_max / k_min)


def rule_values(modes, case):
    """The six reference steps (s) of a case."""
    w, xi = modes["omega_max"], case["xi"]
    return {"cundall": modes["cundall"], "hart": modes["hart"],
            "damped": modes["damped"],
            "modes": modes["dt_2_over_omega"],
            "modes_damped": modes["dt_2_over_omega"] * damp_factor(modes["xi_max"]),
            "bound": modes["dt_2_over_omega"] *
            damp_factor(bound_xi(xi, w, case["m_max"], case["k_min"]))}


def run_case(esfera, work, case, modes, cfg, do_sweep):
    """Modes-based estimate, bisection, optional sweep; the case's result row."""
    rules = rule_values(modes, case)
    closed = leapfrog_limit(case["closed"]) if case["closed"] else None
    estimate = rules["modes_damped"]  # the closed form is only compared with, after
    prober = Prober(esfera, work, case, modes["omega_max"], cfg["periods"], rules)
    lo, hi = bisect_limit(prober, estimate)
    limit = math.sqrt(lo * hi)
    if do_sweep:
        sweep(prober, limit, cfg["sweep_points"])
    row = {"case": case["name"], "family": case["family"], "kt_over_kn": case["kt_ratio"],
           "eta": case["eta"], "xi": case["xi"], "particles": int(modes["particles"]),
           "contacts": int(modes["contacts"]), "omega_max": modes["omega_max"],
           "xi_max": modes["xi_max"], "sqrt_m_over_k": modes["cundall"],
           "dt_stable": lo, "dt_unstable": hi, "dt_limit": limit,
           "tau_limit": limit / modes["cundall"],
           "dt_closed_form": closed if closed else float("nan"),
           "closed_form_in_bracket": int(lo <= closed <= hi) if closed else "",
           "closed_form_outside": (max(closed / hi, lo / closed) - 1 if not
                                   lo <= closed <= hi else 0.0) if closed else "",
           "limit_over_closed_form": limit / closed if closed else float("nan"),
           "xi_bound": bound_xi(case["xi"], modes["omega_max"], case["m_max"],
                                case["k_min"]),
           "runs": len(prober.rows),
           "inconsistent_runs": consistency(prober.rows, lo, hi)}
    for r in RULES:
        row[f"dt_{r}"] = rules[r]
        row[f"margin_{r}"] = limit / rules[r]
        row[f"verdict_{r}"] = verdict(lo, hi, rules[r])
    return row, prober.rows


def verdict(lo, hi, rule):
    if hi < rule:
        return "unsafe"
    if lo >= rule:
        return "safe"
    return "marginal"


# --------------------------------------------------------------------------- driver
def build_cases(cfg, pack):
    cases = []
    for eta in cfg["etas"]:
        cases.append(wall_case(eta, 0.2, False))
        cases.append(pair_case(eta, 0.2, False))
        for kt in cfg["kts"]:
            cases.append(wall_case(eta, kt, True))
            cases.append(pair_case(eta, kt, True))
        for kt in cfg["pack_kts"]:
            cases.append(pack_case(eta, kt, pack))
    for c in cases:
        c["name"] = case_name(c)
        c["key"] = f"{c['name']}_eta{c['eta']:g}"
        c["k_min"] = KN * min(1.0, c["kt_ratio"])
        c["m_max"] = (sphere_mass(float(np.max(pack["rad"]))) if c["family"] == "pack"
                      else sphere_mass(RADIUS))
    return cases


def all_modes(esfera, work, cases, pool):
    """`esfera modes` per case; the pack's (expensive: a dense eigenproblem) once per
    stiffness ratio, at eta = 1, its damping entries then from the restitution."""
    jobs, pack_jobs = {}, {}
    for c in cases:
        path = os.path.join(work, f"{c['key']}_modes.yaml")
        if c["family"] == "pack":
            if c["kt_ratio"] not in pack_jobs:
                scene = dict(c["scene"])
                scene["materials"] = {"g": material(c["kt_ratio"], 1.0, 0.5, COHESION)}
                p = os.path.join(work, f"pack_kt{c['kt_ratio']:g}_modes.yaml")
                write_scene(p, scene, flow=True)
                pack_jobs[c["kt_ratio"]] = pool.submit(esfera_modes, esfera, p)
            continue
        write_scene(path, c["scene"], flow=True)
        jobs[c["key"]] = pool.submit(esfera_modes, esfera, path)
    out = {}
    for c in cases:
        if c["family"] == "pack":
            m = dict(pack_jobs[c["kt_ratio"]].result())
            m["xi_max"] = c["xi"]
            m["damped"] = 2.0 * m["cundall"] * damp_factor(c["xi"])
            m["dt_damped"] = m["dt_2_over_omega"] * damp_factor(c["xi"])
            out[c["key"]] = m
        else:
            out[c["key"]] = jobs[c["key"]].result()
    return out


def run_all(esfera, work, cases, modes, cfg, jobs):
    sweep_names = {"wall_normal", "pair_normal", "wall_tangential_kt1",
                   "pair_tangential_kt1", "pack_kt1", "pack_kt0.25"}
    order = sorted(cases, key=lambda c: c["family"] != "pack")  # long ones first
    results, runs = [], []
    lock = threading.Lock()

    def job(c):
        do_sweep = c["name"] in sweep_names and c["eta"] in cfg["sweep_etas"]
        row, rows = run_case(esfera, work, c, modes[c["key"]], cfg, do_sweep)
        with lock:
            results.append(row)
            runs.extend(rows)

    with cf.ThreadPoolExecutor(max_workers=jobs) as pool:
        for f in [pool.submit(job, c) for c in order]:
            f.result()
    key = {c["key"]: i for i, c in enumerate(cases)}
    results.sort(key=lambda r: key[f"{r['case']}_eta{r['eta']:g}"])
    return results, runs


# ----------------------------------------------------------------------------- plots
def case_names(results):
    seen = []
    for r in results:
        if r["case"] not in seen:
            seen.append(r["case"])
    return seen


def of_case(results, name):
    rs = [r for r in results if r["case"] == name]
    return sorted(rs, key=lambda r: r["xi"])


def plot_limits(results, path):
    names = case_names(results)
    ncol = 4
    nrow = math.ceil(len(names) / ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.2 * ncol, 3.2 * nrow), squeeze=False)
    xs = np.linspace(0, 1, 101)
    for ax, name in zip(axes.flat, names):
        rs = of_case(results, name)
        xi = np.array([r["xi"] for r in rs])
        unit = np.array([r["sqrt_m_over_k"] for r in rs])
        ax.errorbar(xi, [r["tau_limit"] for r in rs],
                    yerr=[[r["tau_limit"] - r["dt_stable"] / r["sqrt_m_over_k"] for r in rs],
                          [r["dt_unstable"] / r["sqrt_m_over_k"] - r["tau_limit"] for r in rs]],
                    fmt="ko", ms=4, label="measured", zorder=5)
        ax.plot(xs, np.ones_like(xs), label=RULE_LABEL["cundall"])
        ax.plot(xs, np.full_like(xs, math.sqrt(2)), label=RULE_LABEL["hart"])
        ax.plot(xs, 2 * (np.sqrt(1 + xs ** 2) - xs), label=RULE_LABEL["damped"])
        w = rs[0]["dt_modes"] / unit[0]
        ax.plot(xs, np.full_like(xs, w), "--", label=RULE_LABEL["modes"])
        ax.plot(xs, w * (np.sqrt(1 + xs ** 2) - xs), "--", label=RULE_LABEL["modes_damped"])
        ax.plot(xi, [r["dt_bound"] / r["sqrt_m_over_k"] for r in rs], "-.", color="gray",
                label=RULE_LABEL["bound"] + ", xi_b = xi w sqrt(m_max/k_min)")
        if not math.isnan(rs[0]["dt_closed_form"]):
            ax.plot(xi, [r["dt_closed_form"] / r["sqrt_m_over_k"] for r in rs], "k:",
                    label="closed form (modes' own xi)")
        ax.set_title(name, fontsize=10)
        ax.set_xlabel("contact damping ratio xi")
        ax.set_ylabel("dt / sqrt(m/k)")
        ax.set_ylim(0, 2.2)
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[len(names):]:
        ax.axis("off")
    h, lab = axes.flat[0].get_legend_handles_labels()
    fig.legend(h, lab, loc="lower center", ncol=4, fontsize=9)
    fig.suptitle("Measured leapfrog stability limit against the critical-step rules")
    fig.tight_layout(rect=(0, 0.06, 1, 0.97))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_margins(results, path):
    names = case_names(results)
    fig, axes = plt.subplots(1, len(RULES), figsize=(4.0 * len(RULES), 5.2), sharey=True)
    cmap = plt.get_cmap("tab20")
    for ax, rule in zip(axes, RULES):
        for k, name in enumerate(names):
            rs = of_case(results, name)
            ax.plot([r["xi"] for r in rs], [r[f"margin_{rule}"] for r in rs], "o-",
                    ms=3, color=cmap(k % 20), label=name)
        ax.axhline(1.0, color="r", lw=1)
        ax.axhline(0.1, color="r", lw=0.8, ls=":")
        ax.set_yscale("log")
        ax.set_title(RULE_LABEL[rule], fontsize=10)
        ax.set_xlabel("xi")
        ax.grid(alpha=0.3, which="both")
    axes[0].set_ylabel("margin = measured limit / rule  (< 1: unsafe at FRAC 1)")
    h, lab = axes[0].get_legend_handles_labels()
    fig.legend(h, lab, loc="lower center", ncol=min(len(names), 6), fontsize=8)
    fig.suptitle("Safety margins (red: FRAC 1; dotted: the seeds' FRAC 0.1)")
    nrow_leg = math.ceil(len(names) / 6)
    fig.tight_layout(rect=(0, 0.04 + 0.04 * nrow_leg, 1, 0.96))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_kt(results, path):
    fams = [f for f in ("wall_tangential", "pair_tangential", "pack")
            if any(r["family"] == f for r in results)]
    fig, axes = plt.subplots(1, len(fams), figsize=(5 * len(fams), 4), squeeze=False)
    for ax, fam in zip(axes[0], fams):
        etas = sorted({r["eta"] for r in results if r["family"] == fam}, reverse=True)
        for eta in etas:
            rs = sorted([r for r in results if r["family"] == fam and r["eta"] == eta],
                        key=lambda r: r["kt_over_kn"])
            kt = [r["kt_over_kn"] for r in rs]
            line, = ax.plot(kt, [r["tau_limit"] for r in rs], "o-", ms=4,
                            label=f"eta {eta:g} (xi {rs[0]['xi']:.2f})")
            ax.plot(kt, [r["dt_modes_damped"] / r["sqrt_m_over_k"] for r in rs], "--",
                    color=line.get_color(), lw=0.8)
        ax.axhline(1.0, color="k", lw=0.8)
        ax.axhline(math.sqrt(2), color="k", lw=0.8, ls="-.")
        ax.set_title(fam, fontsize=10)
        ax.set_xlabel("kt / kn")
        ax.set_ylabel("dt limit / sqrt(m/k)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=6)
    fig.suptitle("Measured limit against kt/kn (solid) and (2/omega_max) f(xi_max) "
                 "(dashed); black lines: Cundall (1) and Hart (1.41) rules", fontsize=10)
    fig.tight_layout(rect=(0, 0, 1, 0.94))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def plot_sweep(runs, results, path):
    sw = [r for r in runs if r["purpose"] == "sweep"]
    names = case_names([r for r in results if any(s["case"] == r["case"] for s in sw)])
    if not names:
        return
    fig, axes = plt.subplots(1, len(names), figsize=(4.2 * len(names), 3.8), squeeze=False)
    for ax, name in zip(axes[0], names):
        for eta in sorted({r["eta"] for r in sw if r["case"] == name}, reverse=True):
            rs = sorted([r for r in sw if r["case"] == name and r["eta"] == eta],
                        key=lambda r: r["tau"])
            g = [min(r["growth"], 1e12) if r["exit"] == 0 else 1e12 for r in rs]
            ax.plot([r["tau"] for r in rs], g, "o-", ms=3, label=f"eta {eta:g}")
        xi0 = 0.0
        for tau, lab, ls in ((1.0, "Cundall", "-"), (math.sqrt(2), "Hart", "-."),
                             (2 * damp_factor(xi0), "damped (xi 0)", ":")):
            ax.axvline(tau, color="k", ls=ls, lw=0.8)
        ax.axhline(GROWTH, color="r", lw=0.8)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(f"{name}\n(black: Cundall, Hart, damped rule at xi 0)", fontsize=9)
        ax.set_xlabel("dt / sqrt(m/k)")
        ax.set_ylabel("KE growth (1e12: stopped by esfera)")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# ---------------------------------------------------------------------------- report
def fmt_cases(rows):
    if not rows:
        return "none"
    by = {}
    for r in rows:
        by.setdefault(r["case"], []).append(r)
    parts = []
    for name, rs in by.items():
        xis = sorted(r["xi"] for r in rs)
        margins = [r["m"] for r in rs]
        parts.append(f"{name} (xi {xis[0]:.2f}-{xis[-1]:.2f}, margin "
                     f"{min(margins):.3f}-{max(margins):.3f})")
    return "; ".join(parts)


def verdict_lists(results, rule):
    out = {}
    for v in ("unsafe", "marginal"):
        out[v] = [dict(case=r["case"], xi=r["xi"], m=r[f"margin_{rule}"])
                  for r in results if r[f"verdict_{rule}"] == v]
    return out


def margin_table(results, etas):
    lines = ["| case | eta | xi | tau limit | " + " | ".join(RULES) + " |",
             "|---" * (4 + len(RULES)) + "|"]
    for name in case_names(results):
        for r in of_case(results, name):
            if r["eta"] not in etas:
                continue
            cells = []
            for rule in RULES:
                m = r[f"margin_{rule}"]
                flag = {"unsafe": " **unsafe**", "marginal": " (at limit)"}.get(
                    r[f"verdict_{rule}"], "")
                cells.append(f"{m:.3f}{flag}")
            lines.append(f"| {name} | {r['eta']:g} | {r['xi']:.3f} | "
                         f"{r['tau_limit']:.3f} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def closed_form_lines(results):
    rs = [r for r in results if not math.isnan(r["limit_over_closed_form"])]
    if not rs:
        return "no single-contact case"
    dev = [abs(r["limit_over_closed_form"] - 1) for r in rs]
    worst = rs[int(np.argmax(dev))]
    inside = sum(r["closed_form_in_bracket"] == 1 for r in rs)
    outside = max(float(r["closed_form_outside"]) for r in rs)
    return (f"the closed form lies inside the measured stable/unstable bracket in "
            f"{inside} of {len(rs)} single-contact cases (the others within "
            f"{outside * 100:.2f} % of it); measured / closed form "
            f"{min(r['limit_over_closed_form'] for r in rs):.4f} to "
            f"{max(r['limit_over_closed_form'] for r in rs):.4f} (largest deviation "
            f"{max(dev) * 100:.2f} % in {worst['case']} at eta {worst['eta']:g})")


def modes_lines(results):
    out = []
    for name in case_names(results):
        rs = of_case(results, name)
        m0 = [r["margin_modes"] for r in rs if r["xi"] == 0.0]
        md = [r["margin_modes_damped"] for r in rs]
        out.append(f"| {name} | {rs[0]['omega_max'] * rs[0]['sqrt_m_over_k']:.3f} | "
                   f"{m0[0] if m0 else float('nan'):.3f} | {min(md):.3f} | {max(md):.3f} |")
    return "\n".join(["| case | omega_max sqrt(m/k) | limit / (2/omega_max), xi 0 | "
                      "limit / ((2/omega_max) f(xi_max)): min | max |",
                      "|---|---|---|---|---|"] + out)


def write_report(path, results, runs, info):
    n_runs = len(runs)
    incons = sum(r["inconsistent_runs"] for r in results)
    st, quick, seconds, esfera = info, info["quick"], info["seconds"], info["esfera"]
    etas = sorted({r["eta"] for r in results}, reverse=True)
    etas_shown = {etas[0], etas[-1]} | ({0.5} if 0.5 in etas else set())
    L = [f"# Critical time step of the leapfrog (issue 7, study 1){' — quick' if quick else ''}",
         "",
         f"Generated by `studies/critical_dt.py{' --quick' if quick else ''}` "
         f"({n_runs} esfera runs, {seconds:.0f} s wall on this machine; esfera: "
         f"`{esfera}`). Data: `limits.csv` (one row per case and restitution: the "
         "bracket, the limit, every rule's step and margin and verdict), `runs.csv` "
         "(every run: dt, tau, steps, exit status, kinetic-energy growth), "
         "`pack_particles.csv` (the settled pack and its perturbation).",
         "",
         "## Method",
         "",
         "Each case starts in its loaded equilibrium with a small velocity kick "
         f"(single contacts: {AMP:g} of the static overlap times the mode's "
         "frequency, in every mode; the pack: random velocities and spins) and runs "
         "with the production leapfrog at a fixed dt (`allow_unstable: true`) for "
         f"{info['periods']:g} periods of its fastest mode (2 pi/omega_max from "
         f"`esfera modes`; at least {MIN_STEPS} steps). **Criterion:** unstable when "
         "esfera stops the run (exit 1) or when the kinetic energy (energy.csv, "
         f"every step) exceeds {GROWTH:g} x the kick's at any time of the run. The "
         "limit is bisected geometrically until the unstable/stable bounds are "
         f"within {RESOLUTION * 100:g} %; `tau` = dt / sqrt(m_min/k_max) (Cundall's "
         "rule = 1, Hart's = 1.414, the damped rule = 2 f(xi), f(xi) = "
         "sqrt(1+xi^2) - xi). Margin = measured limit / rule, i.e. the largest "
         "stable FRAC of that rule; **unsafe** = the rule's own step (FRAC 1) was "
         "measured unstable, *at limit* = it falls inside the final 1 % bracket. "
         "Definitions, cases and the reasons for the criterion: the module docstring.",
         "",
         f"Pack: {st['n']} spheres, r 4.5-5.5 mm, box {st['side'] * 1000:.0f} mm "
         f"square, height {st['height'] * 1000:.1f} mm, solid fraction "
         f"{st['solid_fraction']:.3f}; coordination (pairs + walls) {st['z_all']:.2f} "
         f"over all, {st['z_bulk']:.2f} in the bulk ({st['n_bulk']} particles two "
         f"diameters from walls, floor and surface), {st['rattlers']} with fewer than "
         "two contacts. Poured frictionless (so the bulk is near isostatic, Z about "
         "6) and settled to rest, then studied with sticking tangential springs.",
         "",
         "## Results",
         "",
         "### Margins (measured limit / rule) at selected restitutions",
         "",
         "Columns: the rules cundall sqrt(m/k), hart 2 sqrt(m/2k), damped "
         "2 sqrt(m/k) f(xi) (FRAC = 1, esfera's values); modes 2/omega_max and "
         "modes_damped (2/omega_max) f(xi_max) from `esfera modes`; bound "
         "(2/omega_max) f(xi_b) with xi_b = xi omega_max sqrt(m_max/k_min) (conclusion "
         "5). `tau limit` = measured limit / sqrt(m_min/k_max).",
         "",
         margin_table(results, etas_shown),
         "",
         "Every restitution is in `limits.csv` and `margins.png`; the limits against "
         "xi with the rules' curves in `limit_vs_xi.png`, against kt/kn in "
         "`limit_vs_kt.png`; the dt sweeps past the limit in `sweep.png`.",
         "",
         "### Where each rule is unsafe (FRAC = 1)",
         ""]
    for rule in RULES:
        v = verdict_lists(results, rule)
        L.append(f"- **{RULE_LABEL[rule]}**: unsafe in {fmt_cases(v['unsafe'])}. "
                 f"At the limit (within 1 %): {fmt_cases(v['marginal'])}.")
    L += ["",
          "With the seeds' FRAC = 0.1 a rule is unsafe where its margin is below 0.1: "]
    for rule in ("cundall", "hart", "damped"):
        bad = [dict(case=r["case"], xi=r["xi"], m=r[f"margin_{rule}"]) for r in results
               if r[f"margin_{rule}"] < 0.1]
        L.append(f"- {RULE_LABEL[rule]} at FRAC 0.1: unsafe in {fmt_cases(bad)}.")
    L += ["",
          "### 2/omega_max from `esfera modes`",
          "",
          modes_lines(results),
          "",
          "### Checks",
          "",
          f"- Closed forms (each mode of a single contact with its own damping "
          f"ratio): {closed_form_lines(results)}.",
          f"- Single stability boundary: {incons} of {n_runs} runs contradict the "
          "bisected bracket (stable above it or unstable below it), including the "
          f"sweeps from {SWEEP_SPAN[0]} to {SWEEP_SPAN[1]} x the limit.",
          "",
          "## Conclusions",
          ""]
    L += conclusions(results, runs, info)
    with open(path, "w") as fh:
        fh.write("\n".join(L) + "\n")


def pick(results, name, eta):
    for r in results:
        if r["case"] == name and r["eta"] == eta:
            return r
    return None


def onset(results, name, rule):
    """The least damped result row of a case where the rule is unsafe (None: none)."""
    bad = [r for r in of_case(results, name) if r[f"verdict_{rule}"] == "unsafe"]
    return bad[0] if bad else None


def onset_text(results, name, rule):
    o = onset(results, name, rule)
    return "never unsafe" if o is None else f"unsafe from xi = {o['xi']:.2f} (eta {o['eta']:g})"


def xi_effective(tau, omega_tau):
    """The damping ratio for which (2/omega) f(xi) equals the measured limit:
    f = tau omega / 2 gives xi = (1 - f^2) / (2 f)."""
    f = tau * omega_tau / 2.0
    return (1.0 - f * f) / (2.0 * f)


def c_validation(results):
    single = [r for r in results if r["closed_form_in_bracket"] != ""]
    ratio = [r["margin_modes"] for r in results if r["xi"] == 0.0]
    if not single:
        return ""
    inside = sum(r["closed_form_in_bracket"] == 1 for r in single)
    dev = max(abs(r["limit_over_closed_form"] - 1) for r in single)
    return (f"**The measurement is exact to its resolution.** For every single contact "
            f"the measured limit is the closed form min over modes (2/w) f(xi_m): "
            f"inside the 1 % bracket in {inside} of {len(single)} cases, within "
            f"{dev * 100:.2f} % everywhere. The factor f(xi) is exact for esfera's "
            f"leapfrog because its dashpots see the half-step velocity v(n-1/2). "
            f"Undamped, the measured limit is 2/omega_max of `esfera modes` in every "
            f"case, packs included (limit / (2/omega_max) = {min(ratio):.3f} to "
            f"{max(ratio):.3f}, the bracket's midpoint just under the bound).")


def c_normal(results):
    e0 = max(r["eta"] for r in results)
    w, p = pick(results, "wall_normal", e0), pick(results, "pair_normal", e0)
    if not (w and p):
        return ""
    return (f"**Normal contacts.** On a wall (omega^2 = kn/m) the undamped margins are "
            f"Cundall {w['margin_cundall']:.2f}, Hart {w['margin_hart']:.2f}, damped "
            f"rule {w['margin_damped']:.3f}: the damped rule 2 sqrt(m/k) f(xi) is the "
            f"exact limit at every xi (no margin at FRAC 1), Cundall's rule is "
            f"{onset_text(results, 'wall_normal', 'cundall')}, Hart's "
            f"{onset_text(results, 'wall_normal', 'hart')} (neither has the damping "
            f"factor). A free pair oscillates with the reduced mass m/2 (omega^2 = "
            f"2 kn/m) while the rules take the particle mass: every rule loses sqrt(2). "
            f"Hart's rule is then exactly the undamped limit (margin "
            f"{p['margin_hart']:.3f}) and "
            f"{onset_text(results, 'pair_normal', 'hart')}; the damped rule is unsafe "
            f"at every xi (margin {p['margin_damped']:.3f} = 1/sqrt 2); Cundall's is "
            f"{onset_text(results, 'pair_normal', 'cundall')}.")


def c_tangential(results):
    tw = sorted({r["kt_over_kn"] for r in results if r["family"] == "wall_tangential"})
    if not tw:
        return ""
    e0 = max(r["eta"] for r in results)
    k1 = tw[-1]
    a, b = pick(results, f"wall_tangential_kt{k1:g}", e0), \
        pick(results, f"pair_tangential_kt{k1:g}", e0)
    md = [r["margin_modes_damped"] for r in results
          if r["family"] in ("wall_tangential", "pair_tangential")]
    text = (f"**Tangential springs with rotation.** The sticking spring moves the "
            f"contact point by translation and rotation, omega_t^2 = kt (1/m + l^2/I) "
            f"= 3.5 kt/m on a wall and 7 kt/m for a pair, so it is the fastest mode "
            f"for kt/kn > 2/7, which the rules (built on max(kn, kt) and the mass "
            f"alone) ignore. At kt = {k1:g} kn, undamped, the margins are Cundall "
            f"{a['margin_cundall']:.3f}, Hart {a['margin_hart']:.3f}, damped rule "
            f"{a['margin_damped']:.3f} on a wall and {b['margin_cundall']:.3f}, "
            f"{b['margin_hart']:.3f}, {b['margin_damped']:.3f} for a pair. The "
            f"tangential dashpot c_t = 2 xi sqrt(m* kt) acts on the mode's smaller "
            f"effective mass (m/3.5 on a wall), so the mode's damping ratio is "
            f"xi sqrt(m*/m_eff) = 1.87 xi: with damping even `esfera modes`' "
            f"(2/omega_max) f(xi_max) is unsafe (margins down to {min(md):.3f}).")
    if 0.2 in tw:
        c = onset(results, "wall_tangential_kt0.2", "modes_damped")
        if c:
            text += (f" At kt = 0.2 kn the normal mode is the fastest undamped, yet the "
                     f"more damped tangential mode sets the limit from xi = {c['xi']:.2f} "
                     f"(eta {c['eta']:g}).")
    return text


def c_pack(results, info):
    pk = sorted({r["kt_over_kn"] for r in results if r["family"] == "pack"})
    if not pk:
        return ""
    e0, e1 = max(r["eta"] for r in results), min(r["eta"] for r in results)
    parts = []
    for kt in pk:
        a, b = pick(results, f"pack_kt{kt:g}", e0), pick(results, f"pack_kt{kt:g}", e1)
        w = a["omega_max"] * a["sqrt_m_over_k"]
        part = (f"kt = {kt:g} kn: omega_max sqrt(m/k) = {w:.2f}, undamped limit "
                f"tau = {a['tau_limit']:.3f} (margins Cundall {a['margin_cundall']:.3f}, "
                f"Hart {a['margin_hart']:.3f}, damped rule {a['margin_damped']:.3f})")
        if e1 < 1:
            xe = xi_effective(b["tau_limit"], w)
            part += (f"; at eta {e1:g} tau = {b['tau_limit']:.3f} (margins "
                     f"{b['margin_cundall']:.3f}, {b['margin_hart']:.3f}, "
                     f"{b['margin_damped']:.3f}; (2/omega_max) f(xi_max) "
                     f"{b['margin_modes_damped']:.3f}), i.e. the fastest mode behaves "
                     f"as if damped with xi = {xe:.2f} = {xe / b['xi']:.2f} x the "
                     f"contacts' xi")
        parts.append(part)
    zb = float(info["z_bulk"])
    zb = f"{zb:.1f} in the bulk" if zb == zb else f"{float(info['z_all']):.1f}"
    return (f"**Dense pack** ({int(info['n'])} spheres, coordination {zb}). The fastest modes are spheres "
            f"turning against all their sticking tangential springs (Z kt l^2 against "
            f"I = 0.4 m r^2) and collective normal modes: " + "; ".join(parts) +
            ". Every seed rule is unsafe at FRAC 1 at every damping. The "
            "restitution-derived dashpots are nearly stiffness-proportional "
            "(c/k = 2 xi sqrt(m*/k)), so a mode of frequency w is damped with "
            "about xi w sqrt(m*/k): the fast modes are the most damped, and the "
            "contact's xi underestimates them.")


def c_frac01(results):
    bad = {}
    for rule in ("cundall", "hart", "damped"):
        rs = [r for r in results if r[f"margin_{rule}"] < 0.1]
        if rs:
            bad[rule] = rs
    if not bad:
        worst = min(r[f"margin_{x}"] for r in results for x in ("cundall", "hart", "damped"))
        return (f"**At the seeds' FRAC = 0.1** every rule is safe in every case "
                f"(smallest margin {worst:.3f}).")
    txt = []
    for rule, rs in bad.items():
        xi0 = min(r["xi"] for r in rs)
        txt.append(f"{RULE_LABEL[rule]} in {', '.join(sorted({r['case'] for r in rs}))} "
                   f"from xi = {xi0:.2f} (margin down to "
                   f"{min(r['margin_' + rule] for r in rs):.3f})")
    rest = [r["margin_" + x] for r in results for x in ("cundall", "hart", "damped")
            if r["margin_" + x] >= 0.1]
    return ("**Even at the seeds' FRAC = 0.1** rules are unsafe: " + "; ".join(txt) +
            f". Elsewhere the smallest margin of the three rules is {min(rest):.3f}: "
            f"FRAC = 0.1 keeps a factor {10 * min(rest):.2f} there.")


def c_signatures(results, runs):
    unst = [r for r in runs if r["unstable"] == 1]
    if not unst:
        return ""
    silent = [r for r in unst if r["exit"] == 0]
    lim = {(r["case"], r["eta"]): r["dt_limit"] for r in results}
    near = [r for r in silent if r["dt"] <= 1.5 * lim[(r["case"], r["eta"])]]
    near_all = [r for r in unst if r["dt"] <= 1.5 * lim[(r["case"], r["eta"])]]
    return (f"**Instability is often silent.** Of {len(unst)} unstable runs esfera "
            f"stopped {len(unst) - len(silent)} (runaway energy, overlap); "
            f"{len(silent)} ran to the end with exit status 0 ({len(near)} of the "
            f"{len(near_all)} within 1.5 x the limit). Past the limit a sphere on a "
            f"wall settles into a bouncing limit cycle, a tangential spring into "
            f"sliding and spinning at the Coulomb cap (the ledger balances, as the "
            f"friction books the work), and the pack sheds the contacts whose modes "
            f"grew and calms down: wrong physics without a warning.")


def c_modes(results):
    rs = [r for r in results if r["xi"] > 0]
    if not rs:
        return ""
    normal = [r for r in rs if r["family"] in ("wall_normal", "pair_normal")]
    other = [r for r in rs if r not in normal]
    bound = [r for r in results if r["verdict_bound"] == "unsafe"]
    mb = [r["margin_bound"] for r in results]
    txt = ("**2/omega_max.** Undamped it is the limit (conclusion 1); it ignores "
           "damping, so it is unsafe for any xi > 0. With the factor f(xi_max) "
           "(`esfera modes`' dt_damped) it is exact for normal contacts (margins "
           f"{min(r['margin_modes_damped'] for r in normal):.3f}-"
           f"{max(r['margin_modes_damped'] for r in normal):.3f}) but unsafe wherever "
           "the fastest mode is damped more than the contact's xi: tangential modes "
           "and the pack (margins down to "
           f"{min(r['margin_modes_damped'] for r in other):.3f}). ")
    txt += ("Bounding the fastest mode's ratio instead, xi_b = xi omega_max "
            "sqrt(m_max/k_min) (every dashpot has c/k <= 2 xi sqrt(m_max/k_min), so "
            "C <= beta K and phi.C.phi/(2 omega) <= beta omega/2), gives a step "
            "(2/omega_max) f(xi_b) that is ")
    tight = [r for r in results if r["verdict_bound"] == "marginal"]
    txt += ("never unsafe " if not bound else
            f"unsafe in {len(bound)} cases ({', '.join(sorted({r['case'] for r in bound}))}) ")
    txt += (f"(margins {min(mb):.3f} to {max(mb):.3f}; equal to the limit within the "
            f"1 % bracket in {len(tight)} of {len(results)} cases, listed above: it is "
            "tight where xi_b is the fastest mode's own ratio). It is the safe "
            "replacement the measurements support; `esfera modes` could report the "
            "exact ratio phi.C.phi/(2 omega_max) of its top eigenvector phi instead.")
    return txt


def conclusions(results, runs, info):
    """Numbered conclusions, each quoting the numbers it rests on."""
    items = [c_validation(results), c_normal(results), c_tangential(results),
             c_pack(results, info), c_modes(results), c_frac01(results),
             c_signatures(results, runs)]
    return [f"{i + 1}. {t}" for i, t in enumerate(t for t in items if t)]


# ------------------------------------------------------------------------------ main
def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="reduced study (< 60 s)")
    ap.add_argument("--out", default=os.path.join(REPO, "studies", "results",
                                                  "critical_dt"))
    ap.add_argument("--esfera", default=os.path.join(REPO, "build", "esfera"))
    ap.add_argument("--jobs", type=int, default=2, help="concurrent esfera runs")
    ap.add_argument("--replot", action="store_true",
                    help="only redraw the plots and report.md from DIR's CSV files")
    return ap.parse_args(argv)


def main(argv):
    args = parse_args(argv)
    if args.replot:
        return replot(os.path.abspath(args.out))
    t0 = time.time()
    cfg = QUICK if args.quick else FULL
    esfera = os.path.abspath(args.esfera)
    if not os.access(esfera, os.X_OK):
        print(f"critical_dt: no esfera executable at {esfera}", file=sys.stderr)
        return 2
    out = os.path.abspath(args.out)
    work = os.path.join(out, "tmp")
    os.makedirs(work, exist_ok=True)
    pack = prepare_pack(esfera, work, cfg["pack_n"], cfg["pack_box"])
    print(f"critical_dt: pack of {pack['stats']['n']} settled "
          f"({time.time() - t0:.1f} s)", flush=True)
    cases = build_cases(cfg, pack)
    with cf.ThreadPoolExecutor(max_workers=args.jobs) as pool:
        modes = all_modes(esfera, work, cases, pool)
    print(f"critical_dt: modes of {len(cases)} cases ({time.time() - t0:.1f} s)",
          flush=True)
    results, runs = run_all(esfera, work, cases, modes, cfg, args.jobs)
    seconds = time.time() - t0
    write_csv(os.path.join(out, "limits.csv"), results)
    write_csv(os.path.join(out, "runs.csv"), runs)
    write_pack_csv(os.path.join(out, "pack_particles.csv"), pack["pos"], pack["rad"],
                   pack["vel"], pack["spin"])
    info = dict(pack["stats"], quick=int(args.quick), seconds=round(seconds, 1),
                periods=cfg["periods"], esfera=os.path.relpath(esfera, REPO),
                runs=len(runs))
    write_csv(os.path.join(out, "summary.csv"),
              [{"key": k, "value": v} for k, v in info.items()])
    render(out, results, runs, info)
    print(f"critical_dt: {len(results)} limits, {len(runs)} runs, "
          f"{time.time() - t0:.1f} s; results in {out}")
    return 0


def render(out, results, runs, info):
    """Plots and report.md from the results (fresh or read back with --replot)."""
    plot_limits(results, os.path.join(out, "limit_vs_xi.png"))
    plot_margins(results, os.path.join(out, "margins.png"))
    plot_kt(results, os.path.join(out, "limit_vs_kt.png"))
    plot_sweep(runs, results, os.path.join(out, "sweep.png"))
    write_report(os.path.join(out, "report.md"), results, runs, info)


def replot(out):
    results = read_csv(os.path.join(out, "limits.csv"))
    for r in results:
        r["eta"], r["xi"] = float(r["eta"]), float(r["xi"])
    runs = read_csv(os.path.join(out, "runs.csv"))
    info = {r["key"]: r["value"] for r in read_csv(os.path.join(out, "summary.csv"))}
    render(out, results, runs, info)
    print(f"critical_dt: plots and report rewritten in {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
