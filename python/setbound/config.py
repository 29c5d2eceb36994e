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
    # omega = {lower = [...], upper = [...]} or {center = [...], generators = [[...]]}: explicit
    # bounds of ω instead of the unit box (converted: ω = c + G ξ, ξ in the unit box; an offset
    # c becomes an input column that is always 1, appended after the user's inputs).
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
    method = "offline"                      # a registered estimator kind (ESTIMATORS)
    normalization = "logdet"                # per-method options
    name = "offline-logdet"                 # optional, unique; default: the method

    [plots]                                 # optional: what `setbound run` draws
    reference = "offline"                   # widths relative to this estimator (default: the first guaranteed one)
    steps = [0, 10, 49]                     # steps of the 2-D projections (default: first, middle, last)
    dims = [0, 1]                           # state components of the projections
    enabled = true                          # false: no PNG files

Registry
--------
The estimator kinds and system kinds a job file may name live in two registries, so a new
method or model is added in one place:

* ``register_system(kind, keys, build, cls)`` — ``[system] kind = "..."``: ``keys`` are the
  allowed keys (besides ``kind``), ``build(table)`` validates the table and returns the system
  object (raise :class:`ConfigError` naming ``system.<key>``), ``cls`` its Python type (used to
  decide which estimators apply). Registered: ``linear`` (:class:`~setbound.LinearSystem`) and
  ``descriptor`` (:class:`~setbound.DescriptorSystem`).
* ``register_estimator(method, family, options, build, systems=("linear",), ...)`` — ``method``
  is the name used in ``[[estimator]] method = "..."``, ``options`` the allowed options with
  their defaults, ``systems`` the system kinds it applies to, and ``build(job, options)`` returns
  ``(estimator, design)``: an object with ``run(y, u) -> Trajectory`` and the offline design
  (or ``None``). ``steady_volume(design, trajectory)`` optionally gives the steady-state volume
  of the method (the ellipsoidal designs' ``volume_inf``); otherwise the summary reports the
  final volume. Registered: ``offline``, ``online``, ``scaled``, ``improved``, ``descriptor``
  (ellipsoidal), ``segment_min``, ``volume_min``, ``pradius`` (zonotopic), ``kalman``.

The thesis kinds (system kinds ``thesis``, ``lpv``, ``nonlinear``; estimators
``interval_luenberger``, ``interval_invariant``, ``nonlinear_interval``, ``ellipsoidal_sm``,
``lpv_sm``, ``invariant_tube``) live in :mod:`setbound.thesis_jobs`, imported at the end of this
module. A system object may bring its own simulation (``simulate_job``, plus extra
``[simulation]`` keys in ``simulation_keys``) and per-step data for its estimators
(``job.extra``, e.g. the LPV scheduling signal); :func:`compile_expression` evaluates the
whitelisted expressions with extra variables (``k``, the state ``x1 … xn``, a parameter ``p``).

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
from typing import Any, Callable

import numpy as np

from .errors import InvalidArgumentError, SetboundError
from .system import DescriptorSystem, LinearSystem

class ConfigError(InvalidArgumentError):
    """A job file is invalid; the message starts with the offending key."""


@dataclass(frozen=True)
class BuiltSystem:
    """What a system kind's ``build`` may return instead of the bare system: the system and
    ``constant_input`` — True when the conversion appended an input column that is always 1 (the
    offset of non-centred disturbance bounds); jobs then append that column to the inputs."""

    system: Any
    constant_input: bool = False


@dataclass(frozen=True)
class SystemKind:
    """A registered ``[system] kind``: allowed ``keys``, ``build(table) -> system``, the Python ``cls``."""

    kind: str
    keys: frozenset
    build: Callable[[dict], Any]
    cls: type
    description: str = ""


@dataclass(frozen=True)
class EstimatorKind:
    """A registered ``[[estimator]] method``: see the module docstring (Registry)."""

    method: str
    family: str
    options: dict[str, Any]
    build: Callable[["Job", dict], tuple[Any, Any]]
    systems: tuple[str, ...] = ("linear",)
    guaranteed: bool = True
    steady_volume: Callable[[Any, Any], float] | None = None
    description: str = ""
    checks: dict[str, tuple[Callable[[Any], bool], str]] = field(default_factory=dict)


#: Registered system kinds, ``kind -> SystemKind``.
SYSTEMS: dict[str, SystemKind] = {}
#: Registered estimator kinds, ``method -> EstimatorKind``.
ESTIMATORS: dict[str, EstimatorKind] = {}
#: ``method -> (family, allowed options with defaults)``: a view of :data:`ESTIMATORS` kept in step
#: by :func:`register_estimator` (the older name of the table).
METHODS: dict[str, tuple[str, dict[str, Any]]] = {}


def register_system(kind: str, keys, build: Callable[[dict], Any], cls: type, *, description: str = "",
                    replace: bool = False) -> SystemKind:
    """Adds a system kind usable as ``[system] kind = "<kind>"`` (see the module docstring)."""
    if kind in SYSTEMS and not replace:
        raise ValueError(f"kind: the system kind {kind!r} is already registered (replace=True to override)")
    entry = SystemKind(kind, frozenset(keys) | {"kind"}, build, cls, description)
    SYSTEMS[kind] = entry
    return entry


def register_estimator(method: str, family: str, options: dict[str, Any], build, *, systems=("linear",),
                       guaranteed: bool = True, steady_volume=None, description: str = "", checks=None,
                       replace: bool = False) -> EstimatorKind:
    """Adds an estimator kind usable as ``[[estimator]] method = "<method>"`` (see the module
    docstring). ``options`` must not contain ``method`` or ``name``. ``checks`` maps an option to
    ``(predicate, what it must be)``: values given in a job file are validated when it is loaded."""
    if method in ESTIMATORS and not replace:
        raise ValueError(f"method: the estimator {method!r} is already registered (replace=True to override)")
    bad = {"method", "name"} & set(options)
    if bad:
        raise ValueError(f"options: {', '.join(sorted(bad))} is reserved")
    entry = EstimatorKind(method, family, dict(options), build, tuple(systems), guaranteed, steady_volume,
                          description, dict(checks or {}))
    ESTIMATORS[method] = entry
    METHODS[method] = (family, entry.options)
    return entry


def system_kind_of(system) -> str:
    """The registered kind of a system object (the most specific registered class)."""
    for kind, entry in SYSTEMS.items():
        if type(system) is entry.cls:
            return kind
    for kind, entry in SYSTEMS.items():
        if isinstance(system, entry.cls):
            return kind
    raise ConfigError(f"system: {type(system).__name__} is not a registered system kind "
                      f"({', '.join(SYSTEMS)})")


@dataclass
class EstimatorSpec:
    """One ``[[estimator]]`` table: the registered ``method``, a unique ``name`` and its options."""

    method: str
    name: str
    options: dict[str, Any]


@dataclass
class PlotSpec:
    """The ``[plots]`` table: ``reference`` estimator name for relative widths (None: the first
    guaranteed), projection ``steps`` (None: first, middle, last), projection ``dims``, ``enabled``."""

    reference: str | None = None
    steps: list[int] | None = None
    dims: tuple[int, int] = (0, 1)
    enabled: bool = True


@dataclass
class Job:
    """A validated job: the system and initial set, the data (``y``, ``u``, ``x_true`` when known,
    time values ``t``), the estimators to run and the plot options."""

    title: str
    system: Any
    initial: Any
    y: np.ndarray | None = None
    u: np.ndarray | None = None
    x_true: np.ndarray | None = None
    t: np.ndarray | None = None
    estimators: list[EstimatorSpec] = field(default_factory=list)
    source: str = ""
    plots: PlotSpec = field(default_factory=PlotSpec)
    system_kind: str = "linear"
    #: True when ``[system.omega]`` had an offset: the last column of ``u`` is then the constant 1
    constant_input: bool = False
    #: per-step data besides y/u from a system kind's own simulation (e.g. ``"rho"``: the LPV
    #: scheduling signal, N × n_ρ), or from a data file
    extra: dict = field(default_factory=dict)
    #: offline designs used by the estimators of the job (key -> (design, seconds to compute))
    designs: dict = field(default_factory=dict, repr=False)

    def cached_design(self, key, make):
        """``make()`` once per ``key`` and system: estimators with the same design options share
        the design, also across jobs of one process with an identical system (``setbound compare``,
        tests). Returns ``(design, seconds it took to compute)``."""
        full = (_fingerprint(self.system), key)
        if full not in _DESIGN_CACHE:
            t0 = time.perf_counter()
            d = make()
            if len(_DESIGN_CACHE) >= 32:
                _DESIGN_CACHE.pop(next(iter(_DESIGN_CACHE)))
            _DESIGN_CACHE[full] = (d, time.perf_counter() - t0)
        self.designs[key] = _DESIGN_CACHE[full]
        return self.designs[key]


# Offline designs depend only on the system and the design options: a small process-wide cache.
_DESIGN_CACHE: dict = {}


def _fingerprint(system) -> tuple:
    if hasattr(system, "fingerprint"):  # a system kind with more data than the matrices below
        return (type(system).__qualname__, system.fingerprint())
    parts = [type(system).__qualname__]
    for name in ("E", "A", "A_rad", "B", "C", "D", "F"):
        a = getattr(system, name, None)
        if isinstance(a, np.ndarray):
            parts.append((name, a.shape, a.tobytes()))
    return tuple(parts)


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


def compile_expression(expr: str, key: str, names=("t",)) -> Callable[[dict], Any]:
    """Parses a simple expression once and returns ``f(env)`` evaluating it with the variables of
    ``env`` (a dict name -> number or array). Allowed: numbers, the variables ``names``, + − * /
    **, sin cos tan exp sqrt abs log sign floor tanh, pi, e; nothing else (an AST whitelist, no
    attribute access, no other calls). Errors are :class:`ConfigError` naming ``key``."""
    if not isinstance(expr, str):
        raise ConfigError(f"{key}: expected an expression (a string), got {expr!r}")
    try:
        tree = ast.parse(expr, mode="eval")
    except SyntaxError as exc:
        raise ConfigError(f"{key}: cannot parse the expression {expr!r} ({exc.msg})") from None
    allowed = tuple(names)

    def check(node):  # validate once, so evaluation cannot meet an unsupported construct
        if isinstance(node, ast.Expression):
            return check(node.body)
        if isinstance(node, ast.Constant) and isinstance(node.value, (int, float)) and not isinstance(node.value, bool):
            return
        if isinstance(node, ast.Name):
            if node.id in allowed or node.id in _CONSTS:
                return
            raise ConfigError(f"{key}: unknown name {node.id!r} in {expr!r} (only {', '.join(allowed)}, pi, e)")
        if isinstance(node, ast.BinOp) and type(node.op) in _BINOPS:
            check(node.left)
            return check(node.right)
        if isinstance(node, ast.UnaryOp) and isinstance(node.op, (ast.USub, ast.UAdd)):
            return check(node.operand)
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id in _FUNCS \
                and len(node.args) == 1 and not node.keywords:
            return check(node.args[0])
        raise ConfigError(f"{key}: unsupported construct in {expr!r} (numbers, {', '.join(allowed)}, + - * / **, "
                          f"{', '.join(sorted(_FUNCS))})")

    check(tree)

    def ev(node, env):
        if isinstance(node, ast.Expression):
            return ev(node.body, env)
        if isinstance(node, ast.Constant):
            return float(node.value)
        if isinstance(node, ast.Name):
            return env[node.id] if node.id in allowed else _CONSTS[node.id]
        if isinstance(node, ast.BinOp):
            return _BINOPS[type(node.op)](ev(node.left, env), ev(node.right, env))
        if isinstance(node, ast.UnaryOp):
            v = ev(node.operand, env)
            return -v if isinstance(node.op, ast.USub) else v
        return _FUNCS[node.func.id](ev(node.args[0], env))

    def f(env):
        with np.errstate(all="ignore"):
            return ev(tree, env)
    f.names = frozenset(n.id for n in ast.walk(tree) if isinstance(n, ast.Name) and n.id in allowed)
    return f


def eval_expression(expr: str, t: np.ndarray, key: str) -> np.ndarray:
    """Evaluates a simple expression of ``t`` (numbers, + − * / **, sin cos tan exp sqrt abs log
    sign floor tanh, pi, e) on the array ``t``; nothing else is allowed."""
    f = compile_expression(expr, key, ("t",))
    v = np.broadcast_to(np.asarray(f({"t": t}), dtype=float), t.shape).copy()
    if not np.all(np.isfinite(v)):
        raise ConfigError(f"{key}: the expression {expr!r} is not finite for every t")
    return v


# ---------------------------------------------------------------- sections
def _linear_system(tab):
    from .interval import IntervalMatrix
    from .system import LinearSystem

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
    constant_input = False
    if "omega" in tab:
        E, F, offset = _omega_bounds(tab["omega"], E.shape[1], E, F)
        if np.any(offset[0] != 0) or np.any(offset[1] != 0):
            # ω = c + G ξ with c ≠ 0: E c and F c enter as an input column that is always 1
            constant_input = True
            B = np.hstack([B if B is not None else np.zeros((n, 0)), offset[0][:, None]])
            D = np.hstack([D if D is not None else np.zeros((C.shape[0], B.shape[1] - 1)), offset[1][:, None]])
    try:
        system = LinearSystem(A, C, B=B, D=D, E=E, F=F)
    except SetboundError as exc:
        raise ConfigError(f"system: {exc}") from None
    return BuiltSystem(system, constant_input) if constant_input else system


def _omega_bounds(tab, nw: int, E, F):
    """``[system.omega]``: explicit bounds of ω instead of the unit box — a box (``lower``,
    ``upper``) or a zonotope (``center``, ``generators``, nω × m). With ω = c + G ξ, ξ in the unit
    box, the model becomes ``E G``, ``F G`` and the offsets ``E c``, ``F c``."""
    where = "system.omega"
    _check_keys(tab, {"lower", "upper", "center", "generators"}, where)
    if "lower" in tab or "upper" in tab:
        if "center" in tab or "generators" in tab:
            raise ConfigError(f"{where}: give a box (lower, upper) or a zonotope (center, generators), not both")
        lo = _matrix(_require(tab, "lower", where), f"{where}.lower", ndim=1, shape=(nw,))
        hi = _matrix(_require(tab, "upper", where), f"{where}.upper", ndim=1, shape=(nw,))
        if np.any(lo > hi):
            k = int(np.flatnonzero(lo > hi)[0])
            raise ConfigError(f"{where}.lower: entry {k} is above {where}.upper")
        c, G = (lo + hi) / 2, np.diag((hi - lo) / 2)
    else:
        c = _matrix(_require(tab, "center", where), f"{where}.center", ndim=1, shape=(nw,))
        G = _matrix(_require(tab, "generators", where), f"{where}.generators", shape=(nw, None))
    keep = np.any(G != 0, axis=0)  # drop zero generators (a fixed component of ω)
    G = G[:, keep] if np.any(keep) else np.zeros((nw, 1))
    return E @ G, F @ G, (E @ c, F @ c)


def _descriptor_system(tab):
    from .system import DescriptorSystem

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


def _system(tab):
    if not isinstance(tab, dict):
        raise ConfigError(f"system: expected a table, got {type(tab).__name__}")
    kind = tab.get("kind", "linear")
    if not isinstance(kind, str) or kind not in SYSTEMS:
        raise ConfigError(f"system.kind: expected one of {', '.join(map(repr, SYSTEMS))}, got {kind!r}")
    entry = SYSTEMS[kind]
    _check_keys(tab, entry.keys, "system")
    built = entry.build(tab)
    if isinstance(built, BuiltSystem):
        return kind, built.system, built.constant_input
    return kind, built, False


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


def _estimators(lst, system_kind: str):
    if not isinstance(lst, list) or not lst:
        raise ConfigError("estimator: at least one [[estimator]] table is required")
    out, names = [], set()
    for i, tab in enumerate(lst):
        where = f"estimator[{i}]"
        if not isinstance(tab, dict):
            raise ConfigError(f"{where}: expected a table")
        method = _require(tab, "method", where)
        if not isinstance(method, str) or method not in ESTIMATORS:
            raise ConfigError(f"{where}.method: unknown method {method!r} (one of {', '.join(ESTIMATORS)})")
        kind = ESTIMATORS[method]
        _check_keys(tab, {"method", "name", *kind.options}, where)
        if system_kind not in kind.systems:
            raise ConfigError(f"{where}.method: {method!r} does not apply to a {system_kind} system "
                              f"(it applies to: {', '.join(kind.systems)})")
        for k, v in tab.items():
            if k in kind.checks and not kind.checks[k][0](v):
                raise ConfigError(f"{where}.{k}: must be {kind.checks[k][1]}, got {v!r}")
        opts = {**kind.options, **{k: v for k, v in tab.items() if k in kind.options}}
        name = tab.get("name", method)
        if not isinstance(name, str) or not name or any(ch in name for ch in "/\\:*?\"<>|") or name.startswith("."):
            raise ConfigError(f"{where}.name: must be a non-empty string usable as a file name, got {name!r}")
        if name in names:
            raise ConfigError(f"{where}.name: duplicate estimator name {name!r}")
        names.add(name)
        out.append(EstimatorSpec(method, name, opts))
    return out


def _plots(tab, n: int, N: int, names: list[str]) -> PlotSpec:
    _check_keys(tab, {"reference", "steps", "dims", "enabled"}, "plots")
    spec = PlotSpec()
    if "enabled" in tab:
        if not isinstance(tab["enabled"], bool):
            raise ConfigError(f"plots.enabled: must be true or false, got {tab['enabled']!r}")
        spec.enabled = tab["enabled"]
    if "reference" in tab:
        if tab["reference"] not in names:
            raise ConfigError(f"plots.reference: {tab['reference']!r} is not the name of an estimator of this job "
                              f"({', '.join(names)})")
        spec.reference = tab["reference"]
    if "steps" in tab:
        st = tab["steps"]
        if not isinstance(st, list) or not st or not all(isinstance(k, int) and not isinstance(k, bool) for k in st):
            raise ConfigError(f"plots.steps: expected a non-empty list of integers, got {st!r}")
        bad = [k for k in st if not 0 <= k < N]
        if bad:
            raise ConfigError(f"plots.steps: step {bad[0]} out of range 0..{N - 1}")
        spec.steps = list(st)
    if "dims" in tab:
        d = tab["dims"]
        if not (isinstance(d, list) and len(d) == 2 and all(isinstance(i, int) and not isinstance(i, bool) for i in d)
                and d[0] != d[1] and all(0 <= i < n for i in d)):
            raise ConfigError(f"plots.dims: expected two distinct state indices in 0..{n - 1}, got {d!r}")
        spec.dims = (d[0], d[1])
    return spec


def _with_constant(u, N: int, constant_input: bool):
    if not constant_input:
        return u
    return np.hstack([u if u is not None else np.zeros((N, 0)), np.ones((N, 1))])


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
    """Validates a parsed job (the dictionary of a TOML file); relative data files are looked up
    under ``base``. Raises ConfigError naming the key on any problem."""
    from .simulation import simulate

    _check_keys(doc, {"title", "system", "initial", "simulation", "data", "estimator", "plots"}, "job")
    system_kind, system, constant_input = _system(_require(doc, "system", "job"))
    nu = system.nu - (1 if constant_input else 0)  # the inputs the user gives
    n = system.nx
    initial = _initial(_require(doc, "initial", "job"), n)
    job = Job(title=str(doc.get("title", Path(source).stem or "job")), system=system, initial=initial, source=source,
              system_kind=system_kind, constant_input=constant_input)
    if ("simulation" in doc) == ("data" in doc):
        raise ConfigError("job: exactly one of [simulation] and [data] is required")
    if "simulation" in doc:
        sim = doc["simulation"]
        custom = getattr(system, "simulate_job", None)  # a system kind with its own simulation (thesis_jobs)
        _check_keys(sim, {"horizon", "seed", "disturbance", "inputs", "time", "x0", "A_choice",
                          *getattr(system, "simulation_keys", ())}, "simulation")
        N = _require(sim, "horizon", "simulation")
        if not isinstance(N, int) or isinstance(N, bool) or N < 1:
            raise ConfigError(f"simulation.horizon: must be a positive integer, got {N!r}")
        tt = sim.get("time", {"start": 0.0, "step": 1.0})
        _check_keys(tt, {"start", "stop", "step"}, "simulation.time")
        start = float(tt.get("start", 0.0))
        if "stop" in tt and "step" in tt:
            raise ConfigError("simulation.time: give either stop or step, not both")
        t = np.linspace(start, float(tt["stop"]), N) if "stop" in tt else start + float(tt.get("step", 1.0)) * np.arange(N)
        u = _with_constant(_inputs(sim.get("inputs"), t, nu, "simulation.inputs"), N, constant_input)
        x0 = sim.get("x0", "sample")
        if x0 != "sample":
            x0 = _matrix(x0, "simulation.x0", ndim=1, shape=(n,))
        kind = sim.get("disturbance", "uniform")
        seed = sim.get("seed", 0)
        if not isinstance(seed, int) or isinstance(seed, bool):
            raise ConfigError(f"simulation.seed: must be an integer, got {seed!r}")
        if custom is not None:
            # x_true, y and the extra per-step data (e.g. the LPV scheduling signal) from the system
            s = custom(sim, initial, N, t, u, x0, seed)
            job.y, job.u, job.x_true, job.t = s.y, (s.u if system.nu else None), s.x, t
            job.extra = dict(getattr(s, "extra", {}) or {})
            job.estimators = _estimators(doc.get("estimator"), system_kind)
            job.plots = _plots(doc.get("plots", {}), n, len(job.y), [e.name for e in job.estimators])
            return job
        if kind not in ("uniform", "vertex", "gaussian", "zero"):
            raise ConfigError(f"simulation.disturbance: expected uniform, vertex, gaussian or zero, got {kind!r}")
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
        if nu and "u" not in arrays:
            raise ConfigError(f"data.u: missing (the system has {nu} inputs)")
        job.u = _with_constant(_matrix(arrays["u"], "data.u", shape=(N, nu)) if nu else None, N, constant_input)
        job.x_true = _matrix(arrays["x"], "data.x", shape=(N, n)) if "x" in arrays else None
        job.t = np.arange(N, dtype=float)
    job.estimators = _estimators(doc.get("estimator"), system_kind)
    job.plots = _plots(doc.get("plots", {}), n, len(job.y), [e.name for e in job.estimators])
    return job


# ---------------------------------------------------------------- running
@dataclass
class Result:
    """The outcome of one estimator on a job: its ``trajectory`` (None when it failed, then
    ``error`` says why, e.g. an infeasible design), the offline ``design`` (or None), timings in
    seconds, ``contained`` (was the true state inside at every step; None when unknown or not
    guaranteed) and ``steady_volume`` with ``steady_volume_kind`` (``"rho_inf"``: the design's
    steady-state volume, ``"final"``: the volume of the last set, ``""``: none)."""

    name: str
    method: str
    trajectory: Any
    design_time: float
    step_time: float
    contained: bool | None
    design: Any = None
    error: str | None = None
    steady_volume: float = float("nan")
    steady_volume_kind: str = ""

    @property
    def ok(self) -> bool:
        """True when the estimator ran (no design or run error)."""
        return self.error is None


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


# ---------------------------------------------------------------- the registered kinds
def _build_ellipsoidal(method):
    def build(job: Job, o: dict):
        from . import ellipsoidal as ell

        design, _ = job.cached_design(("ellipsoidal", o["normalization"], o["beta"]),
                                      lambda: ell.design_offline(job.system, normalization=o["normalization"],
                                                                 beta=o["beta"]))
        x0 = _ellipsoidal_initial(job.initial, job.system.nx)
        if method == "offline":
            est = ell.OfflineEstimator(design, x0)
        elif method == "online":
            est = ell.OnlineEstimator(design, x0)
        elif method == "scaled":
            est = ell.OnlineEstimator(design, x0, scaling=True)
        elif method == "improved":
            est = ell.ImprovedEstimator(design, x0, o["option"], feedback=o["feedback"], predictor=o["predictor"])
        else:
            est = ell.DescriptorEstimator(design, x0)
        return est, design
    return build


def _build_kalman(job: Job, o: dict):
    from . import ellipsoidal as ell

    x0 = _ellipsoidal_initial(job.initial, job.system.nx)
    cov0 = np.linalg.inv(x0.P) * x0.rho / 9.0 if o["cov0"] is None else _matrix(o["cov0"], "cov0")
    W = None if o["omega_cov"] is None else _matrix(o["omega_cov"], "omega_cov")
    return ell.KalmanFilter(job.system, x0.center, cov0, W, nsigma=float(o["nsigma"])), None


def _build_zonotopic(method):
    def build(job: Job, o: dict):
        from . import zonotopic as zono

        x0 = _zonotopic_initial(job.initial)
        kw = dict(max_generators=int(o["max_generators"]), use_first_measurement=bool(o["use_first_measurement"]),
                  reduction=str(o["reduction"]))
        if method == "segment_min":
            return zono.SegmentMinEstimator(job.system, x0, **kw), None
        if method == "volume_min":
            return zono.VolumeMinEstimator(job.system, x0, **kw), None
        design, _ = job.cached_design(("pradius", int(o["approach"])),
                                      lambda: zono.design_pradius(job.system, approach=int(o["approach"])))
        return zono.PRadiusEstimator(design, x0, **kw), design
    return build


def _rho_inf_volume(design, trajectory) -> float:
    return float(design.volume_inf)


_ELL = {"normalization": "logdet", "beta": None}
_ZONO = {"max_generators": 20, "use_first_measurement": True, "reduction": "combastel"}


def _one_of(*values):
    return (lambda v: isinstance(v, str) and v in values), "one of " + ", ".join(map(repr, values))


def _is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


_POS_INT = ((lambda v: isinstance(v, int) and not isinstance(v, bool) and v >= 1), "a positive integer")
_BOOL = ((lambda v: isinstance(v, bool)), "true or false")
_ELL_CHECKS = {"normalization": _one_of("logdet", "ball", "paper_trace"),
               "beta": ((lambda v: _is_number(v) and 0 < v < 1), "a number in (0, 1)")}
_ZONO_CHECKS = {"max_generators": _POS_INT, "use_first_measurement": _BOOL,
                "reduction": _one_of("combastel", "girard", "pca")}
register_system("linear", {"A", "A_radius", "B", "C", "D", "E", "F", "omega"}, _linear_system, LinearSystem,
                description="x+ = A x + B u + E w, y = C x + D u + F w (A may be an interval matrix; "
                            "w in the unit box or in the [system.omega] box/zonotope)")
register_system("descriptor", {"E", "A", "B", "C", "D", "F"}, _descriptor_system, DescriptorSystem,
                description="E x+ = A x + B u + D w, y = C x + F w (papers.md §4)")
register_estimator("offline", "ellipsoidal", _ELL, _build_ellipsoidal("offline"), steady_volume=_rho_inf_volume,
                   checks=_ELL_CHECKS,
                   description="[BenChabane2014] offline gain (papers.md §1.1)")
register_estimator("online", "ellipsoidal", _ELL, _build_ellipsoidal("online"), checks=_ELL_CHECKS,
                   description="[BenChabane2014] online LMI per step (papers.md §1.2)")
register_estimator("scaled", "ellipsoidal", _ELL, _build_ellipsoidal("scaled"), checks=_ELL_CHECKS,
                   description="[BenChabane2014] online with scaling (papers.md §1.3)")
register_estimator("improved", "ellipsoidal",
                   {**_ELL, "option": "det_normalized", "feedback": "fixed_shape", "predictor": "online"},
                   _build_ellipsoidal("improved"),
                   checks={**_ELL_CHECKS, "option": _one_of("det_normalized", "fixed_shape", "ball_normalized"),
                           "feedback": _one_of("fixed_shape", "outer_bound", "none"),
                           "predictor": _one_of("online", "scaled", "offline")},
                   description="[Merhy2017] improved measurement correction (papers.md §2.2, §6)")
register_estimator("descriptor", "ellipsoidal", _ELL, _build_ellipsoidal("descriptor"), systems=("descriptor",),
                   steady_volume=_rho_inf_volume, checks=_ELL_CHECKS, description="[Merhy2019] descriptor systems (papers.md §4.1)")
register_estimator("kalman", "kalman", {"omega_cov": None, "cov0": None, "nsigma": 3.0}, _build_kalman,
                   guaranteed=False, checks={"nsigma": ((lambda v: _is_number(v) and v > 0), "a positive number")},
                   description="Kalman filter contrast, mean ± nsigma·σ (papers.md §2.3)")
register_estimator("segment_min", "zonotopic", _ZONO, _build_zonotopic("segment_min"), checks=_ZONO_CHECKS,
                   description="[Alamo2005] segment minimisation (papers.md §5.1)")
register_estimator("volume_min", "zonotopic", _ZONO, _build_zonotopic("volume_min"), checks=_ZONO_CHECKS,
                   description="[Alamo2005] volume minimisation (papers.md §5.2)")
register_estimator("pradius", "zonotopic", {**_ZONO, "approach": 1}, _build_zonotopic("pradius"),
                   checks={**_ZONO_CHECKS, "approach": ((lambda v: v in (1, 2) and not isinstance(v, bool)), "1 or 2")},
                   description="[Le2013] offline P-radius gains (papers.md §3.2, §3.3)")


def _concat(parts):
    from .trajectory import Trajectory

    if len(parts) == 1:
        return parts[0]
    t = Trajectory(np.vstack([p.center for p in parts]), np.vstack([p.lower for p in parts]),
                   np.vstack([p.upper for p in parts]), [s for p in parts for s in p.sets],
                   guaranteed=all(p.guaranteed for p in parts))
    if all(hasattr(p, "covariance") for p in parts):
        t.covariance = np.concatenate([p.covariance for p in parts])
    return t


def run_trajectory(estimator, y, u=None, *, label: str = "", quiet: bool = False, chunk: int | None = None):
    """``estimator.run(y, u)`` with a progress bar (see :mod:`setbound.progress`) when stderr is a
    terminal: then in chunks (``chunk`` rows, default N/50). Every estimator's ``run`` continues
    from its current state, so the chunks join into the same trajectory as one call."""
    from .progress import Progress

    N = len(y)
    with Progress(N, label, quiet=quiet) as bar:
        if not bar.enabled and chunk is None:
            return estimator.run(y, u)  # nothing to draw: one call
        if chunk is None:
            chunk = max(1, -(-N // 50))
        parts = []
        for a in range(0, N, chunk):
            b = min(N, a + chunk)
            parts.append(estimator.run(y[a:b], None if u is None else u[a:b]))
            bar.update(b - a)
    return _concat(parts)


def run_estimator(job: Job, spec: EstimatorSpec, *, keep_going: bool = False, quiet: bool = False) -> Result:
    """Builds and runs one estimator of ``job``. With ``keep_going`` a library error (an
    infeasible design, an undetectable pair, …) is returned in :attr:`Result.error` instead of
    raised."""
    kind = ESTIMATORS[spec.method]
    t0 = time.perf_counter()
    try:
        est, design = kind.build(job, spec.options)
        t1 = time.perf_counter()
        traj = run_trajectory(est, job.y, job.u, label=spec.name, quiet=quiet)
        t2 = time.perf_counter()
    except SetboundError as exc:
        if not keep_going:
            raise
        return Result(spec.name, spec.method, None, time.perf_counter() - t0, float("nan"), None,
                      error=f"{type(exc).__name__}: {exc}")
    contained = None
    if job.x_true is not None and traj.guaranteed:
        contained = bool(np.all(traj.contains(job.x_true)))
    # a design shared with an earlier estimator of the job: report what it took to compute
    shared = max((dt for d, dt in job.designs.values() if d is design), default=0.0) if design is not None else 0.0
    res = Result(spec.name, spec.method, traj, max(t1 - t0, shared), (t2 - t1) / max(1, len(job.y)), contained,
                 design=design)
    if kind.steady_volume is not None and design is not None:
        res.steady_volume, res.steady_volume_kind = float(kind.steady_volume(design, traj)), "rho_inf"
    elif traj.sets:
        v = traj.volume
        if len(v) and np.isfinite(v[-1]):
            res.steady_volume, res.steady_volume_kind = float(v[-1]), "final"
    return res


def run(job: Job, *, keep_going: bool = False, quiet: bool = False) -> list[Result]:
    """Runs every estimator of ``job`` in order (see :func:`run_estimator`)."""
    return [run_estimator(job, spec, keep_going=keep_going, quiet=quiet) for spec in job.estimators]


# the thesis system and estimator kinds (thesis.md): registered on import
from . import thesis_jobs  # noqa: E402,F401
