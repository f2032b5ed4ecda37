#!/usr/bin/python3
"""Study 2 (issue 7): damping in esfera — what each damping model delivers.

Every experiment writes an esfera scene into OUT/tmp, runs `esfera run SCENE --out D
--quiet`, reads D/energy.csv and D/frames.h5 and compares the measurement with the
closed form of the model where one exists.

Definitions
-----------
eta       the restitution requested from a material (`restitution`); the normal
          dashpot is c = 2 zeta sqrt(m* k) with Tsuji's zeta = -ln eta /
          sqrt(pi^2 + ln^2 eta) (004 2.27-2.29), m* the reduced mass (m at a wall).
omega     the contact's natural frequency sqrt(k/m*), f_c = omega / 2 pi.
e         measured restitution: separation speed / approach speed of an impact.
cut form  the linear spring-dashpot impact with the no-tension cut (the contact ends
          when k u + c u' returns to zero, not when u does):
          e = -exp(-zeta th/s)(cos th - zeta/s sin th), th = pi - atan2(2 zeta s,
          1 - 2 zeta^2), s = sqrt(1 - zeta^2) (tests/simtest.h, in studies/common.py); for
          zeta >= 1 (and with a body damper) the same cut oscillator solved exactly.
log decrement  delta = ln(x_k / x_{k+1}) for successive peaks one period apart of the
          free vibration x(t) of a sphere resting on a wall about its equilibrium; we
          fit ln|x| over all half-cycle peaks, so delta = -2 x slope per half cycle and
          zeta_measured = delta / sqrt(4 pi^2 + delta^2).
          Viscous: delta = 2 pi zeta / sqrt(1 - zeta^2), i.e. one half cycle
          multiplies the amplitude by exactly eta (Tsuji's relation).
          Global damping alpha (1/s): zeta = alpha / (2 omega).
          Local (Cundall) damping coefficient c: the damping force c|F| opposes v, so
          the effective stiffness is k(1 + c) moving out and k(1 - c) moving in, and
          one half cycle multiplies the amplitude by sqrt((1 - c)/(1 + c)):
          delta = ln((1 + c)/(1 - c)) ~ 2c, zeta_equiv ~ c / pi.
          Rayleigh (001 3.59-3.60; zeta_R, f_R): alpha = 2 omega_R zeta_R on the
          bodies, c = beta k with beta = 2 zeta_R / omega_R on the contacts, so a mode
          of frequency f gets zeta(f) = (alpha/omega + beta omega)/2
          = zeta_R (f_R / f + f / f_R): 2 zeta_R at f = f_R, since each of the seed's
          two coefficients alone already gives zeta_R there.
unbalanced force  |F_i| / (m_i g), F_i the frames' `force` dataset (contacts and
          gravity, without the damping force), averaged over the spheres.
pour      spheres generated loose in a box fall and settle; settled when the kinetic
          energy (translational and rotational) stays below ke_frac x N m g d (N
          spheres of mean mass m and mean diameter d). Reported: steps to get there,
          the final solid fraction in a slab away from floor and free surface, and the
          last frame's unbalanced force.
load step the settled pack reloaded at rest under 2 g (a quasi-static loading step);
          converged when the mean unbalanced force stays below force_tol x m g.

Experiments
-----------
1. Restitution: a sphere launched at a plane and a free head-on pair, eta = 1e-7 ... 1,
   several time steps (first-order convergence of the leapfrog's dashpot); the decay of
   a sphere resting on a wall after a vertical kick (contact dashpot, global and local
   damping of both forms). Parameters of seed 004's damping demo (Table 1: k = 2e7 N/m,
   rho = 2000 kg/m^3; radius 0.05 m assumed as in scenes/damping_demo.yaml).
2. Rayleigh: zeta_R = 0.05 (the example of docs/scene.md; seed 001 gives the formulas
   and names the inputs `_frac`, `_freq`, but no values) at f_R / f_c = 0.03 ... 30:
   the modal damping of the resting sphere and the restitution of a pair, against
   zeta(f); the body damper's free-fall terminal speed g / alpha; the contact damping
   the example setting gives on the study's pack.
3. Local vs global vs adaptive damping: (a) quasi-static settling of a pack (a pour
   and a load step); (b) a bouncing sphere (apex heights against the undamped sphere
   and the closed forms) and a pulse along a chain of touching spheres (arrival time
   and amplitude at the far end); seed 004's vibrated bed (quasi-2D quick variant,
   25 Hz, 6 g; moving walls of issue 4): flight height and period of the bed's centre
   of mass against the inelastic bouncing-ball model, and where the shaker's work goes.
   With an esfera that refuses wall motion the report says the bed is not available.

Running
-------
    /usr/bin/python3 studies/damping.py [--quick] [--out DIR] [--esfera PATH] [--jobs N]

Defaults: --esfera build/esfera and --out studies/results/damping (relative to the
repository root), --jobs 2. --quick runs a reduced set (under a minute on 2 cores).
Writes DIR/*.csv, DIR/*.png and DIR/report.md; scenes and raw runs go to DIR/tmp.
Needs Debian's python3 with numpy, matplotlib and h5py.
"""
import argparse
import collections
import concurrent.futures
import dataclasses
import math
import os
import shutil
import sys
import time

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from common import (cut_impact_closed_form, energy, fmt, frames, kinetic,  # noqa: E402
                    last_frame, run, tsuji_zeta, write_csv, write_particles_csv,
                    write_scene)

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
G = 9.81


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


# --- closed forms -----------------------------------------------------------------------


Cut = collections.namedtuple("Cut", "e t_end u_end")


def cut_impact(zeta_c, a=0.0):
    """The cut impact for any contact damping ratio zeta_c and a body damper alpha =
    a omega acting on the relative velocity as well (Rayleigh's mass term): returns
    Cut(e, t_end omega, overlap at t_end x omega / v0). Solved exactly (the closed form
    common.cut_impact_closed_form covers 0 <= zeta_c < 1 without the body damper):
    u'' + (2 zeta_c + a) u' + u = 0 (omega = 1)
    from u = 0, u' = 1, until the contact force u + 2 zeta_c u' returns to zero."""
    zt = zeta_c + a / 2
    root = np.sqrt(complex(zt * zt - 1))
    if abs(root) < 1e-9:
        root = 1e-9  # critical: the limit of the formula below
    lp, lm = -zt + root, -zt - root

    def state(t):
        ep, em = np.exp(lp * t), np.exp(lm * t)
        return ((ep - em) / (lp - lm)).real, ((lp * ep - lm * em) / (lp - lm)).real

    def force(t):
        u, v = state(t)
        return u + 2 * zeta_c * v

    if zeta_c == 0:
        tz = math.pi / abs(root.imag) if zt < 1 else float("inf")
    else:  # first sign change of the force, scanning then bisecting
        t, h, tz = 0.0, 0.01, None
        while t < 200:
            if force(t + h) <= 0:
                lo, hi = t, t + h
                for _ in range(80):
                    mid = 0.5 * (lo + hi)
                    lo, hi = (mid, hi) if force(mid) > 0 else (lo, mid)
                tz = hi
                break
            t += h
        if tz is None:
            return Cut(0.0, float("inf"), 0.0)
    u, v = state(tz)
    return Cut(-v, tz, u)


def viscous_decrement(zeta):
    return 2 * math.pi * zeta / math.sqrt(1 - zeta * zeta) if zeta < 1 else float("inf")


def zeta_from_decrement(delta):
    return delta / math.sqrt(4 * math.pi**2 + delta * delta)


def local_decrement(c):
    """Log decrement of a linear oscillator under Cundall's local damping c."""
    return math.log((1 + c) / (1 - c))


def rayleigh_zeta(zeta_r, f_over_fr):
    """Modal damping ratio of a mode at f under Rayleigh damping with the seed's
    alpha = 2 omega_R zeta_R and beta = 2 zeta_R / omega_R (001 3.59-3.60):
    zeta(f) = (alpha / omega + beta omega) / 2 = zeta_R (f_R / f + f / f_R), which is
    2 zeta_R at f = f_R (each term alone would give zeta_R there)."""
    return zeta_r * (1 / f_over_fr + f_over_fr)


# --- measurements -----------------------------------------------------------------------


def half_cycle_peaks(t, x):
    """(times, |peaks|) of x between successive zero crossings, each peak refined by a
    parabola through three samples. The trailing half cycle counts only when it has
    died out (|x| at the end below 1% of its peak: the motion froze at round-off)."""
    sign = np.sign(x)
    cross = np.nonzero(sign[1:] * sign[:-1] < 0)[0] + 1
    bounds = np.concatenate([[0], cross])
    tail = np.abs(x[bounds[-1]:])
    if len(tail) > 2 and tail[-1] < 0.01 * tail.max():
        bounds = np.concatenate([bounds, [len(x)]])
    tp, xp = [], []
    for a, b in zip(bounds[:-1], bounds[1:]):
        k = a + int(np.argmax(np.abs(x[a:b])))
        if 0 < k < len(x) - 1:
            y0, y1, y2 = np.abs(x[k - 1 : k + 2])
            den = y0 - 2 * y1 + y2
            d = 0.5 * (y0 - y2) / den if den != 0 else 0.0
            tp.append(t[k] + d * (t[k + 1] - t[k]))
            xp.append(y1 - 0.25 * (y0 - y2) * d)
        else:
            tp.append(t[k])
            xp.append(abs(x[k]))
    return np.array(tp), np.array(xp)


def decrement_from_peaks(xp, floor):
    """Log decrement per full cycle from the half-cycle peaks above floor (least-squares
    slope of ln|peak| per half cycle, times -2); nan with fewer than two peaks."""
    keep = np.nonzero(xp > floor)[0]
    if len(keep):  # the leading run of consecutive half cycles
        gaps = np.nonzero(np.diff(keep) != 1)[0]
        keep = keep[: gaps[0] + 1] if len(gaps) else keep
    if len(keep) < 2:
        return float("nan"), len(keep)
    slope = np.polyfit(keep, np.log(xp[keep]), 1)[0]
    return -2 * slope, len(keep)


def apex_heights(t, z):
    """Local maxima of z(t) after the start, refined by parabolas: (times, heights)."""
    k = np.nonzero((z[1:-1] > z[:-2]) & (z[1:-1] >= z[2:]))[0] + 1
    tp, zp = [], []
    for i in k:
        y0, y1, y2 = z[i - 1 : i + 2]
        den = y0 - 2 * y1 + y2
        d = 0.5 * (y0 - y2) / den if den != 0 else 0.0
        tp.append(t[i] + d * (t[i + 1] - t[i]))
        zp.append(y1 - 0.25 * (y0 - y2) * d)
    return np.array(tp), np.array(zp)


def cross_time(t, y, level):
    """First time y reaches level (linear interpolation); nan if never."""
    k = np.nonzero(y >= level)[0]
    if len(k) == 0:
        return float("nan")
    i = k[0]
    if i == 0:
        return t[0]
    return t[i - 1] + (level - y[i - 1]) / (y[i] - y[i - 1]) * (t[i] - t[i - 1])


def slab_fraction(z, r, a, b, area):
    """Solid fraction of spheres (centres z, radii r) in the slab a < z < b."""
    lo = np.clip(a - z, -r, r)
    hi = np.clip(b - z, -r, r)
    vol = np.pi * (r * r * (hi - lo) - (hi**3 - lo**3) / 3)
    return vol.sum() / (area * (b - a))


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


def worst_moderate(rest, frac):
    """Largest |e / e_exact - 1| of the impacts at frac with eta 0.1-0.9 (nan: none)."""
    errs = [abs(r["rel_error"]) for r in rest
            if r["frac"] == frac and 0.1 <= r["eta_requested"] <= 0.9]
    return max(errs) if errs else float("nan")


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


def plot_part1(rest, decay, res, Q):
    fig, ax = plt.subplots(1, 3, figsize=(16, 4.8))
    etas = np.logspace(-7, 0, 200)
    ax[0].semilogx(etas, [cut_impact_closed_form(tsuji_zeta(x)).e if x < 1 else 1
                          for x in etas], "k-", label="cut oscillator (closed form)")
    ax[0].semilogx(etas, etas, "k:", label="requested e = eta")
    fbest = min(Q["fracs"])
    for kind, mk in (("wall", "o"), ("pair", "s")):
        pts = [(r["eta_requested"], r["e_measured"]) for r in rest
               if r["kind"] == kind and r["frac"] == fbest]
        ax[0].semilogx(*zip(*pts), mk, mfc="none", label=f"{kind}, frac {fbest:g}")
    ax[0].set_xlabel("requested restitution eta")
    ax[0].set_ylabel("measured restitution e")
    ax[0].set_title("Impact restitution (seed 004 demo sphere)")
    ax[0].legend(fontsize=8)
    for kind, ls in (("wall", "-"), ("pair", "--")):
        for eta in Q["err_etas"]:
            pts = sorted((r["omega_dt"], abs(r["rel_error"])) for r in rest
                         if r["kind"] == kind and r["eta_requested"] == eta)
            if pts:
                ax[1].loglog(*zip(*pts), ls, marker="o", ms=3, label=f"{kind} eta {eta:g}")
    ax[1].set_xlabel("omega dt")
    ax[1].set_ylabel("|e / e_exact - 1|")
    ax[1].set_title("Leapfrog error in restitution (first order)")
    ax[1].legend(fontsize=7, ncol=2)
    zz = np.linspace(0, 0.99, 200)
    ax[2].plot(zz, zz, "k-", lw=0.8, label="measured = nominal")
    marks = {"contact": "o", "global": "s", "component": "^", "vector": "v"}
    for kind, mk in marks.items():
        pts = [(g["zeta_nominal"], g["zeta_measured"]) for g in decay
               if g["case"].kind == kind]
        if pts:
            ax[2].plot(*zip(*pts), mk, mfc="none", label=kind if kind in
                       ("contact", "global") else f"local {kind} (zeta of its decrement)")
    cs = np.linspace(0.001, 0.95, 200)
    ax[2].plot([zeta_from_decrement(local_decrement(c)) for c in cs], cs / math.pi, "c:",
               label="c / pi (small-c rule)")
    ax[2].set_xlabel("nominal damping ratio zeta")
    ax[2].set_ylabel("zeta from measured log decrement")
    ax[2].set_title("Free vibration of a sphere resting on a wall")
    ax[2].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(res, "restitution_decay.png"), dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for g in decay:
        if g["case"] in Q["decay_show"]:
            w = g["omega"]
            ax.semilogy(g["t"] * w / (2 * math.pi), np.abs(g["x"]) + 1e-30,
                        lw=0.8, label=f"{g['case'].kind} {g['case'].value:.3g}")
    ax.set_ylim(1e-17, 1e-6)
    ax.set_xlabel("time / contact period")
    ax.set_ylabel("|u - u_static| (m)")
    ax.set_title("Resting sphere after a kick")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(res, "decay_series.png"), dpi=110)
    plt.close(fig)


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
    plot_rayleigh(rows, res, zr, fc, ff)
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


def plot_rayleigh(rows, res, zr, fc, ff):
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    q = np.logspace(-2, 2, 300)
    ax[0].loglog(q, rayleigh_zeta(zr, 1 / q), "k-", label="zeta(f) = zeta_R (f_R/f + f/f_R)")
    ax[0].loglog(q, zr * q, "k:", lw=0.8, label="mass term alpha / 2 omega")
    ax[0].loglog(q, zr / q, "k--", lw=0.8, label="stiffness term beta omega / 2")
    ax[0].axhline(zr, color="r", lw=0.6, label="zeta_R requested")
    pts = [(r["f_R_over_f_wall"], r["zeta_mode_wall_measured"]) for r in rows]
    ax[0].loglog(*zip(*pts), "o", mfc="none", label="measured, sphere on wall")
    ax[0].axhline(1, color="grey", lw=0.5)
    ax[0].set_xlabel("f_R / f_contact")
    ax[0].set_ylabel("damping ratio of the contact mode")
    ax[0].set_title(f"Rayleigh zeta_R = {zr:g}: damping of a mode at f_contact = {fc:.0f} Hz")
    ax[0].legend(fontsize=8)
    qq = [r["f_R_over_f_wall"] for r in rows]
    ax[1].semilogx(qq, [r["e_pair_measured"] for r in rows], "o", mfc="none",
                   label="measured pair restitution")
    ax[1].semilogx(qq, [r["e_pair_expected"] for r in rows], "k-",
                   label="cut oscillator with alpha and beta")
    ax[1].semilogx(qq, [r["e_pair_contact_dashpot_only"] for r in rows], "k:",
                   label="contact dashpot beta k only")
    ax[1].set_xlabel("f_R / f_contact (wall)")
    ax[1].set_ylabel("restitution of a head-on pair")
    ax[1].set_title("Impact restitution under Rayleigh damping")
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(os.path.join(res, "rayleigh.png"), dpi=110)
    plt.close(fig)


def rayleigh_on_pack(Q):
    """What the example Rayleigh setting gives on the study's pack contacts."""
    zr, fr = Q["rayleigh_zeta"], Q["rayleigh_example_f"]
    wr = 2 * math.pi * fr
    beta, alpha = 2 * zr / wr, 2 * wr * zr
    P = PACK
    out = []
    for label, r, wall in (("smallest pair", P["rmin"], False),
                           ("mean pair", P["rmean"], False),
                           ("largest pair", P["rmax"], False),
                           ("mean sphere on wall", P["rmean"], True)):
        m = 4 / 3 * math.pi * r**3 * P["density"]
        w = math.sqrt(P["kn"] / (m if wall else 0.5 * m))
        zc = beta * w / 2
        out.append(dict(contact=label, f_c=w / (2 * math.pi), zeta_dashpot=zc,
                        zeta_with_alpha=0.5 * (alpha / w) + zc, e=cut_impact(zc, alpha / w).e))
    return alpha, beta, out


# --- part 3a: settling a pack ----------------------------------------------------------

PACK = {"density": 2500.0, "kn": 1.0e4, "kt": 7.0e3, "rmin": 0.0012, "rmax": 0.0022,
        "rmean": 0.0017, "friction": 0.5, "box": 0.02}


def pack_materials(eta):
    P = PACK
    return {"g": {"density": P["density"], "kn": P["kn"], "kt": P["kt"], "restitution": eta,
                  "friction": P["friction"]},
            "wall": {"kn": P["kn"], "kt": P["kt"], "restitution": eta,
                     "friction": P["friction"]}}


def pack_scene(Q, eta, damping, source=None, rule="hart"):
    """The pour (source None: spheres generated loose and let fall under g) or the load
    step (source: a CSV of a settled pack, reloaded at rest under 2 g)."""
    L = PACK["box"]
    H = Q["pack_height"]
    if source is None:
        parts = [{"generate": "random", "region": {"min": [0, 0, 0], "max": [L, L, H]},
                  "count": Q["pack_n"],
                  "radius": {"uniform": [PACK["rmin"], PACK["rmax"]]},
                  "material": "g", "seed": 11}]
        gz, dur, every, frame_every = -G, Q["pack_duration"], Q["pack_energy_every"], 0
    else:
        parts = [{"file": source, "material": "g"}]
        gz, dur = -2 * G, Q["load_duration"]
        every, frame_every = Q["load_duration"] / 2000, Q["load_duration"] / Q["load_frames"]
    scene = {
        "name": "settle",
        "gravity": [0, 0, gz],
        "materials": pack_materials(eta),
        "particles": parts,
        "walls": [{"box": {"min": [0, 0, 0], "max": [L, L, 2 * H]}, "open": ["top"],
                   "material": "wall"}],
        "contact": {"allow_initial_overlap": True},
        "integrator": {"method": "leapfrog", "dt": "auto", "dt_rule": rule, "frac": 0.1},
        "run": {"duration": dur},
        "output": {"every": frame_every, "energy_every": every},
    }
    if damping:
        scene["damping"] = damping
    return scene


def pack_configs(Q, stage):
    """The setups (label, material restitution, damping, dt rule) of the settling
    comparison."""
    ray = {"rayleigh": {"zeta": Q["rayleigh_zeta"], "frequency": Q["rayleigh_example_f"]}}
    rlab = f"Rayleigh zeta {Q['rayleigh_zeta']:g}, f {Q['rayleigh_example_f']:g} Hz"
    full = [Setup("none (eta 1, friction only)"),
            Setup("contact dashpot eta 0.5", 0.5),
            Setup("local component 0.7", damping=local(0.7)),
            Setup("local vector 0.7", damping=local(0.7, "vector")),
            Setup("local component 0.3", damping=local(0.3)),
            Setup("global alpha 20/s", damping=drag(20.0)),
            Setup("global alpha 200/s", damping=drag(200.0)),
            Setup("adaptive global", damping=ADAPTIVE),
            Setup(rlab, damping=ray),
            Setup(rlab + ", damped dt rule", damping=ray, rule="damped")]
    if not Q["quick"]:
        return full
    keep = {"pour": ("none (eta 1, friction only)", "contact dashpot eta 0.5",
                     "local component 0.7", "global alpha 20/s"),
            "load": ("none (eta 1, friction only)", "local component 0.7",
                     "local vector 0.7", "global alpha 20/s", "adaptive global")}[stage]
    return [c for c in full if c.label in keep]


def ke_settle_time(t, ke, thr):
    """First time after which ke stays below thr (nan if it ends above)."""
    above = np.nonzero(ke > thr)[0]
    if len(above) and above[-1] == len(ke) - 1:
        return float("nan")
    return t[above[-1] + 1] if len(above) else t[0]


def unbalanced(d, g=G):
    """Per-particle |F| / (m g) of a frame (F: contacts and gravity)."""
    m = 4 / 3 * np.pi * d["radius"] ** 3 * PACK["density"]
    return np.linalg.norm(d["force"], axis=1) / (m * g)


def pack_fraction(d):
    """Solid fraction in the slab from one mean diameter above the floor to two below
    the highest sphere top."""
    z, r = d["position"][:, 2], d["radius"]
    top = np.max(z + r)
    dbar = 2 * r.mean()
    return slab_fraction(z, r, dbar, top - 2 * dbar, PACK["box"] ** 2), top


def measure_pour(R, Q, k, cfg):
    run_ = R.run(f"pour_{k}", pack_scene(Q, cfg.eta, cfg.damping, rule=cfg.rule))
    out, summ = run_.out, run_.summary
    E = energy(out)
    d1 = last_frame(out).data
    r = d1["radius"]
    mass = 4 / 3 * np.pi * r**3 * PACK["density"]
    scale = len(r) * mass.mean() * G * 2 * r.mean()
    ke = kinetic(E) / scale
    t_settle = ke_settle_time(E["time"], ke, Q["ke_frac"])
    phi, top = pack_fraction(d1)
    fres = unbalanced(d1)
    return {"label": cfg.label, "t": E["time"], "ke": ke, "dt": summ["dt"], "out": out,
            "steps_settle": t_settle / summ["dt"], "t_settle": t_settle, "phi": phi,
            "f_res": fres.mean(), "f_res_med": np.median(fres), "ke_end": ke[-1],
            "height": top, "wall_s": summ.get("wall_s", float("nan"))}


def measure_load(R, Q, k, cfg, source):
    run_ = R.run(f"load_{k}", pack_scene(Q, cfg.eta, cfg.damping, source, cfg.rule))
    summ = run_.summary
    fr = frames(run_.out)
    t = np.array([f.time for f in fr])
    fmean = np.array([unbalanced(f.data).mean() for f in fr])
    E = energy(run_.out)
    t_f = ke_settle_time(t, fmean, Q["force_tol"])
    d0, d1 = fr[0].data, fr[-1].data
    phi, _ = pack_fraction(d1)
    return {"label": cfg.label, "t": t, "fmean": fmean, "dt": summ["dt"], "t_f": t_f,
            "steps_f": t_f / summ["dt"], "f_end": fmean[-1],
            "f_med_end": np.median(unbalanced(d1)), "ke_t": E["time"], "ke": kinetic(E),
            "phi": phi,
            "drop": (np.mean(d0["position"][:, 2]) - np.mean(d1["position"][:, 2]))}


def settling_study(R, Q, res):
    cfgs = pack_configs(Q, "pour")
    pour = R.map(lambda kc: measure_pour(R, Q, *kc), list(enumerate(cfgs)))
    write_csv(os.path.join(res, "settling_pour.csv"), [dict(
        damping=g["label"], steps_to_ke_threshold=g["steps_settle"],
        time_to_ke_threshold_s=g["t_settle"], solid_fraction=g["phi"],
        mean_unbalanced_force_over_mg=g["f_res"], median_unbalanced_force_over_mg=g["f_res_med"],
        final_ke_over_NmgD=g["ke_end"], pack_top_m=g["height"]) for g in pour], blank=True)
    src_cfg = next(g for g in pour if g["label"] == Q["load_source"])
    source = os.path.join(R.tmp, "settled_pack.csv")
    write_particles_csv(source, last_frame(src_cfg["out"]).data)
    cfgs = pack_configs(Q, "load")
    load = R.map(lambda kc: measure_load(R, Q, *kc, source), list(enumerate(cfgs)))
    write_csv(os.path.join(res, "settling_load.csv"), [dict(
        damping=g["label"], steps_to_force_tolerance=g["steps_f"],
        time_to_force_tolerance_s=g["t_f"], final_mean_unbalanced_force_over_mg=g["f_end"],
        final_median_unbalanced_force_over_mg=g["f_med_end"], solid_fraction=g["phi"],
        mean_settlement_m=g["drop"]) for g in load], blank=True)
    plot_settling(pour, load, res, Q)
    return pour, load


def plot_settling(pour, load, res, Q):
    fig, ax = plt.subplots(1, 2, figsize=(14, 5))
    for g in pour:
        ax[0].semilogy(g["t"] / g["dt"], np.maximum(g["ke"], 1e-14), lw=1, label=g["label"])
    ax[0].axhline(Q["ke_frac"], color="k", ls=":", lw=0.8, label="threshold")
    ax[0].set_xlabel("steps")
    ax[0].set_ylabel("kinetic energy / (N m g d)")
    ax[0].set_title(f"(a1) Pour: {Q['pack_n']} spheres fall into a box")
    ax[0].legend(fontsize=7)
    for g in load:
        ax[1].semilogy(g["t"] / g["dt"], np.maximum(g["fmean"], 1e-6), lw=1, label=g["label"])
    ax[1].axhline(Q["force_tol"], color="k", ls=":", lw=0.8, label="tolerance")
    ax[1].set_xlabel("steps")
    ax[1].set_ylabel("mean |F| / (m g)")
    ax[1].set_title("(a2) Load step: the settled pack under 2 g")
    ax[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(res, "settling.png"), dpi=110)
    plt.close(fig)


# --- part 3b: dynamics: bouncing sphere and chain pulse --------------------------------

BALL = {"density": 2500.0, "kn": 1.0e6, "radius": 0.01, "h0": 0.1}


def dynamic_configs(Q):
    cfgs = [Setup("undamped"),
            Setup("contact eta 0.8", 0.8),
            Setup("global alpha 1/s", damping=drag(1.0)),
            Setup("global alpha 100/s", damping=drag(100.0)),
            Setup("local component 0.1", damping=local(0.1)),
            Setup("local component 0.3", damping=local(0.3)),
            Setup("local component 0.7", damping=local(0.7)),
            Setup("local vector 0.7", damping=local(0.7, "vector")),
            Setup("adaptive global", damping=ADAPTIVE)]
    if Q["quick"]:
        cfgs = [c for c in cfgs if c.label in ("undamped", "contact eta 0.8",
                                               "local component 0.7", "global alpha 1/s")]
    return cfgs


def bounce_scene(eta, damping, duration):
    b = BALL
    scene = {
        "name": "bounce",
        "gravity": [0, 0, -G],
        "materials": {"ball": {"density": b["density"], "kn": b["kn"], "restitution": eta},
                      "floor": {"kn": b["kn"], "restitution": 1.0}},
        "particles": [{"material": "ball", "radius": b["radius"],
                       "position": [0, 0, b["radius"] + b["h0"]]}],
        "walls": [{"plane": {"point": [0, 0, 0], "normal": [0, 0, 1]}, "material": "floor"}],
        "integrator": {"method": "leapfrog", "dt": "auto", "dt_rule": "hart", "frac": 0.05},
        "run": {"duration": duration},
        "output": {"every": 0, "energy_every": 5e-5},
    }
    if damping:
        scene["damping"] = damping
    return scene


def drag_apex(h, alpha):
    """Apex height after one elastic bounce of a body dropped from h under linear drag
    alpha (global damping): fall z = h - (g/a) t + (g/a^2)(1 - exp(-a t)) to z = 0, then
    rise from the impact speed v to v/a - (g/a^2) ln(1 + a v/g)."""
    a = alpha
    z = lambda t: h - G / a * t + G / a**2 * (1 - math.exp(-a * t))  # noqa: E731
    lo, hi = 0.0, 10 * math.sqrt(2 * h / G) + 10 / a
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if z(mid) > 0 else (lo, mid)
    v = G / a * (1 - math.exp(-a * lo))
    return v / a - G / a**2 * math.log(1 + a * v / G)


def predicted_apex(eta, damping):
    """First apex / h0 of the bouncing sphere from the closed forms (nan: none)."""
    if damping is None:
        return cut_impact(tsuji_zeta(eta)).e ** 2
    if "local" in damping:
        c = damping["local"]["coefficient"]
        return ((1 - c) / (1 + c)) ** 2  # flight x contact, each (1 - c)/(1 + c)
    g = damping.get("global", {})
    if "translation" in g and "auto" not in g:
        return drag_apex(BALL["h0"], g["translation"]) / BALL["h0"]
    return float("nan")


def measure_bounce(R, Q, k, cfg):
    E = energy(R.run(f"bounce_{k}", bounce_scene(cfg.eta, cfg.damping,
                                                  Q["bounce_duration"])).out)
    m = 4 / 3 * math.pi * BALL["radius"] ** 3 * BALL["density"]
    z = E["potential_gravity"] / (m * G)
    tp, zp = apex_heights(E["time"], z)
    h = zp - BALL["radius"]
    keep = h > 1e-6
    tp, h = tp[keep], h[keep]
    el = E["elastic_normal"]
    first = E["time"][np.nonzero(el > 0)[0][0]] if np.any(el > 0) else float("nan")
    return {"label": cfg.label, "t": E["time"], "z": z, "apex_t": tp, "apex_h": h / BALL["h0"],
            "first_impact": first, "predicted": predicted_apex(cfg.eta, cfg.damping)}


def apexes(g, nb):
    """The first nb apex heights / h0 of a bounce, nan where there was none."""
    return list(g["apex_h"][:nb]) + [float("nan")] * (nb - min(nb, len(g["apex_h"])))


def chain_scene(Q, eta, damping):
    n, r, v0 = Q["chain_n"], 0.005, 0.1
    w = math.sqrt(1e5 / (4 / 3 * math.pi * r**3 * 2500))
    duration = 3.0 * n / w
    scene = {
        "name": "chain",
        "gravity": [0, 0, 0],
        "materials": {"b": {"density": 2500, "kn": 1.0e5, "restitution": eta}},
        "particles": [{"material": "b", "radius": r, "position": [2 * r * i, 0, 0],
                       "velocity": [v0 if i == 0 else 0, 0, 0]} for i in range(n)],
        "contact": {"allow_initial_overlap": True},
        "integrator": {"method": "leapfrog", "dt": "auto", "dt_rule": "hart", "frac": 0.1},
        "run": {"duration": duration},
        "output": {"every": duration / Q["chain_frames"], "energy_every": 0},
    }
    if damping:
        scene["damping"] = damping
    return scene, v0, w


def measure_chain(R, Q, k, cfg):
    scene, v0, w = chain_scene(Q, cfg.eta, cfg.damping)
    fr = frames(R.run(f"chain_{k}", scene).out)
    t = np.array([f.time for f in fr])
    v_all = np.array([f.data["velocity"][:, 0] for f in fr]) / v0  # frame x sphere
    v_last = v_all[:, -1]
    vmax = v_last.max()
    return {"label": cfg.label, "t": t, "v": v_last, "amp": vmax,
            "t50": cross_time(t, v_last, 0.5 * vmax) if vmax > 0 else float("nan"),
            "t10": cross_time(t, v_last, 0.1 * vmax) if vmax > 0 else float("nan"),
            "v_end": v_last[-1], "momentum_end": v_all[-1].sum(), "striker_end": v_all[-1, 0],
            "omega": w}


def dynamics_study(R, Q, res):
    cfgs = dynamic_configs(Q)
    items = list(enumerate(cfgs))
    bounce = R.map(lambda kc: measure_bounce(R, Q, *kc), items)
    chain = R.map(lambda kc: measure_chain(R, Q, *kc), items)
    nb = Q["bounces"]
    write_csv(os.path.join(res, "bounce.csv"), [dict(
        damping=g["label"], first_impact_s=g["first_impact"], apex1_predicted=g["predicted"],
        **{f"apex{k + 1}_over_h0": h for k, h in enumerate(apexes(g, nb))}) for g in bounce],
        blank=True)
    ref = chain[0]
    write_csv(os.path.join(res, "chain.csv"), [dict(
        damping=g["label"], arrival_t50_s=g["t50"], arrival_vs_undamped=g["t50"] / ref["t50"],
        arrival_t10_s=g["t10"], peak_velocity_over_v0=g["amp"],
        amplitude_vs_undamped=g["amp"] / ref["amp"], final_velocity_over_v0=g["v_end"],
        final_momentum_over_m_v0=g["momentum_end"],
        striker_final_velocity_over_v0=g["striker_end"]) for g in chain], blank=True)
    fig, ax = plt.subplots(1, 2, figsize=(13, 4.8))
    for g in bounce:
        ax[0].plot(g["t"], (g["z"] - BALL["radius"]) / BALL["h0"], lw=0.9, label=g["label"])
    ax[0].set_xlabel("time (s)")
    ax[0].set_ylabel("height of the sphere's bottom / h0")
    ax[0].set_title("Bouncing sphere (dropped from h0 = 0.1 m)")
    ax[0].legend(fontsize=7)
    for g in chain:
        ax[1].plot(g["t"] * g["omega"], g["v"], lw=0.9, label=g["label"])
    ax[1].set_xlabel("time x omega (omega = sqrt(k/m))")
    ax[1].set_ylabel("velocity of the far-end sphere / striker speed")
    ax[1].set_title(f"Pulse along a chain of {Q['chain_n']} spheres")
    ax[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(res, "dynamics.png"), dpi=110)
    plt.close(fig)
    return bounce, chain


BED = {"n": 160, "dmin": 0.0009, "dmax": 0.0011, "width": 0.016, "depth": 0.0011,
       "density": 2500.0, "kn": 5.0e4, "eta": 0.7, "f": 25.0, "gamma": 6.0}


def bed_amplitude():
    return BED["gamma"] * G / (2 * math.pi * BED["f"]) ** 2


def bed_configs(Q):
    cfgs = [Setup("contact eta 0.7 (seed)"),
            Setup("local component 0.7", damping=local(0.7)),
            Setup("local vector 0.7", damping=local(0.7, "vector")),
            Setup("local component 0.1", damping=local(0.1)),
            Setup("global alpha 20/s", damping=drag(20.0)),
            Setup("adaptive global", damping=ADAPTIVE)]
    if Q["quick"]:
        cfgs = cfgs[:2]
    return cfgs


def bed_scene(Q, damping):
    """Seed 004's vibrated bed (T17-18) as a quasi-2D quick variant: 160 glass spheres
    (d 0.9-1.1 mm) in a 16 mm x 1.1 mm box shaken vertically at 25 Hz, 6 g."""
    B = BED
    scene = {
        "name": "vibrated_bed",
        "gravity": [0, 0, -G],
        "materials": {"glass": {"density": B["density"], "kn": B["kn"], "kt": B["kn"],
                                "restitution": B["eta"], "friction": 0.0}},
        "particles": [{"generate": "random",
                       "region": {"min": [0, 0, 0.0005], "max": [B["width"], B["depth"], 0.03]},
                       "count": B["n"], "radius": {"uniform_diameter": [B["dmin"], B["dmax"]]},
                       "material": "glass", "seed": 3}],
        "walls": [{"box": {"min": [0, 0, 0], "max": [B["width"], B["depth"], 0.1]},
                   "material": "glass",
                   "motion": {"oscillate": {"direction": [0, 0, 1], "frequency": B["f"],
                                            "acceleration": B["gamma"]}}}],
        "integrator": {"method": "leapfrog", "dt": "auto", "dt_rule": "hart", "frac": 0.2},
        "run": {"duration": Q["bed_duration"]},
        "output": {"every": 0, "energy_every": 1e-4},
    }
    if damping:
        scene["damping"] = damping
    return scene


def bed_model(c=0.0, alpha=0.0, cycles=14, steps=4000):
    """The inelastic bouncing ball on the plate z_p = A sin(w t), with local damping c
    (free flight: a = -g - c g sign(v)) or global damping alpha (a = -g - alpha v). It
    leaves the plate when the plate's acceleration falls below the free one and sticks
    on landing. Returns the largest lift above the plate, the airborne fraction and the
    landings per driving period over the last four cycles (lift, air, lands)."""
    w = 2 * math.pi * BED["f"]
    A = bed_amplitude()
    dt = 1 / (BED["f"] * steps)
    free = lambda v: -G - c * G * np.sign(v) - alpha * v  # noqa: E731
    z, v, on, lift, air, count, lands, n_off = 0.0, A * w, True, 0.0, 0, 0, 0, 0
    for n in range(cycles * steps):
        t = (n + 1) * dt
        zp, vp, ap = A * math.sin(w * t), A * w * math.cos(w * t), -A * w * w * math.sin(w * t)
        if on:
            z, v = zp, vp
            on = not ap < free(vp)
            n_off = n
        else:
            v += free(v) * dt
            z += v * dt
            if z <= zp:
                z, v, on = zp, vp, True
                lands += n >= (cycles - 4) * steps and n - n_off > 0.05 * steps
        if n >= (cycles - 4) * steps:
            lift = max(lift, z - zp)
            air += not on
            count += 1
    return {"lift": lift, "air": air / count, "lands": lands / 4}


def flights_per_period(t, h, T):
    """Flights of the bed per driving period: maxima of the lift h(t) standing out by
    more than 30% of the largest lift above the lower of the minima within 0.75 T on
    either side, at least half a period apart."""
    n = max(1, int(0.75 * T / (t[1] - t[0])))
    k = np.nonzero((h[1:-1] >= h[:-2]) & (h[1:-1] > h[2:]))[0] + 1
    peaks = []
    for i in k:
        prom = h[i] - max(h[max(0, i - n):i].min(), h[i + 1:i + n + 1].min())
        if prom > 0.3 * h.max():
            if peaks and t[i] - t[peaks[-1]] < 0.5 * T:
                if h[i] > h[peaks[-1]]:
                    peaks[-1] = i
            else:
                peaks.append(i)
    return len(peaks) / ((t[-1] - t[0]) / T)


def measure_bed(R, Q, k, cfg):
    """Runs one bed; returns the lift of its centre of mass above the floor."""
    damping = cfg.damping
    r = R.run(f"bed_{k}", bed_scene(Q, damping), check=False)
    if r.returncode != 0:
        err = r.stderr.strip()
        return {"label": cfg.label, "error": dict(returncode=r.returncode,
                                                  message=err.splitlines()[-1] if err else "")}
    E = energy(r.out)
    d0 = frames(r.out, [0])[0].data
    M = np.sum(4 / 3 * np.pi * d0["radius"] ** 3 * BED["density"])
    t = E["time"]
    floor = bed_amplitude() * np.sin(2 * np.pi * BED["f"] * t)
    rel = E["potential_gravity"] / (M * G) - floor
    win = t > 2 / BED["f"]
    rest = rel[win].min()
    h = rel - rest
    W = E["work_walls"][-1]
    art = E["dissipated_local"][-1] + E["dissipated_global"][-1]
    c = damping["local"]["coefficient"] if damping and "local" in damping else 0.0
    a = (damping["global"].get("translation", 0.0)
         if damping and "global" in damping and "auto" not in damping["global"] else 0.0)
    model = (bed_model(c, a) if not (damping and "auto" in damping.get("global", {}))
             else dict.fromkeys(("lift", "air", "lands"), float("nan")))
    up = h[win] > 0.1 * BED["dmin"]
    lands = flights_per_period(t[win], h[win], 1 / BED["f"])
    return {"label": cfg.label, "t": t, "h": h, "lift": h[win].max(),
            "air": np.mean(up), "lands": lands, "model_lands": model["lands"], "work": W,
            "art_frac": art / W if W > 0 else float("nan"),
            "contact_frac": E["dissipated_contact"][-1] / W if W > 0 else float("nan"),
            "model_lift": model["lift"], "model_air": model["air"]}


def bed_study(R, Q, res):
    cfgs = bed_configs(Q)
    first = measure_bed(R, Q, 0, cfgs[0])
    if "error" in first:  # an esfera without moving walls (issue 4)
        return {"unavailable": first["error"]}
    got = [first] + R.map(lambda kc: measure_bed(R, Q, *kc), list(enumerate(cfgs))[1:])
    got = [g for g in got if "error" not in g]
    write_csv(os.path.join(res, "vibrated_bed.csv"), [dict(
        damping=g["label"], max_lift_mm=1e3 * g["lift"], model_lift_mm=1e3 * g["model_lift"],
        airborne_fraction=g["air"], model_airborne_fraction=g["model_air"],
        flights_per_period=g["lands"], model_flights_per_period=g["model_lands"],
        wall_work_to_damping=g["art_frac"], wall_work_to_contacts=g["contact_frac"])
        for g in got], blank=True)
    fig, ax = plt.subplots(figsize=(9, 4.5))
    for g in got:
        ax.plot(g["t"] * BED["f"], 1e3 * g["h"], lw=0.9, label=g["label"])
    ax.set_xlabel("time / driving period")
    ax.set_ylabel("bed's centre of mass above its rest height on the floor (mm)")
    ax.set_title(f"Vibrated bed, {BED['f']:g} Hz, {BED['gamma']:g} g ({BED['n']} spheres)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(res, "vibrated_bed.png"), dpi=110)
    plt.close(fig)
    return {"runs": got}


# --- report ------------------------------------------------------------------------------


def md_table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(fmt(x, blank=True) for x in r) + " |" for r in rows]
    return "\n".join(out)


def write_report(res, Q, P1, P2, P3, timing):
    rest, decay, conv = P1
    (ray_rows, fc, ff), (_, beta_ex, pack_ray) = P2
    settle, bounce, chain, vib = P3
    L = ["# Study 2: damping\n",
         f"Generated by `studies/damping.py{' --quick' if Q['quick'] else ''}` "
         f"({timing:.0f} s on {Q['jobs']} workers). Data: `*.csv`; plots: `*.png`. "
         "Definitions and closed forms: the script's docstring.\n"]
    L += glance(Q, rest, decay, ray_rows, ff, pack_ray, settle, bounce, chain, vib)
    L += report_part1(Q, rest, decay, conv)
    L += report_part2(Q, ray_rows, fc, ff, beta_ex, pack_ray)
    L += report_part3a(Q, *settle)
    L += report_part3b(Q, bounce, chain, vib)
    with open(os.path.join(res, "report.md"), "w") as fh:
        fh.write("\n".join(L))


def report_part1(Q, rest, decay, conv):
    fbest = min(Q["fracs"])
    L = ["## 1. Requested vs measured restitution and decay\n"]
    L.append("Seed 004's damping demo sphere (k = 2e7 N/m, rho = 2000 kg/m^3, r = 0.05 m) "
             "launched at 0.1 m/s at a plane and as a head-on pair, no gravity.\n")
    fcoarse = max(Q["fracs"])

    def one(kind, eta, frac):
        return next(r for r in rest if r["kind"] == kind and r["eta_requested"] == eta
                    and r["frac"] == frac)

    sel = [r for r in rest if r["frac"] == fbest]
    rows = []
    for eta in Q["etas"]:
        w_, p_ = one("wall", eta, fbest), one("pair", eta, fbest)
        e_cf = w_["e_closed_form"]
        rows.append([f"{eta:g}", w_["zeta"], e_cf if np.isfinite(e_cf) else w_["e_exact_solver"],
                     w_["e_measured"], p_["e_measured"], 100 * w_["rel_error"],
                     100 * p_["rel_error"], 100 * one("wall", eta, fcoarse)["rel_error"]])
    L.append(md_table(["eta requested", "zeta (Tsuji)", "e closed form", f"e wall (frac {fbest:g})",
                       f"e pair (frac {fbest:g})", "wall err %", "pair err %",
                       f"wall err % (frac {max(Q['fracs']):g})"], rows))
    worst_mod, worst_crs = worst_moderate(rest, fbest), worst_moderate(rest, fcoarse)
    lo = [r for r in sel if r["eta_requested"] <= 1e-3 and r["kind"] == "wall"]
    wdt = [r["omega_dt"] for r in sel]
    L.append("")
    L.append(f"- The measured restitution follows the cut-oscillator closed form, **not** the "
             f"requested eta: at frac {fbest:g} (omega dt {min(wdt):.3g}–{max(wdt):.3g}) every "
             f"moderate case (eta 0.1–0.9) is within "
             f"{100 * worst_mod:.2f}% of it; at the production frac {max(Q['fracs']):g} within "
             f"{100 * worst_crs:.2f}%. The leapfrog error is first order in dt (the dashpot "
             "force jumps at first touch and uses the half-step velocity).")
    if lo:
        L.append(f"- The 'overdamped' eta = 1e-7 of the seed is not overdamped: Tsuji's zeta "
                 f"is {tsuji_zeta(1e-7):.4f} < 1, and with the no-tension cut the sphere "
                 f"still rebounds with e = {lo[0]['e_measured']:.4f} (closed form "
                 f"{lo[0]['e_exact_solver']:.4f}); no "
                 "requested eta can give e below "
                 f"{cut_impact(0.99999).e:.3f}.")
    L.append(f"- e exceeds eta everywhere below eta ~ 1: eta 0.5 gives e = "
             f"{cut_impact_closed_form(tsuji_zeta(0.5)).e:.3f}, eta 0.1 gives "
             f"{cut_impact_closed_form(tsuji_zeta(0.1)).e:.3f}. A user who wants e should "
             "invert the cut form, not Tsuji's.\n")
    L.append("![restitution and decay](restitution_decay.png)\n")
    L.append("Resting sphere kicked upward (amplitude half its static overlap, so the "
             "contact never opens): the half-cycle amplitude ratio and the log decrement.\n")
    rows = [[g["case"].kind, f"{g['case'].value:.4g}", g["zeta_nominal"], g["delta_nominal"],
             g["delta"], g["zeta_measured"], g["half_ratio"], g["peaks"]] for g in decay]
    L.append(md_table(["damping", "parameter", "zeta nominal", "decrement expected",
                       "decrement measured", "zeta measured", "half-cycle ratio", "peaks"], rows))
    con = [g for g in decay if g["case"].kind == "contact" and np.isfinite(g["half_ratio"])
           and g["case"].value >= 0.1 and g["delta_nominal"] > 0]
    err_c = max(abs(g["delta"] / g["delta_nominal"] - 1) for g in con)
    gl = [g for g in decay if g["case"].kind == "global"]
    err_g = max(abs(g["delta"] / g["delta_nominal"] - 1) for g in gl)
    loc = [g for g in decay if g["case"].kind in ("component", "vector")]
    err_l = max(abs(g["delta"] / g["delta_nominal"] - 1) for g in loc)
    L.append("")
    L.append(f"- Without the cut (contact kept closed) the dashpot delivers what was "
             f"requested: the half-cycle amplitude ratio equals eta (decrement within "
             f"{100 * err_c:.2f}% of 2 pi zeta / sqrt(1 - zeta^2) for eta >= 0.1 at "
             f"omega dt = {Q['decay_frac'] * math.sqrt(2):.3g}). So eta is the restitution of "
             "the *uncut* oscillator; impacts rebound harder because the contact lets go "
             "early.")
    L.append("- Near critical damping the half-cycle ratio is hypersensitive to zeta "
             "(d delta / d zeta = 2 pi / s^3): the leapfrog's dashpot, one half step behind, "
             "shifts the effective zeta by O(zeta omega dt), so small eta are met only as "
             "dt -> 0 (first order):\n")
    L.append(md_table(["eta requested", "frac", "omega dt", "half-cycle ratio measured",
                       "decrement error %"],
                      [[f"{r['eta_requested']:g}", r["frac"], r["omega_dt"],
                        r["half_cycle_ratio"], 100 * r["rel_error"]] for r in conv]))
    lost = [g for g in decay if g["case"].kind == "contact" and not np.isfinite(g["delta"])]
    if lost:
        L.append("\n  For eta = " + ", ".join(f"{g['case'].value:g}" for g in lost) + " the second "
                 "peak (eta x 1e-7 m) lies below the position's resolution at a 0.05 m radius "
                 "(the overlap r - |x - q| is rounded to ~1e-17 m and the motion freezes near "
                 "1e-16 m), so no decrement is measurable.")
    L.append("")
    L.append(f"- Global damping gives zeta = alpha / (2 omega) (decrement within "
             f"{100 * err_g:.2f}%).")
    L.append(f"- Local damping behaves like a linear damper with decrement ln((1 + c)/(1 - c)) "
             f"(within {100 * err_l:.2f}%), component and vector forms alike for this "
             f"one-dimensional motion: c = 0.7 is zeta_equiv = "
             f"{zeta_from_decrement(local_decrement(0.7)):.3f} (the small-c rule c / pi gives "
             f"{0.7 / math.pi:.3f}); c = 0.1 is {zeta_from_decrement(local_decrement(0.1)):.4f}. "
             "Unlike viscous damping its decrement does not depend on the frequency.\n")
    L.append("![decay series](decay_series.png)\n")
    return L


def report_part2(Q, ray_rows, fc, ff, beta_ex, pack_ray):
    L = ["## 2. Rayleigh damping (seed 001)\n"]
    L.append("Seed 001 gives Rayleigh damping as formulas only (3.46–3.61: alpha = 2 omega "
             "zeta, beta = 2 zeta / omega, f = omega / 2 pi, inputs `_frac` and `_freq` of "
             "the SAND program) and **no numerical values** of zeta or f; "
             "`docs/physics.md#damping` has none either. The study therefore uses "
             f"zeta_R = {Q['rayleigh_zeta']:g} (docs/scene.md's example), sweeps f_R against "
             f"the contact frequency, and evaluates the example f_R = "
             f"{Q['rayleigh_example_f']:g} Hz.\n")
    rows = [[r["f_R_over_f_wall"], r["f_R_Hz"], r["zeta_mode_wall_expected"],
             r["zeta_mode_wall_measured"], r["zeta_mode_pair_expected"],
             r["zeta_contact_pair_beta"], r["e_pair_measured"], r["e_pair_expected"],
             r["e_pair_contact_dashpot_only"]] for r in ray_rows]
    L.append(md_table(["f_R / f_c", "f_R (Hz)", "zeta mode expected", "zeta mode measured",
                       "zeta pair mode", "zeta pair dashpot", "e pair measured",
                       "e pair expected", "e dashpot only"], rows))
    ovd = [r for r in ray_rows if not np.isfinite(r["zeta_mode_wall_measured"])]
    if ovd:
        L.append("\n  Blank measured mode ratio: at f_R / f_c = "
                 + ", ".join(f"{r['f_R_over_f_wall']:g}" for r in ovd)
                 + " the mode is overdamped (zeta > 1): no oscillation, no decrement.")
    stuck = [r for r in ray_rows if not np.isfinite(r["e_pair_measured"])]
    if stuck:
        L.append("\n  Blank e: at f_R / f_c = "
                 + ", ".join(f"{r['f_R_over_f_wall']:g}" for r in stuck)
                 + " the body damper alone overdamps the pair's relative motion while the "
                 "contact dashpot is too weak to end the contact: the spheres creep to rest "
                 "in contact and never separate (e = 0).\n")
    errs = [abs(r["zeta_mode_wall_measured"] / r["zeta_mode_wall_expected"] - 1)
            for r in ray_rows if np.isfinite(r["zeta_mode_wall_measured"])]
    eerr = [abs(r["rel_error"]) for r in ray_rows if np.isfinite(r["rel_error"])]
    L.append("")
    at = [r for r in ray_rows if r["f_R_over_f_wall"] == 1]
    L.append("- The seed's pair of coefficients **doubles** the requested ratio: with alpha = "
             "2 omega_R zeta_R and beta = 2 zeta_R / omega_R each term alone gives zeta_R "
             "at f_R, together a mode at f gets zeta(f) = (alpha/omega + beta omega)/2 = "
             "zeta_R (f_R/f + f/f_R), 2 zeta_R at f = f_R"
             + (f" (measured {at[0]['zeta_mode_wall_measured']:.4f} for zeta_R = "
                f"{Q['rayleigh_zeta']:g})" if at else "")
             + f". The measured damping of the sphere-on-wall mode (f_c = {fc:.0f} Hz) "
             f"follows zeta(f) within {100 * max(errs):.2f}% over the sweep, and the pair "
             f"restitution the cut oscillator carrying both terms within "
             f"{100 * max(eerr):.2f}%. A decade away from f_R a mode gets "
             f"{rayleigh_zeta(Q['rayleigh_zeta'], 10):.3f}; the classical single-frequency "
             "Rayleigh fit would be alpha = omega_R zeta_R, beta = zeta_R / omega_R.")
    L.append(f"- The mass term is a drag on every body, whatever its contacts: with zeta_R = "
             f"{ff['zeta']:g}, f_R = {ff['f']:g} Hz it is alpha = {ff['alpha']:.1f} 1/s; a "
             f"free-falling sphere reaches {ff['v_end']:.4f} m/s after {ff['t']:.3f} s "
             f"(expected {ff['v_expected']:.4f}, terminal g/alpha = {ff['v_term']:.4f} m/s) "
             f"and falls {ff['fall_1s']:.3f} m in 1 s instead of {ff['fall_1s_undamped']:.2f} m.")
    rows = [[p["contact"], p["f_c"], p["zeta_dashpot"], p["zeta_with_alpha"], p["e"]]
            for p in pack_ray]
    L.append(f"- On the study's pack (glass, k = 1e4 N/m, r 1.2–2.2 mm) the same setting "
             f"(beta = {beta_ex:.3g} s) gives these contacts:\n")
    L.append(md_table(["contact", "f_c (Hz)", "zeta dashpot beta omega/2",
                       "zeta with alpha", "impact e"], rows))
    L.append("\n  so a Rayleigh setting tuned in Hz is overdamped or underdamped depending on "
             "particle size and stiffness; its contact damping scales with f_c.\n")
    L.append("![rayleigh](rayleigh.png)\n")
    return L


def report_part3a(Q, pour, load):
    L = ["## 3. Local vs global vs adaptive damping\n"]
    L.append(f"### (a) Quasi-static settling\n\n**(a1) Pour.** {Q['pack_n']} glass spheres "
             f"(r 1.2–2.2 mm, k_n 1e4, k_t 7e3 N/m, mu 0.5) generated loose (solid fraction "
             f"~{pack_initial_fraction(Q):.2f}) in a {PACK['box'] * 100:.0f} cm square box fall "
             f"under gravity for {Q['pack_duration']:g} s (dt = 0.1 x Hart's step unless "
             f"stated). Settled: kinetic energy stays below {Q['ke_frac']:g} N m g d. Solid "
             "fraction in the slab from one diameter above the floor to two below the top; "
             "unbalanced force |F|/(m g) from the last frame.\n")
    rows = [[g["label"], g["steps_settle"] if np.isfinite(g["steps_settle"]) else "not reached",
             g["t_settle"], g["phi"], g["f_res"], g["f_res_med"], g["ke_end"]] for g in pour]
    L.append(md_table(["damping", "steps to threshold", "time (s)", "solid fraction",
                       "mean abs(F)/(m g)", "median abs(F)/(m g)", "final KE / (N m g d)"],
                      rows))
    L.append("")
    L.append(f"**(a2) Load step.** The pack settled by '{Q['load_source']}' is reloaded at "
             "rest (tangential springs reset) and gravity doubled: a quasi-static loading "
             "step. Converged: mean unbalanced force stays below "
             f"{Q['force_tol']:g} m g (frames every "
             f"{Q['load_duration'] / Q['load_frames'] * 1e3:.1f} ms).\n")
    rows = [[g["label"], g["steps_f"] if np.isfinite(g["steps_f"]) else "not reached",
             g["t_f"], g["f_end"], g["f_med_end"], g["phi"], g["drop"] * 1e6] for g in load]
    L.append(md_table(["damping", "steps to tolerance", "time (s)", "final mean abs(F)/(m g)",
                       "final median abs(F)/(m g)", "solid fraction", "mean settlement (um)"],
                      rows))
    L.append("")
    L.extend(settle_conclusions(Q, pour, load))
    L.append("\n![settling](settling.png)\n")
    return L


def report_part3b(Q, bounce, chain, vib):
    L = ["### (b) Dynamics\n"]
    L.append("**Bouncing sphere** (r = 1 cm, k = 1e6 N/m, dropped from h0 = 0.1 m, elastic "
             "contact unless stated): apex heights / h0.\n")
    nb = Q["bounces"]
    rows = []
    for g in bounce:
        rows.append([g["label"], g["first_impact"], g["predicted"]] + apexes(g, nb))
    L.append(md_table(["damping", "first impact (s)", "apex 1 predicted"]
                      + [f"apex {k + 1}" for k in range(nb)], rows))
    L.append("")
    L.extend(bounce_conclusions(bounce))
    L.append(f"\n**Pulse along a chain** of {Q['chain_n']} touching spheres (r = 5 mm, "
             "k = 1e5 N/m, no gravity; the first strikes at v0 = 0.1 m/s): the far-end "
             "sphere's velocity. Arrival = when it reaches half its peak.\n")
    ref = chain[0]
    rows = [[g["label"], g["t50"] * 1e3, g["t50"] / ref["t50"], g["amp"], g["amp"] / ref["amp"],
             g["momentum_end"], g["striker_end"]] for g in chain]
    L.append(md_table(["damping", "arrival (ms)", "arrival / undamped", "peak v / v0",
                       "amplitude / undamped", "chain momentum at end / m v0",
                       "striker's final v / v0"], rows))
    L.append("")
    L.extend(chain_conclusions(chain))
    L.append("\n![dynamics](dynamics.png)\n")
    L += report_bed(Q, vib)
    return L


def report_bed(Q, vib):
    if "unavailable" in vib:
        rc, msg = vib["unavailable"]["returncode"], vib["unavailable"]["message"]
        return ["### Vibrated bed: not available\n",
                "The vibrated bed (seed 004 Tables 17–18) needs a wall with prescribed "
                f"motion (issue 4), which this esfera refuses (exit status {rc}: `{msg}`). "
                "No result is given for it.\n"]
    runs = vib["runs"]
    L = ["### Vibrated bed\n",
         f"Seed 004's vibrated bed (T17–18) as a quasi-2D quick variant: {BED['n']} glass "
         f"spheres (d 0.9–1.1 mm, eta 0.7, frictionless, k = 5e4 N/m) in a 16 mm x 1.1 mm "
         f"box shaken at {BED['f']:g} Hz, peak acceleration {BED['gamma']:g} g, for "
         f"{Q['bed_duration']:g} s. Lift: the centre of mass above its lowest height over "
         "the floor (after two settling cycles), from the ledger's gravity energy. Model: "
         "the inelastic bouncing ball with the same damping on its free flight. Last two "
         "columns: where the walls' work went.\n"]
    rows = [[g["label"], 1e3 * g["lift"], 1e3 * g["model_lift"], g["air"], g["model_air"],
             g["lands"], g["model_lands"], g["art_frac"], g["contact_frac"]] for g in runs]
    L.append(md_table(["damping", "max lift (mm)", "model lift (mm)", "airborne fraction",
                       "model airborne", "flights / period", "model flights / period",
                       "wall work -> damping", "wall work -> contacts"], rows))
    L.append("")
    ref = runs[0]
    for g in runs[1:]:
        L.append(f"- {g['label']}: lift {g['lift'] / ref['lift']:.2f} x the seed bed's "
                 f"({1e3 * g['lift']:.2f} mm vs {1e3 * ref['lift']:.2f} mm), airborne "
                 f"{100 * g['air']:.0f}% of the time (seed bed {100 * ref['air']:.0f}%); the "
                 f"damping absorbs {100 * g['art_frac']:.0f}% of the walls' work.")
    L.append("- Flights per period: 0.5 is the seed bed's period doubling (one flight every "
             "two cycles, as the inelastic bouncing-ball model predicts at 6 g), 1 a flight "
             "every cycle.")
    switched = [g["label"] for g in runs[1:] if abs(g["lands"] - ref["lands"]) > 0.2]
    model = [g["model_lift"] for g in runs if np.isfinite(g["model_lift"])]
    L.append("- Local damping sees the bed's free flight as unbalanced motion (each sphere's "
             "unbalanced force is its weight) and brakes it like the bouncing sphere above. "
             f"The single-ball model with the same flight damping gives lifts of "
             f"{1e3 * min(model):.1f}–{1e3 * max(model):.1f} mm and keeps the period "
             "doubling in every case"
             + (f"; the many-sphere bed under {', '.join(switched)} flies every cycle "
                "instead (period 2 becomes period 1): the damping also works in the "
                "collisions inside the bed, which the ball lacks (for local damping an "
                "effective restitution sqrt((1 - c)/(1 + c)) per contact), so the bed flies "
                "lower and shorter than the ball and lands within the cycle."
                if switched else "."))
    L.append("\n![vibrated bed](vibrated_bed.png)\n")
    return L


def glance(Q, rest, decay, ray_rows, ff, pack_ray, settle, bounce, chain, vib):
    """The report's summary: one or two sentences per part, numbers from the runs."""
    pour, load = settle
    fine, coarse = min(Q["fracs"]), max(Q["fracs"])
    e_of = {r["eta_requested"]: r["e_measured"] for r in rest
            if r["kind"] == "wall" and r["frac"] == fine}
    loc7 = next((g for g in decay if g["case"] == Case("component", 0.7)), None)
    L = ["## At a glance\n"]
    L.append(f"1. **Restitution.** Measured impact restitution is the cut-oscillator closed "
             f"form (within {100 * worst_moderate(rest, fine):.2f}% at omega dt ~ "
             f"{fine * 1.41:.2g}, {100 * worst_moderate(rest, coarse):.1f}% at the production "
             f"frac {coarse:g}), always above the "
             f"requested eta: eta 0.5 -> e {e_of.get(0.5, float('nan')):.3f}, eta 0.1 -> "
             f"{e_of.get(0.1, float('nan')):.3f}, the seed's 'overdamped' eta 1e-7 -> "
             f"{e_of.get(1e-7, float('nan')):.3f}. A resting sphere (contact never opening) "
             "loses exactly eta per half cycle; global damping gives zeta = alpha/(2 omega); "
             "local damping c acts as a frequency-independent damper with decrement "
             "ln((1 + c)/(1 - c))"
             + (f" (c = 0.7: zeta_equiv {loc7['zeta_measured']:.3f})" if loc7 else "")
             + ", component and vector forms identical in 1D.")
    at = [r for r in ray_rows if r["f_R_over_f_wall"] == 1]
    ovd = [p["zeta_dashpot"] for p in pack_ray]
    rp = [g for g in pour if g["label"].startswith("Rayleigh")]
    rl = [g for g in load if g["label"].startswith("Rayleigh")]
    txt = ("2. **Rayleigh.** The seed's alpha = 2 omega zeta, beta = 2 zeta / omega give a "
           "mode at f the ratio zeta_R (f_R/f + f/f_R): twice zeta_R at f_R"
           + (f" (measured {at[0]['zeta_mode_wall_measured']:.4f} for zeta_R "
              f"{Q['rayleigh_zeta']:g})" if at else "")
           + f", rising away from it. The example zeta 0.05, f 100 Hz is a body drag "
           f"alpha = {ff['alpha']:.1f} 1/s (free fall capped at {ff['v_end']:.3f} m/s) and "
           f"overdamps the pack's contacts (zeta {min(ovd):.2f}–{max(ovd):.2f})")
    if len(rp) >= 2 and len(rl) >= 2:
        txt += ("; at Hart's step x 0.1 these dashpots are explicitly unstable in the pack "
                "(a sphere's summed c dt / m exceeds 2) and it never comes to rest (mean "
                f"unbalanced force {rp[0]['f_res']:.2g} m g after the pour, "
                f"{rl[0]['f_end']:.2g} m g in the "
                f"load step); with the 'damped' step rule it settles "
                f"({rl[1]['f_end']:.1g} m g).")
    else:
        txt += "."
    L.append(txt)
    bl = {g["label"]: g for g in pour}
    ll = {g["label"]: g for g in load}
    none_p, loc_p = bl.get("none (eta 1, friction only)"), bl.get("local component 0.7")
    loc_l, none_l = ll.get("local component 0.7"), ll.get("none (eta 1, friction only)")
    fastest_p = min((g for g in pour if np.isfinite(g["steps_settle"])),
                    key=lambda g: g["steps_settle"], default=None)
    glob_l = [g for g in load if g["label"].startswith(("global", "adaptive"))
              and np.isfinite(g["steps_f"])]
    txt = "3. **Local vs global vs adaptive.** "
    if loc_p and none_p and fastest_p:
        txt += (f"Pouring a pack, local damping 0.7 is slow (it damps gravity itself: "
                f"{fmt(loc_p['steps_settle'], True)} steps vs "
                f"{fmt(none_p['steps_settle'], True)} with no "
                f"added damping, {fastest_p['steps_settle']:.0f} with {fastest_p['label']}) and "
                f"leaves a looser pack (solid fraction {loc_p['phi']:.3f} vs "
                f"{none_p['phi']:.3f}). ")
    if loc_l and none_l:
        txt += (f"In a quasi-static load step it converges in {loc_l['steps_f']:.0f} steps "
                f"to 1% unbalanced force"
                + (", against " + ", ".join(f"{g['steps_f']:.0f} ({g['label']})"
                                            for g in glob_l) if glob_l else "")
                + (", and never without damping. " if not np.isfinite(none_l["steps_f"])
                   else f", {none_l['steps_f']:.0f} without damping. "))
    bb = {g["label"]: g for g in bounce}
    cc = {g["label"]: g for g in chain}
    if "local component 0.7" in bb and "local component 0.7" in cc:
        b7, c7 = bb["local component 0.7"], cc["local component 0.7"]
        txt += (f"It distorts dynamics heavily: a bouncing sphere keeps ((1 - c)/(1 + c))^2 of "
                f"its height per bounce ({b7['apex_h'][0]:.3f} for c = 0.7) and falls at "
                f"(1 - c) g (first impact {b7['first_impact']:.3f} s instead of "
                f"{bounce[0]['first_impact']:.3f} s); a pulse along a chain arrives with "
                f"{100 * c7['amp'] / chain[0]['amp']:.2g}% of its undamped amplitude, "
                f"{100 * (c7['t50'] / chain[0]['t50'] - 1):.0f}% late")
        if "local component 0.1" in cc:
            txt += (f" (c = 0.1 already removes "
                    f"{100 * (1 - cc['local component 0.1']['amp'] / chain[0]['amp']):.0f}%)")
        txt += (f", and momentum is not conserved (chain momentum {c7['momentum_end']:.2f} "
                "m v0 at the end). ")
    if "runs" in vib:
        ref = vib["runs"][0]
        lv = [g for g in vib["runs"] if g["label"] == "local component 0.7"]
        if lv:
            txt += (f"In the vibrated bed (25 Hz, 6 g) local damping 0.7 lowers the flight "
                    f"from {1e3 * ref['lift']:.1f} to {1e3 * lv[0]['lift']:.1f} mm and takes "
                    f"{100 * lv[0]['art_frac']:.0f}% of the shaker's work"
                    + (f", turning the period doubling ({ref['lands']:.1f} flights per "
                       f"period) into {lv[0]['lands']:.1f}. "
                       if abs(lv[0]["lands"] - ref["lands"]) > 0.2 else ". "))
    if "adaptive global" in bb:
        a = bb["adaptive global"]
        txt += (f"Adaptive damping, tuned on the rate of change of kinetic energy, drags free "
                f"flight as well (first apex {a['apex_h'][0]:.3f} h0). ")
    L.append(txt + "\n")
    return L


def pack_initial_fraction(Q):
    P = PACK
    r3 = (P["rmax"] ** 4 - P["rmin"] ** 4) / (4 * (P["rmax"] - P["rmin"]))
    return Q["pack_n"] * 4 / 3 * math.pi * r3 / (P["box"] ** 2 * Q["pack_height"])


def settle_conclusions(Q, pour, load):
    out = []
    for stage, runs, key in (("pour", pour, "steps_settle"), ("load step", load, "steps_f")):
        by = {g["label"]: g for g in runs}
        none = runs[0]
        fin = sorted((g for g in runs if np.isfinite(g[key])), key=lambda g: g[key])
        txt = ", ".join(f"{g['label']} {g[key]:.0f}" for g in fin)
        miss = [g["label"] for g in runs if not np.isfinite(g[key])]
        out.append(f"- {stage}: steps to converge, fastest first: {txt}"
                   + (f"; not converged: {', '.join(miss)}" if miss else "") + ".")
        for lab in ("local component 0.7", "local vector 0.7"):
            if lab in by and np.isfinite(by[lab][key]) and np.isfinite(none[key]):
                out.append(f"  - {lab} takes {by[lab][key] / none[key]:.2f} x the steps of "
                           "no added damping.")
    ray = [g for g in pour if g["label"].startswith("Rayleigh")]
    if len(ray) >= 2:
        beta = 2 * Q["rayleigh_zeta"] / (2 * math.pi * Q["rayleigh_example_f"])
        m_min = 4 / 3 * math.pi * PACK["rmin"] ** 3 * PACK["density"]
        cdt = [beta * PACK["kn"] / m_min * g["dt"] for g in ray]
        out.append(f"- Rayleigh (beta = {beta:.3g} s): the dashpot force c v uses the "
                   "half-step velocity, an explicit scheme stable only while a sphere's summed "
                   f"c dt / m stays below 2. Per contact on the smallest sphere c dt / m = "
                   f"{cdt[0]:.2f} at dt = {ray[0]['dt']:.3g} s (Hart x 0.1), so four contacts "
                   "exceed the limit: the pack jitters (bounded by the no-tension cut) and "
                   "never comes to rest. The 'damped' rule (which allows for one contact's damping "
                   f"ratio) gives dt = {ray[1]['dt']:.3g} s, c dt / m = {cdt[1]:.2f} per "
                   "contact, and the pack settles.")
    return out


def bounce_conclusions(bounce):
    out = []
    ref = bounce[0]
    for g in bounce[1:]:
        lab, h = g["label"], g["apex_h"]
        txt = f"- {lab}: first apex {h[0]:.4g} h0" if len(h) else f"- {lab}: no rebound"
        if np.isfinite(g["predicted"]) and len(h):
            txt += f" (closed form {g['predicted']:.4g})"
        if len(h) >= 2:
            txt += f", then {h[1] / h[0]:.3g} of the previous apex"
        txt += (f"; first impact at {g['first_impact']:.4f} s (undamped "
                f"{ref['first_impact']:.4f} s).")
        out.append(txt)
    out.append("- Local damping c acts on free flight too: the fall accelerates at (1 - c) g "
               "and the rise decelerates at (1 + c) g, so flight alone keeps (1 - c)/(1 + c) "
               "of the height; in the contact (a half oscillation about the static overlap) "
               "it keeps the same fraction of the energy, an effective restitution "
               "sqrt((1 - c)/(1 + c)) (0.42 for c = 0.7). Each bounce keeps "
               "((1 - c)/(1 + c))^2 of the height, independent of stiffness and speed.")
    return out


def chain_conclusions(chain):
    ref = chain[0]
    out = []
    for g in chain[1:]:
        out.append(f"- {g['label']}: amplitude {100 * (g['amp'] / ref['amp'] - 1):+.1f}%, "
                   f"arrival {100 * (g['t50'] / ref['t50'] - 1):+.1f}% vs undamped.")
    return out


# --- main --------------------------------------------------------------------------------


def settings(quick, jobs):
    Q = {"quick": quick, "jobs": jobs, "bounces": 5, "ke_frac": 1e-4, "force_tol": 0.01,
         "load_source": "global alpha 20/s",
         "rayleigh_zeta": 0.05, "rayleigh_example_f": 100.0,
         "decay_frac": 0.02, "err_etas": [1e-7, 0.1, 0.5, 0.9]}
    if quick:
        Q.update(etas=[1e-7, 0.1, 0.3, 0.5, 0.7, 0.9, 1.0], fracs=[0.1, 0.01],
                 decay_etas=[0.1, 0.5, 0.9], decay_zetas=[0.05, 0.3],
                 local_coefs=[0.1, 0.7], periods=8, rayleigh_ratios=[0.1, 1, 10],
                 decay_conv=([0.1], [0.04, 0.01]),
                 ray_impact_frac=0.01, pack_n=120, pack_height=0.025, pack_duration=0.35,
                 pack_energy_every=1e-3, load_duration=0.1, load_frames=50, chain_n=12,
                 chain_frames=120, bounce_duration=0.8, bed_duration=0.2)
    else:
        Q.update(etas=[1e-7, 1e-5, 1e-3, 0.01, 0.05, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8,
                       0.9, 0.95, 0.99, 1.0],
                 fracs=[0.1, 0.03, 0.01, 0.003],
                 decay_etas=[1e-7, 1e-5, 1e-3, 0.01, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99],
                 decay_zetas=[0.01, 0.05, 0.1, 0.2, 0.4, 0.7],
                 local_coefs=[0.01, 0.05, 0.1, 0.2, 0.4, 0.7, 0.9], periods=14,
                 decay_conv=([1e-5, 1e-3, 0.1, 0.5], [0.04, 0.02, 0.01, 0.005]),
                 rayleigh_ratios=[0.03, 0.1, 0.3, 1, 3, 10, 30], ray_impact_frac=0.003,
                 pack_n=300, pack_height=0.06, pack_duration=1.0, pack_energy_every=1e-3,
                 load_duration=0.3, load_frames=150,
                 chain_n=20, chain_frames=300, bounce_duration=1.5, bed_duration=0.4)
    Q["decay_show"] = [Case("contact", 0.5), Case("global", global_alpha(Q["decay_zetas"][0])),
                       Case("component", 0.1), Case("vector", 0.7), Case("contact", 0.1)]
    return Q


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="reduced study (< 60 s)")
    ap.add_argument("--out", default=os.path.join(REPO, "studies", "results", "damping"))
    ap.add_argument("--esfera", default=os.path.join(REPO, "build", "esfera"))
    ap.add_argument("--jobs", type=int, default=2)
    a = ap.parse_args(argv)
    esfera = os.path.abspath(a.esfera)
    if not os.access(esfera, os.X_OK):
        sys.exit(f"damping.py: no esfera executable at {esfera}")
    res = os.path.abspath(a.out)
    os.makedirs(res, exist_ok=True)
    R = Runner(esfera, os.path.join(res, "tmp"), a.jobs)
    Q = settings(a.quick, a.jobs)
    t0 = time.time()
    stamp = lambda s: print(f"[{time.time() - t0:6.1f} s] {s}", flush=True)  # noqa: E731
    rest = restitution_study(R, Q, res)
    stamp("restitution")
    decay, conv = decay_study(R, Q, res)
    plot_part1(rest, decay, res, Q)
    stamp("decay")
    ray = rayleigh_study(R, Q, res)
    pack_ray = rayleigh_on_pack(Q)
    stamp("rayleigh")
    settle = settling_study(R, Q, res)
    stamp("settling")
    bounce, chain = dynamics_study(R, Q, res)
    vib = bed_study(R, Q, res)
    stamp("dynamics")
    write_report(res, Q, (rest, decay, conv), (ray, pack_ray), (settle, bounce, chain, vib),
                 time.time() - t0)
    stamp(f"report: {os.path.join(res, 'report.md')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
