"""Zonotopic estimators (Methods › Zonotopic estimation).

The estimator structure of Methods › Zonotopic estimation › Estimator structure: exact prediction ``A X ⊕ E B`` (or the
[Le2013] inclusion for an interval ``A``), correction strip by strip with a gain ``λ``,
reduction to at most ``max_generators`` generators. The true state is in the set for any
``λ``; the gain rule only decides the size.

Available: :class:`SegmentMinEstimator` ([Alamo2005] segment minimisation, Methods › Zonotopic estimation › Segment minimisation),
:class:`VolumeMinEstimator` ([Alamo2005] volume minimisation, an LP per strip, › Volume minimisation),
:class:`PRadiusEstimator` with the offline gains of :func:`design_pradius` ([Le2013],
approaches 1 and 2, › P-radius designs), and the accuracy reference :func:`exact_hull`.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._native import as_f64, check, dptr, ffi, lib
from ._state import StateMixin, reconstructible, remember_call, run_from_initial_set
from ._validate import as_bool, as_choice, as_float, as_int, check_memory
from .errors import DimensionError, InvalidArgumentError
from .measurement import POLICIES, ReadingChecks, measurement_or_missing
from .sets import Zonotope, as_zonotope
from .system import as_system, LinearSystem, run_inputs, step_inputs
from .trajectory import Trajectory


def _check_system_and_x0(system, x0, name: str = "x0") -> Zonotope:
    """The system must be a LinearSystem; ``x0`` a set of its state dimension, returned as a
    Zonotope (a box exactly, an ellipsoid by its bounding box: setbound.sets.as_zonotope; the C
    ABI takes the dimension from the system and cannot check the caller's arrays)."""
    if not isinstance(system, LinearSystem):
        raise InvalidArgumentError(f"system: expected a setbound.LinearSystem, got {type(system).__name__}")
    x0 = as_zonotope(x0, name)
    if x0.n != system.nx:
        raise DimensionError(f"{name}: expected a zonotope of dimension {system.nx}, got {x0.n}")
    return x0


#: Order reductions of the zonotopic estimators (keyword ``reduction``).
REDUCTIONS = {"combastel": lib.SB_ZONO_REDUCE_COMBASTEL, "girard": lib.SB_ZONO_REDUCE_GIRARD,
              "pca": lib.SB_ZONO_REDUCE_PCA}


#: Upper bound of ``max_generators`` (see :class:`_ZonotopicEstimator`).
MAX_GENERATORS = lib.SB_ZONO_MAX_GENERATORS  # 100000, the C library refuses more too


class _ZonotopicEstimator(ReadingChecks, StateMixin):
    """Common options: ``max_generators`` (the reduction limit; the pending rounding box of
    relative size ~1e-15 is not counted, so before the first reduction a set may carry up to
    n_x more axis-aligned generators), ``use_first_measurement``, ``strip_order`` and
    ``reduction``: ``"combastel"`` (default, Methods › Sets, intervals and LMI tools › Ellipsoids), ``"girard"`` (CORA's default) or
    ``"pca"`` (CORA's ``reduce(Z,'pca',order)``, used by its observer examples).

    ``max_generators`` is an integer in [n_x, ``MAX_GENERATORS``] (100000: the reduction sorts
    and the correction touches every generator at every step, and the sets are n_x × m arrays;
    CORA's observers use orders up to about 100); ``use_first_measurement`` a bool.

    Real data (:mod:`setbound.measurement`): NaN entries of ``y`` (or ``step(None)``) are missing
    outputs; a reading outside the predicted output set is never used and is handled by
    ``on_inconsistency``: ``"flag"`` (default), ``"raise"`` or ``"reset"`` (restart from
    ``reset_set``, a :class:`~setbound.sets.Zonotope`, by default ``x0``). ``last_check`` and the
    trajectory's ``status`` and ``margin`` report what each step did with each output."""

    _gain: int
    #: row k of a trajectory used y_k (Trajectory.filter)
    is_filter = True
    _last_check_fn = lib.sb_zonotopic_last_check
    _lambdas = None
    _state_prefix = "sb_zonotopic"

    def __init__(self, system: LinearSystem, x0: Zonotope, *, max_generators: int = 20,
                 use_first_measurement: bool = True, strip_order=None, reduction: str = "combastel",
                 on_inconsistency: str = "flag", reset_set: Zonotope | None = None):
        system = as_system(system)
        x0 = _check_system_and_x0(system, x0)
        max_generators = as_int(max_generators, "max_generators", lo=1, hi=MAX_GENERATORS)
        # two n_x × (max_generators + ...) generator matrices and the reduction's workspace
        check_memory("max_generators", max_generators,
                     4 * 8.0 * system.nx * (max_generators + system.nx + system.ny + system.nw))
        use_first_measurement = as_bool(use_first_measurement, "use_first_measurement")
        reduction = as_choice(reduction, "reduction", REDUCTIONS)
        on_inconsistency = as_choice(on_inconsistency, "on_inconsistency", POLICIES)
        if reset_set is not None:
            if on_inconsistency != "reset":
                raise InvalidArgumentError('reset_set: only used with on_inconsistency="reset"')
            reset_set = as_zonotope(reset_set, "reset_set")
            if reset_set.n != system.nx:
                raise DimensionError(f"reset_set: expected a zonotope of dimension {system.nx}, got {reset_set.n}")
        self.system = system
        order_ptr = ffi.NULL
        if strip_order is not None:
            order = np.asarray(strip_order)
            if order.shape != (system.ny,) or not np.issubdtype(order.dtype, np.integer):
                raise InvalidArgumentError(f"strip_order: expected {system.ny} integers (a permutation of the outputs)")
            self._order = ffi.new("int[]", [int(i) for i in order])
            order_ptr = self._order
        handle = ffi.new("sb_zonotopic**")
        lam = ffi.NULL if self._lambdas is None else dptr(self._lambdas)
        check(lib.sb_zonotopic_create(system._handle, self._gain, lam, max_generators,
                                      1 if use_first_measurement else 0, order_ptr, x0.m,
                                      dptr(x0.center), dptr(x0.generators), handle))
        self._handle = ffi.gc(handle[0], lib.sb_zonotopic_free)
        check(lib.sb_zonotopic_set_reduction(self._handle, REDUCTIONS[reduction]))
        self.reduction = reduction
        if reset_set is None:
            check(lib.sb_zonotopic_set_inconsistency_policy(self._handle, POLICIES[on_inconsistency], 0, ffi.NULL,
                                                            ffi.NULL))
        else:
            check(lib.sb_zonotopic_set_inconsistency_policy(self._handle, POLICIES[on_inconsistency], reset_set.m,
                                                            dptr(reset_set.center), dptr(reset_set.generators)))
        self.on_inconsistency = on_inconsistency
        self._m = ffi.new("int*")
        self._init_checks()

    def restore_state(self, state) -> None:
        """Restore a state from ``save_state`` (the reduction method is part of the state).

        Parameters
        ----------
        state : bytes
            A state returned by ``save_state`` of an estimator of the same kind and design.
        """
        super().restore_state(state)
        code = int(np.frombuffer(bytes(state), dtype="<f8")[7])
        self.reduction = {v: k for k, v in REDUCTIONS.items()}.get(code, self.reduction)

    def _step(self, y, u):
        s = self.system
        y, up = step_inputs(s, measurement_or_missing(y, s.ny), u)
        c, lo, hi = np.empty(s.nx), np.empty(s.nx), np.empty(s.nx)
        check(lib.sb_zonotopic_step(self._handle, dptr(y), up,
                                    dptr(c), dptr(lo), dptr(hi), self._m))
        return c, lo, hi

    def _last_set(self) -> Zonotope:
        m = self._m[0]
        p, H = np.empty(self.system.nx), np.empty((self.system.nx, m))
        cap = ffi.new("int*", m)
        check(lib.sb_zonotopic_last_set(self._handle, cap, dptr(p), dptr(H)))
        return Zonotope(p, H)

    def step(self, y, u=None) -> Zonotope:
        """Use ``y_k`` (and ``u_k``): returns the set for ``x_k`` and predicts ``x_{k+1}``.

        See ``last_check`` for what the step did with each output.

        Parameters
        ----------
        y : array_like, shape (n_y,), or None
            The measurement ``y_k`` (None or NaN entries: missing outputs).
        u : array_like, shape (n_u,), optional
            The input ``u_k``.

        Returns
        -------
        Zonotope
        """
        self._step(y, u)
        return self._last_set()

    @property
    def steps(self) -> int:
        """Number of steps taken (a filter: the last step's set bounds ``x_{steps−1}``)."""
        s = ffi.new("int*")
        check(lib.sb_zonotopic_steps(self._handle, s))
        return int(s[0])

    def reset(self) -> None:
        """Back to the initial set, no step taken (the options are kept)."""
        check(lib.sb_zonotopic_reset(self._handle))

    @run_from_initial_set
    def run(self, y, u=None) -> Trajectory:
        """Process a record from the initial set; row ``k`` is about ``x_k``.

        Parameters
        ----------
        y : array_like, shape (N, n_y), or control.TimeResponseData
            Measurements (NaN entries: missing outputs). A python-control ``TimeResponseData`` gives the
            outputs, known inputs and time.
        u : array_like, shape (N, n_u), optional
            Known inputs.
        reset : bool, optional
            Start from the initial set (default). ``False`` continues from the current state, to process
            a record in pieces. A failed run leaves the estimator as it was.
        t : array_like, shape (N,), optional
            Time of the rows (default: ``k·dt`` with the system's sampling time, else the step index).

        Returns
        -------
        Trajectory
            Row ``k`` is about ``x_k``; ``status``, ``margin`` and ``resets`` say what each step did
            with each reading.
        """
        s = self.system
        y, u = run_inputs(s, y, u)
        N = y.shape[0]
        centers, lows, highs, sets = np.empty((N, s.nx)), np.empty((N, s.nx)), np.empty((N, s.nx)), []
        status, margin = np.empty((N, s.ny), dtype=np.int8), np.empty((N, s.ny))
        resets = np.zeros(N, dtype=bool)
        for k in range(N):
            centers[k], lows[k], highs[k] = self._step(y[k], u[k] if s.nu > 0 else None)
            sets.append(self._last_set())
            resets[k] = self._check_into(status[k], margin[k])
        return Trajectory(centers, lows, highs, sets, status=status, margin=margin, resets=resets)


@reconstructible
class SegmentMinEstimator(_ZonotopicEstimator):
    """Zonotopic estimator with segment minimisation ([Alamo2005]).

    Per strip, ``λ* = H Hᵀ c / (cᵀ H Hᵀ c + φ²)``, the minimiser of the squared generator lengths
    (Methods › Zonotopic estimation › Segment minimisation). A filter.

    Parameters
    ----------
    system : LinearSystem
        The model (``A`` may be an interval matrix).
    x0 : Zonotope, Box or Ellipsoid
        Initial set (a box exactly, an ellipsoid by its bounding box).
    max_generators : int, optional
        Generators kept after each step (order reduction).
    use_first_measurement : bool, optional
        Correct the initial set with ``y_0`` (row 0 is then a filtered set).
    strip_order : sequence of int, optional
        Order in which the output strips are applied (default: natural order).
    reduction : {"combastel", "girard", "pca"}, optional
        Order-reduction method (:meth:`~setbound.sets.Zonotope.reduce`).
    on_inconsistency : {"flag", "raise", "reset"}, optional
        What a reading outside the predicted output set does (:mod:`setbound.measurement`):
        skipped and flagged (default), an :class:`~setbound.errors.InconsistentMeasurementError`,
        or a restart from ``reset_set``.
    reset_set : optional
        The restart set of ``on_inconsistency="reset"`` (default: the initial set).

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.9, 0.2], [0.0, 0.7]], C=[[1.0, 0.0]],
    ...                             E=[[0.1, 0.0], [0.0, 0.0]], F=[[0.0, 0.05]])
    >>> est = setbound.zonotopic.SegmentMinEstimator(sys, setbound.Box([-1, -1], [1, 1]))
    >>> traj = est.run(np.zeros((5, 1)))
    >>> bool(traj.contains(np.zeros((5, 2))).all())
    True
    """

    _gain = lib.SB_ZONO_GAIN_SEGMENT_MIN


@reconstructible
class VolumeMinEstimator(_ZonotopicEstimator):
    """Zonotopic estimator with volume minimisation ([Alamo2005]).

    Per strip, the ``λ`` minimising the exact volume of the corrected zonotope, found by a linear
    program on the bundled solver (Methods › Zonotopic estimation › Volume minimisation). A filter.

    Parameters
    ----------
    system : LinearSystem
        The model (``A`` may be an interval matrix).
    x0 : Zonotope, Box or Ellipsoid
        Initial set (a box exactly, an ellipsoid by its bounding box).
    max_generators : int, optional
        Generators kept after each step (order reduction).
    use_first_measurement : bool, optional
        Correct the initial set with ``y_0`` (row 0 is then a filtered set).
    strip_order : sequence of int, optional
        Order in which the output strips are applied (default: natural order).
    reduction : {"combastel", "girard", "pca"}, optional
        Order-reduction method (:meth:`~setbound.sets.Zonotope.reduce`).
    on_inconsistency : {"flag", "raise", "reset"}, optional
        What a reading outside the predicted output set does (:mod:`setbound.measurement`):
        skipped and flagged (default), an :class:`~setbound.errors.InconsistentMeasurementError`,
        or a restart from ``reset_set``.
    reset_set : optional
        The restart set of ``on_inconsistency="reset"`` (default: the initial set).

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.0, -0.5], [1.0, 1.0]], C=[[-2.0, 1.0], [1.0, 1.0]],
    ...                             E=[[-0.12, 0, 0], [0.02, 0, 0]], F=[[0, 0.2, 0], [0, 0, 0.2]])
    >>> est = setbound.zonotopic.VolumeMinEstimator(sys, setbound.Box([-3, -3], [3, 3]))
    >>> bool(est.run(np.zeros((3, 2))).contains(np.zeros((3, 2))).all())
    True
    """

    _gain = lib.SB_ZONO_GAIN_VOLUME_MIN


@dataclass(frozen=True)
class ExactHull:
    """Interval hull of the exact consistent state set; row ``k`` is about ``x_k``.

    Parameters
    ----------
    lower, upper : ndarray, shape (N, n_x)
        The hull's bounds per step.
    """

    lower: np.ndarray
    upper: np.ndarray


def exact_hull(system: LinearSystem, y, u=None, *, x0: Zonotope, use_first_measurement: bool = True) -> ExactHull:
    """The exact reference: the interval hull of the states consistent with the data (known ``A`` only).

    For each step, ``2 n_x`` linear programs over the initial set and every disturbance give the
    interval hull of the states consistent with ``y_0 … y_k`` (Methods › Zonotopic estimation ›
    The exact reference hull). Slow by nature; every guaranteed estimator's hull contains it.

    Parameters
    ----------
    system : LinearSystem
        The model (``A`` a real matrix).
    y : array_like, shape (N, n_y)
        Measurements (NaN entries: missing outputs, no constraint).
    u : array_like, shape (N, n_u), optional
        Known inputs.
    x0 : Zonotope
        Initial set.
    use_first_measurement : bool, optional
        Use ``y_0`` in row 0.

    Returns
    -------
    ExactHull

    Raises
    ------
    InfeasibleError
        When no state can produce the data.

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.0, -0.5], [1.0, 1.0]], C=[[-2.0, 1.0], [1.0, 1.0]],
    ...                             E=[[-0.12, 0, 0], [0.02, 0, 0]], F=[[0, 0.2, 0], [0, 0, 0.2]])
    >>> x0 = setbound.Zonotope([0.0, 0.0], 3 * np.eye(2))
    >>> y = np.zeros((3, 2))
    >>> hull = setbound.exact_hull(sys, y, x0=x0)
    >>> est = setbound.zonotopic.SegmentMinEstimator(sys, x0).run(y)
    >>> bool(np.all(est.lower <= hull.lower + 1e-9) and np.all(hull.upper <= est.upper + 1e-9))
    True
    """
    use_first_measurement = as_bool(use_first_measurement, "use_first_measurement")
    system = as_system(system)
    x0 = _check_system_and_x0(system, x0)
    y = as_f64(y, "y", shape=(None, system.ny))
    N = y.shape[0]
    if system.nu > 0:
        u = as_f64(u, "u", shape=(N, system.nu))
    lower, upper = np.empty((N, system.nx)), np.empty((N, system.nx))
    check(lib.sb_exact_hull(system._handle, x0.m, dptr(x0.center), dptr(x0.generators), N, dptr(y),
                            dptr(u) if system.nu > 0 else ffi.NULL, 1 if use_first_measurement else 0,
                            dptr(lower), dptr(upper)))
    return ExactHull(lower, upper)


@dataclass(frozen=True)
class PRadiusDesign:
    """Offline P-radius gains ([Le2013]), one per output strip.

    Methods › Zonotopic estimation › P-radius designs. The P-radius recursion is
    ``L_k <= beta L_{k-1} + psi + sum phi^2``.

    Parameters
    ----------
    system : LinearSystem
        The system designed for.
    approach : int
        1 or 2 (see :func:`design_pradius`).
    strip_order : ndarray of int
        Order in which the strips are applied.
    lambdas : ndarray, shape (n_y, n_x)
        Row ``i`` is the gain of output ``i``.
    P : ndarray, shape (n_y, n_x, n_x)
        Certificate matrix of each strip.
    beta : ndarray, shape (n_y,)
        Contraction factor of each strip's certificate.
    tau : ndarray, shape (n_y,)
        Smallest eigenvalue of each normalised limit ellipsoid.
    psi : float
        Disturbance term of the recursion.
    """

    system: LinearSystem
    approach: int
    strip_order: np.ndarray
    lambdas: np.ndarray
    P: np.ndarray
    beta: np.ndarray
    tau: np.ndarray
    psi: float


def design_pradius(system: LinearSystem, approach: int = 1, order=None, *,
                   beta_range: tuple[float, float] = (1e-3, 1 - 1e-3)) -> PRadiusDesign:
    """P-radius gain design of [Le2013].

    ``approach=1`` designs every strip alone; ``approach=2`` designs strip ``j`` with the earlier
    gains fixed (Methods › Zonotopic estimation › P-radius designs).

    Parameters
    ----------
    system : LinearSystem
        The model.
    approach : int, optional
        The integer 1 or 2 (not ``True``).
    order : sequence of int or "best", optional
        A permutation of the outputs, ``None`` (natural order) or ``"best"`` (approach 2: try every
        order, keep the one with the largest final ``tau``).
    beta_range : (float, float), optional
        ``beta`` is chosen in this range by a scalar search maximising ``tau``; ``0 < lo < hi < 1``.

    Returns
    -------
    PRadiusDesign

    Raises
    ------
    InfeasibleError
        When no gain contracts.

    Examples
    --------
    The system of [Le2013] with a known ``A``:

    >>> sys = setbound.LinearSystem(A=[[0.0, -0.5], [1.0, 1.0]], C=[[-2.0, 1.0], [1.0, 1.0]],
    ...                             E=[[-0.12, 0, 0], [0.02, 0, 0]], F=[[0, 0.2, 0], [0, 0, 0.2]])
    >>> d = setbound.zonotopic.design_pradius(sys, approach=2)
    >>> d.lambdas.shape, bool(np.all((0 < d.beta) & (d.beta < 1)))
    ((2, 2), True)
    """
    system = as_system(system)
    if not isinstance(system, LinearSystem):
        raise InvalidArgumentError(f"system: expected a setbound.LinearSystem, got {type(system).__name__}")
    approach = as_choice(approach, "approach", (1, 2))
    try:
        lo, hi = beta_range
    except (TypeError, ValueError):
        raise InvalidArgumentError(f"beta_range: expected a pair (lo, hi) with 0 < lo < hi < 1, got {beta_range!r}") \
            from None
    lo = as_float(lo, "beta_range[0]", lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    hi = as_float(hi, "beta_range[1]", lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    if not lo < hi:
        raise InvalidArgumentError(f"beta_range: expected lo < hi, got ({lo:g}, {hi:g})")
    ny, nx = system.ny, system.nx
    try_all = isinstance(order, str)
    if try_all and order != "best":
        raise InvalidArgumentError(f"order: expected a permutation of the outputs, None or 'best', got {order!r}")
    order_ptr = ffi.NULL
    if order is not None and not try_all:
        o = np.asarray(order)
        if o.shape != (ny,) or not np.issubdtype(o.dtype, np.integer):
            raise InvalidArgumentError(f"order: expected {ny} integers (a permutation of the outputs)")
        order_ptr = ffi.new("int[]", [int(i) for i in o])
    lambdas, P = np.empty((ny, nx)), np.empty((ny, nx, nx))
    beta, tau, used = np.empty(ny), np.empty(ny), ffi.new("int[]", ny)
    psi = ffi.new("double*")
    check(lib.sb_pradius_design(system._handle, approach, order_ptr, 1 if try_all else 0, lo, hi,
                                dptr(lambdas), dptr(P), dptr(beta), dptr(tau), psi, used))
    return PRadiusDesign(system, approach, np.array([used[i] for i in range(ny)]), lambdas, P, beta, tau,
                         float(psi[0]))


@reconstructible
class PRadiusEstimator(_ZonotopicEstimator):
    """Zonotopic estimator with the offline P-radius gains of a :class:`PRadiusDesign`, applied in the design's strip order.

    Methods › Zonotopic estimation › P-radius designs ([Le2013]). A filter.

    Parameters
    ----------
    design : PRadiusDesign
        The gains (:func:`design_pradius`).
    x0 : Zonotope, Box or Ellipsoid
        Initial set (a box exactly, an ellipsoid by its bounding box).
    max_generators : int, optional
        Generators kept after each step (order reduction).
    use_first_measurement : bool, optional
        Correct the initial set with ``y_0`` (row 0 is then a filtered set).
    reduction : {"combastel", "girard", "pca"}, optional
        Order-reduction method (:meth:`~setbound.sets.Zonotope.reduce`).
    on_inconsistency : {"flag", "raise", "reset"}, optional
        What a reading outside the predicted output set does (:mod:`setbound.measurement`):
        skipped and flagged (default), an :class:`~setbound.errors.InconsistentMeasurementError`,
        or a restart from ``reset_set``.
    reset_set : optional
        The restart set of ``on_inconsistency="reset"`` (default: the initial set).

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.0, -0.5], [1.0, 1.0]], C=[[-2.0, 1.0], [1.0, 1.0]],
    ...                             E=[[-0.12, 0, 0], [0.02, 0, 0]], F=[[0, 0.2, 0], [0, 0, 0.2]])
    >>> est = setbound.zonotopic.PRadiusEstimator(setbound.zonotopic.design_pradius(sys),
    ...                                             setbound.Box([-3, -3], [3, 3]))
    >>> bool(est.run(np.zeros((5, 2))).contains(np.zeros((5, 2))).all())
    True
    """

    _gain = lib.SB_ZONO_GAIN_FIXED

    def __init__(self, design: PRadiusDesign, x0: Zonotope, *, max_generators: int = 20,
                 use_first_measurement: bool = True, reduction: str = "combastel", on_inconsistency: str = "flag",
                 reset_set: Zonotope | None = None):
        if not isinstance(design, PRadiusDesign):
            raise InvalidArgumentError(f"design: expected a PRadiusDesign, got {type(design).__name__}")
        self.design = design
        self._lambdas = np.ascontiguousarray(design.lambdas, dtype=float)
        super().__init__(design.system, x0, max_generators=max_generators,
                         use_first_measurement=use_first_measurement, strip_order=design.strip_order,
                         reduction=reduction, on_inconsistency=on_inconsistency, reset_set=reset_set)


# ---- CORA's names (setbound.cora.observe) -------------------------------------------------------

def _cora_runner(cls):
    """FRad-A / VolMin-A: the estimator with the model's zonotope order and reduction technique
    (CORA's settings); the two conventions coincide for these methods."""
    def runner(model, *, convention, gain, **options):
        est = cls(model.system, model.x0, **{**model.estimator_options(), **options})

        def run():
            t = est.run(model.y, model.u)
            return t.lower, t.upper, t.sets
        return run
    return runner


def _register_cora_names():
    from .cora import register_algorithm
    register_algorithm("FRad-A", _cora_runner(SegmentMinEstimator),
                       summary="segment (F-radius) minimisation per strip [Alamo 2005] = SegmentMinEstimator")
    register_algorithm("VolMin-A", _cora_runner(VolumeMinEstimator),
                       summary="exact volume minimisation per strip (LP) [Alamo 2005] = VolumeMinEstimator")


_register_cora_names()
