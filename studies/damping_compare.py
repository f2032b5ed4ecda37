"""damping_compare.py -- part 3 of the damping study (studies/damping.py runs it): local
vs global vs adaptive damping compared on a pack (the pour and the load step, and what the
example Rayleigh setting gives its contacts), on dynamics (a bouncing sphere, a pulse along
a chain) and on seed 004's vibrated bed (with the inelastic bouncing-ball model). Each
*_study runs its scenes and writes its CSV files.
"""
import math
import os

import numpy as np

from common import (energy, frames, kinetic, last_frame, tsuji_zeta, write_csv,
                    write_particles_csv)
from damping_cases import ADAPTIVE, Setup, drag, local
from damping_forms import (G, apex_heights, cross_time, cut_impact, drag_apex,
                           flights_per_period, ke_settle_time, slab_fraction)


# --- part 3a: settling a pack ----------------------------------------------------------

PACK = {"density": 2500.0, "kn": 1.0e4, "kt": 7.0e3, "rmin": 0.0012, "rmax": 0.0022,
        "rmean": 0.0017, "friction": 0.5, "box": 0.02}


def pack_materials(eta):
    P = PACK
    return {"g": {"density": P["density"], "kn": P["kn"], "kt": P["kt"], "restitution": eta,
                  "friction": P["friction"]},
            "wall": {"kn": P["kn"], "kt": P["kt"], "restitution": eta,
                     "friction": P["friction"]}}


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
    return pour, load


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
    return {"runs": got}
