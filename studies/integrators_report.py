"""integrators_report.py -- the integrator study's output from the scenes' rows: the
error-against-cost plots (SCENE_rhs.png, SCENE_wall.png) and report.md (the headline, then
per scene the cheapest method per error level, Pareto fronts, observed orders, frozen vs
state history, roots, wall time per rhs evaluation, cost at matched accuracy), and at its
end DIR/hertz.md when integrators_hertz.py has written it.
"""
import collections
import json
import math
import os

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from integrators_curves import (BS3, DP5, HEUN, NOMINAL, SHORT, V6, by_curve,  # noqa: E402
                                cheapest, cost_at, label, ok_rows, orders, pair_compare,
                                pareto, row_key)

TARGETS = (1e-2, 1e-4, 1e-6)  # the error levels of the report
COLOR = {"leapfrog": "tab:blue", "verlet": "tab:orange", "rk4": "tab:green",
         HEUN: "tab:olive", BS3: "tab:purple", DP5: "tab:red", V6: "tab:brown",
         "cvode-adams": "tab:gray"}


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
    hertz = os.path.join(os.path.dirname(path), "hertz.md")  # integrators_hertz.py's
    if os.path.exists(hertz):
        with open(hertz) as fh:
            lines += [fh.read().rstrip("\n")]
    with open(path, "w") as fh:
        fh.write("\n".join(lines) + "\n")
