"""Simulation of the true system: the data that the estimators are run on in the examples,
the demo and the containment tests.

``simulate(system, x0, N, disturbance=..., rng=...)`` returns the true states ``x`` (N × n_x),
the measurements ``y`` (N × n_y) and the disturbances ``omega`` (N × n_ω), with
``x_{k+1} = A_k x_k + B u_k + E ω_k`` and ``y_k = C x_k + D u_k + F ω_k`` (row ``k`` of every
array is time ``k``).

Disturbance kinds: ``"uniform"`` (each component uniform in [−1, 1]), ``"vertex"`` (each
component ±1 with equal probability: the worst case of the bounded-noise guarantee),
``"gaussian"`` (standard normal: *outside* the box assumption, for the Kalman contrast),
``"zero"``. With an interval ``A`` a matrix of ``[A]`` is drawn at each step (``A_choice``:
``"vertex"`` or ``"uniform"``; ``"mid"`` keeps ``mid[A]``).

A :class:`~setbound.DescriptorSystem` ``E x⁺ = A x + B u + D w`` with singular ``E`` is
simulated through its index-1 decomposition: with ``E = U diag(Σ, 0) Vᵀ`` and ``x = V ξ``,
the algebraic rows give ``ξ₂(k)`` from ``ξ₁(k)``, ``u_k`` and ``w_k``; the others give
``ξ₁(k+1)``. Higher-index pencils are rejected.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._validate import as_bool, as_choice, as_int, check_memory
from .errors import DimensionError, InvalidArgumentError
from .sets import Ellipsoid, Zonotope
from .system import DescriptorSystem, LinearSystem, as_system

_KINDS = ("uniform", "vertex", "gaussian", "zero")


@dataclass(frozen=True)
class Simulation:
    """A simulated run: row ``k`` is time ``k``.

    Parameters
    ----------
    x : ndarray, shape (N, n_x)
        True states.
    y : ndarray, shape (N, n_y)
        Measurements.
    omega : ndarray, shape (N, n_ω)
        Disturbances (in the unit box).
    u : ndarray, shape (N, n_u)
        Inputs.
    """
    x: np.ndarray  # (N, n_x) true states
    y: np.ndarray  # (N, n_y) measurements
    omega: np.ndarray  # (N, n_ω) disturbances
    u: np.ndarray  # (N, n_u) inputs


#: Upper bound of the horizon ``N`` of :func:`simulate` (the loop runs in Python, a few µs per
#: step: 10^8 steps are minutes); the memory of the result is checked as well.
MAX_STEPS = 10**8


def _rng(rng) -> np.random.Generator:
    try:
        return np.random.default_rng(rng)
    except (TypeError, ValueError) as e:
        raise InvalidArgumentError(f"rng: expected None, a seed (an integer >= 0) or a numpy Generator, got {rng!r} "
                                   f"({e})") from None


def disturbances(kind: str, N: int, n: int, rng: np.random.Generator) -> np.ndarray:
    """N × n disturbances of the given kind (see the module docstring); ``N``, ``n`` integers
    >= 0 whose N·n·8 bytes must fit in half the machine's memory.

    Parameters
    ----------
    kind : {"uniform", "vertex", "gaussian", "zero"}
        Profile.
    N, n : int
        Steps and components.
    rng : numpy.random.Generator
        Random source.

    Returns
    -------
    ndarray, shape (N, n)

    Examples
    --------
    >>> w = setbound.simulation.disturbances("vertex", 4, 2, np.random.default_rng(0))
    >>> bool(np.all(np.abs(w) == 1))
    True
    """
    kind = as_choice(kind, "kind", _KINDS)
    N, n = as_int(N, "N", lo=0, hi=MAX_STEPS), as_int(n, "n", lo=0)
    check_memory("N", N, 8.0 * N * n)
    if kind == "uniform":
        return rng.uniform(-1.0, 1.0, size=(N, n))
    if kind == "vertex":
        return rng.choice([-1.0, 1.0], size=(N, n))
    if kind == "gaussian":
        return rng.standard_normal(size=(N, n))
    if kind == "zero":
        return np.zeros((N, n))
    raise AssertionError(kind)  # unreachable: as_choice above


def sample_in(x0, rng: np.random.Generator, *, boundary: bool = False) -> np.ndarray:
    """A point of the set ``x0`` (Ellipsoid, Zonotope or Box; an array is returned as it is):
    uniform inside, or on the boundary with ``boundary=True`` (a bool; a box: a corner).

    Parameters
    ----------
    x0 : Ellipsoid, Zonotope, Box or array_like
        The set (or a point).
    rng : numpy.random.Generator
        Random source.
    boundary : bool, optional
        Draw on the boundary.

    Returns
    -------
    ndarray

    Examples
    --------
    >>> x = setbound.simulation.sample_in(setbound.Box([0, 0], [1, 1]), np.random.default_rng(0))
    >>> bool(setbound.Box([0, 0], [1, 1]).contains(x))
    True
    """
    from .interval import Box

    boundary = as_bool(boundary, "boundary")
    if isinstance(x0, Box):
        lo, hi = np.asarray(x0.lo, dtype=float), np.asarray(x0.hi, dtype=float)
        x0 = Zonotope((lo + hi) / 2, np.diag((hi - lo) / 2))
    if isinstance(x0, Ellipsoid):
        n = x0.n
        d = rng.standard_normal(n)
        d /= np.linalg.norm(d)
        r = 1.0 if boundary else rng.uniform() ** (1.0 / n)
        # x = c + sqrt(ρ) L⁻ᵀ d with P = L Lᵀ: (x − c)ᵀ P (x − c) = ρ |d|² r².
        L = np.linalg.cholesky(x0.P)
        return x0.center + r * np.sqrt(x0.rho) * np.linalg.solve(L.T, d) * (1 - 1e-12)
    if isinstance(x0, Zonotope):
        s = rng.choice([-1.0, 1.0], size=x0.m) if boundary else rng.uniform(-1.0, 1.0, size=x0.m)
        return x0.center + x0.generators @ s
    return np.asarray(x0, dtype=float)


def _inputs(u, N: int, nu: int) -> np.ndarray:
    if nu == 0:
        if u is not None and np.size(u) != 0:
            raise DimensionError("u: the system has no input")
        return np.zeros((N, 0))
    if u is None:
        raise InvalidArgumentError(f"u: the system has {nu} inputs; give an (N, {nu}) array")
    u = np.asarray(u, dtype=float)
    if u.shape != (N, nu):
        raise DimensionError(f"u: expected shape ({N}, {nu}), got {u.shape}")
    return u


def simulate(system, x0, N: int, *, disturbance: str = "uniform", rng=None, u=None,
             A_choice: str = "vertex", boundary_start: bool | None = None) -> Simulation:
    """Simulates ``N`` steps of ``system`` from a true initial state drawn from ``x0`` (a set or a
    point); see the module docstring. ``boundary_start`` (a bool) defaults to True for vertex
    noise. ``N``: an integer in [1, ``MAX_STEPS``] (10^8), refused before anything is drawn
    when the arrays of the result (8 bytes per number) exceed half the machine's memory.

    Parameters
    ----------
    system : LinearSystem or DescriptorSystem
        The model.
    x0 : set or array_like
        Initial set (the true initial state is drawn from it) or the state itself.
    N : int
        Number of steps.
    disturbance : {"uniform", "vertex", "gaussian", "zero"}, optional
        Disturbance profile.
    rng : numpy.random.Generator or int, optional
        Random source or seed.
    u : array_like, shape (N, n_u), optional
        Inputs.
    A_choice : str, optional
        How an interval ``A`` is drawn at each step (default ``"vertex"``).
    boundary_start : bool, optional
        Start on the boundary of ``x0``.

    Returns
    -------
    Simulation

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.9, 0.2], [0.0, 0.7]], C=[[1.0, 0.0]],
    ...                             E=[[0.1, 0.0], [0.0, 0.0]], F=[[0.0, 0.05]])
    >>> sim = setbound.simulation.simulate(sys, setbound.Box([-1, -1], [1, 1]), 10, rng=1)
    >>> sim.x.shape, sim.y.shape
    ((10, 2), (10, 1))
    """
    N = as_int(N, "N", lo=1, hi=MAX_STEPS)
    disturbance = as_choice(disturbance, "disturbance", _KINDS)
    A_choice = as_choice(A_choice, "A_choice", ("vertex", "uniform", "mid"))
    system = as_system(system)
    rng = _rng(rng)
    if boundary_start is None:
        boundary_start = disturbance == "vertex"
    boundary_start = as_bool(boundary_start, "boundary_start")
    if isinstance(system, (LinearSystem, DescriptorSystem)):
        per_step = system.nx + system.ny + system.nw + system.nu
        check_memory("N", N, 8.0 * N * (2 * per_step + 1))  # the result and the draws
    if isinstance(system, DescriptorSystem):
        return _simulate_descriptor(system, x0, int(N), disturbance, rng, u, boundary_start)
    if not isinstance(system, LinearSystem):
        raise InvalidArgumentError(f"system: expected a LinearSystem or DescriptorSystem, got {type(system).__name__}")
    s = system
    U = _inputs(u, N, s.nu)
    W = disturbances(disturbance, N, s.nw, rng)
    x = np.empty((N, s.nx))
    y = np.empty((N, s.ny))
    x[0] = sample_in(x0, rng, boundary=boundary_start)
    for k in range(N):
        y[k] = s.C @ x[k] + s.D @ U[k] + s.F @ W[k]
        if k + 1 < N:
            if s.uncertain_A and A_choice != "mid":
                if A_choice == "vertex":
                    delta = rng.choice([-1.0, 1.0], size=s.A.shape)
                elif A_choice == "uniform":
                    delta = rng.uniform(-1.0, 1.0, size=s.A.shape)
                else:
                    raise InvalidArgumentError(f"A_choice: expected 'vertex', 'uniform' or 'mid', got {A_choice!r}")
                Ak = s.A + delta * s.A_rad
            else:
                Ak = s.A
            x[k + 1] = Ak @ x[k] + s.B @ U[k] + s.E @ W[k]
    return Simulation(x, y, W, U)


def _simulate_descriptor(s: DescriptorSystem, x0, N, kind, rng, u, boundary_start) -> Simulation:
    U = _inputs(u, N, s.nu)
    W = disturbances(kind, N, s.nw, rng)
    Uo, sv, Vt = np.linalg.svd(s.E)
    r = int(np.sum(sv > 1e-12 * max(1.0, sv.max())))
    V = Vt.T
    At, Bt, Dt = Uo.T @ s.A @ V, Uo.T @ s.B, Uo.T @ s.D
    A11, A12, A21, A22 = At[:r, :r], At[:r, r:], At[r:, :r], At[r:, r:]
    if r < s.nx:
        if np.linalg.matrix_rank(A22) < s.nx - r:
            raise InvalidArgumentError("system: only index-1 descriptor systems can be simulated "
                                       "(the algebraic part of the pencil is singular)")
        A22inv = np.linalg.inv(A22)

    def full_state(xi1, k):
        if r == s.nx:
            return V @ xi1
        xi2 = -A22inv @ (A21 @ xi1 + Bt[r:] @ U[k] + Dt[r:] @ W[k])
        return V @ np.concatenate([xi1, xi2])

    # Initial state: the differential part from a point of x0; the algebraic part then follows
    # from w_0. Redraw (point and w_0) until the consistent x_0 lies in x0 when x0 is a set.
    for _attempt in range(10000):
        p = sample_in(x0, rng, boundary=False)
        xi1 = (V.T @ p)[:r]
        x_first = full_state(xi1, 0)
        if not isinstance(x0, (Ellipsoid, Zonotope)) or bool(np.all(x0.contains(x_first[None, :]))):
            break
        W[0] = disturbances(kind, 1, s.nw, rng)[0]
    else:
        raise InvalidArgumentError("x0: no state consistent with the algebraic equations was found in the "
                                   "initial set (10000 draws)")
    x = np.empty((N, s.nx))
    y = np.empty((N, s.ny))
    for k in range(N):
        x[k] = full_state(xi1, k)
        y[k] = s.C @ x[k] + s.F @ W[k]
        if k + 1 < N:
            xi2 = (V.T @ x[k])[r:]
            xi1 = np.linalg.solve(np.diag(sv[:r]), A11 @ xi1 + A12 @ xi2 + Bt[:r] @ U[k] + Dt[:r] @ W[k])
    return Simulation(x, y, W, U)
