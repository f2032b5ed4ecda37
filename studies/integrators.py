#!/usr/bin/python3
"""integrators.py - issue 7, study 3: error against cost for every integrator of esfera.

The study runs the esfera program (never the library) on scenes it writes itself into
DIR/tmp (the vibrated bed: a scene of scenes/ with --set overrides), sweeps the step size
(fixed-step methods) or the tolerance (adaptive methods) of every method of the testbed,
and records for each run the error, the number of
right-hand-side evaluations (the summary line's rhs_evals) and the wall time of the time
loop (wall_s; for short runs recomputed from steps * particles / particle_steps_per_s,
which the summary prints to six digits, and the least of three repeats).

Methods (docs/integrators.md):
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

Code: this file holds the command line and the driver (main); integrators_curves.py the
methods, curves and the analysis of their rows, integrators_scenes.py the scenes and
their measurement, integrators_report.py the plots and report.md.
"""
import argparse
import os
import shutil
import sys
import time

from common import write_csv
from integrators_curves import curves_full, curves_quick
from integrators_report import plot_scene, write_report
from integrators_scenes import (BUILDERS, CSV_FIELDS, QUICK_SCENES, REPO, Esfera, Scene,
                                esfera_version, run_scene, write_meta)


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
