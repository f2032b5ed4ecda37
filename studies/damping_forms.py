"""damping_forms.py -- the damping study's closed forms and signal analysis, without
esfera: the cut impact oscillator (with a body damper), the log decrements of viscous,
local and Rayleigh damping, the apex of a ball under linear drag; and the detectors run on
esfera's series: half-cycle peaks and their decrement, apexes, level crossings, slab solid
fraction, settling time, flights per period. Definitions: studies/damping.py's docstring.
"""
import collections
import math

import numpy as np

G = 9.81


# --- closed forms -----------------------------------------------------------------------


Cut = collections.namedtuple("Cut", "e t_end u_end")


def cut_impact(zeta_c, a=0.0):
    """The cut impact for any contact damping ratio zeta_c and a body damper alpha =
    a omega acting on the relative velocity as well (Rayleigh's mass term): returns
    Cut(e, t_end omega, overlap at t_end x omega / v0). Solved exactly (the closed form
    common.cut_impact_closed_form covers 0 <= zeta_c < 1 without the body damper):
    u'' + (2 zeta_c + a) u' + u = 0 (omega = 1)
    from u = 0, u' = 1, until the contact force u + 2 zeta_c u' returns to zero."""
    zt = zeta_c + a / 2
    root = np.sqrt(complex(zt * zt - 1))
    if abs(root) < 1e-9:
        root = 1e-9  # critical: the limit of the formula below
    lp, lm = -zt + root, -zt - root

    def state(t):
        ep, em = np.exp(lp * t), np.exp(lm * t)
        return ((ep - em) / (lp - lm)).real, ((lp * ep - lm * em) / (lp - lm)).real

    def force(t):
        u, v = state(t)
        return u + 2 * zeta_c * v

    if zeta_c == 0:
        tz = math.pi / abs(root.imag) if zt < 1 else float("inf")
    else:  # first sign change of the force, scanning then bisecting
        t, h, tz = 0.0, 0.01, None
        while t < 200:
            if force(t + h) <= 0:
                lo, hi = t, t + h
                for _ in range(80):
                    mid = 0.5 * (lo + hi)
                    lo, hi = (mid, hi) if force(mid) > 0 else (lo, mid)
                tz = hi
                break
            t += h
        if tz is None:
            return Cut(0.0, float("inf"), 0.0)
    u, v = state(tz)
    return Cut(-v, tz, u)


def viscous_decrement(zeta):
    return 2 * math.pi * zeta / math.sqrt(1 - zeta * zeta) if zeta < 1 else float("inf")


def zeta_from_decrement(delta):
    return delta / math.sqrt(4 * math.pi**2 + delta * delta)


def local_decrement(c):
    """Log decrement of a linear oscillator under Cundall's local damping c."""
    return math.log((1 + c) / (1 - c))


def rayleigh_zeta(zeta_r, f_over_fr):
    """Modal damping ratio of a mode at f under Rayleigh damping with the seed's
    alpha = 2 omega_R zeta_R and beta = 2 zeta_R / omega_R (001 3.59-3.60):
    zeta(f) = (alpha / omega + beta omega) / 2 = zeta_R (f_R / f + f / f_R), which is
    2 zeta_R at f = f_R (each term alone would give zeta_R there)."""
    return zeta_r * (1 / f_over_fr + f_over_fr)


def drag_apex(h, alpha):
    """Apex height after one elastic bounce of a body dropped from h under linear drag
    alpha (global damping): fall z = h - (g/a) t + (g/a^2)(1 - exp(-a t)) to z = 0, then
    rise from the impact speed v to v/a - (g/a^2) ln(1 + a v/g)."""
    a = alpha
    z = lambda t: h - G / a * t + G / a**2 * (1 - math.exp(-a * t))  # noqa: E731
    lo, hi = 0.0, 10 * math.sqrt(2 * h / G) + 10 / a
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if z(mid) > 0 else (lo, mid)
    v = G / a * (1 - math.exp(-a * lo))
    return v / a - G / a**2 * math.log(1 + a * v / G)


# --- measurements -----------------------------------------------------------------------


def half_cycle_peaks(t, x):
    """(times, |peaks|) of x between successive zero crossings, each peak refined by a
    parabola through three samples. The trailing half cycle counts only when it has
    died out (|x| at the end below 1% of its peak: the motion froze at round-off)."""
    sign = np.sign(x)
    cross = np.nonzero(sign[1:] * sign[:-1] < 0)[0] + 1
    bounds = np.concatenate([[0], cross])
    tail = np.abs(x[bounds[-1]:])
    if len(tail) > 2 and tail[-1] < 0.01 * tail.max():
        bounds = np.concatenate([bounds, [len(x)]])
    tp, xp = [], []
    for a, b in zip(bounds[:-1], bounds[1:]):
        k = a + int(np.argmax(np.abs(x[a:b])))
        if 0 < k < len(x) - 1:
            y0, y1, y2 = np.abs(x[k - 1 : k + 2])
            den = y0 - 2 * y1 + y2
            d = 0.5 * (y0 - y2) / den if den != 0 else 0.0
            tp.append(t[k] + d * (t[k + 1] - t[k]))
            xp.append(y1 - 0.25 * (y0 - y2) * d)
        else:
            tp.append(t[k])
            xp.append(abs(x[k]))
    return np.array(tp), np.array(xp)


def decrement_from_peaks(xp, floor):
    """Log decrement per full cycle from the half-cycle peaks above floor (least-squares
    slope of ln|peak| per half cycle, times -2); nan with fewer than two peaks."""
    keep = np.nonzero(xp > floor)[0]
    if len(keep):  # the leading run of consecutive half cycles
        gaps = np.nonzero(np.diff(keep) != 1)[0]
        keep = keep[: gaps[0] + 1] if len(gaps) else keep
    if len(keep) < 2:
        return float("nan"), len(keep)
    slope = np.polyfit(keep, np.log(xp[keep]), 1)[0]
    return -2 * slope, len(keep)


def apex_heights(t, z):
    """Local maxima of z(t) after the start, refined by parabolas: (times, heights)."""
    k = np.nonzero((z[1:-1] > z[:-2]) & (z[1:-1] >= z[2:]))[0] + 1
    tp, zp = [], []
    for i in k:
        y0, y1, y2 = z[i - 1 : i + 2]
        den = y0 - 2 * y1 + y2
        d = 0.5 * (y0 - y2) / den if den != 0 else 0.0
        tp.append(t[i] + d * (t[i + 1] - t[i]))
        zp.append(y1 - 0.25 * (y0 - y2) * d)
    return np.array(tp), np.array(zp)


def cross_time(t, y, level):
    """First time y reaches level (linear interpolation); nan if never."""
    k = np.nonzero(y >= level)[0]
    if len(k) == 0:
        return float("nan")
    i = k[0]
    if i == 0:
        return t[0]
    return t[i - 1] + (level - y[i - 1]) / (y[i] - y[i - 1]) * (t[i] - t[i - 1])


def slab_fraction(z, r, a, b, area):
    """Solid fraction of spheres (centres z, radii r) in the slab a < z < b."""
    lo = np.clip(a - z, -r, r)
    hi = np.clip(b - z, -r, r)
    vol = np.pi * (r * r * (hi - lo) - (hi**3 - lo**3) / 3)
    return vol.sum() / (area * (b - a))


def ke_settle_time(t, ke, thr):
    """First time after which ke stays below thr (nan if it ends above)."""
    above = np.nonzero(ke > thr)[0]
    if len(above) and above[-1] == len(ke) - 1:
        return float("nan")
    return t[above[-1] + 1] if len(above) else t[0]


def flights_per_period(t, h, T):
    """Flights of the bed per driving period: maxima of the lift h(t) standing out by
    more than 30% of the largest lift above the lower of the minima within 0.75 T on
    either side, at least half a period apart."""
    n = max(1, int(0.75 * T / (t[1] - t[0])))
    k = np.nonzero((h[1:-1] >= h[:-2]) & (h[1:-1] > h[2:]))[0] + 1
    peaks = []
    for i in k:
        prom = h[i] - max(h[max(0, i - n):i].min(), h[i + 1:i + n + 1].min())
        if prom > 0.3 * h.max():
            if peaks and t[i] - t[peaks[-1]] < 0.5 * T:
                if h[i] > h[peaks[-1]]:
                    peaks[-1] = i
            else:
                peaks.append(i)
    return len(peaks) / ((t[-1] - t[0]) / T)
