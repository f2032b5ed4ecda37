"""integrators_curves.py -- the integrator study's methods and curves, and what is
computed from a curve's rows: the method names (DP5, BS3, ...) with their short names and
nominal orders; a curve (method, history, roots, mode and its settings) and the --set
overrides of one of its runs; the full and quick sweeps; then the analysis of the rows:
grouping per curve, cost at an error level, the cheapest curve, the Pareto front, fitted
orders and pairwise comparisons.
"""
import collections
import math

import numpy as np

# --------------------------------------------------------------------------- methods

ATOL_PER_RTOL = 1e-5  # atol = 1e-5 * rtol (m, m/s, rad/s)
DP5 = "erk:ARKODE_DORMAND_PRINCE_7_4_5"
BS3 = "erk:ARKODE_BOGACKI_SHAMPINE_4_2_3"
V6 = "erk:ARKODE_VERNER_8_5_6"
HEUN = "erk:ARKODE_HEUN_EULER_2_1_2"
SHORT = {"leapfrog": "leapfrog", "verlet": "verlet", "rk4": "RK4", HEUN: "Heun2",
         BS3: "BS3", DP5: "DP5", V6: "V6", "cvode-adams": "CVODE-Adams"}
NOMINAL = {"leapfrog": 2, "verlet": 2, "rk4": 4, HEUN: 2, BS3: 3, DP5: 5, V6: 6}


# ---------------------------------------------------------------------------- curves

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
