"""Recursive optimal parallelotopes (CORA's ROPO; Methods › Zonotopic estimation).

Vicino & Zappa, *Sequential approximation of feasible parameter sets for identification with set
membership uncertainty*, IEEE TAC 41(6), 1996: the set is a parallelotope ``θ ⊕ T B^n`` (``T`` n×n).
At every step the prediction ``A X ⊕ B u ⊕ E B`` is reduced to a parallelotope (CORA's order-1
reduction: ``"girard"`` boxes it, ``"pca"`` boxes it in its principal axes), then each output's
strip is applied with the Vicino–Zappa step: tighten the strip to the parallelotope's range,
shrink each generator segment to what the strip allows, and keep the least-volume parallelotope
of the ``n + 1`` candidates (the set itself, or one face pair replaced by the strip).

A module of its own (the zonotopic catalogue of :mod:`setbound.zonotopic` is one skeleton with
a gain rule; this estimator has its own set and step). CORA's name ``"ROPO"`` is registered with
:mod:`setbound.cora` on import.
"""
from __future__ import annotations

import numpy as np

from ._native import check, dptr, ffi, lib
from ._state import StateMixin, reconstructible, run_from_initial_set
from ._validate import as_choice
from .errors import InvalidArgumentError
from .measurement import POLICIES, ReadingChecks, measurement_or_missing
from .sets import Zonotope
from .system import LinearSystem, as_system, run_inputs, step_inputs
from .trajectory import Trajectory

__all__ = ["ParallelotopeEstimator"]

#: Reductions to a parallelotope (keyword ``reduction``): CORA's ``reduce(Z, technique, 1)``.
REDUCTIONS = {"girard": lib.SB_ZONO_REDUCE_GIRARD, "pca": lib.SB_ZONO_REDUCE_PCA}
#: The conventions (keyword ``convention``).
CONVENTIONS = {"setbound": lib.SB_CONVENTION_SETBOUND, "cora": lib.SB_CONVENTION_CORA}


@reconstructible
class ParallelotopeEstimator(ReadingChecks, StateMixin):
    """Vicino–Zappa recursive optimal parallelotopes (CORA's ROPO), a filter.

    Row ``k`` of a run is the set for ``x_k`` after ``y_k``: the prediction from ``x_{k−1}`` is
    reduced to a parallelotope and corrected with the strips ``|C_i x − (y_i − D_i u)| ≤ σ_i``,
    ``σ_i = Σ_j |F_ij|``, one output after another (Vicino & Zappa 1996). Cost ``O(p n²)`` per step
    plus the reduction.

    ``convention="setbound"`` (default) is guaranteed: the truth is in every set after
    floating-point rounding (rounding errors are bounded and carried in a pending axis box; the
    bounds of the step are rounded outward), the first step corrects the initial set (reduced to a
    parallelotope) with ``y_0``, and a reading outside the predicted output set (an empty
    intersection) is never used and is handled by ``on_inconsistency``. ``convention="cora"`` runs CORA's ``priv_observe_ROPO`` as it is: row 0
    is ``x0`` itself (``y_0`` unused), CORA's normalised arithmetic without rounding control, no
    emptiness check; it is not guaranteed, and every output needs a noise bound.

    Degenerate cases: a generator with ``C_i t_j = 0`` keeps its full segment; a generator shrunk
    to zero stays as a zero column; a reduced set with fewer than ``n`` generators is padded with
    zero columns (CORA indexes out of range there). Missing outputs (NaN) are skipped.

    Parameters
    ----------
    system : LinearSystem
        The model (a known ``A``; the constant term enters through ``B u``).
    x0 : Zonotope, Box or Ellipsoid
        Initial set (any zonotope: it is reduced to a parallelotope at the first correction).
    reduction : {"girard", "pca"}, optional
        CORA's reduction technique: the interval hull (default) or a PCA-oriented box.
    convention : {"setbound", "cora"}, optional
        setbound's guaranteed algorithm (default) or CORA's code as it is.
    on_inconsistency : {"flag", "raise", "reset"}, optional
        What a reading outside the predicted output set does (:mod:`setbound.measurement`; reset:
        restart from ``x0``). Only ``"flag"`` with ``convention="cora"`` (CORA tests nothing).

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.9, 0.2], [0.0, 0.7]], C=[[1.0, 0.0]],
    ...                             E=[[0.1, 0.0], [0.0, 0.0]], F=[[0.0, 0.05]])
    >>> est = setbound.parallelotope.ParallelotopeEstimator(sys, setbound.Box([-1, -1], [1, 1]))
    >>> t = est.run(np.zeros((5, 1)))
    >>> theta, T, r = est.parallelotope  # the last set: θ ⊕ T B² ⊕ [−r, r]
    >>> bool(t.contains(np.zeros((5, 2))).all()), T.shape
    (True, (2, 2))
    """

    #: row k of a trajectory used y_k (Trajectory.filter)
    is_filter = True
    _last_check_fn = lib.sb_ropo_last_check
    _state_prefix = "sb_ropo"

    def __init__(self, system: LinearSystem, x0: Zonotope, *, reduction: str = "girard",
                 convention: str = "setbound", on_inconsistency: str = "flag"):
        from .zonotopic import _check_system_and_x0

        system = as_system(system)
        x0 = _check_system_and_x0(system, x0)
        reduction = as_choice(reduction, "reduction", REDUCTIONS)
        convention = as_choice(convention, "convention", CONVENTIONS)
        on_inconsistency = as_choice(on_inconsistency, "on_inconsistency", POLICIES)
        if system.A_rad is not None and np.any(np.asarray(system.A_rad) != 0):
            raise InvalidArgumentError("system: ParallelotopeEstimator needs a known A (an interval A is not supported)")
        self.system = system
        self.x0 = x0
        self.reduction = reduction
        self.convention = convention
        self.on_inconsistency = on_inconsistency
        opts = ffi.new("sb_ropo_options*")
        check(lib.sb_ropo_default_options(opts))
        opts.reduction = REDUCTIONS[reduction]
        opts.convention = CONVENTIONS[convention]
        opts.on_inconsistency = POLICIES[on_inconsistency]
        handle = ffi.new("sb_ropo**")
        check(lib.sb_ropo_create(system._handle, opts, x0.m, dptr(x0.center), dptr(x0.generators), handle))
        self._handle = ffi.gc(handle[0], lib.sb_ropo_free)
        self._init_checks()

    @property
    def steps(self) -> int:
        """Number of steps taken (the last step's set bounds ``x_{steps−1}``)."""
        s = ffi.new("int*")
        check(lib.sb_ropo_steps(self._handle, s))
        return int(s[0])

    def reset(self) -> None:
        """Back to the initial set, no step taken (the options are kept)."""
        check(lib.sb_ropo_reset(self._handle))

    def current_set(self) -> Zonotope:
        """The set of the last step: the parallelotope's ``n`` columns, then the rounding box as
        axis-aligned generators (``convention="cora"``, step 0: ``x0`` itself).

        Returns
        -------
        Zonotope
        """
        m = ffi.new("int*", 0)
        p = np.empty(self.system.nx)
        code = lib.sb_ropo_current_set(self._handle, m, dptr(p), ffi.NULL)
        if code != lib.SB_ERR_BUFFER_TOO_SMALL:
            check(code)
        H = np.empty((self.system.nx, m[0]))
        check(lib.sb_ropo_current_set(self._handle, m, dptr(p), dptr(H)))
        return Zonotope(p, H)

    @property
    def parallelotope(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The last step's set as ``(θ, T, r)``: ``θ ⊕ T B^n ⊕ [−r, r]`` (``T`` n×n, ``r`` the pending
        rounding box, zero in the cora convention)."""
        n = self.system.nx
        theta, T, r = np.empty(n), np.empty((n, n)), np.empty(n)
        check(lib.sb_ropo_parallelotope(self._handle, dptr(theta), dptr(T), dptr(r)))
        return theta, T, r

    def _step(self, y, u):
        s = self.system
        y, up = step_inputs(s, measurement_or_missing(y, s.ny), u)
        c, lo, hi = np.empty(s.nx), np.empty(s.nx), np.empty(s.nx)
        check(lib.sb_ropo_step(self._handle, dptr(y), up, dptr(c), dptr(lo), dptr(hi), ffi.NULL))
        return c, lo, hi

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
        return self.current_set()

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
            Row ``k`` is the set for ``x_k`` after ``y_k``; ``status``, ``margin`` and ``resets`` say
            what each step did with each reading.
        """
        s = self.system
        y, u = run_inputs(s, y, u)
        N = y.shape[0]
        centers, lows, highs, sets = np.empty((N, s.nx)), np.empty((N, s.nx)), np.empty((N, s.nx)), []
        status, margin = np.empty((N, s.ny), dtype=np.int8), np.empty((N, s.ny))
        resets = np.zeros(N, dtype=bool)
        for k in range(N):
            centers[k], lows[k], highs[k] = self._step(y[k], u[k] if s.nu > 0 else None)
            sets.append(self.current_set())
            resets[k] = self._check_into(status[k], margin[k])
        return Trajectory(centers, lows, highs, sets, status=status, margin=margin, resets=resets)


# ---- CORA's name (setbound.cora.observe) --------------------------------------------------------

def _ropo_runner(model, *, convention, gain, **options):
    """ROPO with CORA's reduction technique of the model (overridable) and the convention."""
    from .zonotopic import _refuse_cora_quirk

    _refuse_cora_quirk(model, "ROPO", convention, False)
    est = ParallelotopeEstimator(model.system, model.x0, **{"reduction": model.reduction_method,
                                                            "convention": convention, **options})

    def run():
        t = est.run(model.y, model.u)
        return t.lower, t.upper, t.sets
    return run


def _register_cora_names():
    from .cora import register_algorithm
    register_algorithm("ROPO", _ropo_runner,
                       summary="recursive optimal parallelotopes [Vicino & Zappa 1996] = "
                               "parallelotope.ParallelotopeEstimator")


_register_cora_names()
