"""Point estimators of CORA's catalogue: the Rauch–Tung–Striebel smoother (NOT guaranteed).

:func:`rts_smooth` is the textbook fixed-interval smoother (Rauch, Tung, Striebel, *Maximum
likelihood estimates of linear dynamic systems*, AIAA J. 3(8), 1965; the form of Giron-Sierra,
*Digital Signal Processing with Matlab Examples*, Vol. 3, Springer 2017, which CORA cites): a
forward Kalman filter (the library's :class:`~setbound.ellipsoidal.KalmanFilter` step), then a
backward pass ``J_k = P_k Aᵀ M_{k+1}⁺``, ``x^s_k = x̂_k + J_k (x^s_{k+1} − x̄_{k+1})``. Its estimates
are points with Gaussian covariances, never sets: no containment is claimed.

CORA's names ``"Rauch-Tung-Striebel"`` and ``"RTS"`` are registered with :mod:`setbound.cora` on
import; that runner reads the noise from CORA's sets as CORA's file intends: ``x₀`` the centre of
``R0``, ``P₀ = 0.33² G_R0 G_R0ᵀ``, ``Σ_w = 0.33² G_W G_Wᵀ``, ``Σ_v = 0.33² G_V G_Vᵀ`` (generators
read as three standard deviations), and returns ``lower = upper = x^s_k``. CORA's own file cannot
run (undefined names); the deviations from it are listed in ``include/setbound/estimators/point/
rts_smoother.hpp``: the per-step ``M_{k+1}`` (CORA uses the last one for every step), the last row
stored, ``G Gᵀ`` for CORA's ``(G G)ᵀ``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._native import as_f64, check, dptr, ffi, lib
from ._validate import as_bool
from .errors import InvalidArgumentError
from .system import LinearSystem, as_system, run_inputs

__all__ = ["RtsResult", "rts_smooth"]


@dataclass(frozen=True)
class RtsResult:
    """The result of :func:`rts_smooth`; row ``k`` is about ``x_k``.

    Attributes
    ----------
    smoothed : ndarray, shape (N, n_x)
        The smoothed estimates ``x^s_k`` (from every measurement of the record).
    smoothed_cov : ndarray, shape (N, n_x, n_x)
        Their error covariances ``P^s_k``.
    filtered : ndarray, shape (N, n_x)
        The forward Kalman filter's estimates ``x̂_k`` (from the measurements up to ``k``).
    filtered_cov : ndarray, shape (N, n_x, n_x)
        Their error covariances ``P_k``.
    """
    smoothed: np.ndarray
    smoothed_cov: np.ndarray
    filtered: np.ndarray
    filtered_cov: np.ndarray


def rts_smooth(system: LinearSystem, x0, P0, Sigma_w, Sigma_v, y, u=None, *,
               use_first_measurement: bool = True) -> RtsResult:
    """Rauch–Tung–Striebel smoothing of a record (point estimates, not guaranteed sets).

    Model ``x_{k+1} = A x_k + B u_k + w_k``, ``y_k = C x_k + D u_k + v_k`` with ``w_k ~ N(0, Σ_w)``,
    ``v_k ~ N(0, Σ_v)`` independent and white and ``x_0 ~ N(x0, P0)``; ``A, B, C, D`` are the
    system's (its ``E``, ``F`` are not used: the noise is given by its covariances).

    Parameters
    ----------
    system : LinearSystem
        The model (a known ``A``).
    x0 : array_like, shape (n_x,)
        Mean of the initial state.
    P0 : array_like, shape (n_x, n_x)
        Covariance of the initial state (symmetric positive semidefinite).
    Sigma_w : array_like, shape (n_x, n_x)
        Process noise covariance (symmetric positive semidefinite).
    Sigma_v : array_like, shape (n_y, n_y)
        Measurement noise covariance (symmetric positive definite).
    y : array_like, shape (N, n_y)
        Measurements (NaN entries: missing outputs).
    u : array_like, shape (N, n_u), optional
        Known inputs.
    use_first_measurement : bool, optional
        ``True`` (default, the textbook): ``x0, P0`` is the prior of ``x_0`` and ``y_0`` corrects
        it. ``False``: CORA's indexing, the estimate of ``x_0`` is ``x0`` and ``y_0`` is not used.

    Returns
    -------
    RtsResult

    Raises
    ------
    DimensionError, NotFiniteError, NotSymmetricError, NotPositiveDefiniteError
        A bad argument (the message names it).

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[1.0]], C=[[1.0]], E=[[0.0]], F=[[0.0]])
    >>> r = setbound.point.rts_smooth(sys, [0.0], [[1.0]], [[0.1]], [[0.5]], [[1.0], [2.0], [1.5]])
    >>> r.smoothed.shape, bool(r.smoothed[-1, 0] == r.filtered[-1, 0])
    ((3, 1), True)
    >>> bool(np.trace(r.smoothed_cov[0]) <= np.trace(r.filtered_cov[0]))
    True
    """
    system = as_system(system)
    if not isinstance(system, LinearSystem):
        raise InvalidArgumentError(f"system: expected a setbound.LinearSystem, got {type(system).__name__}")
    if system.A_rad is not None and np.any(np.asarray(system.A_rad) != 0):
        raise InvalidArgumentError("system: the RTS smoother needs a known A (an interval A is not supported)")
    use_first_measurement = as_bool(use_first_measurement, "use_first_measurement")
    n, ny = system.nx, system.ny
    x0 = as_f64(x0, "x0", shape=(n,))
    P0 = as_f64(P0, "P0", shape=(n, n))
    Sigma_w = as_f64(Sigma_w, "Sigma_w", shape=(n, n))
    Sigma_v = as_f64(Sigma_v, "Sigma_v", shape=(ny, ny))
    y, u = run_inputs(system, y, u)
    N = y.shape[0]
    smoothed, filtered = np.empty((N, n)), np.empty((N, n))
    scov, fcov = np.empty((N, n, n)), np.empty((N, n, n))
    up = dptr(np.ascontiguousarray(u, dtype=np.float64)) if system.nu > 0 else ffi.NULL
    check(lib.sb_rts_smooth(system._handle, dptr(x0), dptr(P0), dptr(Sigma_w), dptr(Sigma_v), N, dptr(y), up,
                            1 if use_first_measurement else 0, dptr(smoothed), dptr(scov), dptr(filtered),
                            dptr(fcov)))
    return RtsResult(smoothed, scov, filtered, fcov)


# ---- CORA's names (setbound.cora.observe) -------------------------------------------------------

#: CORA's reading of a zonotope's generators as standard deviations: Σ = 0.33² G Gᵀ.
SIGMA_FACTOR = 0.33


def _rts_runner(model, *, convention, gain, **options):
    """RTS from CORA's sets (module docstring); ``convention="cora"`` uses CORA's time indexing
    (``y_0`` unused). Returns ``lower = upper = x^s_k`` and no sets."""
    if options:
        raise InvalidArgumentError(f"{next(iter(options))}: the Rauch-Tung-Striebel smoother takes no options")
    s = model.system
    f2 = SIGMA_FACTOR ** 2
    G0 = model.x0.generators
    x0, P0 = model.x0.center, f2 * G0 @ G0.T
    Sw, Sv = f2 * s.E @ s.E.T, f2 * s.F @ s.F.T
    first = convention == "setbound"

    def run():
        r = rts_smooth(s, x0, P0, Sw, Sv, model.y, model.u if s.nu > 0 else None, use_first_measurement=first)
        return r.smoothed, r.smoothed.copy(), []
    return run


def _register_cora_names():
    from .cora import register_algorithm
    for name in ("Rauch-Tung-Striebel", "RTS"):
        register_algorithm(name, _rts_runner,
                           summary="Rauch-Tung-Striebel smoother, point estimates, NOT guaranteed "
                                   "[Rauch, Tung & Striebel 1965] = point.rts_smooth")


_register_cora_names()
