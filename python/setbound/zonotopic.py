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


# ---- CORA's zonotopic catalogue on one skeleton (estimators/zonotopic/observer.hpp) ----------------

#: ``convention`` keyword of the observers below: the papers' algorithms or CORA's behaviour.
CONVENTIONS = {"setbound": lib.SB_CONVENTION_SETBOUND, "cora": lib.SB_CONVENTION_CORA}


class _ZonotopicObserver(ReadingChecks, StateMixin):
    """The shared zonotopic skeleton of CORA's catalogue with one gain rule (the varying part).

    Strip-based rules are filters (row ``k`` of a run is the set for ``x_k`` after ``y_k``);
    intersection-free rules are predictors (row ``k`` uses ``y_0 … y_{k−1}``; row 0 is ``x0``).
    Every rule is guaranteed: the correction is an outer bound for any weight, and rounding is
    carried in a pending box that the reduction absorbs. ``convention="cora"`` reproduces CORA's
    behaviour where it differs from the papers (see each class). NaN entries of ``y`` are missing
    outputs (their strips or gain columns are not used).

    Real data (:mod:`setbound.measurement`, ``convention="setbound"``): every reading is tested
    against the output set of the set the step corrects (a filter's prior, a predictor's current
    set, widened by the noise bound); one outside it is never used and is handled by
    ``on_inconsistency``: ``"flag"`` (default), ``"raise"`` or ``"reset"`` (restart from ``x0``).
    ``last_check`` and the trajectory's ``status`` and ``margin`` report it (a margin <= 0 may be an
    upper bound: readings well inside are decided by a cheap lower bound of the radius).
    ``convention="cora"`` tests nothing, as CORA, and accepts only ``"flag"``."""

    _rule: int
    _takes_gain = False
    _state_prefix = "sb_zono_observer"
    _last_check_fn = lib.sb_zono_observer_last_check
    is_filter = True

    def __init__(self, system: LinearSystem, x0: Zonotope, *, gain=None, max_generators: int = 20,
                 reduction: str = "combastel", convention: str = "setbound", on_inconsistency: str = "flag"):
        system = as_system(system)
        x0 = _check_system_and_x0(system, x0)
        max_generators = as_int(max_generators, "max_generators", lo=1, hi=MAX_GENERATORS)
        check_memory("max_generators", max_generators,
                     4 * 8.0 * system.nx * (max_generators + system.nx + system.ny + system.nw))
        reduction = as_choice(reduction, "reduction", REDUCTIONS)
        convention = as_choice(convention, "convention", CONVENTIONS)
        on_inconsistency = as_choice(on_inconsistency, "on_inconsistency", POLICIES)
        if not self.is_filter and system.A_rad is not None and np.any(np.asarray(system.A_rad) != 0):
            raise InvalidArgumentError(f"system: {type(self).__name__} needs a known A (an interval A is not supported "
                                       "by the intersection-free rules; the strip-based filters take one)")
        gptr = ffi.NULL
        if self._takes_gain:
            self._gain_matrix = as_f64(gain, "gain", shape=(system.nx, system.ny))
            gptr = dptr(self._gain_matrix)
        self.system = system
        self.x0 = x0
        self.max_generators = max_generators
        self.reduction = reduction
        self.convention = convention
        handle = ffi.new("sb_zono_observer**")
        check(lib.sb_zono_observer_create(system._handle, self._rule, gptr, max_generators, REDUCTIONS[reduction],
                                          CONVENTIONS[convention], x0.m, dptr(x0.center), dptr(x0.generators), handle))
        self._handle = ffi.gc(handle[0], lib.sb_zono_observer_free)
        check(lib.sb_zono_observer_set_inconsistency_policy(self._handle, POLICIES[on_inconsistency]))
        self.on_inconsistency = on_inconsistency
        self._m = ffi.new("int*")
        self._init_checks()

    @property
    def steps(self) -> int:
        """Number of steps taken."""
        s = ffi.new("int*")
        check(lib.sb_zono_observer_steps(self._handle, s))
        return int(s[0])

    @property
    def last_gain(self) -> np.ndarray:
        """The weight of the last step, shape ``(n_x, n_y)`` (``Λ``, the strips' ``λ_i`` as columns, or
        ``L``); zero columns for missing or unused outputs."""
        g = np.empty((self.system.nx, self.system.ny))
        check(lib.sb_zono_observer_last_gain(self._handle, dptr(g)))
        return g

    def reset(self) -> None:
        """Back to the initial set, no step taken (the options are kept)."""
        check(lib.sb_zono_observer_reset(self._handle))

    def current_set(self) -> Zonotope:
        """The current set (the rounding box as axis-aligned generators): ``x_k`` after the step with
        ``y_k`` for a filter, ``x_{k+1}`` for a predictor (``x0`` before its first step).

        Returns
        -------
        Zonotope
        """
        m = ffi.new("int*", 0)
        p = np.empty(self.system.nx)
        code = lib.sb_zono_observer_current_set(self._handle, m, dptr(p), ffi.NULL)
        if code != lib.SB_ERR_BUFFER_TOO_SMALL:
            check(code)
        return self._set_of_size(m[0])

    def _set_of_size(self, m: int) -> Zonotope:
        # The current set when its generator count is known (a step reports it): one call, no
        # size query (which costs a C++ exception in the library).
        p, H = np.empty(self.system.nx), np.empty((self.system.nx, m))
        cap = ffi.new("int*", m)
        check(lib.sb_zono_observer_current_set(self._handle, cap, dptr(p), dptr(H)))
        return Zonotope(p, H)

    def _step(self, y, u):
        s = self.system
        y, up = step_inputs(s, measurement_or_missing(y, s.ny), u)
        c, lo, hi = np.empty(s.nx), np.empty(s.nx), np.empty(s.nx)
        check(lib.sb_zono_observer_step(self._handle, dptr(y), up, dptr(c), dptr(lo), dptr(hi), self._m))
        return c, lo, hi

    def step(self, y, u=None) -> Zonotope:
        """Use ``y_k`` (and ``u_k``): a filter returns the set for ``x_k``, a predictor the set for ``x_{k+1}``.

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
        return self._set_of_size(self._m[0])

    @run_from_initial_set
    def run(self, y, u=None) -> Trajectory:
        """Process a record from the initial set; row ``k`` is about ``x_k``.

        Parameters
        ----------
        y : array_like, shape (N, n_y), or control.TimeResponseData
            Measurements (NaN entries: missing outputs).
        u : array_like, shape (N, n_u), optional
            Known inputs.
        reset : bool, optional
            Start from the initial set (default); ``False`` continues. A failed run leaves the
            estimator as it was.
        t : array_like, shape (N,), optional
            Time of the rows.

        Returns
        -------
        Trajectory
            Filters: row ``k`` used ``y_0 … y_k``; predictors: ``y_0 … y_{k−1}`` (row 0 is ``x0``).
            ``status``, ``margin`` and ``resets``: what step ``k`` did with ``y_k`` (for a
            predictor, the step that made row ``k + 1``).
        """
        s = self.system
        y, u = run_inputs(s, y, u)
        N = y.shape[0]
        centers, lows, highs, sets = np.empty((N, s.nx)), np.empty((N, s.nx)), np.empty((N, s.nx)), []
        status, margin = np.empty((N, s.ny), dtype=np.int8), np.empty((N, s.ny))
        resets = np.zeros(N, dtype=bool)
        for k in range(N):
            if not self.is_filter:
                # the set for x_k: x0 (or the current set) before the first step, then the last step's
                z = self.current_set() if k == 0 else self._set_of_size(self._m[0])
                centers[k], lows[k], highs[k] = z.center, *self._hull(z)
                sets.append(z)
            c, lo, hi = self._step(y[k], u[k] if s.nu > 0 else None)
            resets[k] = self._check_into(status[k], margin[k])
            if self.is_filter:
                centers[k], lows[k], highs[k] = c, lo, hi
                sets.append(self._set_of_size(self._m[0]))
        return Trajectory(centers, lows, highs, sets, status=status, margin=margin, resets=resets)

    def _hull(self, z: Zonotope):
        # The C library's hull of the current set z (outward rounded); before a predictor's first
        # step it is the hull of x0 computed the same way.
        e = np.abs(z.generators).sum(axis=1) + np.finfo(float).eps * np.abs(z.center)
        e *= 1.0 + (z.m + self.system.nx + 4) * np.finfo(float).eps
        return z.center - e, z.center + e


_OBSERVER_PARAMETERS = """    max_generators : int, optional
        Generators kept after each step (order reduction; the rounding box is not counted).
    reduction : {"combastel", "girard", "pca"}, optional
        Order-reduction method (:meth:`~setbound.sets.Zonotope.reduce`; CORA's models use
        ``"girard"`` or ``"pca"``).
    convention : {"setbound", "cora"}, optional
        The papers' algorithm (default) or CORA's behaviour where it differs.
    on_inconsistency : {"flag", "raise", "reset"}, optional
        What a reading outside the output set of the set a step corrects does (skipped and
        flagged, an :class:`~setbound.errors.InconsistentMeasurementError`, or a restart from
        ``x0``); only ``"flag"`` with ``convention="cora"``, which tests nothing."""


@reconstructible
class BravoEstimator(_ZonotopicObserver):
    """Zonotopic filter with Bravo's candidate parallelotopes per strip (CORA's VolMin-B).

    Bravo, Alamo, Camacho, *Bounded error identification of systems with time-varying parameters*,
    IEEE TAC 51(7), 2006, Property 1: for each strip, the candidates are the set itself and, for
    every generator ``g_j`` with ``a = cᵀg_j ≠ 0``, the set with ``g_j`` replaced by the strip
    direction (``g_i − (cᵀg_i/a) g_j``, ``(σ/a) g_j``); the one with the smallest ``det(T Tᵀ)`` is
    kept (the first on ties). No generator is added. ``convention="cora"`` tests ``|a|`` against
    CORA's absolute threshold ``10¹⁰·eps`` instead of one relative to ``|c|ᵀ|g_j|`` and does not
    reduce the first set. Cost ``O(n² m)`` per strip: the determinant of candidate ``j`` is
    ``(σ/a)² det(G Gᵀ) g_jᵀ (G Gᵀ)⁻¹ g_j``, so one Cholesky factor scores them all (a flat set,
    ``G Gᵀ`` singular, has every determinant 0 and is kept).

    Parameters
    ----------
    system : LinearSystem
        The model (a known ``A``).
    x0 : Zonotope, Box or Ellipsoid
        Initial set.
{params}

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.9, 0.2], [0.0, 0.7]], C=[[1.0, 0.0]],
    ...                             E=[[0.1, 0.0], [0.0, 0.0]], F=[[0.0, 0.05]])
    >>> est = setbound.zonotopic.BravoEstimator(sys, setbound.Box([-1, -1], [1, 1]))
    >>> bool(est.run(np.zeros((5, 1))).contains(np.zeros((5, 2))).all())
    True
    """

    _rule = lib.SB_ZOBS_BRAVO

    def __init__(self, system: LinearSystem, x0: Zonotope, *, max_generators: int = 20, reduction: str = "combastel",
                 convention: str = "setbound", on_inconsistency: str = "flag"):
        super().__init__(system, x0, max_generators=max_generators, reduction=reduction, convention=convention,
                         on_inconsistency=on_inconsistency)


@reconstructible
class WangEstimator(_ZonotopicObserver):
    """Zonotopic filter with Wang et al.'s Kalman-like weight on all strips at once (CORA's FRad-B).

    Wang, Puig, Cembrano, *Set-membership approach and Kalman observer based on zonotopes for
    discrete-time descriptor systems*, Automatica 93, 2018, Thm. 2: ``Λ = R̄ Cᵀ (C R̄ Cᵀ + F Fᵀ)⁻¹``
    with ``R̄ = G Gᵀ`` of the predicted set, then ``p' = p + Λ(y − Cp)``,
    ``G' = [(I − ΛC) G, Λ diag(σ)]``. ``convention="cora"`` forms ``R̄ = A G Gᵀ Aᵀ + E Eᵀ`` from
    the predicted set as CORA does (the dynamics and the disturbance applied twice) and does not
    reduce the first set.

    Parameters
    ----------
    system : LinearSystem
        The model (a known ``A``).
    x0 : Zonotope, Box or Ellipsoid
        Initial set.
{params}

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.9, 0.2], [0.0, 0.7]], C=[[1.0, 0.0]],
    ...                             E=[[0.1, 0.0], [0.0, 0.0]], F=[[0.0, 0.05]])
    >>> est = setbound.zonotopic.WangEstimator(sys, setbound.Box([-1, -1], [1, 1]))
    >>> bool(est.run(np.zeros((5, 1))).contains(np.zeros((5, 2))).all())
    True
    """

    _rule = lib.SB_ZOBS_WANG

    def __init__(self, system: LinearSystem, x0: Zonotope, *, max_generators: int = 20, reduction: str = "combastel",
                 convention: str = "setbound", on_inconsistency: str = "flag"):
        super().__init__(system, x0, max_generators=max_generators, reduction=reduction, convention=convention,
                         on_inconsistency=on_inconsistency)


@reconstructible
class CombastelObserver(_ZonotopicObserver):
    """Intersection-free zonotopic predictor with Combastel's adaptive gain (CORA's FRad-C).

    Combastel, *Zonotopes and Kalman observers: Gain optimality under distinct uncertainty
    paradigms and robust convergence*, Automatica 55, 2015: ``L_k = A P Cᵀ (C P Cᵀ + F Fᵀ)⁻¹`` with
    ``P = G Gᵀ`` of the current set and
    ``X_{k+1} = (A − L_k C) X_k ⊕ (B u_k + L_k (y_k − D u_k)) ⊕ (E − L_k F) B``. A predictor: row
    ``k`` uses ``y_0 … y_{k−1}``. CORA omits the model's constant term here; setbound always keeps it
    (it is in ``B u``), and :func:`setbound.cora.observe` refuses a model with ``c ≠ 0`` under
    ``convention="cora"``.

    Parameters
    ----------
    system : LinearSystem
        The model (a known ``A``).
    x0 : Zonotope, Box or Ellipsoid
        Initial set.
{params}

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.9, 0.2], [0.0, 0.7]], C=[[1.0, 0.0]],
    ...                             E=[[0.1, 0.0], [0.0, 0.0]], F=[[0.0, 0.05]])
    >>> est = setbound.zonotopic.CombastelObserver(sys, setbound.Box([-1, -1], [1, 1]))
    >>> t = est.run(np.zeros((5, 1)))
    >>> bool(t.contains(np.zeros((5, 2))).all()), t.filter
    (True, False)
    """

    _rule = lib.SB_ZOBS_COMBASTEL
    is_filter = False

    def __init__(self, system: LinearSystem, x0: Zonotope, *, max_generators: int = 20, reduction: str = "combastel",
                 convention: str = "setbound", on_inconsistency: str = "flag"):
        super().__init__(system, x0, max_generators=max_generators, reduction=reduction, convention=convention,
                         on_inconsistency=on_inconsistency)


@reconstructible
class StripGainEstimator(_ZonotopicObserver):
    """Zonotopic filter with a given strip weight (CORA's PRad-A with ``all_strips=False``; PRad-B, PRad-C, PRad-D).

    ``all_strips=True``: all strips at once with the ``n_x × n_y`` weight ``Λ``
    (``p' = p + Λ(y − Cp)``, ``G' = [(I − ΛC) G, Λ diag(σ)]``, Le et al., ISIC 2013);
    ``all_strips=False``: strip ``i`` alone with ``λ_i`` = column ``i`` of ``gain``, one after another
    (Le et al., Automatica 2013). Guaranteed for any weight; the weight decides the size (e.g. a
    P-radius design, or CORA's saved gains).

    Parameters
    ----------
    system : LinearSystem
        The model (a known ``A``).
    x0 : Zonotope, Box or Ellipsoid
        Initial set.
    gain : array_like, shape (n_x, n_y)
        The weight.
    all_strips : bool, optional
        One weight for all strips (default) or one column per strip.
{params}

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.9, 0.2], [0.0, 0.7]], C=[[1.0, 0.0]],
    ...                             E=[[0.1, 0.0], [0.0, 0.0]], F=[[0.0, 0.05]])
    >>> est = setbound.zonotopic.StripGainEstimator(sys, setbound.Box([-1, -1], [1, 1]), [[0.5], [0.1]])
    >>> bool(est.run(np.zeros((5, 1))).contains(np.zeros((5, 2))).all())
    True
    """

    _takes_gain = True

    def __init__(self, system: LinearSystem, x0: Zonotope, gain, *, all_strips: bool = True, max_generators: int = 20,
                 reduction: str = "combastel", convention: str = "setbound", on_inconsistency: str = "flag"):
        self.all_strips = as_bool(all_strips, "all_strips")
        self._rule = lib.SB_ZOBS_FIXED_LAMBDA if self.all_strips else lib.SB_ZOBS_FIXED_STRIPS
        super().__init__(system, x0, gain=gain, max_generators=max_generators, reduction=reduction,
                         convention=convention, on_inconsistency=on_inconsistency)

    @property
    def gain(self) -> np.ndarray:
        """The given weight, shape ``(n_x, n_y)``."""
        return self._gain_matrix.copy()


@reconstructible
class PropagationObserver(_ZonotopicObserver):
    """Intersection-free zonotopic predictor with a fixed gain ``L`` (CORA's PRad-E and Nom-G).

    ``X_{k+1} = (A − L C) X_k ⊕ (B u_k + L (y_k − D u_k)) ⊕ (E − L F) B`` (Wang et al., Automatica
    2018; Combastel 2015 with a constant gain). Guaranteed for any ``L``; bounded when
    ``A − L C`` is stable. A predictor: row ``k`` uses ``y_0 … y_{k−1}``.

    Parameters
    ----------
    system : LinearSystem
        The model (a known ``A``).
    x0 : Zonotope, Box or Ellipsoid
        Initial set.
    gain : array_like, shape (n_x, n_y)
        The observer gain ``L``.
{params}

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.9, 0.2], [0.0, 0.7]], C=[[1.0, 0.0]],
    ...                             E=[[0.1, 0.0], [0.0, 0.0]], F=[[0.0, 0.05]])
    >>> est = setbound.zonotopic.PropagationObserver(sys, setbound.Box([-1, -1], [1, 1]), [[0.5], [0.1]])
    >>> bool(est.run(np.zeros((5, 1))).contains(np.zeros((5, 2))).all())
    True
    """

    _rule = lib.SB_ZOBS_FIXED_GAIN
    _takes_gain = True
    is_filter = False

    def __init__(self, system: LinearSystem, x0: Zonotope, gain, *, max_generators: int = 20,
                 reduction: str = "combastel", convention: str = "setbound", on_inconsistency: str = "flag"):
        super().__init__(system, x0, gain=gain, max_generators=max_generators, reduction=reduction,
                         convention=convention, on_inconsistency=on_inconsistency)

    @property
    def gain(self) -> np.ndarray:
        """The given gain ``L``, shape ``(n_x, n_y)``."""
        return self._gain_matrix.copy()


#: The gain rules of the shared skeleton (:class:`ZonotopicObserver`), with CORA's names.
OBSERVER_RULES = {"segment_min": lib.SB_ZOBS_SEGMENT_MIN, "volume_min": lib.SB_ZOBS_VOLUME_MIN,
                  "bravo": lib.SB_ZOBS_BRAVO, "fixed_strips": lib.SB_ZOBS_FIXED_STRIPS, "wang": lib.SB_ZOBS_WANG,
                  "fixed_lambda": lib.SB_ZOBS_FIXED_LAMBDA, "combastel": lib.SB_ZOBS_COMBASTEL,
                  "fixed_gain": lib.SB_ZOBS_FIXED_GAIN}
_GAIN_RULES = ("fixed_strips", "fixed_lambda", "fixed_gain")
_PREDICTOR_RULES = ("combastel", "fixed_gain")


@reconstructible
class ZonotopicObserver(_ZonotopicObserver):
    """The shared zonotopic skeleton of CORA's catalogue with the gain rule as a parameter.

    ``rule`` (CORA's name in brackets): strip-based filters ``"segment_min"`` [FRad-A] (Alamo
    2005's ``λ = G Gᵀc / (cᵀG Gᵀc + σ²)`` per strip), ``"volume_min"`` [VolMin-A] (the ``λ`` of the
    smallest volume per strip, an LP), ``"bravo"`` [VolMin-B], ``"fixed_strips"`` [PRad-A],
    ``"wang"`` [FRad-B], ``"fixed_lambda"`` [PRad-B/C/D]; intersection-free predictors
    ``"combastel"`` [FRad-C], ``"fixed_gain"`` [PRad-E, Nom-G]. The named classes
    (:class:`BravoEstimator`, :class:`WangEstimator`, ...) are this class with one rule.

    The strip-based rules take an interval ``A`` (``system.A_rad``; papers §3.1): the prediction
    adds Le et al.'s two boxes ``rad·rs|G|`` and ``rad·|p|``, and the prior is then kept as
    columns (as for ``"volume_min"``, whose LP needs them). :class:`SegmentMinEstimator` and
    :class:`VolumeMinEstimator` run the same corrections on the papers' estimator, which also has
    ``strip_order``, ``use_first_measurement`` and a screening strip by strip; this skeleton
    screens every reading against the prior.

    Parameters
    ----------
    system : LinearSystem
        The model.
    x0 : Zonotope, Box or Ellipsoid
        Initial set.
    rule : str
        The gain rule (above).
    gain : array_like, shape (n_x, n_y), optional
        The weight of the fixed rules (``"fixed_strips"``: column ``i`` is ``λ_i``; ``"fixed_lambda"``:
        ``Λ``; ``"fixed_gain"``: ``L``); not taken by the others.
{params}

    Examples
    --------
    >>> A = setbound.IntervalMatrix([[0.89, 0.2], [0.0, 0.69]], [[0.91, 0.2], [0.0, 0.71]])
    >>> sys = setbound.LinearSystem(A=A, C=[[1.0, 0.0]], E=[[0.1, 0.0], [0.0, 0.0]], F=[[0.0, 0.05]])
    >>> est = setbound.zonotopic.ZonotopicObserver(sys, setbound.Box([-1, -1], [1, 1]), "segment_min")
    >>> bool(est.run(np.zeros((5, 1))).contains(np.zeros((5, 2))).all())
    True
    """

    def __init__(self, system: LinearSystem, x0: Zonotope, rule: str, *, gain=None, max_generators: int = 20,
                 reduction: str = "combastel", convention: str = "setbound", on_inconsistency: str = "flag"):
        self.rule = as_choice(rule, "rule", OBSERVER_RULES)
        self._rule = OBSERVER_RULES[self.rule]
        self._takes_gain = self.rule in _GAIN_RULES
        self.is_filter = self.rule not in _PREDICTOR_RULES
        if not self._takes_gain and gain is not None:
            raise InvalidArgumentError(f"gain: rule {self.rule!r} computes its own weight; only "
                                       f"{', '.join(_GAIN_RULES)} take a gain")
        if self._takes_gain and gain is None:
            raise InvalidArgumentError(f"gain: rule {self.rule!r} needs a weight (n_x x n_y)")
        super().__init__(system, x0, gain=gain, max_generators=max_generators, reduction=reduction,
                         convention=convention, on_inconsistency=on_inconsistency)

    @property
    def gain(self) -> np.ndarray | None:
        """The given weight of a fixed rule, shape ``(n_x, n_y)`` (None for the other rules)."""
        return self._gain_matrix.copy() if self._takes_gain else None


for _cls in (BravoEstimator, WangEstimator, CombastelObserver, StripGainEstimator, PropagationObserver,
             ZonotopicObserver):
    _cls.__doc__ = _cls.__doc__.replace("{params}", _OBSERVER_PARAMETERS)
del _cls


#: Offline gain designs of :func:`design_zonotopic_gain` (CORA's names).
GAIN_DESIGNS = {"PRad-A": lib.SB_ZOBS_DESIGN_PRAD_A, "PRad-B": lib.SB_ZOBS_DESIGN_PRAD_B,
                "PRad-C": lib.SB_ZOBS_DESIGN_PRAD_C, "PRad-D": lib.SB_ZOBS_DESIGN_PRAD_D,
                "PRad-E": lib.SB_ZOBS_DESIGN_PRAD_E, "Nom-G": lib.SB_ZOBS_DESIGN_NOM_G}


@dataclass(frozen=True)
class ZonotopicGainDesign:
    """An offline weight (PRad-A..D: for :class:`StripGainEstimator`) or gain (PRad-E, Nom-G: for :class:`PropagationObserver`) and its LMI certificate.

    Parameters
    ----------
    method : str
        ``"PRad-A"``, ``"PRad-B"``, ``"PRad-C"``, ``"PRad-D"``, ``"PRad-E"`` or ``"Nom-G"``.
    gain : ndarray, shape (n_x, n_y)
        ``P⁻¹ Y`` (PRad-A: column ``i`` from output ``i``'s own design).
    P : ndarray, shape (n_x, n_x)
        The Lyapunov-type matrix (PRad-A: of the last output).
    Y : ndarray, shape (n_x, n_y) or (n_x, 1)
        ``P`` times the gain (PRad-A: of the last output).
    beta : float
        PRad-A/B/C/D/E: the contraction ``β``; Nom-G: 1 (CORA's ``μ``).
    """

    method: str
    gain: np.ndarray
    P: np.ndarray
    Y: np.ndarray
    beta: float


def design_zonotopic_gain(system: LinearSystem, method: str = "PRad-E", *, max_iterations: int | None = None,
                          time_limit: float | None = None) -> ZonotopicGainDesign:
    """Offline weight or gain of CORA's P-radius and nominal zonotopic observers (PRad-A..E, Nom-G), on the bundled LMI solver.

    ``"PRad-B"`` (Le, Stoica, Alamo, Camacho, Dumur, ISIC 2013, eq. 17): the weight ``Λ`` of all
    strips at once maximising ``τ`` with ``(1 − β)P/ε ⪰ τI`` under the P-radius LMI,
    ``ε = ‖rad W‖₂ + σᵀσ``, ``β`` by CORA's bisection (the last feasible solve kept). ``"PRad-A"``:
    that design for each output alone (Le et al., Automatica 2013); column ``i`` is ``λ_i``.

    ``"PRad-C"`` (Wang, Alamo, Puig, Cembrano, CDC 2018) and ``"PRad-D"`` (Wang, Wang, Puig,
    Cembrano, IEEE TAC 2019): CORA's SDPs are unbounded / infeasible as coded, so these solve the
    papers' P-radius condition ``‖e⁺‖²_P ≤ β‖e‖²_P + wᵀD_w w + vᵀD_v v`` (``w``, ``v`` the unit-box
    coordinates of ``E``, ``F``) for the weight of largest ``λ_min(P)``, i.e. of least certified
    asymptotic radius: PRad-C with diagonal ``D_w``, ``D_v`` and the budget
    ``trace D_w + trace D_v ≤ 1 − β`` (the unit P-ball is invariant), PRad-D with CORA's
    ``D_w = D_v = (1 − β)/2·I``; ``β`` by a scalar search on (0, 1) instead of CORA's bisection.

    ``"PRad-E"`` (Wang, Zhou, Puig, Cembrano, Wang, CCC 2017): ``‖x⁺‖²_P ≤ β‖x‖²_P + ‖E_w w‖² + ‖F_v v‖²``
    for the error dynamics ``A − LC``, maximal ``trace P``, ``β`` by CORA's bisection on (0, 1) (the
    last feasible solve is kept); needs ``E`` of full row rank (else ``trace P`` is unbounded).
    ``"Nom-G"`` (Wang, Puig, Cembrano, Automatica 2018): CORA solves the feasibility problem
    ``(A − LC)ᵀP(A − LC) ⪯ P`` whose answer is wherever its solver stops (a cone containing
    ``P = 0``); here the analytic centre of its slice ``P ⪰ I``, ``trace P ≤ 10 t*`` with ``t*`` the
    least trace in it (``beta`` = 1).

    Parameters
    ----------
    system : LinearSystem
        The model (a known ``A``).
    method : {"PRad-A", "PRad-B", "PRad-C", "PRad-D", "PRad-E", "Nom-G"}, optional
        The design.
    max_iterations : int, optional
        Iteration limit of each LMI solve of the design (default 100).
    time_limit : float, optional
        Time limit of each LMI solve of the design, in seconds (default 30). The designs solve a
        few (PRad-E, Nom-G, PRad-B: up to 8) to a few dozen (PRad-A: per output; PRad-C/D: up to
        16) LMIs.

    Returns
    -------
    ZonotopicGainDesign

    Raises
    ------
    InfeasibleError
        When no gain satisfies the design's LMI.
    NumericalError
        When no LMI solve of the design gave a solution and some stopped undecided, e.g. at
        ``time_limit`` (the message names the limit reached).
    InvalidArgumentError
        For ``max_iterations`` or ``time_limit`` not positive (or not a number).

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.9, 0.2], [0.0, 0.7]], C=[[1.0, 0.0]],
    ...                             E=[[0.1, 0.0, 0.0], [0.0, 0.1, 0.0]], F=[[0.0, 0.0, 0.05]])
    >>> d = setbound.zonotopic.design_zonotopic_gain(sys, "Nom-G")
    >>> bool(np.max(np.abs(np.linalg.eigvals(sys.A - d.gain @ sys.C))) < 1)
    True
    """
    system = as_system(system)
    if not isinstance(system, LinearSystem):
        raise InvalidArgumentError(f"system: expected a setbound.LinearSystem, got {type(system).__name__}")
    method = as_choice(method, "method", GAIN_DESIGNS)
    iters = 0 if max_iterations is None else as_int(max_iterations, "max_iterations", lo=1)
    seconds = 0.0 if time_limit is None else as_float(time_limit, "time_limit", lo=0.0, lo_open=True)
    nx, ny = system.nx, system.ny
    L, P, Y = np.empty((nx, ny)), np.empty((nx, nx)), np.empty((nx, ny))
    beta = ffi.new("double*")
    check(lib.sb_zono_gain_design_limits(system._handle, GAIN_DESIGNS[method], iters, seconds, dptr(L), dptr(P),
                                         dptr(Y), beta))
    return ZonotopicGainDesign(method, L, P, Y, float(beta[0]))


# ---- CORA's names (setbound.cora.observe) -------------------------------------------------------

def _refuse_cora_quirk(model, alg: str, convention: str, intersection_free: bool) -> None:
    """CORA quirks that ``convention="cora"`` does not copy: the intersection-free skeleton omits
    the constant term ``c`` (spec §1.3; not an outer bound when ``c ≠ 0``), and the strips do not
    subtract the centre of ``V`` from ``y`` (spec §1.2; setbound's model subtracts it)."""
    if convention != "cora":
        return
    if intersection_free and model.c is not None and np.any(np.asarray(model.c) != 0):
        raise InvalidArgumentError(
            f"convention: CORA's {alg} omits the constant term c of the dynamics, which is not zero in this model, "
            "so its sets would not contain the state; use convention='setbound'")
    if not intersection_free and model.v_center is not None and np.any(np.asarray(model.v_center) != 0):
        raise InvalidArgumentError(
            f"convention: CORA's {alg} does not subtract the centre of V from y (non-zero in this model); setbound "
            "does not reproduce that; use convention='setbound'")


def _observer_runner(make, alg: str, intersection_free: bool):
    """A runner of the shared skeleton: ``make(model, gain, **kw)`` builds the observer with
    CORA's zonotope order and reduction technique (overridable) and the convention (a gain the
    convention requires is checked by :func:`setbound.cora.prepare`)."""
    def runner(model, *, convention, gain, **options):
        _refuse_cora_quirk(model, alg, convention, intersection_free)
        est = make(model, gain, **{**model.estimator_options(), "convention": convention, **options})

        def run():
            t = est.run(model.y, model.u)
            return t.lower, t.upper, t.sets
        return run
    return runner


def _design_limits(kw: dict) -> dict:
    """Pops ``solver_options`` (the solver limits of :func:`design_zonotopic_gain`:
    ``max_iterations``, ``time_limit``) from the options of ``setbound.cora.observe``."""
    opts = kw.pop("solver_options", None)
    if opts is None:
        return {}
    if not isinstance(opts, dict):
        raise InvalidArgumentError(f"solver_options: expected a dict with max_iterations and/or time_limit, got "
                                   f"{type(opts).__name__}")
    unknown = sorted(set(opts) - {"max_iterations", "time_limit"})
    if unknown:
        raise InvalidArgumentError(f"solver_options: unknown option {unknown[0]!r} (max_iterations, time_limit)")
    return dict(opts)


def _strip_gain(name: str, all_strips: bool):
    def make(model, gain, **kw):
        limits = _design_limits(kw)
        # Without a gain: CORA's LMI design on setbound's solver (design_zonotopic_gain).
        if gain is None:
            gain = design_zonotopic_gain(model.system, name, **limits).gain
        return StripGainEstimator(model.system, model.x0, gain, all_strips=all_strips, **kw)
    return make


def _register_cora_names():
    from .cora import register_algorithm
    register_algorithm("FRad-A", _observer_runner(lambda m, g, **kw: ZonotopicObserver(m.system, m.x0, "segment_min",
                                                                                       **kw), "FRad-A", False),
                       summary="segment (F-radius) minimisation per strip [Alamo 2005] = "
                               "ZonotopicObserver(rule='segment_min')")
    register_algorithm("VolMin-A", _observer_runner(lambda m, g, **kw: ZonotopicObserver(m.system, m.x0, "volume_min",
                                                                                         **kw), "VolMin-A", False),
                       summary="exact volume minimisation per strip (LP) [Alamo 2005] = "
                               "ZonotopicObserver(rule='volume_min')")
    register_algorithm("VolMin-B", _observer_runner(lambda m, g, **kw: BravoEstimator(m.system, m.x0, **kw),
                                                    "VolMin-B", False),
                       summary="Bravo's candidate parallelotopes per strip [Bravo 2006] = BravoEstimator")
    register_algorithm("FRad-B", _observer_runner(lambda m, g, **kw: WangEstimator(m.system, m.x0, **kw),
                                                  "FRad-B", False),
                       summary="Kalman-like weight on all strips [Wang 2018] = WangEstimator")
    register_algorithm("FRad-C", _observer_runner(lambda m, g, **kw: CombastelObserver(m.system, m.x0, **kw),
                                                  "FRad-C", True),
                       summary="adaptive gain, no intersection [Combastel 2015] = CombastelObserver")
    register_algorithm("PRad-A", _observer_runner(_strip_gain("PRad-A", False), "PRad-A", False),
                       summary="fixed P-radius weight per strip [Le 2013] = StripGainEstimator(all_strips=False) + "
                               "design_zonotopic_gain", accepts_gain=True)
    register_algorithm("PRad-B", _observer_runner(_strip_gain("PRad-B", True), "PRad-B", False),
                       summary="fixed P-radius weight on all strips [Le 2013 ISIC] = StripGainEstimator + "
                               "design_zonotopic_gain", accepts_gain=True)
    for name, paper in (("PRad-C", "Wang 2018 CDC"), ("PRad-D", "Wang 2019 TAC")):
        register_algorithm(name, _observer_runner(_strip_gain(name, True), name, False),
                           summary=f"fixed P-radius weight on all strips [{paper}] = StripGainEstimator + "
                                   "design_zonotopic_gain (convention='cora': CORA's gain only)", accepts_gain=True,
                           gain_required={"cora": f"CORA's {name} design cannot be reproduced (its SDP is unbounded "
                                                  "or infeasible as coded); convention='setbound' uses setbound's "
                                                  "design of the paper's condition (design_zonotopic_gain)"})
    for name, paper in (("PRad-E", "Wang 2017 CCC"), ("Nom-G", "Wang 2018")):
        def make(m, g, _name=name, **kw):
            limits = _design_limits(kw)
            # Without a gain: setbound's design (design_zonotopic_gain), timed as CORA's offline part.
            if g is None:
                g = design_zonotopic_gain(m.system, _name, **limits).gain
            return PropagationObserver(m.system, m.x0, g, **kw)
        register_algorithm(name, _observer_runner(make, name, True),
                           summary=f"fixed gain, no intersection [{paper}] = PropagationObserver + "
                                   "design_zonotopic_gain", accepts_gain=True)


_register_cora_names()
