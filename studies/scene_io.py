"""scene_io.py -- what the studies share to talk to esfera: scenes written as YAML from
Python dicts and lists, and the `summary:` line of `esfera run` read back.

    yaml_flow(value)      a value in YAML flow style ([lists], {maps}, plain scalars:
                          esfera wants `auto`, not "auto")
    to_yaml(scene)        a scene dict: top-level keys in block style, lists of maps one
                          item a line, everything below in flow style
    parse_summary(stdout) the last `summary: k=v ...` line as a dict, numbers as floats
                          ({} when there is none)
"""

import numpy as np


def yaml_flow(v):
    """A value in YAML flow style."""
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


def to_yaml(scene):
    """A scene dict as YAML text."""
    lines = []
    for key, val in scene.items():
        if isinstance(val, list) and val and isinstance(val[0], dict):
            lines.append(f"{key}:")
            lines += [f"  - {yaml_flow(item)}" for item in val]
        elif isinstance(val, dict):
            lines.append(f"{key}:")
            lines += [f"  {k}: {yaml_flow(x)}" for k, x in val.items()]
        else:
            lines.append(f"{key}: {yaml_flow(val)}")
    return "\n".join(lines) + "\n"


def parse_summary(stdout):
    """The last `summary:` line of esfera run's output as a dict."""
    lines = [ln for ln in stdout.strip().splitlines() if ln.startswith("summary:")]
    out = {}
    for tok in (lines[-1].split()[1:] if lines else []):
        k, _, v = tok.partition("=")
        try:
            out[k] = float(v)
        except ValueError:
            out[k] = v
    return out
