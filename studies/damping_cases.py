"""damping_cases.py -- the damping study's runner and parts 1 and 2 (studies/damping.py
runs them): Runner (scenes into OUT/tmp, esfera runs in parallel), the case and setup
records and the scene's `damping:` entries; the demo sphere's impacts (restitution) and
free vibration on a wall (decay, decrement convergence); Rayleigh damping (mode damping,
pair restitution, free fall). Each *_study runs its scenes and writes its CSV files.
"""
import concurrent.futures
import dataclasses
import math
import os
import shutil

import numpy as np

from common import (cut_impact_closed_form, energy, last_frame, run, tsuji_zeta,
                    write_csv, write_scene)
from damping_forms import (G, cut_impact, decrement_from_peaks, half_cycle_peaks,
                           local_decrement, rayleigh_zeta, viscous_decrement,
                           zeta_from_decrement)


class Runner:
    """Writes scenes to tmp/ and runs esfera on them, jobs at a time."""

    def __init__(self, esfera, tmp, jobs):
        self.esfera, self.tmp, self.jobs = esfera, tmp, jobs
        os.makedirs(tmp, exist_ok=True)

    def run(self, name, scene, sets=(), check=True):
        """Runs one scene into tmp/NAME: a common.Run; raises unless it exits with
        status 0 (check=False: any status)."""
        path = write_scene(os.path.join(self.tmp, name + ".yaml"), scene,
                           "written by studies/damping.py")
        out = os.path.join(self.tmp, name)
        shutil.rmtree(out, ignore_errors=True)
        r = run(self.esfera, path, out, sets)
        return r.check() if check else r

    def map(self, fn, items):
        """fn(item) for every item, in parallel, results in order."""
        with concurrent.futures.ThreadPoolExecutor(self.jobs) as ex:
            return list(ex.map(fn, items))


@dataclasses.dataclass(frozen=True)
class Case:
    """A resting-sphere decay case: damping kind (contact, global, component, vector,
    rayleigh), its parameter (eta, alpha, c, zeta_R) and the Rayleigh frequency f_R."""
    kind: str
    value: float
    freq: float = None


@dataclasses.dataclass
class Setup:
    """One damping setup of a comparison (settling, dynamics, vibrated bed)."""
    label: str
    eta: float = 1.0
    damping: dict = None
    rule: str = "hart"


def local(c, form="component"):
    """The scene's `damping:` entry of local (Cundall) damping c."""
    return {"local": {"coefficient": c, "form": form}}


def drag(alpha):
    """The scene's `damping:` entry of global damping alpha (1/s)."""
    return {"global": {"translation": alpha, "rotation": alpha}}


ADAPTIVE = {"global": {"auto": True}}


# --- part 1: restitution and decay -------------------------------------------------------

DEMO = {"density": 2000.0, "kn": 2.0e7, "radius": 0.05}  # seed 004 Table 1 (r assumed)


def demo_mass():
    return 4 / 3 * math.pi * DEMO["radius"] ** 3 * DEMO["density"]


def demo_material(eta):
    return {"density": DEMO["density"], "kn": DEMO["kn"], "kt": DEMO["kn"],
            "restitution": eta, "friction": 0.0}


def impact_scene(kind, eta, frac, damping=None):
    """A sphere launched at a plane (kind 'wall') or a head-on pair ('pair'), no
    gravity, starting a short flight from contact; runs until the contact force has
    ended and the overlap has closed. Returns (scene, v0, zeta_c, a, omega, t_end)."""
    r, v0 = DEMO["radius"], 0.1
    m = demo_mass()
    mstar = m if kind == "wall" else m / 2
    w = math.sqrt(DEMO["kn"] / mstar)
    zeta = tsuji_zeta(eta)
    a = 0.0
    if damping and "rayleigh" in damping:
        rz, rf = damping["rayleigh"]["zeta"], damping["rayleigh"]["frequency"]
        wr = 2 * math.pi * rf
        zeta, a = rz / wr * w, 2 * wr * rz / w
    e, t_end, u_end = cut_impact(zeta, a)
    gap = 0.02 * v0 / w
    if math.isfinite(t_end):
        t_sep = (t_end + u_end / max(e, 1e-3)) / w
    else:  # the body damper overdamps the relative motion: the contact never ends
        t_sep = 20 / w
    scene = {
        "name": f"impact_{kind}",
        "gravity": [0, 0, 0],
        "materials": {"ball": demo_material(eta),
                      "floor": {"kn": DEMO["kn"], "kt": DEMO["kn"], "restitution": 1.0}},
        "integrator": {"method": "leapfrog", "dt": "auto", "dt_rule": "hart", "frac": frac},
        "run": {"duration": gap / v0 + t_sep + 0.1 / w},
        "output": {"every": 0, "energy_every": 0},
    }
    if kind == "wall":
        scene["particles"] = [{"material": "ball", "radius": r,
                               "position": [0, 0, r + gap], "velocity": [0, 0, -v0]}]
        scene["walls"] = [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]},
                           "material": "floor"}]
    else:
        scene["particles"] = [
            {"material": "ball", "radius": r, "position": [-r - gap / 2, 0, 0],
             "velocity": [v0 / 2, 0, 0]},
            {"material": "ball", "radius": r, "position": [r + gap / 2, 0, 0],
             "velocity": [-v0 / 2, 0, 0]}]
    if damping:
        scene["damping"] = damping
    return scene, v0, zeta, a, w, t_end / w


def measure_impact(R, name, kind, eta, frac, damping=None):
    """Runs one impact; returns {e (measured), zeta, a, omega, dt}. With a body damper
    (Rayleigh) the free flight after the contact, which decays as exp(-alpha t), is
    divided out: e = v(T) / v0 x exp(alpha (T - t_end))."""
    scene, v0, zeta, a, w, t_end = impact_scene(kind, eta, frac, damping)
    r = R.run(name, scene)
    t, d = last_frame(r.out)
    v = d["velocity"]
    e = v[0, 2] / v0 if kind == "wall" else (v[1, 0] - v[0, 0]) / v0
    if np.any(d["force"] != 0):  # still in contact: the run was too short
        e = float("nan")
    e = e * math.exp(a * w * (t - t_end)) if math.isfinite(t_end) else float("nan")
    return dict(e=e, zeta=zeta, a=a, omega=w, dt=r.summary.get("dt", float("nan")))


def restitution_study(R, Q, res):
    """Measured restitution of wall and pair impacts over eta and frac."""
    jobs = [(kind, eta, frac) for frac in Q["fracs"] for kind in ("wall", "pair")
            for eta in Q["etas"]]

    def one(job):
        kind, eta, frac = job
        return measure_impact(R, f"rest_{kind}_{eta:g}_{frac:g}", kind, eta, frac)

    rows = []
    for (kind, eta, frac), m in zip(jobs, R.map(one, jobs)):
        zeta = m["zeta"]
        e_ex = cut_impact(zeta).e
        e_cf = cut_impact_closed_form(zeta).e if zeta < 1 else float("nan")
        rows.append(dict(kind=kind, eta_requested=eta, zeta=zeta, frac=frac,
                         omega_dt=m["omega"] * m["dt"], e_measured=m["e"], e_closed_form=e_cf,
                         e_exact_solver=e_ex, rel_error=m["e"] / e_ex - 1))
    write_csv(os.path.join(res, "restitution.csv"), rows, blank=True)
    return rows


def resting_scene(case, frac, periods):
    """A sphere resting on a plane at its static overlap, kicked upward at half the
    speed that would lift it off; the energy ledger every step."""
    kind, val = case.kind, case.value
    r, m, k = DEMO["radius"], demo_mass(), DEMO["kn"]
    w = math.sqrt(k / m)
    u_eq = m * G / k
    eta, damping = 1.0, {}
    if kind == "contact":
        eta = val
    elif kind == "global":
        damping = drag(val)
    elif kind in ("component", "vector"):
        damping = local(val, kind)
    elif kind == "rayleigh":
        damping = {"rayleigh": {"zeta": val, "frequency": case.freq}}
    scene = {
        "name": "resting",
        "gravity": [0, 0, -G],
        "materials": {"ball": demo_material(eta),
                      "floor": {"kn": k, "kt": k, "restitution": 1.0}},
        "particles": [{"material": "ball", "radius": r, "position": [0, 0, r - u_eq],
                       "velocity": [0, 0, 0.5 * u_eq * w]}],
        "walls": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]},
                   "material": "floor"}],
        "integrator": {"method": "leapfrog", "dt": "auto", "dt_rule": "hart", "frac": frac},
        "contact": {"allow_initial_overlap": True},  # it starts pressed in, at rest
        "run": {"duration": periods * 2 * math.pi / w},
        "output": {"every": 0, "energy_every": 1e-12},
    }
    if damping:
        scene["damping"] = damping
    return scene, w, u_eq


def nominal_decrement(case, w):
    """(zeta nominal, decrement expected) of a resting-sphere case."""
    kind, val = case.kind, case.value
    if kind == "contact":
        z = tsuji_zeta(val)
        return z, viscous_decrement(z)
    if kind == "global":
        z = val / (2 * w)
        return z, viscous_decrement(z)
    if kind in ("component", "vector"):
        d = local_decrement(val)
        return zeta_from_decrement(d), d
    z = rayleigh_zeta(val, w / (2 * math.pi * case.freq))
    return z, viscous_decrement(z)


def measure_decay(R, name, case, frac, periods):
    """Runs a resting-sphere case; returns dict with the measured decrement."""
    scene, w, u_eq = resting_scene(case, frac, periods)
    E = energy(R.run(name, scene).out)
    u = np.sqrt(np.maximum(2 * E["elastic_normal"] / DEMO["kn"], 0))
    x = u - u_eq
    tp, xp = half_cycle_peaks(E["time"], x)
    delta, npk = decrement_from_peaks(xp, 1e-15)
    z_nom, d_nom = nominal_decrement(case, w)
    z_meas = zeta_from_decrement(delta) if np.isfinite(delta) else float("nan")
    return {"case": case, "t": E["time"], "x": x, "delta": delta, "peaks": npk,
            "zeta_nominal": z_nom, "delta_nominal": d_nom, "zeta_measured": z_meas,
            "half_ratio": math.exp(-delta / 2) if np.isfinite(delta) else float("nan"),
            "omega": w}


def decay_study(R, Q, res):
    cases = [Case("contact", eta) for eta in Q["decay_etas"]]
    cases += [Case("global", global_alpha(z)) for z in Q["decay_zetas"]]
    cases += [Case(form, c) for form in ("component", "vector") for c in Q["local_coefs"]]

    def one(case):
        return measure_decay(R, f"decay_{case.kind}_{case.value:g}", case, Q["decay_frac"],
                             Q["periods"])

    got = R.map(one, cases)
    write_csv(os.path.join(res, "decay.csv"), [dict(
        damping=g["case"].kind, parameter=g["case"].value, zeta_nominal=g["zeta_nominal"],
        decrement_expected=g["delta_nominal"], decrement_measured=g["delta"],
        zeta_measured=g["zeta_measured"], half_cycle_ratio=g["half_ratio"],
        peaks_used=g["peaks"]) for g in got], blank=True)
    etas, fracs = Q["decay_conv"]
    jobs = [(eta, fr) for eta in etas for fr in fracs]

    def conv(job):
        eta, fr = job
        return measure_decay(R, f"decay_conv_{eta:g}_{fr:g}", Case("contact", eta), fr,
                             Q["periods"])

    crow = [dict(eta_requested=eta, frac=fr,
                 omega_dt=fr * math.sqrt(2),  # Hart's step x frac, times omega (wall)
                 half_cycle_ratio=g["half_ratio"], decrement_measured=g["delta"],
                 decrement_expected=g["delta_nominal"],
                 rel_error=g["delta"] / g["delta_nominal"] - 1)
            for (eta, fr), g in zip(jobs, R.map(conv, jobs))]
    write_csv(os.path.join(res, "decay_convergence.csv"), crow, blank=True)
    return got, crow


def global_alpha(zeta):
    """The global damping alpha (1/s) giving the resting sphere the ratio zeta."""
    return 2 * zeta * math.sqrt(DEMO["kn"] / demo_mass())


# --- part 2: Rayleigh ---------------------------------------------------------------------


def rayleigh_study(R, Q, res):
    zr = Q["rayleigh_zeta"]
    w_wall = math.sqrt(DEMO["kn"] / demo_mass())
    fc = w_wall / (2 * math.pi)
    ratios = Q["rayleigh_ratios"]
    cases = [Case("rayleigh", zr, fc * q) for q in ratios]

    def decay(case):
        return measure_decay(R, f"ray_decay_{case.freq:.6g}", case, Q["decay_frac"],
                             Q["periods"])

    def impact(case):
        damp = {"rayleigh": {"zeta": case.value, "frequency": case.freq}}
        return measure_impact(R, f"ray_pair_{case.freq:.6g}", "pair", 1.0,
                              Q["ray_impact_frac"], damp)

    dec = R.map(decay, cases)
    imp = R.map(impact, cases)
    rows = []
    w_pair = math.sqrt(2) * w_wall
    for q, d, m in zip(ratios, dec, imp):
        zc, e = m["zeta"], m["e"]
        ref = cut_impact(zc, m["a"]).e
        rows.append(dict(
            zeta_R=zr, f_R_Hz=fc * q, f_R_over_f_wall=q,
            zeta_mode_wall_expected=d["zeta_nominal"],
            zeta_mode_wall_measured=d["zeta_measured"],
            zeta_mode_pair_expected=rayleigh_zeta(zr, w_pair / (2 * math.pi * fc * q)),
            zeta_contact_pair_beta=zc, alpha_1_per_s=m["a"] * m["omega"],
            e_pair_measured=e, e_pair_expected=ref,
            rel_error=e / ref - 1 if ref > 0 else float("nan"),
            e_pair_contact_dashpot_only=cut_impact(zc).e))
    write_csv(os.path.join(res, "rayleigh.csv"), rows, blank=True)
    ff = freefall_rayleigh(R, Q)
    return rows, fc, ff


def freefall_rayleigh(R, Q):
    """A sphere falling from rest under the example Rayleigh setting: terminal speed
    against g / alpha and the e-folding time 1/alpha."""
    zr, fr = Q["rayleigh_zeta"], Q["rayleigh_example_f"]
    alpha = 2 * (2 * math.pi * fr) * zr
    scene = {
        "name": "freefall",
        "gravity": [0, 0, -G],
        "materials": {"ball": demo_material(1.0)},
        "particles": [{"material": "ball", "radius": DEMO["radius"], "position": [0, 0, 0]}],
        "damping": {"rayleigh": {"zeta": zr, "frequency": fr}},
        "integrator": {"method": "leapfrog", "dt": 1e-4},
        "run": {"duration": 5 / alpha},
        "output": {"every": 0, "energy_every": 0},
    }
    t, d = last_frame(R.run("ray_freefall", scene).out)
    return {"zeta": zr, "f": fr, "alpha": alpha, "v_end": -d["velocity"][0, 2],
            "v_term": G / alpha, "t": t,
            "v_expected": G / alpha * (1 - math.exp(-alpha * t)),
            "fall_1s_undamped": 0.5 * G,
            "fall_1s": G / alpha * (1 - (1 - math.exp(-alpha)) / alpha)}
