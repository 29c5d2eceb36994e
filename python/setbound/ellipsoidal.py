"""Ellipsoidal estimators (Methods › Ellipsoidal estimation) and the Kalman filter baseline.

Sets are ``E(P, c, ρ) = {x : (x − c)ᵀ P (x − c) ≤ ρ}`` (:class:`setbound.Ellipsoid`).

* :func:`design_offline` — the offline LMI design (Methods › Ellipsoidal estimation › Offline design; shape ``P``, gain ``L``, ``β``,
  ``σ``), for a :class:`~setbound.LinearSystem` (robust over ``vert[A]`` when ``A`` is an
  interval matrix) or a :class:`~setbound.DescriptorSystem` (› Descriptor systems).
* :class:`OfflineEstimator`, :class:`OnlineEstimator` (› Online vertex LMI; ``scaling=True``: › Online with scaling) —
  one-step predictors: ``step(y_k, u_k)`` returns the set for ``x_{k+1}``.
* :class:`ImprovedEstimator` (› Improved correction) and :class:`DescriptorEstimator` — filters:
  ``step(y_k, u_k)`` returns the set for ``x_k`` after using ``y_k``.
* :class:`KalmanFilter` (› Kalman filter) — the contrast, not guaranteed.

Real data (:mod:`setbound.measurement`): NaN entries of ``y`` (``step(None)``) are missing
outputs; a reading outside the predicted output set (the support of the predicted ellipsoid in
``±C_i``, widened by the noise bound) is never used and is handled by ``on_inconsistency``
(``"flag"``, ``"raise"``, ``"reset"`` to ``reset_set``). A step with outputs missing or skipped
uses the design's gain restricted to the outputs present (or no correction, whichever certified
level is smaller). The descriptor estimator needs every output (its state is fixed through them).

``run(y, u=None)`` returns a :class:`~setbound.Trajectory` whose row ``k`` is about ``x_k``
for every estimator (predictors: row 0 is the initial set and row ``k`` used ``y_0 … y_{k-1}``;
filters: row ``k`` used ``y_0 … y_k``). After ``run`` a predictor holds the prediction for
``x_N`` in :attr:`current`.
"""
from __future__ import annotations

import math
import warnings
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ._native import as_f64, check, dptr, ffi, lib
from ._state import MadeByCall, StateMixin, reconstructible, remember_call, run_from_initial_set
from ._validate import as_bool, as_choice, as_float
from .errors import DimensionError, InvalidArgumentError
from .measurement import POLICIES, ReadingChecks, measurement_or_missing
from .sets import Ellipsoid, as_ellipsoid
from .system import as_system, DescriptorSystem, LinearSystem, refuse_missing, run_inputs, step_inputs
from .trajectory import Trajectory

_NORMALIZATIONS = {
    "logdet": lib.SB_ELL_NORM_LOGDET,
    "ball": lib.SB_ELL_NORM_BALL,
    "paper_trace": lib.SB_ELL_NORM_PAPER_TRACE,
}
_NORM_NAMES = {v: k for k, v in _NORMALIZATIONS.items()}
_OPTIONS = {
    "fixed_shape": lib.SB_ELL_CORR_FIXED_SHAPE,
    "det_normalized": lib.SB_ELL_CORR_DET_NORMALIZED,
    "ball_normalized": lib.SB_ELL_CORR_BALL_NORMALIZED,
}
_FEEDBACK = {
    "none": lib.SB_ELL_FEEDBACK_NONE,
    "outer_bound": lib.SB_ELL_FEEDBACK_OUTER_BOUND,
    "fixed_shape": lib.SB_ELL_FEEDBACK_FIXED_SHAPE,
}
_PREDICTORS = {
    "offline": lib.SB_ELL_OFFLINE,
    "online": lib.SB_ELL_ONLINE_VERTEX,
    "scaled": lib.SB_ELL_ONLINE_SCALED,
}


class DegenerateDesignWarning(UserWarning):
    """The printed ``tr P ≤ 1`` normalisation (Methods › Ellipsoidal estimation › Offline design) was asked for: it bounds P from
    above, so the LMI's infimum is at P → 0 and the shape is whatever the solver stops at."""


def _choice(value: str, table: dict, name: str) -> int:
    # as_choice compares by type and value, so an unhashable value (a list) is a clean error too
    return table[as_choice(value, name, table)]


@dataclass(frozen=True)
class EllDesign(MadeByCall):
    """An offline ellipsoidal design: every estimator of this module starts from one.

    Made by :func:`design_offline`; ``ρ⁺ ≤ βρ + σ`` is the level recursion it certifies
    (Methods › Ellipsoidal estimation › Offline design).

    Parameters
    ----------
    P : ndarray, shape (n_x, n_x)
        Shape of the ellipsoids.
    L : ndarray, shape (n_x, n_y)
        Observer gain.
    beta, sigma : float
        Contraction and growth of the level, ``ρ⁺ ≤ βρ + σ``.
    rho_inf : float
        Steady-state level ``σ/(1−β)``.
    volume_inf : float
        Volume of the steady-state ellipsoid ``E(P, ·, rho_inf)``.
    normalization : str
        The normalisation used (see :func:`design_offline`).
    vertex_blocks : int
        Number of LMI blocks imposed.
    system : LinearSystem or DescriptorSystem
        The system designed for.
    """

    P: np.ndarray
    L: np.ndarray
    beta: float
    sigma: float
    rho_inf: float
    volume_inf: float
    normalization: str
    vertex_blocks: int
    system: Any = field(repr=False)
    _handle: Any = field(repr=False, compare=False)

    @property
    def nx(self) -> int:
        """State dimension n_x."""
        return self.P.shape[0]


def design_offline(system, normalization: str = "logdet", beta: float | None = None) -> EllDesign:
    """The offline LMI design of [BenChabane2014] (Theorem 1), or of [Merhy2019] for a descriptor system.

    Methods › Ellipsoidal estimation › Offline design (and › Descriptor systems). With an interval
    ``A`` the design is robust over the vertices of ``[A]``.

    Parameters
    ----------
    system : LinearSystem or DescriptorSystem
        The model.
    normalization : {"logdet", "ball", "paper_trace"}, optional
        ``"logdet"`` (``log det P ≥ 0``: the minimum steady-state volume; the default), ``"ball"``
        (``P ⪰ I``), or ``"paper_trace"`` (``tr P ≤ 1`` as printed; degenerate, warns with
        :class:`DegenerateDesignWarning`).
    beta : float, optional
        A fixed value in (0, 1), or ``None`` to choose it by a scalar search on the steady-state
        volume (logdet) or on ``ρ∞`` (ball).

    Returns
    -------
    EllDesign

    Raises
    ------
    NotDetectableError
        When ``(C, A)`` is not detectable.
    InfeasibleError
        When no design exists.

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.9, 0.2], [0.0, 0.7]], C=[[1.0, 0.0]],
    ...                             E=[[0.1, 0.0], [0.0, 0.0]], F=[[0.0, 0.05]])
    >>> d = setbound.ellipsoidal.design_offline(sys)
    >>> 0 < d.beta < 1 and d.L.shape == (2, 1)
    True
    """
    args = (system, normalization, beta)
    system = as_system(system)
    norm = _choice(normalization, _NORMALIZATIONS, "normalization")
    if norm == lib.SB_ELL_NORM_PAPER_TRACE:
        warnings.warn("normalization='paper_trace' (tr P <= 1, Methods › Ellipsoidal estimation › Offline design) is degenerate: the LMI is "
                      "homogeneous, so an upper bound on P drives P towards 0; use 'logdet' or 'ball'",
                      DegenerateDesignWarning, stacklevel=2)
    b = math.nan if beta is None else as_float(beta, "beta", lo=0.0, hi=1.0, lo_open=True, hi_open=True)
    handle = ffi.new("sb_ell_design**")
    if isinstance(system, DescriptorSystem):
        check(lib.sb_ell_design_descriptor(system._handle, norm, b, handle))
    elif isinstance(system, LinearSystem):
        check(lib.sb_ell_design_offline(system._handle, norm, b, handle))
    else:
        raise InvalidArgumentError(f"system: expected a LinearSystem or DescriptorSystem, got {type(system).__name__}")
    h = ffi.gc(handle[0], lib.sb_ell_design_free)
    nx, ny = ffi.new("int*"), ffi.new("int*")
    check(lib.sb_ell_design_dims(h, nx, ny))
    P, L, sc = np.empty((nx[0], nx[0])), np.empty((nx[0], ny[0])), np.empty(4)
    blocks, nm = ffi.new("int*"), ffi.new("int*")
    check(lib.sb_ell_design_get(h, dptr(P), dptr(L), dptr(sc), blocks, nm))
    for a in (P, L):
        a.flags.writeable = False
    return remember_call(EllDesign(P, L, float(sc[0]), float(sc[1]), float(sc[2]), float(sc[3]), _NORM_NAMES[nm[0]],
                                   int(blocks[0]), system, h), design_offline, *args)


class _EllipsoidalEstimator(ReadingChecks, StateMixin):
    _method: int
    _last_check_fn = lib.sb_ellipsoidal_last_check
    _state_prefix = "sb_ellipsoidal"
    is_filter: bool = False

    def _create(self, design: EllDesign, x0: Ellipsoid, *, option=0, feedback=0, predictor=0, descriptor=None,
                on_inconsistency: str = "flag", reset_set: Ellipsoid | None = None):
        on_inconsistency = as_choice(on_inconsistency, "on_inconsistency", POLICIES)
        if reset_set is not None:
            if on_inconsistency != "reset":
                raise InvalidArgumentError('reset_set: only used with on_inconsistency="reset"')
            reset_set = as_ellipsoid(reset_set, "reset_set")
        if not isinstance(design, EllDesign):
            raise InvalidArgumentError(f"design: expected an EllDesign (from design_offline), got {type(design).__name__}")
        x0 = as_ellipsoid(x0, "x0")  # a box or a zonotope: the ellipsoid through its hull's corners
        if x0.n != design.nx:
            raise DimensionError(f"x0: expected an ellipsoid of dimension {design.nx}, got {x0.n}")
        self.design = design
        self.system = design.system
        handle = ffi.new("sb_ellipsoidal**")
        check(lib.sb_ellipsoidal_create(design._handle, self._method, option, feedback, predictor,
                                        descriptor._handle if descriptor is not None else ffi.NULL,
                                        dptr(x0.P), dptr(x0.center), x0.rho, handle))
        self._handle = ffi.gc(handle[0], lib.sb_ellipsoidal_free)
        if reset_set is not None and reset_set.n != design.nx:
            raise DimensionError(f"reset_set: expected an ellipsoid of dimension {design.nx}, got {reset_set.n}")
        if reset_set is None:
            check(lib.sb_ellipsoidal_set_inconsistency_policy(self._handle, POLICIES[on_inconsistency], ffi.NULL,
                                                              ffi.NULL, 0.0))
        else:
            check(lib.sb_ellipsoidal_set_inconsistency_policy(self._handle, POLICIES[on_inconsistency],
                                                              dptr(reset_set.P), dptr(reset_set.center),
                                                              reset_set.rho))
        self.on_inconsistency = on_inconsistency
        self._init_checks()
        n = design.nx
        self._P, self._c, self._rho = np.empty((n, n)), np.empty(n), ffi.new("double*")
        self._lo, self._hi = np.empty(n), np.empty(n)

    def _snapshot(self):
        return (Ellipsoid(self._P.copy(), self._c.copy(), self._rho[0]), self._lo.copy(), self._hi.copy())

    @property
    def current(self) -> Ellipsoid:
        """Predictors: the set for the next state ``x_k`` (before ``y_k`` is used); filters: the
        set returned by the last step."""
        check(lib.sb_ellipsoidal_current(self._handle, dptr(self._P), dptr(self._c), self._rho,
                                         dptr(self._lo), dptr(self._hi)))
        return self._snapshot()[0]

    @property
    def steps(self) -> int:
        s = ffi.new("int*")
        check(lib.sb_ellipsoidal_info(self._handle, ffi.NULL, s, ffi.NULL, ffi.NULL, ffi.NULL))
        return int(s[0])

    def _step(self, y, u):
        y, up = step_inputs(self.system, measurement_or_missing(y, self.system.ny), u)
        if self._method == lib.SB_ELL_DESCRIPTOR:
            refuse_missing(y, type(self).__name__)
        check(lib.sb_ellipsoidal_step(self._handle, dptr(y), up, dptr(self._P), dptr(self._c), self._rho,
                                      dptr(self._lo), dptr(self._hi)))

    def step(self, y, u=None) -> Ellipsoid:
        """Use ``y_k`` (and ``u_k``).

        Predictors return the set for ``x_{k+1}``, filters the set for ``x_k``. Missing outputs
        (None or NaN entries) are not accepted by the descriptor estimator. See ``last_check`` for
        what the step did with each output. On error (wrong shape, ±inf, policy ``"raise"``) the
        estimator is unchanged.

        Parameters
        ----------
        y : array_like, shape (n_y,), or None
            The measurement ``y_k`` (None or NaN entries: missing outputs).
        u : array_like, shape (n_u,), optional
            The input ``u_k``.

        Returns
        -------
        Ellipsoid
        """
        self._step(y, u)
        return self._snapshot()[0]

    def reset(self) -> None:
        """Back to the initial set, no step taken (the options are kept)."""
        check(lib.sb_ellipsoidal_reset(self._handle))

    def last_step(self) -> dict:
        """``beta`` and gain ``L`` of the last prediction, and ``fallback`` (True when the online
        LMI could not be solved and certified and the design's values were used)."""
        b, fb = ffi.new("double*"), ffi.new("int*")
        L = np.empty((self.design.nx, self.system.ny))
        check(lib.sb_ellipsoidal_last_step(self._handle, b, dptr(L), fb))
        return {"beta": float(b[0]), "L": L, "fallback": bool(fb[0])}

    @run_from_initial_set
    def run(self, y, u=None) -> Trajectory:
        """Process a record from the initial set; row ``k`` of the result is about ``x_k``.

        Predictors: row 0 is the initial set and row ``k`` used ``y_0 … y_{k-1}``; filters: row ``k``
        used ``y_0 … y_k``.

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
        if self._method == lib.SB_ELL_DESCRIPTOR:
            refuse_missing(y, type(self).__name__)
        N = y.shape[0]
        n = self.design.nx
        centers, lows, highs, sets = np.empty((N, n)), np.empty((N, n)), np.empty((N, n)), []
        status, margin = np.empty((N, s.ny), dtype=np.int8), np.empty((N, s.ny))
        resets = np.zeros(N, dtype=bool)
        if not self.is_filter and N > 0:
            check(lib.sb_ellipsoidal_current(self._handle, dptr(self._P), dptr(self._c), self._rho,
                                             dptr(self._lo), dptr(self._hi)))
        for k in range(N):
            if self.is_filter:
                self._step(y[k], u[k] if s.nu > 0 else None)
            E, lo, hi = self._snapshot()
            centers[k], lows[k], highs[k] = E.center, lo, hi
            sets.append(E)
            if not self.is_filter:
                self._step(y[k], u[k] if s.nu > 0 else None)
            resets[k] = self._check_into(status[k], margin[k])
        return Trajectory(centers, lows, highs, sets, status=status, margin=margin, resets=resets)


@reconstructible
class OfflineEstimator(_EllipsoidalEstimator):
    """The offline ellipsoidal estimator: fixed gain ``L``, ``x̄⁺ = A x̄ + B u + L (y − C x̄ − D u)``, ``ρ⁺ = βρ + σ``.

    A one-step predictor: ``step(y_k)`` returns the set for ``x_{k+1}``
    (Methods › Ellipsoidal estimation › Offline design, [BenChabane2014]).

    Parameters
    ----------
    design : EllDesign
        An offline design (:func:`design_offline`).
    x0 : Ellipsoid, Box or Zonotope
        Initial set (a box or a zonotope is replaced by the ellipsoid through its hull's corners);
        converted to the design's shape.
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
    >>> est = setbound.ellipsoidal.OfflineEstimator(setbound.ellipsoidal.design_offline(sys),
    ...                                            setbound.Ellipsoid(np.eye(2), [0.0, 0.0], 1.0))
    >>> traj = est.run(np.zeros((5, 1)))
    >>> traj.center.shape, bool(traj.contains(np.zeros((5, 2))).all())
    ((5, 2), True)
    """

    _method = lib.SB_ELL_OFFLINE

    def __init__(self, design: EllDesign, x0: Ellipsoid, *, on_inconsistency: str = "flag",
                 reset_set: Ellipsoid | None = None):
        self._create(design, x0, on_inconsistency=on_inconsistency, reset_set=reset_set)


@reconstructible
class OnlineEstimator(_EllipsoidalEstimator):
    """The online ellipsoidal estimator: per step, the LMI in ``(β_k, L_k, ρ_{k+1})`` with the design's shape.

    Methods › Ellipsoidal estimation › Online vertex LMI and › Online with scaling
    ([BenChabane2014]). With an interval ``A`` the centre term of Methods › Ellipsoidal estimation
    › Interval uncertainty on A is included. A one-step predictor.

    Parameters
    ----------
    design : EllDesign
        An offline design (:func:`design_offline`).
    x0 : Ellipsoid, Box or Zonotope
        Initial set (a box or a zonotope is replaced by the ellipsoid through its hull's corners);
        converted to the design's shape.
    scaling : bool, optional
        ``True``: the scaling technique (one LMI, no vertex enumeration; never smaller than the
        vertex version).
    reuse_tolerance : float, optional
        The step's LMI is solved again only when ``ρ_k`` moved by more than this (relative);
        otherwise the last certified solution is reused.
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
    >>> design = setbound.ellipsoidal.design_offline(sys)
    >>> x0 = setbound.Ellipsoid(np.eye(2), [0.0, 0.0], 1.0)
    >>> online = setbound.ellipsoidal.OnlineEstimator(design, x0).run(np.zeros((6, 1)))
    >>> offline = setbound.ellipsoidal.OfflineEstimator(design, x0).run(np.zeros((6, 1)))
    >>> bool(np.all(online.radius <= offline.radius * (1 + 1e-9)))
    True
    """

    def __init__(self, design: EllDesign, x0: Ellipsoid, scaling: bool = False,
                 reuse_tolerance: float = 1e-9, *, on_inconsistency: str = "flag",
                 reset_set: Ellipsoid | None = None):
        scaling = as_bool(scaling, "scaling")
        reuse_tolerance = as_float(reuse_tolerance, "reuse_tolerance", lo=0.0)
        self._method = lib.SB_ELL_ONLINE_SCALED if scaling else lib.SB_ELL_ONLINE_VERTEX
        self.scaling = scaling
        self._create(design, x0, on_inconsistency=on_inconsistency, reset_set=reset_set)
        self.reuse_tolerance = reuse_tolerance

    @property
    def reuse_tolerance(self) -> float:
        """The LMI is solved again only when ρ_k moved by more than this relative amount since
        the last solve; otherwise the last certified (β, L, σ) is reused, which is at most
        ``|Δρ|`` above the optimum (the LMI does not depend on ρ_k; the optimal value is concave
        in ρ with supergradient β ∈ (0, 1)). 0 solves at every step. A finite number >= 0
        (every value is sound; a large one only reuses more). Not used with an interval A."""
        return self._reuse_tolerance

    @reuse_tolerance.setter
    def reuse_tolerance(self, tol: float) -> None:
        tol = as_float(tol, "reuse_tolerance", lo=0.0)
        check(lib.sb_ellipsoidal_set_reuse_tolerance(self._handle, tol))
        self._reuse_tolerance = tol

    @property
    def online_solves(self) -> int:
        """Number of steps that solved the per-step LMI (the others reused the last solve)."""
        out = ffi.new("int*")
        check(lib.sb_ellipsoidal_online_solves(self._handle, out))
        return int(out[0])


@reconstructible
class ImprovedEstimator(_EllipsoidalEstimator):
    """The measurement-based improved correction of [Merhy2017]: a prediction, then an LMI correction with the new measurement.

    A filter (Methods › Ellipsoidal estimation › Improved correction). The reported bounds intersect
    the corrected and predicted hulls.

    Parameters
    ----------
    design : EllDesign
        An offline design (:func:`design_offline`).
    x0 : Ellipsoid, Box or Zonotope
        Initial set (a box or a zonotope is replaced by the ellipsoid through its hull's corners);
        converted to the design's shape.
    option : {"det_normalized", "fixed_shape", "ball_normalized"}, optional
        Normalisation of the correction: minimum ``ρ'`` with ``det P' ≥ det P`` (the minimum-volume
        corrected set; default), ``P' = P``, or ``P' ⪰ I``.
    feedback : {"fixed_shape", "outer_bound", "none"}, optional
        What the next prediction starts from: ``"fixed_shape"`` (default: solve the fixed-shape
        correction too and feed back the better P-shaped bound), ``"outer_bound"`` (the P-shaped
        bound of the corrected set when smaller: cheaper, rarely helps), ``"none"`` (report only).
    predictor : {"online", "scaled", "offline"}, optional
        The prediction step (default ``"online"``, as [Merhy2017]).
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
    >>> design = setbound.ellipsoidal.design_offline(sys)
    >>> x0 = setbound.Ellipsoid(np.eye(2), [0.0, 0.0], 1.0)
    >>> traj = setbound.ellipsoidal.ImprovedEstimator(design, x0).run(np.zeros((3, 1)))
    >>> bool(traj.contains(np.zeros((3, 2))).all())
    True
    """

    _method = lib.SB_ELL_IMPROVED
    is_filter = True

    def __init__(self, design: EllDesign, x0: Ellipsoid, option: str = "det_normalized", *,
                 feedback: str = "fixed_shape", predictor: str = "online", on_inconsistency: str = "flag",
                 reset_set: Ellipsoid | None = None):
        self.option, self.feedback, self.predictor = option, feedback, predictor
        self._create(design, x0, option=_choice(option, _OPTIONS, "option"),
                     feedback=_choice(feedback, _FEEDBACK, "feedback"),
                     predictor=_choice(predictor, _PREDICTORS, "predictor"),
                     on_inconsistency=on_inconsistency, reset_set=reset_set)


@reconstructible
class DescriptorEstimator(_EllipsoidalEstimator):
    """The descriptor-system estimator of [Merhy2019]: ``x̄_{k+1} = T A x̄_k + T B u_k + N y_{k+1} + L (y_k − C x̄_k)``, ``ρ⁺ = βρ + σ``.

    A filter: row ``k`` uses ``y_0 … y_k`` (row 0 is ``x0`` in the design's shape). It needs every
    output at every step (Methods › Ellipsoidal estimation › Descriptor systems).

    Parameters
    ----------
    design : EllDesign
        A design from ``design_offline(DescriptorSystem(...))``.
    x0 : Ellipsoid, Box or Zonotope
        Initial set.

    Examples
    --------
    >>> E = [[1, 0, 0], [0, 1, 0], [0, 0, 0]]
    >>> A = [[0.5, 0, 0], [0.8, 0.95, 0], [-1, 0.5, 1]]
    >>> C = [[1, 0, 1], [1, -1, 0]]
    >>> D = np.hstack([np.diag([0.1, 1.5, 0.6]), np.zeros((3, 2))])
    >>> F = np.hstack([np.zeros((2, 3)), np.diag([0.5, 1.5])])
    >>> ds = setbound.DescriptorSystem(E, A, C, D=D, F=F)
    >>> est = setbound.ellipsoidal.DescriptorEstimator(setbound.ellipsoidal.design_offline(ds),
    ...                                               setbound.Ellipsoid(np.eye(3), np.zeros(3), 1.0))
    >>> bool(est.run(np.zeros((3, 2))).contains(np.zeros((3, 3))).all())
    True
    """

    _method = lib.SB_ELL_DESCRIPTOR
    is_filter = True

    def __init__(self, design: EllDesign, x0: Ellipsoid):
        if not isinstance(getattr(design, "system", None), DescriptorSystem):
            raise InvalidArgumentError("design: DescriptorEstimator needs a design made for a DescriptorSystem")
        self._create(design, x0, descriptor=design.system)


@reconstructible
class KalmanFilter(StateMixin):
    """The Kalman filter in Joseph form — the contrast, **not guaranteed**.

    ``ω ~ N(0, omega_cov)`` drives ``x⁺ = Ax + Bu + Eω`` and ``y = Cx + Du + Fω`` (correlated
    state/output noise handled); ``x_0 ~ N(mean0, cov0)`` (Methods › Ellipsoidal estimation › Kalman
    filter, as written in [Merhy2017]).

    Parameters
    ----------
    system : LinearSystem
        The model.
    mean0 : array_like, shape (n_x,)
        Initial mean.
    cov0 : array_like, shape (n_x, n_x)
        Initial covariance.
    omega_cov : array_like, shape (n_ω, n_ω), optional
        Covariance of ``ω`` (default: identity).
    nsigma : float, optional
        Half-width of the reported boxes in standard deviations.

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.9]], C=[[1.0]], E=[[0.1, 0.0]], F=[[0.0, 0.1]])
    >>> kf = setbound.ellipsoidal.KalmanFilter(sys, [0.0], [[1.0]])
    >>> traj = kf.run(np.zeros((3, 1)))
    >>> traj.guaranteed, traj.covariance.shape
    (False, (3, 1, 1))
    """

    #: row k of a trajectory used y_k (Trajectory.filter)
    is_filter = True

    def __init__(self, system: LinearSystem, mean0, cov0, omega_cov=None, *, nsigma: float = 3.0):
        system = as_system(system)
        if not isinstance(system, LinearSystem):
            raise InvalidArgumentError(f"system: expected a setbound.LinearSystem, got {type(system).__name__}")
        n = system.nx
        mean0 = as_f64(mean0, "mean0", shape=(n,))
        cov0 = as_f64(cov0, "cov0", shape=(n, n))
        W = None if omega_cov is None else as_f64(omega_cov, "omega_cov", shape=(system.nw, system.nw))
        nsigma = as_float(nsigma, "nsigma", lo=0.0, lo_open=True)
        handle = ffi.new("sb_kalman**")
        check(lib.sb_kalman_create(system._handle, dptr(mean0), dptr(cov0), dptr(W) if W is not None else ffi.NULL,
                                   handle))
        self._handle = ffi.gc(handle[0], lib.sb_kalman_free)
        self.system, self.nsigma = system, float(nsigma)
        self.mean, self.covariance = mean0.copy(), cov0.copy()

    _state_prefix = "sb_kalman"

    def _after_restore(self) -> None:
        m, G = np.empty(self.system.nx), np.empty((self.system.nx, self.system.nx))
        check(lib.sb_kalman_current(self._handle, dptr(m), dptr(G), ffi.NULL))
        self.mean, self.covariance = m, G

    @property
    def steps(self) -> int:
        """Number of steps taken (the last step's mean is about ``x_{steps−1}``)."""
        s = ffi.new("int*")
        check(lib.sb_kalman_current(self._handle, ffi.NULL, ffi.NULL, s))
        return int(s[0])

    def step(self, y, u=None):
        """Correction with ``y_k``, then prediction.

        Parameters
        ----------
        y : array_like, shape (n_y,), or None
            The measurement ``y_k`` (None or NaN entries: missing outputs).
        u : array_like, shape (n_u,), optional
            The input ``u_k``.

        Returns
        -------
        mean : ndarray, shape (n_x,)
        covariance : ndarray, shape (n_x, n_x)
            Of ``x_k`` given ``y_0 … y_k``.
        """
        s = self.system
        y, up = step_inputs(s, measurement_or_missing(y, s.ny), u)
        m, G = np.empty(s.nx), np.empty((s.nx, s.nx))
        check(lib.sb_kalman_step(self._handle, dptr(y), up, dptr(m), dptr(G)))
        self.mean, self.covariance = m, G
        return m.copy(), G.copy()

    @run_from_initial_set
    def run(self, y, u=None) -> Trajectory:
        """Filter a record: the Trajectory of means and ``mean ± nsigma·σ`` boxes (``guaranteed = False``).

        Row ``k`` uses ``y_0 … y_k``; ``covariance`` (N × n × n) is attached.

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
        means, covs = np.empty((N, s.nx)), np.empty((N, s.nx, s.nx))
        for k in range(N):
            means[k], covs[k] = self.step(y[k], u[k] if s.nu > 0 else None)
        sd = self.nsigma * np.sqrt(np.maximum(np.diagonal(covs, axis1=1, axis2=2), 0.0))
        t = Trajectory(means, means - sd, means + sd, [], guaranteed=False)
        t.covariance = covs
        return t


# ---- Bounding ellipsoids with ellipsoidal noise: CORA's ESO-A and ESO-B (issue 22) -------------

_CONVENTIONS = {"setbound": lib.SB_CONVENTION_SETBOUND, "cora": lib.SB_CONVENTION_CORA}


def enclosing_ellipsoid_shape(G) -> np.ndarray:
    """Shape ``Q`` of an ellipsoid ``{Q^{1/2} b : ‖b‖₂ ≤ 1}`` that contains the zonotope ``{G b : ‖b‖∞ ≤ 1}``.

    ``Q = m G Gᵀ`` with ``m`` the number of non-zero columns (``‖b‖₂² ≤ m`` on the box), rounded so
    that it stays an outer bound. It is CORA's ``ellipsoid(Z)`` (the enclosing conversion) with its
    norm bound at its largest value, 1; for ``n`` generators in ``n`` dimensions it is CORA's value
    exactly.

    Parameters
    ----------
    G : array_like, shape (n, m)
        Generators.

    Returns
    -------
    ndarray, shape (n, n)

    Examples
    --------
    >>> Q = setbound.ellipsoidal.enclosing_ellipsoid_shape([[1.0, 0.0], [0.0, 2.0]])
    >>> np.round(Q, 12)
    array([[2., 0.],
           [0., 8.]])
    """
    G = np.atleast_2d(as_f64(G, "G"))
    if G.ndim != 2:
        raise DimensionError(f"G: expected a matrix, got {G.ndim} dimensions")
    n, m = G.shape
    Q = np.empty((n, n))
    check(lib.sb_enclosing_ellipsoid_shape(n, m, dptr(np.ascontiguousarray(G)), dptr(Q)))
    return Q


class _BoundingEllipsoidEstimator(StateMixin):
    _rule: int
    _state_prefix = "sb_bounding_ellipsoid"
    #: row k of a trajectory used y_k
    is_filter = True

    def __init__(self, system: LinearSystem, x0, *, QW=None, QV=None, convention: str = "setbound",
                 step_cap: float = 1e-4):
        system = as_system(system)
        if not isinstance(system, LinearSystem):
            raise InvalidArgumentError(f"system: expected a setbound.LinearSystem, got {type(system).__name__}")
        n, p = system.nx, system.ny
        self.convention = as_choice(convention, "convention", _CONVENTIONS)
        self.step_cap = as_float(step_cap, "step_cap", lo=0.0, hi=1.0, lo_open=True, hi_open=True)
        if isinstance(x0, tuple):
            if len(x0) != 2:
                raise InvalidArgumentError("x0: a tuple must be (centre, shape matrix Q)")
            q0 = as_f64(x0[0], "x0", shape=(n,))
            M = as_f64(x0[1], "x0", shape=(n, n))
            rho0, form = 1.0, lib.SB_BE_X0_SHAPE
        else:
            E = as_ellipsoid(x0, "x0")
            if E.n != n:
                raise DimensionError(f"x0: expected an ellipsoid of dimension {n}, got {E.n}")
            q0, M, rho0, form = E.center, E.P, E.rho, lib.SB_BE_X0_INVERSE
        W = None if QW is None else as_f64(QW, "QW", shape=(n, n))
        V = None if QV is None else as_f64(QV, "QV", shape=(p, p))
        handle = ffi.new("sb_bounding_ellipsoid**")
        check(lib.sb_bounding_ellipsoid_create(system._handle, dptr(W) if W is not None else ffi.NULL,
                                               dptr(V) if V is not None else ffi.NULL, dptr(q0), dptr(M),
                                               float(rho0), form, self._rule, _CONVENTIONS[self.convention],
                                               self.step_cap, handle))
        self._handle = ffi.gc(handle[0], lib.sb_bounding_ellipsoid_free)
        self.system = system
        self._P, self._c, self._rho = np.empty((n, n)), np.empty(n), ffi.new("double*")
        self._lo, self._hi = np.empty(n), np.empty(n)

    @property
    def guaranteed(self) -> bool:
        """True in the ``"setbound"`` convention; CORA's recursion (``"cora"``) is not guaranteed."""
        return self.convention == "setbound"

    @property
    def noise(self) -> tuple[np.ndarray, np.ndarray]:
        """The noise shapes in use, ``(QW, QV)``: ``w ∈ E(0, QW)``, ``v ∈ E(0, QV)``."""
        n, p = self.system.nx, self.system.ny
        QW, QV = np.empty((n, n)), np.empty((p, p))
        check(lib.sb_bounding_ellipsoid_noise(self._handle, dptr(QW), dptr(QV)))
        return QW, QV

    def _snapshot(self):
        return Ellipsoid(self._P.copy(), self._c.copy(), self._rho[0]), self._lo.copy(), self._hi.copy()

    @property
    def current(self) -> Ellipsoid:
        """The set of the last step (the initial set before the first step)."""
        check(lib.sb_bounding_ellipsoid_current(self._handle, dptr(self._P), dptr(self._c), self._rho,
                                                dptr(self._lo), dptr(self._hi)))
        return self._snapshot()[0]

    @property
    def shape(self) -> np.ndarray:
        """The current set in shape form: ``{x : (x − c)ᵀ Q⁻¹ (x − c) ≤ 1}`` (CORA's ``E.Q``)."""
        Q = np.empty((self.system.nx, self.system.nx))
        check(lib.sb_bounding_ellipsoid_shape(self._handle, dptr(Q)))
        return Q

    @property
    def steps(self) -> int:
        """Number of steps taken."""
        s = ffi.new("int*")
        check(lib.sb_bounding_ellipsoid_info(self._handle, ffi.NULL, ffi.NULL, s))
        return int(s[0])

    def last_step(self) -> dict:
        """``lambda`` of the last correction (0: the reading did not change the set) and
        ``inconsistent`` (True when the reading contradicted the prediction, which was then kept)."""
        lam, inc = ffi.new("double*"), ffi.new("int*")
        check(lib.sb_bounding_ellipsoid_info(self._handle, lam, inc, ffi.NULL))
        return {"lambda": float(lam[0]), "inconsistent": bool(inc[0])}

    def reset(self) -> None:
        """Back to the initial set, no step taken."""
        check(lib.sb_bounding_ellipsoid_reset(self._handle))

    def _step(self, y, u):
        s = self.system
        y = as_f64(y, "y", shape=(s.ny,))
        _, up = step_inputs(s, y, u)
        check(lib.sb_bounding_ellipsoid_step(self._handle, dptr(y), up, dptr(self._P), dptr(self._c), self._rho,
                                             dptr(self._lo), dptr(self._hi)))

    def step(self, y, u=None) -> Ellipsoid:
        """Correct with ``y_k``, return the set for ``x_k``, then predict ``x_{k+1}`` with ``u_k``.

        On error (wrong shape, NaN or ±inf) the estimator is unchanged.

        Parameters
        ----------
        y : array_like, shape (n_y,)
            The measurement ``y_k`` (every output is needed).
        u : array_like, shape (n_u,), optional
            The input ``u_k``.

        Returns
        -------
        Ellipsoid
        """
        self._step(y, u)
        return self._snapshot()[0]

    @run_from_initial_set
    def run(self, y, u=None) -> Trajectory:
        """Filter a record from the initial set; row ``k`` is the set for ``x_k`` after ``y_k``.

        Parameters
        ----------
        y : array_like, shape (N, n_y), or control.TimeResponseData
            Measurements.
        u : array_like, shape (N, n_u), optional
            Known inputs.
        reset : bool, optional
            Start from the initial set (default). ``False`` continues from the current state.
        t : array_like, shape (N,), optional
            Time of the rows (default: ``k·dt`` with the system's sampling time, else the step index).

        Returns
        -------
        Trajectory
            ``guaranteed`` is False in the ``"cora"`` convention.
        """
        s = self.system
        y, u = run_inputs(s, y, u)
        N, n = y.shape[0], s.nx
        centers, lows, highs, sets = np.empty((N, n)), np.empty((N, n)), np.empty((N, n)), []
        for k in range(N):
            self._step(y[k], u[k] if s.nu > 0 else None)
            E, lo, hi = self._snapshot()
            centers[k], lows[k], highs[k] = E.center, lo, hi
            sets.append(E)
        return Trajectory(centers, lows, highs, sets, guaranteed=self.guaranteed)


@reconstructible
class OptimalBoundingEllipsoidEstimator(_BoundingEllipsoidEstimator):
    """Optimal bounding ellipsoid (OBE) filter: Gollamudi's correction with Liu's prediction — CORA's ``ESO-A``.

    The model is ``x⁺ = A x + B u + w``, ``y = C x + D u + v`` with ellipsoidal noise
    ``w ∈ E(0, QW)``, ``v ∈ E(0, QV)`` (shape form ``{Q^{1/2} b : ‖b‖₂ ≤ 1}``); the correction
    bounds ``v`` by the ball of radius ``φ = √λ_max(QV)`` and intersects with
    ``‖y − D u − C x‖ ≤ φ`` by Gollamudi, Nagaraj, Kapoor and Huang, *Set-membership state
    estimation with optimal bounding ellipsoids*, ISITA 1996 (Thms. 1–2: the step
    ``λ = min(α, ν)`` that minimises ``σ²``); the prediction encloses the Minkowski sum with the
    trace-optimal parameter of Liu, Zhao and Wu, IET Control Theory Appl. 10(4), 2016 (eqs. 21,
    48). Cost ``O(n³ + n² p + p³)`` per step.

    Parameters
    ----------
    system : LinearSystem
        ``A``, ``B``, ``C``, ``D``; its ``E``, ``F`` give the noise ellipsoids when ``QW`` / ``QV`` are
        not given (each disturbance enclosed by :func:`enclosing_ellipsoid_shape`).
    x0 : Ellipsoid, Box, Zonotope or tuple
        Initial set: a set (a box or a zonotope is enclosed by an ellipsoid), or ``(q0, Q0)``, the
        centre and shape matrix of CORA's ``ellipsoid(Q0, q0)``.
    QW : array_like, shape (n_x, n_x), optional
        Process noise shape (symmetric positive semidefinite).
    QV : array_like, shape (n_y, n_y), optional
        Output noise shape (symmetric positive semidefinite).
    convention : {"setbound", "cora"}, optional
        ``"setbound"`` (default): the paper's algorithm, each set an outer bound after rounding.
        ``"cora"``: CORA's ``priv_observe_ESO_A`` as it is (σ² starts at 0.3, the test against φ
        instead of φ², the centre moved with the old shape, the shape divided by σ²); it reproduces
        CORA's numbers and is **not** guaranteed.
    step_cap : float, optional
        Gollamudi's cap ``α`` on the step ``λ``, in (0, 1) (CORA: 1e-4).

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.9, 0.1], [0.0, 0.8]], C=[[1.0, 0.0]],
    ...                             E=[[0.05, 0.0], [0.0, 0.0]], F=[[0.0, 0.1]])
    >>> est = setbound.ellipsoidal.OptimalBoundingEllipsoidEstimator(sys, setbound.Box([-1, -1], [1, 1]),
    ...                                                              step_cap=0.5)
    >>> traj = est.run(np.zeros((10, 1)))
    >>> bool(traj.contains(np.zeros((10, 2))).all()), traj.guaranteed
    (True, True)
    """

    _rule = lib.SB_BE_GOLLAMUDI


@reconstructible
class EllipsoidalStateBoundingEstimator(_BoundingEllipsoidEstimator):
    """Ellipsoidal state bounding of Liu, Zhao and Wu (IET Control Theory Appl. 10(4), 2016) — CORA's ``ESO-B``.

    Same model and prediction as :class:`OptimalBoundingEllipsoidEstimator`; the correction
    intersects with the noise ellipsoid itself, ``(y − D u − C x)ᵀ QV⁻¹ (y − D u − C x) ≤ 1``,
    with the step of Thm. 3 (eqs. 23–27, 51–52; Gollamudi's ``ν`` in the whitened outputs, no cap).
    Cost ``O(n³ + n² p + p³)`` per step.

    Parameters
    ----------
    system : LinearSystem
        ``A``, ``B``, ``C``, ``D``; its ``E``, ``F`` give the noise ellipsoids when ``QW`` / ``QV`` are
        not given.
    x0 : Ellipsoid, Box, Zonotope or tuple
        Initial set, or ``(q0, Q0)`` (CORA's ``ellipsoid(Q0, q0)``).
    QW : array_like, shape (n_x, n_x), optional
        Process noise shape (symmetric positive semidefinite).
    QV : array_like, shape (n_y, n_y), optional
        Output noise shape (symmetric positive definite).
    convention : {"setbound", "cora"}, optional
        ``"setbound"`` (default): the paper's algorithm, guaranteed after rounding. ``"cora"``: CORA's
        ``priv_observe_ESO_B`` as it is (σ² starts at 0.3, the unweighted test ``σ² + δᵀδ > 1``, the new
        shape multiplied by ``1 − λ``); it reproduces CORA's numbers and is **not** guaranteed.
    step_cap : float, optional
        Not used by this rule (kept for a common signature).

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.9, 0.1], [0.0, 0.8]], C=[[1.0, 0.0]],
    ...                             E=[[0.05, 0.0], [0.0, 0.0]], F=[[0.0, 0.1]])
    >>> est = setbound.ellipsoidal.EllipsoidalStateBoundingEstimator(sys, setbound.Box([-1, -1], [1, 1]))
    >>> traj = est.run(np.zeros((10, 1)))
    >>> bool(traj.contains(np.zeros((10, 2))).all())
    True
    """

    _rule = lib.SB_BE_LIU


# ---- CORA's names (setbound.cora.observe) -------------------------------------------------------

def _cora_noise_generators(system: LinearSystem) -> tuple[np.ndarray, np.ndarray]:
    """W's and V's generators of a model made by setbound.benchmarks.load_cora (E = [G_W, 0],
    F = [0, G_V]): the first split where E has no column on the right and F none on the left."""
    E, F = np.asarray(system.E), np.asarray(system.F)
    for j in range(E.shape[1] + 1):
        if not np.any(E[:, j:]) and not np.any(F[:, :j]):
            return E[:, :j], F[:, j:]
    raise InvalidArgumentError("model: E and F share disturbance columns; CORA's W and V are separate sets "
                               "(E = [G_W, 0], F = [0, G_V], as setbound.benchmarks.load_cora builds them)")


def _cora_ellipsoid_shape(G, mode: str) -> np.ndarray:
    """CORA's ``ellipsoid(Z)`` ("outer") or ``ellipsoid(Z, 'inner:norm')`` ("inner") of the zonotope
    (0, G), as the unit tests apply them before ESO-A/B (spec cora_observers.md §1.6).

    The rank is decided with a relative tolerance of 1e-10 (pedestrian's W is rank 2 in exact data).
    A parallelotope in its span (as many generators as its rank) is exact in both modes: inner
    ``G Gᵀ``; outer ``n G Gᵀ`` with ``n`` full-dimensional generators, else CORA's norm-bound branch
    ``(λ + 1e-6)² m G Gᵀ``. That branch's λ is an SDP's upper bound of the whitened zonotope's norm,
    which is at most 1; λ = 1 is used here (exact for the whitened cube and for pedestrian's W, an
    outer bound always). An inscribed ellipsoid of a zonotope that is not a parallelotope is not
    provided."""
    G = np.asarray(G, float)
    n = G.shape[0]
    G = G[:, np.any(G != 0.0, axis=0)]
    m = G.shape[1]
    if m == 0:
        return np.zeros((n, n))
    sv = np.linalg.svd(G, compute_uv=False)
    r = int(np.sum(sv > 1e-10 * sv[0]))
    GG = G @ G.T
    if mode == "inner":
        if m != r:
            raise InvalidArgumentError("ellipsoids: an inscribed ellipsoid of a zonotope that is not a "
                                       "parallelotope is not provided (CORA's tests never need one)")
        return GG
    if m == n and r == n:
        return n * GG
    return (1.0 + 1e-6) ** 2 * m * GG


def _cora_eso_runner(cls):
    """ESO-A / ESO-B: the R0, W, V zonotopes become ellipsoids first. ``convention="cora"``: as
    CORA's tests convert them (``ellipsoids="auto"``: inscribed for vehicle2 and the 2-D example,
    enclosing otherwise; spec §1.6); ``"setbound"``: enclosing (:func:`enclosing_ellipsoid_shape`),
    so the sets stay guaranteed."""
    def runner(model, *, convention, gain, ellipsoids: str = "auto", **options):
        mode = as_choice(ellipsoids, "ellipsoids", ("auto", "inner", "outer"))
        Gw, Gv = _cora_noise_generators(model.system)
        G0, q0 = np.asarray(model.x0.generators), np.asarray(model.x0.center)
        if convention == "cora":
            if mode == "auto":
                mode = "inner" if model.name.startswith(("vehicle2", "alamo2005")) else "outer"
            QW, QV, Q0 = (_cora_ellipsoid_shape(G, mode) for G in (Gw, Gv, G0))
        else:
            if mode == "inner":
                raise InvalidArgumentError('ellipsoids: "inner" ellipsoids are not outer bounds of the sets; '
                                           'use convention="cora" to reproduce CORA\'s inscribed conversion')
            QW, QV, Q0 = (enclosing_ellipsoid_shape(G) if G.shape[1] else np.zeros((G.shape[0],) * 2)
                          for G in (Gw, Gv, G0))
        est = cls(model.system, (q0, Q0), QW=QW, QV=QV, convention=convention, **options)

        def run():
            t = est.run(model.y, model.u)
            return t.lower, t.upper, t.sets
        return run
    return runner


def _register_cora_names():
    from .cora import register_algorithm
    register_algorithm("ESO-A", _cora_eso_runner(OptimalBoundingEllipsoidEstimator),
                       summary="optimal bounding ellipsoid [Gollamudi 1996] with Liu 2016's prediction "
                               "= OptimalBoundingEllipsoidEstimator")
    register_algorithm("ESO-B", _cora_eso_runner(EllipsoidalStateBoundingEstimator),
                       summary="ellipsoidal state bounding [Liu 2016] = EllipsoidalStateBoundingEstimator")


_register_cora_names()
