#!/usr/bin/python3
"""integrators.py - issue 7, study 3: error against cost for every integrator of esfera.

The study runs the esfera program (never the library) on scenes it writes itself into
DIR/tmp (the vibrated bed: a scene of scenes/ with --set overrides), sweeps the step size
(fixed-step methods) or the tolerance (adaptive methods) of every method of the testbed,
and records for each run the error, the number of
right-hand-side evaluations (the summary line's rhs_evals) and the wall time of the time
loop (wall_s; for short runs recomputed from steps * particles / particle_steps_per_s,
which the summary prints to six digits, and the least of three repeats).

Methods (README "Integrators"):
  leapfrog, verlet                 fixed step, integrator.frac sweep
  rk4, erk:<TABLE> fixed step      frac sweep with rtol = 0 (Heun-Euler 2, Bogacki-Shampine
                                   3, Dormand-Prince 5, Verner 6), history frozen and state
  erk:<TABLE> adaptive             rtol sweep, atol = 1e-5 * rtol (m, m/s, rad/s), tables
                                   Dormand-Prince 5, Bogacki-Shampine 3, Verner 6, history
                                   frozen and state, roots false and true (the
                                   vibrated bed: roots for Dormand-Prince and
                                   Bogacki-Shampine only, ~1100 events in its window)
  cvode-adams                      rtol sweep (same atol rule), history frozen
Every fixed step is given as integrator.dt = T/N with N = ceil(T / (frac * dt_hart)), so
that every fixed-step run ends exactly at the scene's end time T; the setting recorded is
the effective frac = dt / dt_hart (dt_hart: the Hart critical step esfera logs).

Scenes and error definitions (all errors are dimensionless):
  head_on  two glass spheres (scenes/head_on.yaml: r = 5 mm, kn = 1e5 N/m, restitution
           0.5, +-1 m/s). Error = max(|e/e_x - 1|, |t_c/t_c,x - 1|), e the restitution and
           t_c the time from first touch to the overlap's return to zero, against the
           closed form of the linear spring-dashpot with the no-tension cut (the formula
           of tests/simtest.h, cut_impact_closed_form in studies/common.py). Both are
           read off the last frame: e = relative velocity / approach speed and, since the
           spheres coast freely after the impact, t_c = T - gap(T)/v_rel - t_touch.
  oblique  a sphere hitting a wall at 1 m/s normal and 0.4 m/s tangential, mu = 0.3, no
           tangential dashpot (tests/test_history.c). Error = max over (vx, vz, r wy) after
           the impact of |value - reference| / |v0|; reference: leapfrog at frac 3e-5,
           checked against frac 1.5e-5 (their difference is the reference floor).
  pack     300 spheres of tests/test_ledger.c (global damping 2/s, friction 0.5, no
           tangential dashpot) poured into a box; a leapfrog run takes them to t = 0.12 s
           (the bottom layers colliding, ~190 contacts) and its state is written to a CSV
           from which every method starts (allow_initial_overlap, history starting at
           zero). Error = RMS over particles of |x - x_ref| at T = 0.5 ms, divided by the
           mean radius; reference: leapfrog at frac 1.25e-4, checked against frac 2.5e-4.
           The pack is chaotic and non-smooth, hence the short window (measured while
           setting the study up: at 10-20 ms runs at any two steps differ by 1e-2 to 1e-1
           r; at 1 ms a particle resting 2 um above the floor already splits runs into two
           branches 2e-5 r apart; at 0.5 ms leapfrog runs agree to ~5e-7) and the
           tangential dashpot is off (with it, stick/slip switching scatters every
           method's result by ~1e-4 r at 2 ms). After the sweep the most accurate runs
           of the history-as-state curves (the most converged ODE solutions) are compared
           with each other and with the reference (oblique, pack, vibrated bed): when
           their median distance from the reference (the gap) exceeds the reference
           floor, errors below twice the gap are reported as not resolved, since the
           leapfrog reference and the ODE solutions have not been shown to agree better
           than that.
  vibrated_bed  scenes/vibrated_bed-quick.yaml (160 glass spheres, frictionless,
           restitution 0.7, a box shaken at 25 Hz, 6 g) run by its own leapfrog to
           t0 = 78.5 ms, about 5 ms after the bed landed on the plate, which is pushing it
           up; the last frame is written to a CSV from which every method starts
           (particles: file, allow_initial_overlap), with the box's oscillation phase
           set to phase + 2 pi f t0 (walls.0.motion.oscillate.phase) so that the box is
           where and moves as it did at t0. Error = RMS over particles of |x - x_ref| at
           T = 0.3 ms / mean radius; reference: leapfrog at frac 5e-5, checked against
           frac 1e-4 (halving its step). The window is short because the dense bed is
           chaotic (measured while setting the study up, from states in contact with the
           plate between 73.5 and 82 ms: the distance between leapfrog runs at two fine
           steps grows 2 to 5 fold every 0.1 ms; at 1 ms runs at frac 7.8e-4 and 3.9e-4
           differ by 4e-4 .. 1e-2 r, at 2 ms by 3e-3 .. 4e-2, with no convergence;
           halving checks at frac 2e-4 / 1e-4 give 1e-6 .. 6e-5 at 0.5 ms and
           2e-7 .. 2e-6 at 0.3 ms, where the leapfrog converges at first order). In
           flight (t0 = 90 ms, few contacts) runs agree to ~2e-6 at 0.5 ms, but the
           plate plays no part there.

Outputs into DIR (default studies/results/integrators/): SCENE.csv (method, history,
roots, setting, error, rhs_evals, wall_s, steps, rejected, then mode, events, restarts,
status), SCENE.json (title, description, Hart step, reference floor and note, model gap
and note, matched-accuracy level, and how the rows were measured: mode, esfera version,
elapsed and esfera time, date), SCENE_rhs.png and SCENE_wall.png (log-log error against
cost, the Pareto front of all runs marked), report.md (cheapest method at errors 1e-2,
1e-4, 1e-6 interpolated along each method's curve, observed orders, frozen vs state
history, roots, cost tables at matched accuracy). A curve stops early when its next
run would exceed the scene's per-run time budget, when its error reached the reference
floor, or when two refinements in a row no longer lower its error by 30 % within 30x of
the floor. The report and the plots are made from the CSV and JSON files alone, so that
scenes can be measured one at a time and the report rebuilt from all of them.

Run (Debian's python with numpy, matplotlib, h5py):
    /usr/bin/python3 studies/integrators.py [--quick] [--out DIR] [--esfera PATH]
                                            [--scenes A,B] [--replot]
--quick: head-on and oblique only, leapfrog, verlet, rk4 (frozen, state), adaptive
Dormand-Prince (frozen, state, state + roots) and cvode-adams, three settings each; about
10 s. tests/study_integrators.sh runs it and checks the outputs. The full mode (head_on,
oblique, pack, vibrated_bed) takes about 5 minutes for the first three and 5 more for
the vibrated bed on this machine (runs one at a time).
--scenes A,B: measure only these scenes of the mode; the mode's other scenes enter the
report from DIR's SCENE.csv and SCENE.json (left out when absent); only the measured
scenes' CSV, JSON and plots are rewritten. --replot: measure nothing, redraw every
scene's plots and the report from DIR's files.
"""
import argparse
import collections
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from common import (cut_impact_closed_form, last_frame, read_csv, run,  # noqa: E402
                    tsuji_zeta, write_csv, write_particles_csv, write_scene)

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

TARGETS = (1e-2, 1e-4, 1e-6)
ATOL_PER_RTOL = 1e-5  # atol = 1e-5 * rtol (m, m/s, rad/s)
DP5 = "erk:ARKODE_DORMAND_PRINCE_7_4_5"
BS3 = "erk:ARKODE_BOGACKI_SHAMPINE_4_2_3"
V6 = "erk:ARKODE_VERNER_8_5_6"
HEUN = "erk:ARKODE_HEUN_EULER_2_1_2"
SHORT = {"leapfrog": "leapfrog", "verlet": "verlet", "rk4": "RK4", HEUN: "Heun2",
         BS3: "BS3", DP5: "DP5", V6: "V6", "cvode-adams": "CVODE-Adams"}
NOMINAL = {"leapfrog": 2, "verlet": 2, "rk4": 4, HEUN: 2, BS3: 3, DP5: 5, V6: 6}
COLOR = {"leapfrog": "tab:blue", "verlet": "tab:orange", "rk4": "tab:green",
         HEUN: "tab:olive", BS3: "tab:purple", DP5: "tab:red", V6: "tab:brown",
         "cvode-adams": "tab:gray"}

# ---------------------------------------------------------------------------- scenes

HEAD_ON = dict(radius=0.005, density=2500.0, kn=1.0e5, eta=0.5, x0=0.0051, v0=1.0,
               duration=0.002)
OBLIQUE = dict(radius=0.005, z0=0.0051, vx=0.4, vz=-1.0, duration=1.0e-3)
PACK = dict(presettle=0.12, duration=5.0e-4)
# The vibrated bed: scenes/vibrated_bed-quick.yaml run by its own leapfrog to t0 (the bed
# landed on the plate ~5 ms before and is being pushed up by it), then windows of T.
VIB = dict(scene=os.path.join("scenes", "vibrated_bed-quick.yaml"), material="glass",
           presettle=0.0785, duration=3.0e-4, ref_frac=5.0e-5, check_frac=1.0e-4)
COMMON = "output: {every: 0, energy_every: 0}\n"


def head_on_yaml():
    p = HEAD_ON
    return (
        "name: head-on\n"
        "gravity: [0, 0, 0]\n"
        "domain: {min: [-0.1, -0.1, -0.1], max: [0.1, 0.1, 0.1]}\n"
        f"materials: {{glass: {{density: {p['density']}, kn: {p['kn']}, kt: {p['kn']}, "
        f"restitution: {p['eta']}, friction: 0.3}}}}\n"
        "particles:\n"
        f"  - {{material: glass, radius: {p['radius']}, position: [{-p['x0']}, 0, 0], "
        f"velocity: [{p['v0']}, 0, 0]}}\n"
        f"  - {{material: glass, radius: {p['radius']}, position: [{p['x0']}, 0, 0], "
        f"velocity: [{-p['v0']}, 0, 0]}}\n"
        "integrator: {method: leapfrog, dt: auto, dt_rule: hart, frac: 0.1}\n"
        f"run: {{duration: {p['duration']}}}\n" + COMMON)


def oblique_yaml():
    p = OBLIQUE
    return (
        "name: oblique\n"
        "gravity: [0, 0, 0]\n"
        "materials: {glass: {density: 2500, kn: 1.0e5, kt: 1.0e5, restitution: 0.5, "
        "tangential_restitution: 1, friction: 0.3}}\n"
        "particles:\n"
        f"  - {{material: glass, radius: {p['radius']}, position: [0, 0, {p['z0']}], "
        f"velocity: [{p['vx']}, 0, {p['vz']}]}}\n"
        "walls:\n"
        "  - {plane: {point: [0, 0, 0], normal: [0, 0, 1]}, material: glass}\n"
        "integrator: {dt: auto, dt_rule: hart, frac: 0.1}\n"
        f"run: {{duration: {p['duration']}}}\n" + COMMON)


def pack_yaml(particles, duration):
    """The pack of tests/test_ledger.c; particles: a generator entry or a file entry."""
    return (
        "name: pack\n"
        "materials:\n"
        "  g: {density: 2500, kn: 1.0e4, kt: 7.0e3, restitution: 0.4,\n"
        "      tangential_restitution: 1, friction: 0.5}\n"
        "  wallmat: {kn: 2.0e4, restitution: 0.3, friction: 0.3}\n"
        "particles:\n"
        f"  - {particles}\n"
        "walls:\n"
        "  - {box: {min: [0, 0, 0], max: [0.03, 0.03, 0.1]}, open: [top], "
        "material: wallmat}\n"
        "contact: {allow_initial_overlap: true}\n"
        "integrator: {dt: auto, dt_rule: hart, frac: 0.1}\n"
        "damping: {global: {translation: 2.0, rotation: 2.0}}\n"
        f"run: {{duration: {duration}}}\n" + COMMON)


PACK_GENERATOR = ("{generate: random, region: {min: [0, 0, 0.0], max: [0.03, 0.03, "
                  "0.09]}, count: 300, radius: {uniform: [0.0012, 0.0022]}, material: g, "
                  "seed: 9}")


# ----------------------------------------------------------------- closed form, errors

def head_on_exact():
    """(restitution, time to zero overlap) of the head-on pair: the cut closed form."""
    p = HEAD_ON
    m = 4.0 / 3.0 * math.pi * p["radius"] ** 3 * p["density"]
    c = cut_impact_closed_form(tsuji_zeta(p["eta"]), math.sqrt(p["kn"] / (m / 2)))
    return np.array([c.e, c.t_sep])


def head_on_observe(frame):
    """(restitution, overlap duration) from the last frame of a head-on run."""
    t, d = frame
    p = HEAD_ON
    x, v = d["position"][:, 0], d["velocity"][:, 0]
    v_rel, gap = v[1] - v[0], x[1] - x[0] - 2 * p["radius"]
    if not (v_rel > 0 and gap > 0):
        return np.array([np.nan, np.nan])
    t_touch = (2 * p["x0"] - 2 * p["radius"]) / (2 * p["v0"])
    return np.array([v_rel / (2 * p["v0"]), t - gap / v_rel - t_touch])


def head_on_error(obs, exact):
    return float(np.max(np.abs(obs / exact - 1)))


def oblique_observe(frame):
    _, d = frame
    v0 = math.hypot(OBLIQUE["vx"], OBLIQUE["vz"])
    u = [d["velocity"][0, 0], d["velocity"][0, 2],
         d["radius"][0] * d["angular_velocity"][0, 1]]
    return np.array(u) / v0


def max_abs_error(obs, ref):
    return float(np.max(np.abs(obs - ref)))


def pack_observe(frame):
    _, d = frame
    return {"x": d["position"], "r_mean": float(np.mean(d["radius"]))}


def pack_error(obs, ref):
    if obs["x"].shape != ref["x"].shape:
        return float("nan")
    dev = np.sqrt(np.mean(np.sum((obs["x"] - ref["x"]) ** 2, axis=1)))
    return float(dev / ref["r_mean"])


# ------------------------------------------------------------------------- running

Outcome = collections.namedtuple("Outcome", "status summary frame elapsed")


def last_frame_by_id(outdir):
    """(time, {dataset: array}) of the last frame, rows sorted by particle id."""
    t, d = last_frame(outdir)
    order = np.argsort(d["id"])
    return t, {k: (a[order] if getattr(a, "shape", ())[:1] == order.shape else a)
               for k, a in d.items()}


class Esfera:
    """Runs esfera into tmp/runs/TAG: an Outcome (status "ok", the summary and the last
    frame; else what went wrong), the time spent in esfera summed in machine_s."""

    def __init__(self, path, tmp, timeout):
        self.path, self.tmp, self.timeout = path, tmp, timeout
        self.machine_s = 0.0

    def write_scene(self, name, text):
        return write_scene(os.path.join(self.tmp, name + ".yaml"), text)

    def run(self, scene, sets, tag, keep=False):
        r = run(self.path, scene, os.path.join(self.tmp, "runs", tag), sets, self.timeout)
        self.machine_s += r.elapsed
        if r.returncode is None:
            return Outcome(f"timeout after {self.timeout:.0f} s", None, None, self.timeout)
        if r.returncode != 0:
            msg = (r.stderr.strip().splitlines() or ["?"])[0]
            return Outcome(f"exit {r.returncode}: {msg}", None, None, r.elapsed)
        frame = last_frame_by_id(r.out)
        if not keep:
            shutil.rmtree(r.out, ignore_errors=True)
        return Outcome("ok", r.summary, frame, r.elapsed)

    def log_text(self, tag):
        with open(os.path.join(self.tmp, "runs", tag, "log.txt")) as fh:
            return fh.read()


def loop_wall(summ):
    """Wall time of the time loop, to more digits than wall_s (printed as %.4f)."""
    steps, parts = float(summ["steps"]), float(summ["particles"])
    rate = float(summ["particle_steps_per_s"])
    if rate > 0 and steps > 0:
        return steps * parts / rate
    return float(summ["wall_s"])


# ------------------------------------------------------------------- methods, curves

Key = collections.namedtuple("Key", "method history roots mode")  # a curve's identity
Curve = collections.namedtuple("Curve", Key._fields + ("settings",))


def row_key(r):
    """The Key of the curve a CSV row belongs to."""
    return Key(r["method"], r["history"], r["roots"] == "true", r["mode"])


def label(c):
    """A curve's name in plots and tables (c: a Curve or a Key)."""
    name = SHORT.get(c.method, c.method)
    if c.method in ("leapfrog", "verlet"):
        return name
    extra = " roots" if c.roots else ""
    return f"{name} {c.mode} {c.history}{extra}"


def curve_sets(c, setting, scene):
    """--set overrides of one run of curve c at one setting (after the scene's own)."""
    sets = list(scene.sets) + [f"integrator.method={c.method}"]
    if c.mode == "fixed":
        n = math.ceil(scene.duration / (setting * scene.hart) - 1e-9)
        sets.append(f"integrator.dt={scene.duration / n!r}")
    else:
        sets += [f"integrator.rtol={setting:g}",
                 f"integrator.atol={setting * ATOL_PER_RTOL:g}"]
    if c.method not in ("leapfrog", "verlet"):
        if c.mode == "fixed":
            sets.append("integrator.rtol=0")
        sets.append(f"integrator.history={c.history}")
        if c.method != "cvode-adams":
            sets.append(f"integrator.roots={'true' if c.roots else 'false'}")
    return sets


def effective_frac(c, setting, scene):
    if c.mode != "fixed":
        return setting
    n = math.ceil(scene.duration / (setting * scene.hart) - 1e-9)
    return scene.duration / n / scene.hart


def fracs(first, count):
    return [first / 2 ** k for k in range(count)]


def rtols(first_exp, last_exp):
    return [10.0 ** -k for k in range(first_exp, last_exp + 1)]


def curves_full(scene_name):
    """Every method of the testbed with the scene's sweep."""
    roots_for = (DP5, BS3, V6)
    if scene_name in ("pack", "vibrated_bed"):
        f_lv, f_ode, tol = fracs(0.2, 10), fracs(0.2, 7), rtols(3, 8)
        if scene_name == "vibrated_bed":  # ~1100 contact events in 0.3 ms
            roots_for = (DP5, BS3)
            f_lv = fracs(0.2, 12)  # down to ~1e-6, to compare with the ODE methods there
    else:
        f_lv, f_ode, tol = fracs(0.2, 15), fracs(0.2, 15), rtols(2, 12)
    out = [Curve("leapfrog", "-", False, "fixed", f_lv),
           Curve("verlet", "-", False, "fixed", f_lv)]
    for m in ("rk4", HEUN, BS3, DP5, V6):
        for h in ("frozen", "state"):
            out.append(Curve(m, h, False, "fixed", f_ode))
    for m in (DP5, BS3, V6):
        for h in ("frozen", "state"):
            for r in (False, True):
                if r and m not in roots_for:
                    continue
                out.append(Curve(m, h, r, "adaptive", tol))
    out.append(Curve("cvode-adams", "frozen", False, "adaptive", tol))
    return out


def curves_quick(scene_name):
    f, tol = [0.1, 0.025, 0.00625], [1e-4, 1e-6, 1e-8]
    return [Curve("leapfrog", "-", False, "fixed", f),
            Curve("verlet", "-", False, "fixed", f),
            Curve("rk4", "frozen", False, "fixed", f),
            Curve("rk4", "state", False, "fixed", f),
            Curve(DP5, "frozen", False, "adaptive", tol),
            Curve(DP5, "state", False, "adaptive", tol),
            Curve(DP5, "state", True, "adaptive", tol),
            Curve("cvode-adams", "frozen", False, "adaptive", tol)]


# ------------------------------------------------------------------------ a scene

class Scene:
    """A scene file, its end time, Hart step, observable, reference and error."""

    META = ("name", "title", "description", "duration", "budget_s", "hart", "floor",
            "ref_note", "gap", "gap_note", "exact_ref", "matched", "matched_why", "run")

    def __init__(self, name, title, path, duration, observe, error, budget_s):
        self.name, self.title, self.path = name, title, path
        self.duration, self.observe, self.error = duration, observe, error
        self.budget_s = budget_s  # per-run limit on the predicted elapsed time
        self.sets = []  # --set overrides of every run of the scene (before the curve's)
        self.ref_fracs = None  # (reference frac, check frac); None: a closed form
        self.description = ""
        self.run = {}  # how and when the rows were measured (report header)
        self.hart = None
        self.ref = None
        self.floor = 0.0
        self.ref_note = ""
        self.gap, self.gap_note = 0.0, ""
        self.exact_ref = False  # the reference is a closed form
        self.matched, self.matched_why = None, ""  # error level of the cost table
        self.rows = []

    def resolvable(self):
        """Smallest error the study resolves: the reference floor or the model gap."""
        return max(self.floor, self.gap)

    def meta(self):
        return {k: getattr(self, k) for k in self.META}

    @classmethod
    def load(cls, out, name):
        """A scene measured before: DIR/NAME.json (its reference, floor, gap, notes) and
        DIR/NAME.csv (its runs); None when either is missing."""
        jp, cp = os.path.join(out, name + ".json"), os.path.join(out, name + ".csv")
        if not (os.path.exists(jp) and os.path.exists(cp)):
            return None
        with open(jp) as fh:
            meta = json.load(fh)
        sc = cls(name, meta["title"], None, meta["duration"], None, None, meta["budget_s"])
        for k in cls.META:
            if k in meta:
                setattr(sc, k, meta[k])
        sc.rows = read_rows(cp)
        return sc


def probe_hart(es, scene):
    """The Hart critical step of the scene, from esfera's log of a one-step run."""
    r = es.run(scene.path, list(scene.sets) + ["run.duration=1e-9"], scene.name + "_probe",
               keep=True)
    if r.status != "ok":
        raise RuntimeError(f"{scene.name}: probe run failed: {r.status}")
    m = re.search(r"critical dt \(FRAC = 1\):.*?hart ([0-9.eE+-]+) s",
                  es.log_text(scene.name + "_probe"))
    shutil.rmtree(os.path.join(es.tmp, "runs", scene.name + "_probe"), ignore_errors=True)
    if not m:
        raise RuntimeError(f"{scene.name}: no critical dt in the log")
    return float(m.group(1))


def leapfrog_reference(es, scene, frac, check_frac):
    """Reference: leapfrog at frac; floor: its distance from the run at check_frac."""
    c = Curve("leapfrog", "-", False, "fixed", [])
    obs = {}
    for f in (frac, check_frac):
        r = es.run(scene.path, curve_sets(c, f, scene), f"{scene.name}_ref")
        if r.status != "ok":
            raise RuntimeError(f"{scene.name}: reference run failed: {r.status}")
        obs[f] = scene.observe(r.frame)
    scene.ref = obs[frac]
    scene.floor = scene.error(obs[check_frac], scene.ref)
    scene.ref_note = (f"leapfrog at frac {effective_frac(c, frac, scene):.3g}; the run at "
                      f"frac {effective_frac(c, check_frac, scene):.3g} differs from it by "
                      f"{scene.floor:.2g} (the reference floor)")


def model_gap(scene, count=3):
    """The most accurate runs of `count` different history-as-state methods (those
    within 10x of the best), the most converged ODE solutions: their spread (largest
    mutual error) and their median error against the reference, the gap. A gap above
    the reference floor means the leapfrog reference and the ODE solutions have not
    been shown to agree better than that: it then bounds the resolvable error."""
    best = {}  # method -> its most accurate history-as-state run
    for key, rows in by_curve(scene.rows).items():
        good = [r for r in ok_rows(rows) if "_obs" in r]
        if key.history == "state" and good:
            r = min(good, key=lambda q: q["error"])
            if key.method not in best or r["error"] < best[key.method]["error"]:
                best[key.method] = r
    picks = sorted(best.values(), key=lambda r: r["error"])[:count]
    picks = [r for r in picks if r["error"] <= 10 * picks[0]["error"]]
    if len(picks) < 2 or scene.exact_ref:
        return
    spread = max(scene.error(a["_obs"], b["_obs"])
                 for i, a in enumerate(picks) for b in picks[i + 1:])
    gap = float(np.median([r["error"] for r in picks]))
    names = ", ".join(f"{label(row_key(r))} at {r['setting']:.3g} ({r['error']:.2g})"
                      for r in picks)
    scene.gap_note = (f"the most accurate history-as-state runs ({names}) agree among "
                      f"themselves to {spread:.2g} but lie {gap:.2g} (median) from the "
                      "reference")
    if gap > scene.floor:
        scene.gap = gap
        kind = ("a different limit" if gap > 3 * spread else
                "no common limit closer than their own spread")
        scene.gap_note += (f", above the reference floor: the ODE solutions reach {kind}; "
                           f"errors below {2 * gap:.2g} are not resolved")


def measure(es, scene, c, setting, tag):
    """One run of curve c at one setting: a CSV row (dict)."""
    row = dict(method=c.method, history=c.history, roots=str(c.roots).lower(),
               setting=effective_frac(c, setting, scene), mode=c.mode,
               error=float("nan"), rhs_evals="", wall_s="", steps="", rejected="",
               events="", restarts="", status="")
    r = es.run(scene.path, curve_sets(c, setting, scene), tag)
    row["elapsed"] = r.elapsed
    row["status"] = r.status
    if r.status != "ok":
        return row
    s = r.summary
    wall = loop_wall(s)
    for _ in range(2):  # short runs: the least of three timings
        if r.elapsed > 0.3:
            break
        again = es.run(scene.path, curve_sets(c, setting, scene), tag)
        if again.status == "ok":
            wall = min(wall, loop_wall(again.summary))
    row["_obs"] = scene.observe(r.frame)
    row.update(error=scene.error(row["_obs"], scene.ref),
               rhs_evals=int(s["rhs_evals"]), wall_s=wall, steps=int(s["steps"]),
               rejected=int(s.get("rejected", 0)), events=int(s.get("events", 0)),
               restarts=int(s.get("restarts", 0)))
    return row


def sweep_curve(es, scene, c, log):
    """Runs curve c from its coarsest setting down; stops when the next run would
    exceed the scene's budget, the error reached the floor, or refining stalls near
    the floor (within 30x of it)."""
    rows = []
    growth = 2.2 if c.mode == "fixed" else 3.0
    for k, setting in enumerate(c.settings):
        if rows and rows[-1]["elapsed"] * growth > scene.budget_s:
            log(f"  {label(c)}: stop before {setting:g} (budget)")
            break
        row = measure(es, scene, c, setting, f"{scene.name}_{k}")
        rows.append(row)
        log(f"  {label(c):34s} {setting:9.3g} err {row['error']:.3e} rhs "
            f"{row['rhs_evals']!s:>9} wall {fmt_wall(row['wall_s'])} [{row['status'][:60]}]")
        ok = [q for q in rows if q["status"] == "ok" and np.isfinite(q["error"])]
        if ok and ok[-1] is row and row["error"] <= scene.floor:
            break
        if (len(ok) >= 3 and row["error"] < 30 * scene.floor
                and stalled([q["error"] for q in ok[-3:]])):
            log(f"  {label(c)}: error stalled, stop")
            break
    return rows


def stalled(errs):
    """Two refinements in a row that did not lower the error by 30 %."""
    return errs[1] > 0.7 * errs[0] and errs[2] > 0.7 * errs[1]


def fmt_wall(w):
    return f"{w:.3g} s" if isinstance(w, float) else "-"


# -------------------------------------------------------------------------- analysis

def ok_rows(rows):
    return [r for r in rows if r["status"] == "ok" and np.isfinite(r["error"])
            and r["error"] > 0]


def by_curve(rows):
    """Rows grouped per curve, in sweep order (coarse to fine)."""
    groups = collections.OrderedDict()
    for r in rows:
        groups.setdefault(row_key(r), []).append(r)
    return groups


def cost_at(rows, target, cost):
    """Cost at which the curve first reaches error <= target, interpolated log-log
    between the last run above and the first run at or below it. Returns (cost, flag):
    flag 'coarsest' when already the coarsest run was below the target."""
    pts = [(r[cost], r["error"]) for r in ok_rows(rows)]
    for i, (c, e) in enumerate(pts):
        if e <= target:
            if i == 0:
                return c, "coarsest"
            c0, e0 = pts[i - 1]
            if e0 <= e or c0 <= 0 or c <= 0:
                return c, ""
            f = (math.log(target) - math.log(e0)) / (math.log(e) - math.log(e0))
            return math.exp(math.log(c0) + f * (math.log(c) - math.log(c0))), ""
    return None, ""


Best = collections.namedtuple("Best", "key cost flag")


def cheapest(groups, target, cost):
    """The curve reaching error <= target at the least cost: Best(key, cost, flag)."""
    best = None
    for key, rows in groups.items():
        c, flag = cost_at(rows, target, cost)
        if c is not None and (best is None or c < best.cost):
            best = Best(key, c, flag)
    return best


def pareto(rows, cost):
    """Runs no other run beats in both cost and error, by increasing cost (runs that tie
    exactly with a member, as leapfrog and verlet often do, included)."""
    front, best = [], math.inf
    for r in sorted(ok_rows(rows), key=lambda q: (q[cost], q["error"])):
        if r["error"] < best or (front and (r[cost], r["error"]) ==
                                 (front[-1][cost], front[-1]["error"])):
            front.append(r)
            best = r["error"]
    return front


def slope(xs, ys):
    if len(xs) < 2:
        return float("nan")
    return float(np.polyfit(np.log(xs), np.log(ys), 1)[0])


def orders(rows, floor):
    """Fitted slope of log error against log step over the runs above 3x the floor,
    the slope of the three coarsest and of the three finest of them, local slopes."""
    pts = [(r["setting"], r["error"]) for r in ok_rows(rows) if r["error"] > 3 * floor]
    if len(pts) < 2:
        return None
    x, y = zip(*pts)
    local = [math.log(y[i] / y[i + 1]) / math.log(x[i] / x[i + 1])
             for i in range(len(x) - 1)]
    envelope = [max(y[i:]) for i in range(len(y))]  # the bound C h^p, luck removed
    half = max(2, (len(x) + 1) // 2)
    return dict(all=slope(x, y), envelope=slope(x, envelope),
                coarse=slope(x[:half], y[:half]), fine=slope(x[-half:], y[-half:]),
                local=local, e_max=max(y), e_min=min(y))


def pair_compare(groups, a_key, b_key, cost="rhs_evals"):
    """Compare two curves at the settings they share: geometric mean of the error
    ratio a/b and of the cost ratio b/a."""
    a = {round(r["setting"], 12): r for r in ok_rows(groups.get(a_key, []))}
    b = {round(r["setting"], 12): r for r in ok_rows(groups.get(b_key, []))}
    common = sorted(set(a) & set(b), reverse=True)
    if not common:
        return None
    er = [a[s]["error"] / b[s]["error"] for s in common]
    cr = [b[s][cost] / a[s][cost] for s in common]
    return dict(n=len(common), err=float(np.exp(np.mean(np.log(er)))),
                err_min=min(er), err_max=max(er),
                cost=float(np.exp(np.mean(np.log(cr)))),
                best_a=min(a[s]["error"] for s in common),
                best_b=min(b[s]["error"] for s in common))


# ---------------------------------------------------------------------------- output

CSV_FIELDS = ["method", "history", "roots", "setting", "error", "rhs_evals", "wall_s",
              "steps", "rejected", "mode", "events", "restarts", "status"]


def read_rows(path):
    """A SCENE.csv's rows, numbers parsed; setting, error and wall_s always floats (nan
    where empty), the other columns empty where the run failed."""
    rows = read_csv(path)
    for r in rows:
        for k in ("setting", "error", "wall_s"):
            r[k] = float(r[k]) if r[k] != "" else float("nan")
    return rows


def write_meta(path, scene):
    with open(path, "w") as fh:
        json.dump(scene.meta(), fh, indent=1)
        fh.write("\n")


def style(key):
    method, history, roots, mode = key
    ls = "--" if history == "state" else "-"
    marker = "o" if mode == "fixed" else ("^" if roots else "s")
    return dict(color=COLOR.get(method, "k"), linestyle=ls, marker=marker,
                markersize=7 if method == "leapfrog" else 4,
                linewidth=3 if method == "leapfrog" else 1.1,
                markerfacecolor="none" if roots else None)


def plot_scene(scene, out, cost, xlabel):
    groups = by_curve(scene.rows)
    fig, ax = plt.subplots(figsize=(11, 6.5))
    for key, rows in groups.items():
        pts = ok_rows(rows)
        if pts:
            ax.loglog([r[cost] for r in pts], [r["error"] for r in pts],
                      label=label(key), **style(key))
    front = pareto(scene.rows, cost)
    if front:
        ax.step([r[cost] for r in front], [r["error"] for r in front], where="post",
                color="k", linewidth=2.2, alpha=0.35, label="Pareto front")
        ax.plot([r[cost] for r in front], [r["error"] for r in front], "o", ms=10,
                mfc="none", mec="k", alpha=0.6)
    if scene.floor > 0:
        ax.axhline(scene.floor, color="k", linestyle=":", linewidth=1,
                   label="reference floor")
    if scene.gap > 0:
        ax.axhline(scene.gap, color="tab:red", linestyle=":", linewidth=1,
                   label="model gap (state ODE limit vs reference)")
    for t in TARGETS:
        ax.axhline(t, color="0.8", linewidth=0.6, zorder=0)
    ax.set_xlabel(xlabel)
    ax.set_ylabel("error")
    ax.set_title(f"{scene.title}: error against {xlabel}")
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=6.5, loc="center left", bbox_to_anchor=(1.01, 0.5), ncol=1)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def fmt_cost(c, cost):
    if c is None:
        return "not reached"
    return f"{c:.3g}" if cost == "rhs_evals" else f"{c:.3g} s"


def cheapest_table(scene):
    groups = by_curve(scene.rows)
    lines = ["| error | cheapest in rhs evaluations | rhs evals | cheapest in wall time "
             "| wall time |", "|---|---|---|---|---|"]
    for t in TARGETS:
        cells = [f"{t:g}"]
        if scene.resolvable() > 0 and t < 2 * scene.resolvable():
            cells += [f"not resolved (reference floor / model gap "
                      f"{scene.resolvable():.2g})", "-"] * 2
            lines.append("| " + " | ".join(cells) + " |")
            continue
        for cost in ("rhs_evals", "wall_s"):
            best = cheapest(groups, t, cost)
            if best is None:
                cells += ["not reached", "-"]
            else:
                note = " (at its coarsest run)" if best.flag else ""
                cells += [label(best.key) + note, fmt_cost(best.cost, cost)]
        lines.append("| " + " | ".join(cells) + " |")
    return lines


def orders_table(scene):
    lines = ["| method | history | nominal | fitted slope | envelope slope | coarse half "
             "| fine half | local slopes (coarse to fine) | error span |",
             "|---|---|---|---|---|---|---|---|---|"]
    fits = []
    for key, rows in by_curve(scene.rows).items():
        if key.mode != "fixed":
            continue
        o = orders(rows, scene.resolvable())
        if o is None:
            continue
        fits.append((key, o))
        loc = " ".join(f"{s:.1f}" for s in o["local"])
        lines.append(f"| {SHORT.get(key.method, key.method)} | {key.history} | "
                     f"{NOMINAL.get(key.method)} | "
                     f"{o['all']:.2f} | {o['envelope']:.2f} | {o['coarse']:.2f} | "
                     f"{o['fine']:.2f} | {loc} | {o['e_max']:.1e} .. {o['e_min']:.1e} |")
    return lines, orders_summary(fits)


def orders_summary(fits):
    """One sentence: the range of the fitted slopes against the nominal orders."""
    if not fits:
        return ""
    sl = [o["all"] for _, o in fits]
    env = [o["envelope"] for _, o in fits]
    hi = max(max(o["e_max"] for _, o in fits), 0)
    lo = min(o["e_min"] for _, o in fits)
    nom = sorted({NOMINAL.get(k.method) for k, _ in fits})
    text = (f"Fitted slopes {min(sl):.2f} .. {max(sl):.2f} (envelopes {min(env):.2f} .. "
            f"{max(env):.2f}) for nominal orders {nom[0]} .. {nom[-1]}, over errors "
            f"{hi:.0e} .. {lo:.0e}.")
    if max(sl) < 1.5:
        text += (" Every fixed-step method is capped at first order over the whole range "
                 "measured: at contact onset the dashpot force jumps from 0 to c_n v_n "
                 "inside a step, an O(h) error per impact whose size depends on where "
                 "the onset falls in the step (hence the scatter of the local slopes); "
                 "the nominal order does not show anywhere in the range.")
    return text


def history_table(scene):
    groups = by_curve(scene.rows)
    lines = ["| method | mode | roots | shared settings | error frozen/state (geo. mean, "
             "range) | rhs state/frozen | wall state/frozen | best error frozen | best "
             "error state |", "|---|---|---|---|---|---|---|---|---|"]
    for key in groups:
        method, history, roots, mode = key
        if history != "frozen":
            continue
        skey = key._replace(history="state")
        cmp = pair_compare(groups, key, skey)
        if cmp is None:
            continue
        cmpw = pair_compare(groups, key, skey, cost="wall_s")
        lines.append(f"| {SHORT.get(method, method)} | {mode} | {str(roots).lower()} | "
                     f"{cmp['n']} | {cmp['err']:.3g} ({cmp['err_min']:.2g} .. "
                     f"{cmp['err_max']:.2g}) | {cmp['cost']:.2f} | {cmpw['cost']:.2f} | "
                     f"{cmp['best_a']:.2e} | {cmp['best_b']:.2e} |")
    return lines


def best_by_history(scene):
    """The best errors the frozen and the state curves reached (median and range)."""
    best = {"frozen": [], "state": []}
    for key, rows in by_curve(scene.rows).items():
        good = ok_rows(rows)
        if key.history in best and good and key.method != "cvode-adams":
            best[key.history].append(min(r["error"] for r in good))
    parts = [f"{h} median {np.median(v):.2g} ({min(v):.2g} .. {max(v):.2g}, "
             f"{len(v)} curves)" for h, v in best.items() if v]
    return ("Best error reached per erk/rk4 curve: " + "; ".join(parts) + ". A curve "
            "whose best error sits well above the reference floor stopped because "
            "refining no longer lowered its error, the budget or the sweep ended.")


def roots_table(scene):
    groups = by_curve(scene.rows)
    lines = ["| method | history | shared rtols | error no-roots/roots (geo. mean, range) "
             "| rhs roots/no-roots | wall roots/no-roots | events (finest) |",
             "|---|---|---|---|---|---|---|"]
    for key in groups:
        method, history, roots, mode = key
        if mode != "adaptive" or roots or method == "cvode-adams":
            continue
        rkey = key._replace(roots=True)
        cmp = pair_compare(groups, key, rkey)
        cmpw = pair_compare(groups, key, rkey, cost="wall_s")
        if cmp is None:
            continue
        ev = ok_rows(groups[rkey])[-1]["events"] if ok_rows(groups[rkey]) else "-"
        lines.append(f"| {SHORT.get(method, method)} | {history} | {cmp['n']} | "
                     f"{cmp['err']:.3g} ({cmp['err_min']:.2g} .. {cmp['err_max']:.2g}) | "
                     f"{cmp['cost']:.2f} | {cmpw['cost']:.2f} | {ev} |")
    return lines


def matched_table(scene, target):
    """For every curve its cheapest run with error <= target, and the interpolated cost."""
    lines = [f"Matched accuracy, error <= {target:g}: for each method its cheapest run "
             "reaching it (setting, measured error, rhs evaluations, wall time) and the "
             "costs interpolated to exactly that error.", "",
             "| method | setting | error | rhs evals | wall time | rhs at target | wall at "
             "target |", "|---|---|---|---|---|---|---|"]
    entries = []
    for key, rows in by_curve(scene.rows).items():
        good = [r for r in ok_rows(rows) if r["error"] <= target]
        if not good:
            entries.append((math.inf, f"| {label(key)} | not reached | - | - | - | "
                                      "- | - |"))
            continue
        r = min(good, key=lambda q: q["rhs_evals"])
        c_rhs, _ = cost_at(rows, target, "rhs_evals")
        c_wall, _ = cost_at(rows, target, "wall_s")
        kind = "frac" if key.mode == "fixed" else "rtol"
        entries.append((c_rhs, f"| {label(key)} | {kind} {r['setting']:.3g} | "
                               f"{r['error']:.2e} | {r['rhs_evals']} | {r['wall_s']:.3g} s "
                               f"| {c_rhs:.3g} | {c_wall:.3g} s |"))
    return lines + [e[1] for e in sorted(entries, key=lambda q: q[0])]


def per_rhs_table(scene):
    """Median wall time per rhs evaluation of each curve's runs."""
    cells = []
    for key, rows in by_curve(scene.rows).items():
        q = [r["wall_s"] / r["rhs_evals"] for r in ok_rows(rows) if r["rhs_evals"]]
        if q:
            cells.append((float(np.median(q)), label(key)))
    lines = ["| method | wall time per rhs evaluation (median) |", "|---|---|"]
    return lines + [f"| {n} | {t * 1e6:.3g} us |" for t, n in sorted(cells)]


def pareto_members(scene, cost):
    names = []
    for r in pareto(scene.rows, cost):
        n = label(row_key(r))
        if n not in names:
            names.append(n)
    return ", ".join(names)


def failures(scene):
    bad = [r for r in scene.rows if r["status"] != "ok"]
    return [f"- {label(row_key(r))} at {r['setting']:.3g}: {r['status']}" for r in bad]


def scene_section(scene):
    out = [f"## {scene.title}", "", scene.description, ""]
    if scene.ref_note:
        out += [f"Reference: {scene.ref_note}.", ""]
    if scene.gap_note:
        out += [f"Convergence check: {scene.gap_note}.", ""]
    out += [f"![error vs rhs]({scene.name}_rhs.png)", "",
            f"![error vs wall]({scene.name}_wall.png)", "",
            f"Runs: {len(scene.rows)} ({len(ok_rows(scene.rows))} measured), data in "
            f"[{scene.name}.csv]({scene.name}.csv).", "",
            "### Cheapest method per error level", "",
            "Costs interpolated (log-log) along each method's curve to the first crossing "
            "of the error level.", ""]
    out += cheapest_table(scene)
    out += ["", f"Pareto front in rhs evaluations: {pareto_members(scene, 'rhs_evals')}.",
            "", f"Pareto front in wall time: {pareto_members(scene, 'wall_s')}.", ""]
    ot, osum = orders_table(scene)
    out += ["### Observed orders (fixed step)", "",
            "Slope of log error against log step (frac) over the runs above 3x the "
            "reference floor (or gap); the envelope slope fits the running maximum "
            "(coarse to fine) of the errors, the bound without the lucky dips; the halves "
            "fit the coarser and the finer half of the runs.", ""] + ot + ["", osum, ""]
    ht = history_table(scene)
    if len(ht) > 2:
        out += ["### Frozen vs state history", "",
                "Ratios at equal settings (frac or rtol): above 1 means state is more "
                "accurate at that setting.", ""] + ht + ["", best_by_history(scene), ""]
    rt = roots_table(scene)
    if len(rt) > 2:
        out += ["### Roots (steps ending at contact onset and separation)", "",
                "Ratios at equal rtol: error above 1 means roots is more accurate there.",
                ""] + rt + [""]
    out += ["### Wall time per rhs evaluation", "",
            "What turns rhs evaluations into wall time: the force loop plus each "
            "integrator's overhead (ERKStep's vector operations, restarts with history "
            "as state, event functions with roots).", ""] + per_rhs_table(scene) + [""]
    if scene.matched:
        out += ["### Cost at matched accuracy", ""]
        if scene.matched_why:
            out += [scene.matched_why, ""]
        out += matched_table(scene, scene.matched) + [""]
    fl = failures(scene)
    if fl:
        out += ["Runs without a measurement:", ""] + fl + [""]
    return out


# ------------------------------------------------------------------------- the study

def make_head_on(es):
    e_x, tc_x = head_on_exact()
    ho = Scene("head_on", "Head-on collision", es.write_scene("head_on", head_on_yaml()),
               HEAD_ON["duration"], head_on_observe, head_on_error, 6.0)
    ho.matched = 1e-4
    ho.description = (
        "Two equal glass spheres, r = 5 mm, kn = 1e5 N/m, restitution 0.5, 1 m/s each, "
        "no gravity, T = 2 ms (scenes/head_on.yaml). Error = max(|e/e_x - 1|, "
        "|t_c/t_c,x - 1|) against the no-tension closed form (e_x = "
        f"{e_x:.6f}, t_c,x = {tc_x * 1e6:.3f} us).")
    return ho


def make_oblique(es):
    ob = Scene("oblique", "Oblique frictional impact",
               es.write_scene("oblique", oblique_yaml()), OBLIQUE["duration"],
               oblique_observe, max_abs_error, 6.0)
    ob.ref_fracs = (3e-5, 1.5e-5)
    ob.description = (
        "A glass sphere (r = 5 mm, kn = kt = 1e5 N/m, restitution 0.5, mu = 0.3, no "
        "tangential dashpot) hits a wall at 1 m/s normal, 0.4 m/s tangential; T = 1 ms "
        "(tests/test_history.c). Error = max over (vx, vz, r wy) after the impact of "
        "|value - reference| / |v0|.")
    return ob


def make_pack(es):
    """The poured pack at t = 0.12 s (a leapfrog run), written to a CSV start state."""
    gen = es.write_scene("pack_pour", pack_yaml(PACK_GENERATOR, PACK["presettle"]))
    r = es.run(gen, [], "pack_pour")
    if r.status != "ok":
        raise RuntimeError(f"pack pour failed: {r.status}")
    _, d = r.frame
    write_particles_csv(os.path.join(es.tmp, "pack_start.csv"), d, motion=True)
    path = es.write_scene("pack", pack_yaml("{file: pack_start.csv, material: g}",
                                            PACK["duration"]))
    pk = Scene("pack", "Settling pack", path, PACK["duration"], pack_observe, pack_error,
               45.0)
    pk.ref_fracs = (1.25e-4, 2.5e-4)
    pk.matched = 1e-5
    pk.matched_why = ("At 1e-4 every method of the pack already meets the level at its "
                      "coarsest setting, so the table is at 1e-5, where the curves cross.")
    pk.description = (
        f"{len(d['radius'])} spheres of tests/test_ledger.c (r 1.2-2.2 mm, kn = 1e4 N/m, "
        "walls 2e4 N/m, restitution 0.4/0.3, mu 0.5/0.3, global damping 2/s, no "
        "tangential dashpot) poured into a 3 cm box; every run starts from the leapfrog "
        f"state at t = {PACK['presettle']} s (bottom layers in collision, history "
        f"starting at zero) and runs T = {PACK['duration'] * 1e3:g} ms. Error = RMS "
        "|x - x_ref| over the particles / mean radius.")
    return pk


def scene_number(text, key):
    """The first number after `key:` in a scene file's text (None when absent)."""
    m = re.search(r"\b" + key + r":\s*([-+0-9.eE]+)", text)
    return float(m.group(1)) if m else None


def make_vibrated_bed(es):
    """scenes/vibrated_bed-quick.yaml run by its own leapfrog to t0 = VIB['presettle'];
    the last frame is the CSV start state of every run, and the box's oscillation phase
    is set to (phase + 2 pi f t0) so that the box is where, and moves as, it did at t0."""
    path = os.path.join(REPO, VIB["scene"])
    with open(path) as fh:
        text = fh.read()
    freq, gam = scene_number(text, "frequency"), scene_number(text, "acceleration")
    phase0 = scene_number(text, "phase") or 0.0
    if freq is None or gam is None:
        raise RuntimeError(f"{VIB['scene']}: no oscillate frequency / acceleration found")
    r = es.run(path, [f"run.duration={VIB['presettle']!r}", "output.every=0",
                      "output.energy_every=0"], "vibrated_bed_pour")
    if r.status != "ok":
        raise RuntimeError(f"vibrated bed presettle failed: {r.status}")
    t0, d = r.frame
    csv_path = os.path.join(es.tmp, "vibrated_bed_start.csv")
    write_particles_csv(csv_path, d, motion=True)
    w = 2 * math.pi * freq
    th = phase0 + w * t0
    amp = gam * 9.81 / w ** 2
    zp, vp, ap = amp * math.sin(th), amp * w * math.cos(th), -amp * w * w * math.sin(th)
    gap = d["position"][:, 2] - d["radius"] - zp  # the box's floor is at z = 0 at rest
    vb = Scene("vibrated_bed", "Vibrated bed (moving wall)", path, VIB["duration"],
               pack_observe, pack_error, 40.0)
    vb.sets = [f"particles=[{{file: {csv_path}, material: {VIB['material']}}}]",
               f"walls.0.motion.oscillate.phase={math.fmod(th, 2 * math.pi)!r}",
               "contact.allow_initial_overlap=true", "output.every=0",
               "output.energy_every=0", f"run.duration={VIB['duration']!r}"]
    vb.ref_fracs = (VIB["ref_frac"], VIB["check_frac"])
    vb.matched = 1e-5
    vb.description = (
        f"{VIB['scene']}: {len(d['radius'])} glass spheres (d 0.9-1.1 mm, kn = kt = "
        f"5e4 N/m, restitution 0.7, frictionless) in a 16 x 1.1 mm box shaken "
        f"vertically at {freq:g} Hz, {gam:g} g. The scene's leapfrog (frac 0.2) runs it "
        f"to t0 = {t0 * 1e3:.4g} ms, in the third cycle, about 5 ms after the bed landed "
        f"on the plate: {int(np.sum(gap < 2e-6))} spheres within 2 um of the plate (of "
        f"{int(np.sum(gap < 2e-5))} within 20 um), which is at {zp * 1e3:+.3f} mm moving "
        f"up at {vp:.3f} m/s and accelerating at {ap / 9.81:+.2f} g, pushing the bed "
        f"(mean vz {np.mean(d['velocity'][:, 2]):+.3f} m/s) up. Every run starts from "
        "that frame (a CSV, allow_initial_overlap) with the box's phase set to "
        f"2 pi f t0 = {math.fmod(th, 2 * math.pi):.6f} rad, so that the box is where it "
        f"was at t0, and runs T = {VIB['duration'] * 1e3:g} ms. Error = RMS |x - x_ref| "
        "over the particles / mean radius. The window is short because the dense bed is "
        "chaotic: measured while setting the study up from starts between 73.5 "
        "and 82 ms (the bed on the plate), leapfrog runs at two fine steps (frac 7.8e-4 "
        "and 3.9e-4) differ by 4e-4 .. 1e-2 after 1 ms and 3e-3 .. 4e-2 after 2 ms, "
        "without converging; the distance between runs grows 2 to 5 fold every 0.1 ms; "
        "halving checks at frac 2e-4 / 1e-4 give 1e-6 .. 6e-5 at 0.5 ms and "
        "2e-7 .. 2e-6 at 0.3 ms, where the leapfrog converges at first order.")
    return vb


def run_scene(es, scene, curves, log):
    scene.hart = probe_hart(es, scene)
    log(f"{scene.name}: hart dt {scene.hart:.4g} s")
    if scene.ref_fracs is None:  # head-on: the closed form
        scene.ref, scene.floor, scene.exact_ref = head_on_exact(), 1e-12, True
    else:
        leapfrog_reference(es, scene, *scene.ref_fracs)
    log(f"{scene.name}: reference floor {scene.floor:.3g} {scene.ref_note}")
    for c in curves:
        scene.rows += sweep_curve(es, scene, c, log)
    model_gap(scene)
    if scene.gap_note:
        log(f"{scene.name}: {scene.gap_note}")


BUILDERS = collections.OrderedDict([("head_on", make_head_on), ("oblique", make_oblique),
                                    ("pack", make_pack),
                                    ("vibrated_bed", make_vibrated_bed)])
QUICK_SCENES = ("head_on", "oblique")


def summary_lines(scenes):
    """Headline: the cheapest method per scene and error level."""
    out = ["| scene | error | cheapest (rhs evals) | cheapest (wall time) |",
           "|---|---|---|---|"]
    for s in scenes:
        g = by_curve(s.rows)
        for t in TARGETS:
            cells = []
            for cost in ("rhs_evals", "wall_s"):
                if s.resolvable() > 0 and t < 2 * s.resolvable():
                    cells.append("not resolved (floor)")
                    continue
                b = cheapest(g, t, cost)
                cells.append("not reached" if b is None else
                             f"{label(b.key)} ({fmt_cost(b.cost, cost)})")
            out.append(f"| {s.title} | {t:g} | {cells[0]} | {cells[1]} |")
    return out


def run_lines(scenes):
    """How each scene's rows were measured: scenes measured together are listed
    together (their times are then the batch's)."""
    groups = collections.OrderedDict()
    for s in scenes:
        key = json.dumps(s.run, sort_keys=True)
        groups.setdefault(key, []).append(s)
    out = []
    for key, ss in groups.items():
        r = json.loads(key)
        names = ", ".join(s.title for s in ss)
        if not r:
            out.append(f"- {names}: no record of the run.")
            continue
        together = " together" if len(ss) > 1 else ""
        out.append(f"- {names}: {r.get('mode', '?')} mode, {r.get('version', '?')}, "
                   f"{r.get('elapsed_s', float('nan')):.0f} s elapsed, "
                   f"{r.get('machine_s', float('nan')):.0f} s in esfera processes"
                   f"{together}" + (f" ({r['note']})" if r.get("note") else "") + ".")
    return out


def write_report(path, scenes, args):
    quick = " --quick" if args.quick else ""
    lines = [
        "# Study 3: integrators, error against cost", "",
        f"Generated by `studies/integrators.py{quick}`, runs one at a time. Wall times "
        "are the time loop alone (summary wall_s); the machine was shared with other "
        "jobs, so they carry some noise, rhs evaluations do not. The scenes' runs:", ""]
    lines += run_lines(scenes) + [
        "",
        "Methods: leapfrog and verlet (fixed step), rk4 and erk tables at fixed step "
        "(frac sweep, rtol = 0), adaptive erk (rtol sweep, atol = 1e-5 rtol), "
        "cvode-adams (rtol sweep); every ODE method with history frozen, the erk ones "
        "(rk4 included) also with history state, adaptive erk with and without roots "
        "(the vibrated bed: roots for DP5 and BS3 only). Fixed steps are dt = T/N, the "
        "setting is the effective frac = dt/dt_hart. A curve stops when its next run "
        "would exceed the scene's per-run budget, at the reference floor, or when "
        "refining stops lowering the error.", ""]
    if args.quick:
        lines += ["Vibrated bed (moving wall): measured in the full mode only.", ""]
    lines += ["## Headline", ""] + summary_lines(scenes) + [""]
    for s in scenes:
        lines += scene_section(s)
    with open(path, "w") as fh:
        fh.write("\n".join(lines) + "\n")


def esfera_version(path):
    try:
        return subprocess.run([path, "--version"], capture_output=True, text=True,
                              timeout=30).stdout.strip() or "esfera (unknown version)"
    except OSError:
        return "esfera (unknown version)"


def parse_args(argv):
    ap = argparse.ArgumentParser(description="Integrator study: error against cost.")
    ap.add_argument("--quick", action="store_true",
                    help="reduced sweep: head-on and oblique, 8 curves x 3 settings")
    ap.add_argument("--out", default=os.path.join(REPO, "studies", "results",
                                                  "integrators"))
    ap.add_argument("--esfera", default=os.path.join(REPO, "build", "esfera"))
    ap.add_argument("--timeout", type=float, default=300.0,
                    help="limit for one esfera run, s")
    ap.add_argument("--scenes", default=None,
                    help="comma-separated scenes to measure (of " + ", ".join(BUILDERS) +
                    "); the mode's other scenes are taken from OUT's SCENE.csv and "
                    "SCENE.json; default: all of the mode")
    ap.add_argument("--replot", action="store_true",
                    help="measure nothing: plots and report from OUT's CSV and JSON files")
    return ap.parse_args(argv)


def main(argv):
    args = parse_args(argv)
    names = QUICK_SCENES if args.quick else tuple(BUILDERS)
    measure_names = names if args.scenes is None else [
        n.strip() for n in args.scenes.split(",") if n.strip()]
    bad = [n for n in measure_names if n not in names]
    if bad:
        print(f"integrators.py: unknown scene(s) {', '.join(bad)} for the "
              f"{'quick' if args.quick else 'full'} mode (of {', '.join(names)})",
              file=sys.stderr)
        return 2
    if args.replot:
        measure_names = []
    esf = os.path.abspath(args.esfera)
    if measure_names and not os.access(esf, os.X_OK):
        print(f"integrators.py: no esfera program at {esf}", file=sys.stderr)
        return 2
    out = os.path.abspath(args.out)
    tmp = os.path.join(out, "tmp")
    os.makedirs(os.path.join(tmp, "runs"), exist_ok=True)
    es = Esfera(esf, tmp, args.timeout)
    t0 = time.monotonic()
    version = esfera_version(esf) if measure_names else None

    def log(msg):
        print(f"[{time.monotonic() - t0:7.1f} s] {msg}", file=sys.stderr, flush=True)

    def plots(s):
        plot_scene(s, os.path.join(out, s.name + "_rhs.png"), "rhs_evals",
                   "rhs evaluations")
        plot_scene(s, os.path.join(out, s.name + "_wall.png"), "wall_s", "wall time (s)")

    scenes = []
    for name in names:
        if name in measure_names:
            ts, ms = time.monotonic(), es.machine_s
            s = BUILDERS[name](es)
            run_scene(es, s, (curves_quick if args.quick else curves_full)(name), log)
            s.run = dict(mode="quick" if args.quick else "full", version=version,
                         elapsed_s=round(time.monotonic() - ts, 1),
                         machine_s=round(es.machine_s - ms, 1),
                         date=time.strftime("%Y-%m-%d"))
            write_csv(os.path.join(out, name + ".csv"), s.rows, CSV_FIELDS)
            write_meta(os.path.join(out, name + ".json"), s)
            log(f"{name}: {s.run['elapsed_s']:.0f} s elapsed, "
                f"{s.run['machine_s']:.0f} s in esfera")
        s = Scene.load(out, name)  # the report is made from the files alone
        if s is None:
            log(f"{name}: no {name}.csv / {name}.json in {out}: left out of the report")
            continue
        if name in measure_names or args.replot:
            plots(s)
        scenes.append(s)
    write_report(os.path.join(out, "report.md"), scenes, args)
    shutil.rmtree(os.path.join(tmp, "runs"), ignore_errors=True)
    log(f"done: {out}/report.md")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
