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
          esfera's values, src/core/timestep.c); 2/omega_max and (2/omega_max) f(xi_max)
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

Code: this file holds the command line and the driver (main, render, replot);
critical_dt_cases.py the cases, the runs and the bisection, critical_dt_report.py the
plots and report.md.
"""
import argparse
import concurrent.futures as cf
import os
import sys
import time

from common import read_csv, write_csv
from critical_dt_cases import (FULL, QUICK, all_modes, build_cases, prepare_pack, run_all,
                               write_pack_csv)
from critical_dt_report import (plot_kt, plot_limits, plot_margins, plot_sweep,
                                write_report)

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


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
