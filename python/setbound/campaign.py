"""Guarantee campaigns: every guaranteed estimator on many random systems, containment checked
at every step (docs/reliability.md, "Guarantee campaigns").

A *case* is fully determined by ``(estimator, seed)``: :func:`random_case` draws the system
(n_x, stable or unstable, possibly ill-conditioned), the disturbance kind (uniform or vertex),
the initial set and the estimator's options from ``numpy.random.default_rng(seed)``;
:func:`run_case` designs the estimator, simulates the true system
(:func:`setbound.simulation.simulate`), runs the estimator and checks the true state against
the returned set at every step. A design the library refuses (``SetboundError``: not
detectable, LMI infeasible, ...) is counted as *design failed* with the library's message; it
is not a violation. A violation is a step whose true state is outside the set by more than
the documented allowance (:func:`ellipsoid_excess`, :func:`box_excess`,
:func:`zonotope_excess`, :func:`parallelotope_excess`); it is reported with its seed and a one-line
reproduction command (``python -m setbound.campaign --estimator NAME --seed SEED``). A step whose
membership test cannot decide is counted as *undecided* (``CaseResult.undecided``), never as
contained nor as a violation.

Command line: ``python -m setbound.campaign [--steps N] [--processes 2] [--json FILE]
[--estimator NAME ...] [--seed SEED] [--max-nx 8] [--scheduler ADDR | --scheduler-file PATH]``.
The cases run on the machinery of :mod:`setbound.studies` (Dask; ``--processes 1``: serially in
this process). A case that kills its worker process is reported as *crashed* with its
reproduction command and the campaign exits 1.
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import math
import os
import sys
import time
from dataclasses import dataclass, field

import numpy as np

from . import constrained_zonotopic, ellipsoidal, hinf, interval_observers, parallelotope, zonotopic
from ._validate import as_bool, as_float, as_int
from .errors import SetboundError
from .interval import Box, IntervalMatrix
from .plant import Plant
from .sets import ConstrainedZonotope, Ellipsoid, Zonotope
from .simulation import simulate
from .system import DescriptorSystem, LinearSystem

__all__ = ["ESTIMATORS", "TAU", "LOOSE", "Case", "CaseResult", "RandomSystem", "random_system", "random_case", "run_case",
           "run_campaign", "campaign_case", "format_table", "ellipsoid_excess", "box_excess", "zonotope_excess",
           "parallelotope_excess", "czono_excess",
           "simulation_error_bound", "main"]

#: Relative allowance of the containment checks: a point counts as contained when it lies in the
#: set scaled by ``1 + TAU`` about its centre (plus the simulation error box, see
#: :func:`simulation_error_bound`). It absorbs the evaluation of the membership test and the
#: rounding of the measurements ``y = C x + F ω`` (≈ 1e-16 |y|), which the estimators take as
#: exact; a wrong bound in an estimator shows up many orders of magnitude above it.
TAU = 1e-9

_U = np.finfo(float).eps / 2


def _gamma(k: int) -> float:
    return k * _U / (1 - k * _U)


def simulation_error_bound(A_abs, terms_abs, N: int, m: int | None = None) -> np.ndarray:
    """Componentwise bound ``δ_k`` on ``|x_k − x̂_k|``, where ``x̂_k`` is the floating-point
    simulation and ``x_k`` the exact trajectory of the same initial state and disturbances:
    ``δ_0 = 0``, ``δ_{k+1} = |A| δ_k + γ_m r_k`` with ``r_k = |A||x̂_k| + |E||ω_k| (+ |B||u_k|)``
    (``terms_abs``, N × n) the magnitudes summed by one simulation step and γ_m = m u/(1 − m u)
    the dot-product rounding factor (``m`` products summed per component; default n + 2 + the
    number of columns of ``E`` is the caller's to give). ``A_abs`` is ``|A|`` (for an interval
    or LPV matrix: an entrywise bound of ``|A_k|``).

    Parameters
    ----------
    A_abs : ndarray, shape (n, n)
        ``|A|`` (or an entrywise bound).
    terms_abs : ndarray, shape (N, n)
        Magnitudes summed by each simulation step.
    N : int
        Number of steps.
    m : int, optional
        Products summed per component.

    Returns
    -------
    ndarray, shape (N, n)
    """
    n = A_abs.shape[0]
    g = _gamma(m if m is not None else 2 * n + 2)
    r = g * np.asarray(terms_abs, float)
    d = np.zeros((N, n))
    with np.errstate(over="ignore", invalid="ignore"):
        for k in range(N - 1):
            d[k + 1] = (A_abs @ d[k] + r[k]) * (1 + 4 * _U)
    return d


def _stable_error_bound(A, r, N: int):
    """Tighter bound for a constant Schur-stable ``A`` (the |A| recursion grows when ρ(|A|) > 1):
    ``e_k = Σ_i A^i r_{k−1−i}``, so ``|e_k| ≤ S r̄_k + t ‖r̄_k‖∞ 1`` with ``S = Σ_{i<M} |A^i|``,
    ``r̄_k`` the running componentwise maximum of the local errors, and the tail
    ``t = q Σ_{i<M} ‖A^i‖∞ / (1 − q)``, ``q = ‖A^M‖∞ < 1`` (``‖A^{jM+i}‖ ≤ q^j ‖A^i‖``).
    Returns None when no ``M ≤ 2000`` gives ``q < 1/2``."""
    n = A.shape[0]
    S = np.zeros((n, n))
    Pk = np.eye(n)
    norms = 0.0
    for M in range(1, 2001):
        S += np.abs(Pk)
        norms += np.abs(Pk).sum(axis=1).max()
        Pk = Pk @ A
        q = np.abs(Pk).sum(axis=1).max()
        if q < 0.5:
            break
    else:
        return None
    t = q * norms / (1 - q) * (1 + 1e-6)
    rbar = np.maximum.accumulate(np.vstack([np.zeros((1, n)), r[: N - 1]]), axis=0)
    return (rbar @ S.T + t * rbar.max(axis=1, keepdims=True)) * (1 + 1e-6)


def ellipsoid_excess(P, c, rho, x, delta) -> float:
    """How far ``x`` is outside ``E(P, c, ρ)`` beyond the allowance, in units of the set's
    ``√ρ``: ``(√q − (1+TAU)√ρ − √(δᵀ|P|δ) − √e_q)/√ρ`` with ``q = (x−c)ᵀP(x−c)``, ``e_q`` the
    rounding bound ``γ_{n+2}|x−c|ᵀ|P||x−c|`` of that evaluation and ``√(δᵀ|P|δ)`` a bound on
    the P-norm of the simulation error. Positive means a violation.

    Parameters
    ----------
    P : ndarray, shape (n, n)
        Shape.
    c : ndarray, shape (n,)
        Centre.
    rho : float
        Level.
    x : ndarray, shape (n,)
        The true state.
    delta : ndarray, shape (n,)
        Bound of the simulation error (:func:`simulation_error_bound`).

    Returns
    -------
    float
    """
    d = np.asarray(x, float) - np.asarray(c, float)
    n = d.size
    q = float(d @ P @ d)
    ad = np.abs(d)
    Pabs = np.abs(P)
    eq = _gamma(n + 2) * float(ad @ Pabs @ ad)
    sd = math.sqrt(max(float(delta @ Pabs @ delta), 0.0))
    r = math.sqrt(max(rho, 0.0))
    excess = math.sqrt(max(q, 0.0)) - (1 + TAU) * r - sd - math.sqrt(eq)
    return excess / r if r > 0 else (math.inf if excess > 0 else excess)


def box_excess(lo, hi, x, delta) -> float:
    """Largest distance of ``x`` outside the box ``[lo, hi]`` scaled by ``1 + TAU`` about its
    centre and widened by the simulation error ``δ``, relative to the box's largest half-width
    (exact interval test; positive means a violation).

    Parameters
    ----------
    lo, hi : ndarray, shape (n,)
        The box.
    x : ndarray, shape (n,)
        The true state.
    delta : ndarray, shape (n,)
        Bound of the simulation error (:func:`simulation_error_bound`).

    Returns
    -------
    float
    """
    lo, hi, x = np.asarray(lo, float), np.asarray(hi, float), np.asarray(x, float)
    if np.isnan(lo).any() or np.isnan(hi).any():
        return math.inf  # a NaN bound is never a valid answer
    delta = np.broadcast_to(np.asarray(delta, float), x.shape)
    finite = np.isfinite(lo) & np.isfinite(hi)
    out = np.empty_like(x)
    # A bound that overflowed to ±inf (a diverging error bound) still contains everything on its
    # side; the other side is tested as it is, without the relative allowance.
    out[~finite] = np.maximum(lo[~finite] - x[~finite], x[~finite] - hi[~finite]) - delta[~finite]
    lf, hf = lo[finite], hi[finite]
    mid, rad = 0.5 * (lf + hf), 0.5 * (hf - lf)
    out[finite] = np.abs(x[finite] - mid) - ((1 + TAU) * rad + delta[finite] + TAU * np.abs(mid))
    scale = max(float(rad.max()) if rad.size else 0.0, 1e-300)
    return float(out.max()) / scale


def zonotope_excess(c, G, x, delta) -> float:
    """``t* − (1 + TAU)`` where ``t*`` is the smallest ``t`` with ``x ∈ c + G [−t, t]^m ⊕ [−δ, δ]``
    (the exact containment test as a linear program). A least-squares certificate answers first
    when it exists: a ``ξ`` with ``|ξ|∞ ≤ 1`` and ``G ξ = x − c`` (up to δ) proves containment, and
    ``|ξ|∞ − (1 + TAU)`` is then returned, an upper bound of the excess (the least-squares ``ξ``
    need not minimise ``|ξ|∞``). Positive means a violation (beyond the LP's own 1e-9 feasibility
    tolerance, which is added to the allowance; an infeasible LP is a violation too). A violation
    the LP reports, or an LP that fails (iteration limit, numerical trouble), goes to the library's exact facet test (:meth:`setbound.Zonotope.contains` with
    ``rel_tol = TAU``) of the zonotope widened by the δ box, because the LP is badly scaled when
    generator lengths span many orders of magnitude; NaN (undecided, never a violation) when the
    LP failed and the facet test is too large to run.

    Parameters
    ----------
    c : ndarray, shape (n,)
        Centre.
    G : ndarray, shape (n, m)
        Generators.
    x : ndarray, shape (n,)
        The true state.
    delta : ndarray, shape (n,)
        Bound of the simulation error (:func:`simulation_error_bound`).

    Returns
    -------
    float
    """
    c, G, x = np.asarray(c, float), np.asarray(G, float), np.asarray(x, float)
    r = x - c
    n, m = G.shape
    if m == 0:
        return box_excess(c, c, x, delta)
    xi, *_ = np.linalg.lstsq(G, r, rcond=None)
    res = np.abs(G @ xi - r)
    if np.max(np.abs(xi)) <= 1.0 and np.all(res <= delta + 1e-12 * (np.abs(r) + np.abs(G) @ np.abs(xi))):
        return float(np.max(np.abs(xi))) - (1 + TAU)
    from scipy.optimize import linprog

    # variables (ξ, t): min t s.t. |ξ_i| <= t, |G ξ − r| <= δ. Each row i of G ξ − r is divided by
    # its own scale (rs|G|_i, |r_i|, δ_i): the same ξ are feasible, and HiGHS's absolute
    # feasibility tolerance means the same on a set of size 1 as on one of size 1e39 (a diverging
    # system with an interval A: HiGHS called the unscaled problem infeasible).
    scale = np.maximum.reduce([np.abs(G).sum(axis=1), np.abs(r), np.asarray(delta, float)])
    scale[~(scale > 0) | ~np.isfinite(scale)] = 1.0
    Gs, rs, ds = G / scale[:, None], r / scale, np.asarray(delta, float) / scale
    cost = np.zeros(m + 1)
    cost[-1] = 1.0
    Im = np.eye(m)
    A_ub = np.block([[Im, -np.ones((m, 1))], [-Im, -np.ones((m, 1))],
                     [Gs, np.zeros((n, 1))], [-Gs, np.zeros((n, 1))]])
    b_ub = np.concatenate([np.zeros(2 * m), rs + ds, -rs + ds])
    sol = linprog(cost, A_ub=A_ub, b_ub=b_ub, bounds=[(None, None)] * m + [(0, None)], method="highs",
                  options={"primal_feasibility_tolerance": 1e-9, "dual_feasibility_tolerance": 1e-9})
    # status 2 (infeasible): no t at all, x is off the set's affine hull (a violation); any other
    # non-zero status (iteration limit, numerical trouble) decides nothing: NaN
    excess = (float(sol.x[-1]) - (1 + TAU) - 1e-9 if sol.status == 0
              else math.inf if sol.status == 2 else math.nan)
    if not excess <= 0:
        # The LP is badly scaled when generator lengths span many orders of magnitude (tiny
        # rounding generators next to the state's): confirm a reported violation, or decide where
        # the LP failed, with the library's exact test (facet enumeration) of the zonotope widened
        # by the δ box.
        keep = np.any(G != 0, axis=0)
        Gd = np.hstack([G[:, keep], np.diag(delta)[:, delta > 0]])
        if Gd.shape[1] >= n and math.comb(Gd.shape[1], n - 1) <= 200_000:
            if bool(Zonotope(c, Gd).contains(x, rel_tol=TAU)):
                return -TAU
            return excess if excess > 0 else math.inf  # outside: a violation of unknown size
        # Too many facets with the δ columns: the set without them (inside it is inside the
        # widened one; outside it decides nothing).
        Gk = G[:, keep]
        if Gk.shape[1] >= n and math.comb(Gk.shape[1], n - 1) <= 200_000 and \
                bool(Zonotope(c, Gk).contains(x, rel_tol=TAU)):
            return -TAU
    return excess


def _exact_inverse(T):
    """The exact inverse of the float matrix ``T`` (its entries taken as the rationals they are), as
    rows of :class:`fractions.Fraction`; None when ``T`` is singular."""
    from fractions import Fraction

    n = T.shape[0]
    M = [[Fraction(float(T[i, j])) for j in range(n)] + [Fraction(int(i == j)) for j in range(n)] for i in range(n)]
    for col in range(n):
        piv = max(range(col, n), key=lambda i: abs(M[i][col]))
        if M[piv][col] == 0:
            return None
        M[col], M[piv] = M[piv], M[col]
        inv = 1 / M[col][col]
        M[col] = [v * inv for v in M[col]]
        for i in range(n):
            f = M[i][col]
            if i != col and f:
                Mc = M[col]
                M[i] = [a - f * b for a, b in zip(M[i], Mc)]
    return [row[n:] for row in M]


def parallelotope_excess(c, T, r, x, delta) -> float:
    """``t* − (1 + TAU)`` for the parallelotope ``c + T [−1, 1]^n`` (``T`` square) plus the axis box
    ``[−r, r]``, decided in exact rational arithmetic: ``t*`` is the smallest ``t`` with
    ``x ∈ c + t (T B^n ⊕ [−r, r]) ⊕ [−δ, δ]``. Positive means a violation, ``nan`` that the test
    could not decide (never counted as contained nor as a violation).

    A general LP or a least-squares residual cannot decide membership when ``T`` is
    ill-conditioned (the campaign met cond(T) ≈ 1e17: ROPO's parallelotope of a diverging
    interval-hull recursion). Here every answer carries a certificate evaluated exactly:

    * *inside*: a point ``ξ`` with ``T ξ + η + e = x − c`` (``|η_i| ≤ t r_i``, ``|e_i| ≤ δ_i``) gives
      ``t* ≤ max(‖ξ‖∞, max_i |η_i| / r_i)``; ``ξ`` is the floating-point solve with its residual bounded
      rigorously (Higham's γ), or else the exact ``T⁻¹(x − c)`` (rationals), or else the point of a
      linear program in the coordinates ``T⁻¹ x``, re-evaluated exactly;
    * *outside*: a direction ``h`` gives ``t* ≥ (|hᵀ(x − c)| − |h|ᵀδ) / (Σ_j |hᵀt_j| + |h|ᵀ r)``, evaluated
      exactly; the directions tried are the facet normals (rows of the exact ``T⁻¹``) and the dual
      direction of that linear program.

    The returned excess is the certified upper bound when it is ≤ 0, the certified lower bound
    when that is > 0, and ``nan`` when neither decides. A singular ``T`` (a flat parallelotope) is
    handed to :func:`zonotope_excess` with the box as generators.

    Parameters
    ----------
    c : ndarray, shape (n,)
        Centre.
    T : ndarray, shape (n, n)
        Generators of the parallelotope.
    r : ndarray, shape (n,)
        Radii of the axis box (zeros when there is none).
    x : ndarray, shape (n,)
        The true state.
    delta : ndarray, shape (n,)
        Bound of the simulation error (:func:`simulation_error_bound`).

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> from setbound.campaign import parallelotope_excess
    >>> T = np.array([[1.0, 1.0], [0.0, 1e-12]])
    >>> z = np.zeros(2)
    >>> parallelotope_excess(z, T, z, np.array([2.0, 1e-12]), z) <= 0
    True
    >>> parallelotope_excess(z, T, z, np.array([2.0, 1.1e-12]), z) > 0
    True
    """
    from fractions import Fraction

    c, T, x = np.asarray(c, float), np.asarray(T, float), np.asarray(x, float)
    n = c.size
    r = np.broadcast_to(np.asarray(r, float), (n,))
    delta = np.broadcast_to(np.asarray(delta, float), (n,))
    if T.shape != (n, n) or x.shape != (n,):
        raise ValueError(f"T: expected shape ({n}, {n}) and x of length {n}, got {T.shape} and {x.shape}")
    if np.isnan(c).any() or np.isnan(T).any() or np.isnan(r).any():
        return math.inf  # a NaN set is never an answer
    if not (np.all(np.isfinite(c)) and np.all(np.isfinite(T)) and np.all(np.isfinite(r))):
        return math.nan  # an overflowed set: not decided here
    if np.any(r < 0) or np.any(delta < 0) or not np.all(np.isfinite(delta)):
        raise ValueError("r, delta: expected finite non-negative radii")
    lim = 1 + TAU
    fuzz = 1 + 16 * _U  # the float evaluation of the bound of step 1 itself

    def bound_from(xi, res_abs):
        # t with |ξ|∞ <= t and |residual| <= t r + δ (inf when a row without box is not covered)
        need = res_abs - delta
        t = float(np.max(np.abs(xi)))
        for i in np.flatnonzero(need > 0):
            t = max(t, need[i] / r[i]) if r[i] > 0 else math.inf
        return t

    # 1. the floating-point solve, its residual bounded rigorously (γ of the dot products and the
    #    subtractions; any summation order).
    d = x - c
    with np.errstate(all="ignore"):
        try:
            xi = np.linalg.solve(T, d)
        except np.linalg.LinAlgError:
            xi = None
        if xi is not None and np.all(np.isfinite(xi)):
            res = d - T @ xi
            err = _gamma(n + 3) * (np.abs(x) + np.abs(c) + np.abs(T) @ np.abs(xi) + np.abs(res))
            t = bound_from(xi, (np.abs(res) + err) * (1 + 4 * _U)) * fuzz
            if t <= lim:
                return t - lim
    # 2. exact: z = T⁻¹(x − c) and the facet normals.
    M = _exact_inverse(T)
    if M is None:  # a flat parallelotope (ROPO pads T with zero columns): the general zonotope test
        keep = np.any(T != 0, axis=0)
        return zonotope_excess(c, np.hstack([T[:, keep], np.diag(r)[:, r > 0]]), x, delta)
    F = Fraction
    limq = 1 + F(TAU)

    def inside(t):  # t <= limq exactly: the excess as a float <= 0
        return float(t - limq)

    def outside(t):  # t > limq exactly: the excess as a float > 0
        return max(float(t - limq), 5e-324)

    dq = [F(float(a)) - F(float(b)) for a, b in zip(x, c)]
    rq = [F(float(v)) for v in r]
    deltaq = [F(float(v)) for v in delta]
    z = [sum((m * e for m, e in zip(row, dq)), F(0)) for row in M]
    U = max(abs(v) for v in z)  # ξ = z, η = e = 0
    if U <= limq:
        return inside(U)
    if any(v > 0 for v in rq):
        # ξ = s z, η = (1 − s)(x − c) with s = B / (U + B), B = max_i |x_i − c_i| / r_i: the box takes
        # a share of the residual (t* <= U B / (U + B)); a row without box must have x_i = c_i.
        if all(v > 0 or di == 0 for v, di in zip(rq, dq)):
            B = max(abs(di) / v for v, di in zip(rq, dq) if v > 0)
            tq = U * B / (U + B)
            if tq <= limq:
                return inside(tq)

    L = F(0)
    for i in range(n):
        # the facet normal m_i (row i of T⁻¹): hᵀt_j = [i = j], so the denominator is 1 + |m_i|ᵀ r
        m = M[i]
        num = abs(z[i]) - sum((abs(a) * b for a, b in zip(m, deltaq)), F(0))
        L = max(L, num / (1 + sum((abs(a) * b for a, b in zip(m, rq)), F(0))))
    if L > limq:
        return outside(L)
    # 3. undecided by the facets: an LP in the coordinates z (ξ = z − M(η + e)), its point and its
    #    dual direction re-evaluated exactly.
    from scipy.optimize import linprog

    Mf = np.array([[float(v) for v in row] for row in M])
    zf = np.array([float(v) for v in z])
    # variables (η, e, t): min t s.t. |zf − Mf(η + e)| <= t, |η_i| <= t r_i, |e_i| <= δ_i
    cost = np.zeros(2 * n + 1)
    cost[-1] = 1.0
    one = np.ones((n, 1))
    I, Z0 = np.eye(n), np.zeros((n, n))
    A_ub = np.block([[-Mf, -Mf, -one], [Mf, Mf, -one], [I, Z0, -r[:, None]], [-I, Z0, -r[:, None]]])
    b_ub = np.concatenate([-zf, zf, np.zeros(2 * n)])
    bounds = [(None, None)] * n + [(-float(v), float(v)) for v in delta] + [(0, None)]
    sol = linprog(cost, A_ub=A_ub, b_ub=b_ub, bounds=bounds, method="highs")
    if sol.status == 0:
        eta = np.where(r > 0, sol.x[:n], 0.0)
        e = np.clip(sol.x[n:2 * n], -delta, delta)
        w = [F(float(a)) + F(float(b)) for a, b in zip(eta, e)]
        xi_q = [zi - sum((m * v for m, v in zip(row, w)), F(0)) for zi, row in zip(z, M)]
        tq = max(abs(v) for v in xi_q)
        for i in range(n):
            if r[i] > 0:
                tq = max(tq, abs(F(float(eta[i]))) / rq[i])
        if tq <= limq:
            return inside(tq)
        # the dual of the first two blocks: a direction g in z-space, h = Mᵀ g in x-space
        g = sol.ineqlin.marginals[n:2 * n] - sol.ineqlin.marginals[:n]
        if np.all(np.isfinite(g)) and np.any(g != 0):
            gq = [F(float(v)) for v in g]
            h = [sum((gq[k] * M[k][i] for k in range(n)), F(0)) for i in range(n)]
            # the support of t (T B ⊕ [−r, r]) ⊕ [−δ, δ] in the direction h, exactly
            ht = [sum((h[i] * F(float(T[i, j])) for i in range(n)), F(0)) for j in range(n)]
            den = sum((abs(v) for v in ht), F(0)) + sum((abs(a) * b for a, b in zip(h, rq)), F(0))
            num = abs(sum((a * b for a, b in zip(h, dq)), F(0))) - sum((abs(a) * b for a, b in zip(h, deltaq)), F(0))
            if den > 0 and num / den > limq:
                return outside(num / den)
    return math.nan


def czono_excess(Z: ConstrainedZonotope, x, delta) -> float:
    """``t* − (1 + TAU)`` where ``t*`` is the smallest ``t`` with ``x ∈ {c + Gξ : Aξ = b, ‖ξ‖∞ ≤ t}
    ⊕ [−(r + δ), r + δ]`` (``r`` the set's rounding box; a linear program). ``t* ≤ 1`` exactly when
    ``x`` is in the constrained zonotope widened by the simulation-error box. Positive means a
    violation (beyond the LP's 1e-9 tolerance); a violation the LP reports is confirmed by the
    library's certified membership test of the widened set (which answers "outside" only with a
    verified certificate), as the LP may be badly scaled.

    Parameters
    ----------
    Z : ConstrainedZonotope
        The estimate.
    x : ndarray, shape (n,)
        The true state.
    delta : ndarray, shape (n,)
        Bound of the simulation error (:func:`simulation_error_bound`).

    Returns
    -------
    float
    """
    from scipy.optimize import linprog

    x, delta = np.asarray(x, float), np.asarray(delta, float)
    G, A, b = Z.generators, Z.A, Z.b
    n, m = G.shape
    q = A.shape[0]
    r = x - Z.center
    slack = Z.rounding + delta
    if m == 0:
        return box_excess(Z.center - Z.rounding, Z.center + Z.rounding, x, delta)
    # variables (ξ, t): min t s.t. A ξ = b, |ξ_i| <= t, |G ξ − r| <= rounding + δ
    cost = np.zeros(m + 1)
    cost[-1] = 1.0
    Im = np.eye(m)
    A_ub = np.block([[Im, -np.ones((m, 1))], [-Im, -np.ones((m, 1))],
                     [G, np.zeros((n, 1))], [-G, np.zeros((n, 1))]])
    b_ub = np.concatenate([np.zeros(2 * m), r + slack, -r + slack])
    A_eq = np.hstack([A, np.zeros((q, 1))]) if q else None
    sol = linprog(cost, A_ub=A_ub, b_ub=b_ub, A_eq=A_eq, b_eq=b if q else None,
                  bounds=[(None, None)] * m + [(0, None)], method="highs",
                  options={"primal_feasibility_tolerance": 1e-9, "dual_feasibility_tolerance": 1e-9})
    excess = float(sol.x[-1]) - (1 + TAU) - 1e-9 if sol.status == 0 else math.inf
    if excess > 0 and ConstrainedZonotope(Z.center, G, A, b, rounding=slack * (1 + TAU)).contains(x):
        return -TAU  # the LP's scaling, not a violation: the certified test finds x inside
    return excess


# ---------------------------------------------------------------------------------------------
# random systems


def _random_A(rng, n: int, unstable: bool) -> np.ndarray:
    """A = V Λ V⁻¹ with a well-conditioned V and a real block-diagonal Λ: moduli in [0, 0.95]
    (stable) or at least one mode with modulus in (1, 1.08] (unstable)."""
    blocks, k = [], 0
    while k < n:
        mod = rng.uniform(0.0, 0.95)
        if k + 1 < n and rng.uniform() < 0.4:
            th = rng.uniform(0.1, math.pi - 0.1)
            blocks.append(mod * np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]]))
            k += 2
        else:
            blocks.append(np.array([[mod * rng.choice([-1.0, 1.0])]]))
            k += 1
    if unstable:
        i = int(rng.integers(len(blocks)))
        b = blocks[i]
        blocks[i] = b / max(np.max(np.abs(np.linalg.eigvals(b))), 1e-3) * rng.uniform(1.01, 1.08)
    Lam = np.zeros((n, n))
    k = 0
    for b in blocks:
        s = b.shape[0]
        Lam[k:k + s, k:k + s] = b
        k += s
    Q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    V = Q @ np.diag(rng.uniform(0.5, 2.0, n))
    return V @ Lam @ np.linalg.inv(V)


@dataclass
class RandomSystem:
    """One random system of a case: ``x⁺ = A x + E ω``, ``y = C x + F ω``, ``ω ∈ [−1, 1]^{n_ω}``
    with ``ω = (d, v)``: ``E = [Fd, 0]``, ``F = [0, Z]``; ``T`` the diagonal similarity applied
    (identity unless ill-conditioned).

    Parameters
    ----------
    A, C : ndarray
        State and output matrices.
    Fd, Z : ndarray
        State-disturbance and noise matrices.
    T : ndarray
        The similarity applied.
    family : str
        The family.
    nx, ny : int
        Dimensions.
    """

    A: np.ndarray
    C: np.ndarray
    Fd: np.ndarray
    Z: np.ndarray
    T: np.ndarray
    family: str
    nx: int
    ny: int

    @property
    def E(self):
        """``[Fd, 0]``: the state-disturbance matrix of the LinearSystem form."""
        return np.hstack([self.Fd, np.zeros((self.nx, self.Z.shape[1]))])

    @property
    def F(self):
        """``[0, Z]``: the measurement-noise matrix of the LinearSystem form."""
        return np.hstack([np.zeros((self.ny, self.Fd.shape[1])), self.Z])

    def linear_system(self, A=None) -> LinearSystem:
        """The system as a :class:`~setbound.LinearSystem` (``A`` may replace the matrix, e.g. by an
        IntervalMatrix).

        Parameters
        ----------
        A : array_like or IntervalMatrix, optional
            Replaces the matrix.

        Returns
        -------
        LinearSystem
        """
        return LinearSystem(self.A if A is None else A, self.C, E=self.E, F=self.F)

    def plant(self) -> Plant:
        """The system as a thesis :class:`~setbound.Plant` (``F = Fd``, ``Z``)."""
        return Plant(self.A, self.C, Fd=self.Fd, Z=self.Z)


def random_system(rng, max_nx: int = 8, *, min_nx: int = 1, family: str | None = None,
                  max_nw: int = 16) -> RandomSystem:
    """A random detectable system (the form of Methods › Ellipsoidal estimation › Model): n_x uniform in [min_nx, max_nx],
    n_y in [1, n_x], at most ``max_nw`` disturbances ``ω = (d, v)`` (the ellipsoidal designs
    enumerate the 2^{n_ω} vertices of the disturbance box), ``family`` ``"stable"``, ``"unstable"``, ``"ill_stable"`` or
    ``"ill_unstable"`` (drawn when None). The ill-conditioned families apply
    ``x → T x`` with ``T = diag(10^U(−2, 2))``: the entries of A, C, E then span about
    1e-4 … 1e4.

    Parameters
    ----------
    rng : numpy.random.Generator
        Random source.
    max_nx : int, optional
        Largest state dimension.
    min_nx : int, optional
        Smallest state dimension.
    family : str, optional
        The family (drawn when None).
    max_nw : int, optional
        Largest number of disturbances.

    Returns
    -------
    RandomSystem
    """
    nx = int(rng.integers(min_nx, max_nx + 1))
    if family is None:
        family = str(rng.choice(["stable", "unstable", "ill_stable", "ill_unstable"]))
    A = _random_A(rng, nx, unstable=family.endswith("unstable"))
    ny = int(rng.integers(1, min(nx, max_nw - 1) + 1))
    C = rng.standard_normal((ny, nx))
    nd = int(rng.integers(1, min(nx, max_nw - ny) + 1))
    Fd = rng.standard_normal((nx, nd)) * 10 ** rng.uniform(-2, -0.5)
    Z = np.diag(10 ** rng.uniform(-2, -0.5, ny))
    T = np.eye(nx)
    if family.startswith("ill"):
        T = np.diag(10 ** rng.uniform(-2, 2, nx))
        Ti = np.diag(1 / np.diag(T))
        A, C, Fd = T @ A @ Ti, C @ Ti, T @ Fd
    return RandomSystem(A, C, Fd, Z, T, family, nx, ny)


# ---------------------------------------------------------------------------------------------
# the estimators

@dataclass
class Case:
    """What :func:`random_case` drew for one (estimator, seed).

    Parameters
    ----------
    estimator : str
        Estimator name.
    seed : int
        Seed of the case.
    system : RandomSystem
        The system drawn.
    disturbance : str
        Disturbance profile.
    N : int
        Number of steps.
    options : dict, optional
        Estimator options.
    """

    estimator: str
    seed: int
    system: RandomSystem
    disturbance: str
    N: int
    options: dict = field(default_factory=dict)


def _horizon(rng, family: str, nmax: int) -> int:
    # unstable systems: the true state grows like 1.08^N; the floating-point simulation error
    # grows with it (simulation_error_bound), so the horizon is kept moderate.
    return int(rng.integers(nmax // 2, nmax + 1)) if not family.endswith("unstable") else int(rng.integers(40, 81))


_IMPROVED_OPTIONS = ("det_normalized", "fixed_shape", "ball_normalized")
_IMPROVED_FEEDBACK = ("fixed_shape", "outer_bound", "none")
_IMPROVED_PREDICTORS = ("online", "scaled", "offline")


def random_case(estimator: str, seed: int, max_nx: int = 8) -> Case:
    """Draws the case ``(estimator, seed)`` (deterministic).

    Parameters
    ----------
    estimator : str
        Estimator name.
    seed : int
        Seed.
    max_nx : int, optional
        Largest state dimension.

    Returns
    -------
    Case
    """
    if estimator not in ESTIMATORS:
        raise ValueError(f"estimator: expected one of {', '.join(ESTIMATORS)}, got {estimator!r}")
    spec = ESTIMATORS[estimator]
    rng = np.random.default_rng([seed, spec.index])
    family = None
    if spec.stable_only:
        family = str(rng.choice(["stable", "ill_stable"]))
    s = random_system(rng, min(max_nx, spec.max_nx), family=family, max_nw=spec.max_nw)
    dist = str(rng.choice(["uniform", "vertex"]))
    opts: dict = {}
    if estimator == "ell_improved":
        opts = {"option": str(rng.choice(_IMPROVED_OPTIONS)), "feedback": str(rng.choice(_IMPROVED_FEEDBACK)),
                "predictor": str(rng.choice(_IMPROVED_PREDICTORS))}
    if estimator in ("ell_interval_A", "zono_obs_interval_A"):
        k = int(rng.integers(1, min(3, s.nx * s.nx) + 1))
        idx = rng.choice(s.nx * s.nx, size=k, replace=False)
        rad = np.zeros(s.nx * s.nx)
        rad[idx] = np.abs(s.A.ravel()[idx]) * rng.uniform(0.01, 0.1, k) + 1e-3 * np.abs(s.A).max() * rng.uniform(0, 1, k)
        opts = {"A_rad": rad.reshape(s.nx, s.nx), "A_choice": str(rng.choice(["vertex", "uniform"]))}
        if estimator == "zono_obs_interval_A":
            # the volume LP enumerates subsets of n_x − 1 of the reduced set's, E's, the two boxes' and
            # the strips' columns: only up to n_x = 4 (the observer refuses what would pass its limit)
            rules = _INTERVAL_A_RULES if s.nx <= 4 else tuple(r for r in _INTERVAL_A_RULES if r != "volume_min")
            opts["rule"] = str(rng.choice(rules))
    if estimator == "pradius":
        opts = {"approach": int(rng.choice([1, 2]))}
    if estimator == "zono_strip_gain":
        opts = {"all_strips": int(rng.integers(0, 2))}
    if estimator == "ropo":
        opts = {"reduction": str(rng.choice(["girard", "pca"]))}
    if estimator == "thesis_lpv":
        nv = int(rng.integers(2, 4))
        dA = [rng.standard_normal((s.nx, s.nx)) * 0.05 * np.abs(s.A).max() for _ in range(nv)]
        if s.family.startswith("ill"):
            dA = [s.T @ (np.linalg.inv(s.T) @ d @ s.T) @ np.linalg.inv(s.T) for d in dA]
        opts = {"dA": dA}
    if estimator == "interval_nonlinear":
        opts = {"h_rad": 10 ** rng.uniform(-3, -1.5, s.nx) * np.diag(s.T)}
    if estimator == "descriptor":
        opts = {"algebraic": int(rng.integers(0, 2))}
    N = _horizon(rng, s.family, spec.horizon)
    if spec.run in (_run_ellipsoidal, _run_descriptor):
        # Normalisation of the offline design (drawn last: the earlier draws are unchanged). The
        # log-det design (the default) solves a maxdet problem per β and takes 10–200 s at
        # n_x = 7–8, the ball design 1–5 s; containment does not depend on it, so two cases in
        # three use the ball and one the default.
        opts["normalization"] = "logdet" if rng.uniform() < 1 / 3 else "ball"
    return Case(estimator, int(seed), s, dist, N, opts)


@dataclass
class CaseResult:
    """Outcome of one case: ``status`` ``"ok"`` or ``"design_failed"`` (``reason``: the
    library's message), ``steps`` checked, ``violations`` (step, excess) pairs and
    ``max_excess`` (largest excess seen, ≤ 0 when every step was contained), ``unverified``
    (steps whose simulation-error allowance exceeded ``LOOSE`` times the set's size: not
    counted in ``steps``). A case of an estimator with ``runs_per_design > 1`` simulates that many
    trajectories with one design; a violation's step index then counts over the runs (run r,
    step k → ``r · (N + 1) + k``).

    Parameters
    ----------
    estimator : str
        Estimator name.
    seed : int
        Seed.
    nx : int
        State dimension.
    family : str
        System family.
    disturbance : str
        Disturbance profile.
    status : str
        ``"ok"`` or ``"design_failed"``.
    steps : int, optional
        Steps checked.
    reason : str, optional
        The library's message.
    violations : list, optional
        ``(step, excess)`` pairs.
    max_excess : float, optional
        Largest excess.
    options : dict, optional
        Estimator options.
    unverified : int, optional
        Steps not counted.
    false_alarms : int, optional
        Readings flagged as impossible on fault-free data (must stay 0).
    undecided : int, optional
        Steps the membership test could not decide (not counted in ``steps``).
    step_offset : int, optional
        ``r · (N + 1)`` while run ``r`` of a multi-run case is checked.
    command_options : str, optional
        Options for the reproduction command.
    """

    estimator: str
    seed: int
    nx: int
    family: str
    disturbance: str
    status: str
    steps: int = 0
    reason: str = ""
    violations: list = field(default_factory=list)
    max_excess: float = -math.inf
    options: dict = field(default_factory=dict)
    unverified: int = 0
    #: Verified steps at which the estimator reported an impossible reading (setbound.measurement)
    #: although the data are fault-free: a false alarm is a bug in the guarantee.
    false_alarms: int = 0
    #: Steps whose membership test could not decide (:func:`parallelotope_excess` returned nan):
    #: not counted in ``steps``, never counted as contained.
    undecided: int = 0
    step_offset: int = 0  # r · (N + 1) while run r of a multi-run case is checked

    command_options: str = ""

    def reproduce(self) -> str:
        """The one-line command that re-runs this case."""
        return (f"python -m setbound.campaign --estimator {self.estimator} --seed {self.seed}"
                f"{self.command_options} --verbose")


def _ball_ellipsoid(s: RandomSystem, rng) -> tuple[Ellipsoid, np.ndarray]:
    """Initial set: the ball of radius r around a random centre, in the original coordinates
    (mapped by T); returns the ellipsoid and a true initial state drawn in it."""
    n = s.nx
    r = float(10 ** rng.uniform(-1, 0.5))
    c0 = rng.standard_normal(n)
    Ti = np.diag(1 / np.diag(s.T))
    P = Ti.T @ Ti
    P = 0.5 * (P + P.T)
    E0 = Ellipsoid(P, s.T @ c0, r * r)
    return E0


def _x0_box(s: RandomSystem, rng) -> tuple[np.ndarray, np.ndarray]:
    r = float(10 ** rng.uniform(-1, 0.5))
    c0 = s.T @ rng.standard_normal(s.nx)
    h = r * np.diag(s.T)
    return c0 - h, c0 + h


def _delta(A_abs, x, E, W, A=None) -> np.ndarray:
    """:func:`simulation_error_bound` of a run of :func:`setbound.simulation.simulate`
    (``A_k x + E ω``: n_x + n_ω products, plus the additions); ``A``: the constant matrix, when
    it is one (then the tighter :func:`_stable_error_bound` is used where it applies)."""
    terms = np.abs(x) @ A_abs.T + np.abs(W) @ np.abs(E).T
    m = A_abs.shape[0] + E.shape[1] + 2
    d = simulation_error_bound(A_abs, terms, x.shape[0], m)
    if A is not None:
        d2 = _stable_error_bound(A, _gamma(m) * terms, x.shape[0])
        if d2 is not None:
            d = np.fmin(d, d2)
    return d


#: A step is *checked* only when the simulation-error allowance is below this fraction of the
#: set's size; otherwise it is counted as unverified (``CaseResult.unverified``), never as
#: contained.
LOOSE = 1e-6


def _check_ellipsoids(sets, x, delta, res: CaseResult, start: int = 0):
    for k, S in enumerate(sets):
        d = delta[k + start]
        if not (np.all(np.isfinite(d)) and float(d @ np.abs(S.P) @ d) <= (LOOSE ** 2) * S.rho):
            res.unverified += 1
            continue
        e = ellipsoid_excess(S.P, S.center, S.rho, x[k + start], d)
        _record(res, k + start, e)


def _check_boxes(lo, hi, x, delta, res: CaseResult, flagged=None):
    """Containment of x_k in the boxes at the verified steps; ``flagged`` (per row: the reading of
    that row was declared impossible) counts false alarms there (at an unverified step the
    simulated reading itself is too inaccurate to judge)."""
    for k in range(lo.shape[0]):
        d = delta[k]
        if not (np.all(np.isfinite(d)) and np.all(d <= LOOSE * 0.5 * (hi[k] - lo[k]))):
            res.unverified += 1
            continue
        _record(res, k, box_excess(lo[k], hi[k], x[k], d))
        if flagged is not None:
            res.false_alarms += int(flagged[k])


def _record(res: CaseResult, k: int, e: float):
    if math.isnan(e):  # the membership test could not decide: neither contained nor a violation
        res.undecided += 1
        return
    res.steps += 1
    if e > res.max_excess:
        res.max_excess = e
    if e > 0:
        res.violations.append((int(k) + res.step_offset, float(e)))


def _run_ellipsoidal(case: Case, res: CaseResult, rng):
    s = case.system
    name = case.estimator
    if name == "ell_interval_A":
        A_rad = case.options["A_rad"]
        system = s.linear_system(IntervalMatrix(s.A - A_rad, s.A + A_rad))
        A_abs = np.abs(s.A) + A_rad
    else:
        system = s.linear_system()
        A_abs = np.abs(s.A)
    design = ellipsoidal.design_offline(system, normalization=case.options.get("normalization", "logdet"))
    for run in range(ESTIMATORS[name].runs_per_design):
        res.step_offset = run * (case.N + 1)
        x0 = _ball_ellipsoid(s, rng)
        if name == "ell_offline":
            est = ellipsoidal.OfflineEstimator(design, x0)
        elif name in ("ell_online_vertex", "ell_interval_A"):
            est = ellipsoidal.OnlineEstimator(design, x0)
        elif name == "ell_online_scaled":
            est = ellipsoidal.OnlineEstimator(design, x0, scaling=True)
        else:
            est = ellipsoidal.ImprovedEstimator(design, x0, **{k: case.options[k] for k in ("option", "feedback", "predictor")})
        sim = simulate(system, x0, case.N, disturbance=case.disturbance, rng=rng,
                       A_choice=case.options.get("A_choice", "vertex"))
        delta = _delta(A_abs, sim.x, system.E, sim.omega, None if name == "ell_interval_A" else s.A)
        traj = est.run(sim.y)
        _check_ellipsoids(traj.sets, sim.x, delta, res)
        res.false_alarms += int(np.sum(traj.flagged))  # fault-free data: any flag is a bug


def _random_descriptor(case: Case, rng):
    """A descriptor system from the case's system: ``E x⁺ = A x + D w`` with E = I (regular
    case) or one algebraic row (E singular, index 1: the algebraic equation 0 = a x + d w is
    seen by an extra output)."""
    s = case.system
    n = s.nx
    Ed = np.eye(n)
    Ad = s.A.copy()
    D = s.E
    if case.options.get("algebraic") and n >= 2:
        Ed[-1, :] = 0.0
        Ad[-1, :] = 0.0
        Ad[-1, -1] = -1.0
        Ad[-1, 0] = 0.5
    return DescriptorSystem(Ed, Ad, s.C, D=D, F=s.F)


def _run_descriptor(case: Case, res: CaseResult, rng):
    s = case.system
    system = _random_descriptor(case, rng)
    design = ellipsoidal.design_offline(system, normalization=case.options.get("normalization", "logdet"))
    for run in range(ESTIMATORS[case.estimator].runs_per_design):
        res.step_offset = run * (case.N + 1)
        x0 = _ball_ellipsoid(s, rng)
        est = ellipsoidal.DescriptorEstimator(design, x0)
        sim = simulate(system, x0, case.N, disturbance=case.disturbance, rng=rng)
        # the descriptor simulation solves a linear system per step: bound its error generously by
        # the regular-case bound of the (E = I) part and TAU (documented in docs/reliability.md)
        A_abs = np.abs(system.A)
        delta = _delta(A_abs, sim.x, system.D, sim.omega) * 4
        traj = est.run(sim.y)
        _check_ellipsoids(traj.sets, sim.x, delta, res)


def _run_bounding_ellipsoid(case: Case, res: CaseResult, rng):
    """CORA's ESO-A / ESO-B in setbound's (guaranteed) convention; the noise ellipsoids enclose E ω and
    F ω of the case's box disturbance."""
    s = case.system
    system = s.linear_system()
    cls = (ellipsoidal.OptimalBoundingEllipsoidEstimator if case.estimator == "eso_a_obe"
           else ellipsoidal.EllipsoidalStateBoundingEstimator)
    x0 = _ball_ellipsoid(s, rng)
    est = cls(system, x0, step_cap=0.5)
    sim = simulate(system, x0, case.N, disturbance=case.disturbance, rng=rng)
    delta = _delta(np.abs(s.A), sim.x, system.E, sim.omega, s.A)
    traj = est.run(sim.y)
    _check_ellipsoids(traj.sets, sim.x, delta, res)
def _kalman_gains(system, iterations: int = 300):
    """Stationary Kalman predictor and filter gains of the model (E Eᵀ, F Fᵀ as covariances, the
    Riccati recursion iterated from the identity): ``(L, Λ)`` with ``L = A Λ``."""
    A, C = system.A, system.C
    Q = system.E @ system.E.T
    R = system.F @ system.F.T + 1e-9 * np.eye(system.ny)
    P = np.eye(system.nx)
    for _ in range(iterations):
        S = C @ P @ C.T + R
        K = P @ C.T @ np.linalg.inv(S)
        P = A @ (P - K @ C @ P) @ A.T + Q
        P = 0.5 * (P + P.T)
    K = P @ C.T @ np.linalg.inv(C @ P @ C.T + R)
    return A @ K, K


#: The strip-based rules the interval-A campaign draws from (ZonotopicObserver).
_INTERVAL_A_RULES = ("segment_min", "volume_min", "bravo", "wang")


def _run_zonotopic(case: Case, res: CaseResult, rng):
    s = case.system
    A_rad = case.options.get("A_rad")
    system = s.linear_system() if A_rad is None else s.linear_system(IntervalMatrix(s.A - A_rad, s.A + A_rad))
    lo, hi = _x0_box(s, rng)
    x0 = Zonotope(0.5 * (lo + hi), np.diag(0.5 * (hi - lo)))
    if case.estimator == "zono_segment_min":
        est = zonotopic.SegmentMinEstimator(system, x0)
    elif case.estimator == "zono_volume_min":
        # the volume-minimising gain has one L1 row per subset of n_x − 1 generators: keep few
        est = zonotopic.VolumeMinEstimator(system, x0, max_generators=s.nx + 2)
    elif case.estimator == "zono_obs_segment_min":
        est = zonotopic.ZonotopicObserver(system, x0, "segment_min")
    elif case.estimator == "zono_obs_volume_min":
        # n_x generators kept (the least): the LP's subsets of n_x − 1 of them, E's and the strips'
        est = zonotopic.ZonotopicObserver(system, x0, "volume_min", max_generators=s.nx)
    elif case.estimator == "zono_obs_interval_A":
        rule = case.options["rule"]
        est = zonotopic.ZonotopicObserver(system, x0, rule, max_generators=s.nx if rule == "volume_min" else 20)
    elif case.estimator == "zono_bravo":
        est = zonotopic.BravoEstimator(system, x0)
    elif case.estimator == "zono_wang":
        est = zonotopic.WangEstimator(system, x0)
    elif case.estimator == "zono_combastel":
        est = zonotopic.CombastelObserver(system, x0)
    elif case.estimator == "ropo":
        # CORA's ROPO (setbound.parallelotope): a parallelotope plus its rounding box per step
        est = parallelotope.ParallelotopeEstimator(system, x0, reduction=case.options["reduction"])
    elif case.estimator in ("zono_strip_gain", "zono_propagation"):
        # A fixed gain from the stationary Kalman recursion of the model (any gain is guaranteed;
        # this one keeps the sets bounded on detectable systems).
        L_pred, L_filt = _kalman_gains(system)
        if case.estimator == "zono_propagation":
            est = zonotopic.PropagationObserver(system, x0, L_pred)
        else:
            est = zonotopic.StripGainEstimator(system, x0, L_filt, all_strips=bool(case.options["all_strips"]))
    else:
        design = zonotopic.design_pradius(system, approach=case.options["approach"])
        est = zonotopic.PRadiusEstimator(design, x0)
    if A_rad is None:
        sim = simulate(system, x0, case.N, disturbance=case.disturbance, rng=rng)
        delta = _delta(np.abs(s.A), sim.x, system.E, sim.omega, s.A)
    else:
        sim = simulate(system, x0, case.N, disturbance=case.disturbance, rng=rng, A_choice=case.options["A_choice"])
        delta = _delta(np.abs(s.A) + A_rad, sim.x, system.E, sim.omega, None)
    traj = est.run(sim.y)
    flagged = traj.flagged
    n = s.nx
    for k, Z in enumerate(traj.sets):
        d = delta[k]
        if not (np.all(np.isfinite(d)) and np.all(d <= LOOSE * np.abs(Z.generators).sum(axis=1))):
            res.unverified += 1
            continue
        split = _parallelotope_and_box(Z.generators, n) if case.estimator == "ropo" else None
        if split is not None:
            # ROPO's set: its n × n parallelotope (ill-conditioned when the interval-hull recursion
            # diverges) and the rounding box after it; decided exactly.
            e = parallelotope_excess(Z.center, split[0], split[1], sim.x[k], d)
        else:
            e = zonotope_excess(Z.center, Z.generators, sim.x[k], d)
        _record(res, k, e)
        res.false_alarms += int(flagged[k])


def _parallelotope_and_box(G, n: int):
    """``(T, r)`` when ``G = [T, axis-aligned columns]`` with ``T`` n × n (ROPO's
    :meth:`~setbound.parallelotope.ParallelotopeEstimator.current_set`), ``r`` the box radii
    rounded up; None otherwise."""
    G = np.asarray(G, float)
    if G.shape[0] != n or G.shape[1] < n:
        return None
    B = G[:, n:]
    if np.any(np.count_nonzero(B, axis=0) > 1):
        return None
    k = np.count_nonzero(B, axis=1)
    r = np.abs(B).sum(axis=1)
    r = np.where(k > 1, r * (1 + (k + 1) * _U), r)  # several columns in a row: their sum rounded up
    return G[:, :n], r


def _run_constrained_zonotopic(case: Case, res: CaseResult, rng):
    """CZN-A / CZN-B in setbound's default (bounded) mode."""
    s = case.system
    system = s.linear_system()
    lo, hi = _x0_box(s, rng)
    x0 = Zonotope(0.5 * (lo + hi), np.diag(0.5 * (hi - lo)))
    correction = "exact_output" if case.estimator == "czn_a" else "wang_strips"
    est = constrained_zonotopic.ConstrainedZonotopicEstimator(system, x0, correction=correction)
    sim = simulate(system, x0, case.N, disturbance=case.disturbance, rng=rng)
    delta = _delta(np.abs(s.A), sim.x, system.E, sim.omega, s.A)
    traj = est.run(sim.y)
    flagged = traj.flagged
    for k, Z in enumerate(traj.sets):
        d = delta[k]
        if not (np.all(np.isfinite(d)) and np.all(d <= LOOSE * (np.abs(Z.generators).sum(axis=1) + Z.rounding))):
            res.unverified += 1
            continue
        _record(res, k, czono_excess(Z, sim.x[k], d))
        res.false_alarms += int(flagged[k])


def _sim_plant(case: Case, rng, A_seq=None, h=None):
    """True trajectory of ``x⁺ = A_k x + Fd d + h_k``, ``y = C x + Z v`` (d, v in the unit box,
    h_k in a box), from x_0 in the initial box. Returns (x0 box, x, y, δ)."""
    s = case.system
    lo, hi = _x0_box(s, rng)
    N = case.N
    n = s.nx
    vert = case.disturbance == "vertex"
    x = np.empty((N, n))
    x[0] = np.where(rng.uniform(size=n) < 0.5, lo, hi) if vert else rng.uniform(lo, hi)
    nd, nv = s.Fd.shape[1], s.Z.shape[1]
    W = rng.choice([-1.0, 1.0], size=(N, nd + nv)) if vert else rng.uniform(-1, 1, size=(N, nd + nv))
    y = np.empty((N, s.ny))
    terms = np.zeros((N, n))
    A_abs = np.abs(s.A)
    hv = None
    if h is not None:
        hv = (np.where(rng.uniform(size=(N, n)) < 0.5, -1.0, 1.0) if vert else rng.uniform(-1, 1, size=(N, n))) * h
    for k in range(N):
        y[k] = s.C @ x[k] + s.Z @ W[k, nd:]
        if k + 1 < N:
            Ak = s.A if A_seq is None else A_seq[k]
            x[k + 1] = Ak @ x[k] + s.Fd @ W[k, :nd] + (hv[k] if hv is not None else 0.0)
            terms[k] = np.abs(Ak) @ np.abs(x[k]) + np.abs(s.Fd) @ np.abs(W[k, :nd]) + (
                np.abs(hv[k]) if hv is not None else 0.0)
            if A_seq is not None:
                A_abs = np.maximum(A_abs, np.abs(Ak))
    m = n + nd + 2 + (1 if hv is not None else 0)
    delta = simulation_error_bound(A_abs, terms, N, m)
    if A_seq is None:
        d2 = _stable_error_bound(s.A, _gamma(m) * terms, N)
        if d2 is not None:
            delta = np.fmin(delta, d2)
    return (lo, hi), x, y, delta


def _run_thesis(case: Case, res: CaseResult, rng):
    s = case.system
    name = case.estimator
    wbar = np.ones(s.Fd.shape[1] + s.Z.shape[1])
    if name in ("thesis_sm_observer", "eso_d"):
        plant = s.plant()
        design = (hinf.design_ellipsoidal_sm_observer if name == "thesis_sm_observer" else hinf.design_eso_d)(plant,
                                                                                                             wbar)
        (lo, hi), x, y, delta = _sim_plant(case, rng)
        xh = 0.5 * (lo + hi)
        obs = hinf.EllipsoidalSMObserver(design, xh, hinf.mu0_from_box(design, lo - xh, hi - xh))
        traj = obs.run(y)
    elif name == "thesis_lpv":
        dA = case.options["dA"]
        Av = [s.A + d for d in dA]
        nvtx = len(Av)
        theta = np.eye(nvtx)[:, : nvtx - 1] if nvtx > 1 else np.zeros((1, 1))
        lpv = hinf.LpvPlant(Av, s.C, theta, Fd=[s.Fd] * nvtx, Z=s.Z)
        design = hinf.design_ellipsoidal_sm_observer_lpv(lpv, wbar)
        alphas = rng.dirichlet(np.ones(nvtx), size=case.N)
        if case.disturbance == "vertex":
            alphas = np.eye(nvtx)[rng.integers(nvtx, size=case.N)]
        A_seq = [sum(a[i] * Av[i] for i in range(nvtx)) for a in alphas]
        rho = alphas @ theta
        (lo, hi), x, y, delta = _sim_plant(case, rng, A_seq=A_seq)
        xh = 0.5 * (lo + hi)
        obs = hinf.LPVEllipsoidalSMObserver(design, xh, hinf.mu0_from_box(design, lo - xh, hi - xh))
        traj = obs.run(y, rho=rho)
    elif name == "interval_luenberger":
        plant = s.plant()
        (lo, hi), x, y, delta = _sim_plant(case, rng)
        ones_d, ones_v = np.ones(s.Fd.shape[1]), np.ones(s.Z.shape[1])
        obs = interval_observers.IntervalLuenbergerObserver(plant, Box(lo, hi), 0.5 * (lo + hi),
                                                            Box(-ones_d, ones_d), Box(-ones_v, ones_v))
        traj = obs.run(y)
    elif name == "interval_invariant":
        plant = s.plant()
        (lo, hi), x, y, delta = _sim_plant(case, rng)
        ones_d, ones_v = np.ones(s.Fd.shape[1]), np.ones(s.Z.shape[1])
        design = interval_observers.offline_error_sequence(plant, Box(lo, hi), 0.5 * (lo + hi),
                                                           Box(-ones_d, ones_d), Box(-ones_v, ones_v))
        obs = interval_observers.IntervalInvariantObserver(design)
        traj = obs.run(y)
    elif name == "interval_nonlinear":
        # x⁺ = A x + h_k + Fd d with the state disturbance folded into the box of h (F = I)
        hr = case.options["h_rad"] + np.abs(s.Fd).sum(axis=1)
        plant = Plant(s.A, s.C, Fd=np.eye(s.nx), Z=s.Z)
        case_h = Case(case.estimator, case.seed, RandomSystem(s.A, s.C, np.zeros((s.nx, 0)), s.Z, s.T, s.family,
                                                              s.nx, s.ny), case.disturbance, case.N)
        (lo, hi), x, y, delta = _sim_plant(case_h, rng, h=hr)
        ones_v = np.ones(s.Z.shape[1])
        obs = interval_observers.NonlinearIntervalObserver(plant, Box(lo, hi), 0.5 * (lo + hi),
                                                           Box(-ones_v, ones_v), Box(-hr, hr))
        traj = obs.run(y)
    else:  # pragma: no cover - guarded by ESTIMATORS
        raise ValueError(name)
    _check_boxes(traj.lower, traj.upper, x, delta, res, traj.flagged)  # fault-free data: a flag is a bug


# interval_invariant: n_x <= 4, its offline design (polyhedral invariant set Φ_0 and the
# shrinking sequence) took more than 5 min of CPU for one n_x = 8 case.
# Time-varying A (interval A, LPV): only the |A| recursion bounds the simulation error, and it
# grows when ρ(|A|) > 1, so those runs are kept short (steps beyond it would be unverified).
@dataclass(frozen=True)
class _Spec:
    index: int
    run: object
    max_nx: int = 8
    horizon: int = 200
    stable_only: bool = False
    max_nw: int = 16
    # trajectories simulated per design (fresh initial state and disturbances each): the
    # ellipsoidal LMI designs cost seconds at n_x = 8, far more than their steps
    runs_per_design: int = 1


#: The guaranteed estimators of the campaign (name → how a case is run).
ESTIMATORS = {
    "ell_offline": _Spec(0, _run_ellipsoidal, max_nw=4, horizon=4000, runs_per_design=4),
    "ell_online_vertex": _Spec(1, _run_ellipsoidal, max_nw=4, horizon=1000, runs_per_design=6),
    "ell_online_scaled": _Spec(2, _run_ellipsoidal, max_nw=4, horizon=1000, runs_per_design=6),
    "ell_improved": _Spec(3, _run_ellipsoidal, max_nw=4, horizon=1000, runs_per_design=6),
    "ell_interval_A": _Spec(4, _run_ellipsoidal, max_nw=3, horizon=200, runs_per_design=8),
    "descriptor": _Spec(5, _run_descriptor, max_nw=4, horizon=4000, runs_per_design=4),
    "zono_segment_min": _Spec(6, _run_zonotopic, horizon=1000),
    # one row of the gain's L1 problem per subset of n_x − 1 generators at every step (n_x + 2
    # generators kept: at most 120 rows at n_x = 8)
    "zono_volume_min": _Spec(7, _run_zonotopic, max_nw=8, horizon=600),
    "pradius": _Spec(8, _run_zonotopic, horizon=1000),
    # CORA's zonotopic catalogue on the shared skeleton (estimators/zonotopic/observer.hpp);
    # Bravo's horizon (600) dates from when its candidates cost O(n² m²) per strip (now
    # O(n² m)); kept so that the recorded campaigns stay comparable
    "zono_bravo": _Spec(40, _run_zonotopic, horizon=600),
    "zono_wang": _Spec(41, _run_zonotopic, horizon=1000),
    "zono_combastel": _Spec(42, _run_zonotopic, horizon=1000),
    "zono_strip_gain": _Spec(43, _run_zonotopic, horizon=1000),
    "zono_propagation": _Spec(44, _run_zonotopic, horizon=1000),
    # FRad-A and VolMin-A on the shared skeleton (ZonotopicObserver's segment_min / volume_min
    # rules), and its strip-based rules with an interval A (the prior kept as columns)
    "zono_obs_segment_min": _Spec(45, _run_zonotopic, horizon=1000),
    "zono_obs_volume_min": _Spec(46, _run_zonotopic, max_nw=8, horizon=600),
    "zono_obs_interval_A": _Spec(47, _run_zonotopic, max_nw=8, horizon=200),
    "thesis_sm_observer": _Spec(9, _run_thesis, horizon=4000),
    "thesis_lpv": _Spec(10, _run_thesis, horizon=300),
    "interval_luenberger": _Spec(11, _run_thesis, horizon=2000),
    "interval_invariant": _Spec(12, _run_thesis, horizon=4000, max_nx=4),
    "interval_nonlinear": _Spec(13, _run_thesis, horizon=2000),
    # constrained zonotopes in the default bounded mode (4 n_x rows, 24 n_x generators)
    "czn_a": _Spec(14, _run_constrained_zonotopic, horizon=1000),
    "czn_b": _Spec(15, _run_constrained_zonotopic, horizon=1000),
    # CORA's catalogue (issue 22), default convention
    "eso_a_obe": _Spec(16, _run_bounding_ellipsoid, horizon=2000),
    "eso_b_liu": _Spec(17, _run_bounding_ellipsoid, horizon=2000),
    # CORA's ROPO, Vicino–Zappa parallelotopes (setbound.parallelotope), default convention
    "ropo": _Spec(18, _run_zonotopic, horizon=1000),
    # ESO-D (CORA's name): design_eso_d + the thesis observer; up to 200 feasibility SDPs per design
    "eso_d": _Spec(19, _run_thesis, horizon=2000),
}


def run_case(estimator: str, seed: int, max_nx: int = 8, max_steps: int | None = None) -> CaseResult:
    """Runs the case ``(estimator, seed)`` (n_x at most ``max_nx``, at most ``max_steps`` steps)
    and checks containment at every step.

    Parameters
    ----------
    estimator : str
        Estimator name.
    seed : int
        Seed.
    max_nx : int, optional
        Largest state dimension.
    max_steps : int, optional
        Largest horizon.

    Returns
    -------
    CaseResult
    """
    case = random_case(estimator, seed, max_nx)
    if max_steps is not None:
        case.N = max(2, min(case.N, int(max_steps)))
    s = case.system
    res = CaseResult(estimator, int(seed), s.nx, s.family, case.disturbance, "ok",
                     options={k: v for k, v in case.options.items() if isinstance(v, (str, int))})
    res.command_options = (f" --max-nx {max_nx}" if max_nx != 8 else "") + (
        f" --max-steps {max_steps}" if max_steps is not None else "")
    rng = np.random.default_rng([seed, 1000 + ESTIMATORS[estimator].index])
    try:
        ESTIMATORS[estimator].run(case, res, rng)
    except SetboundError as e:
        if res.steps == 0:
            res.status, res.reason = "design_failed", f"{type(e).__name__}: {e}"
        else:
            res.status, res.reason = "step_failed", f"{type(e).__name__}: {e}"
    return res


def campaign_case(context: dict, case: dict) -> dict:
    """The campaign's task (:mod:`setbound.studies.executor`): :func:`run_case` of
    ``case["estimator"]``, ``case["seed"]`` with ``context["max_nx"]``/``["max_steps"]``, as a
    plain dict (the :class:`CaseResult` fields, ``violations`` as ``[step, excess]`` pairs, and
    ``reproduce``).

    Parameters
    ----------
    context : dict
        ``max_nx``, ``max_steps``.
    case : dict
        ``estimator``, ``seed``.

    Returns
    -------
    dict
    """
    r = run_case(case["estimator"], case["seed"], context["max_nx"], context["max_steps"])
    rec = dataclasses.asdict(r)
    rec["violations"] = [[int(k), float(e)] for k, e in r.violations]
    rec.update(i=case["i"], key=case["key"], reproduce=r.reproduce())
    return rec


def _reproduce(context):
    opts = (f" --max-nx {context['max_nx']}" if context["max_nx"] != 8 else "") + (
        f" --max-steps {context['max_steps']}" if context["max_steps"] is not None else "")

    def reproduce(case) -> str:
        return f"python -m setbound.campaign --estimator {case['estimator']} --seed {case['seed']}{opts} --verbose"
    return reproduce


def run_campaign(estimators=None, steps: int = 100_000, *, processes: int = 2, seed0: int = 0,
                 max_nx: int = 8, max_steps: int | None = None, time_limit: float | None = None,
                 progress=None, client=None, scheduler: str | None = None, scheduler_file: str | None = None,
                 timeout: float = 30.0, out=None, resume: bool = False) -> dict:
    """Runs cases ``seed0, seed0 + 1, …`` of each estimator until ``steps`` steps were checked
    (or ``time_limit`` seconds per estimator passed). Returns ``{name: summary}`` with
    ``systems``, ``design_failed`` (count and the distinct reasons), ``steps``, ``violations``
    (each with seed, step, excess and the reproduction command), ``crashed`` (cases that killed
    their worker, with the command), ``max_excess`` and ``seconds``.

    The cases run on :mod:`setbound.studies` (Dask): an embedded LocalCluster of ``processes``
    worker processes, an existing cluster (``scheduler``, ``scheduler_file``) or the caller's
    ``client`` (left open); ``processes=1`` runs them one after the other in this process. Cases are
    submitted while the steps (or the time) are not reached, one case per task and one task per
    worker thread in flight, so a few cases past the target may run (all are counted).

    ``out`` (a folder) checkpoints the run: every finished case is appended to a
    :class:`setbound.studies.store.ResultStore` there (one JSON line per case, fsync-ed), so a
    killed or timed-out campaign loses at most the cases in flight. With ``resume=True`` the cases
    already in ``out`` are read back into the summaries and skipped, and the campaign continues
    until ``steps`` is reached (a larger ``steps`` than the first run extends it; a resume with
    another ``seed0``, ``max_nx`` or ``max_steps`` is refused, since they decide what each case is).
    ``seconds`` then counts this run only and ``resumed_cases`` how many came from the folder.

    Parameters
    ----------
    estimators : list of str, optional
        Estimator names (default: every guaranteed one).
    steps : int, optional
        Steps to check per estimator.
    processes : int, optional
        Workers of the embedded cluster (1: serial).
    seed0 : int, optional
        First seed.
    max_nx : int, optional
        Largest state dimension.
    max_steps : int, optional
        Largest horizon of a case.
    time_limit : float, optional
        Seconds per estimator.
    progress : callable, optional
        Called with progress reports.
    client, scheduler, scheduler_file : optional
        An existing Dask cluster (see :class:`setbound.studies.Engine`).
    timeout : float, optional
        Seconds to reach a scheduler.
    out : str or path-like, optional
        Checkpoint folder (a :class:`setbound.studies.store.ResultStore`).
    resume : bool, optional
        Continue the run checkpointed in ``out``.

    Returns
    -------
    dict
        ``{estimator: summary}``.
    """
    from .studies.engine import Engine
    from .studies.executor import run_cases

    names = list(ESTIMATORS) if not estimators else list(estimators)
    for n in names:
        if n not in ESTIMATORS:
            raise ValueError(f"estimators: expected names among {', '.join(ESTIMATORS)}, got {n!r}")
    steps = as_int(steps, "steps", lo=1, hi=None)
    seed0 = as_int(seed0, "seed0", lo=0, hi=2**62)
    max_nx = as_int(max_nx, "max_nx", lo=1, hi=64)
    if max_steps is not None:
        max_steps = as_int(max_steps, "max_steps", lo=2, hi=None)
    if time_limit is not None:
        time_limit = as_float(time_limit, "time_limit", lo=0, lo_open=True)
    context = {"max_nx": max_nx, "max_steps": max_steps}
    store, previous = _open_store(out, resume, seed0, context)
    summaries = {}
    with Engine(client=client, scheduler=scheduler, scheduler_file=scheduler_file, processes=processes,
                timeout=timeout) as engine:
        for name in names:
            t0 = time.monotonic()
            summ = {"systems": 0, "design_failed": 0, "step_failed": 0, "reasons": {}, "steps": 0, "violations": [],
                    "max_excess": -math.inf, "nx_max": 0, "families": {}, "seeds": [seed0, seed0], "unverified": 0,
                    "undecided": 0, "false_alarms": 0, "crashed": [], "resumed_cases": 0}
            done = set()
            for r in previous.get(name, ()):
                _accumulate(summ, r)
                done.add(r["seed"])
            summ["resumed_cases"] = len(done)

            def more() -> bool:
                return summ["steps"] < steps and (time_limit is None or time.monotonic() - t0 < time_limit)

            def cases(name=name, more=more, done=done):
                seed = seed0
                while more():
                    if seed not in done:
                        yield {"i": seed - seed0, "key": f"{name}:{seed}", "estimator": name, "seed": seed}
                    seed += 1

            def sink(records, summ=summ):
                if store is not None:
                    store.append(records)
                for r in records:
                    _accumulate(summ, r)

            # One case per task and one task per worker thread in flight, as the fork pool had: case
            # durations are heavy-tailed (a design can take seconds where a run takes milliseconds),
            # so a chunk sized on the fast cases could hold a few slow ones and run far past the
            # time limit; and the steps target is checked after every case.
            run_cases("setbound.campaign:campaign_case", cases(), sink, context=context, engine=engine,
                      max_chunk=1, max_in_flight=engine.threads, reproduce=_reproduce(context), label=name,
                      quiet=True)
            summ["violations"].sort(key=lambda v: (v["seed"], v["step"]))
            summ["crashed"].sort(key=lambda c: c["seed"])
            summ["seconds"] = round(time.monotonic() - t0, 1)
            summaries[name] = summ
            if progress:
                progress(name, summ)
    if store is not None:
        store.close()
    return summaries


def _open_store(out, resume, seed0: int, context: dict):
    """The checkpoint folder of a campaign (None without ``out``) and the records it already holds,
    by estimator (empty unless resuming)."""
    if out is None:
        return None, {}
    from .studies.store import ResultStore

    resume = as_bool(resume, "resume")
    options = {"seed0": seed0, "max_nx": context["max_nx"], "max_steps": context["max_steps"]}
    store = ResultStore(out, {"kind": "campaign", "options": options, "cases": None}, resume=resume)
    previous: dict = {}
    if store.resumed:
        seen = set()
        for r in store.records():
            name, seed = r.get("estimator"), r.get("seed")
            if name not in ESTIMATORS or not isinstance(seed, int):
                from .studies.store import StoreError
                raise StoreError(f"out: {store.out}: a record names estimator {name!r} and seed {seed!r}, "
                                 f"not a campaign case")
            if (name, seed) in seen:  # a case re-run after a torn write elsewhere: count it once
                continue
            seen.add((name, seed))
            previous.setdefault(name, []).append(r)
    return store, previous


def _accumulate(summ: dict, r: dict) -> None:
    """Adds one case record (:func:`campaign_case`, or a crashed/error record) to an estimator's
    summary."""
    summ["systems"] += 1
    summ["seeds"][1] = max(summ["seeds"][1], r["seed"])
    if r["status"] in ("crashed", "error"):  # the case killed its worker, or raised outside SetboundError
        summ["crashed"].append({"seed": r["seed"], "status": r["status"], "reason": r.get("reason", ""),
                                "reproduce": r.get("reproduce", "")})
        return
    if r["status"] != "ok":
        summ[r["status"]] += 1
        key = r["reason"].split(":")[0] + ": " + r["reason"].split(":", 1)[-1].strip()[:90]
        summ["reasons"][key] = summ["reasons"].get(key, 0) + 1
    summ["steps"] += r["steps"]
    summ["unverified"] += r["unverified"]
    summ["undecided"] = summ.get("undecided", 0) + r.get("undecided", 0)  # records before it had no field
    summ["false_alarms"] += r["false_alarms"]
    summ["nx_max"] = max(summ["nx_max"], r["nx"] if r["steps"] else 0)
    if r["steps"]:
        summ["families"][r["family"]] = summ["families"].get(r["family"], 0) + r["steps"]
    summ["max_excess"] = max(summ["max_excess"], r["max_excess"])
    for k, e in r["violations"][:3]:
        summ["violations"].append({"seed": r["seed"], "step": k, "excess": e, "nx": r["nx"], "family": r["family"],
                                   "disturbance": r["disturbance"], "reproduce": r["reproduce"]})


def format_table(summary: dict) -> str:
    """The campaign table (one row per estimator).

    Parameters
    ----------
    summary : dict
        From :func:`run_campaign`.

    Returns
    -------
    str
    """
    head = (f"{'estimator':22} {'systems':>7} {'failed':>6} {'steps':>8} {'viol.':>5} {'false al.':>9} "
            f"{'max excess':>11} {'s':>6}")
    lines = [head, "-" * len(head)]
    for name, s in summary.items():
        lines.append(f"{name:22} {s['systems']:7d} {s['design_failed'] + s['step_failed']:6d} {s['steps']:8d} "
                     f"{len(s['violations']):5d} {s.get('false_alarms', 0):9d} {s['max_excess']:11.2e} "
                     f"{s['seconds']:6.0f}")
    return "\n".join(lines)


def main(argv=None) -> int:
    """Command line (see the module docstring); exits 1 when a violation was found.

    Parameters
    ----------
    argv : list of str, optional
        Arguments.

    Returns
    -------
    int
    """
    ap = argparse.ArgumentParser(prog="python -m setbound.campaign", description=__doc__.split("\n\n")[0])
    ap.add_argument("--estimator", action="append", choices=list(ESTIMATORS))
    ap.add_argument("--steps", type=int, default=100_000, help="steps per estimator (default 100000)")
    ap.add_argument("--seed", type=int, help="run this one case (with --estimator) and print it")
    ap.add_argument("--seed0", type=int, default=0, help="first seed of the campaign")
    ap.add_argument("--processes", type=int, default=2,
                    help="worker processes of the embedded Dask cluster (1: serially in this process)")
    ap.add_argument("--scheduler", help="run on an existing Dask scheduler (tcp://HOST:PORT)")
    ap.add_argument("--scheduler-file", help="run on the Dask scheduler of this scheduler file")
    ap.add_argument("--timeout", type=float, default=30.0, help="seconds to reach the scheduler (default 30)")
    ap.add_argument("--max-nx", type=int, default=8)
    ap.add_argument("--max-steps", type=int, default=None, help="steps per case at most")
    ap.add_argument("--time-limit", type=float, default=None, help="seconds per estimator at most")
    ap.add_argument("--json", help="write the summary to this file")
    ap.add_argument("--out", help="checkpoint every finished case into this folder (a ResultStore)")
    ap.add_argument("--resume", action="store_true",
                    help="with --out: read the cases already there and continue to --steps")
    ap.add_argument("--verbose", action="store_true")
    a = ap.parse_args(argv)
    if a.resume and not a.out:
        ap.error("--resume needs --out (the folder to resume)")
    if a.seed is not None:
        bad = 0
        for name in a.estimator or list(ESTIMATORS):
            r = run_case(name, a.seed, a.max_nx, a.max_steps)
            print(f"{name} seed={a.seed} nx={r.nx} family={r.family} disturbance={r.disturbance} "
                  f"options={r.options} status={r.status} steps={r.steps} unverified={r.unverified} undecided={r.undecided} "
                  f"max_excess={r.max_excess:.3e} false_alarms={r.false_alarms}"
                  + (f" reason={r.reason}" if r.reason else ""))
            for k, e in r.violations:
                print(f"  violation at step {k}: excess {e:.3e}")
            bad += len(r.violations) + r.false_alarms
        return 1 if bad else 0
    t0 = time.monotonic()

    def progress(name, s):
        print(f"{name}: {s['steps']} steps, {s['systems']} systems ({s['design_failed']} designs failed), "
              f"{len(s['violations'])} violations, max excess {s['max_excess']:.2e}, {s['unverified']} unverified, {s.get('undecided', 0)} undecided "
              f"({s['seconds']} s)",
              file=sys.stderr, flush=True)

    try:
        summary = run_campaign(a.estimator, a.steps, processes=a.processes, seed0=a.seed0, max_nx=a.max_nx,
                               max_steps=a.max_steps, time_limit=a.time_limit, progress=progress,
                               scheduler=a.scheduler, scheduler_file=a.scheduler_file, timeout=a.timeout,
                               out=a.out, resume=a.resume)
    except (ValueError, ConnectionError) as exc:
        print(f"{ap.prog}: error: {exc}", file=sys.stderr)
        return 2
    print(format_table(summary))
    total = time.monotonic() - t0
    print(f"total {total:.0f} s, {sum(s['steps'] for s in summary.values())} steps, "
          f"{sum(len(s['violations']) for s in summary.values())} violations, "
          f"{sum(s['false_alarms'] for s in summary.values())} false alarms, "
          f"{sum(s.get('undecided', 0) for s in summary.values())} undecided steps")
    for name, s in summary.items():
        for v in s["violations"][:5]:
            print(f"VIOLATION {name} seed={v['seed']} step={v['step']} excess={v['excess']:.3e}: {v['reproduce']}")
        for c in s["crashed"][:5]:
            print(f"CRASHED {name} seed={c['seed']} ({c['status']}: {c['reason']}): {c['reproduce']}")
    if a.json:
        os.makedirs(os.path.dirname(os.path.abspath(a.json)), exist_ok=True)
        with open(a.json, "w") as f:
            json.dump({"total_seconds": round(total, 1), "tau": TAU, "estimators": summary}, f, indent=1,
                      default=float)
    return 1 if any(s["violations"] or s["false_alarms"] or s["crashed"] for s in summary.values()) else 0


if __name__ == "__main__":
    sys.exit(main())
