"""critical_dt_cases.py -- the critical-step study's cases and their runs: the
constants and configurations (FULL, QUICK), the closed forms (damping factor, the modes'
leapfrog limit), the scenes (a sphere on a wall, a pair, the settled pack), `esfera run`
and `esfera modes`, the pack's pouring and settling, the Prober (one case at one step,
stable or not), the bisection and sweep, the rules' steps, and the driver that runs every
case (run_all). Definitions: studies/critical_dt.py's docstring.
"""
import concurrent.futures as cf
import math
import os
import shutil
import subprocess
import threading

import numpy as np

from common import (energy, kinetic, last_frame, parse_line, run, tsuji_zeta,
                    write_scene)

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
RULES = ["cundall", "hart", "damped", "modes", "modes_damped", "bound", "live"]
RULE_LABEL = {"cundall": "Cundall sqrt(m/k)", "hart": "Hart 2 sqrt(m/2k)",
              "damped": "damped 2 sqrt(m/k) f(xi)", "modes": "2/omega_max",
              "modes_damped": "(2/omega_max) f(xi_max)",
              "bound": "(2/omega_max) f(xi_b)",
              "live": "live check: lambda(dt^2 A + 2 dt B) = 4"}


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
            "integrator": {"method": "leapfrog", "dt": 1e-6, "allow_unstable": True,
                           "stability": "warn"},
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
        self.live = []  # (dt, the live check's limit in that run's log)

    def live_at(self, limit):
        """The live check's limit logged by the run nearest the measured limit."""
        if not self.live:
            return float("nan")
        return min(self.live, key=lambda p: abs(math.log(p[0] / limit)))[1]

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
        live = live_limit(self.run_dir)
        if live:
            self.live.append((dt, live))
        shutil.rmtree(self.run_dir, ignore_errors=True)
        unstable = rc != 0 or not growth <= GROWTH
        # the live check (stability: warn) found lambda >= 4: with `stability: stop`
        # (the default without allow_unstable) the same run would have ended with exit 1
        flagged = r.summary.get("stability", 0.0) >= 1.0
        self.rows.append({"case": self.case["name"], "eta": self.case["eta"],
                          "xi": self.case["xi"], "purpose": purpose, "dt": dt,
                          "tau": dt / self.rules["cundall"],
                          "frac_cundall": dt / self.rules["cundall"],
                          "frac_hart": dt / self.rules["hart"],
                          "frac_damped": dt / self.rules["damped"],
                          "steps": n, "exit": rc,
                          "growth": growth, "unstable": int(unstable),
                          "check": int(flagged), "exit_stop": 1 if flagged else rc,
                          "message": first_line(r.stderr.strip()) if rc else ""})
        return unstable


def live_limit(run_dir):
    """The step below which the first live check found the run stable (log.txt)."""
    try:
        with open(os.path.join(run_dir, "log.txt")) as fh:
            for ln in fh:
                if ln.startswith("stability check at step") and "stable below dt = " in ln:
                    return float(ln.split("stable below dt = ")[1].split()[0])
    except OSError:
        pass
    return None


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
    rules["live"] = prober.live_at(limit)
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
