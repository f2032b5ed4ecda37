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

Code: this file holds the parameters (settings) and the driver (main);
damping_forms.py the closed forms and signal analysis, damping_cases.py the runner and
parts 1-2, damping_compare.py part 3, damping_report.py the plots and report.md.
"""

import argparse
import os
import sys
import time

from damping_cases import (Case, Runner, decay_study, global_alpha, rayleigh_study,
                           restitution_study)
from damping_compare import bed_study, dynamics_study, rayleigh_on_pack, settling_study
from damping_report import (plot_bed, plot_dynamics, plot_part1, plot_rayleigh, plot_settling,
                            write_report)

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def settings(quick, jobs):
    """The study's parameters Q: the full set, or the reduced one of --quick."""
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
    plot_rayleigh(*ray, res, Q)
    pack_ray = rayleigh_on_pack(Q)
    stamp("rayleigh")
    settle = settling_study(R, Q, res)
    plot_settling(*settle, res, Q)
    stamp("settling")
    bounce, chain = dynamics_study(R, Q, res)
    plot_dynamics(bounce, chain, res, Q)
    vib = bed_study(R, Q, res)
    if "runs" in vib:
        plot_bed(vib["runs"], res)
    stamp("dynamics")
    write_report(res, Q, (rest, decay, conv), (ray, pack_ray), (settle, bounce, chain, vib),
                 time.time() - t0)
    stamp(f"report: {os.path.join(res, 'report.md')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
