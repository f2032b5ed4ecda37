"""critical_dt_report.py -- the critical-step study's plots (limit_vs_xi.png,
margins.png, limit_vs_kt.png, sweep.png) and report.md (method, margin tables, where each
rule is unsafe, checks and the numbered conclusions), made from the result rows (fresh,
or read back from limits.csv, runs.csv and summary.csv by --replot).
"""
import math

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from critical_dt_cases import (AMP, GROWTH, MIN_STEPS, RESOLUTION, RULE_LABEL,  # noqa: E402
                               RULES, SWEEP_SPAN, damp_factor)


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
          "### The live stability check",
          "",
          live_lines(results, runs),
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


def live_counts(results, runs):
    """The live check against the measurement: runs (its verdict against the growth
    criterion's) and cases (its limit against the bisected bracket)."""
    rs = [r for r in runs if r.get("check", "") != ""]
    unst = [r for r in rs if r["unstable"] == 1]
    stab = [r for r in rs if r["unstable"] == 0]
    missed = [r for r in unst if int(r["exit_stop"]) == 0]
    alarms = [r for r in stab if int(r["exit_stop"]) != 0]
    lim = {(r["case"], r["eta"]): r for r in results}
    over = [r["dt"] / lim[(r["case"], r["eta"])]["dt_live"] for r in alarms]
    cs = [r for r in results if r["dt_live"] == r["dt_live"]]
    inside = [r for r in cs if r["dt_stable"] <= r["dt_live"] <= r["dt_unstable"]]
    ratio = [r["dt_limit"] / r["dt_live"] for r in cs]
    below = [r for r in cs if r["dt_live"] < r["dt_stable"]]
    return dict(runs=len(rs), unst=len(unst), stab=len(stab), missed=missed,
                alarms=alarms, over=max(over) if over else 1.0, below=below,
                cases=len(cs), inside=len(inside),
                rmin=min(ratio) if ratio else float("nan"),
                rmax=max(ratio) if ratio else float("nan"))


def live_lines(results, runs):
    c = live_counts(results, runs)
    if not c["runs"]:
        return "No run recorded the live check (runs.csv from an older esfera)."
    out = [f"Every run had the live check on (`stability: warn`, so that it did not stop "
           f"the run it judged: the same run with `stability: stop`, the default without "
           f"`allow_unstable`, ends with exit 1 where it warned).",
           "",
           f"- Runs the growth criterion judged unstable: {c['unst']}; with "
           f"`stability: stop` {c['unst'] - len(c['missed'])} of them exit 1, "
           f"{len(c['missed'])} exit 0.",
           f"- Runs judged stable: {c['stab']}; {c['stab'] - len(c['alarms'])} exit 0, "
           f"{len(c['alarms'])} exit 1, all at a dt between the live limit and "
           f"{c['over']:.3f} times it.",
           f"- The live check's limit (the first check's, in the run nearest the "
           f"measured limit) lies inside the bisected 1 % bracket in {c['inside']} of "
           f"{c['cases']} cases; measured limit / live limit {c['rmin']:.4f} to "
           f"{c['rmax']:.4f}."]
    bl = c["below"]
    if bl:
        out.append(f"- The live limit lies below the bracket in {len(bl)} cases: "
                   + "; ".join(f"{r['case']} eta {r['eta']:g} (measured / live "
                               f"{r['dt_limit'] / r['dt_live']:.4f})" for r in bl) +
                   ". λ_max(dt² A + 2 dt B) < 4 makes the discrete energy positive "
                   "definite, which is sufficient for stability and exact when the "
                   "damping is proportional to the stiffness or the modes do not "
                   "couple (every single contact: there the live limit is the closed "
                   "form, which the 300-period runs miss by 0.05 % in two cases); in a "
                   "pack it is not, and the check can stop a run a little below the "
                   "true limit, never above it by more than the bisection's "
                   "resolution.")
    for r in c["missed"][:10]:
        out.append(f"  - missed: {r['case']} eta {r['eta']:g} dt {r['dt']:.6g} growth "
                   f"{r['growth']:.3g}")
    for r in c["alarms"][:10]:
        out.append(f"  - stopped though judged stable: {r['case']} eta {r['eta']:g} dt "
                   f"{r['dt']:.6g} growth {r['growth']:.3g}")
    return "\n".join(out)


def c_live(results, runs):
    c = live_counts(results, runs)
    if not c["runs"]:
        return ""
    return (f"**The live check** (esfera's leapfrog, at step 0, every stability_every steps (2000 in these runs) and at the end: "
            f"the largest eigenvalue of dt^2 A + 2 dt B of the contact network, stable "
            f"below 4) turns the silent instabilities into exit 1: of {c['unst']} runs "
            f"judged unstable {c['unst'] - len(c['missed'])} would stop, and of "
            f"{c['stab']} judged stable {len(c['alarms'])} would (at most "
            f"{c['over']:.3f} x the live limit). Its limit is the measured one within "
            f"the 1 % bracket in {c['inside']} of {c['cases']} cases (measured / live "
            f"{c['rmin']:.4f} to {c['rmax']:.4f}: a sufficient condition, conservative "
            f"only where the damping is not proportional to the stiffness), damping of "
            f"every mode and rotation included, where every seed rule and "
            f"(2/omega_max) f(xi_max) are unsafe.")


def conclusions(results, runs, info):
    """Numbered conclusions, each quoting the numbers it rests on."""
    items = [c_validation(results), c_normal(results), c_tangential(results),
             c_pack(results, info), c_modes(results), c_frac01(results),
             c_signatures(results, runs), c_live(results, runs)]
    return [f"{i + 1}. {t}" for i, t in enumerate(t for t in items if t)]
