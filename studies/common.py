"""common.py -- what the studies share: scenes written as YAML, `esfera run` and its
`summary:` line, results read through esfera_h5.py, one CSV writer and reader, and the
contact closed forms.

    to_yaml(scene), write_scene(path, scene)   scene dicts as YAML (esfera wants `auto`,
                                               not "auto")
    run(esfera, scene, out, sets, timeout)     `esfera run SCENE --out OUT --quiet
                                               --overwrite [--set K=V]...` -> Run
                                               (summary parsed)
    parse_line(stdout, prefix)                 the last `prefix k=v ...` line as a dict
    energy(out), kinetic(e), frames(out), last_frame(out), write_particles_csv(...)
    write_csv(path, rows), read_csv(path)      rows are dicts: column -> value
    tsuji_zeta(eta), cut_impact_closed_form(zeta, omega)
"""

import collections
import csv
import dataclasses
import math
import os
import subprocess
import time

import numpy as np

import esfera_h5

# ------------------------------------------------------------------------ scenes (YAML)


def yaml_flow(v):
    """A value in YAML flow style ([lists], {maps}, plain scalars)."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        return repr(float(v))
    if isinstance(v, dict):
        return "{" + ", ".join(f"{k}: {yaml_flow(x)}" for k, x in v.items()) + "}"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(yaml_flow(x) for x in v) + "]"
    return str(v)


def to_yaml(scene, flow=False):
    """A scene dict as YAML text: top-level keys in block style, lists of maps one item
    a line, everything below in flow style (flow: every top-level value on its line)."""
    lines = []
    for key, val in scene.items():
        if flow:
            lines.append(f"{key}: {yaml_flow(val)}")
        elif isinstance(val, list) and val and isinstance(val[0], dict):
            lines.append(f"{key}:")
            lines += [f"  - {yaml_flow(item)}" for item in val]
        elif isinstance(val, dict):
            lines.append(f"{key}:")
            lines += [f"  {k}: {yaml_flow(x)}" for k, x in val.items()]
        else:
            lines.append(f"{key}: {yaml_flow(val)}")
    return "\n".join(lines) + "\n"


def write_scene(path, scene, comment=None, flow=False):
    """Writes a scene (a dict, or YAML text as it is) to path, under a comment line."""
    text = scene if isinstance(scene, str) else to_yaml(scene, flow)
    with open(path, "w") as fh:
        fh.write((f"# {comment}\n" if comment else "") + text)
    return path


# ------------------------------------------------------------------------ running esfera


@dataclasses.dataclass
class Run:
    """One `esfera run`: returncode None when it timed out; summary is its `summary:`
    line ({} when none)."""
    cmd: list
    out: str
    returncode: object
    stdout: str
    stderr: str
    elapsed: float
    summary: dict

    def check(self, ok=(0,)):
        """self, or RuntimeError when the exit status is not in ok."""
        if self.returncode not in ok:
            raise RuntimeError(f"{' '.join(self.cmd)}: exit {self.returncode}: "
                               f"{self.stderr.strip()}")
        return self


def run(esfera, scene, out, sets=(), timeout=None):
    """Runs `esfera run scene --out out --quiet --overwrite --set s...` (elapsed: wall
    seconds)."""
    cmd = [esfera, "run", scene, "--out", out, "--quiet", "--overwrite"]  # reruns reuse out
    for s in sets:
        cmd += ["--set", s]
    t0 = time.monotonic()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return Run(cmd, out, None, "", "", time.monotonic() - t0, {})
    return Run(cmd, out, p.returncode, p.stdout, p.stderr, time.monotonic() - t0,
               parse_summary(p.stdout))


def parse_line(stdout, prefix):
    """The last line starting with prefix (`summary:`, `modes:`) as a dict of its
    k=v tokens, numbers as floats ({} when there is none)."""
    lines = [ln for ln in stdout.strip().splitlines() if ln.startswith(prefix)]
    out = {}
    for tok in (lines[-1].split()[1:] if lines else []):
        k, _, v = tok.partition("=")
        try:
            out[k] = float(v)
        except ValueError:
            out[k] = v
    return out


def parse_summary(stdout):
    """The last `summary:` line of esfera run's output as a dict."""
    return parse_line(stdout, "summary:")


# ----------------------------------------------------------------------- reading results


def energy(out):
    """OUT/energy.csv as {column: array}: the CSV's rounded values, not frames.h5's
    /energy (the doubles), since the studies' results are computed from the CSV."""
    return esfera_h5.load_energy(os.path.join(out, "energy.csv"))


def kinetic(e):
    """Kinetic energy (translational + rotational) of energy rows."""
    return e["kinetic_translational"] + e["kinetic_rotational"]


def frames(out, select=None):
    """The frames of OUT/frames.h5 (select: frame numbers, negative from the end) as
    esfera_h5.Frame(time, data)."""
    return esfera_h5.load_frames(out, select)


def last_frame(out):
    """The last frame of OUT/frames.h5, an esfera_h5.Frame(time, data)."""
    return esfera_h5.load_frames(out, select=[-1])[0]


def write_particles_csv(path, d, motion=False):
    """A frame's particles as esfera's particle CSV (x, y, z, radius; motion: also the
    velocity and angular velocity), the start state of a scene (particles: file)."""
    cols, head = [d["position"], d["radius"]], "x,y,z,radius"
    if motion:
        cols += [d["velocity"], d["angular_velocity"]]
        head += ",vx,vy,vz,wx,wy,wz"
    np.savetxt(path, np.column_stack(cols), delimiter=",", fmt="%.17g", header=head,
               comments="")


# --------------------------------------------------------------------------------- CSV


def fmt(x, blank=False):
    """A CSV or table cell: floats to 6 digits (blank: non-finite ones as "")."""
    if isinstance(x, (float, np.floating)):
        return "" if blank and not np.isfinite(x) else f"{x:.6g}"
    return "" if x is None else str(x)


def write_csv(path, rows, fields=None, blank=False):
    """Rows (dicts) as CSV, columns fields (default: the first row's keys; other keys
    ignored); nothing is written without rows or fields."""
    fields = fields or (list(rows[0]) if rows else None)
    if not fields:
        return
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(fields)
        w.writerows([fmt(r.get(k), blank) for k in fields] for r in rows)


def read_csv(path):
    """Rows of a CSV as dicts, numbers parsed (int, else float; other cells as text)."""
    def parse(v):
        for kind in (int, float):
            try:
                return kind(v)
            except ValueError:
                pass
        return v
    with open(path, newline="") as fh:
        return [{k: parse(v) for k, v in row.items()} for row in csv.DictReader(fh)]


# ------------------------------------------------------------------------ closed forms


def tsuji_zeta(eta):
    """Damping ratio of the linear dashpot for restitution eta (Tsuji; 004 2.28):
    zeta = -ln eta / sqrt(pi^2 + ln^2 eta), 0 for eta >= 1."""
    if eta >= 1:
        return 0.0
    ln = -math.log(eta)
    return ln / math.sqrt(math.pi**2 + ln**2)


CutImpact = collections.namedtuple("CutImpact", "e t_end t_sep")


def cut_impact_closed_form(zeta, omega=1.0):
    """The linear spring-dashpot impact u'' + 2 zeta w u' + w^2 u = 0 (0 <= zeta < 1)
    with the no-tension cut (tests/simtest.h): the force k u + c u' ends at phase
    th = pi - atan2(2 zeta s, 1 - 2 zeta^2), s = sqrt(1 - zeta^2), at t_end = th/(w s),
    with the restitution e = -exp(-zeta th/s)(cos th - zeta/s sin th); the bodies then
    coast apart at e v0 from the overlap left, which closes at t_sep. Times in 1/omega."""
    s = math.sqrt(1 - zeta * zeta)
    th = math.pi - math.atan2(2 * zeta * s, 1 - 2 * zeta * zeta)
    decay = math.exp(-zeta * th / s)
    t_end = th / (omega * s)
    e = -decay * (math.cos(th) - zeta / s * math.sin(th))
    return CutImpact(e, t_end, t_end + decay * math.sin(th) / (omega * s) / e)
