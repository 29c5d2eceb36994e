"""H∞ set-membership observers of the thesis, Chapters 1–3 (Methods › Invariant sets › Bounded-real-lemma RPI ellipsoid; Methods › H∞ set-membership observers).

* :func:`brl_ellipsoidal_rpi` — Bounded-Real-Lemma RPI ellipsoid (1.48, 1.55);
* :func:`hinf_observer_gain` — LMI (2.35) (a :class:`~setbound.Plant`) or the vertex LMIs
  (3.13) with a common P (an :class:`LpvPlant`);
* :func:`ellipsoidal_error_rpi`, :func:`refine_dissipation_matrix`,
  :func:`covariance_dissipation_matrix`, :func:`chebyshev_error_ellipsoid`;
* :func:`design_ellipsoidal_sm_observer` (Algorithm 2) and
  :func:`design_ellipsoidal_sm_observer_lpv` (Algorithm 3) → :class:`EllipsoidalSMDesign`;
* :class:`EllipsoidalSMObserver` and :class:`LPVEllipsoidalSMObserver` (online, a one-step
  predictor: row k of a run bounds x_k using y_0..y_{k-1}), with :func:`mu0_from_ball`,
  :func:`mu0_from_vertices` and :func:`mu0_from_box`;
* :func:`polytopic_weights` (closed form for a box in any vertex order, LP otherwise).

Every design is certified in floating point by the C++ library (see docs/thesis_hinf.md).
The optimal γ is unique, L and P are not (Methods › H∞ set-membership observers › Observer gain).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ._native import as_f64, check, dptr, ffi, lib
from ._state import MadeByCall, StateMixin, reconstructible, remember_call, run_from_initial_set
from ._validate import as_choice, as_float, as_int
from .errors import DimensionError, InvalidArgumentError
from .interval import Box
from .plant import Plant, as_plant
from .measurement import POLICIES, ReadingChecks, measurement_or_missing, _set_box_policy
from .system import refuse_infinite
from .trajectory import Trajectory

__all__ = [
    "LpvPlant", "HinfGain", "BrlRpi", "ErrorRpi", "EllipsoidalSMDesign", "EllipsoidalSMObserver",
    "LPVEllipsoidalSMObserver", "brl_ellipsoidal_rpi", "hinf_observer_gain", "ellipsoidal_error_rpi",
    "refine_dissipation_matrix", "covariance_dissipation_matrix", "chebyshev_error_ellipsoid",
    "polytopic_weights", "design_ellipsoidal_sm_observer", "design_ellipsoidal_sm_observer_lpv",
    "mu0_from_ball", "mu0_from_vertices", "mu0_from_box", "box_corners",
    "EsoDDesign", "design_eso_d", "CORA_GAMMA_GRID",
]

_ROUTES = {None: -1, "default": -1, "logdet": 0, "direct": 1, "input_or_logdet": 2, "largest": 3}


def _route(r) -> int:
    # by type and value (as_choice), so that an unhashable value (a list) is a clean error as well
    return _ROUTES[as_choice(r, "lambda_route", list(_ROUTES))]


#: Upper bound of ``passes`` of the ellipsoidal SM design (the thesis uses 2; every pass solves
#: the LMIs again, about a second each, so ``passes=2**30`` would run for decades).
MAX_PASSES = lib.SB_HINF_MAX_PASSES  # 100, the C library refuses more too


class LpvPlant:
    """A polytopic LPV plant ``x⁺ = A(ρ)x + B(ρ)u + F(ρ)d``, ``y = Cx + Zv``, ``M(ρ) = Σ α_i(ρ) M_i``, ``ρ ∈ conv{θ_i}``.

    Methods › H∞ set-membership observers › LPV systems.

    Parameters
    ----------
    A : sequence of array_like
        Vertex matrices ``A_i`` (one per row θ_i of ``theta``, in the same order).
    C : array_like, shape (n_y, n_x)
        Common output matrix.
    theta : array_like, shape (N, n_ρ)
        Vertices of the scheduling polytope.
    B : sequence of array_like, optional
        Vertex input matrices.
    Fd : sequence of array_like, optional
        Vertex disturbance matrices (the thesis's ``F``).
    Z : array_like, optional
        Common measurement-noise matrix.
    **wrong
        Refused (``F=`` gets a message pointing to ``Fd=``).

    Examples
    --------
    >>> lpv = setbound.LpvPlant([[[0.5, 0.1], [0.0, 0.4]], [[0.6, 0.1], [0.0, 0.4]]], [[1.0, 0.0]], [[0.0], [1.0]],
    ...                         Fd=[0.1 * np.eye(2), 0.1 * np.eye(2)], Z=[[0.1]])
    >>> lpv.weights([0.25]).round(6).tolist()
    [0.75, 0.25]
    """

    def __init__(self, A, C, theta, *, B=None, Fd=None, Z=None, **wrong):
        if "F" in wrong:
            raise InvalidArgumentError("F: the vertex state-disturbance matrices are passed as Fd= (as for Plant)")
        if wrong:
            raise TypeError(f"LpvPlant() got unexpected keyword arguments {sorted(wrong)}")
        F = Fd
        A = [as_f64(a, f"A[{i}]", ndim=2) for i, a in enumerate(A)]
        if not A:
            raise DimensionError("A: at least one vertex matrix is required")
        N = len(A)
        theta = as_f64(theta, "theta")
        if theta.ndim == 1:
            theta = theta.reshape(-1, 1)
        if theta.ndim != 2 or theta.shape[0] != N:
            raise DimensionError(f"theta: expected shape ({N}, n_rho) (one vertex per A_i), got {theta.shape}")
        B = [None] * N if B is None else list(B)
        F = [None] * N if F is None else list(F)
        if len(B) != N:
            raise DimensionError(f"B: expected {N} vertex matrices, got {len(B)}")
        if len(F) != N:
            raise DimensionError(f"F: expected {N} vertex matrices, got {len(F)}")
        self.vertices = [Plant(A[i], C, B=B[i], Fd=F[i], Z=Z) for i in range(N)]
        for i, p in enumerate(self.vertices):
            for name, M, M0 in (("A", p.A, self.vertices[0].A), ("B", p.B, self.vertices[0].B),
                                ("F", p.F, self.vertices[0].F)):
                if M.shape != M0.shape:
                    raise DimensionError(f"{name}[{i}]: expected shape {M0.shape} (as vertex 0), got {M.shape}")
        self.theta = np.ascontiguousarray(theta)
        self.C, self.Z = self.vertices[0].C, self.vertices[0].Z

    A = property(lambda self: [p.A for p in self.vertices], doc="vertex matrices A_i (list)")
    B = property(lambda self: [p.B for p in self.vertices], doc="vertex matrices B_i (list)")
    F = property(lambda self: [p.F for p in self.vertices], doc="vertex matrices F_i (list)")
    N = property(lambda self: len(self.vertices), doc="number of vertices")
    nx = property(lambda self: self.vertices[0].nx, doc="state dimension")
    nu = property(lambda self: self.vertices[0].nu, doc="input dimension")
    ny = property(lambda self: self.vertices[0].ny, doc="output dimension")
    nd = property(lambda self: self.vertices[0].nd, doc="state-disturbance dimension")
    nv = property(lambda self: self.vertices[0].nv, doc="noise dimension")
    m = property(lambda self: self.vertices[0].m, doc="disturbance dimension n_d + n_v")
    n_rho = property(lambda self: self.theta.shape[1], doc="dimension of the scheduling vector ρ")

    def weights(self, rho) -> np.ndarray:
        """Barycentric weights ``α(ρ)`` of a scheduling vector (thesis (3.2)).

        Parameters
        ----------
        rho : array_like, shape (n_ρ,)
            Scheduling vector.

        Returns
        -------
        ndarray, shape (N,)
        """
        return polytopic_weights(self.theta, rho)

    def at(self, rho) -> Plant:
        """The frozen plant at ``ρ``: ``Σ α_i(ρ)·(A_i, B_i, F_i)``.

        Parameters
        ----------
        rho : array_like, shape (n_ρ,)
            Scheduling vector.

        Returns
        -------
        Plant
        """
        a = self.weights(rho)
        return Plant(sum(w * p.A for w, p in zip(a, self.vertices)), self.C,
                     B=sum(w * p.B for w, p in zip(a, self.vertices)),
                     Fd=sum(w * p.F for w, p in zip(a, self.vertices)), Z=self.Z)

    def __repr__(self) -> str:
        return f"LpvPlant(N={self.N}, n_rho={self.n_rho}, n_x={self.nx}, n_u={self.nu}, n_y={self.ny})"


def _stack(ms, rows, cols) -> np.ndarray:
    return np.ascontiguousarray(np.stack([np.asarray(m, dtype=np.float64).reshape(rows, cols) for m in ms]))


def _vertex_data(plant):
    if isinstance(plant, LpvPlant):
        return plant.N, plant.vertices[0], plant.A, plant.F
    plant = as_plant(plant)  # a Plant, or a LinearSystem / StateSpace converted (unit-box d, v)
    return 1, plant, [plant.A], [plant.F]


@dataclass
class HinfGain:
    """Result of :func:`hinf_observer_gain`.

    Parameters
    ----------
    P : ndarray, shape (n_x, n_x)
        Lyapunov matrix of the error.
    U : ndarray
        ``P L``: (n_x, n_y) for a Plant, (N, n_x, n_y) for an LpvPlant.
    L : ndarray
        Observer gain(s) ``P⁻¹U``, same shape as ``U``.
    Q : ndarray, shape (n_x, n_x)
        Dissipation matrix used.
    gamma, g : float
        The H∞ level γ and ``g = γ²``.
    """
    P: np.ndarray
    U: np.ndarray  # (n_x, n_y) for a Plant, (N, n_x, n_y) for an LpvPlant
    L: np.ndarray  # P⁻¹U, same shape as U
    Q: np.ndarray
    gamma: float
    g: float


def hinf_observer_gain(plant, Q=None) -> HinfGain:
    """The H∞ observer gain: LMI (2.35) for a Plant, (3.13) for an LpvPlant; minimises ``g = γ²``, ``L = P⁻¹U`` (Methods › H∞ set-membership observers › Observer gain).

    Parameters
    ----------
    plant : Plant or LpvPlant
        The plant.
    Q : array_like, shape (n_x, n_x), optional
        Dissipation matrix (default: identity).

    Returns
    -------
    HinfGain

    Examples
    --------
    >>> plant = setbound.Plant([[0.2, 0.2], [0.0, 0.5]], [[1.0, 0.0]], Fd=[[0.0], [0.1]], Z=[[0.1]])
    >>> gain = setbound.hinf.hinf_observer_gain(plant)
    >>> Ao = np.asarray(plant.A) - gain.L @ np.asarray(plant.C)
    >>> bool(max(abs(np.linalg.eigvals(Ao))) < 1)
    True
    """
    N, p0, As, Fs = _vertex_data(plant)
    n, ny = p0.nx, p0.ny
    Qa = None if Q is None else as_f64(Q, "Q", shape=(n, n))
    A, F = _stack(As, n, n), _stack(Fs, n, p0.nd)
    P, U, L = np.empty((n, n)), np.empty((N, n, ny)), np.empty((N, n, ny))
    gam, g = ffi.new("double*"), ffi.new("double*")
    check(lib.sb_hinf_observer_gain(N, n, ny, p0.nd, p0.nv, dptr(A), dptr(p0.C), dptr(F), dptr(p0.Z),
                                    dptr(Qa) if Qa is not None else ffi.NULL, dptr(P), dptr(U), dptr(L), gam, g))
    if N == 1 and not isinstance(plant, LpvPlant):
        U, L = U[0], L[0]
    return HinfGain(P, U, L, np.eye(n) if Qa is None else Qa.copy(), gam[0], g[0])


@dataclass
class BrlRpi:
    """Result of :func:`brl_ellipsoidal_rpi`: the RPI ellipsoid ``Ψ = {xᵀPx ≤ level}``.

    Parameters
    ----------
    P : ndarray, shape (n, n)
        Shape.
    gamma, g : float
        The bounded-real-lemma level γ and ``g = γ²``.
    level : float
        Level of Ψ.
    """
    P: np.ndarray
    gamma: float
    g: float
    level: float  # Ψ = {xᵀPx ≤ level}


def brl_ellipsoidal_rpi(A, E, wbar) -> BrlRpi:
    """The bounded-real-lemma RPI ellipsoid of ``x⁺ = Ax + Ew``, ``|w| ≤ w̄`` (thesis LMI (1.48), set (1.55)).

    Minimal γ; ``Ψ = {xᵀPx ≤ λ_max(P)γ²w̄ᵀw̄}`` (Methods › Invariant sets › Bounded-real-lemma RPI
    ellipsoid).

    Parameters
    ----------
    A : array_like, shape (n, n)
        Schur-stable matrix.
    E : array_like, shape (n, m)
        Disturbance matrix.
    wbar : array_like, shape (m,)
        Bounds of ``|w_i|``.

    Returns
    -------
    BrlRpi

    Examples
    --------
    The system of [Loukkas2018] Example 1.5:

    >>> r = setbound.hinf.brl_ellipsoidal_rpi([[0.2, 0.2], [-0.2, 0.5]], [[0.0], [1.0]], [1.0])
    >>> bool(r.gamma > 0 and r.level > 0)
    True
    """
    A = as_f64(A, "A", ndim=2)
    n = A.shape[0]
    E = as_f64(E, "E", shape=(n, None))
    wbar = as_f64(wbar, "wbar", shape=(E.shape[1],))
    P = np.empty((n, n))
    gam, g, lvl = ffi.new("double*"), ffi.new("double*"), ffi.new("double*")
    check(lib.sb_brl_ellipsoidal_rpi(n, E.shape[1], dptr(A), dptr(E), dptr(wbar), dptr(P), gam, g, lvl))
    return BrlRpi(P, gam[0], g[0], lvl[0])


@dataclass
class ErrorRpi:
    """Result of :func:`ellipsoidal_error_rpi`.

    Parameters
    ----------
    lambda_ : float
        ``λ = λ_min(Q, P)``.
    cbar : float
        Level ``c̄`` of the invariant error ellipsoid ``{eᵀPe ≤ c̄}``.
    e_inf : ndarray, shape (n,)
        Half-widths ``ē∞`` of its bounding box.
    """
    lambda_: float
    cbar: float
    e_inf: np.ndarray


def ellipsoidal_error_rpi(P, Q, g, wbar) -> ErrorRpi:
    """The invariant error ellipsoid of [Loukkas2018] Prop 2.2/2.3 (Methods › H∞ set-membership observers › Error RPI ellipsoid).

    ``λ = λ_min(Q, P)``, ``c̄ = γ²w̄ᵀw̄/λ``, ``ē∞ = sqrt(diag(c̄P⁻¹))``.

    Parameters
    ----------
    P, Q : array_like, shape (n, n)
        Lyapunov and dissipation matrices.
    g : float
        ``γ²``.
    wbar : array_like
        Half-widths of ``w``.

    Returns
    -------
    ErrorRpi

    Examples
    --------
    >>> plant = setbound.Plant([[0.2, 0.2], [0.0, 0.5]], [[1.0, 0.0]], Fd=[[0.0], [0.1]], Z=[[0.1]])
    >>> gain = setbound.hinf.hinf_observer_gain(plant)
    >>> rpi = setbound.hinf.ellipsoidal_error_rpi(gain.P, gain.Q, gain.g, [1.0, 1.0])
    >>> bool(0 < rpi.lambda_ <= 1), rpi.e_inf.shape
    (True, (2,))
    """
    P = as_f64(P, "P", ndim=2)
    n = P.shape[0]
    Q = as_f64(Q, "Q", shape=(n, n))
    wbar = as_f64(wbar, "wbar", ndim=1)
    lam, cb, e = ffi.new("double*"), ffi.new("double*"), np.empty(n)
    g = as_float(g, "g")
    check(lib.sb_ellipsoidal_error_rpi(n, dptr(P), dptr(Q), g, wbar.size, dptr(wbar), lam, cb, dptr(e)))
    return ErrorRpi(lam[0], cb[0], e)


def refine_dissipation_matrix(plant, P, L, g, route: str = "logdet"):
    """Refine the dissipation matrix with ``P``, ``L`` and ``g`` fixed (thesis (2.36), (3.20); Methods › H∞ set-membership observers › Dissipation matrix refinement).

    Parameters
    ----------
    plant : Plant or LpvPlant
        The plant.
    P : array_like, shape (n_x, n_x)
        Lyapunov matrix.
    L : array_like
        Gain(s).
    g : float
        ``γ²``.
    route : {"logdet", "direct"}, optional
        ``"logdet"``: maximise ``log det Q``; ``"direct"`` [proposed]: the largest ``λ`` with
        ``Q = λP``.

    Returns
    -------
    Q : ndarray
    lam : float
        ``λ_min(Q, P)``.
    """
    N, p0, As, Fs = _vertex_data(plant)
    n, ny = p0.nx, p0.ny
    r = {"logdet": 0, "direct": 1}[as_choice(route, "route", ("logdet", "direct"))]
    g = as_float(g, "g")
    P = as_f64(P, "P", shape=(n, n))
    L = np.ascontiguousarray(np.asarray(L, dtype=np.float64).reshape(N, n, ny)) if np.size(L) == N * n * ny else \
        as_f64(L, "L", shape=(n, ny))
    A, F = _stack(As, n, n), _stack(Fs, n, p0.nd)
    Q, lam = np.empty((n, n)), ffi.new("double*")
    check(lib.sb_refine_dissipation_matrix(N, n, ny, p0.nd, p0.nv, dptr(A), dptr(p0.C), dptr(F), dptr(p0.Z),
                                           dptr(P), dptr(L), g, r, dptr(Q), lam))
    return Q, lam[0]


def covariance_dissipation_matrix(Ao, E, W):
    """The error covariance ``V`` and ``Q = V⁻¹`` (thesis (2.43), (3.60)–(3.61)).

    ``V`` is the mean of the ``V_i`` with ``A_o,i V_i A_o,iᵀ − V_i = −E_i W E_iᵀ``.

    Parameters
    ----------
    Ao : array_like or sequence of array_like
        Error matrix ``A − LC`` (or its vertex matrices).
    E : array_like or sequence of array_like
        Error-input matrix ``[F, −LZ]`` (or its vertex matrices).
    W : array_like
        Covariance of ``w = (d, v)``.

    Returns
    -------
    V, Q : ndarray
    """
    Aos = [Ao] if np.ndim(Ao) == 2 else list(Ao)
    Es = [E] if np.ndim(E) == 2 else list(E)
    if len(Aos) != len(Es):
        raise DimensionError(f"E: expected {len(Aos)} vertex matrices (as Ao), got {len(Es)}")
    n = np.shape(Aos[0])[0]
    m = np.shape(Es[0])[1]
    W = as_f64(W, "W", shape=(m, m))
    A, Em = _stack(Aos, n, n), _stack(Es, n, m)
    V, Q = np.empty((n, n)), np.empty((n, n))
    check(lib.sb_covariance_dissipation_matrix(len(Aos), n, m, dptr(A), dptr(Em), dptr(W), dptr(V), dptr(Q)))
    return V, Q


def chebyshev_error_ellipsoid(V, t):
    """The Chebyshev ellipsoid ``{eᵀV⁻¹e ≤ t²}``, which holds with probability at least ``1 − n/t²`` (thesis (2.41); reporting only, not guaranteed).

    Parameters
    ----------
    V : array_like, shape (n, n)
        Error covariance.
    t : float
        Radius, ``t² > n``.

    Returns
    -------
    Vinv : ndarray
        ``V⁻¹``.
    t2 : float
        ``t²``.
    probability : float
        ``1 − n/t²``.

    Examples
    --------
    >>> Vinv, t2, p = setbound.hinf.chebyshev_error_ellipsoid(np.eye(2), 3.0)
    >>> t2, round(p, 6)
    (9.0, 0.777778)
    """
    V = as_f64(V, "V", ndim=2)
    n = V.shape[0]
    S, lvl, pr = np.empty((n, n)), ffi.new("double*"), ffi.new("double*")
    check(lib.sb_chebyshev_error_ellipsoid(n, dptr(V), as_float(t, "t"), dptr(S), lvl, pr))
    return S, lvl[0], pr[0]


def polytopic_weights(theta, rho) -> np.ndarray:
    """Barycentric weights: ``α ≥ 0``, ``Σα = 1``, ``Σ α_i θ_i = ρ`` (thesis (3.2)).

    Parameters
    ----------
    theta : array_like, shape (N, n_ρ)
        Vertices (one per row).
    rho : array_like, shape (n_ρ,)
        The point.

    Returns
    -------
    ndarray, shape (N,)

    Examples
    --------
    >>> setbound.hinf.polytopic_weights([[0.0], [1.0]], [0.25]).round(6).tolist()
    [0.75, 0.25]
    """
    theta = as_f64(theta, "theta")
    if theta.ndim == 1:
        theta = theta.reshape(-1, 1)
    rho = np.atleast_1d(as_f64(rho, "rho"))
    a = np.empty(theta.shape[0])
    check(lib.sb_polytopic_weights(theta.shape[0], theta.shape[1], dptr(theta), dptr(rho), dptr(a)))
    return a


@dataclass
class DesignPass:
    P: np.ndarray
    L: np.ndarray
    Q_input: np.ndarray
    Q_refined: np.ndarray
    g: float
    gamma: float
    lambda_input: float
    lambda_refined: float
    lambda_direct: float
    lambda_: float
    refinement_failed: bool


@dataclass
class EllipsoidalSMDesign(MadeByCall):
    """Output of Algorithm 2 (LTI) or 3 (LPV) of [Loukkas2018] (Methods › H∞ set-membership observers › Algorithm 2).

    Parameters
    ----------
    plant : Plant or LpvPlant
        The plant designed for.
    L : ndarray
        Gain: (n_x, n_y) for a Plant, (N, n_x, n_y) for an LpvPlant.
    P : ndarray, shape (n_x, n_x)
        Lyapunov matrix.
    Q_input, Q_refined : ndarray, shape (n_x, n_x)
        Dissipation matrix given to the LMI and its refinement.
    V : ndarray, shape (n_x, n_x)
        Error covariance (for the Chebyshev ellipsoid).
    e_inf : ndarray, shape (n_x,)
        Half-widths of the box of the invariant error ellipsoid.
    gamma, g : float
        H∞ level and its square.
    lambda_, lambda_input, lambda_refined : float
        The ``λ`` used and the two candidates.
    cbar : float
        Level of the invariant error ellipsoid.
    wtw : float
        ``w̄ᵀw̄``.
    lambda_max_P : float
        Largest eigenvalue of ``P``.
    design_time : float
        Seconds.
    passes : list, optional
        Per-pass details.
    """
    plant: object
    L: np.ndarray
    P: np.ndarray
    Q_input: np.ndarray
    Q_refined: np.ndarray
    V: np.ndarray
    e_inf: np.ndarray
    gamma: float
    g: float
    lambda_: float
    lambda_input: float
    lambda_refined: float
    cbar: float
    wtw: float
    lambda_max_P: float
    design_time: float
    passes: list = field(default_factory=list)
    _handle: object = field(default=None, repr=False)

    @property
    def L_vertices(self) -> np.ndarray:
        """The vertex gains L_i stacked, (N, n_x, n_y); the LTI design has N = 1."""
        return self.L if self.L.ndim == 3 else self.L[None]


def _design(plant, wbar, W, lambda_route, passes, lpv: bool) -> EllipsoidalSMDesign:
    # checked first: the C ABI reads passes <= 0 as "2" and would run any large count
    passes = as_int(passes, "passes", lo=1, hi=MAX_PASSES)
    route = _route(lambda_route)
    if not lpv:
        plant = as_plant(plant)
    N, p0, As, Fs = _vertex_data(plant)
    n, nu, ny, nd, nv = p0.nx, p0.nu, p0.ny, p0.nd, p0.nv
    m = nd + nv
    wbar = np.ones(m) if wbar is None else as_f64(wbar, "wbar", shape=(m,))
    Wa = None if W is None else as_f64(W, "W", shape=(m, m))
    A, F = _stack(As, n, n), _stack(Fs, n, nd)
    if lpv:
        B = _stack(plant.B, n, nu)
        theta, nrho = plant.theta, plant.n_rho
    else:
        B, theta, nrho = p0.B, None, 0
    h = ffi.new("sb_hinf_design**")
    check(lib.sb_hinf_design_create(N, n, nu, ny, nd, nv, nrho, dptr(A), dptr(np.ascontiguousarray(B)), dptr(p0.C),
                                    dptr(F), dptr(p0.Z), dptr(theta) if theta is not None else ffi.NULL, dptr(wbar),
                                    dptr(Wa) if Wa is not None else ffi.NULL, route, passes, h))
    handle = ffi.gc(h[0], lib.sb_hinf_design_free)
    npass = ffi.new("int*")
    check(lib.sb_hinf_design_dims(handle, ffi.NULL, ffi.NULL, ffi.NULL, ffi.NULL, ffi.NULL, ffi.NULL, ffi.NULL, npass))
    P, L, Qi, Qr, V, e, s = (np.empty((n, n)), np.empty((N, n, ny)), np.empty((n, n)), np.empty((n, n)),
                             np.empty((n, n)), np.empty(n), np.empty(9))
    check(lib.sb_hinf_design_get(handle, dptr(P), dptr(L), dptr(Qi), dptr(Qr), dptr(V), dptr(e), dptr(s)))
    ps = []
    for k in range(npass[0]):
        pP, pL, pQi, pQr, ss = np.empty((n, n)), np.empty((N, n, ny)), np.empty((n, n)), np.empty((n, n)), np.empty(7)
        check(lib.sb_hinf_design_pass(handle, k, dptr(pP), dptr(pL), dptr(pQi), dptr(pQr), dptr(ss)))
        ps.append(DesignPass(pP, pL if lpv else pL[0], pQi, pQr, ss[0], ss[1], ss[2], ss[3], ss[4], ss[5], bool(ss[6])))
    return remember_call(EllipsoidalSMDesign(plant, L if lpv else L[0], P, Qi, Qr, V, e, s[0], s[1], s[2], s[3], s[4],
                                             s[5], s[6], s[7], s[8], ps, handle),
                         _design, plant, wbar, W, lambda_route, passes, lpv)


def design_ellipsoidal_sm_observer(plant: Plant, wbar=None, *, W=None, lambda_route=None, passes: int = 2):
    """Algorithm 2 of [Loukkas2018]: gain, invariant error ellipsoid and ``λ`` of the Chapter 2 observer (Methods › H∞ set-membership observers › Algorithm 2).

    Parameters
    ----------
    plant : Plant, LinearSystem or control.StateSpace
        The plant (a LinearSystem / StateSpace is converted by :func:`setbound.plant.as_plant`).
    wbar : array_like, optional
        Half-widths of the centred box of ``w = (d, v)`` (default: ones, the unit box of a
        converted LinearSystem).
    W : array_like, optional
        Covariance of ``w`` for (2.44) (default: uniform on ``[−w̄, w̄]``).
    lambda_route : {"logdet", "direct", "input_or_logdet", "largest"}, optional
        How ``λ`` is chosen (default ``"logdet"``, as printed).
    passes : int, optional
        In ``[1, MAX_PASSES]`` (100; the thesis uses 2, each pass solves the LMIs again).

    Returns
    -------
    EllipsoidalSMDesign

    Examples
    --------
    The example of [Loukkas2018] §2.5:

    >>> plant = setbound.Plant([[0.2, 0.2], [0.0, 0.5]], [[1.0, 0.0]], B=[[1.0], [1.0]], Fd=[[0.0], [0.1]], Z=[[0.1]])
    >>> design = setbound.hinf.design_ellipsoidal_sm_observer(plant)
    >>> bool(0 < design.lambda_ <= 1), design.e_inf.shape
    (True, (2,))
    """
    if isinstance(plant, LpvPlant):
        raise InvalidArgumentError("plant: an LpvPlant needs design_ellipsoidal_sm_observer_lpv")
    return _design(plant, wbar, W, lambda_route, passes, False)


def design_ellipsoidal_sm_observer_lpv(plant: LpvPlant, wbar, *, W=None, lambda_route=None, passes: int = 2):
    """Algorithm 3 of [Loukkas2018]: vertex LMIs with a common ``P`` for an LPV plant (Methods › H∞ set-membership observers › LPV systems).

    ``λ`` defaults to the larger of ``λ_min(Q_input, P)`` and ``λ_min(Q_refined, P)``.

    Parameters
    ----------
    plant : LpvPlant
        The plant.
    wbar : array_like
        Half-widths of the centred box of ``w = (d, v)``.
    W : array_like, optional
        Covariance of ``w``.
    lambda_route : str, optional
        As :func:`design_ellipsoidal_sm_observer`.
    passes : int, optional
        As :func:`design_ellipsoidal_sm_observer`.

    Returns
    -------
    EllipsoidalSMDesign

    Examples
    --------
    >>> lpv = setbound.LpvPlant([[[0.5, 0.1], [0.0, 0.4]], [[0.6, 0.1], [0.0, 0.4]]], [[1.0, 0.0]], [[0.0], [1.0]],
    ...                         Fd=[0.1 * np.eye(2), 0.1 * np.eye(2)], Z=[[0.1]])
    >>> design = setbound.hinf.design_ellipsoidal_sm_observer_lpv(lpv, np.ones(3))
    >>> design.L.shape
    (2, 2, 1)
    """
    if not isinstance(plant, LpvPlant):
        raise InvalidArgumentError("plant: expected a setbound.hinf.LpvPlant")
    return _design(plant, wbar, W, lambda_route, passes, True)


def mu0_from_ball(design: EllipsoidalSMDesign, radius: float) -> float:
    """``μ_0 = max(1, λ_max(P)·radius²/c̄)`` for ``‖x_0 − x̂_0‖ ≤ radius`` (thesis (2.65)–(2.67)).

    Parameters
    ----------
    design : EllipsoidalSMDesign
        The design.
    radius : float
        Radius of the initial ball around ``x̂_0``.

    Returns
    -------
    float

    Examples
    --------
    >>> plant = setbound.Plant([[0.2, 0.2], [0.0, 0.5]], [[1.0, 0.0]], Fd=[[0.0], [0.1]], Z=[[0.1]])
    >>> design = setbound.hinf.design_ellipsoidal_sm_observer(plant)
    >>> setbound.hinf.mu0_from_ball(design, 1.0) >= 1
    True
    """
    out = ffi.new("double*")
    check(lib.sb_hinf_design_mu0_ball(design._handle, as_float(radius, "radius", lo=0.0), out))
    return out[0]


def mu0_from_vertices(design: EllipsoidalSMDesign, vertices) -> float:
    """``μ_0 = max(1, max_j v_jᵀPv_j/c̄)`` for ``e_0 ∈ conv{v_j}`` (thesis (3.73)–(3.74)).

    Parameters
    ----------
    design : EllipsoidalSMDesign
        The design.
    vertices : array_like, shape (q, n_x)
        Vertices ``v_j`` (rows).

    Returns
    -------
    float
    """
    n = design.P.shape[0]
    V = as_f64(vertices, "vertices", shape=(None, n))
    out = ffi.new("double*")
    check(lib.sb_hinf_design_mu0_vertices(design._handle, V.shape[0], dptr(V), out))
    return out[0]


def mu0_from_box(design: EllipsoidalSMDesign, lo, hi) -> float:
    """``μ_0`` for an initial error ``e_0 = x_0 − x̂_0`` in the box ``[lo, hi]``.

    For ``n_x <= 20`` the exact maximum of ``vᵀPv / c̄`` over the box's ``2^n`` corners; beyond,
    where the corners are too many, a guaranteed upper bound of it (with ``r = max(|lo|, |hi|)``,
    the smaller of ``rᵀ|P|r / c̄`` and ``λ_max(P) rᵀr / c̄``).

    Parameters
    ----------
    design : EllipsoidalSMDesign
        The design.
    lo, hi : array_like, shape (n_x,)
        The box of ``e_0``.

    Returns
    -------
    float
    """
    n = design.P.shape[0]
    lo, hi = as_f64(lo, "lo", shape=(n,)), as_f64(hi, "hi", shape=(n,))
    out = ffi.new("double*")
    check(lib.sb_hinf_design_mu0_box(design._handle, dptr(lo), dptr(hi), out))
    return out[0]


def box_corners(lo, hi) -> np.ndarray:
    """The ``2^n`` corners of the box ``[lo, hi]``, one per row (``n <= 24``).

    Parameters
    ----------
    lo, hi : array_like, shape (n,)
        Corners of the box.

    Returns
    -------
    ndarray, shape (2^n, n)

    Examples
    --------
    >>> setbound.hinf.box_corners([0, 0], [1, 2]).tolist()
    [[0.0, 0.0], [1.0, 0.0], [0.0, 2.0], [1.0, 2.0]]
    """
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    n = lo.size
    if n > 24:
        raise DimensionError(f"lo: a box of dimension {n} has 2^{n} corners; at most 24 dimensions")
    return np.array([[hi[i] if (j >> i) & 1 else lo[i] for i in range(n)] for j in range(1 << n)])


# ---- ESO-D (CORA's name): Martinez, Loukkas, Meslem 2020, LTI case ----------------------------

#: CORA's γ grid of its H∞ designs: MATLAB's ``linspace(1, 50, 100)``.
CORA_GAMMA_GRID = np.linspace(1.0, 50.0, 100)
#: Upper bound of the length of a γ grid (each value is an SDP); ``SB_HINF_MAX_GAMMAS``.
MAX_GAMMAS = lib.SB_HINF_MAX_GAMMAS

#: What a γ of a grid search gave (the ``SB_LMI_*`` status of its feasibility problem).
_GAMMA_VERDICTS = {lib.SB_LMI_OPTIMAL: "feasible", lib.SB_LMI_INFEASIBLE: "infeasible",
                   lib.SB_LMI_MAX_ITERATIONS: "not solved (iteration limit)"}


@dataclass
class EsoDDesign(EllipsoidalSMDesign):
    """The ESO-D design of Martinez, Loukkas, Meslem (2020) (CORA's ``ESO-D``), made by :func:`design_eso_d`.

    An :class:`EllipsoidalSMDesign` (so :class:`EllipsoidalSMObserver` runs it): ``passes[0]`` is
    step (a) (``Q_input = I``), ``passes[1]`` step (c) (``Q_input = V⁻¹``); no log-det refinement
    (``Q_refined = Q_input``). The attributes below are the ESO-D extras.

    Parameters
    ----------
    plant, L, P, Q_input, Q_refined, V, e_inf, gamma, g, lambda_, lambda_input, lambda_refined, cbar, wtw, lambda_max_P, design_time, passes : object
        As :class:`EllipsoidalSMDesign` (``V``: step (b)'s ``V``; ``lambda_input = lambda_refined =
        lambda_ = λ_min(V⁻¹, P)``).
    gamma_trials : list of list of (float, str)
        The γ values searches (a) and (c) tried, in grid order, each with its verdict:
        ``"feasible"`` (the last one), ``"infeasible"`` (certificate), ``"not solved (iteration
        limit)"`` or ``"not solved (numerical trouble)"``.
    lyapunov_shift : float
        ``δ`` of step (b): 0 when ``V`` solves the Lyapunov equation, ``> 0`` when that ``V`` was
        singular and the right-hand side became ``E W Eᵀ + δI``.
    """
    gamma_trials: list = field(default_factory=list)
    lyapunov_shift: float = 0.0


def _design_eso_d(plant, wbar, W, gammas) -> EsoDDesign:
    plant = as_plant(plant)
    n, nu, ny, nd, nv = plant.nx, plant.nu, plant.ny, plant.nd, plant.nv
    m = nd + nv
    wbar = np.ones(m) if wbar is None else as_f64(wbar, "wbar", shape=(m,))
    Wa = None if W is None else as_f64(W, "W", shape=(m, m))
    g = None
    if gammas is not None:
        g = as_f64(gammas, "gammas", ndim=1)
        if g.size == 0 or g.size > MAX_GAMMAS:
            raise InvalidArgumentError(f"gammas: expected 1 .. {MAX_GAMMAS} values (each is an SDP), got {g.size}")
    h = ffi.new("sb_hinf_design**")
    check(lib.sb_eso_d_design_create(n, nu, ny, nd, nv, dptr(plant.A), dptr(plant.B), dptr(plant.C), dptr(plant.F),
                                     dptr(plant.Z), dptr(wbar), dptr(Wa) if Wa is not None else ffi.NULL,
                                     0 if g is None else g.size, dptr(g) if g is not None else ffi.NULL, h))
    handle = ffi.gc(h[0], lib.sb_hinf_design_free)
    P, L, Qi, Qr, V, e, s = (np.empty((n, n)), np.empty((1, n, ny)), np.empty((n, n)), np.empty((n, n)),
                             np.empty((n, n)), np.empty(n), np.empty(9))
    check(lib.sb_hinf_design_get(handle, dptr(P), dptr(L), dptr(Qi), dptr(Qr), dptr(V), dptr(e), dptr(s)))
    ps = []
    for k in range(2):
        pP, pL, pQi, pQr, ss = np.empty((n, n)), np.empty((1, n, ny)), np.empty((n, n)), np.empty((n, n)), np.empty(7)
        check(lib.sb_hinf_design_pass(handle, k, dptr(pP), dptr(pL), dptr(pQi), dptr(pQr), dptr(ss)))
        ps.append(DesignPass(pP, pL[0], pQi, pQr, ss[0], ss[1], ss[2], ss[3], ss[4], ss[5], bool(ss[6])))
    trials = []
    for search in range(2):
        cnt = ffi.new("int*", 0)
        check(lib.sb_hinf_design_gammas(handle, search, cnt, ffi.NULL, ffi.NULL))
        gv, st = np.empty(cnt[0]), ffi.new("int[]", max(cnt[0], 1))
        check(lib.sb_hinf_design_gammas(handle, search, cnt, dptr(gv), st))
        trials.append([(float(gv[i]), _GAMMA_VERDICTS.get(st[i], "not solved (numerical trouble)"))
                       for i in range(cnt[0])])
    shift = ffi.new("double*")
    check(lib.sb_eso_d_design_lyapunov_shift(handle, shift))
    d = EsoDDesign(plant, L[0], P, Qi, Qr, V, e, s[0], s[1], s[2], s[3], s[4], s[5], s[6], s[7], s[8], ps, handle,
                   trials, shift[0])
    return remember_call(d, _design_eso_d, plant, wbar, W, gammas)


def design_eso_d(plant, wbar=None, *, W=None, gammas=None) -> EsoDDesign:
    """The ESO-D design of Martinez, Loukkas, Meslem (2020) (LTI case, CORA's ``ESO-D``) for :class:`EllipsoidalSMObserver`.

    The online observer is the one of Loukkas' Chapter 2 (Methods › H∞ set-membership observers ›
    Online recursion); the offline design is the 2020 paper's Algorithm 1 as CORA codes it:

    (a) LMI (2.35) with ``Q = I`` at the first ``γ`` of the grid with a solution → ``P``, ``L``;
    (b) ``V ⪰ 0``, ``A_o V A_oᵀ − V ⪯ −E W Eᵀ`` (``A_o = A − LC``, ``E = [F, −LZ]``,
        ``W = diag(w̄²/3)``, CORA's ``I/3``), ``Q = V⁻¹``;
    (c) LMI (2.35) with that ``Q``, ``γ`` again from the grid's start; ``λ = λ_min(Q, P)``.

    Where CORA's result depends on its solver, this design makes a defined choice: step (b) takes
    the least-trace ``V`` (the Lyapunov equation's solution, the least feasible ``V``: CORA's
    feasibility problem has no objective and uses YALMIP's default solver), a ``γ`` counts as
    infeasible only with a certificate, and ``λ`` is the true smallest generalized eigenvalue
    (CORA's ``eigs`` returns the 6 largest, not the minimum when ``n > 6``). Every quantity the
    bound uses is certified in floating point, as for :func:`design_ellipsoidal_sm_observer`.

    Parameters
    ----------
    plant : Plant, LinearSystem or control.StateSpace
        The plant (converted by :func:`setbound.plant.as_plant`).
    wbar : array_like, optional
        Half-widths of the centred box of ``w = (d, v)`` (default: ones).
    W : array_like, optional
        Covariance of ``w`` in step (b) (default ``diag(w̄²/3)``).
    gammas : array_like, optional
        The ``γ`` grid of both searches, strictly increasing and positive, at most
        :data:`MAX_GAMMAS` values (default CORA's ``linspace(1, 50, 100)``).

    Returns
    -------
    EsoDDesign

    Raises
    ------
    setbound.errors.InfeasibleError
        LMI (2.35) is infeasible at every ``γ`` of the grid (step (a) or (c), named).
    setbound.errors.NumericalError
        Some ``γ`` was not solved (iteration limit, numerical trouble) and none was feasible.
    setbound.errors.NotDetectableError
        ``(A, C)`` is not detectable.

    Examples
    --------
    >>> plant = setbound.Plant([[0.9, 0.2], [-0.2, 0.8]], [[1.0, 0.0]], B=[[0.0], [1.0]],
    ...                        Fd=0.05 * np.eye(2), Z=[[0.1]])
    >>> design = setbound.hinf.design_eso_d(plant)
    >>> bool(0 < design.lambda_ <= 1), design.gamma_trials[0][-1][1]
    (True, 'feasible')
    >>> obs = setbound.hinf.EllipsoidalSMObserver(design, setbound.Box([-1, -1], [1, 1]))
    >>> traj = obs.run(np.zeros((5, 1)), np.zeros((5, 1)))
    >>> bool(traj.in_bounds(np.zeros((5, 2))).all())
    True
    """
    if isinstance(plant, LpvPlant):
        raise InvalidArgumentError("plant: ESO-D is designed here for LTI plants (the LPV case of the 2020 paper is "
                                   "not implemented); use design_ellipsoidal_sm_observer_lpv for an LpvPlant")
    return _design_eso_d(plant, wbar, W, gammas)


class _Observer(ReadingChecks, StateMixin):
    _lpv = False
    #: row k of a trajectory used y_0 … y_{k−1} only (Trajectory.filter)
    is_filter = False
    _state_prefix = "sb_hinf_observer"
    _state_handle_attr = "_h"
    _check_handle_attr = "_h"
    _last_check_fn = lib.sb_hinf_observer_last_check

    def _reading_ny(self) -> int:
        return self.ny

    def __init__(self, design: EllipsoidalSMDesign, xhat0, mu0: float | None = None, *,
                 on_inconsistency: str = "flag", reset_set=None):
        as_choice(on_inconsistency, "on_inconsistency", POLICIES)  # named before any other argument
        if not isinstance(design, EllipsoidalSMDesign):
            raise InvalidArgumentError("design: expected an EllipsoidalSMDesign")
        from .interval import Box as _Box
        from .sets import Ellipsoid as _Ell, Zonotope as _Zono, as_box

        if isinstance(xhat0, (_Box, _Zono, _Ell)):  # an initial set: x̂0 its hull's centre, μ0 from the hull
            hull = as_box(xhat0, "xhat0")
            lo, hi = np.asarray(hull.lo, dtype=float), np.asarray(hull.hi, dtype=float)
            xhat0 = 0.5 * (lo + hi)
            if mu0 is None:  # e0 = x0 − x̂0 lies in the centred box of the hull's half-widths
                mu0 = mu0_from_box(design, lo - xhat0, hi - xhat0)
        elif mu0 is None:
            raise InvalidArgumentError("mu0: give mu0 with a point xhat0, or an initial set (Box, Zonotope, "
                                       "Ellipsoid) as xhat0")
        if isinstance(design.plant, LpvPlant) != self._lpv:
            raise InvalidArgumentError("design: " + ("an LPV design needs LPVEllipsoidalSMObserver" if not self._lpv
                                                     else "LPVEllipsoidalSMObserver needs an LPV design"))
        self.design = design
        p = self.plant = design.plant  # the model (its dt times the results)
        self.nx, self.nu, self.ny = p.nx, p.nu, p.ny
        self.n_rho = p.n_rho if self._lpv else 0
        x0 = as_f64(xhat0, "xhat0", shape=(self.nx,))
        h = ffi.new("sb_hinf_observer**")
        check(lib.sb_hinf_observer_create(design._handle, dptr(x0), as_float(mu0, "mu0"), h))
        self._h = ffi.gc(h[0], lib.sb_hinf_observer_free)
        #: what a step does with an impossible reading (:mod:`setbound.measurement`)
        self.on_inconsistency = _set_box_policy(lib.sb_hinf_observer_set_inconsistency_policy, self._h,
                                               on_inconsistency, reset_set, self.nx)
        self._init_checks()
        self._c, self._lo, self._hi, self._mu = np.empty(self.nx), np.empty(self.nx), np.empty(self.nx), ffi.new("double*")
        check(lib.sb_hinf_observer_current(self._h, dptr(self._c), dptr(self._lo), dptr(self._hi), self._mu, ffi.NULL))

    def _after_restore(self) -> None:
        check(lib.sb_hinf_observer_current(self._h, dptr(self._c), dptr(self._lo), dptr(self._hi), self._mu, ffi.NULL))

    @property
    def center(self) -> np.ndarray:
        return self._c.copy()

    @property
    def mu(self) -> float:
        return self._mu[0]

    @property
    def box(self) -> Box:
        return Box(self._lo, self._hi)

    @property
    def steps(self) -> int:
        s = ffi.new("int*")
        check(lib.sb_hinf_observer_current(self._h, ffi.NULL, ffi.NULL, ffi.NULL, ffi.NULL, s))
        return s[0]

    def _step(self, y, u, rho) -> Box:
        y = as_f64(np.atleast_1d(measurement_or_missing(y, self.ny)), "y", shape=(self.ny,))
        u = as_f64(np.zeros(0) if u is None else np.atleast_1d(u), "u", shape=(self.nu,))
        r = ffi.NULL
        if self._lpv:
            ra = as_f64(np.atleast_1d(rho), "rho", shape=(self.n_rho,))
            r = dptr(ra)
        check(lib.sb_hinf_observer_step(self._h, dptr(y), dptr(u), r, dptr(self._c), dptr(self._lo), dptr(self._hi),
                                        self._mu))
        return Box(self._lo, self._hi)

    def _run(self, y, u, rho) -> Trajectory:
        y = np.asarray(y, dtype=np.float64)
        if y.ndim == 1 and self.ny == 1:
            y = y.reshape(-1, 1)
        y = as_f64(y, "y", shape=(None, self.ny))
        refuse_infinite(y)  # NaN: a missing reading
        T = y.shape[0]
        if u is None:
            if self.nu:
                raise InvalidArgumentError(f"u: the plant has {self.nu} inputs; give u with shape ({T}, {self.nu})")
            u = np.zeros((T, 0))
        u = np.asarray(u, dtype=np.float64)
        if u.ndim == 1 and self.nu == 1:
            u = u.reshape(-1, 1)
        u = as_f64(u, "u", shape=(T, self.nu))
        if self._lpv:
            if rho is None:
                raise InvalidArgumentError(f"rho: the LPV observer needs the scheduling signal, shape ({T}, {self.n_rho})")
            rho = np.asarray(rho, dtype=np.float64)
            if rho.ndim == 1 and self.n_rho == 1:
                rho = rho.reshape(-1, 1)
            rho = as_f64(rho, "rho", shape=(T, self.n_rho))
        # The library's convention (python/setbound/trajectory.py): N rows, row k = x_k having used
        # y_0 … y_{k−1}; the observer itself advances to x_N (current()). Row k's status and
        # margin say what the step did with y_k.
        C, Lo, Hi, M = np.empty((T, self.nx)), np.empty((T, self.nx)), np.empty((T, self.nx)), np.empty(T)
        status, margin = np.empty((T, self.ny), dtype=np.int8), np.empty((T, self.ny))
        resets = np.zeros(T, dtype=bool)
        for k in range(T):
            C[k], Lo[k], Hi[k], M[k] = self._c, self._lo, self._hi, self._mu[0]
            self._step(y[k], u[k], rho[k] if self._lpv else None)
            resets[k] = self._check_into(status[k], margin[k])
        traj = Trajectory(C, Lo, Hi, sets=[Box(Lo[k], Hi[k]) for k in range(T)], guaranteed=True, status=status,
                          margin=margin, resets=resets)
        traj.mu = M
        return traj


@reconstructible
class EllipsoidalSMObserver(_Observer):
    """The ellipsoidal-invariant-set observer of [Loukkas2018] Chapter 2 (Methods › H∞ set-membership observers › Online recursion).

    ``x̂⁺ = (A − LC)x̂ + Bu + Ly``, ``μ⁺ = (1 − λ)μ + λ``; the state is in the box ``x̂ ± ē∞√μ``.
    ``step(y_k, u_k)`` returns the box of ``x_{k+1}``; ``run(y, u)`` returns a Trajectory with N
    rows (row k = ``x_k`` having used ``y_0 … y_{k−1}``; row 0 = the initial box) and ``traj.mu``.

    Real data (:mod:`setbound.measurement`): NaN entries of ``y`` are missing outputs; each present
    reading is tested against the support of the observer's ellipsoid in ``±C_i`` plus its noise
    bound. A step without some output is made in interval arithmetic (the box narrowed by the
    outputs present, then ``A[x] + Bu + F[d]``) and the recursion restarts from the predicted box
    (x̂ its centre, μ from its corners).

    Parameters
    ----------
    design : EllipsoidalSMDesign
        The design (Algorithm 2 or 3).
    xhat0 : array_like or Box, Zonotope, Ellipsoid
        The initial estimate ``x̂_0``; or an initial set, then ``x̂_0`` is its hull's centre and
        ``μ_0`` comes from the hull (:func:`mu0_from_box`).
    mu0 : float, optional
        Initial scaling ``μ_0 >= 1`` (with a point ``xhat0``; see :func:`mu0_from_ball`).
    on_inconsistency : {"flag", "raise", "reset"}, optional
        What a reading outside the predicted output set does (:mod:`setbound.measurement`):
        skipped and flagged (default), an :class:`~setbound.errors.InconsistentMeasurementError`,
        or a restart from ``reset_set``.
    reset_set : optional
        The restart set of ``on_inconsistency="reset"`` (default: the initial set).

    Examples
    --------
    >>> plant = setbound.Plant([[0.2, 0.2], [0.0, 0.5]], [[1.0, 0.0]], Fd=[[0.0], [0.1]], Z=[[0.1]])
    >>> obs = setbound.hinf.EllipsoidalSMObserver(setbound.hinf.design_ellipsoidal_sm_observer(plant),
    ...                                          setbound.Box([-1, -1], [1, 1]))
    >>> traj = obs.run(np.zeros((5, 1)))
    >>> bool(traj.in_bounds(np.zeros((5, 2))).all()), bool(traj.mu[-1] < traj.mu[0])
    (True, True)
    """

    def step(self, y, u=None) -> Box:
        """Use ``y_k`` and ``u_k``, advance the observer and return the box of ``x_{k+1}`` (unchanged on error).

        Readings outside the predicted output set follow ``on_inconsistency`` (``last_check`` says what
        the step did with each).

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
        return self._step(y, u, None)

    @run_from_initial_set
    def run(self, y, u=None) -> Trajectory:
        """Run over a record from the initial set; row ``k`` bounds ``x_k`` (row 0: the initial box).

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
        return self._run(y, u, None)


@reconstructible
class LPVEllipsoidalSMObserver(_Observer):
    """The LPV observer of [Loukkas2018] Chapter 3, with the scheduling vector ``ρ_k`` given per step (Methods › H∞ set-membership observers › LPV systems).

    Missing and impossible readings as :class:`EllipsoidalSMObserver` (the interval step uses
    ``A(ρ_k)``, ``B(ρ_k)``, ``F(ρ_k)`` widened by the rounding of their combination).

    Parameters
    ----------
    design : EllipsoidalSMDesign
        The design (Algorithm 2 or 3).
    xhat0 : array_like or Box, Zonotope, Ellipsoid
        The initial estimate ``x̂_0``; or an initial set, then ``x̂_0`` is its hull's centre and
        ``μ_0`` comes from the hull (:func:`mu0_from_box`).
    mu0 : float, optional
        Initial scaling ``μ_0 >= 1`` (with a point ``xhat0``; see :func:`mu0_from_ball`).
    on_inconsistency : {"flag", "raise", "reset"}, optional
        What a reading outside the predicted output set does (:mod:`setbound.measurement`):
        skipped and flagged (default), an :class:`~setbound.errors.InconsistentMeasurementError`,
        or a restart from ``reset_set``.
    reset_set : optional
        The restart set of ``on_inconsistency="reset"`` (default: the initial set).
    """
    _lpv = True

    def step(self, y, u=None, rho=None) -> Box:
        """Use ``y_k``, ``u_k`` and ``ρ_k``, advance the observer and return the box of ``x_{k+1}``.

        Parameters
        ----------
        y : array_like, shape (n_y,), or None
            The measurement ``y_k`` (None or NaN entries: missing outputs).
        u : array_like, shape (n_u,), optional
            The input ``u_k``.
        rho : array_like, shape (n_ρ,)
            Scheduling vector ``ρ_k`` (in the polytope of the plant).

        Returns
        -------
        Box
        """
        if rho is None:
            raise InvalidArgumentError("rho: the LPV observer needs the scheduling value of this step")
        return self._step(y, u, rho)

    @run_from_initial_set
    def run(self, y, u=None, rho=None) -> Trajectory:
        """Run over a record and its scheduling signal from the initial set; row ``k`` bounds ``x_k``.

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

        rho : array_like, shape (N, n_ρ)
            Scheduling signal.

        Returns
        -------
        Trajectory
            Row ``k`` is about ``x_k``; ``status``, ``margin`` and ``resets`` say what each step did
            with each reading.
        """
        return self._run(y, u, rho)


# ---- CORA's names (setbound.cora.observe; issue 22) ---------------------------------------------

def _thesis_box_runner(model, name, allowed, design_fn, options):
    """The runner shared by ESO-C and ESO-D: the thesis's EllipsoidalSMObserver with W's and V's
    generators (|w_i| <= 1) as the plant's disturbances, ``design_fn(plant, **options)`` as its
    design, and the interval hull of R0 as the initial box (guaranteed)."""
    from .ellipsoidal import _cora_noise_generators

    s = model.system
    unknown = set(options) - allowed
    if unknown:
        raise InvalidArgumentError(f"{sorted(unknown)[0]}: not an option of {name}")
    if np.any(s.D != 0.0):
        raise InvalidArgumentError(f"model: an output offset (D u) is not supported by {name}")
    Gw, Gv = _cora_noise_generators(s)
    plant = Plant(s.A, s.C, B=s.B, Fd=Gw if Gw.shape[1] else np.zeros((s.nx, 1)),
                  Z=Gv if Gv.shape[1] else np.zeros((s.ny, 1)))
    design = design_fn(plant, **options)
    c = np.asarray(model.x0.center)
    r = np.abs(np.asarray(model.x0.generators)).sum(axis=1)
    obs = EllipsoidalSMObserver(design, Box(c - r, c + r))

    def run():
        t = obs.run(model.y, model.u)
        return t.lower, t.upper, []
    return run


def _eso_c_runner(model, *, convention, gain, **options):
    """ESO-C = Loukkas, Martinez, Meslem, IFAC 2017 (Alg. 1): the thesis's Chapter 2 observer
    (design_ellipsoidal_sm_observer + EllipsoidalSMObserver). CORA's own ESO-C cannot run (its gain
    design reads an undefined variable; the unit tests comment it out as badly conditioned), so
    there is no CORA convention to reproduce. Options: those of design_ellipsoidal_sm_observer
    (lambda_route, passes)."""
    if convention == "cora":
        raise InvalidArgumentError("convention: CORA's ESO-C cannot run (priv_observe_gain_ESO_C reads an undefined "
                                   "variable; its unit tests are commented out), so there is nothing to reproduce; "
                                   'use convention="setbound" (Loukkas\' observer, guaranteed)')
    return _thesis_box_runner(model, "ESO-C", {"lambda_route", "passes"}, design_ellipsoidal_sm_observer, options)


def _eso_d_runner(model, *, convention, gain, **options):
    """ESO-D = Martinez, Loukkas, Meslem, Int. J. Control 2020 (Alg. 1, LTI case): design_eso_d +
    the thesis's EllipsoidalSMObserver, with W's and V's generators (|w_i| <= 1) and the initial
    box of R0 (guaranteed). CORA's own result depends on YALMIP's default solver (a feasibility
    problem with no objective), so the cora convention is refused. Options: gammas."""
    if convention == "cora":
        raise InvalidArgumentError("convention: CORA's ESO-D cannot be reproduced: its design solves feasibility "
                                   "problems with no objective (step (b) with YALMIP's default solver, not "
                                   "options.solver), so its gain and hull are whatever that solver stops at; "
                                   'use convention="setbound" (the same algorithm with defined choices, guaranteed)')
    return _thesis_box_runner(model, "ESO-D", {"gammas"}, design_eso_d, options)


def _register_cora_names():
    from .cora import register_algorithm
    register_algorithm("ESO-C", _eso_c_runner,
                       summary="invariant-ellipsoid set-membership observer [Loukkas 2017] = the thesis's "
                               "EllipsoidalSMObserver (CORA's own ESO-C cannot run)")
    register_algorithm("ESO-D", _eso_d_runner,
                       summary="H-infinity set-membership observer [Martinez 2020], CORA's gamma-grid design "
                               "(design_eso_d) with the thesis's EllipsoidalSMObserver")


_register_cora_names()
