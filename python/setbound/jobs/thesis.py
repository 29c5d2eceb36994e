"""Job-file kinds for the thesis ([Loukkas2018]): system kinds in the thesis letters and the thesis
estimators, registered in :mod:`setbound.jobs.registry` on import (``setbound.thesis_jobs``
re-exports this module's public names).

System kinds
------------
``kind = "thesis"`` — the plant ``x⁺ = A x + B u + F d``, ``y = C x + Z v`` (Methods › H∞ set-membership observers › Model)::

    [system]
    kind = "thesis"
    A = [[0.2, 0.2], [0, 0.5]]
    B = [[1], [1]]                      # optional
    C = [[1, 0]]
    F = [[0], [0.1]]                    # optional (no state disturbance)
    Z = [[0.1]]                         # optional (no measurement noise)
    d = [1.0]                           # radius vector (d in [-r, r]) or {lower = [...], upper = [...]}
    v = {lower = [-1], upper = [1]}

  The job's system is a :class:`ThesisSystem`, a :class:`~setbound.LinearSystem` holding the
  equivalent unit-box model (``ω = (ξ_d, ξ_v)``; the offsets of non-centred boxes are an input
  column that is always 1, as for ``[system.omega]``), so the papers' estimators apply too. The
  thesis estimators receive the unscaled :class:`~setbound.Plant` (``system.plant``) and the
  boxes ``system.d``, ``system.v``. Its simulation runs in the thesis letters; ``[simulation]
  disturbance`` is ``"uniform"``, ``"vertex"`` (each component at a bound), ``"center"`` or a
  deterministic profile ``{d = ["expr", …], v = ["expr", …]}`` (expressions of ``t`` and ``k``,
  checked against the boxes).

``kind = "lpv"`` — polytopic LPV (Methods › H∞ set-membership observers › LPV systems): ``A = [A_1, …, A_N]`` (vertex matrices),
  ``B``, ``F`` likewise (optional), common ``C``, ``Z``, the vertices ``theta`` (N × n_ρ, in the
  order of the matrices), the boxes ``d``, ``v`` and the scheduling signal ``scheduling = [expr,
  …]`` — expressions of ``t``, ``k`` and the state ``x1 … xn`` (quasi-LPV: ``"x1"``). ``clip``
  (default false): project ρ_k onto the bounding box of the vertices first. ρ_k must lie in
  conv{θ_i} (else a ConfigError naming ``system.scheduling``). The system matrices at ρ_k are
  ``Σ α_i M_i`` with the weights of :func:`polytopic_weights_lp`. The simulated ρ is kept in
  ``job.extra["rho"]`` and given to the LPV observer.

``kind = "nonlinear"`` — ``x⁺ = A x + h(p, x, k) + B u``, ``y = C x + Z v`` (Methods › Interval observers › Nonlinear interval observer):
  ``h = [expr, …]`` (n_x expressions of ``t``, ``k``, ``x1 … xn`` and the parameter ``p``),
  ``p = {lower, upper}`` (the parameter's interval), ``h_bounds = {lower, upper}`` (the
  inclusion box [h], validated along the simulation), ``v``. ``[simulation] parameter`` is the
  value of p used by the simulation (default: the upper bound).

Estimator kinds
---------------
``interval_luenberger`` (Methods › Interval observers › Interval Luenberger observer; ``variant`` tight | wrapped | naive), ``interval_invariant``
(Methods › Interval observers › Invariant-set observer; ``mu``, ``inflation``, ``epsilon``, ``variant``), ``nonlinear_interval`` (Methods › Interval observers › Nonlinear interval observer),
``ellipsoidal_sm`` (Ch. 2, Algorithm 2), ``lpv_sm`` (Ch. 3, Algorithm 3) and
``invariant_tube`` (Ch. 1 Algorithm 1 as an open-loop estimator, for the autonomous Ex 1.5:
the error of the "observer" x̂ ≡ 0 is the state itself, so x_k ∈ A^k[x_0] ⊕ Ω_k, bounded by the
boxes of Φ_k once [x_0] ⊆ Φ_0). All take ``xhat0`` (the observer's initial estimate; default:
the centre of the initial box).
"""
from __future__ import annotations

import importlib.util
from dataclasses import dataclass, field

import numpy as np

from ..errors import InvalidArgumentError, SetboundError
from ..interval import Box
from ..interval_observers import MAX_WINDOW as _API_MAX_WINDOW
from ..invariant import MAX_ITERATIONS as _API_MAX_ITERATIONS
from ..plant import Plant
from ..system import LinearSystem
from .expressions import compile_expression, evaluate
from .registry import (BuiltSystem, boolean, number, one_of, optional_matrix, optional_vector, positive_int,
                       register_estimator, register_system)
from .schema import ConfigError, as_float, describe
from .schema import check_keys as _check_keys
from .schema import matrix as _matrix
from .schema import require as _require

__all__ = ["ThesisSystem", "LpvSystem", "NonlinearSystem", "polytopic_weights_lp"]


# ---------------------------------------------------------------- helpers
def _bounds(spec, n: int, key: str):
    """A box given as a radius vector (or a number for n = 1) or as {lower, upper}."""
    if isinstance(spec, dict):
        _check_keys(spec, {"lower", "upper"}, key)
        lo = _matrix(_require(spec, "lower", key), f"{key}.lower", ndim=1, shape=(n,))
        hi = _matrix(_require(spec, "upper", key), f"{key}.upper", ndim=1, shape=(n,))
        if np.any(lo > hi):
            i = int(np.flatnonzero(lo > hi)[0])
            raise ConfigError(f"{key}.lower: entry {i} is above {key}.upper")
        return lo, hi
    if isinstance(spec, (int, float)) and not isinstance(spec, bool):
        spec = [spec]
    r = _matrix(spec, key, ndim=1, shape=(n,))
    if np.any(r < 0):
        raise ConfigError(f"{key}: radii must be >= 0")
    return -r, r.copy()


def _opt_matrix(tab, name, shape):
    return _matrix(tab[name], f"system.{name}", shape=shape) if name in tab else None


def _state_names(n: int):
    return tuple(f"x{i + 1}" for i in range(n))


def _expressions(spec, count: int, key: str, names):
    if not isinstance(spec, list) or len(spec) != count:
        raise ConfigError(f"{key}: expected a list of {count} expressions, got {describe(spec)}")
    return [compile_expression(s, f"{key}[{i}]", names) for i, s in enumerate(spec)]


def _eval_all(fs, env, key: str, k: int) -> np.ndarray:
    # a failure (1/(k-2) at k = 2, an overflow) names the key, the step and the cause
    return np.array([evaluate(f, env, f"{key}[{i}]", step=k) for i, f in enumerate(fs)])


def _sample_box(lo, hi, kind: str, rng, key: str):
    if kind == "uniform":
        return rng.uniform(lo, hi)
    if kind == "vertex":
        return np.where(rng.random(lo.shape) < 0.5, lo, hi)
    if kind == "center":
        return (lo + hi) / 2
    raise ConfigError(f"{key}: expected 'uniform', 'vertex', 'center' or a table of expressions, got {describe(kind)}")


def _initial_box(initial) -> Box:
    from ..sets import Ellipsoid, Zonotope

    if isinstance(initial, Box):
        return initial
    if isinstance(initial, Ellipsoid):
        lo, hi = initial.bounding_box()
        return Box(lo, hi)
    if isinstance(initial, Zonotope):
        lo, hi = initial.interval_hull()
        return Box(lo, hi)
    raise ConfigError("initial: expected a box, ellipsoid or zonotope")


def _true_x0(initial, x0, rng, kind: str):
    if not isinstance(x0, str):
        return np.asarray(x0, dtype=float)
    if isinstance(initial, Box):
        lo, hi = np.asarray(initial.lo, float), np.asarray(initial.hi, float)
        return _sample_box(lo, hi, "vertex" if kind == "vertex" else "uniform", rng, "simulation.x0")
    from ..simulation import sample_in

    return sample_in(initial, rng, boundary=kind == "vertex")


@dataclass
class ThesisSimulation:
    """A simulation in the thesis letters: states, outputs, inputs (as the job uses them), the
    disturbances ``d``, ``v`` and ``extra`` per-step data (``"rho"`` for LPV)."""

    x: np.ndarray
    y: np.ndarray
    u: np.ndarray
    d: np.ndarray
    v: np.ndarray
    extra: dict = field(default_factory=dict)


class _DisturbanceSource:
    """``[simulation] disturbance`` for thesis systems: a sampling kind or expressions of t, k."""

    def __init__(self, spec, dlo, dhi, vlo, vhi, rng):
        self.dlo, self.dhi, self.vlo, self.vhi, self.rng = dlo, dhi, vlo, vhi, rng
        key = "simulation.disturbance"
        self.kind, self.fd, self.fv = None, None, None
        if isinstance(spec, dict):
            _check_keys(spec, {"d", "v"}, key)
            self.fd = _expressions(spec["d"], dlo.size, f"{key}.d", ("t", "k")) if "d" in spec else None
            self.fv = _expressions(spec["v"], vlo.size, f"{key}.v", ("t", "k")) if "v" in spec else None
            self.kind = "uniform"  # components without an expression
        elif isinstance(spec, str) and spec in ("uniform", "vertex", "center", "zero"):
            self.kind = "center" if spec == "zero" else spec
            if spec == "zero" and (np.any(dlo > 0) | np.any(dhi < 0) | np.any(vlo > 0) | np.any(vhi < 0)):
                raise ConfigError(f"{key}: 'zero' is outside the disturbance boxes (use 'center')")
        else:
            raise ConfigError(f"{key}: expected 'uniform', 'vertex', 'center', 'zero' or a table "
                              f"{{d = [...], v = [...]}} of expressions of t and k, got {describe(spec)}")

    def _one(self, fs, lo, hi, env, k, key):
        if fs is None:
            return _sample_box(lo, hi, self.kind, self.rng, key)
        val = _eval_all(fs, env, key, k)
        tol = 1e-12 * np.maximum(1.0, np.abs(val))
        bad = np.flatnonzero((val < lo - tol) | (val > hi + tol))
        if bad.size:
            i = int(bad[0])
            raise ConfigError(f"{key}[{i}]: the value {val[i]:.6g} at step k = {k} is outside the bounds "
                              f"[{lo[i]:.6g}, {hi[i]:.6g}]")
        return np.clip(val, lo, hi)

    def __call__(self, k: int, t: float):
        env = {"t": t, "k": float(k)}
        return (self._one(self.fd, self.dlo, self.dhi, env, k, "simulation.disturbance.d"),
                self._one(self.fv, self.vlo, self.vhi, env, k, "simulation.disturbance.v"))


def _sim_common(sim, initial, x0, seed, nd, nv, dlo, dhi, vlo, vhi):
    rng = np.random.default_rng(seed)
    kind = sim.get("disturbance", "uniform")
    src = _DisturbanceSource(kind, dlo, dhi, vlo, vhi, rng)
    return rng, src, _true_x0(initial, x0, rng, kind if isinstance(kind, str) else "uniform")


def _check_x0_inside(initial, xt):
    if isinstance(initial, Box):
        lo, hi = np.asarray(initial.lo, float), np.asarray(initial.hi, float)
        if np.any(xt < lo) or np.any(xt > hi):
            raise ConfigError("simulation.x0: outside the initial box")


# ---------------------------------------------------------------- kind = "thesis"
class ThesisSystem(LinearSystem):
    """The thesis plant with its disturbance boxes, as the equivalent unit-box
    :class:`~setbound.LinearSystem` (so every estimator of the papers applies). ``plant`` is the
    unscaled :class:`~setbound.Plant`, ``d``/``v`` the boxes of d and v (``None`` when n_d or
    n_v is 0) and ``offset`` True when the boxes are not centred (then the last input of the
    LinearSystem is the constant 1).

    Parameters
    ----------
    plant : Plant
        The unscaled plant.
    dlo, dhi : ndarray
        Box of the state disturbance ``d``.
    vlo, vhi : ndarray
        Box of the measurement noise ``v``.
    """

    simulation_keys = ()

    def __init__(self, plant: Plant, dlo, dhi, vlo, vhi):
        n, ny, nd, nv = plant.nx, plant.ny, plant.nd, plant.nv
        rd, cd = (dhi - dlo) / 2, (dhi + dlo) / 2
        rv, cv = (vhi - vlo) / 2, (vhi + vlo) / 2
        E = np.hstack([plant.F * rd, np.zeros((n, nv))])
        Fo = np.hstack([np.zeros((ny, nd)), plant.Z * rv])
        offset = bool(np.any(cd != 0) or np.any(cv != 0))
        B, D = plant.B, None
        if offset:
            B = np.hstack([plant.B, (plant.F @ cd)[:, None]])
            D = np.hstack([np.zeros((ny, plant.nu)), (plant.Z @ cv)[:, None]])
        super().__init__(plant.A, plant.C, B=B if B.shape[1] else None, D=D, E=E, F=Fo)
        self.plant, self.offset = plant, offset
        self.dlo, self.dhi, self.vlo, self.vhi = dlo, dhi, vlo, vhi

    @property
    def d(self) -> Box | None:
        """The box of the state disturbance d (None without F)."""
        return Box(self.dlo, self.dhi) if self.dlo.size else None

    @property
    def v(self) -> Box | None:
        """The box of the measurement noise v (None without Z)."""
        return Box(self.vlo, self.vhi) if self.vlo.size else None

    @property
    def wbar(self) -> np.ndarray:
        """Half-widths of w = (d, v) (the thesis's w̄; the boxes must be centred)."""
        return np.concatenate([(self.dhi - self.dlo) / 2, (self.vhi - self.vlo) / 2])

    @property
    def centred(self) -> bool:
        """True when both boxes are centred at 0."""
        return not self.offset

    def fingerprint(self):
        """Bytes identifying the plant and the boxes (the key of the shared design cache)."""
        p = self.plant
        return tuple(a.tobytes() for a in (p.A, p.B, p.C, p.F, p.Z, self.dlo, self.dhi, self.vlo, self.vhi))

    def simulate_job(self, sim, initial, N, t, u, x0, seed) -> ThesisSimulation:
        """The ``[simulation]`` of a job in the thesis letters (d, v sampled in their boxes or
        given as expressions of t, k); ``u`` includes the constant offset column, if any.

        Parameters
        ----------
        sim : dict
            The ``[simulation]`` table.
        initial : set
            The initial set.
        N : int
            Number of steps.
        t : ndarray, shape (N,)
            Time values.
        u : ndarray, shape (N, n_u)
            Inputs.
        x0 : ndarray, optional
            True initial state (default: drawn in ``initial``).
        seed : int
            Random seed.

        Returns
        -------
        ThesisSimulation
        """
        p = self.plant
        rng, src, xt = _sim_common(sim, initial, x0, seed, p.nd, p.nv, self.dlo, self.dhi, self.vlo, self.vhi)
        _check_x0_inside(initial, xt)
        U = np.zeros((N, p.nu)) if u is None else np.asarray(u, float)[:, :p.nu]
        x, y = np.empty((N, p.nx)), np.empty((N, p.ny))
        D, V = np.empty((N, p.nd)), np.empty((N, p.nv))
        x[0] = xt
        for k in range(N):
            D[k], V[k] = src(k, float(t[k]))
            y[k] = p.C @ x[k] + p.Z @ V[k]
            if k + 1 < N:
                x[k + 1] = p.A @ x[k] + p.B @ U[k] + p.F @ D[k]
        uu = np.asarray(u, float) if u is not None else np.zeros((N, 0))
        return ThesisSimulation(x, y, uu, D, V)


def _plant_from(tab, *, need_F=True):
    A = _matrix(_require(tab, "A", "system"), "system.A")
    n = A.shape[0]
    if A.shape != (n, n):
        raise ConfigError(f"system.A: must be square, got shape {A.shape}")
    C = _matrix(_require(tab, "C", "system"), "system.C", shape=(None, n))
    ny = C.shape[0]
    B = _opt_matrix(tab, "B", (n, None))
    F = _opt_matrix(tab, "F", (n, None)) if need_F else None
    Z = _opt_matrix(tab, "Z", (ny, None))
    return A, B, C, F, Z


def _boxes(tab, nd, nv):
    if nd:
        dlo, dhi = _bounds(_require(tab, "d", "system"), nd, "system.d")
    else:
        if "d" in tab:
            raise ConfigError("system.d: given without system.F (there is no state disturbance)")
        dlo = dhi = np.zeros(0)
    if nv:
        vlo, vhi = _bounds(_require(tab, "v", "system"), nv, "system.v")
    else:
        if "v" in tab:
            raise ConfigError("system.v: given without system.Z (there is no measurement noise)")
        vlo = vhi = np.zeros(0)
    return dlo, dhi, vlo, vhi


def _thesis_system(tab):
    A, B, C, F, Z = _plant_from(tab)
    try:
        plant = Plant(A, C, B=B, Fd=F, Z=Z)
    except SetboundError as exc:
        raise ConfigError(f"system: {exc}") from None
    dlo, dhi, vlo, vhi = _boxes(tab, plant.nd, plant.nv)
    try:
        with np.errstate(over="ignore", invalid="ignore"):  # huge boxes: the system refuses non-finite matrices
            s = ThesisSystem(plant, dlo, dhi, vlo, vhi)
    except SetboundError as exc:
        raise ConfigError(f"system: {exc}") from None
    return BuiltSystem(s, True) if s.offset else s


# ---------------------------------------------------------------- kind = "lpv"
def polytopic_weights_lp(theta: np.ndarray, rho: np.ndarray) -> np.ndarray | None:
    """Weights α ≥ 0, Σα = 1, Σ α_i θ_i = ρ (a feasibility LP; None when ρ ∉ conv{θ_i}).

    Parameters
    ----------
    theta : ndarray, shape (N, n_ρ)
        Vertices.
    rho : ndarray, shape (n_ρ,)
        The point.

    Returns
    -------
    ndarray or None
    """
    from scipy.optimize import linprog

    N = theta.shape[0]
    Aeq = np.vstack([theta.T, np.ones((1, N))])
    beq = np.concatenate([rho, [1.0]])
    r = linprog(np.zeros(N), A_eq=Aeq, b_eq=beq, bounds=[(0, None)] * N, method="highs")
    if r.status != 0:
        return None
    a = np.clip(r.x, 0, None)
    return a / a.sum()


class _OutputModel:
    """The attributes the CLI and the plots use: the unit-box output model (C, D, F)."""

    def _set_output(self, C, Z, vlo, vhi, nu):
        self.C = C
        self.F = Z * ((vhi - vlo) / 2) if Z.shape[1] else np.zeros((C.shape[0], 1))
        self.D = np.zeros((C.shape[0], nu))

    nx = property(lambda self: self.A[0].shape[0] if isinstance(self.A, list) else self.A.shape[0])
    ny = property(lambda self: self.C.shape[0])


class LpvSystem(_OutputModel):
    """Polytopic LPV plant with its scheduling signal (see the module docstring).

    Parameters
    ----------
    A, B, F : list of ndarray
        Vertex matrices (one per row of ``theta``).
    C, Z : ndarray
        Common output and noise matrices.
    theta : ndarray, shape (N, n_ρ)
        Vertices of the scheduling polytope.
    dlo, dhi : ndarray
        Box of the state disturbance ``d``.
    vlo, vhi : ndarray
        Box of the measurement noise ``v``.
    scheduling : callable
        ``ρ(t, k, x)`` (compiled from the job file).
    clip : bool
        Clip ``ρ`` into the box of ``theta`` instead of refusing it.
    """

    simulation_keys = ()

    def __init__(self, A, B, F, C, Z, theta, dlo, dhi, vlo, vhi, scheduling, clip: bool):
        self.A, self.B, self.Fd, self.Z, self.theta = A, B, F, Z, theta
        self.dlo, self.dhi, self.vlo, self.vhi = dlo, dhi, vlo, vhi
        self.scheduling, self.clip = scheduling, clip
        self._set_output(C, Z, vlo, vhi, B[0].shape[1])
        self.rho_lo, self.rho_hi = theta.min(axis=0), theta.max(axis=0)

    nu = property(lambda self: self.B[0].shape[1], doc="Number of known inputs.")
    n_rho = property(lambda self: self.theta.shape[1], doc="Number of scheduling parameters.")

    def lpv_plant(self):
        """The :class:`setbound.hinf.LpvPlant` of the vertex matrices (for the Ch. 3 design)."""
        from ..hinf import LpvPlant

        return LpvPlant(self.A, self.C, self.theta, B=self.B, Fd=self.Fd, Z=self.Z)

    @property
    def wbar(self):
        """Half-widths of w = (d, v) (the thesis's w̄)."""
        return np.concatenate([(self.dhi - self.dlo) / 2, (self.vhi - self.vlo) / 2])

    @property
    def centred(self) -> bool:
        """True when both boxes are centred at 0."""
        return bool(np.all(self.dhi == -self.dlo) and np.all(self.vhi == -self.vlo))

    def fingerprint(self):
        """Bytes identifying the model (the key of the shared design cache)."""
        return tuple(a.tobytes() for a in (*self.A, *self.B, *self.Fd, self.C, self.Z, self.theta, self.dlo, self.dhi,
                                           self.vlo, self.vhi))

    def matrices_at(self, rho, k: int):
        """(A(ρ), B(ρ), F(ρ)) after the clip/validation of ρ; raises ConfigError naming the key.

        Parameters
        ----------
        rho : ndarray, shape (n_ρ,)
            Scheduling vector.
        k : int
            Step (for messages).

        Returns
        -------
        A, B, F : ndarray
        """
        if self.clip:
            rho = np.clip(rho, self.rho_lo, self.rho_hi)
        a = polytopic_weights_lp(self.theta, rho)
        if a is None:
            raise ConfigError(f"system.scheduling: rho = {np.array2string(rho, precision=4)} at step k = {k} is "
                              f"outside the polytope conv(theta)" + ("" if self.clip else " (clip = true projects it "
                                                                      "onto the vertices' bounding box)"))
        M = lambda ms: sum(w * m for w, m in zip(a, ms))  # noqa: E731
        return rho, M(self.A), M(self.B), M(self.Fd)

    def simulate_job(self, sim, initial, N, t, u, x0, seed) -> ThesisSimulation:
        """Simulates with the state-dependent scheduling ρ_k (validated or clipped, see
        :meth:`matrices_at`); ``extra["rho"]`` is the N × n_ρ signal.

        Parameters
        ----------
        sim : dict
            The ``[simulation]`` table.
        initial : set
            The initial set.
        N : int
            Number of steps.
        t : ndarray, shape (N,)
            Time values.
        u : ndarray, shape (N, n_u)
            Inputs.
        x0 : ndarray, optional
            True initial state (default: drawn in ``initial``).
        seed : int
            Random seed.

        Returns
        -------
        ThesisSimulation
        """
        n, nu = self.nx, self.nu
        rng, src, xt = _sim_common(sim, initial, x0, seed, self.dlo.size, self.vlo.size, self.dlo, self.dhi,
                                   self.vlo, self.vhi)
        _check_x0_inside(initial, xt)
        U = np.zeros((N, nu)) if u is None else np.asarray(u, float)
        x, y = np.empty((N, n)), np.empty((N, self.ny))
        D, V, R = np.empty((N, self.dlo.size)), np.empty((N, self.vlo.size)), np.empty((N, self.n_rho))
        names = _state_names(n)
        x[0] = xt
        for k in range(N):
            D[k], V[k] = src(k, float(t[k]))
            y[k] = self.C @ x[k] + self.Z @ V[k]
            env = {"t": float(t[k]), "k": float(k), **{nm: float(x[k, i]) for i, nm in enumerate(names)}}
            rho = _eval_all(self.scheduling, env, "system.scheduling", k)
            R[k], Ak, Bk, Fk = self.matrices_at(rho, k)
            if k + 1 < N:
                x[k + 1] = Ak @ x[k] + Bk @ U[k] + Fk @ D[k]
        return ThesisSimulation(x, y, U, D, V, extra={"rho": R})


def _matrix_list(v, key, shape):
    if not isinstance(v, list) or not v or not all(isinstance(m, list) for m in v):
        raise ConfigError(f"{key}: expected a list of vertex matrices")
    return [_matrix(m, f"{key}[{i}]", shape=shape) for i, m in enumerate(v)]


def _lpv_system(tab):
    A = _matrix_list(_require(tab, "A", "system"), "system.A", None)
    n = A[0].shape[0]
    for i, a in enumerate(A):
        if a.shape != (n, n):
            raise ConfigError(f"system.A[{i}]: expected shape ({n}, {n}) (square, as A[0]), got {a.shape}")
    N = len(A)
    C = _matrix(_require(tab, "C", "system"), "system.C", shape=(None, n))
    ny = C.shape[0]
    B = _matrix_list(tab["B"], "system.B", (n, None)) if "B" in tab else [np.zeros((n, 0))] * N
    F = _matrix_list(tab["F"], "system.F", (n, None)) if "F" in tab else [np.zeros((n, 0))] * N
    for name, ms in (("B", B), ("F", F)):
        if len(ms) != N:
            raise ConfigError(f"system.{name}: expected {N} vertex matrices (one per A_i), got {len(ms)}")
        for i, m in enumerate(ms):
            if m.shape != ms[0].shape:
                raise ConfigError(f"system.{name}[{i}]: expected shape {ms[0].shape} (as {name}[0]), got {m.shape}")
    Z = _matrix(tab["Z"], "system.Z", shape=(ny, None)) if "Z" in tab else np.zeros((ny, 0))
    theta = _matrix(_require(tab, "theta", "system"), "system.theta", shape=(N, None))
    dlo, dhi, vlo, vhi = _boxes(tab, F[0].shape[1], Z.shape[1])
    names = ("t", "k") + _state_names(n)
    sched = _expressions(_require(tab, "scheduling", "system"), theta.shape[1], "system.scheduling", names)
    clip = boolean(tab.get("clip", False), "system.clip")
    if F[0].shape[1] + Z.shape[1] == 0:
        raise ConfigError("system.F: the plant has no disturbance (give F or Z)")
    return LpvSystem(A, B, F, C, Z, theta, dlo, dhi, vlo, vhi, sched, clip)


# ---------------------------------------------------------------- kind = "nonlinear"
class NonlinearSystem(_OutputModel):
    """``x⁺ = A x + h(p, x, k) + B u``, ``y = C x + Z v`` with the inclusion box [h] (Methods › Interval observers › Nonlinear interval observer).

    Parameters
    ----------
    A, B, C, Z : ndarray
        The linear part.
    h : callable
        ``h(p, x, k)`` (compiled from the job file).
    plo, phi : ndarray
        Bounds of the parameter ``p``.
    hlo, hhi : ndarray
        The inclusion box ``[h]``.
    vlo, vhi : ndarray
        Box of the measurement noise ``v``.
    """

    simulation_keys = ("parameter",)

    def __init__(self, A, B, C, Z, h, plo, phi, hlo, hhi, vlo, vhi):
        self.A, self.B, self.Z, self.h = A, B, Z, h
        self.plo, self.phi, self.hlo, self.hhi, self.vlo, self.vhi = plo, phi, hlo, hhi, vlo, vhi
        self._set_output(C, Z, vlo, vhi, B.shape[1])
        self.plant = Plant(A, C, B=B if B.shape[1] else None, Fd=np.eye(A.shape[0]), Z=Z if Z.shape[1] else None)

    nu = property(lambda self: self.B.shape[1], doc="Number of known inputs.")

    @property
    def h_box(self) -> Box:
        """The inclusion box [h] of the nonlinearity."""
        return Box(self.hlo, self.hhi)

    @property
    def v(self) -> Box | None:
        """The box of the measurement noise v (None without Z)."""
        return Box(self.vlo, self.vhi) if self.vlo.size else None

    def fingerprint(self):
        """Bytes identifying the model (the key of the shared design cache)."""
        return tuple(a.tobytes() for a in (self.A, self.B, self.C, self.Z, self.hlo, self.hhi, self.vlo, self.vhi))

    def simulate_job(self, sim, initial, N, t, u, x0, seed) -> ThesisSimulation:
        """Simulates with the parameter ``[simulation] parameter``; every h(p, x_k, k) is
        checked against [h]; ``extra["h"]`` holds the values.

        Parameters
        ----------
        sim : dict
            The ``[simulation]`` table.
        initial : set
            The initial set.
        N : int
            Number of steps.
        t : ndarray, shape (N,)
            Time values.
        u : ndarray, shape (N, n_u)
            Inputs.
        x0 : ndarray, optional
            True initial state (default: drawn in ``initial``).
        seed : int
            Random seed.

        Returns
        -------
        ThesisSimulation
        """
        n = self.nx
        p = as_float(sim.get("parameter", float(self.phi)), "simulation.parameter")
        if not self.plo <= p <= self.phi:
            raise ConfigError(f"simulation.parameter: {p} is outside system.p = [{self.plo}, {self.phi}]")
        rng, src, xt = _sim_common(sim, initial, x0, seed, 0, self.vlo.size, np.zeros(0), np.zeros(0), self.vlo,
                                   self.vhi)
        _check_x0_inside(initial, xt)
        U = np.zeros((N, self.nu)) if u is None else np.asarray(u, float)
        x, y, V = np.empty((N, n)), np.empty((N, self.ny)), np.empty((N, self.vlo.size))
        H = np.empty((N, n))
        names = _state_names(n)
        x[0] = xt
        for k in range(N):
            _, V[k] = src(k, float(t[k]))
            y[k] = self.C @ x[k] + self.Z @ V[k]
            env = {"t": float(t[k]), "k": float(k), "p": float(p), **{nm: float(x[k, i]) for i, nm in enumerate(names)}}
            H[k] = _eval_all(self.h, env, "system.h", k)
            bad = np.flatnonzero((H[k] < self.hlo) | (H[k] > self.hhi))
            if bad.size:
                i = int(bad[0])
                raise ConfigError(f"system.h_bounds: h[{i}] = {H[k, i]:.6g} at step k = {k} is outside "
                                  f"[{self.hlo[i]:.6g}, {self.hhi[i]:.6g}] (the inclusion box must hold)")
            if k + 1 < N:
                x[k + 1] = self.A @ x[k] + H[k] + self.B @ U[k]
        return ThesisSimulation(x, y, U, np.zeros((N, 0)), V, extra={"h": H})


def _nonlinear_system(tab):
    A, B, C, _, Z = _plant_from(tab, need_F=False)
    n, ny = A.shape[0], C.shape[0]
    B = B if B is not None else np.zeros((n, 0))
    Z = Z if Z is not None else np.zeros((ny, 0))
    plo, phi = _bounds(_require(tab, "p", "system"), 1, "system.p")
    hlo, hhi = _bounds(_require(tab, "h_bounds", "system"), n, "system.h_bounds")
    h = _expressions(_require(tab, "h", "system"), n, "system.h", ("t", "k", "p") + _state_names(n))
    if Z.shape[1]:
        vlo, vhi = _bounds(_require(tab, "v", "system"), Z.shape[1], "system.v")
    else:
        if "v" in tab:
            raise ConfigError("system.v: given without system.Z (there is no measurement noise)")
        vlo = vhi = np.zeros(0)
    try:
        return NonlinearSystem(A, B, C, Z, h, float(plo[0]), float(phi[0]), hlo, hhi, vlo, vhi)
    except SetboundError as exc:
        raise ConfigError(f"system: {exc}") from None


# ---------------------------------------------------------------- estimators
class _JobRunner:
    """Adapts a thesis observer to the job's ``run(y, u)``: drops the constant input column of
    non-centred boxes, passes the scheduling signal (LPV) chunk by chunk and keeps N rows (an
    observer returning N + 1 rows — the prediction of x_N too — loses its last row; the next
    chunk starts from that state, so chunks join)."""

    def __init__(self, est, nu: int, rho=None, run_kw=None):
        self.est, self.nu, self.rho, self.pos = est, nu, rho, 0
        self.run_kw = run_kw or {}

    def run(self, y, u=None, *, reset: bool = True):
        """From the initial set, or (``reset=False``) from where the last chunk stopped."""
        y = np.asarray(y, float)
        T = y.shape[0]
        if reset:
            self.pos = 0
        uu = None if u is None or self.nu == 0 else np.asarray(u, float)[:, :self.nu]
        kw = dict(self.run_kw)
        if self.rho is not None:
            kw["rho"] = self.rho[self.pos:self.pos + T]
        traj = self.est.run(y, uu, reset=reset, **kw)
        self.pos += T
        if len(traj) == T + 1:
            from ..trajectory import Trajectory

            cut = (lambda a: None if a is None else np.asarray(a)[:T])
            t2 = Trajectory(traj.center[:T], traj.lower[:T], traj.upper[:T], list(traj.sets[:T]),
                            guaranteed=traj.guaranteed, status=cut(traj.status), margin=cut(traj.margin),
                            resets=cut(traj.resets))
            for extra in ("mu",):
                if hasattr(traj, extra):
                    setattr(t2, extra, np.asarray(getattr(traj, extra))[:T])
            traj = t2
        return traj


class _NaiveLuenberger:
    """The naive recursion (4.15) around the Luenberger point observer: x̂_k from the observer,
    [e_k] from :func:`~setbound.interval_observers.interval_error_recursion` (``"naive"``, data
    independent), [x_k] = x̂_k + [e_k]."""

    def __init__(self, obs, plant, e0: Box, w: Box):
        from ..interval_observers import interval_error_recursion

        self.obs, self.plant, self.e0, self.w = obs, plant, e0, w
        self.Ao = plant.A - obs.L @ plant.C
        self.E = plant.error_input(obs.L)
        self._rec = interval_error_recursion
        self.k = 0

    def run(self, y, u=None, *, reset: bool = True):
        from ..trajectory import Trajectory

        from ..system import refuse_missing

        # The naive boxes (4.15) are data independent, tied to the point observer's start: a step
        # that skips a reading restarts that observer, which the naive recursion cannot follow.
        refuse_missing(np.asarray(y, float), "interval_luenberger with variant = \"naive\" (use \"tight\")")
        if reset:
            self.k = 0
            self.obs.reset()
        T = len(y)
        boxes = self._rec(self.Ao, self.E, self.e0, self.w, self.k + T, "naive")[self.k:self.k + T]
        lo, hi, sets = np.empty((T, self.plant.nx)), np.empty((T, self.plant.nx)), []
        for j in range(T):
            xh = self.obs.xhat
            b = Box(xh + boxes[j].lo, xh + boxes[j].hi)  # outward rounding below
            lo[j] = np.nextafter(xh + boxes[j].lo, -np.inf)
            hi[j] = np.nextafter(xh + boxes[j].hi, np.inf)
            sets.append(Box(lo[j], hi[j]) if np.all(np.isfinite(lo[j]) & np.isfinite(hi[j])) else b)
            self.obs.step(y[j], None if u is None else u[j])
            if self.obs.last_check.flagged:
                raise InvalidArgumentError(f"y: row {j}: an impossible reading; the naive recursion (4.15) cannot "
                                           "skip it (use variant = \"tight\", which flags it)")
        self.k += T
        return Trajectory((lo + hi) / 2, lo, hi, sets)


@dataclass
class _View:
    """The thesis plant and boxes an estimator works on."""

    plant: Plant
    dlo: np.ndarray
    dhi: np.ndarray
    vlo: np.ndarray
    vhi: np.ndarray

    d = property(lambda self: Box(self.dlo, self.dhi) if self.dlo.size else None)
    v = property(lambda self: Box(self.vlo, self.vhi) if self.vlo.size else None)
    wbar = property(lambda self: np.concatenate([(self.dhi - self.dlo) / 2, (self.vhi - self.vlo) / 2]))
    centred = property(lambda self: bool(np.all(self.dhi == -self.dlo) and np.all(self.vhi == -self.vlo)))


def _view(job) -> _View:
    """A ``thesis`` system as it is; a ``linear`` one (the papers' unit-box model) through
    :meth:`Plant.from_linear_system`: each ω component drives the state (a column of d) or the
    output (a column of v), never both, with d, v in unit boxes; the constant input column of
    ``[system.omega]`` offsets stays an input."""
    s = job.system
    if isinstance(s, ThesisSystem):
        return _View(s.plant, s.dlo, s.dhi, s.vlo, s.vhi)
    p = Plant.from_linear_system(s)  # raises (naming the system) when d and v are not independent
    return _View(p, -np.ones(p.nd), np.ones(p.nd), -np.ones(p.nv), np.ones(p.nv))


def _xhat0(job, o, n):
    if o.get("xhat0") is None:
        b = _initial_box(job.initial)
        return (np.asarray(b.lo, float) + np.asarray(b.hi, float)) / 2
    return _matrix(o["xhat0"], "xhat0", ndim=1, shape=(n,))


def _user_nu(job) -> int:
    """The inputs of the thesis plant: for a thesis system, without the constant column of the
    offsets (the thesis estimators take the boxes unscaled); for a linear one, all of them."""
    if isinstance(job.system, ThesisSystem):
        return job.system.plant.nu
    return job.system.nu


def _L(o, n, ny):
    return None if o.get("L") is None else _matrix(o["L"], "L", shape=(n, ny))


def _build_luenberger(job, o):
    from ..interval_observers import IntervalLuenbergerObserver

    s = _view(job)
    p = s.plant
    x0 = _initial_box(job.initial)
    xh = _xhat0(job, o, p.nx)
    variant = o["variant"]
    obs = IntervalLuenbergerObserver(p, x0, xh, s.d, s.v, L=_L(o, p.nx, p.ny),
                                     variant="tight" if variant == "naive" else variant,
                                     on_inconsistency=o["on_inconsistency"])
    if variant == "naive":
        e0 = Box(np.asarray(x0.lo, float) - xh, np.asarray(x0.hi, float) - xh)
        w = Box(np.concatenate([s.dlo, s.vlo]), np.concatenate([s.dhi, s.vhi]))
        return _JobRunner(_NaiveLuenberger(obs, p, e0, w), _user_nu(job)), obs
    return _JobRunner(obs, _user_nu(job)), obs


def _build_invariant(job, o):
    from ..interval_observers import IntervalInvariantObserver, offline_error_sequence

    s = _view(job)
    p = s.plant
    x0 = _initial_box(job.initial)
    xh = _xhat0(job, o, p.nx)
    key = ("interval_invariant", tuple(np.asarray(x0.lo)), tuple(np.asarray(x0.hi)), tuple(xh), o["mu"],
           o["inflation"], o["epsilon"], o["variant"])
    design, _ = job.cached_design(key, lambda: offline_error_sequence(
        p, x0, xh, s.d, s.v, mu=float(o["mu"]), inflation=None if o["inflation"] is None else float(o["inflation"]),
        epsilon=float(o["epsilon"]), variant=o["variant"]))
    return _JobRunner(IntervalInvariantObserver(design, on_inconsistency=o["on_inconsistency"]), _user_nu(job)), design


def _build_nonlinear(job, o):
    from ..interval_observers import NonlinearIntervalObserver

    s = job.system
    p = s.plant
    x0 = _initial_box(job.initial)
    xh = _xhat0(job, o, p.nx)
    obs = NonlinearIntervalObserver(p, x0, xh, s.v, h=s.h_box, L=_L(o, p.nx, p.ny), window=int(o["window"]),
                                    on_inconsistency=o["on_inconsistency"])
    return _JobRunner(obs, s.nu), obs


def _W(o, m):
    if o.get("W") is None:
        return None
    return _matrix(o["W"], "W", shape=(m, m))


def _need_centred(s, what):
    if not s.centred:
        raise InvalidArgumentError(f"system.d: {what} needs centred disturbance boxes (|d| <= d̄, |v| <= v̄)")


def _build_ellipsoidal_sm(job, o):
    from .. import hinf

    s = _view(job)
    _need_centred(s, "the Ch. 2 observer")
    p = s.plant
    x0 = _initial_box(job.initial)
    xh = _xhat0(job, o, p.nx)
    key = ("ellipsoidal_sm", o["passes"], o["lambda_route"], None if o["W"] is None else str(o["W"]))
    design, _ = job.cached_design(key, lambda: hinf.design_ellipsoidal_sm_observer(
        p, s.wbar, W=_W(o, p.m), lambda_route=o["lambda_route"], passes=int(o["passes"])))
    mu0 = hinf.mu0_from_box(design, np.asarray(x0.lo, float) - xh, np.asarray(x0.hi, float) - xh)
    return _JobRunner(hinf.EllipsoidalSMObserver(design, xh, mu0, on_inconsistency=o["on_inconsistency"]),
                      _user_nu(job)), design


def _build_lpv_sm(job, o):
    from .. import hinf

    s = job.system
    _need_centred(s, "the Ch. 3 observer")
    x0 = _initial_box(job.initial)
    xh = _xhat0(job, o, s.nx)
    plant = s.lpv_plant()
    key = ("lpv_sm", o["passes"], o["lambda_route"], None if o["W"] is None else str(o["W"]))
    design, _ = job.cached_design(key, lambda: hinf.design_ellipsoidal_sm_observer_lpv(
        plant, s.wbar, W=_W(o, plant.m), lambda_route=o["lambda_route"], passes=int(o["passes"])))
    mu0 = hinf.mu0_from_box(design, np.asarray(x0.lo, float) - xh, np.asarray(x0.hi, float) - xh)
    rho = job.extra.get("rho")
    if rho is None:
        raise InvalidArgumentError("rho: the LPV observer needs the scheduling signal (a [simulation] of an lpv system)")
    return _JobRunner(hinf.LPVEllipsoidalSMObserver(design, xh, mu0, on_inconsistency=o["on_inconsistency"]), s.nu,
                      rho=rho), design


class _InvariantTube:
    """Ex 1.5 as an open-loop estimator (no measurement is used): for ``x⁺ = A x + F d``,
    ``d ∈ [−d̄, d̄]`` and ``[x_0] ⊆ Φ_0`` (the polyhedral RPI set of Algorithm 1),
    ``x_k ∈ Φ_k`` for every k (Φ_{k+1} = AΦ_k ⊕ FΔ) and ``Φ_k ⊆ Φ_{k*}`` for k ≥ k*;
    the boxes are the exact, outward-rounded interval hulls of Φ_k."""

    def __init__(self, design, n: int):
        self.design, self.n, self.k = design, n, 0

    def run(self, y, u=None, *, reset: bool = True):
        from ..trajectory import Trajectory

        if reset:
            self.k = 0
        T = len(y)
        boxes = self.design.boxes
        ks = [min(self.k + j, self.design.k_star) for j in range(T)]
        lo = np.array([np.asarray(boxes[k].lo, float) for k in ks]).reshape(T, self.n)
        hi = np.array([np.asarray(boxes[k].hi, float) for k in ks]).reshape(T, self.n)
        self.k += T
        return Trajectory((lo + hi) / 2, lo, hi, [Box(lo[j], hi[j]) for j in range(T)])


def _build_invariant_tube(job, o):
    from .. import invariant

    s = _view(job)
    p = s.plant
    if p.nu:
        raise InvalidArgumentError("system.B: the invariant tube (Algorithm 1) is for the autonomous "
                                   "x+ = A x + F d (no input)")
    if p.nd == 0:
        raise InvalidArgumentError("system.F: the invariant tube needs the state disturbance F d")
    if not (np.all(s.dhi == -s.dlo)):
        raise InvalidArgumentError("system.d: the invariant tube needs a centred box |d| <= d̄")
    key = ("invariant_tube", o["mu"], o["epsilon"], o["stop"], o["max_iterations"])
    design, _ = job.cached_design(key, lambda: invariant.mrpi_outer_shrinking(
        p.A, p.F, s.dhi, eps=float(o["epsilon"]), mu=float(o["mu"]), stop=o["stop"],
        max_iterations=int(o["max_iterations"])))
    x0 = _initial_box(job.initial)
    lo, hi = np.asarray(x0.lo, float), np.asarray(x0.hi, float)
    corners = np.array(np.meshgrid(*[[a, b] for a, b in zip(lo, hi)], indexing="ij")).reshape(p.nx, -1).T
    if not np.all(design.phi0.contains(corners, tol=0.0)):
        raise InvalidArgumentError("initial: [x_0] is not inside the invariant set Phi_0 of Algorithm 1 (choose a "
                                   "smaller initial box or a larger mu)")
    return _InvariantTube(design, p.nx), design


def _optional(check):
    return lambda v, key: None if v is None else check(v, key)


_XHAT = {"xhat0": optional_vector}
# on_inconsistency: what an impossible reading does (setbound.measurement); "reset" restarts from
# the job's initial box. A missing or skipped reading makes an interval step and restarts the
# observer's error bound (thesis/reading_screen.hpp).
_POLICY = {"on_inconsistency": "flag"}
_POLICY_CHECKS = {"on_inconsistency": one_of("flag", "raise", "reset")}
_GAIN = {"L": optional_matrix}
_SM = {"xhat0": None, "W": None, "passes": 2, "lambda_route": None, **_POLICY}
_SM_CHECKS = {**_XHAT, **_POLICY_CHECKS, "W": optional_matrix, "passes": one_of(1, 2),
              "lambda_route": _optional(one_of("logdet", "direct", "input_or_logdet", "largest"))}
# the work of these designs grows with the value: the Python API's own bounds, so that a value
# the observer would refuse is a job-file error at load time
_WINDOW_MAX = _API_MAX_WINDOW
_ITERATIONS_MAX = _API_MAX_ITERATIONS

register_system("thesis", {"A", "B", "C", "F", "Z", "d", "v"}, _thesis_system, ThesisSystem,
                description="x+ = A x + B u + F d, y = C x + Z v with boxes d, v (Methods › H∞ set-membership observers › Model)")
register_system("lpv", {"A", "B", "C", "F", "Z", "d", "v", "theta", "scheduling", "clip"}, _lpv_system,
                LpvSystem, description="polytopic LPV x+ = A(rho) x + B(rho) u + F(rho) d, y = C x + Z v, "
                                       "rho(t, k, x) in conv(theta) (Methods › H∞ set-membership observers › LPV systems)")
register_system("nonlinear", {"A", "B", "C", "Z", "h", "p", "h_bounds", "v"}, _nonlinear_system,
                NonlinearSystem, description="x+ = A x + h(p, x, k) + B u, y = C x + Z v, h in [h] "
                                             "(Methods › Interval observers › Nonlinear interval observer)")
register_estimator("interval_luenberger", "interval", {"xhat0": None, "L": None, "variant": "tight", **_POLICY},
                   _build_luenberger, systems=("thesis", "linear"),
                   checks={**_XHAT, **_GAIN, **_POLICY_CHECKS, "variant": one_of("tight", "wrapped", "naive")},
                   description="thesis Ch. 4 interval Luenberger observer (Methods › Interval observers › Interval Luenberger observer)")
register_estimator("interval_invariant", "interval",
                   {"xhat0": None, "mu": 2.0, "inflation": None, "epsilon": 0.01, "variant": "tight", **_POLICY},
                   _build_invariant, systems=("thesis", "linear"),
                   checks={**_XHAT, **_POLICY_CHECKS, "mu": number(lo=1, lo_open=True),
                           "inflation": _optional(number(lo=1)),
                           "epsilon": number(lo=0, lo_open=True),
                           "variant": one_of("tight", "wrapped")},
                   description="thesis Ch. 4 interval observer with an invariant-set tail (Methods › Interval observers › Invariant-set observer)")
register_estimator("nonlinear_interval", "interval", {"xhat0": None, "L": None, "window": 256, **_POLICY},
                   _build_nonlinear, systems=("nonlinear",),
                   checks={**_XHAT, **_GAIN, **_POLICY_CHECKS, "window": positive_int(_WINDOW_MAX)},
                   description="thesis Ch. 4 nonlinear interval observer (Methods › Interval observers › Nonlinear interval observer)")
# The Ch. 1-3 estimators need setbound.hinf / setbound.invariant (the thesis branches); a kind is
# registered only when its module is present, so a job naming it otherwise fails as an unknown method.
_HAVE = {m: importlib.util.find_spec(f"setbound.{m}") is not None for m in ("hinf", "invariant")}
if _HAVE["hinf"]:
    register_estimator("ellipsoidal_sm", "thesis-ellipsoidal", dict(_SM), _build_ellipsoidal_sm,
                       systems=("thesis", "linear"),
                       checks=_SM_CHECKS,
                       description="thesis Ch. 2 ellipsoidal-invariant-set observer, Algorithm 2 (Methods › H∞ set-membership observers › Algorithm 2)")
    register_estimator("lpv_sm", "thesis-ellipsoidal", dict(_SM), _build_lpv_sm, systems=("lpv",),
                       checks=_SM_CHECKS,
                       description="thesis Ch. 3 LPV ellipsoidal-invariant-set observer, Algorithm 3 (Methods › H∞ set-membership observers › LPV systems)")
if _HAVE["invariant"]:
    register_estimator("invariant_tube", "invariant", {"mu": 1.05, "epsilon": 4.4e-3, "stop": "shrinking_index",
                                                       "max_iterations": 1000},
                       _build_invariant_tube, systems=("thesis",),
                       checks={"mu": number(lo=1, lo_open=True),
                               "epsilon": number(lo=0, lo_open=True),
                               "stop": one_of("radius", "shrinking_index", "vertex_norm"),
                               "max_iterations": positive_int(_ITERATIONS_MAX)},
                       description="thesis Ch. 1 Algorithm 1 as an open-loop tube x_k in Phi_k for the "
                                   "autonomous x+ = A x + F d (Methods › Invariant sets › Algorithm 1, Ex 1.5)")
