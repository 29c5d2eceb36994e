"""CORA-style entry point: run an observer of CORA's ``linearSysDT/observe`` catalogue by its name.

A researcher coming from CORA (MATLAB) writes ``observe(model, alg="FRad-A")`` with the model
file they know and gets the same sets, in setbound's row-per-step layout. ``model`` is a
CORA-format JSON file (``../shared/benchmarks/cora_linearSysDT_observe/``) or what
:func:`setbound.benchmarks.load_cora` returns. The estimator families register their CORA names
here (:func:`register_algorithm`); :func:`algorithms` lists them.

Two conventions (``convention=``): ``"setbound"`` (default) runs the papers' algorithms with
setbound's guarantees; ``"cora"`` reproduces CORA's exact behaviour where it differs (reduction
rules, quirks), so CORA's saved numbers come out. Where a CORA quirk would break the guarantee,
``convention="cora"`` refuses with a clear error instead of returning a wrong set.

CORA's loop corrects the initial set with the first measurement, so row ``k`` of the result is the
set for ``x_k`` after ``y_k`` (setbound's filter indexing); CORA's ``timeStep`` is ``model.dt``.
"""
from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from .benchmarks import CoraBenchmark, load_cora
from .errors import InvalidArgumentError

CONVENTIONS = ("setbound", "cora")


@dataclass
class CoraResult:
    """The sets of one :func:`observe` run and CORA's two metrics.

    Parameters
    ----------
    alg : str
        CORA's name of the observer.
    convention : str
        ``"setbound"`` or ``"cora"``.
    lower, upper : ndarray, shape (N, n_x)
        Interval hull of the set of each step (row ``k``: ``x_k`` after ``y_k``).
    sets : list
        The set of each step (the estimator family's set class), when the method keeps them.
    design_seconds : float
        Time of the offline design (gains, LMIs); 0 for methods without one.
    seconds_per_step : float
        Wall time of the run divided by the number of steps (Python, C library underneath).
    dt : float
        CORA's sampling time of the model.
    """
    alg: str
    convention: str
    lower: np.ndarray
    upper: np.ndarray
    sets: list = field(default_factory=list)
    design_seconds: float = 0.0
    seconds_per_step: float = 0.0
    dt: float = 1.0

    @property
    def iradius(self) -> np.ndarray:
        """CORA's IRadius per dimension (``performanceObserver``): the root mean square over time of
        the interval radius ``(upper − lower) / 2``.

        Returns
        -------
        ndarray, shape (n_x,)
        """
        r = 0.5 * (self.upper - self.lower)
        return np.sqrt(np.mean(r * r, axis=0))

    @property
    def mean_iradius(self) -> float:
        """The mean of :attr:`iradius` over the dimensions.

        Returns
        -------
        float
        """
        return float(np.mean(self.iradius))


#: A runner builds the estimator (the design, if any, is timed here) and returns a zero-argument
#: callable that runs it over the whole data and returns ``(lower, upper, sets)``.
Runner = Callable[..., Callable[[], tuple]]


@dataclass(frozen=True)
class _Algorithm:
    runner: Runner
    summary: str
    accepts_gain: bool
    gain_required: dict  # convention -> why that convention has no design (a gain must be given)


_ALGORITHMS: dict[str, _Algorithm] = {}


def register_algorithm(name: str, runner: Runner, *, summary: str, accepts_gain: bool = False,
                       gain_required: dict | None = None) -> None:
    """Makes an observer reachable by its CORA name.

    Parameters
    ----------
    name : str
        CORA's name (``"FRad-A"``, ``"CZN-A"``, ...), matched case-sensitively.
    runner : callable
        ``runner(model, convention=..., gain=..., **options)`` with ``model`` a
        :class:`~setbound.benchmarks.CoraBenchmark`; does the design and returns a zero-argument
        callable that runs the data and returns ``(lower, upper, sets)``. It raises a setbound
        error on an option it does not know.
    summary : str
        One line: what the method is (listed by :func:`algorithms`).
    accepts_gain : bool, optional
        Whether the method takes a given gain (``gain=L``, ``n_x × n_y``) instead of its design.
    gain_required : dict, optional
        The conventions under which the method has no design, so that a gain must be given, each
        with the reason (one sentence, shown in the error). :func:`prepare` and the job files
        (:mod:`setbound.jobs.cora`) both read this one rule.
    """
    from ._validate import as_bool, as_str

    name, summary = as_str(name, "name"), as_str(summary, "summary")
    accepts_gain = as_bool(accepts_gain, "accepts_gain")
    if not callable(runner):
        raise InvalidArgumentError(f"runner: expected a callable, got {type(runner).__name__}")
    if gain_required is not None and not isinstance(gain_required, dict):
        raise InvalidArgumentError(f"gain_required: expected a dict {{convention: reason}}, got "
                                   f"{type(gain_required).__name__}")
    gain_required = dict(gain_required or {})
    for conv, why in gain_required.items():
        if conv not in CONVENTIONS or not isinstance(why, str):
            raise InvalidArgumentError(f"gain_required: expected {{convention: reason}} with a convention of "
                                       f"{CONVENTIONS}, got {conv!r}: {why!r}")
    if gain_required and not accepts_gain:
        raise InvalidArgumentError("gain_required: only for a method that accepts a gain (accepts_gain=True)")
    if name in _ALGORITHMS:
        raise InvalidArgumentError(f"register_algorithm: {name!r} is registered already")
    _ALGORITHMS[name] = _Algorithm(runner, summary, accepts_gain, gain_required)



def algorithms() -> dict[str, str]:
    """The CORA names :func:`observe` knows, with a one-line summary of each.

    Returns
    -------
    dict
        ``{name: summary}``, in registration order.

    Examples
    --------
    >>> import setbound.cora as cora
    >>> "FRad-A" in cora.algorithms()
    True
    """
    _load_families()
    return {k: a.summary for k, a in _ALGORITHMS.items()}


def _load_families() -> None:
    # The families register their names on import; importing them here keeps `setbound.cora`
    # importable on its own and the registry complete.
    from . import constrained_zonotopic, ellipsoidal, hinf, interval_observers, zonotopic  # noqa: F401
    from . import parallelotope, point  # noqa: F401  (ROPO; Rauch-Tung-Striebel)


def as_model(model) -> CoraBenchmark:
    """The model of :func:`observe`: a CORA-format JSON path or a loaded benchmark.

    Parameters
    ----------
    model : str, Path or CoraBenchmark

    Returns
    -------
    CoraBenchmark
    """
    if isinstance(model, CoraBenchmark):
        return model
    if isinstance(model, (str, Path)):
        return load_cora(model)
    raise InvalidArgumentError(
        f"model: expected a CORA-format JSON path or setbound.benchmarks.load_cora(...), got {type(model).__name__}")


def accepts_gain(alg: str) -> bool:
    """Whether the observer CORA calls ``alg`` takes a given gain (``gain=L``).

    Parameters
    ----------
    alg : str
        CORA's name of the observer (:func:`algorithms` lists them).

    Returns
    -------
    bool

    Raises
    ------
    InvalidArgumentError
        Unknown ``alg``.

    Examples
    --------
    >>> import setbound.cora as cora
    >>> cora.accepts_gain("PRad-E"), cora.accepts_gain("FRad-B")
    (True, False)
    """
    return _algorithm(alg).accepts_gain


def gain_requirement(alg: str, convention: str) -> str | None:
    """Why ``alg`` needs a given gain under ``convention`` (it has no design there), or None.

    Parameters
    ----------
    alg : str
        CORA's name of the observer.
    convention : {"setbound", "cora"}
        The convention.

    Returns
    -------
    str or None
        The reason, or None when the method designs its gain (or takes none).

    Raises
    ------
    InvalidArgumentError
        Unknown ``alg``.

    Examples
    --------
    >>> from setbound.cora import gain_requirement
    >>> gain_requirement("FRad-B", "cora") is None
    True
    """
    return _algorithm(alg).gain_required.get(convention)


def _algorithm(alg) -> _Algorithm:
    _load_families()
    if not isinstance(alg, str) or alg not in _ALGORITHMS:
        raise InvalidArgumentError(f"alg: unknown CORA observer {alg!r}; known: {', '.join(_ALGORITHMS)}")
    return _ALGORITHMS[alg]


def prepare(model, alg: str, *, convention: str = "setbound", gain=None, **options) -> Callable[[], tuple]:
    """The offline part of :func:`observe` (checks, estimator, design): returns the run.

    What :func:`observe` and the job files (``method = "<CORA name>"``, :mod:`setbound.jobs.cora`)
    share: the same checks and the same runner, so both give the same sets.

    Parameters
    ----------
    model : str, Path or CoraBenchmark
        As in :func:`observe`.
    alg : str
        CORA's name of the observer.
    convention : {"setbound", "cora"}, optional
        setbound's guaranteed algorithm (default) or CORA's exact behaviour.
    gain : array_like, shape (n_x, n_y), optional
        A given observer gain (gain-based methods only).
    **options
        The method's own options.

    Returns
    -------
    callable
        ``run()`` processes ``model.y`` from the initial set and returns ``(lower, upper, sets)``;
        it may be called again (each call starts from the initial set).

    Raises
    ------
    InvalidArgumentError
        As :func:`observe`.

    Examples
    --------
    >>> import numpy as np
    >>> from setbound.cora import prepare
    >>> from setbound.sets import Zonotope
    >>> from setbound.benchmarks import CoraBenchmark
    >>> from setbound.system import LinearSystem
    >>> sys = LinearSystem([[0.5, 0.1], [0.0, 0.6]], [[1.0, 0.0]], E=[[0.1], [0.1]], F=[[0.0]])
    >>> m = CoraBenchmark("toy", sys, Zonotope([0, 0], np.eye(2)), y=np.zeros((5, 1)),
    ...                   u=np.zeros((5, 0)), truth=None, zonotope_order=20, reduction="girard")
    >>> lower, upper, sets = prepare(m, "FRad-B")()
    >>> lower.shape, len(sets)
    ((5, 2), 5)
    """
    a = _algorithm(alg)
    if convention not in CONVENTIONS:
        raise InvalidArgumentError(f"convention: expected one of {CONVENTIONS}, got {convention!r}")
    if gain is not None and not a.accepts_gain:
        raise InvalidArgumentError(f"gain: {alg} has no observer gain to give")
    if gain is None and convention in a.gain_required:
        raise InvalidArgumentError(f"gain: {alg} with convention={convention!r} needs a given gain (gain=L, "
                                   f"n_x x n_y): {a.gain_required[convention]}")
    return a.runner(as_model(model), convention=convention, gain=gain, **options)


def observe(model, alg: str, *, convention: str = "setbound", gain=None, steps: int | None = None,
            **options) -> CoraResult:
    """Runs the observer CORA calls ``alg`` on a CORA model and its measurements.

    Parameters
    ----------
    model : str, Path or CoraBenchmark
        A CORA-format JSON file (as in CORA's ``linearSysDT/observe`` unit tests) or
        :func:`setbound.benchmarks.load_cora`'s result.
    alg : str
        CORA's name of the observer (:func:`algorithms` lists them).
    convention : {"setbound", "cora"}, optional
        setbound's guaranteed algorithm (default) or CORA's exact behaviour.
    gain : array_like, shape (n_x, n_y), optional
        A given observer gain instead of the method's design (gain-based methods only).
    steps : int, optional
        Use only the first ``steps`` measurements (CORA's ``tFinal`` shortened).
    **options
        The method's own options (its estimator's keywords). The methods whose gain setbound
        designs (PRad-A..E, Nom-G) also take ``solver_options={"max_iterations": ..., "time_limit":
        ...}``: the limits of each LMI solve of the design (defaults 100 iterations, 30 s; see
        :func:`setbound.zonotopic.design_zonotopic_gain`).

    Returns
    -------
    CoraResult

    Raises
    ------
    InvalidArgumentError
        Unknown ``alg`` or ``convention``, a gain for a method without one, a bad model.

    Examples
    --------
    >>> import numpy as np
    >>> from setbound.cora import observe
    >>> from setbound.sets import Zonotope
    >>> from setbound.benchmarks import CoraBenchmark
    >>> from setbound.system import LinearSystem
    >>> sys = LinearSystem([[0.5, 0.1], [0.0, 0.6]], [[1.0, 0.0]], E=[[0.1], [0.1]], F=[[0.0]])
    >>> m = CoraBenchmark("toy", sys, Zonotope([0, 0], np.eye(2)), y=np.zeros((5, 1)),
    ...                   u=np.zeros((5, 0)), truth=None, zonotope_order=20, reduction="girard")
    >>> r = observe(m, "FRad-A")
    >>> r.lower.shape
    (5, 2)
    """
    a = _algorithm(alg)
    if convention not in CONVENTIONS:
        raise InvalidArgumentError(f"convention: expected one of {CONVENTIONS}, got {convention!r}")
    if gain is not None and not a.accepts_gain:  # before reading the model, as prepare's own checks
        raise InvalidArgumentError(f"gain: {alg} has no observer gain to give")
    m = as_model(model)
    if steps is not None:
        from ._validate import as_int
        k = as_int(steps, "steps", lo=1, hi=len(m.y))
        m = dataclasses.replace(m, y=m.y[:k], u=m.u[:k], truth=None if m.truth is None else m.truth[:k])
    t0 = time.perf_counter()
    run = prepare(m, alg, convention=convention, gain=gain, **options)
    t1 = time.perf_counter()
    lower, upper, sets = run()
    t2 = time.perf_counter()
    return CoraResult(alg=alg, convention=convention, lower=np.asarray(lower), upper=np.asarray(upper),
                      sets=list(sets) if sets is not None else [], design_seconds=t1 - t0,
                      seconds_per_step=(t2 - t1) / max(len(m.y), 1), dt=m.dt)
