"""Thesis Chapter 4: interval observers with an explicit error enclosure (Methods › Interval observers).

* :func:`interval_error_recursion` — the error boxes of ``e⁺ = A_o e + E w`` (› Error recursions):
  ``"tight"`` (exact interval hull ``A_o^k[e_0] + Σ (A_o^i E)[w]``, attained), ``"wrapped"``
  (the thesis's formula, ``[g_0] = E[w]`` boxed first) or ``"naive"`` (4.15, wraps every step).
* :func:`interval_error_limit` — the limit box ``[g] = Σ_{i≥0} A_o^i E[w]``.
* :class:`IntervalLuenbergerObserver` — online observer ``x̂_k + [e_k]``.
* :func:`offline_error_sequence` + :class:`IntervalInvariantObserver` — a precomputed
  box sequence ``[s_0..s_k*]`` with a polyhedral-invariant-set tail; online only the point
  observer runs.
* :class:`NonlinearIntervalObserver` — ``x⁺ = A x + h(p, x, k) + B u`` with an inclusion
  box of ``h`` per step (a callable, or a constant :class:`~setbound.Box`).

All observers are one-step predictors: ``run(y, u)`` returns a :class:`~setbound.Trajectory`
whose row ``k`` bounds ``x_k`` having used ``y_0 … y_{k−1}`` (row 0 is the initial box), with
one :class:`~setbound.Box` per row in ``sets``, and row ``k``'s ``status``/``margin`` saying
what the step did with ``y_k``. Real data (:mod:`setbound.measurement`): NaN entries of ``y``
are missing outputs; each present reading is tested against ``C_i[x_k] + Z_i[v]``; a step
without some output is made in interval arithmetic (the box narrowed by the outputs present,
then propagated) and the error bound restarts from the predicted box. ``on_inconsistency``:
``"flag"`` (default), ``"raise"`` or ``"reset"`` (to ``reset_set``, default the initial box). Every box is guaranteed in floating point
(docs/thesis_interval.md). A gain ``L=None`` means the H∞ gain of LMI (4.13) (``Q = I``;
for the nonlinear observer LMI (4.46), i.e. ``F = I``).
"""
from __future__ import annotations

import pickle
from typing import Callable, Union

import numpy as np

from ._native import as_f64, check, dptr, ffi, lib
from ._state import MadeByCall, StateMixin, reconstructible, remember_call, run_from_initial_set
from ._state import _reduce as _state_reduce
from ._validate import INT_MAX, as_float, as_int, check_memory
from .errors import DimensionError, InvalidArgumentError
from .interval import Box
from .plant import Plant, as_plant
from .measurement import ReadingChecks, measurement_or_missing, _set_box_policy
from .system import refuse_infinite
from .trajectory import Trajectory

__all__ = [
    "interval_error_recursion",
    "interval_error_limit",
    "IntervalLuenbergerObserver",
    "NonlinearIntervalObserver",
    "InvariantObserverDesign",
    "offline_error_sequence",
    "IntervalInvariantObserver",
    "CoraIntervalObserver",
]

_VARIANTS = {"tight": 0, "wrapped": 1, "naive": 2}
#: Upper bound of ``window`` of :class:`NonlinearIntervalObserver`.
MAX_WINDOW = lib.SB_INTERVAL_MAX_WINDOW  # 100000, the C library refuses more too
#: Python memory of one Box of the result of interval_error_recursion besides its 2 n doubles.
_BOX_BYTES = 400


def _variant(v: str, allow_naive: bool = True) -> int:
    if not isinstance(v, str):  # str(v) would turn any object into a (wrong) name
        allowed = "'tight', 'wrapped'" + (", 'naive'" if allow_naive else "")
        raise InvalidArgumentError(f"variant: expected one of {allowed}, got {v!r} ({type(v).__name__})")
    key = v.lower()
    if key not in _VARIANTS or (key == "naive" and not allow_naive):
        allowed = "'tight', 'wrapped'" + (", 'naive'" if allow_naive else "")
        raise InvalidArgumentError(f"variant: expected one of {allowed}, got {v!r}")
    return _VARIANTS[key]


def _box(b, n: int, name: str) -> Box:
    """A Box of n components: a Box, a (lo, hi) pair, or the interval hull of a zonotope or an
    ellipsoid (a guaranteed enclosure; setbound.sets.as_box)."""
    from .sets import Ellipsoid, Zonotope, as_box

    if isinstance(b, (Zonotope, Ellipsoid)):
        b = as_box(b, name)
    if not isinstance(b, Box):
        try:
            lo, hi = b
        except (TypeError, ValueError):
            raise InvalidArgumentError(f"{name}: expected a setbound.Box or a (lo, hi) pair") from None
        b = Box(np.atleast_1d(np.asarray(lo, dtype=float)), np.atleast_1d(np.asarray(hi, dtype=float)), name=name)
    if len(b) != n:
        raise DimensionError(f"{name}: expected a box with {n} components, got {len(b)}")
    return b


def _lohi(b: Box):
    lo = np.ascontiguousarray(b.lo, dtype=np.float64)
    hi = np.ascontiguousarray(b.hi, dtype=np.float64)
    return lo, hi


def _plant(plant) -> Plant:
    return as_plant(plant)  # a Plant, or a LinearSystem / StateSpace converted (unit-box d, v)


def _plant_args(p: Plant):
    arrs = [np.ascontiguousarray(m, dtype=np.float64) for m in (p.A, p.B, p.C, p.F, p.Z)]
    return arrs, [dptr(a) for a in arrs]


def interval_error_recursion(Ao, E, e0, w, steps: int, variant: str = "tight") -> list[Box]:
    """The boxes ``[e_0] … [e_steps]`` of ``e⁺ = A_o e + E w`` for every ``e_0 ∈ e0`` and ``w_k ∈ w`` (Methods › Interval observers › Error recursions).

    Parameters
    ----------
    Ao : array_like, shape (n, n)
        Error matrix.
    E : array_like, shape (n, m)
        Error-input matrix.
    e0 : Box or (array_like, array_like)
        Initial error box.
    w : Box or (array_like, array_like)
        The box of ``w``.
    steps : int
        Number of steps, ``>= 0`` (about 16·n + 400 bytes per step; refused above half the
        machine's memory before anything is computed).
    variant : {"tight", "wrapped", "naive"}, optional
        The exact hull (default), the thesis's numbers, or the naive recursion (4.15), which
        re-boxes at every step and may diverge.

    Returns
    -------
    list of Box

    Examples
    --------
    The wrapping effect: re-boxing at every step (``"naive"``) grows where the exact hull shrinks.

    >>> c = 0.9 * np.sqrt(0.5)
    >>> Ao, E = [[c, -c], [c, c]], np.zeros((2, 1))
    >>> e0, w = setbound.Box([-1, -1], [1, 1]), setbound.Box([0.0], [0.0])
    >>> tight = setbound.interval_error_recursion(Ao, E, e0, w, 6)
    >>> naive = setbound.interval_error_recursion(Ao, E, e0, w, 6, variant="naive")
    >>> bool(naive[-1].width.max() > 2 > tight[-1].width.max())
    True
    """
    steps = as_int(steps, "steps", lo=0, hi=INT_MAX - 1)  # steps + 1 boxes cross the C ABI
    variant_code = _variant(variant)
    Ao = as_f64(Ao, "Ao", ndim=2)
    n = Ao.shape[0]
    E = as_f64(E, "E", ndim=2)
    if E.shape[0] != n:
        raise DimensionError(f"E: expected {n} rows, got {E.shape[0]}")
    m = E.shape[1]
    e0, w = _box(e0, n, "e0"), _box(w, m, "w")
    check_memory("steps", steps, (steps + 1) * (16.0 * n + _BOX_BYTES))
    lo, hi = np.empty((steps + 1, n)), np.empty((steps + 1, n))
    (elo, ehi), (wlo, whi) = _lohi(e0), _lohi(w)
    check(lib.sb_interval_error_recursion(n, m, dptr(Ao), dptr(E), dptr(elo), dptr(ehi), dptr(wlo), dptr(whi),
                                          steps, variant_code, dptr(lo), dptr(hi)))
    return [Box(lo[k], hi[k]) for k in range(steps + 1)]


def interval_error_limit(Ao, E, w, variant: str = "tight") -> Box:
    """The limit box ``[g] = Σ_{i≥0} A_o^i E [w]`` (tight) or ``Σ A_o^i (E[w])`` (wrapped).

    Parameters
    ----------
    Ao : array_like, shape (n, n)
        Schur-stable error matrix.
    E : array_like, shape (n, m)
        Error-input matrix.
    w : Box or (array_like, array_like)
        The box of ``w``.
    variant : {"tight", "wrapped"}, optional
        Exact hull or the thesis's formula.

    Returns
    -------
    Box

    Examples
    --------
    >>> g = setbound.interval_error_limit([[0.5]], [[1.0]], setbound.Box([-1.0], [1.0]))
    >>> print(np.round(g.lo, 9), np.round(g.hi, 9))  # 1 + 0.5 + 0.25 + ... = 2, rounded outward
    [-2.] [2.]
    """
    Ao = as_f64(Ao, "Ao", ndim=2)
    n = Ao.shape[0]
    E = as_f64(E, "E", ndim=2)
    if E.shape[0] != n:
        raise DimensionError(f"E: expected {n} rows, got {E.shape[0]}")
    w = _box(w, E.shape[1], "w")
    lo, hi = np.empty(n), np.empty(n)
    wlo, whi = _lohi(w)
    check(lib.sb_interval_error_limit(n, E.shape[1], dptr(Ao), dptr(E), dptr(wlo), dptr(whi), _variant(variant),
                                      dptr(lo), dptr(hi)))
    return Box(lo, hi)


class _OnlineObserver(ReadingChecks, StateMixin):
    """Shared step/run logic (one-step predictors)."""

    _prefix = ""
    #: row k of a trajectory used y_0 … y_{k−1} only (Trajectory.filter)
    is_filter = False

    @property
    def _state_prefix(self) -> str:
        return self._prefix

    def _reading_ny(self) -> int:
        return self.plant.ny

    def _set_policy(self, on_inconsistency: str, reset_set) -> None:
        #: what a step does with an impossible reading (:mod:`setbound.measurement`)
        self.on_inconsistency = _set_box_policy(getattr(lib, self._prefix + "_set_inconsistency_policy"),
                                               self._handle, on_inconsistency, reset_set, self.plant.nx)
        self._init_checks()

    def _y(self, y):
        """One reading (None or NaN entries: missing outputs)."""
        return as_f64(np.atleast_1d(measurement_or_missing(y, self.plant.ny)), "y", shape=(self.plant.ny,))

    def _io(self):
        n = self.plant.nx
        return np.empty(n), np.empty(n), np.empty(n)

    def _u(self, u):
        p = self.plant
        if p.nu > 0:
            if u is None:
                raise InvalidArgumentError(f"u: the plant has {p.nu} inputs; an input is required")
            u = as_f64(np.atleast_1d(u), "u", shape=(p.nu,))
            return u, dptr(u)
        if u is not None and np.size(u) != 0:
            raise DimensionError("u: the plant has no input")
        return None, ffi.NULL

    def current(self) -> Box:
        """The box of ``x_k`` (k = steps taken)."""
        xh, lo, hi = self._io()
        check(getattr(lib, self._prefix + "_current")(self._handle, dptr(xh), dptr(lo), dptr(hi)))
        return Box(lo, hi)

    @property
    def xhat(self) -> np.ndarray:
        """The point observer's state ``x̂_k``."""
        xh, lo, hi = self._io()
        check(getattr(lib, self._prefix + "_current")(self._handle, dptr(xh), dptr(lo), dptr(hi)))
        return xh

    @run_from_initial_set
    def run(self, y, u=None, **kw) -> Trajectory:
        """Process a record; row ``k`` bounds ``x_k`` having used ``y_0 … y_{k−1}`` (row 0 is the initial box).

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
        **kw
            Passed to each ``step`` (the nonlinear observer's ``h``).

        Returns
        -------
        Trajectory
            Row ``k`` is about ``x_k``; ``status``, ``margin`` and ``resets`` say what each step did
            with each reading.
        """
        p = self.plant
        y = as_f64(y, "y", ndim=2)
        N = y.shape[0]
        if y.shape[1] != p.ny:
            raise DimensionError(f"y: expected shape (N, {p.ny}), got {y.shape}")
        refuse_infinite(y)  # NaN: a missing reading
        if p.nu > 0:
            u = as_f64(u, "u", shape=(N, p.nu))
        elif u is not None and np.size(u) != 0:
            raise DimensionError("u: the plant has no input")
        lows, highs, sets = np.empty((N, p.nx)), np.empty((N, p.nx)), []
        status, margin = np.empty((N, p.ny), dtype=np.int8), np.empty((N, p.ny))
        resets = np.zeros(N, dtype=bool)
        for k in range(N):
            b = self.current()
            lows[k], highs[k] = b.lo, b.hi
            sets.append(b)
            self.step(y[k], u[k] if p.nu > 0 else None, **kw)
            resets[k] = self._check_into(status[k], margin[k])
        return Trajectory(0.5 * (lows + highs), lows, highs, sets, status=status, margin=margin, resets=resets)


@reconstructible
class IntervalLuenbergerObserver(_OnlineObserver):
    """The interval Luenberger observer of [Loukkas2018] Chapter 4 (Methods › Interval observers › Interval Luenberger observer).

    ``x̂⁺ = A x̂ + B u + L (y − C x̂)`` (4.9) and ``[x_k] = x̂_k + [e_k]`` (4.12) with the tight
    (default) or wrapped error recursion.

    Parameters
    ----------
    plant : Plant or LinearSystem
        The plant.
    x0 : Box, Zonotope or Ellipsoid
        Initial set (its interval hull is used).
    xhat0 : array_like, shape (n_x,), optional
        Initial estimate in ``x0`` (default: its centre).
    d, v : Box or (array_like, array_like), optional
        Disturbance and noise boxes (default: the unit box).
    L : array_like, shape (n_x, n_y), optional
        Gain; ``None``: the H∞ gain of LMI (4.13) (then ``gamma`` and ``P`` are the design's).
    variant : {"tight", "wrapped"}, optional
        Error recursion: the exact interval hull, or the thesis's formula.
    on_inconsistency : {"flag", "raise", "reset"}, optional
        What a reading outside the predicted output set does (:mod:`setbound.measurement`):
        skipped and flagged (default), an :class:`~setbound.errors.InconsistentMeasurementError`,
        or a restart from ``reset_set``.
    reset_set : optional
        The restart set of ``on_inconsistency="reset"`` (default: the initial set).

    Examples
    --------
    >>> plant = setbound.Plant([[0.5, 0.1], [0.0, 0.6]], [[1.0, 0.0]], Fd=0.1 * np.eye(2), Z=[[0.05]])
    >>> obs = setbound.IntervalLuenbergerObserver(plant, setbound.Box([-1, -1], [1, 1]))
    >>> traj = obs.run(np.zeros((4, 1)))
    >>> bool(traj.contains(np.zeros((4, 2))).all())
    True
    """

    _prefix = "sb_interval_luenberger"
    _last_check_fn = lib.sb_interval_luenberger_last_check

    def __init__(self, plant: Plant, x0, xhat0=None, d=None, v=None, *, L=None, variant: str = "tight",
                 on_inconsistency: str = "flag", reset_set=None):
        p = self.plant = _plant(plant)
        x0 = _box(x0, p.nx, "x0")
        xhat0 = 0.5 * (np.asarray(x0.lo) + np.asarray(x0.hi)) if xhat0 is None else xhat0
        d = _box(d if d is not None else (-np.ones(p.nd), np.ones(p.nd)), p.nd, "d")
        v = _box(v if v is not None else (-np.ones(p.nv), np.ones(p.nv)), p.nv, "v")
        xh = as_f64(xhat0, "xhat0", shape=(p.nx,))
        Lp = ffi.NULL
        if L is not None:
            L = as_f64(L, "L", shape=(p.nx, p.ny))
            Lp = dptr(L)
        arrs, ptrs = _plant_args(p)
        (x0lo, x0hi), (dlo, dhi), (vlo, vhi) = _lohi(x0), _lohi(d), _lohi(v)
        h = ffi.new("sb_interval_luenberger**")
        check(lib.sb_interval_luenberger_create(p.nx, p.nu, p.ny, p.nd, p.nv, *ptrs, Lp, dptr(x0lo), dptr(x0hi),
                                                dptr(xh), dptr(dlo), dptr(dhi), dptr(vlo), dptr(vhi),
                                                _variant(variant, False), h))
        self._handle = ffi.gc(h[0], lib.sb_interval_luenberger_free)
        self._set_policy(on_inconsistency, reset_set)
        self.variant = variant
        Lo, Po = np.empty((p.nx, p.ny)), np.full((p.nx, p.nx), np.nan)
        check(lib.sb_interval_luenberger_gain(self._handle, dptr(Lo), dptr(Po)))
        g, fi, c = ffi.new("double*"), ffi.new("int*"), ffi.new("double*")
        check(lib.sb_interval_luenberger_info(self._handle, ffi.NULL, fi, c, g))
        #: the gain used; ``P``/``gamma``: the H∞ design (None/NaN for a user gain)
        self.L = Lo
        self.P = None if L is not None else Po
        self.gamma = float(g[0])
        self.freeze_index = int(fi[0])
        self.contraction = float(c[0])

    @property
    def steps(self) -> int:
        """Number of steps taken (k of the current box)."""
        s = ffi.new("int*")
        check(lib.sb_interval_luenberger_info(self._handle, s, ffi.NULL, ffi.NULL, ffi.NULL))
        return int(s[0])

    def step(self, y, u=None) -> Box:
        """Use ``y_k`` (and ``u_k``); returns the box of ``x_{k+1}``. On error the observer is unchanged.

        Parameters
        ----------
        y : array_like, shape (n_y,), or None
            The measurement ``y_k`` (None or NaN entries: missing outputs).
        u : array_like, shape (n_u,), optional
            The input ``u_k``.

        Returns
        -------
        Box
        """
        y = self._y(y)
        _, up = self._u(u)
        xh, lo, hi = self._io()
        check(lib.sb_interval_luenberger_step(self._handle, dptr(y), up, dptr(xh), dptr(lo), dptr(hi)))
        return Box(lo, hi)


HBox = Union[Box, Callable[[Box, int], Box]]


@reconstructible
class NonlinearIntervalObserver(_OnlineObserver):
    """The nonlinear interval observer of [Loukkas2018] §4.6 for ``x⁺ = A x + h(p, x, k) + B u``, ``y = C x + Z v`` (Methods › Interval observers › Nonlinear interval observer).

    The plant's ``F`` must be ``I`` (``E = [I, −LZ]``). The error box stays the exact tight hull
    when ``[h]_k`` varies: the last ``window`` radii are convolved with the powers of ``A_o``; older
    ones are bounded by a certified geometric tail.

    Parameters
    ----------
    plant : Plant
        The linear part (``Fd`` the identity).
    x0 : Box, Zonotope or Ellipsoid
        Initial set.
    xhat0 : array_like, shape (n_x,)
        Initial estimate.
    v : Box or (array_like, array_like), optional
        Noise box (default: the unit box).
    h : Box or callable, optional
        The thesis's constant ``[h]``, or ``h(x_box, k) -> Box`` returning an inclusion of
        ``h(p, x_k, k)`` for every ``x_k ∈ x_box`` and every admissible parameter.
    L : array_like, optional
        Gain (default: LMI (4.46)).
    window : int, optional
        In ``[1, MAX_WINDOW]`` (100000; the work per step grows with it); the window used is
        ``min(window, K)``, K the number of stored powers of ``A_o`` (reported as ``.window``).
    on_inconsistency : {"flag", "raise", "reset"}, optional
        What a reading outside the predicted output set does (:mod:`setbound.measurement`):
        skipped and flagged (default), an :class:`~setbound.errors.InconsistentMeasurementError`,
        or a restart from ``reset_set``.
    reset_set : optional
        The restart set of ``on_inconsistency="reset"`` (default: the initial set).

    Examples
    --------
    A constant inclusion box ``[h] = [−0.1, 0.1]²``:

    >>> plant = setbound.Plant([[0.3, -0.7], [0.6, -0.5]], [[1.0, 0.0]], Fd=np.eye(2), Z=[[1.0]])
    >>> obs = setbound.NonlinearIntervalObserver(plant, setbound.Box([-1, -1], [1, 1]), [0.0, 0.0],
    ...                                          v=setbound.Box([-0.1], [0.1]), h=setbound.Box([-0.1, -0.1], [0.1, 0.1]))
    >>> traj = obs.run(np.zeros((4, 1)))
    >>> bool(traj.in_bounds(np.zeros((4, 2))).all())
    True
    """

    _prefix = "sb_interval_nonlinear"
    _last_check_fn = lib.sb_interval_nonlinear_last_check

    def __init__(self, plant: Plant, x0, xhat0, v=None, h: HBox | None = None, *, L=None, window: int = 256,
                 on_inconsistency: str = "flag", reset_set=None):
        # the C ABI reads window <= 0 as the default: refused here instead
        window = as_int(window, "window", lo=1, hi=MAX_WINDOW)
        p = self.plant = _plant(plant)
        if p.nd != p.nx or not np.array_equal(p.F, np.eye(p.nx)):
            raise InvalidArgumentError("plant.F: the nonlinear observer needs F = I (h enters the state directly, "
                                       "E = [I, -L Z], Methods › Interval observers › Nonlinear interval observer)")
        x0 = _box(x0, p.nx, "x0")
        v = _box(v if v is not None else (-np.ones(p.nv), np.ones(p.nv)), p.nv, "v")
        xh = as_f64(xhat0, "xhat0", shape=(p.nx,))
        if h is not None and not isinstance(h, Box) and not callable(h):
            raise InvalidArgumentError("h: expected a setbound.Box or a callable (x_box, k) -> Box")
        if isinstance(h, Box):
            _box(h, p.nx, "h")
        self.h = h
        Lp = ffi.NULL
        if L is not None:
            L = as_f64(L, "L", shape=(p.nx, p.ny))
            Lp = dptr(L)
        A, B, C, Z = (np.ascontiguousarray(m, dtype=np.float64) for m in (p.A, p.B, p.C, p.Z))
        (x0lo, x0hi), (vlo, vhi) = _lohi(x0), _lohi(v)
        hh = ffi.new("sb_interval_nonlinear**")
        check(lib.sb_interval_nonlinear_create(p.nx, p.nu, p.ny, p.nv, dptr(A), dptr(B), dptr(C), dptr(Z), Lp,
                                               dptr(x0lo), dptr(x0hi), dptr(xh), dptr(vlo), dptr(vhi), window,
                                               hh))
        self._handle = ffi.gc(hh[0], lib.sb_interval_nonlinear_free)
        self._set_policy(on_inconsistency, reset_set)
        Lo, Po = np.empty((p.nx, p.ny)), np.full((p.nx, p.nx), np.nan)
        check(lib.sb_interval_nonlinear_gain(self._handle, dptr(Lo), dptr(Po)))
        g, wi = ffi.new("double*"), ffi.new("int*")
        check(lib.sb_interval_nonlinear_info(self._handle, ffi.NULL, wi, g))
        self.L = Lo
        self.P = None if L is not None else Po
        self.gamma = float(g[0])
        self.window = int(wi[0])

    def __reduce__(self):
        """Pickles the construction arguments and the state; the callable ``h`` must pickle."""
        if self.h is not None and not isinstance(self.h, Box):
            try:
                pickle.dumps(self.h)
            except Exception as e:  # noqa: BLE001 - any pickling failure of the user's callable
                raise InvalidArgumentError(f"h: the nonlinearity callable cannot be pickled ({type(e).__name__}: {e}); "
                                           "use a module-level function or a Box, or save_state() and rebuild the "
                                           "observer with the callable yourself") from e
        return _state_reduce(self)

    @property
    def steps(self) -> int:
        """Number of steps taken (k of the current box)."""
        s = ffi.new("int*")
        check(lib.sb_interval_nonlinear_info(self._handle, s, ffi.NULL, ffi.NULL))
        return int(s[0])

    def step(self, y, u=None, h: HBox | None = None) -> Box:
        """Use ``y_k``, ``u_k`` and the inclusion box of ``h`` at step ``k``; returns the box of ``x_{k+1}``.

        On error the observer is unchanged.

        Parameters
        ----------
        y : array_like, shape (n_y,), or None
            The measurement ``y_k`` (None or NaN entries: missing outputs).
        u : array_like, shape (n_u,), optional
            The input ``u_k``.
        h : Box, optional
            The inclusion of ``h`` at this step (default: the one given at construction, a Box or
            ``h(current_box, k)``).

        Returns
        -------
        Box
        """
        p = self.plant
        y = self._y(y)
        _, up = self._u(u)
        src = h if h is not None else self.h
        if src is None:
            raise InvalidArgumentError("h: no nonlinearity box given (pass h to the constructor or to step)")
        hb = src if isinstance(src, Box) else src(self.current(), self.steps)
        if not isinstance(hb, Box):
            hb = _box(hb, p.nx, "h")
        if len(hb) != p.nx:
            raise DimensionError(f"h: expected a box with {p.nx} components, got {len(hb)}")
        hlo, hhi = _lohi(hb)
        xh, lo, hi = self._io()
        check(lib.sb_interval_nonlinear_step(self._handle, dptr(y), up, dptr(hlo), dptr(hhi), dptr(xh), dptr(lo),
                                             dptr(hi)))
        return Box(lo, hi)


class InvariantObserverDesign(MadeByCall):
    """The offline design of the invariant-set interval observer (from :func:`offline_error_sequence`; Methods › Interval observers › Invariant-set observer).

    Attributes: ``L``, ``P``, ``E``, ``gamma`` (LMI 4.13), ``beta`` (``A_oᵀPA_o ⪯ β²P``), ``mu``,
    ``inflation`` (λ used), ``inflation_min`` (smallest λ with ``[e_0] ⊆ λΦ_0``), ``epsilon`` (a
    radius), ``k_star``, ``c_in``/``c_out`` (levels of Ψ̄⁺(μ), Ψ̄(μ)), ``sequence`` (list of the
    error boxes ``[s_0] … [s_k*]``; ``[s_k] = [s_k*]`` for k ≥ k*), ``lower``/``upper``
    ((k*+1) × n arrays of the same), ``shrinking_index`` (ρ(k), k = 0..k*) and ``phi0_vertices``
    (n × p), ``phi0_H``, ``phi0_b`` (``Φ_0 = {x : Hx ≤ b}``).

    Parameters
    ----------
    handle : cffi pointer
        The C design (made by :func:`offline_error_sequence`, not by users).
    plant : Plant
        The plant.
    x0 : Box
        Initial set.
    xhat0 : ndarray
        Initial estimate.
    """

    def __init__(self, handle, plant: Plant, x0: Box, xhat0: np.ndarray):
        self._handle = handle
        self.plant, self.x0, self.xhat0 = plant, x0, xhat0
        n = plant.nx
        ks, nv, nf = ffi.new("int*"), ffi.new("int*"), ffi.new("int*")
        d = [ffi.new("double*") for _ in range(8)]
        check(lib.sb_interval_invariant_design_info(handle, ks, nv, nf, *d))
        self.k_star = int(ks[0])
        (self.gamma, self.beta, self.mu, self.inflation, self.inflation_min, self.epsilon, self.c_in,
         self.c_out) = (float(x[0]) for x in d)
        self.L, self.P, self.E = np.empty((n, plant.ny)), np.empty((n, n)), np.empty((n, plant.m))
        check(lib.sb_interval_invariant_design_matrices(handle, dptr(self.L), dptr(self.P), dptr(self.E)))
        K = self.k_star + 1
        self.lower, self.upper, self.shrinking_index = np.empty((K, n)), np.empty((K, n)), np.empty(K)
        check(lib.sb_interval_invariant_design_sequence(handle, dptr(self.lower), dptr(self.upper),
                                                        dptr(self.shrinking_index)))
        self.sequence = [Box(self.lower[k], self.upper[k]) for k in range(K)]
        self.phi0_vertices = np.empty((n, int(nv[0])))
        self.phi0_H, self.phi0_b = np.empty((int(nf[0]), n)), np.empty(int(nf[0]))
        check(lib.sb_interval_invariant_design_phi0(handle, dptr(self.phi0_vertices), dptr(self.phi0_H),
                                                    dptr(self.phi0_b)))

    def box_at(self, k: int) -> Box:
        """The error box ``[s_k]`` (constant for ``k ≥ k*``).

        Parameters
        ----------
        k : int
            Step, ``>= 0``.

        Returns
        -------
        Box
        """
        return self.sequence[min(as_int(k, "k", lo=0, hi=None), self.k_star)]

    def __repr__(self) -> str:
        return (f"InvariantObserverDesign(gamma={self.gamma:.6g}, beta={self.beta:.6g}, k_star={self.k_star}, "
                f"inflation={self.inflation:.6g}, mu={self.mu}, epsilon={self.epsilon})")


def offline_error_sequence(plant: Plant, x0, xhat0, d=None, v=None, *, L=None, P=None, gamma=None, mu: float = 2.0,
                           inflation: float | None = None, epsilon: float = 0.01,
                           variant: str = "tight") -> InvariantObserverDesign:
    """Offline design of the invariant-set interval observer (Methods › Interval observers › Invariant-set observer).

    Parameters
    ----------
    plant : Plant or LinearSystem
        The plant.
    x0 : Box, Zonotope or Ellipsoid
        Initial set.
    xhat0 : array_like, shape (n_x,)
        Initial estimate.
    d, v : Box or (array_like, array_like), optional
        Disturbance and noise boxes (default: the unit box).
    L : array_like, optional
        Gain; ``None``: the H∞ gain of LMI (4.13). Otherwise ``L``, ``P`` and ``gamma`` must
        satisfy (4.13) (checked).
    P : array_like, optional
        Lyapunov matrix with a user ``L``.
    gamma : float, optional
        H∞ level with a user ``L`` (finite, > 0).
    mu : float, optional
        Expansion factor, finite and > 1.
    inflation : float, optional
        ``None``: the smallest λ ≥ 1 with ``[e_0] ⊆ λΦ_0``; else a finite number >= 1.
    epsilon : float, optional
        Stop radius (finite, > 0).
    variant : {"tight", "wrapped"}, optional
        Interval part (the thesis's Table 4.1 rows 1–2).

    Returns
    -------
    InvariantObserverDesign

    Examples
    --------
    >>> plant = setbound.Plant([[0.5, 0.1], [0.0, 0.6]], [[1.0, 0.0]], Fd=0.1 * np.eye(2), Z=[[0.05]])
    >>> design = setbound.offline_error_sequence(plant, setbound.Box([-1, -1], [1, 1]), [0.0, 0.0])
    >>> design.k_star >= 0, design.box_at(design.k_star + 5).subset(design.box_at(0))
    (True, True)
    """
    call = ((plant, x0, xhat0, d, v), dict(L=L, P=P, gamma=gamma, mu=mu, inflation=inflation, epsilon=epsilon,
                                            variant=variant))
    mu = as_float(mu, "mu", lo=1.0, lo_open=True)
    inflation = 0.0 if inflation is None else as_float(inflation, "inflation", lo=1.0)  # C: 0 = the smallest
    epsilon = as_float(epsilon, "epsilon", lo=0.0, lo_open=True)
    gamma = None if gamma is None else as_float(gamma, "gamma", lo=0.0, lo_open=True)
    variant_code = _variant(variant, False)
    p = _plant(plant)
    x0 = _box(x0, p.nx, "x0")
    d = _box(d if d is not None else (-np.ones(p.nd), np.ones(p.nd)), p.nd, "d")
    v = _box(v if v is not None else (-np.ones(p.nv), np.ones(p.nv)), p.nv, "v")
    xh = as_f64(xhat0, "xhat0", shape=(p.nx,)).copy()
    Lp = Pp = ffi.NULL
    g = float("nan")
    if L is not None:
        if P is None or gamma is None:
            raise InvalidArgumentError("P: a user gain L needs the matching P and gamma of LMI (4.13)")
        L = as_f64(L, "L", shape=(p.nx, p.ny))
        P = as_f64(P, "P", shape=(p.nx, p.nx))
        Lp, Pp, g = dptr(L), dptr(P), gamma
    arrs, ptrs = _plant_args(p)
    (x0lo, x0hi), (dlo, dhi), (vlo, vhi) = _lohi(x0), _lohi(d), _lohi(v)
    h = ffi.new("sb_interval_invariant_design**")
    check(lib.sb_interval_invariant_design_create(p.nx, p.nu, p.ny, p.nd, p.nv, *ptrs, Lp, Pp, g, dptr(x0lo),
                                                  dptr(x0hi), dptr(xh), dptr(dlo), dptr(dhi), dptr(vlo), dptr(vhi),
                                                  mu, inflation, epsilon, variant_code, h))
    return remember_call(InvariantObserverDesign(ffi.gc(h[0], lib.sb_interval_invariant_design_free), p, x0, xh),
                         offline_error_sequence, *call[0], **call[1])


@reconstructible
class IntervalInvariantObserver(_OnlineObserver):
    """The invariant-set interval observer of [Loukkas2018] §4.4 (Methods › Interval observers › Invariant-set observer).

    ``x̂⁺ = A x̂ + B u + L (y − C x̂) + E w_c`` (4.34) and the table look-up
    ``[x_k] = x̂_k + [s_min(k, k*)]`` of the offline error boxes.

    Parameters
    ----------
    design : InvariantObserverDesign
        The offline design (:func:`offline_error_sequence`).
    on_inconsistency : {"flag", "raise", "reset"}, optional
        What a reading outside the predicted output set does (:mod:`setbound.measurement`):
        skipped and flagged (default), an :class:`~setbound.errors.InconsistentMeasurementError`,
        or a restart from ``reset_set``.
    reset_set : optional
        The restart set of ``on_inconsistency="reset"`` (default: the initial set).

    Examples
    --------
    >>> plant = setbound.Plant([[0.5, 0.1], [0.0, 0.6]], [[1.0, 0.0]], Fd=0.1 * np.eye(2), Z=[[0.05]])
    >>> design = setbound.offline_error_sequence(plant, setbound.Box([-1, -1], [1, 1]), [0.0, 0.0])
    >>> traj = setbound.IntervalInvariantObserver(design).run(np.zeros((4, 1)))
    >>> bool(traj.in_bounds(np.zeros((4, 2))).all())
    True
    """

    _prefix = "sb_interval_invariant"
    _last_check_fn = lib.sb_interval_invariant_last_check

    def __init__(self, design: InvariantObserverDesign, *, on_inconsistency: str = "flag", reset_set=None):
        if not isinstance(design, InvariantObserverDesign):
            raise InvalidArgumentError("design: expected the result of offline_error_sequence")
        self.design = design
        self.plant = design.plant
        h = ffi.new("sb_interval_invariant**")
        check(lib.sb_interval_invariant_create(design._handle, h))
        self._handle = ffi.gc(h[0], lib.sb_interval_invariant_free)
        self._set_policy(on_inconsistency, reset_set)

    @property
    def steps(self) -> int:
        """Number of steps taken (k of the current box)."""
        s = ffi.new("int*")
        check(lib.sb_interval_invariant_info(self._handle, s))
        return int(s[0])

    def step(self, y, u=None) -> Box:
        """Use ``y_k`` (and ``u_k``); returns the box of ``x_{k+1}``.

        ``last_check`` says what the step did with each output.

        Parameters
        ----------
        y : array_like, shape (n_y,), or None
            The measurement ``y_k`` (None or NaN entries: missing outputs).
        u : array_like, shape (n_u,), optional
            The input ``u_k``.

        Returns
        -------
        Box
        """
        y = self._y(y)
        _, up = self._u(u)
        xh, lo, hi = self._io()
        check(lib.sb_interval_invariant_step(self._handle, dptr(y), up, dptr(xh), dptr(lo), dptr(hi)))
        return Box(lo, hi)


# ---- CORA's Hinf-G (setbound.cora.observe; issue 22) --------------------------------------------

@reconstructible
class CoraIntervalObserver(StateMixin):
    """CORA's interval observer as CORA runs it (its Hinf-G with a given gain) — **not guaranteed**.

    Tang, Wang, Wang, Raïssi and Shen, *Interval estimation methods for discrete-time linear
    time-invariant systems*, IEEE Trans. Autom. Control 64(11), 2019: a Luenberger estimate
    ``x̂⁺ = A x̂ + B u + L (y − C x̂)`` plus the interval hulls of the propagated initial set and
    noise. CORA's recursion is kept with its quirks: row ``k ≥ 1`` is computed before the update with
    ``y_{k−1}`` (a one-step lag) and row 1 counts the initial centre twice. For guaranteed sets with
    the same error recursion use :class:`IntervalLuenbergerObserver` (``variant="tight"``), which
    ``setbound.cora.observe(model, "Hinf-G")`` runs in the default convention.

    Parameters
    ----------
    system : LinearSystem
        ``x⁺ = A x + B u + E ω``, ``y = C x + F ω`` (``D`` must be zero), ``ω`` in the unit box.
    x0 : Zonotope or Box
        The initial set ``R0``.
    L : array_like, shape (n_x, n_y)
        The observer gain.

    Examples
    --------
    >>> sys = setbound.LinearSystem([[0.5, 0.1], [0.0, 0.6]], [[1.0, 0.0]], E=[[0.1, 0], [0, 0.1]], F=[[0, 0]])
    >>> obs = setbound.interval_observers.CoraIntervalObserver(sys, setbound.Box([-1, -1], [1, 1]), [[0.3], [0.1]])
    >>> traj = obs.run(np.zeros((3, 1)))
    >>> traj.guaranteed, traj.lower.shape
    (False, (3, 2))
    """

    _state_prefix = "sb_cora_interval"
    #: row k of a trajectory is CORA's R{k+1} (lagged; see the class description)
    is_filter = True

    def __init__(self, system, x0, L):
        from .sets import Zonotope
        from .system import LinearSystem, as_system

        system = as_system(system)
        if not isinstance(system, LinearSystem):
            raise InvalidArgumentError(f"system: expected a setbound.LinearSystem, got {type(system).__name__}")
        n, p = system.nx, system.ny
        if isinstance(x0, Box):
            x0 = Zonotope(0.5 * (x0.lo + x0.hi), np.diag(0.5 * (x0.hi - x0.lo)))
        if not isinstance(x0, Zonotope):
            raise InvalidArgumentError(f"x0: expected a Zonotope or a Box, got {type(x0).__name__}")
        if x0.n != n:
            raise DimensionError(f"x0: expected dimension {n}, got {x0.n}")
        self.L = as_f64(L, "L", shape=(n, p))
        c0, G0 = np.ascontiguousarray(x0.center), np.ascontiguousarray(x0.generators)
        handle = ffi.new("sb_cora_interval**")
        check(lib.sb_cora_interval_create(system._handle, dptr(c0), G0.shape[1], dptr(G0), dptr(self.L), handle))
        self._handle = ffi.gc(handle[0], lib.sb_cora_interval_free)
        self.system = system
        self._lo, self._hi = np.empty(n), np.empty(n)

    @property
    def steps(self) -> int:
        """Number of steps taken."""
        s = ffi.new("int*")
        check(lib.sb_cora_interval_current(self._handle, ffi.NULL, ffi.NULL, s))
        return int(s[0])

    def reset(self) -> None:
        """Back to the initial set, no step taken."""
        check(lib.sb_cora_interval_reset(self._handle))

    def step(self, y, u=None) -> Box:
        """One row of CORA's result: see the class description for its time.

        Parameters
        ----------
        y : array_like, shape (n_y,)
            The measurement ``y_k``.
        u : array_like, shape (n_u,), optional
            The input ``u_k``.

        Returns
        -------
        Box
        """
        from .system import step_inputs

        s = self.system
        y = as_f64(y, "y", shape=(s.ny,))
        _, up = step_inputs(s, y, u)
        check(lib.sb_cora_interval_step(self._handle, dptr(y), up, dptr(self._lo), dptr(self._hi)))
        return Box(self._lo.copy(), self._hi.copy())

    @run_from_initial_set
    def run(self, y, u=None) -> Trajectory:
        """CORA's rows for a record, from the initial set.

        Parameters
        ----------
        y : array_like, shape (N, n_y)
            Measurements.
        u : array_like, shape (N, n_u), optional
            Known inputs.
        reset : bool, optional
            Start from the initial set (default).
        t : array_like, shape (N,), optional
            Time of the rows.

        Returns
        -------
        Trajectory
            ``guaranteed`` is False.
        """
        from .system import run_inputs

        s = self.system
        y, u = run_inputs(s, y, u)
        N = y.shape[0]
        lo, hi = np.empty((N, s.nx)), np.empty((N, s.nx))
        for k in range(N):
            b = self.step(y[k], u[k] if s.nu > 0 else None)
            lo[k], hi[k] = b.lo, b.hi
        return Trajectory(0.5 * (lo + hi), lo, hi, [], guaranteed=False)


def _hinf_g_runner(model, *, convention, gain, **options):
    """Hinf-G. ``convention="cora"``: CORA's lagged recursion with the given gain (CORA's own design
    is a feasibility SDP whose result is whatever its solver stopped at, spec §2.12: pass its gain).
    Default: the guaranteed interval observer (IntervalLuenbergerObserver, tight error recursion) with
    the given gain, or the H∞ gain of its LMI design when none is given."""
    from .ellipsoidal import _cora_noise_generators

    s = model.system
    if convention == "cora":
        if options:
            raise InvalidArgumentError(f"{next(iter(options))}: not an option of Hinf-G")
        if np.any(s.B[:, -1] != 0.0) or np.any(s.D != 0.0):
            raise InvalidArgumentError("model: convention cora: CORA's interval observer omits the constant "
                                       "term c (and the offsets of W and V); this model has one, so CORA's "
                                       "sets would be wrong")
        from .system import LinearSystem
        sysc = LinearSystem(s.A, s.C, B=s.B[:, :-1] if s.nu > 1 else None, E=s.E, F=s.F)
        obs = CoraIntervalObserver(sysc, model.x0, gain)
        u = model.u[:, :-1] if s.nu > 1 else None

        def run():
            t = obs.run(model.y, u)
            return t.lower, t.upper, []
        return run
    Gw, Gv = _cora_noise_generators(s)
    if np.any(s.D != 0.0):
        raise InvalidArgumentError("model: an output offset (D u) is not supported by the interval observer")
    plant = Plant(s.A, s.C, B=s.B, Fd=Gw if Gw.shape[1] else np.zeros((s.nx, 1)),
                  Z=Gv if Gv.shape[1] else np.zeros((s.ny, 1)))
    obs = IntervalLuenbergerObserver(plant, model.x0, L=gain, **options)

    def run():
        t = obs.run(model.y, model.u)
        return t.lower, t.upper, t.sets
    return run


def _register_cora_names():
    from .cora import register_algorithm
    register_algorithm("Hinf-G", _hinf_g_runner, accepts_gain=True,
                       gain_required={"cora": "CORA's design is a feasibility SDP whose result depends on the solver "
                                              "(spec §2.12), so convention='cora' runs with CORA's gain"},
                       summary="interval observer with an H∞ gain [Tang 2019]; default = IntervalLuenbergerObserver, "
                               "cora = CoraIntervalObserver (CORA's one-step lag)")


_register_cora_names()
