"""Reading and validating a job: :func:`load` (a TOML file) and :func:`from_dict` (a parsed one).

Validation comes first and is complete: every section, every estimator's options, the data
file, the true initial state (inside the initial set) and the memory the run would need are
checked before anything runs. ``simulate=False`` (what ``setbound check`` uses) stops there,
after a short trial of the simulation (:data:`TRIAL_STEPS` steps: it meets a failing
expression such as ``h = ["1/(k-2)"]`` at k = 2 without simulating the whole horizon).
"""
from __future__ import annotations

import os
import tomllib
from pathlib import Path

import numpy as np

from ..errors import SetboundError
from .data import check_shapes, read_data_file
from .expressions import eval_expression
from .faults import parse_faults, parse_hypotheses
from .model import EstimatorSpec, Job, PlotSpec
from .registry import ESTIMATORS, SYSTEMS, BuiltSystem, check_option, unknown_method
from .schema import (MAX_DEPTH, ConfigError, as_choice, as_float, as_int, check_document, check_keys, closest,
                     describe, matrix, require)

__all__ = ["load", "from_dict", "estimator_spec", "memory_estimate", "available_memory", "TRIAL_STEPS", "MAX_HORIZON"]

#: Steps simulated by ``simulate=False`` (``setbound check``) to meet failing expressions early.
TRIAL_STEPS = 64
#: Largest horizon (every count crosses the C ABI as an ``int``).
MAX_HORIZON = 2**31 - 1
#: Largest job file read (bytes): a job file holds a model, not data.
MAX_FILE_BYTES = 64 * 1024 ** 2
#: Input expressions are checked at most at this many times by ``simulate=False``.
_INPUT_SAMPLES = 10000


# ---------------------------------------------------------------- memory
def available_memory() -> int | None:
    """The memory this process may still use (MemAvailable of /proc/meminfo, else the physical
    memory), in bytes; None when unknown."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    try:
        return os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE")
    except (ValueError, OSError, AttributeError):
        return None


# Bytes kept per step and estimator besides the bounds: the set object of the step (a Python
# object holding numpy arrays, about 400 bytes besides their data) plus its matrix. Measured with
# tracemalloc on 5000-step runs (n_x = 2): segment_min 901 B/step (estimate 996), offline 498
# (676), kalman 101 (224); the estimate errs on the large side, as it is for refusing horizons
# that cannot fit, not for accounting.
_SET_OVERHEAD = 500


def _per_step_set_bytes(family: str, n: int, options: dict) -> int:
    if family == "kalman":
        return 8 * (n * n + n)  # no set object: the covariance of the step
    if family == "zonotopic":
        m = options.get("max_generators", 20)
        if m is None and "zonotope_order" in options:  # CORA's names: order x n_x generators (default 20)
            order = options["zonotope_order"]
            m = int(min(order if isinstance(order, (int, float)) and not isinstance(order, bool) else 20.0, 1e6) * n)
        m = m if isinstance(m, int) else 20
        return 8 * n * (min(m, 10**6) + n + 1) + _SET_OVERHEAD
    if family == "interval":
        return 16 * n + _SET_OVERHEAD
    if family == "constrained_zonotopic":
        # the set of the step: n × n_g generators and n_c × n_g constraints (bounded mode's limits;
        # CORA's reduction keeps order·n + n_c generators; without reduction the sizes grow and the
        # per-step figure is the limit's, so the estimate errs on the small side there)
        mc = options.get("max_constraints")
        mc = mc if isinstance(mc, int) and mc >= 0 else 4 * n
        mg = options.get("max_generators")
        mg = mg if isinstance(mg, int) and mg >= 0 else 20 * n + mc
        mg, mc = min(mg, 10**6), min(mc, 10**6)
        return 8 * (n * mg + mc * mg + mc + 2 * n) + 4 * _SET_OVERHEAD
    return 8 * (n * n + n) + _SET_OVERHEAD  # ellipsoids and the rest


def memory_estimate(system, N: int, estimators) -> int:
    """Bytes a run of ``N`` steps keeps at its peak: the simulated or measured data and, per
    estimator, its trajectory (bounds and one set per step, twice over while chunks are joined)."""
    n = int(system.nx)
    ny = int(getattr(system, "ny", 1))
    nu = int(getattr(system, "nu", 0))
    nw = int(getattr(system, "nw", n + ny))
    per_step = 8 * (2 * n + ny + nu + nw + 2)  # x, y, u, w, t (and the disturbance draw)
    for spec in estimators:
        family = ESTIMATORS[spec.method].family
        per_step += 2 * (8 * 4 * n) + _per_step_set_bytes(family, n, spec.options)
    return int(N) * per_step


def _gib(b: float) -> str:
    return f"{b / 1024 ** 3:.1f} GiB" if b >= 1024 ** 3 else f"{b / 1024 ** 2:.0f} MiB"


def _check_memory(system, N: int, estimators, key: str) -> int:
    need = memory_estimate(system, N, estimators)
    have = available_memory()
    if have is not None and need > have:
        raise ConfigError(f"{key}: {N} steps would need about {_gib(need)} of memory (estimate for "
                          f"{len(estimators)} estimator{'s' if len(estimators) != 1 else ''}), this machine has "
                          f"{_gib(have)} available; shorten the horizon or run fewer estimators")
    return need


# ---------------------------------------------------------------- sections
def _system(tab):
    if not isinstance(tab, dict):
        raise ConfigError(f"system: expected a table, got {describe(tab)}")
    kind = tab.get("kind", "linear")
    if not isinstance(kind, str) or kind not in SYSTEMS:
        raise ConfigError(f"system.kind: expected one of {', '.join(map(repr, SYSTEMS))}, got "
                          f"{describe(kind)}{closest(kind, SYSTEMS)}")
    entry = SYSTEMS[kind]
    check_keys(tab, entry.keys, "system")
    built = entry.build(tab)
    if isinstance(built, BuiltSystem):
        return kind, built.system, built.constant_input
    return kind, built, False


def _initial(tab, n):
    from ..interval import Box
    from ..sets import Ellipsoid, Zonotope

    check_keys(tab, {"center", "P", "rho", "generators", "lower", "upper"}, "initial")
    try:
        if "lower" in tab or "upper" in tab:
            for k in ("center", "P", "rho", "generators"):
                if k in tab:
                    raise ConfigError(f"initial.{k}: not used with a box (lower, upper); give one kind of set")
            lo = matrix(require(tab, "lower", "initial"), "initial.lower", ndim=1, shape=(n,))
            hi = matrix(require(tab, "upper", "initial"), "initial.upper", ndim=1, shape=(n,))
            if np.any(lo > hi):
                raise ConfigError("initial.lower: must be <= initial.upper componentwise")
            return Box(lo, hi)
        c = matrix(require(tab, "center", "initial"), "initial.center", ndim=1, shape=(n,))
        if "generators" in tab:
            for k in ("P", "rho"):
                if k in tab:
                    raise ConfigError(f"initial.{k}: not used with a zonotope (center, generators)")
            G = matrix(tab["generators"], "initial.generators", shape=(n, None))
            return Zonotope(c, G)
        P = tab.get("P", "identity")
        P = np.eye(n) if isinstance(P, str) and P == "identity" else matrix(P, "initial.P", shape=(n, n))
        rho = as_float(require(tab, "rho", "initial"), "initial.rho", lo=0, lo_open=True)
        return Ellipsoid(P, c, rho)
    except ConfigError:
        raise
    except SetboundError as exc:
        raise ConfigError(f"initial: {exc}") from None


def _inputs(spec, t, nu, key, *, sample: bool = False):
    """The N × n_u inputs (expressions of t, or an array). With ``sample`` the expressions are only
    checked at up to :data:`_INPUT_SAMPLES` times spread over the horizon (``setbound check``)."""
    if nu == 0:
        if spec is not None:
            raise ConfigError(f"{key}: the system has no input")
        return None
    if spec is None:
        raise ConfigError(f"{key}: missing (the system has {nu} inputs)")
    if isinstance(spec, list) and spec and all(isinstance(s, str) for s in spec):
        if len(spec) != nu:
            raise ConfigError(f"{key}: expected {nu} expressions (one per input), got {len(spec)}")
        if sample and len(t) > _INPUT_SAMPLES:
            idx = np.unique(np.concatenate([np.arange(TRIAL_STEPS),
                                            np.linspace(0, len(t) - 1, _INPUT_SAMPLES).astype(np.int64)]))
            for i, s in enumerate(spec):
                eval_expression(s, t[idx], f"{key}[{i}]")
            return None
        return np.column_stack([eval_expression(s, t, f"{key}[{i}]") for i, s in enumerate(spec)])
    return matrix(spec, key, shape=(t.shape[0], nu))


# Options whose shape follows from the system: checked at load time (not only when the estimator is
# built, where a wrong shape would be an estimator failure, exit 1, instead of a job-file error).
_OPTION_SHAPES = {"xhat0": lambda s: (s.nx,), "cov0": lambda s: (s.nx, s.nx), "L": lambda s: (s.nx, s.ny),
                  "gain": lambda s: (s.nx, s.ny),
                  "omega_cov": lambda s: (getattr(s, "nw", None), getattr(s, "nw", None))}


def estimator_spec(tab, where: str, system_kind: str = "linear", system=None) -> EstimatorSpec:
    """Validates one ``[[estimator]]`` table (what :func:`load` does for each; ``setbound compare
    --estimators`` for a method named on the command line).

    Parameters
    ----------
    tab : dict
        The table (``method``, optional ``name``, the method's options).
    where : str
        How errors name it (``estimator[0]``).
    system_kind : str, optional
        The job's system kind.
    system : object, optional
        The job's system (then options whose shape follows from it are checked).

    Returns
    -------
    EstimatorSpec

    Examples
    --------
    >>> spec = setbound.jobs.estimator_spec({"method": "FRad-B", "convention": "cora"}, "estimator[0]")
    >>> spec.name, spec.options["convention"]
    ('FRad-B', 'cora')
    """
    if not isinstance(tab, dict):
        raise ConfigError(f"{where}: expected a table, got {describe(tab)}")
    if "method" not in tab:
        for k in tab:  # a misspelt `method` is the likely cause: say so
            if closest(k, {"method"}):
                raise ConfigError(f"{where}.{k}: unknown key (did you mean 'method'?)")
    method = require(tab, "method", where)
    if not isinstance(method, str) or method not in ESTIMATORS:
        raise unknown_method(method, where)
    kind = ESTIMATORS[method]
    check_keys(tab, {"method", "name", *kind.options}, where)
    if system_kind not in kind.systems:
        raise ConfigError(f"{where}.method: {method!r} does not apply to a {system_kind} system "
                          f"(it applies to: {', '.join(kind.systems)})")
    given = {}
    for k, v in tab.items():
        if k in kind.options:
            given[k] = check_option(kind.checks[k], v, f"{where}.{k}") if k in kind.checks else v
    if system is not None:
        for k, v in given.items():
            if k in _OPTION_SHAPES and v is not None:
                shape = _OPTION_SHAPES[k](system)
                matrix(v, f"{where}.{k}", ndim=len(shape), shape=shape)
    opts = {**kind.options, **given}
    if kind.validate is not None:
        kind.validate(opts, where)
    name = tab.get("name", method)
    if not isinstance(name, str) or not name or len(name) > 100 or any(ch in name for ch in "/\\:*?\"<>|\0") \
            or name.startswith(".") or not name.isprintable():
        raise ConfigError(f"{where}.name: must be a non-empty string usable as a file name, got {describe(name)}")
    return EstimatorSpec(method, name, opts)


def _estimators(lst, system_kind: str, system=None):
    if not isinstance(lst, list) or not lst:
        raise ConfigError("estimator: at least one [[estimator]] table is required")
    out, names = [], set()
    for i, tab in enumerate(lst):
        where = f"estimator[{i}]"
        spec = estimator_spec(tab, where, system_kind, system)
        if spec.name in names:
            raise ConfigError(f"{where}.name: duplicate estimator name {spec.name!r}")
        names.add(spec.name)
        out.append(spec)
    return out


def _plots(tab, n: int, N: int, names: list[str]) -> PlotSpec:
    from .schema import as_bool

    check_keys(tab, {"reference", "steps", "dims", "enabled"}, "plots")
    spec = PlotSpec()
    if "enabled" in tab:
        spec.enabled = as_bool(tab["enabled"], "plots.enabled")
    if "reference" in tab:
        if not isinstance(tab["reference"], str) or tab["reference"] not in names:
            raise ConfigError(f"plots.reference: {describe(tab['reference'])} is not the name of an estimator of this "
                              f"job ({', '.join(names)})")
        spec.reference = tab["reference"]
    if "steps" in tab:
        st = tab["steps"]
        if not isinstance(st, list) or not st or len(st) > 100:
            raise ConfigError(f"plots.steps: expected a non-empty list of at most 100 step numbers, got {describe(st)}")
        spec.steps = [as_int(k, f"plots.steps[{i}]", lo=0, hi=N - 1) for i, k in enumerate(st)]
    if "dims" in tab:
        d = tab["dims"]
        if not (isinstance(d, list) and len(d) == 2):
            raise ConfigError(f"plots.dims: expected two distinct state indices in 0..{n - 1}, got {describe(d)}")
        dims = tuple(as_int(v, f"plots.dims[{i}]", lo=0, hi=n - 1) for i, v in enumerate(d))
        if dims[0] == dims[1]:
            raise ConfigError(f"plots.dims: expected two distinct state indices in 0..{n - 1}, got {list(dims)}")
        spec.dims = dims
    return spec


def _with_constant(u, N: int, constant_input: bool):
    if not constant_input:
        return u
    return np.hstack([u if u is not None else np.zeros((N, 0)), np.ones((N, 1))])


def _check_inside(initial, x0, key: str) -> None:
    """The true initial state must lie in the initial set: every guarantee starts there, so a
    state outside it makes every estimator look wrong."""
    from ..interval import Box

    if isinstance(initial, Box):
        lo, hi = np.asarray(initial.lo, float), np.asarray(initial.hi, float)
        tol = 1e-12 * np.maximum(1.0, np.maximum(np.abs(lo), np.abs(hi)))
        out = np.flatnonzero((x0 < lo - tol) | (x0 > hi + tol))
        if out.size:
            i = int(out[0])
            raise ConfigError(f"{key}: component {i} = {x0[i]:.6g} is outside the initial box "
                              f"[{lo[i]:.6g}, {hi[i]:.6g}] (the true state must start in the initial set)")
        return
    try:
        inside = bool(np.all(initial.contains(x0[None, :])))
    except SetboundError as exc:
        raise ConfigError(f"{key}: cannot check it against the initial set ({exc})") from None
    if not inside:
        raise ConfigError(f"{key}: {np.array2string(x0, precision=6)} is outside the initial "
                          f"{type(initial).__name__.lower()} (the true state must start in the initial set)")


# ---------------------------------------------------------------- loading
def _deep_line(text: str) -> str:
    """``line N (key)`` of the first value nested deeper than :data:`~setbound.jobs.schema.MAX_DEPTH`
    (a rough scan of the brackets outside strings: enough to point at the line tomllib gave up on)."""
    depth, quote = 0, None
    for no, line in enumerate(text.splitlines(), start=1):
        for ch in line:
            if quote:
                quote = None if ch == quote else quote
            elif ch in "\"'":
                quote = ch
            elif ch in "[{":
                depth += 1
                if depth > MAX_DEPTH:
                    key = line.split("=", 1)[0].strip() if "=" in line else ""
                    return f"line {no}" + (f" ({key})" if 0 < len(key) < 80 else "")
            elif ch in "]}":
                depth = max(0, depth - 1)
            elif ch == "#":
                break
    return "somewhere"


def load(path, *, simulate: bool = True) -> Job:
    """Reads and validates a job file; raises ConfigError naming the key on any problem.
    ``simulate=False``: validate only (see the module docstring).

    Parameters
    ----------
    path : str or Path
        The TOML file.
    simulate : bool, optional
        Simulate the data (else validate only).

    Returns
    -------
    Job

    Examples
    --------
    >>> job = setbound.jobs.from_dict({"system": {"A": [[0.5]], "C": [[1.0]], "E": [[0.1, 0.0]], "F": [[0.0, 0.1]]},
    ...                                "initial": {"lower": [-1.0], "upper": [1.0]},
    ...                                "simulation": {"horizon": 5, "seed": 1},
    ...                                "estimator": [{"method": "segment_min"}]})
    >>> [(r.name, r.contained) for r in setbound.jobs.run(job, quiet=True)]
    [('segment_min', True)]
    """
    path = Path(path)
    try:
        with open(path, "rb") as fh:
            raw = fh.read(MAX_FILE_BYTES + 1)
    except FileNotFoundError:
        raise ConfigError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise ConfigError(f"{path}: is a directory, not a job file") from None
    except OSError as exc:
        raise ConfigError(f"{path}: cannot read ({exc.strerror})") from None
    if len(raw) > MAX_FILE_BYTES:
        raise ConfigError(f"{path}: larger than {MAX_FILE_BYTES // 1024 ** 2} MiB (put large arrays in a [data] file)")
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ConfigError(f"{path}: not valid TOML (not UTF-8 text at byte {exc.start})") from None
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: not valid TOML ({exc})") from None
    except ValueError as exc:  # e.g. an integer of more than 4300 digits (Python's conversion limit)
        raise ConfigError(f"{path}: not valid TOML ({describe(str(exc), 100)})") from None
    except RecursionError:  # tomllib parses nested arrays recursively
        raise ConfigError(f"{path}: {_deep_line(text)}: arrays or tables nested too deeply (at most "
                          f"{MAX_DEPTH} levels)") from None
    return from_dict(doc, base=path.parent, source=str(path), simulate=simulate)


def from_dict(doc: dict, *, base=Path("."), source: str = "", simulate: bool = True) -> Job:
    """Validates a parsed job (the dictionary of a TOML file); relative data files are looked up
    under ``base``. Raises ConfigError naming the key on any problem. ``simulate=False``:
    validate only, the job has no data (see the module docstring).

    Parameters
    ----------
    doc : dict
        The parsed job.
    base : Path, optional
        Folder of relative data files.
    source : str, optional
        Where it came from (for messages).
    simulate : bool, optional
        Simulate the data (else validate only).

    Returns
    -------
    Job
    """
    check_document(doc)
    # "study": the grid of `setbound study` (setbound.jobs.study); `run` and `check` use the base job
    check_keys(doc, {"title", "system", "initial", "simulation", "data", "estimator", "plots", "fault", "hypothesis",
                     "study"}, "job")
    system_kind, system, constant_input = _system(require(doc, "system", "job"))
    nu = system.nu - (1 if constant_input else 0)  # the inputs the user gives
    n = system.nx
    initial = _initial(require(doc, "initial", "job"), n)
    title = doc.get("title", Path(source).stem or "job")
    if not isinstance(title, str):
        raise ConfigError(f"title: expected a string, got {describe(title)}")
    job = Job(title=title, system=system, initial=initial, source=source, system_kind=system_kind,
              constant_input=constant_input)
    if ("simulation" in doc) == ("data" in doc):
        raise ConfigError("job: exactly one of [simulation] and [data] is required")
    estimators = _estimators(doc.get("estimator"), system_kind, system)
    job.faults = parse_faults(doc.get("fault"), system, system_kind, "simulation" in doc)
    job.hypotheses = parse_hypotheses(doc.get("hypothesis"), system, system_kind, initial)
    if "simulation" in doc:
        _simulation(job, doc["simulation"], estimators, nu, simulate)
    else:
        _data(job, doc["data"], base, nu)
    job.memory_estimate = _check_memory(system, job.horizon, estimators,
                                        "simulation.horizon" if "simulation" in doc else "data.file")
    job.estimators = estimators
    job.plots = _plots(doc.get("plots", {}), n, job.horizon, [e.name for e in estimators])
    return job


def _simulation(job: Job, sim, estimators, nu: int, simulate: bool) -> None:
    from ..simulation import simulate as run_simulation

    system, initial, n = job.system, job.initial, job.system.nx
    custom = getattr(system, "simulate_job", None)  # a system kind with its own simulation (thesis kinds)
    check_keys(sim, {"horizon", "seed", "disturbance", "inputs", "time", "x0", "A_choice",
                     *getattr(system, "simulation_keys", ())}, "simulation")
    N = as_int(require(sim, "horizon", "simulation"), "simulation.horizon", lo=1, hi=MAX_HORIZON)
    job.horizon = N
    # refuse a horizon that cannot fit before allocating anything of its size (t, inputs)
    _check_memory(system, N, estimators, "simulation.horizon")
    tt = sim.get("time", {"start": 0.0, "step": 1.0})
    check_keys(tt, {"start", "stop", "step"}, "simulation.time")
    start = as_float(tt.get("start", 0.0), "simulation.time.start")
    if "stop" in tt and "step" in tt:
        raise ConfigError("simulation.time: give either stop or step, not both")
    if "stop" in tt:
        stop = as_float(tt["stop"], "simulation.time.stop")
        t = np.linspace(start, stop, N)
    else:
        step = as_float(tt.get("step", 1.0), "simulation.time.step")
        t = start + step * np.arange(N)
    if not np.all(np.isfinite(t)):
        raise ConfigError("simulation.time: the times overflow the floating-point range")
    u = _inputs(sim.get("inputs"), t, nu, "simulation.inputs", sample=not simulate)
    x0 = sim.get("x0", "sample")
    if not (isinstance(x0, str) and x0 == "sample"):
        x0 = matrix(x0, "simulation.x0", ndim=1, shape=(n,))
        _check_inside(initial, x0, "simulation.x0")
    seed = as_int(sim.get("seed", 0), "simulation.seed", lo=0, hi=2**63 - 1)
    kind = a_choice = None
    if custom is None:
        kind = as_choice(sim.get("disturbance", "uniform"), "simulation.disturbance",
                         ("uniform", "vertex", "gaussian", "zero"))
        a_choice = as_choice(sim.get("A_choice", "vertex"), "simulation.A_choice", ("vertex", "uniform", "mid"))
    steps = N if simulate else min(N, TRIAL_STEPS)
    if u is None and nu and not simulate:  # inputs only sampled: the trial takes its first steps
        u = _inputs(sim.get("inputs"), t[:steps], nu, "simulation.inputs")
    if u is not None:
        u = u[:steps]
    u = _with_constant(u, steps, job.constant_input)
    try:
        with np.errstate(over="ignore", invalid="ignore"):  # overflow is checked (and reported) below
            s = _simulate(custom, run_simulation, system, sim, initial, steps, t, u, x0, seed, kind, a_choice,
                          job.faults)
    except ConfigError:
        raise
    except SetboundError as exc:
        raise ConfigError(f"simulation: {exc}") from None
    extra = dict(getattr(s, "extra", {}) or {})
    # an unstable system (or huge inputs) overflows: refuse it rather than hand NaN to the estimators
    for name, arr in (("state", s.x), ("output", s.y)):
        bad = np.flatnonzero(~np.all(np.isfinite(np.asarray(arr, float).reshape(len(arr), -1)), axis=1))
        if bad.size:
            raise ConfigError(f"simulation: the simulated {name} is not finite from step k = {int(bad[0])} on (an "
                              f"unstable system or inputs too large for the horizon overflow the floating-point "
                              f"range)")
    if simulate:
        job.y, job.u, job.x_true, job.t = s.y, (s.u if system.nu else None), s.x, t
        job.extra = extra


def _simulate(custom, run_simulation, system, sim, initial, steps, t, u, x0, seed, kind, a_choice, faults=()):
    if faults:  # the plant with its faults (setbound.fault); the estimators see the faulty readings
        from ..fault import simulate_faulty

        return simulate_faulty(system, _sampling_set(initial) if isinstance(x0, str) else x0, steps, faults,
                               disturbance=kind, rng=seed, u=u)
    if custom is not None:
        # x_true, y and the extra per-step data (e.g. the LPV scheduling signal) from the system
        return custom(sim, initial, steps, t[:steps], u, x0, seed)
    return run_simulation(system, _sampling_set(initial) if isinstance(x0, str) else x0, steps, disturbance=kind,
                          rng=seed, u=u, A_choice=a_choice)


def _sampling_set(initial):
    """The initial set as :func:`setbound.simulation.sample_in` draws from it: a box as the zonotope
    with its radii as generators (uniform inside, a corner for boundary draws)."""
    from ..interval import Box
    from ..sets import Zonotope

    if isinstance(initial, Box):
        lo, hi = np.asarray(initial.lo, float), np.asarray(initial.hi, float)
        return Zonotope((lo + hi) / 2, np.diag((hi - lo) / 2))
    return initial


def _data(job: Job, dat, base, nu: int) -> None:
    system = job.system
    check_keys(dat, {"file"}, "data")
    name = require(dat, "file", "data")
    if not isinstance(name, str) or not name or "\0" in name:
        raise ConfigError(f"data.file: expected a file name (a string), got {describe(name)}")
    f = Path(name)
    f = f if f.is_absolute() else Path(base) / f
    arrays = read_data_file(f, name)
    y, u, x = check_shapes(arrays, name, system.ny, nu, system.nx)
    N = y.shape[0]
    job.horizon = N
    job.y = y
    job.u = _with_constant(u if nu else None, N, job.constant_input)
    job.x_true = x
    job.t = np.arange(N, dtype=float)
    if x is not None:
        _check_inside(job.initial, x[0], "data.x")
