"""Jobs described by TOML files (read with ``tomllib``): a system, an initial set, a data
source (a simulation of the true system, or measured data) and one or more estimators.

::

    title = "EX-BC14"                       # optional
    [system]                                # kind = "linear" (default) or "descriptor"
    A = [[1, 0, 0.2], [0, 0.8, 1], [0, 0, 1]]
    C = [[1, 0, 2], [0, -1, 1]]
    E = [[0.1, 0, 0, 0, 0], [0, 0.05, 0, 0, 0], [0, 0, 0.05, 0, 0]]
    F = [[0, 0, 0, 0.15, 0], [0, 0, 0, 0, 0.15]]
    # B, D: inputs; A_radius: entrywise radius of an interval A (A is then its midpoint).
    # kind = "descriptor": E x⁺ = A x + B u + D w, y = C x + F w (the letters of papers.md §4).

    [initial]                               # the initial set: an ellipsoid E(P, center, rho) …
    center = [0, 0, 0]
    P = "identity"                          # or a matrix
    rho = 1.4142135623730951
    # … or a zonotope (center, generators) or a box (lower, upper)

    [simulation]                            # or [data] file = "y.csv" / "run.npz"
    horizon = 50
    seed = 1
    disturbance = "uniform"                 # uniform | vertex | gaussian | zero
    inputs = ["0.5*sin(t) + 1", "-2*cos(t)"]  # expressions of t (or an N × n_u array)
    time = {start = 0.0, stop = 15.707963267948966}   # t_k = linspace(start, stop, horizon)

    [[estimator]]
    method = "offline"                      # see METHODS
    normalization = "logdet"                # per-method options

Every error is a :class:`ConfigError` (a ``ValueError``) whose message starts with the key
(``system.A``, ``estimator[2].option``…) and says what is wrong.
"""
from __future__ import annotations

import ast
import math
import operator
import time
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .errors import InvalidArgumentError, SetboundError

# method → (family, allowed options with their defaults)
METHODS: dict[str, tuple[str, dict[str, Any]]] = {
    "offline": ("ellipsoidal", {"normalization": "logdet", "beta": None}),
    "online": ("ellipsoidal", {"normalization": "logdet", "beta": None}),
    "scaled": ("ellipsoidal", {"normalization": "logdet", "beta": None}),
    "improved": ("ellipsoidal", {"normalization": "logdet", "beta": None, "option": "det_normalized",
                                 "feedback": "fixed_shape", "predictor": "online"}),
    "descriptor": ("ellipsoidal", {"normalization": "logdet", "beta": None}),
    "kalman": ("kalman", {"omega_cov": None, "cov0": None, "nsigma": 3.0}),
    "segment_min": ("zonotopic", {"max_generators": 20, "use_first_measurement": True}),
    "volume_min": ("zonotopic", {"max_generators": 20, "use_first_measurement": True}),
    "pradius": ("zonotopic", {"max_generators": 20, "use_first_measurement": True, "approach": 1}),
}


class ConfigError(InvalidArgumentError):
    """A job file is invalid; the message starts with the offending key."""


@dataclass
class EstimatorSpec:
    method: str
    name: str
    options: dict[str, Any]


@dataclass
class Job:
    title: str
    system: Any
    initial: Any
    y: np.ndarray | None = None
    u: np.ndarray | None = None
    x_true: np.ndarray | None = None
    t: np.ndarray | None = None
    estimators: list[EstimatorSpec] = field(default_factory=list)
    source: str = ""


# ---------------------------------------------------------------- small validators
def _matrix(v, key, *, ndim=2, shape=None) -> np.ndarray:
    if isinstance(v, str):
        raise ConfigError(f"{key}: expected a numeric {'matrix' if ndim == 2 else 'vector'}, got the string {v!r}")
    try:
        a = np.array(v, dtype=float)
    except (TypeError, ValueError):
        raise ConfigError(f"{key}: expected a numeric {'matrix' if ndim == 2 else 'vector'} "
                          f"(rows of equal length, numbers only)") from None
    if ndim == 2 and a.ndim == 1 and a.size > 0 and shape is not None and shape[0] == 1:
        a = a.reshape(1, -1)
    if ndim == 2 and a.ndim == 0:
        a = a.reshape(1, 1)
    if a.ndim != ndim:
        raise ConfigError(f"{key}: expected a {'matrix (list of rows)' if ndim == 2 else 'vector (list of numbers)'}, "
                          f"got an array of shape {a.shape}")
    if shape is not None:
        for want, got in zip(shape, a.shape):
            if want is not None and want != got:
                raise ConfigError(f"{key}: expected shape {tuple('n' if s is None else s for s in shape)}, got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ConfigError(f"{key}: contains a non-finite value (NaN or inf)")
    return a


def _check_keys(table, allowed, where):
    if not isinstance(table, dict):
        raise ConfigError(f"{where}: expected a table, got {type(table).__name__}")
    for k in table:
        if k not in allowed:
            raise ConfigError(f"{where}.{k}: unknown key (allowed: {', '.join(sorted(allowed))})")


def _require(table, key, where):
    if key not in table:
        raise ConfigError(f"{where}.{key}: missing (required)")
    return table[key]


# ---------------------------------------------------------------- expressions of t
_BINOPS = {ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
           ast.Pow: operator.pow}
_FUNCS = {"sin": np.sin, "cos": np.cos, "tan": np.tan, "exp": np.exp, "sqrt": np.sqrt, "abs": np.abs,
          "log": np.log, "sign": np.sign, "floor": np.floor, "tanh": np.tanh}
_CONSTS = {"pi": math.pi, "e": math.e}


def eval_expression(expr: str, t: np.ndarray, key: str) -> np.ndarray:
    """Evaluates a simple expression of ``t`` (numbers, + − * / **, sin cos tan exp sqrt abs log
    sign floor tanh, pi, e) on the array ``t``; nothing else is allowed."""
    try:
        tree = ast.parse(expr, mode="eval")
    except SyntaxError as exc:
        raise ConfigError(f"{key}: cannot parse the expression {expr!r} ({exc.msg})") from None

    def ev(node):
        if isinstance(node, ast.Expression):
            return ev(node.body)
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)):
            return float(node.value)
        if isinstance(node, ast.Name):
            if node.id == "t":
                return t
            if node.id in _CONSTS:
                return _CONSTS[node.id]
            raise ConfigError(f"{key}: unknown name {node.id!r} in {expr!r} (only t, pi, e)")
        if isinstance(node, ast.BinOp) and type(node.op) in _BINOPS:
            return _BINOPS[type(node.op)](ev(node.left), ev(node.right))
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            v = ev(node.operand)
            return -v if isinstance(node.op, ast.USub) else v
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in _FUNCS \
                and len(node.args) == 1 and not node.keywords:
            return _FUNCS[node.func.id](ev(node.args[0]))
        raise ConfigError(f"{key}: unsupported construct in {expr!r} (numbers, t, + - * / **, "
                          f"{', '.join(sorted(_FUNCS))})")

    with np.errstate(all="ignore"):
        v = np.broadcast_to(np.asarray(ev(tree), dtype=float), t.shape).copy()
    if not np.all(np.isfinite(v)):
        raise ConfigError(f"{key}: the expression {expr!r} is not finite for every t")
    return v


# ---------------------------------------------------------------- sections
def _system(tab):
    from .interval import IntervalMatrix
    from .system import DescriptorSystem, LinearSystem

    kind = tab.get("kind", "linear")
    if kind == "linear":
        _check_keys(tab, {"kind", "A", "A_radius", "B", "C", "D", "E", "F"}, "system")
        A = _matrix(_require(tab, "A", "system"), "system.A")
        n = A.shape[0]
        if A.shape != (n, n):
            raise ConfigError(f"system.A: must be square, got shape {A.shape}")
        C = _matrix(_require(tab, "C", "system"), "system.C", shape=(None, n))
        E = _matrix(_require(tab, "E", "system"), "system.E", shape=(n, None))
        F = _matrix(_require(tab, "F", "system"), "system.F", shape=(C.shape[0], E.shape[1]))
        B = _matrix(tab["B"], "system.B", shape=(n, None)) if "B" in tab else None
        D = _matrix(tab["D"], "system.D", shape=(C.shape[0], B.shape[1] if B is not None else None)) \
            if "D" in tab else None
        if D is not None and B is None:
            raise ConfigError("system.D: given without system.B (there is no input)")
        if "A_radius" in tab:
            rad = _matrix(tab["A_radius"], "system.A_radius", shape=(n, n))
            if np.any(rad < 0):
                raise ConfigError("system.A_radius: entries must be >= 0")
            A = IntervalMatrix.from_mid_rad(A, rad)
        try:
            return LinearSystem(A, C, B=B, D=D, E=E, F=F)
        except SetboundError as exc:
            raise ConfigError(f"system: {exc}") from None
    if kind == "descriptor":
        _check_keys(tab, {"kind", "E", "A", "B", "C", "D", "F"}, "system")
        A = _matrix(_require(tab, "A", "system"), "system.A")
        n = A.shape[0]
        E = _matrix(_require(tab, "E", "system"), "system.E", shape=(n, n))
        C = _matrix(_require(tab, "C", "system"), "system.C", shape=(None, n))
        D = _matrix(_require(tab, "D", "system"), "system.D", shape=(n, None))
        F = _matrix(_require(tab, "F", "system"), "system.F", shape=(C.shape[0], D.shape[1]))
        B = _matrix(tab["B"], "system.B", shape=(n, None)) if "B" in tab else None
        try:
            return DescriptorSystem(E, A, C, B=B, D=D, F=F)
        except SetboundError as exc:
            raise ConfigError(f"system: {exc}") from None
    raise ConfigError(f"system.kind: expected 'linear' or 'descriptor', got {kind!r}")


def _initial(tab, n):
    from .interval import Box
    from .sets import Ellipsoid, Zonotope

    _check_keys(tab, {"center", "P", "rho", "generators", "lower", "upper"}, "initial")
    if "lower" in tab or "upper" in tab:
        lo = _matrix(_require(tab, "lower", "initial"), "initial.lower", ndim=1, shape=(n,))
        hi = _matrix(_require(tab, "upper", "initial"), "initial.upper", ndim=1, shape=(n,))
        if np.any(lo > hi):
            raise ConfigError("initial.lower: must be <= initial.upper componentwise")
        return Box(lo, hi)
    c = _matrix(_require(tab, "center", "initial"), "initial.center", ndim=1, shape=(n,))
    if "generators" in tab:
        G = _matrix(tab["generators"], "initial.generators", shape=(n, None))
        return Zonotope(c, G)
    P = tab.get("P", "identity")
    P = np.eye(n) if P == "identity" else _matrix(P, "initial.P", shape=(n, n))
    rho = _require(tab, "rho", "initial")
    if not isinstance(rho, (int, float)) or isinstance(rho, bool) or not (rho > 0 and math.isfinite(rho)):
        raise ConfigError(f"initial.rho: must be a positive number, got {rho!r}")
    try:
        return Ellipsoid(P, c, float(rho))
    except SetboundError as exc:
        raise ConfigError(f"initial: {exc}") from None


def _inputs(spec, t, nu, key):
    if nu == 0:
        if spec is not None:
            raise ConfigError(f"{key}: the system has no input")
        return None
    if spec is None:
        raise ConfigError(f"{key}: missing (the system has {nu} inputs)")
    if isinstance(spec, list) and spec and all(isinstance(s, str) for s in spec):
        if len(spec) != nu:
            raise ConfigError(f"{key}: expected {nu} expressions (one per input), got {len(spec)}")
        return np.column_stack([eval_expression(s, t, f"{key}[{i}]") for i, s in enumerate(spec)])
    return _matrix(spec, key, shape=(t.shape[0], nu))


def _estimators(lst, system):
    from .system import DescriptorSystem

    if not isinstance(lst, list) or not lst:
        raise ConfigError("estimator: at least one [[estimator]] table is required")
    out, names = [], set()
    for i, tab in enumerate(lst):
        where = f"estimator[{i}]"
        if not isinstance(tab, dict):
            raise ConfigError(f"{where}: expected a table")
        method = _require(tab, "method", where)
        if method not in METHODS:
            raise ConfigError(f"{where}.method: unknown method {method!r} (one of {', '.join(METHODS)})")
        family, defaults = METHODS[method]
        _check_keys(tab, {"method", "name", *defaults}, where)
        if (method == "descriptor") != isinstance(system, DescriptorSystem):
            raise ConfigError(f"{where}.method: {method!r} does not apply to a "
                              f"{'descriptor' if isinstance(system, DescriptorSystem) else 'linear'} system")
        opts = {**defaults, **{k: v for k, v in tab.items() if k in defaults}}
        name = tab.get("name", method)
        if name in names:
            raise ConfigError(f"{where}.name: duplicate estimator name {name!r}")
        names.add(name)
        out.append(EstimatorSpec(method, name, opts))
    return out


def load(path) -> Job:
    """Reads and validates a job file; raises ConfigError naming the key on any problem."""
    path = Path(path)
    try:
        with open(path, "rb") as fh:
            doc = tomllib.load(fh)
    except FileNotFoundError:
        raise ConfigError(f"{path}: no such file") from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: not valid TOML ({exc})") from None
    return from_dict(doc, base=path.parent, source=str(path))


def from_dict(doc: dict, *, base=Path("."), source: str = "") -> Job:
    from .simulation import simulate

    _check_keys(doc, {"title", "system", "initial", "simulation", "data", "estimator"}, "job")
    system = _system(_require(doc, "system", "job"))
    n = system.nx
    initial = _initial(_require(doc, "initial", "job"), n)
    job = Job(title=str(doc.get("title", Path(source).stem or "job")), system=system, initial=initial, source=source)
    if ("simulation" in doc) == ("data" in doc):
        raise ConfigError("job: exactly one of [simulation] and [data] is required")
    if "simulation" in doc:
        sim = doc["simulation"]
        _check_keys(sim, {"horizon", "seed", "disturbance", "inputs", "time", "x0", "A_choice"}, "simulation")
        N = _require(sim, "horizon", "simulation")
        if not isinstance(N, int) or isinstance(N, bool) or N < 1:
            raise ConfigError(f"simulation.horizon: must be a positive integer, got {N!r}")
        tt = sim.get("time", {"start": 0.0, "step": 1.0})
        _check_keys(tt, {"start", "stop", "step"}, "simulation.time")
        start = float(tt.get("start", 0.0))
        if "stop" in tt and "step" in tt:
            raise ConfigError("simulation.time: give either stop or step, not both")
        t = np.linspace(start, float(tt["stop"]), N) if "stop" in tt else start + float(tt.get("step", 1.0)) * np.arange(N)
        u = _inputs(sim.get("inputs"), t, system.nu, "simulation.inputs")
        x0 = sim.get("x0", "sample")
        if x0 != "sample":
            x0 = _matrix(x0, "simulation.x0", ndim=1, shape=(n,))
        kind = sim.get("disturbance", "uniform")
        if kind not in ("uniform", "vertex", "gaussian", "zero"):
            raise ConfigError(f"simulation.disturbance: expected uniform, vertex, gaussian or zero, got {kind!r}")
        seed = sim.get("seed", 0)
        if not isinstance(seed, int) or isinstance(seed, bool):
            raise ConfigError(f"simulation.seed: must be an integer, got {seed!r}")
        try:
            s = simulate(system, initial if isinstance(x0, str) else x0, N, disturbance=kind, rng=seed, u=u,
                         A_choice=sim.get("A_choice", "vertex"))
        except SetboundError as exc:
            raise ConfigError(f"simulation: {exc}") from None
        job.y, job.u, job.x_true, job.t = s.y, (s.u if system.nu else None), s.x, t
    else:
        dat = doc["data"]
        _check_keys(dat, {"file", "y", "u", "x"}, "data")
        f = Path(_require(dat, "file", "data"))
        f = f if f.is_absolute() else base / f
        if not f.exists():
            raise ConfigError(f"data.file: no such file {str(f)!r}")
        if f.suffix == ".npz":
            z = np.load(f)
            arrays = {k: z[k] for k in z.files}
        elif f.suffix == ".csv":
            tab = np.genfromtxt(f, delimiter=",", names=True)
            cols = tab.dtype.names
            arrays = {}
            for prefix in ("y", "u", "x"):
                sel = [c for c in cols if c.startswith(prefix) and c[len(prefix):].isdigit()]
                if sel:
                    arrays[prefix] = np.column_stack([tab[c] for c in sorted(sel, key=lambda c: int(c[len(prefix):]))])
        else:
            raise ConfigError(f"data.file: expected a .csv or .npz file, got {f.suffix!r}")
        if "y" not in arrays:
            raise ConfigError("data.file: no measurements (an array 'y', or CSV columns y0, y1, …)")
        job.y = _matrix(arrays["y"], "data.y", shape=(None, system.ny))
        N = job.y.shape[0]
        job.u = _matrix(arrays["u"], "data.u", shape=(N, system.nu)) if system.nu else None
        if system.nu and "u" not in arrays:
            raise ConfigError(f"data.u: missing (the system has {system.nu} inputs)")
        job.x_true = _matrix(arrays["x"], "data.x", shape=(N, n)) if "x" in arrays else None
        job.t = np.arange(N, dtype=float)
    job.estimators = _estimators(doc.get("estimator"), system)
    return job


# ---------------------------------------------------------------- running
@dataclass
class Result:
    name: str
    method: str
    trajectory: Any
    design_time: float
    step_time: float
    contained: bool | None


def _ellipsoidal_initial(initial, n):
    from .interval import Box
    from .sets import Ellipsoid, Zonotope

    if isinstance(initial, Ellipsoid):
        return initial
    if isinstance(initial, Box):
        # the ellipsoid through the box's corners: Σ (x_i − c_i)² / (n r_i²) ≤ 1
        r = np.maximum(np.asarray(initial.radius, dtype=float), 1e-300)
        return Ellipsoid(np.diag(1.0 / (n * r ** 2)), np.asarray(initial.center, dtype=float), 1.0 + 1e-12)
    if isinstance(initial, Zonotope):
        lo, hi = initial.interval_hull()
        r = np.maximum((hi - lo) / 2, 1e-300)
        return Ellipsoid(np.diag(1.0 / (n * r ** 2)), (hi + lo) / 2, 1.0 + 1e-12)
    raise InvalidArgumentError("initial: unsupported set")


def _zonotopic_initial(initial):
    from .interval import Box
    from .sets import Ellipsoid, Zonotope

    if isinstance(initial, Zonotope):
        return initial
    if isinstance(initial, Box):
        lo, hi = np.asarray(initial.lo, float), np.asarray(initial.hi, float)
        return Zonotope((hi + lo) / 2, np.diag((hi - lo) / 2))
    if isinstance(initial, Ellipsoid):
        lo, hi = initial.bounding_box()
        return Zonotope((hi + lo) / 2, np.diag((hi - lo) / 2))
    raise InvalidArgumentError("initial: unsupported set")


def run_estimator(job: Job, spec: EstimatorSpec) -> Result:
    from . import ellipsoidal as ell
    from . import zonotopic as zono

    o = spec.options
    s = job.system
    n = s.nx
    t0 = time.perf_counter()
    if spec.method in ("offline", "online", "scaled", "improved", "descriptor"):
        design = ell.design_offline(s, normalization=o["normalization"], beta=o["beta"])
        x0 = _ellipsoidal_initial(job.initial, n)
        est = {"offline": lambda: ell.OfflineEstimator(design, x0),
               "online": lambda: ell.OnlineEstimator(design, x0),
               "scaled": lambda: ell.OnlineEstimator(design, x0, scaling=True),
               "improved": lambda: ell.ImprovedEstimator(design, x0, o["option"], feedback=o["feedback"],
                                                         predictor=o["predictor"]),
               "descriptor": lambda: ell.DescriptorEstimator(design, x0)}[spec.method]()
    elif spec.method == "kalman":
        x0 = _ellipsoidal_initial(job.initial, n)
        cov0 = np.linalg.inv(x0.P) * x0.rho / 9.0 if o["cov0"] is None else _matrix(o["cov0"], f"{spec.name}.cov0")
        W = None if o["omega_cov"] is None else _matrix(o["omega_cov"], f"{spec.name}.omega_cov")
        est = ell.KalmanFilter(s, x0.center, cov0, W, nsigma=float(o["nsigma"]))
    else:
        x0 = _zonotopic_initial(job.initial)
        kw = dict(max_generators=int(o["max_generators"]), use_first_measurement=bool(o["use_first_measurement"]))
        if spec.method == "segment_min":
            est = zono.SegmentMinEstimator(s, x0, **kw)
        elif spec.method == "volume_min":
            est = zono.VolumeMinEstimator(s, x0, **kw)
        else:
            est = zono.PRadiusEstimator(zono.design_pradius(s, approach=int(o["approach"])), x0, **kw)
    t1 = time.perf_counter()
    traj = est.run(job.y, job.u)
    t2 = time.perf_counter()
    contained = None
    if job.x_true is not None and traj.guaranteed:
        contained = bool(np.all(traj.contains(job.x_true)))
    return Result(spec.name, spec.method, traj, t1 - t0, (t2 - t1) / max(1, len(job.y)), contained)


def run(job: Job) -> list[Result]:
    return [run_estimator(job, spec) for spec in job.estimators]
