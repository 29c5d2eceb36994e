"""Constrained-zonotope estimators: CORA's CZN-A and CZN-B, and setbound's bounded mode.

Scott, Raimondo, Marseglia and Braatz, Automatica 69 (2016): a constrained zonotope represents the
intersection of a set with a measurement exactly (one more constraint), so the estimate tracks the
exact consistent set as long as the representation is not reduced.

* prediction ``A X ⊕ B u ⊕ E B^{n_w}`` (exact);
* correction, ``correction="exact_output"`` (CORA's **CZN-A**): the exact intersection with the
  output set ``{x : y − D u − C x ∈ F B^{n_w}}``; ``correction="wang_strips"`` (**CZN-B**): the
  same strips written in the representation of Wang et al.'s gain (the same set; the sets differ
  only after a reduction);
* reduction, ``reduction="limits"`` (default): at most ``max_constraints`` constraints (Scott's
  rescaling and constraint elimination) and ``max_generators`` generators (the cheapest, priced by
  the hull LPs' multipliers, absorbed into a basis of the set's own generators), so a run of any length
  has bounded memory and cost per step, and every set still contains the true state (CZN-A's
  new constraints are first written with the least-squares gain ``Λ = P Cᵀ (C P Cᵀ + V Vᵀ)⁻¹``,
  ``P = G Gᵀ``: the same set, with smaller generators for the reduction to work on);
  ``reduction="cora"``: CORA's ``conZonotope/reduce`` at ``order`` (CORA's ``zonotopeOrder``),
  for CORA's numbers; ``reduction="none"``: the exact consistent set (memory grows every step).

A filter (row ``k`` of a trajectory used ``y_k``). Readings are screened as in every estimator of
the library (:mod:`setbound.measurement`); readings that are each possible but jointly impossible
leave a certified-empty intersection, and the step is reported inconsistent instead. Except with
``reduction="cora"``, a step first uses all its readings at once and screens them one by one only
when that intersection is not found feasible; the margins of a step that was not screened are then
upper bounds of the exact ones (<= 0), like those of the zonotopic filters.
"""
from __future__ import annotations

import numpy as np

from ._native import check, dptr, ffi, lib
from ._state import StateMixin, reconstructible, run_from_initial_set
from ._validate import as_bool, as_choice, as_float, as_int
from .errors import DimensionError, InvalidArgumentError
from .measurement import POLICIES, ReadingChecks, measurement_or_missing
from .sets import ConstrainedZonotope, as_constrained_zonotope
from .system import LinearSystem, as_system, run_inputs, step_inputs
from .trajectory import Trajectory

__all__ = ["ConstrainedZonotopicEstimator", "CORRECTIONS", "REDUCTIONS", "TECHNIQUES"]

#: Corrections (keyword ``correction``), with CORA's names as aliases.
CORRECTIONS = {"exact_output": lib.SB_CZN_EXACT_OUTPUT, "wang_strips": lib.SB_CZN_WANG_STRIPS,
               "CZN-A": lib.SB_CZN_EXACT_OUTPUT, "CZN-B": lib.SB_CZN_WANG_STRIPS}
#: Reductions (keyword ``reduction``).
REDUCTIONS = {"limits": lib.SB_CZN_REDUCE_LIMITS, "cora": lib.SB_CZN_REDUCE_CORA, "none": lib.SB_CZN_REDUCE_NONE}
#: Zonotope reductions of the lifted set (keyword ``technique``).
TECHNIQUES = {"girard": lib.SB_REDUCE_GIRARD, "pca": lib.SB_REDUCE_PCA}


@reconstructible
class ConstrainedZonotopicEstimator(ReadingChecks, StateMixin):
    """Set-membership estimator on constrained zonotopes (CZN-A / CZN-B, see the module docstring).

    Parameters
    ----------
    system : LinearSystem
        The model (a known ``A``; an interval ``A`` is refused).
    x0 : ConstrainedZonotope, Zonotope, Box or Ellipsoid
        Initial set (a zonotope or box exactly, an ellipsoid by its bounding box).
    correction : {"exact_output", "wang_strips", "CZN-A", "CZN-B"}, optional
        CZN-A (default) or CZN-B.
    reduction : {"limits", "cora", "none"}, optional
        setbound's bounded mode (default), CORA's reduction at ``order``, or none.
    technique : {"girard", "pca"}, optional
        Zonotope reduction of the lifted set (CORA's ``reductionTechnique``).
    order : float, optional
        ``reduction="cora"``: CORA's ``zonotopeOrder`` (≥ 1).
    max_constraints : int, optional
        ``reduction="limits"``: constraints kept (default ``4 n_x``).
    max_generators : int, optional
        ``reduction="limits"``: generators kept (default ``20 n_x + max_constraints``; at least
        ``n_x + max_constraints``).
    use_first_measurement : bool, optional
        Correct the initial set with ``y_0`` (CORA's loop; default).
    on_inconsistency : {"flag", "raise", "reset"}, optional
        What an impossible reading does (:mod:`setbound.measurement`).
    reset_set : optional
        The restart set of ``on_inconsistency="reset"`` (default: the initial set).

    Examples
    --------
    >>> from setbound.constrained_zonotopic import ConstrainedZonotopicEstimator
    >>> sys = setbound.LinearSystem(A=[[0.9, 0.2], [0.0, 0.7]], C=[[1.0, 0.0]],
    ...                             E=[[0.1, 0.0], [0.0, 0.0]], F=[[0.0, 0.05]])
    >>> est = ConstrainedZonotopicEstimator(sys, setbound.Box([-1, -1], [1, 1]))
    >>> traj = est.run(np.zeros((5, 1)))
    >>> bool(traj.contains(np.zeros((5, 2))).all()), traj.sets[-1].nc <= 8
    (True, True)
    """

    #: row k of a trajectory used y_k (Trajectory.filter)
    is_filter = True
    _last_check_fn = lib.sb_czonotopic_last_check
    _state_prefix = "sb_czonotopic"

    def __init__(self, system: LinearSystem, x0, *, correction: str = "exact_output", reduction: str = "limits",
                 technique: str = "girard", order: float = 20.0, max_constraints: int | None = None,
                 max_generators: int | None = None, use_first_measurement: bool = True,
                 on_inconsistency: str = "flag", reset_set=None):
        system = as_system(system)
        if not isinstance(system, LinearSystem):
            raise InvalidArgumentError(f"system: expected a setbound.LinearSystem, got {type(system).__name__}")
        x0 = as_constrained_zonotope(x0, "x0")
        if x0.n != system.nx:
            raise DimensionError(f"x0: expected a set of dimension {system.nx}, got {x0.n}")
        correction = as_choice(correction, "correction", CORRECTIONS)
        reduction = as_choice(reduction, "reduction", REDUCTIONS)
        technique = as_choice(technique, "technique", TECHNIQUES)
        order = as_float(order, "order", lo=1.0)
        mc = -1 if max_constraints is None else as_int(max_constraints, "max_constraints", lo=0,
                                                        hi=lib.SB_CZN_MAX_SIZE)
        mg = -1 if max_generators is None else as_int(max_generators, "max_generators", lo=0, hi=lib.SB_CZN_MAX_SIZE)
        use_first_measurement = as_bool(use_first_measurement, "use_first_measurement")
        on_inconsistency = as_choice(on_inconsistency, "on_inconsistency", POLICIES)
        self.system = system
        self.x0 = x0
        handle = ffi.new("sb_czonotopic**")
        check(lib.sb_czonotopic_create(system._handle, CORRECTIONS[correction], REDUCTIONS[reduction],
                                       TECHNIQUES[technique], order, mc, mg, 1 if use_first_measurement else 0,
                                       *x0._args()[1:], handle))
        self._handle = ffi.gc(handle[0], lib.sb_czonotopic_free)
        if reset_set is not None:
            if on_inconsistency != "reset":
                raise InvalidArgumentError('reset_set: only used with on_inconsistency="reset"')
            reset_set = as_constrained_zonotope(reset_set, "reset_set")
            if reset_set.n != system.nx:
                raise DimensionError(f"reset_set: expected a set of dimension {system.nx}, got {reset_set.n}")
            check(lib.sb_czonotopic_set_inconsistency_policy(self._handle, POLICIES[on_inconsistency],
                                                             *reset_set._args()[1:]))
        else:
            check(lib.sb_czonotopic_set_inconsistency_policy(self._handle, POLICIES[on_inconsistency], 0, 0,
                                                             ffi.NULL, ffi.NULL, ffi.NULL, ffi.NULL, ffi.NULL))
        self.correction = "exact_output" if CORRECTIONS[correction] == lib.SB_CZN_EXACT_OUTPUT else "wang_strips"
        self.reduction, self.technique, self.order = reduction, technique, order
        self.use_first_measurement = use_first_measurement
        self.on_inconsistency = on_inconsistency
        got_mc, got_mg = ffi.new("int*"), ffi.new("int*")
        check(lib.sb_czonotopic_options(self._handle, ffi.NULL, ffi.NULL, ffi.NULL, ffi.NULL, got_mc, got_mg))
        #: the effective limits of ``reduction="limits"`` (after the defaults)
        self.max_constraints, self.max_generators = int(got_mc[0]), int(got_mg[0])
        self._sizes = ffi.new("int[2]")
        self._init_checks()

    def _step(self, y, u):
        s = self.system
        y, up = step_inputs(s, measurement_or_missing(y, s.ny), u)
        lo, hi = np.empty(s.nx), np.empty(s.nx)
        check(lib.sb_czonotopic_step(self._handle, dptr(y), up, dptr(lo), dptr(hi), self._sizes, self._sizes + 1))
        return lo, hi

    def _last_set(self) -> ConstrainedZonotope:
        ng, nc = int(self._sizes[0]), int(self._sizes[1])
        return ConstrainedZonotope._result(lambda *a: lib.sb_czonotopic_last_set(self._handle, *a), (),
                                           self.system.nx, ng, nc)

    def step(self, y, u=None) -> ConstrainedZonotope:
        """Use ``y_k`` (and ``u_k``): returns the set for ``x_k`` and predicts ``x_{k+1}``.

        Parameters
        ----------
        y : array_like, shape (n_y,), or None
            The measurement ``y_k`` (None or NaN entries: missing outputs).
        u : array_like, shape (n_u,), optional
            The input ``u_k``.

        Returns
        -------
        ConstrainedZonotope
        """
        self._step(y, u)
        return self._last_set()

    @property
    def prediction(self) -> ConstrainedZonotope:
        """The set the next step corrects: after ``k`` steps the prediction ``A X_{k−1} ⊕ B u_{k−1} ⊕
        E B^{n_w}`` for ``x_k``, before its measurement (exact up to outward rounding); the initial set
        before the first step.

        Examples
        --------
        >>> sys = setbound.LinearSystem(A=[[0.9, 0.2], [0.0, 0.7]], C=[[1.0, 0.0]],
        ...                             E=[[0.1, 0.0], [0.0, 0.0]], F=[[0.0, 0.05]])
        >>> from setbound.constrained_zonotopic import ConstrainedZonotopicEstimator
        >>> est = ConstrainedZonotopicEstimator(sys, setbound.Box([-1, -1], [1, 1]))
        >>> X = est.step([0.3])
        >>> P = est.prediction
        >>> bool(np.all(P.interval_hull()[1] >= (sys.A @ X).interval_hull()[1]))
        True
        """
        return ConstrainedZonotope._result(lambda *a: lib.sb_czonotopic_prediction(self._handle, *a), (),
                                           self.system.nx, 0, 0)

    @property
    def steps(self) -> int:
        """Number of steps taken (a filter: the last step's set bounds ``x_{steps−1}``)."""
        s = ffi.new("int*")
        check(lib.sb_czonotopic_steps(self._handle, s))
        return int(s[0])

    def reset(self) -> None:
        """Back to the initial set, no step taken (the options are kept)."""
        check(lib.sb_czonotopic_reset(self._handle))

    @run_from_initial_set
    def run(self, y, u=None, *, keep_sets: bool = True) -> Trajectory:
        """Process a record from the initial set; row ``k`` is about ``x_k``.

        Parameters
        ----------
        y : array_like, shape (N, n_y), or control.TimeResponseData
            Measurements (NaN entries: missing outputs).
        u : array_like, shape (N, n_u), optional
            Known inputs.
        keep_sets : bool, optional
            Keep every step's :class:`~setbound.sets.ConstrainedZonotope` in ``sets`` (default);
            False keeps only the hulls (long runs).
        reset : bool, optional
            Start from the initial set (default). ``False`` continues from the current state.
        t : array_like, shape (N,), optional
            Time of the rows (default: ``k·dt`` with the system's sampling time, else the step index).

        Returns
        -------
        Trajectory
            ``center`` is the middle of the hull; ``status``, ``margin`` and ``resets`` say what each
            step did with each reading.
        """
        keep_sets = as_bool(keep_sets, "keep_sets")
        s = self.system
        y, u = run_inputs(s, y, u)
        N = y.shape[0]
        lows, highs, sets = np.empty((N, s.nx)), np.empty((N, s.nx)), []
        status, margin = np.empty((N, s.ny), dtype=np.int8), np.empty((N, s.ny))
        resets = np.zeros(N, dtype=bool)
        for k in range(N):
            lows[k], highs[k] = self._step(y[k], u[k] if s.nu > 0 else None)
            if keep_sets:
                sets.append(self._last_set())
            resets[k] = self._check_into(status[k], margin[k])
        return Trajectory(0.5 * (lows + highs), lows, highs, sets if keep_sets else None, status=status,
                          margin=margin, resets=resets)


# ---- CORA's names (setbound.cora.observe) -------------------------------------------------------

def _cora_runner(correction: str):
    """CZN-A / CZN-B. ``convention="cora"``: CORA's reduction (``conZonotope/reduce`` with the
    model's zonotope order and technique after every correction but the first); default: setbound's
    bounded mode. Both are guaranteed (CORA's CZN methods omit nothing)."""
    def runner(model, *, convention, gain, **options):
        opts = {"reduction": "cora", "order": model.zonotope_order, "technique": model.reduction_method} \
            if convention == "cora" else {}
        est = ConstrainedZonotopicEstimator(model.system, model.x0, correction=correction, **{**opts, **options})

        def run():
            t = est.run(model.y, model.u)
            return t.lower, t.upper, t.sets
        return run
    return runner


def _register_cora_names():
    from .cora import register_algorithm
    register_algorithm("CZN-A", _cora_runner("exact_output"),
                       summary="constrained zonotopes, exact intersection with the output set [Scott 2016]")
    register_algorithm("CZN-B", _cora_runner("wang_strips"),
                       summary="constrained zonotopes, output strips in Wang et al.'s gain representation")


_register_cora_names()
