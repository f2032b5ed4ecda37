"""esfera -- the esfera DEM library from Python (docs/python.md).

    import esfera
    sim = esfera.Sim("scenes/head_on.yaml", set={"integrator.frac": 0.05})
    sim.step(100)                  # the scene's own integrator
    sim.positions, sim.energies    # numpy views, the ledger as a dict

or, on a second Sim, the DEM as an ODE for a solver of your own:

    y = sim.y0(); dy = sim.rhs(sim.time, y); sim.commit(t, y_new)

Built on the C library (esfera.h) with ctypes: no compiled extension. The shared
library is found in this order: $ESFERA_LIB (a file path), the build tree next to this
package (../../build/libesfera.so), the library installed with this package (`meson
install`), then the system's (ctypes.util.find_library).
Errors raise esfera.Error carrying esfera's message (file:line:column for scenes).
"""
import ctypes
import ctypes.util
import os

import numpy as np

__all__ = ["Sim", "Error", "library_path", "version", "ENERGY_COLUMNS", "Q_NAMES"]

_ARRAYS = {"positions": (0, 3), "velocities": (1, 3), "spins": (2, 3), "forces": (3, 3),
           "torques": (4, 3), "radii": (5, 1), "masses": (6, 1), "inertias": (7, 1)}
_CODES = {-1: "bad input", -2: "input/output", -3: "out of memory",
          -4: "numerical failure", -5: "internal error"}


class Error(Exception):
    """A failed esfera call: .code is the status (esfera.h ESF_E*, negative), .message
    esfera's message, located as file:line:column for scene input."""

    def __init__(self, code, message):
        super().__init__(message)
        self.code = code
        self.message = message
        self.kind = _CODES.get(code, "error")


def library_path():
    """The shared library this module loads (see the module's docstring)."""
    env = os.environ.get("ESFERA_LIB")
    if env:
        return env
    here = os.path.dirname(os.path.abspath(__file__))
    local = os.path.join(here, "..", "..", "build", "libesfera.so")
    if os.path.exists(local):
        return os.path.normpath(local)
    try:  # the module `meson install` put beside the installed library
        from . import _installed
        if os.path.exists(_installed.LIBRARY):
            return _installed.LIBRARY
    except ImportError:
        pass
    found = ctypes.util.find_library("esfera")
    if found:
        return found
    raise ImportError("esfera: cannot find libesfera.so: build it (scripts/setup && "
                      "ninja -C build) or set ESFERA_LIB to its path")


def _load():
    lib = ctypes.CDLL(library_path())
    H, D, P, S = ctypes.c_void_p, ctypes.c_double, ctypes.POINTER(ctypes.c_double), \
        ctypes.c_size_t
    sig = {
        "esf_version": (ctypes.c_char_p, []),
        "esf_api_version": (ctypes.c_int, []),
        "esf_handle_open": (ctypes.c_int, [ctypes.POINTER(H), ctypes.c_char_p,
                                           ctypes.POINTER(ctypes.c_char_p), ctypes.c_int]),
        "esf_handle_close": (None, [ctypes.POINTER(H)]),
        "esf_handle_status": (ctypes.c_int, [H]),
        "esf_handle_message": (ctypes.c_char_p, [H]),
        "esf_handle_count": (S, [H]),
        "esf_handle_time": (D, [H]),
        "esf_handle_dt": (D, [H]),
        "esf_handle_steps": (ctypes.c_long, [H]),
        "esf_handle_end_time": (D, [H]),
        "esf_handle_method": (ctypes.c_char_p, [H]),
        "esf_handle_dim": (ctypes.c_int, [H]),
        "esf_handle_set_threads": (ctypes.c_int, [H, ctypes.c_int]),
        "esf_handle_array": (P, [H, ctypes.c_int, ctypes.POINTER(S)]),
        "esf_handle_ids": (ctypes.POINTER(ctypes.c_int64), [H]),
        "esf_energy_column": (ctypes.c_char_p, [ctypes.c_int]),
        "esf_ode_quadrature": (ctypes.c_char_p, [ctypes.c_int]),
        "esf_handle_energies": (ctypes.c_int, [H, P]),
        "esf_handle_step": (ctypes.c_int, [H, ctypes.c_long]),
        "esf_handle_ode_size": (S, [H]),
        "esf_handle_ode_nq": (S, [H]),
        "esf_handle_y0": (ctypes.c_int, [H, P]),
        "esf_handle_rhs": (ctypes.c_int, [H, D, P, P]),
        "esf_handle_commit": (ctypes.c_int, [H, D, P]),
    }
    for name, (res, args) in sig.items():
        f = getattr(lib, name)
        f.restype, f.argtypes = res, args
    return lib


_lib = _load()


def _names(fn):
    """The names fn(0), fn(1), ... up to its first NULL."""
    out = []
    while fn(len(out)) is not None:
        out.append(fn(len(out)).decode())
    return tuple(out)


# The energy row's columns (energy.csv's) and the ODE state's quadratures, as this
# library has them (esfera.h: new ones are added at the end; a scene's y holds the
# first Sim.ode_nq of Q_NAMES: the rolling resistance's only with rolling friction).
ENERGY_COLUMNS = _names(_lib.esf_energy_column)
Q_NAMES = _names(_lib.esf_ode_quadrature)
_NCOLS = len(ENERGY_COLUMNS)


def version():
    """The library's version string."""
    return _lib.esf_version().decode()


def _ptr(a):
    return a.ctypes.data_as(ctypes.POINTER(ctypes.c_double))


def _vector(y, n, what):
    """y as a contiguous float64 array of length n (no copy when it already is)."""
    a = np.ascontiguousarray(y, dtype=np.float64)
    if a.ndim != 1 or a.shape[0] != n:
        raise ValueError(f"esfera: {what}: expected a vector of {n} values, got shape "
                         f"{np.shape(y)}")
    return a


class Sim:
    """One simulation: a scene loaded and set up (esf_handle of esfera.h).

    Sim(scene_path, set={"dotted.key": value, ...}, threads=None) -- overrides as the
    program's --set (values given as Python numbers, strings, or lists, written as YAML
    flow values); threads: worker threads (default all cores; results do not depend on
    it).
    Drive it either with step(k) (the scene's integrator) or as an ODE with y0(), rhs()
    and commit(); the first such call fixes which (Error on mixing: open another Sim).
    """

    def __init__(self, scene_path, set=None, threads=None):
        sets = [f"{k}={_yaml(v)}" for k, v in (set or {}).items()]
        arr = (ctypes.c_char_p * max(len(sets), 1))(*[s.encode() for s in sets])
        self._h = ctypes.c_void_p()
        rc = _lib.esf_handle_open(ctypes.byref(self._h), os.fsencode(scene_path), arr,
                                  len(sets))
        if rc:
            msg = (_lib.esf_handle_message(self._h).decode(errors="replace")
                   if self._h else "out of memory")
            self.close()
            raise Error(rc, msg)
        if threads is not None:
            self._check(_lib.esf_handle_set_threads(self._h, int(threads)))

    def __repr__(self):
        if not self._h:
            return "<esfera.Sim closed>"
        return (f"<esfera.Sim {self.n} particles, {self.method}, t = {self.time:.6g} s, "
                f"{self.steps} steps>")

    # lifetime ---------------------------------------------------------------------
    def close(self):
        """Releases the simulation (also done when the Sim is collected). Arrays taken
        from it must not be used afterwards."""
        if getattr(self, "_h", None):
            _lib.esf_handle_close(ctypes.byref(self._h))
            self._h = None

    def __del__(self):
        self.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _handle(self):
        if not self._h:
            raise Error(-1, "esfera: this Sim is closed")
        return self._h

    def _check(self, rc):
        if rc:
            raise Error(rc, _lib.esf_handle_message(self._h).decode(errors="replace"))

    # scalars ----------------------------------------------------------------------
    n = property(lambda self: int(_lib.esf_handle_count(self._handle())),
                 doc="particle count")
    time = property(lambda self: _lib.esf_handle_time(self._handle()),
                    doc="simulated time, s (of the last step or commit)")
    dt = property(lambda self: _lib.esf_handle_dt(self._handle()),
                  doc="the scene's step, s (the initial one for adaptive methods)")
    steps = property(lambda self: int(_lib.esf_handle_steps(self._handle())),
                     doc="steps taken (or commits)")
    end_time = property(lambda self: _lib.esf_handle_end_time(self._handle()),
                        doc="the scene's end time (run.duration or run.steps x dt), s")
    method = property(lambda self: _lib.esf_handle_method(self._handle()).decode(),
                      doc="the scene's integrator.method")
    dim = property(lambda self: int(_lib.esf_handle_dim(self._handle())),
                   doc="3, or 2 (disks in the x-z plane)")

    # state arrays -----------------------------------------------------------------
    def array(self, name):
        """A read-only numpy view of the library's per-particle array `name` (one of
        positions, velocities, spins, forces, torques: n x 3; radii, masses, inertias:
        n). The view is valid until the next step(), commit() or close(): particles
        leaving the domain are removed and the arrays move. Take .copy() to keep it."""
        which, cols = _ARRAYS[name]
        size = ctypes.c_size_t()
        p = _lib.esf_handle_array(self._handle(), which, ctypes.byref(size))
        if not p or size.value == 0:
            return np.zeros((0, 3) if cols == 3 else (0,))
        buf = (ctypes.c_double * size.value).from_address(ctypes.addressof(p.contents))
        buf.owner = self  # the view keeps the Sim (and its memory) alive
        a = np.frombuffer(buf, dtype=np.float64)
        a.flags.writeable = False
        return a.reshape(-1, 3) if cols == 3 else a

    positions = property(lambda self: self.array("positions"), doc="n x 3, m")
    velocities = property(lambda self: self.array("velocities"),
                          doc="n x 3, m/s (the leapfrog's: at the half step before t)")
    spins = property(lambda self: self.array("spins"), doc="n x 3 angular velocity, rad/s")
    forces = property(lambda self: self.array("forces"),
                      doc="n x 3, N, of the last force evaluation")
    torques = property(lambda self: self.array("torques"), doc="n x 3, N m")
    radii = property(lambda self: self.array("radii"), doc="n, m")
    masses = property(lambda self: self.array("masses"), doc="n, kg")
    inertias = property(lambda self: self.array("inertias"), doc="n, kg m^2")

    @property
    def ids(self):
        """n stable particle identifiers (a copy)."""
        p = _lib.esf_handle_ids(self._handle())
        n = self.n
        return np.ctypeslib.as_array(p, shape=(n,)).copy() if p and n else \
            np.zeros(0, np.int64)

    @property
    def energies(self):
        """The energy ledger now, as a dict of energy.csv's columns (J; time in s,
        alpha_global in 1/s). Needs output.energy_every > 0 in the scene (any value) and
        a first step or ODE call."""
        row = np.zeros(_NCOLS)
        self._check(_lib.esf_handle_energies(self._handle(), _ptr(row)))
        return dict(zip(ENERGY_COLUMNS, row.tolist()))

    # the scene's integrator -------------------------------------------------------
    def step(self, k=1):
        """Takes k steps with the scene's integrator (adaptive methods: k accepted steps,
        not past the scene's end time)."""
        self._check(_lib.esf_handle_step(self._handle(), int(k)))

    def run(self):
        """Runs to the scene's end time (fixed-step methods: whole steps, the last one
        at or past it)."""
        import math
        h = self._handle()
        while _lib.esf_handle_time(h) < self.end_time * (1 - 1e-12):
            left = (self.end_time - self.time) / self.dt
            self.step(max(1, min(10000, math.ceil(left - 1e-9))))

    # the ODE view -----------------------------------------------------------------
    @property
    def ode_size(self):
        """Length of y: 9 n + ode_nq (+ 3 per candidate contact with history as
        state)."""
        m = _lib.esf_handle_ode_size(self._handle())
        if m == 0:
            self._check(_lib.esf_handle_status(self._h) or -5)
        return int(m)

    @property
    def ode_nq(self):
        """The quadratures in this scene's y: the first ode_nq of Q_NAMES (the rolling
        resistance's, dissipated_rolling, only in scenes with rolling friction)."""
        m = _lib.esf_handle_ode_nq(self._handle())
        if m == 0:
            self._check(_lib.esf_handle_status(self._h) or -5)
        return int(m)

    def y0(self):
        """The state to continue from (a new array): y = [x (3n) | v (3n) | w (3n) |
        Q (ode_nq, Q_NAMES) | XI (history as state only)], each vector block particle by
        particle (x0, y0, z0, x1, ...). At the start Q is 0; after a commit it is the
        committed y's."""
        y = np.empty(self.ode_size)
        self._check(_lib.esf_handle_y0(self._h, _ptr(y)))
        return y

    def rhs(self, t, y, out=None):
        """dy/dt at (t, y), the contact histories frozen at the last commit: [v | a |
        dw/dt | powers (W) | dXI/dt]. Writes into `out` when given (float64, contiguous).
        Raises Error on a failure inside (an excessive overlap, a non-finite value)."""
        m = self.ode_size
        y = _vector(y, m, "rhs: y")
        if out is None:
            out = np.empty(m)
        elif not (isinstance(out, np.ndarray) and out.dtype == np.float64 and
                  out.flags.c_contiguous and out.shape == (m,)):
            raise ValueError(f"esfera: rhs: out must be a contiguous float64 vector of {m}")
        self._check(_lib.esf_handle_rhs(self._h, float(t), _ptr(y), _ptr(out)))
        return out

    def commit(self, t, y):
        """Accepts the step to (t, y): commits the contact histories over it, updates
        the ledger and refreshes the contact lists. With history as state continue from
        y0() afterwards (its length may change)."""
        y = _vector(y, self.ode_size, "commit: y")
        self._check(_lib.esf_handle_commit(self._h, float(t), _ptr(y)))

    def split(self, y):
        """The blocks of an ODE vector as views: dict x, v, w (n x 3), q (ode_nq), xi."""
        n, nq = self.n, self.ode_nq
        return {"x": y[:3 * n].reshape(-1, 3), "v": y[3 * n:6 * n].reshape(-1, 3),
                "w": y[6 * n:9 * n].reshape(-1, 3), "q": y[9 * n:9 * n + nq],
                "xi": y[9 * n + nq:]}


def _yaml(v):
    """A Python value as a YAML flow value for --set."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_yaml(x) for x in v) + "]"
    if isinstance(v, float):
        return repr(v)
    return str(v)
