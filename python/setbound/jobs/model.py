"""The validated job and its results: :class:`Job`, :class:`EstimatorSpec`, :class:`PlotSpec`,
:class:`Result`, and the process-wide cache of offline designs."""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["EstimatorSpec", "PlotSpec", "Job", "Result"]


@dataclass
class EstimatorSpec:
    """One ``[[estimator]]`` table: the registered ``method``, a unique ``name`` and its options.

    Parameters
    ----------
    method : str
        A registered estimator kind (:data:`ESTIMATORS`).
    name : str
        Unique name in the job.
    options : dict
        The method's options.
    """

    method: str
    name: str
    options: dict[str, Any]


@dataclass
class PlotSpec:
    """The ``[plots]`` table: ``reference`` estimator name for relative widths (None: the first
    guaranteed), projection ``steps`` (None: first, middle, last), projection ``dims``, ``enabled``.

    Parameters
    ----------
    reference : str, optional
        Reference estimator of the relative widths.
    steps : list of int, optional
        Steps of the projections.
    dims : (int, int), optional
        State components of the projections.
    enabled : bool, optional
        False: no PNG files.
    """

    reference: str | None = None
    steps: list[int] | None = None
    dims: tuple[int, int] = (0, 1)
    enabled: bool = True


@dataclass
class Job:
    """A validated job: the system and initial set, the data (``y``, ``u``, ``x_true`` when known,
    time values ``t``), the estimators to run and the plot options. A job loaded for checking
    only (``simulate=False``) has ``horizon`` set and no data (``y`` is None).

    Parameters
    ----------
    title : str
        Title.
    system : LinearSystem, DescriptorSystem or a registered system object
        The model.
    initial : Ellipsoid, Zonotope or Box
        The initial set.
    y, u, x_true : ndarray, optional
        Measurements, inputs and (simulated) true states, one row per step.
    t : ndarray, optional
        Time of each step.
    estimators : list of EstimatorSpec, optional
        The ``[[estimator]]`` tables.
    source : str, optional
        Where the job came from (a file name).
    plots : PlotSpec, optional
        The ``[plots]`` table.
    system_kind : str, optional
        The registered ``[system] kind``.
    constant_input : bool, optional
        The last input column is the constant 1 (offset of ``[system.omega]``).
    extra : dict, optional
        Per-step data besides ``y``/``u`` (e.g. ``"rho"``).
    designs : dict, optional
        Offline designs shared by the estimators (:meth:`cached_design`).
    horizon : int, optional
        Number of steps.
    memory_estimate : int, optional
        Estimated peak memory of a run, in bytes.
    faults : list of Fault, optional
        ``[[fault]]`` tables.
    hypotheses : list of Hypothesis, optional
        ``[[hypothesis]]`` tables.
    isolation : Isolation, optional
        The bank's result after :func:`setbound.jobs.run`.
    """

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
    #: the number of steps (of the simulation or of the data file)
    horizon: int = 0
    #: the estimated peak memory of ``run`` in bytes (see :func:`setbound.jobs.loader.memory_estimate`)
    memory_estimate: int = 0
    #: ``[[fault]]``: faults injected into the simulated plant (:class:`setbound.fault.Fault`)
    faults: list = field(default_factory=list)
    #: ``[[hypothesis]]``: the isolation bank's models (:class:`setbound.fault.Hypothesis`)
    hypotheses: list = field(default_factory=list)
    #: the bank's :class:`setbound.fault.Isolation` after :func:`setbound.jobs.run`
    isolation: Any = None

    @property
    def fault_start(self) -> int | None:
        """The first step of an injected fault (None: fault-free)."""
        return min((f.start for f in self.faults), default=None)

    def cached_design(self, key, make):
        """``make()`` once per ``key`` and system: estimators with the same design options share
        the design, also across jobs of one process with an identical system (``setbound compare``,
        tests). Returns ``(design, seconds it took to compute)``.

        Parameters
        ----------
        key : hashable
            The design's options.
        make : callable
            ``make() -> design``.

        Returns
        -------
        design : object
        seconds : float
        """
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


@dataclass
class Result:
    """The outcome of one estimator on a job: its ``trajectory`` (None when it failed, then
    ``error`` says why, e.g. an infeasible design), the offline ``design`` (or None), timings in
    seconds, ``contained`` (was the true state inside at every step; None when unknown or not
    guaranteed) and ``steady_volume`` with ``steady_volume_kind`` (``"rho_inf"``: the design's
    steady-state volume, ``"final"``: the volume of the last set, ``""``: none).

    Parameters
    ----------
    name, method : str
        The estimator's name and registered method.
    trajectory : Trajectory or None
        Its result.
    design_time, step_time : float
        Seconds (offline design; mean per step).
    contained : bool or None
        The true state was inside at every step.
    design : object, optional
        The offline design.
    error : str, optional
        Why it failed.
    steady_volume : float, optional
        See above.
    steady_volume_kind : str, optional
        See above.
    """

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
