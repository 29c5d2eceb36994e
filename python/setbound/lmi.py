"""The bundled LMI solver (``include/setbound/lmi``), through the C ABI.

Problem form: minimise ``c @ x`` subject to, for every block ``(F0, Fs)``,
``F0 + sum_i x[i] * Fs[i] ⪰ 0`` (1×1 blocks are linear inequalities), optional equalities
``Aeq @ x == beq`` and an optional objective term ``-log det(G0 + sum_i x[i] * Gs[i])``.

* :func:`solve` — one-shot solve (the contract of issue 3).
* :class:`Problem` — set up once, update values, solve many times with tiny per-call
  overhead (preallocated buffers, cffi pointers made once); also feasibility, GEVP and the
  verified margin of a point.

Statuses are the strings ``"optimal"``, ``"infeasible"``, ``"unbounded"``,
``"max_iterations"``, ``"numerical_error"`` and ``"inaccurate"``. ``margin`` is verified: a
Cholesky factorisation of ``F_b(x) - margin*I`` succeeded for every block (``margin < 0``
means ``x`` is not feasible); code that needs a guarantee must check it.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from ._native import as_f64, check, dptr, ffi, lib
from ._state import ThreadSafe
from ._validate import _is_int, as_bool, as_float, as_int
from .errors import DimensionError, InvalidArgumentError

STATUS_NAMES = {
    lib.SB_LMI_OPTIMAL: "optimal",
    lib.SB_LMI_INFEASIBLE: "infeasible",
    lib.SB_LMI_UNBOUNDED: "unbounded",
    lib.SB_LMI_MAX_ITERATIONS: "max_iterations",
    lib.SB_LMI_NUMERICAL_ERROR: "numerical_error",
    lib.SB_LMI_INACCURATE: "inaccurate",
}


@dataclass
class LmiResult:
    """Result of a solve.

    For ``"infeasible"``, ``x`` is NaN and ``Z``/``y`` hold the certificate (``Z_b ⪰ 0``,
    ``Σ tr(F_b0 Z_b) + beq·y = −1``, ``tr(F_bi Z) = (Aeqᵀy)_i``).

    Parameters
    ----------
    status : str
        ``"optimal"``, ``"infeasible"``, ``"unbounded"``, ``"max_iterations"``,
        ``"numerical_error"`` or ``"inaccurate"``.
    x : ndarray
        The point (NaN when infeasible).
    objective : float
        Primal objective at ``x``.
    iterations : int
        Interior-point iterations.
    margin : float
        Verified margin of ``x``: every block minus ``margin·I`` has a Cholesky factor (negative:
        ``x`` is not feasible).
    solve_time : float
        Seconds.
    dual_objective, gap, relative_gap : float, optional
        Dual objective and duality gaps.
    primal_residual, dual_residual : float, optional
        Relative residuals.
    Z : list of ndarray, optional
        Dual matrices of the blocks.
    y : ndarray, optional
        Dual variables of the equalities.
    """

    status: str
    x: np.ndarray
    objective: float
    iterations: int
    margin: float
    solve_time: float
    dual_objective: float = float("nan")
    gap: float = float("nan")
    relative_gap: float = float("nan")
    primal_residual: float = float("nan")
    dual_residual: float = float("nan")
    Z: list = field(default_factory=list)
    y: np.ndarray | None = None

    @property
    def ok(self) -> bool:
        """True when the point is optimal (or certified feasible) with a positive margin."""
        return self.status == "optimal" and self.margin > 0


def _block_arrays(F0, Fs, m: int, name: str):
    F0a = as_f64(F0, f"{name}[0] (F0)", ndim=2)
    if F0a.shape[0] != F0a.shape[1] or F0a.shape[0] == 0:
        raise DimensionError(f"{name}: F0 must be a non-empty square matrix, got shape {F0a.shape}")
    n = F0a.shape[0]
    Fsa = as_f64(Fs, f"{name}[1] (Fs)", shape=(m, n, n))
    return F0a, Fsa, n


#: Largest ``num_vars`` of a :class:`Problem` (the dense Schur complement: 32 GiB at 65536).
MAX_VARS = lib.SB_LMI_MAX_VARS  # the C library refuses more too
#: Upper bound of ``max_iter`` (an interior-point solve converges in a few dozen iterations).
MAX_ITER = 100_000
#: Upper bound of ``tol`` (relative gap) and of the gevp bisection tolerance.
MAX_TOL = 0.1
#: Upper bound of ``feas``: the certificates are accepted at residual <= feas × objective.
MAX_FEAS = 0.01
#: Lower bound of the gevp bisection tolerance (a few rounding steps of λ).
MIN_GEVP_TOL = 1e-12
#: Upper bound of ``threads`` (the library's own limit).
MAX_THREADS = 256


class Problem(ThreadSafe):
    """A reusable LMI problem: set up once, then update values and re-solve.

    One problem may be shared by threads: each call runs under the problem's own lock.

    Parameters
    ----------
    num_vars : int
        Number of scalar decision variables.

    Examples
    --------
    Minimise ``x`` subject to ``[[x, 1], [1, 1]] ⪰ 0`` (that is ``x >= 1``):

    >>> p = setbound.lmi.Problem(1)
    >>> p.set_objective([1.0])
    >>> p.add_block([[0.0, 1.0], [1.0, 1.0]], [[[1.0, 0.0], [0.0, 0.0]]])
    0
    >>> r = p.solve()
    >>> r.status, round(float(r.x[0]), 4)
    ('optimal', 1.0)
    """

    def __init__(self, num_vars: int):
        """``num_vars``: the number of scalar decision variables, an integer in
        [1, ``MAX_VARS``] (65536: the dense Schur complement of a solve has num_vars² entries,
        32 GiB at the bound, so a larger problem cannot be solved by this solver anyway)."""
        if _is_int(num_vars) and num_vars <= 0:
            # a count of zero is a dimension, as the C library reports it
            raise DimensionError(f"num_vars: expected an integer in [1, {MAX_VARS}], got {num_vars}")
        num_vars = as_int(num_vars, "num_vars", lo=1, hi=MAX_VARS)
        h = ffi.new("sb_lmi_problem**")
        check(lib.sb_lmi_problem_create(int(num_vars), h))
        self._h = ffi.gc(h[0], lib.sb_lmi_problem_free)
        self.num_vars = int(num_vars)
        self._sizes: list[int] = []
        self._neq = 0
        self._res = ffi.new("sb_lmi_result*")
        self._x = np.empty(self.num_vars)
        self._xp = dptr(self._x)

    # --- set-up ------------------------------------------------------------------------
    def set_objective(self, c) -> None:
        """Set the linear objective ``cᵀx``.

        Parameters
        ----------
        c : array_like, shape (num_vars,)
            Objective coefficients.
        """
        ca = as_f64(c, "c", shape=(self.num_vars,))
        check(lib.sb_lmi_set_objective(self._h, dptr(ca)))

    def add_block(self, F0, Fs) -> int:
        """Add the block ``F0 + Σ_i x_i Fs[i] ⪰ 0``.

        Parameters
        ----------
        F0 : array_like, shape (n, n)
            Constant term (symmetric).
        Fs : array_like, shape (num_vars, n, n)
            Coefficient of each variable (symmetric).

        Returns
        -------
        int
            The index of the block (for :meth:`update_block`).
        """
        F0a, Fsa, n = _block_arrays(F0, Fs, self.num_vars, "block")
        idx = ffi.new("int*")
        check(lib.sb_lmi_add_block(self._h, n, dptr(F0a), dptr(Fsa), idx))
        self._sizes.append(n)
        return int(idx[0])

    def update_block(self, index: int, F0, Fs) -> None:
        """Replace the values of a block (no re-analysis of the structure).

        Parameters
        ----------
        index : int
            Index returned by :meth:`add_block`.
        F0 : array_like, shape (n, n)
            New constant term.
        Fs : array_like, shape (num_vars, n, n)
            New coefficients.
        """
        index = as_int(index, "index", lo=None)
        if not 0 <= index < len(self._sizes):
            raise InvalidArgumentError(f"index: block {index} out of range [0, {len(self._sizes)})")
        n = self._sizes[index]
        F0a = as_f64(F0, "F0", shape=(n, n))
        Fsa = as_f64(Fs, "Fs", shape=(self.num_vars, n, n))
        check(lib.sb_lmi_update_block(self._h, int(index), n, dptr(F0a), dptr(Fsa)))

    def set_logdet(self, G0, Gs) -> None:
        """Set the objective term ``-log det(G0 + Σ x_i Gs[i])``; ``None`` removes it.

        Parameters
        ----------
        G0 : array_like, shape (n, n) or None
            Constant term.
        Gs : array_like, shape (num_vars, n, n) or None
            Coefficients.
        """
        if G0 is None:
            check(lib.sb_lmi_set_logdet(self._h, 0, ffi.NULL, ffi.NULL))
            return
        G0a, Gsa, n = _block_arrays(G0, Gs, self.num_vars, "logdet")
        check(lib.sb_lmi_set_logdet(self._h, n, dptr(G0a), dptr(Gsa)))

    def set_equalities(self, Aeq, beq) -> None:
        """Set the equality constraints ``Aeq x = beq``.

        Parameters
        ----------
        Aeq : array_like, shape (q, num_vars)
            Constraint matrix.
        beq : array_like, shape (q,)
            Right-hand side.
        """
        A = as_f64(Aeq, "Aeq", ndim=2)
        if A.shape[1] != self.num_vars:
            raise DimensionError(f"Aeq: expected {self.num_vars} columns, got shape {A.shape}")
        b = as_f64(beq, "beq", shape=(A.shape[0],))
        check(lib.sb_lmi_set_equalities(self._h, A.shape[0], dptr(A), dptr(b)))
        self._neq = A.shape[0]

    def set_options(self, *, tol=None, max_iter=None, feas=None, time_limit=None, threads=None) -> None:
        """Solver options; ``None`` is the library default.

        A value given earlier is reset to the default by ``None``, except ``threads``, which keeps its
        last value. Values that are not numbers, ``bool``, NaN, ±Inf or out of range raise
        InvalidArgumentError naming the option (before anything changes); ``0`` or negative values are
        errors, not "default" (pass ``None``).

        Parameters
        ----------
        tol : float, optional
            Relative duality gap in (0, 0.1] (default 1e-7; ``feas`` then defaults to tol/10).
        max_iter : int, optional
            Iterations, in [1, 100000] (default 100; an interior-point solve converges in a few dozen,
            the bound keeps a typo from running for hours).
        feas : float, optional
            Relative residual of the solution and of the infeasibility/unboundedness certificates, in
            (0, 0.01] (default 1e-8). The certificates are accepted when their residual is below
            ``feas`` times their objective, so a larger value would certify any iterate.
        time_limit : float, optional
            Seconds, finite and > 0 (default 30).
        threads : int, optional
            Threads over the blocks inside each solve, in [1, 256] (default 1; see
            :func:`threads_available`); worth it from a few dozen blocks, and the results agree with
            the serial solve to rounding.
        """
        tol = None if tol is None else as_float(tol, "tol", lo=0.0, hi=MAX_TOL, lo_open=True)
        max_iter = None if max_iter is None else as_int(max_iter, "max_iter", lo=1, hi=MAX_ITER)
        feas = None if feas is None else as_float(feas, "feas", lo=0.0, hi=MAX_FEAS, lo_open=True)
        time_limit = None if time_limit is None else as_float(time_limit, "time_limit", lo=0.0, lo_open=True)
        threads = None if threads is None else as_int(threads, "threads", lo=1, hi=MAX_THREADS)
        if threads is not None:
            check(lib.sb_lmi_set_threads(self._h, threads))
            if tol is None and max_iter is None and feas is None and time_limit is None:
                return  # only the threads: the other options stay as they are
        if tol is not None and feas is None:
            feas = tol * 0.1
        # 0 is the C ABI's "default" (a Python None): the values above are all > 0
        check(lib.sb_lmi_set_options(self._h, max_iter or 0, tol or 0.0, feas or 0.0, time_limit or 0.0))

    # --- solving -----------------------------------------------------------------------
    def solve(self, *, feasibility: bool = False, duals: bool = True) -> LmiResult:
        """Solve the problem (maxdet if a log-det term is set).

        Parameters
        ----------
        feasibility : bool, optional
            Stop at the first certified strictly feasible point.
        duals : bool, optional
            Copy the dual matrices into the result (``False``: fastest path for repeated solves).

        Returns
        -------
        LmiResult
        """
        feasibility = as_bool(feasibility, "feasibility")
        duals = as_bool(duals, "duals")
        cls = lib.SB_LMI_CLASS_FEASIBILITY if feasibility else lib.SB_LMI_CLASS_AUTO
        check(lib.sb_lmi_solve_class(self._h, cls, self._res, self._xp))
        return self._result(duals)

    def _result(self, duals: bool) -> LmiResult:
        r = self._res
        out = LmiResult(
            STATUS_NAMES.get(r.status, "numerical_error"),
            self._x.copy(),
            r.objective,
            r.iterations,
            r.margin,
            r.solve_time,
            r.dual_objective,
            r.gap,
            r.relative_gap,
            r.primal_residual,
            r.dual_residual,
        )
        if duals:
            out.Z = self.duals()
            if self._neq:
                y = np.empty(self._neq)
                check(lib.sb_lmi_dual_eq(self._h, dptr(y)))
                out.y = y
        return out

    def duals(self) -> list[np.ndarray]:
        """The dual matrix of every block from the last solve (the infeasibility certificate after
        an infeasible solve)."""
        Zs = []
        for b, n in enumerate(self._sizes):
            Z = np.empty((n, n))
            check(lib.sb_lmi_dual(self._h, b, ffi.cast("double*", ffi.from_buffer(Z))))
            Zs.append(Z)
        return Zs

    def margin(self, x) -> float:
        """Verified margin of a point (negative: the point is not feasible).

        Parameters
        ----------
        x : array_like, shape (num_vars,)
            The point.

        Returns
        -------
        float
        """
        xa = as_f64(x, "x", shape=(self.num_vars,))
        out = ffi.new("double*")
        check(lib.sb_lmi_margin(self._h, dptr(xa), out))
        return float(out[0])

    def gevp(self, A, B, *, lambda_lo=0.0, lambda_hi=1.0, tol=1e-6) -> tuple[float, LmiResult]:
        """Minimise λ subject to ``λB(x) − A(x) ⪰ 0``, ``B(x) ≻ 0`` and this problem's blocks.

        Parameters
        ----------
        A, B : (array_like, array_like)
            Pairs ``(M0, Ms)`` of affine matrix functions, as in :meth:`add_block`.
        lambda_lo, lambda_hi : float, optional
            Finite numbers bracketing λ, ``lambda_lo < lambda_hi``.
        tol : float, optional
            Relative bisection tolerance in [1e-12, 0.1] (the bisection stops at ``tol·max(1, |λ|)``).

        Returns
        -------
        lam : float
            The smallest λ found.
        result : LmiResult
            ``result.x`` is a certified point at λ and ``result.dual_objective`` a
            certified-infeasible lower value.
        """
        lambda_lo = as_float(lambda_lo, "lambda_lo")
        lambda_hi = as_float(lambda_hi, "lambda_hi")
        if not lambda_lo < lambda_hi:
            raise InvalidArgumentError(f"lambda_lo: must be < lambda_hi, got {lambda_lo:g} >= {lambda_hi:g}")
        tol = as_float(tol, "tol", lo=MIN_GEVP_TOL, hi=MAX_TOL)
        A0, As, n = _block_arrays(A[0], A[1], self.num_vars, "A")
        B0 = as_f64(B[0], "B0", shape=(n, n))
        Bs = as_f64(B[1], "Bs", shape=(self.num_vars, n, n))
        lam = ffi.new("double*")
        check(
            lib.sb_lmi_solve_gevp(
                self._h, n, dptr(A0), dptr(As), dptr(B0), dptr(Bs),
                float(lambda_lo), float(lambda_hi), float(tol), self._res, lam, self._xp,
            )
        )
        return float(lam[0]), self._result(False)


def solve(
    c,
    blocks: Sequence,
    *,
    logdet=None,
    eq=None,
    tol: float | None = None,
    max_iter: int | None = None,
    threads: int | None = None,
) -> LmiResult:
    """Solve one LMI problem (one-shot form of :class:`Problem`).

    Minimise ``c @ x`` (− log det G(x) with ``logdet=(G0, Gs)``) subject to
    ``F0 + Σ x_i Fs[i] ⪰ 0`` for every ``(F0, Fs)`` in ``blocks`` and ``Aeq x = beq`` for
    ``eq=(Aeq, beq)``.

    Parameters
    ----------
    c : array_like, shape (num_vars,)
        Linear objective.
    blocks : sequence of (array_like, array_like)
        The LMI blocks ``(F0, Fs)``.
    logdet : (array_like, array_like), optional
        ``(G0, Gs)`` of a ``-log det`` objective term.
    eq : (array_like, array_like), optional
        ``(Aeq, beq)``.
    tol, max_iter, threads : optional
        As :meth:`Problem.set_options` (checked before the problem is built).

    Returns
    -------
    LmiResult

    Examples
    --------
    >>> r = setbound.lmi.solve([1.0], [([[0.0, 1.0], [1.0, 1.0]], [[[1.0, 0.0], [0.0, 0.0]]])])
    >>> r.status, round(float(r.x[0]), 4)
    ('optimal', 1.0)
    """
    tol = None if tol is None else as_float(tol, "tol", lo=0.0, hi=MAX_TOL, lo_open=True)
    max_iter = None if max_iter is None else as_int(max_iter, "max_iter", lo=1, hi=MAX_ITER)
    threads = None if threads is None else as_int(threads, "threads", lo=1, hi=MAX_THREADS)
    ca = as_f64(c, "c", ndim=1)
    if ca.shape[0] == 0:
        raise DimensionError("c: the problem needs at least one variable, got shape (0,)")
    if blocks is None:
        raise InvalidArgumentError("blocks: a list of (F0, Fs) pairs is required")
    blocks = list(blocks)
    if not blocks and logdet is None:
        raise InvalidArgumentError("blocks: the problem has no LMI block (add at least one)")
    p = Problem(ca.shape[0])
    p.set_objective(ca)
    for i, blk in enumerate(blocks):
        if isinstance(blk, np.ndarray) or not isinstance(blk, (tuple, list)) or len(blk) != 2:
            raise InvalidArgumentError(f"blocks[{i}]: expected a pair (F0, Fs)")
        F0, Fs = blk
        F0a, Fsa, n = _block_arrays(F0, Fs, ca.shape[0], f"blocks[{i}]")
        idx = ffi.new("int*")
        check(lib.sb_lmi_add_block(p._h, n, dptr(F0a), dptr(Fsa), idx))
        p._sizes.append(n)
    if logdet is not None:
        try:
            G0, Gs = logdet
        except (TypeError, ValueError):
            raise InvalidArgumentError("logdet: expected a pair (G0, Gs)") from None
        p.set_logdet(G0, Gs)
    if eq is not None:
        try:
            Aeq, beq = eq
        except (TypeError, ValueError):
            raise InvalidArgumentError("eq: expected a pair (Aeq, beq)") from None
        p.set_equalities(Aeq, beq)
    if tol is not None or max_iter is not None or threads is not None:
        p.set_options(tol=tol, max_iter=max_iter, threads=threads)
    return p.solve()


def threads_available() -> bool:
    """Whether the loaded library was built with OpenMP, so that ``threads > 1`` runs the
    blocks of a solve in parallel (otherwise it is accepted and the solve runs serially)."""
    return bool(lib.sb_lmi_threads_available())


__all__ = ["solve", "Problem", "LmiResult", "STATUS_NAMES", "threads_available"]
