"""Guaranteed fault detection and isolation (issue 24, point 3).

A guaranteed estimator holds a set that contains every state consistent with the model, the
bounds and the data. When a reading falls outside the output set that set predicts, no state of
the model can have produced it (:mod:`setbound.measurement`): that is a *certificate* that the
model, the bounds or the data are wrong. A detector built on it has a property no statistical
detector has: **no false alarm** while the model and the bounds hold (the guarantee campaign
counts false alarms and finds none). What it cannot promise is to see every fault: a fault that
keeps the readings inside the predicted output sets is invisible, and tighter sets see smaller
faults (``docs/fault_detection.md`` measures it).

* :func:`detect` runs any estimator of the library that screens its readings (the zonotopic and
  ellipsoidal families) and reports the first inconsistent step (the alarm), the flagged steps
  and the margin of each step (how far, in noise bounds, the worst reading lies outside its
  predicted output set).
* :class:`FaultBank` isolates: one model per hypothesis (:func:`nominal`, :func:`sensor_bias`,
  :func:`stuck_sensor`, :func:`actuator_loss`, :func:`parameter_change`, or any user-defined
  :class:`Hypothesis`), each run by its own estimator; a hypothesis is rejected at the first
  step whose data no state of *its* model can produce, so at each step the bank says which
  hypotheses are still consistent. A rejection is as certain as an alarm.
* :class:`Fault` and :func:`simulate_faulty` inject faults into a simulated plant (the job
  files' ``[[fault]]`` tables use them).

Example::

    sim = simulate_faulty(system, x0, 200, [Fault("sensor_bias", start=80, output=0, magnitude=0.5)], rng=1)
    det = detect(SegmentMinEstimator(system, x0), sim.y)
    det.alarm                              # first step with an impossible reading (≥ 80), or None
    bank = FaultBank(system, x0, [nominal(system, x0), sensor_bias(system, x0, 0, bound=2.0),
                                  stuck_sensor(system, x0, 1)])
    iso = bank.run(sim.y)
    iso.consistent_at_end                  # e.g. ['sensor_bias[y0]', 'stuck_sensor[y1]']
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np

from ._validate import as_choice, as_float, as_int, as_str
from .errors import DimensionError, InvalidArgumentError
from .sets import Zonotope, as_zonotope
from .simulation import Simulation, _inputs, _rng, disturbances, sample_in
from .system import LinearSystem, as_system

__all__ = ["FAULT_KINDS", "Fault", "simulate_faulty", "Detection", "detect", "Hypothesis", "nominal",
           "sensor_bias", "stuck_sensor", "actuator_loss", "parameter_change", "Isolation", "FaultBank"]

#: Kinds of injected faults (:class:`Fault`).
FAULT_KINDS = ("sensor_bias", "stuck_sensor", "actuator_loss", "parameter_change")


@dataclass(frozen=True)
class Fault:
    """A fault of the simulated plant from step ``start`` on.

    * ``"sensor_bias"``: ``y_i += magnitude`` (``output`` i);
    * ``"stuck_sensor"``: output i keeps the value it read at ``start − 1`` (at ``start`` when
      ``start = 0``), or ``magnitude`` when ``value_given`` (the sensor froze at a value);
    * ``"actuator_loss"``: input j acts as ``(1 − magnitude) u_j`` (``magnitude`` in [0, 1]:
      the fraction of effectiveness lost);
    * ``"parameter_change"``: ``A`` becomes ``A + delta_A``.

    Parameters
    ----------
    kind : {"sensor_bias", "stuck_sensor", "actuator_loss", "parameter_change"}
        The kind of fault.
    start : int
        First faulty step.
    output : int, optional
        The output (sensor faults).
    input : int, optional
        The input (actuator faults).
    magnitude : float, optional
        Bias, stuck value or lost fraction (see above).
    delta_A : ndarray, optional
        Change of ``A`` (parameter change).
    value_given : bool, optional
        The stuck sensor froze at ``magnitude``.
    """

    kind: str
    start: int
    output: int | None = None
    input: int | None = None
    magnitude: float = 0.0
    delta_A: np.ndarray | None = None
    value_given: bool = False

    def __post_init__(self):
        as_choice(self.kind, "kind", FAULT_KINDS)
        as_int(self.start, "start", lo=0)
        as_float(self.magnitude, "magnitude")
        if self.kind in ("sensor_bias", "stuck_sensor") and self.output is None:
            raise InvalidArgumentError(f"output: a {self.kind} fault needs the output it affects")
        if self.kind == "actuator_loss":
            if self.input is None:
                raise InvalidArgumentError("input: an actuator_loss fault needs the input it affects")
            as_float(self.magnitude, "magnitude", lo=0.0, hi=1.0)
        if self.kind == "parameter_change" and self.delta_A is None:
            raise InvalidArgumentError("delta_A: a parameter_change fault needs the change of A")

    def check(self, system: LinearSystem) -> None:
        """Raises a clear error when the fault does not fit ``system`` (an output, input or
        shape out of range).

        Parameters
        ----------
        system : LinearSystem
            The simulated system.
        """
        if self.output is not None and not 0 <= int(self.output) < system.ny:
            raise DimensionError(f"output: {self.output} is out of range, the system has {system.ny} outputs")
        if self.input is not None and not 0 <= int(self.input) < system.nu:
            raise DimensionError(f"input: {self.input} is out of range, the system has {system.nu} inputs")
        if self.delta_A is not None:
            dA = np.asarray(self.delta_A, dtype=float)
            if dA.shape != (system.nx, system.nx):
                raise DimensionError(f"delta_A: expected shape ({system.nx}, {system.nx}), got {dA.shape}")
            if not np.all(np.isfinite(dA)):
                raise InvalidArgumentError("delta_A: must be finite")


def simulate_faulty(system, x0, N: int, faults: Sequence[Fault] = (), *, disturbance: str = "uniform", rng=None,
                    u=None) -> Simulation:
    """``N`` steps of ``system`` (a known-``A`` :class:`~setbound.LinearSystem`) with ``faults``
    injected; the same conventions as :func:`setbound.simulate` (row k is time k; ``u`` the
    *commanded* inputs, which an actuator fault scales before they reach the plant; the
    readings carry the sensor faults).

    Parameters
    ----------
    system : LinearSystem
        The nominal model (known ``A``).
    x0 : set or array_like
        Initial set (the true state is drawn from it) or the true initial state.
    N : int
        Number of steps.
    faults : sequence of Fault, optional
        Faults injected.
    disturbance : str, optional
        Disturbance profile (see :func:`setbound.simulation.disturbances`).
    rng : numpy.random.Generator or int, optional
        Random source or seed.
    u : array_like, shape (N, n_u), optional
        Commanded inputs.

    Returns
    -------
    Simulation
    """
    s = as_system(system)
    if not isinstance(s, LinearSystem):
        raise InvalidArgumentError(f"system: expected a LinearSystem, got {type(s).__name__}")
    if s.uncertain_A:
        raise InvalidArgumentError("system: fault injection needs a known A (the simulated plant)")
    N = as_int(N, "N", lo=1, hi=10**8)
    disturbance = as_choice(disturbance, "disturbance", ("uniform", "vertex", "gaussian", "zero"))
    if isinstance(faults, (str, bytes)) or not hasattr(faults, "__iter__"):
        raise InvalidArgumentError(f"faults: expected a list of setbound.fault.Fault, got {type(faults).__name__}")
    faults = list(faults)
    for f in faults:
        if not isinstance(f, Fault):
            raise InvalidArgumentError(f"faults: expected setbound.fault.Fault items, got {type(f).__name__}")
        f.check(s)
    rng = _rng(rng)
    U = _inputs(u, N, s.nu)
    W = disturbances(disturbance, N, s.nw, rng)
    x = np.empty((N, s.nx))
    y = np.empty((N, s.ny))
    x[0] = sample_in(x0, rng, boundary=disturbance == "vertex")
    for k in range(N):
        Ak, Uk = s.A, U[k].copy()
        for f in faults:
            if k >= f.start:
                if f.kind == "actuator_loss":
                    Uk[f.input] *= 1.0 - f.magnitude
                elif f.kind == "parameter_change":
                    Ak = Ak + np.asarray(f.delta_A, dtype=float)
        y[k] = s.C @ x[k] + s.D @ Uk + s.F @ W[k]
        if k + 1 < N:
            x[k + 1] = Ak @ x[k] + s.B @ Uk + s.E @ W[k]
    for f in faults:  # sensor faults act on the readings only
        if f.kind == "sensor_bias":
            y[f.start:, f.output] += f.magnitude
        elif f.kind == "stuck_sensor" and f.start < N:
            value = f.magnitude if f.value_given else y[max(f.start - 1, 0), f.output]
            y[f.start:, f.output] = value
    return Simulation(x, y, W, U)


# ------------------------------------------------------------------------------------ detection
@dataclass
class Detection:
    """What a guaranteed detector saw on a record.

    ``alarm``: the first step with an impossible reading (None: no alarm); ``flagged`` (N bools);
    ``margin`` (N): the largest margin over the outputs tested at each step, in noise bounds
    (> 0: outside the predicted output set; NaN when no output was tested); ``trajectory``: the
    estimator's :class:`~setbound.Trajectory` (its ``status`` and ``margin`` per output).

    Parameters
    ----------
    alarm : int or None
        First step with an impossible reading.
    flagged : ndarray of bool, shape (N,)
        Steps with an impossible reading.
    margin : ndarray, shape (N,)
        Largest margin per step.
    trajectory : Trajectory, optional
        The estimator's trajectory.
    """

    alarm: int | None
    flagged: np.ndarray
    margin: np.ndarray
    trajectory: object = None

    @classmethod
    def from_trajectory(cls, traj) -> "Detection":
        """The detection a trajectory of an estimator that tested its readings records.

        Parameters
        ----------
        traj : Trajectory
            A trajectory with ``status`` and ``margin``.

        Returns
        -------
        Detection
        """
        flagged = np.asarray(traj.flagged, dtype=bool)
        hits = np.flatnonzero(flagged)
        return cls(int(hits[0]) if hits.size else None, flagged, _largest_margin(traj.margin), traj)

    def delay(self, fault_start: int) -> int | None:
        """Steps from ``fault_start`` to the first alarm at or after it (None: not detected).

        Parameters
        ----------
        fault_start : int
            Step at which the fault starts.

        Returns
        -------
        int or None
        """
        later = np.flatnonzero(self.flagged[fault_start:])
        return int(later[0]) if later.size else None

    def plot(self, ax=None, *, fault_start: int | None = None, title: str | None = None):
        """The margin over time with the alarm (and the fault's start when given): a margin above 0
        is a reading no state of the model can produce.

        Parameters
        ----------
        ax : matplotlib.axes.Axes, optional
            Where to draw (default: a new figure).
        fault_start : int, optional
            Marks the fault's start.
        title : str, optional
            Axes title.

        Returns
        -------
        matplotlib.axes.Axes
            The axes drawn on (``ax.figure`` is the figure).
        """
        fault_start = None if fault_start is None else as_int(fault_start, "fault_start", lo=0)
        title = None if title is None else as_str(title, "title")
        if ax is None:
            from matplotlib.figure import Figure

            ax = Figure(figsize=(7, 3)).subplots()
        k = np.arange(self.margin.size)
        ax.plot(k, self.margin, lw=1.2, label="largest margin (noise bounds)")
        ax.axhline(0.0, color="k", lw=0.8, ls=":")
        if self.flagged.any():
            ax.plot(k[self.flagged], self.margin[self.flagged], "r.", ms=5, label="impossible reading")
        if self.alarm is not None:
            ax.axvline(self.alarm, color="r", lw=1.2, label=f"alarm (step {self.alarm})")
        if fault_start is not None:
            ax.axvline(fault_start, color="0.4", lw=1.0, ls="--", label=f"fault (step {fault_start})")
        ax.set_xlabel("step k")
        ax.set_ylabel("margin")
        if title:
            ax.set_title(title, fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(loc="best", fontsize=7)
        return ax


def _largest_margin(margin: np.ndarray) -> np.ndarray:
    out = np.full(margin.shape[0], np.nan)
    tested = ~np.all(np.isnan(margin), axis=1)
    out[tested] = np.nanmax(margin[tested], axis=1)
    return out


def detect(estimator, y, u=None) -> Detection:
    """Runs ``estimator`` (from its initial set) on ``y`` (N × n_y; NaN entries: missing) and
    ``u``; the alarm is the first step with a reading outside the predicted output set. The
    estimator must screen its readings (zonotopic or ellipsoidal family) and use the ``"flag"``
    policy (the default): ``"raise"`` would stop at the alarm, ``"reset"`` changes what follows.

    Methods › Fault detection and isolation.

    Parameters
    ----------
    estimator : estimator object
        A zonotopic or ellipsoidal estimator with the ``"flag"`` policy.
    y : array_like, shape (N, n_y)
        Measurements.
    u : array_like, shape (N, n_u), optional
        Inputs.

    Returns
    -------
    Detection

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.5]], C=[[1.0]], E=[[0.1, 0.0]], F=[[0.0, 0.1]])
    >>> x0 = setbound.Box([-1.0], [1.0])
    >>> sim = setbound.fault.simulate_faulty(sys, x0, 30, [setbound.fault.Fault("sensor_bias", start=20, output=0,
    ...                                                                      magnitude=2.0)], rng=1)
    >>> det = setbound.fault.detect(setbound.zonotopic.SegmentMinEstimator(sys, x0), sim.y)
    >>> det.alarm is not None and det.alarm >= 20
    True
    """
    policy = getattr(estimator, "on_inconsistency", None)
    if policy is None:
        raise InvalidArgumentError(f"estimator: {type(estimator).__name__} does not test its readings "
                                   "(use a zonotopic or ellipsoidal estimator)")
    if policy != "flag":
        raise InvalidArgumentError(f'estimator: detect() needs on_inconsistency="flag", got {policy!r}')
    return Detection.from_trajectory(estimator.run(y, u))


# ------------------------------------------------------------------------------------ isolation
def _zonotope(x0, n: int, name: str = "x0") -> Zonotope:
    Z = as_zonotope(x0, name)  # a box exactly, an ellipsoid by its bounding box
    if Z.n != n:
        raise DimensionError(f"{name}: expected a set of dimension {n}, got {Z.n}")
    return Z


@dataclass(frozen=True)
class Hypothesis:
    """A model under which the data may be explained: ``system`` and initial set ``x0`` (a
    zonotope or box of its state, which may be augmented by a user-defined model), and
    ``ignore_outputs``: outputs whose readings the model does not explain (their readings are
    treated as missing). User-defined hypotheses are built directly.

    Parameters
    ----------
    name : str
        Name.
    system : LinearSystem
        The model.
    x0 : Zonotope or Box
        Its initial set.
    ignore_outputs : tuple of int, optional
        Outputs the model does not explain.
    """

    name: str
    system: LinearSystem
    x0: object
    ignore_outputs: tuple = ()

    def data(self, y: np.ndarray) -> np.ndarray:
        """The readings this model explains (ignored outputs set to NaN).

        Parameters
        ----------
        y : ndarray, shape (N, n_y)
            Measurements.

        Returns
        -------
        ndarray
        """
        if not self.ignore_outputs:
            return y
        y = np.array(y, dtype=float, copy=True)
        y[:, list(self.ignore_outputs)] = np.nan
        return y


def nominal(system, x0, name: str = "nominal") -> Hypothesis:
    """No fault.

    Parameters
    ----------
    system : LinearSystem
        The nominal model.
    x0 : Zonotope or Box
        Initial set.
    name : str, optional
        Name of the hypothesis.

    Returns
    -------
    Hypothesis
    """
    name = as_str(name, "name")
    s = as_system(system)
    return Hypothesis(name, s, _zonotope(x0, s.nx))


def sensor_bias(system, x0, output: int, bound: float, name: str | None = None) -> Hypothesis:
    """Output ``output`` is off by an unknown bias ``|b_k| ≤ bound`` that may appear at any step
    and vary: an extra noise column of size ``bound`` on that output (an outer model of every
    bias within the bound, whenever it starts). A constant bias as an augmented state
    (``b⁺ = b``) would be tighter, but it cannot explain a bias that appears mid-record, which
    is what a fault does.

    Parameters
    ----------
    system : LinearSystem
        The nominal model.
    x0 : Zonotope or Box
        Initial set.
    output : int
        The output.
    bound : float
        Bound of the bias.
    name : str, optional
        Name of the hypothesis (default: from the kind and index).

    Returns
    -------
    Hypothesis
    """
    name = None if name is None else as_str(name, "name")
    s = as_system(system)
    i = as_int(output, "output", lo=0, hi=s.ny - 1)
    bound = as_float(bound, "bound", lo=0.0, lo_open=True)
    col = np.zeros((s.ny, 1))
    col[i, 0] = bound
    E = np.hstack([s.E, np.zeros((s.nx, 1))])
    F = np.hstack([s.F, col])
    A_arg = s.A_interval if s.uncertain_A else s.A
    aug = LinearSystem(A_arg, s.C, B=s.B if s.nu else None, D=s.D if s.nu else None, E=E, F=F)
    return Hypothesis(name or f"sensor_bias[y{i}]", aug, _zonotope(x0, s.nx))


def stuck_sensor(system, x0, output: int, name: str | None = None) -> Hypothesis:
    """Output ``output`` reads nothing about the state (stuck, dead or drifting): its readings
    are not explained, the others are.

    Parameters
    ----------
    system : LinearSystem
        The nominal model.
    x0 : Zonotope or Box
        Initial set.
    output : int
        The output.
    name : str, optional
        Name of the hypothesis (default: from the kind and index).

    Returns
    -------
    Hypothesis

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.5]], C=[[1.0], [1.0]], E=[[0.1, 0.0, 0.0]], F=[[0.0, 0.1, 0.0], [0.0, 0.0, 0.1]])
    >>> x0 = setbound.Box([-1.0], [1.0])
    >>> setbound.fault.stuck_sensor(sys, x0, 0).ignore_outputs
    (0,)
    """
    name = None if name is None else as_str(name, "name")
    s = as_system(system)
    i = as_int(output, "output", lo=0, hi=s.ny - 1)
    return Hypothesis(name or f"stuck_sensor[y{i}]", s, _zonotope(x0, s.nx), ignore_outputs=(i,))


def actuator_loss(system, x0, input: int, max_loss: float, u_max: float, name: str | None = None) -> Hypothesis:
    """Input ``input`` loses up to ``max_loss`` (in [0, 1]) of its effectiveness: the plant sees
    ``θ u_j`` with ``θ ∈ [1 − max_loss, 1]``. With ``|u_j| ≤ u_max`` the difference
    ``(θ − 1) u_j`` is an extra disturbance column ``B_j · max_loss · u_max`` (an outer model).

    Parameters
    ----------
    system : LinearSystem
        The nominal model.
    x0 : Zonotope or Box
        Initial set.
    input : int
        The input.
    max_loss : float
        Largest lost fraction, in [0, 1].
    u_max : float
        Bound of ``|u_j|``.
    name : str, optional
        Name of the hypothesis (default: from the kind and index).

    Returns
    -------
    Hypothesis
    """
    name = None if name is None else as_str(name, "name")
    s = as_system(system)
    if s.nu == 0:
        raise InvalidArgumentError("input: the system has no input")
    j = as_int(input, "input", lo=0, hi=s.nu - 1)
    max_loss = as_float(max_loss, "max_loss", lo=0.0, hi=1.0)
    u_max = as_float(u_max, "u_max", lo=0.0)
    E = np.hstack([s.E, (s.B[:, j] * max_loss * u_max)[:, None]])
    F = np.hstack([s.F, (s.D[:, j] * max_loss * u_max)[:, None]])
    A_arg = s.A_interval if s.uncertain_A else s.A
    aug = LinearSystem(A_arg, s.C, B=s.B, D=s.D, E=E, F=F)
    return Hypothesis(name or f"actuator_loss[u{j}]", aug, _zonotope(x0, s.nx))


def parameter_change(system, x0, A, name: str = "parameter_change") -> Hypothesis:
    """The plant's ``A`` changed to ``A`` (a matrix or an interval matrix).

    Parameters
    ----------
    system : LinearSystem
        The nominal model.
    x0 : Zonotope or Box
        Initial set.
    A : array_like or IntervalMatrix
        The changed matrix.
    name : str, optional
        Name of the hypothesis.

    Returns
    -------
    Hypothesis
    """
    name = as_str(name, "name")
    s = as_system(system)
    changed = LinearSystem(A, s.C, B=s.B if s.nu else None, D=s.D if s.nu else None, E=s.E, F=s.F)
    if changed.nx != s.nx:
        raise DimensionError(f"A: expected shape ({s.nx}, {s.nx}), got ({changed.nx}, {changed.nx})")
    return Hypothesis(name, changed, _zonotope(x0, s.nx))


def _segment_min(system, x0):
    from .zonotopic import SegmentMinEstimator

    return SegmentMinEstimator(system, x0)


@dataclass
class Isolation:
    """What a :class:`FaultBank` concluded. ``names`` of the hypotheses; ``consistent`` (N × H
    bools): hypothesis h is still consistent after step k (once rejected, always rejected);
    ``rejected_at`` per hypothesis the step of its rejection (None: never); ``detections`` the
    :class:`Detection` of each hypothesis' estimator.

    Parameters
    ----------
    names : list of str
        Hypothesis names.
    consistent : ndarray of bool, shape (N, H)
        Consistency per step and hypothesis.
    rejected_at : list of int or None
        Step of each rejection.
    detections : list of Detection, optional
        Per hypothesis.
    """

    names: list
    consistent: np.ndarray
    rejected_at: list
    detections: list = field(default_factory=list)

    @property
    def consistent_at_end(self) -> list:
        """The hypotheses no reading contradicted."""
        return [n for n, r in zip(self.names, self.rejected_at) if r is None]

    def table(self) -> str:
        """One line per hypothesis: rejected at step k, or consistent."""
        w = max(len(n) for n in self.names) if self.names else 0
        return "\n".join(f"{n:<{w}}  " + ("consistent" if r is None else f"rejected at step {r}")
                         for n, r in zip(self.names, self.rejected_at))


class FaultBank:
    """A bank of guaranteed estimators, one per :class:`Hypothesis`; ``estimator(system, x0)``
    builds each (default: :class:`~setbound.zonotopic.SegmentMinEstimator`; any estimator that
    tests its readings with the ``"flag"`` policy works).

    Methods › Fault detection and isolation.

    Parameters
    ----------
    system : LinearSystem
        The nominal model.
    x0 : Zonotope or Box
        Initial set.
    hypotheses : sequence of Hypothesis
        The models to test.
    estimator : callable, optional
        ``estimator(system, x0)`` returning an estimator.

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.5]], C=[[1.0], [1.0]], E=[[0.1, 0.0, 0.0]], F=[[0.0, 0.1, 0.0], [0.0, 0.0, 0.1]])
    >>> x0 = setbound.Box([-1.0], [1.0])
    >>> sim = setbound.fault.simulate_faulty(sys, x0, 30, [setbound.fault.Fault("sensor_bias", start=10, output=1,
    ...                                                                      magnitude=1.0)], rng=2)
    >>> bank = setbound.fault.FaultBank(sys, x0, [setbound.fault.nominal(sys, x0),
    ...                                          setbound.fault.sensor_bias(sys, x0, 1, bound=2.0)])
    >>> bank.run(sim.y).consistent_at_end
    ['sensor_bias[y1]']
    """

    def __init__(self, system, x0, hypotheses: Sequence[Hypothesis], *,
                 estimator: Callable | None = None):
        self.system = as_system(system)
        hyps = list(hypotheses)
        if not hyps:
            raise InvalidArgumentError("hypotheses: give at least one (e.g. nominal(system, x0))")
        for h in hyps:
            if not isinstance(h, Hypothesis):
                raise InvalidArgumentError(f"hypotheses: expected Hypothesis items, got {type(h).__name__}")
            if h.system.ny != self.system.ny or h.system.nu != self.system.nu:
                raise DimensionError(f"hypotheses: {h.name!r} has {h.system.ny} outputs and {h.system.nu} inputs, "
                                     f"the system {self.system.ny} and {self.system.nu}")
        names = [h.name for h in hyps]
        if len(set(names)) != len(names):
            raise InvalidArgumentError("hypotheses: the names must be distinct")
        self.hypotheses = hyps
        if estimator is not None and not callable(estimator):
            raise InvalidArgumentError("estimator: expected a callable (system, x0) -> estimator")
        self._make = estimator or _segment_min
        self.x0 = x0

    def run(self, y, u=None) -> Isolation:
        """Runs every hypothesis on the record; see :class:`Isolation`.

        Parameters
        ----------
        y : array_like, shape (N, n_y)
            Measurements.
        u : array_like, shape (N, n_u), optional
            Inputs.

        Returns
        -------
        Isolation
        """
        y = np.asarray(y, dtype=float)
        if y.ndim != 2 or y.shape[1] != self.system.ny:
            raise DimensionError(f"y: expected shape (N, {self.system.ny}), got {y.shape}")
        N = y.shape[0]
        consistent = np.ones((N, len(self.hypotheses)), dtype=bool)
        rejected, detections = [], []
        for h_i, h in enumerate(self.hypotheses):
            det = detect(self._make(h.system, h.x0), h.data(y), u)
            detections.append(det)
            rejected.append(det.alarm)
            if det.alarm is not None:
                consistent[det.alarm:, h_i] = False
        return Isolation([h.name for h in self.hypotheses], consistent, rejected, detections)
