"""Inclusion functions ([Loukkas2018] §1.2.8; Methods › Sets, intervals and LMI tools › Inclusion functions).

``[f]`` is an inclusion function of ``f`` when ``f([x]) ⊆ [f]([x])`` for every box. The three
forms below take Python callables that work on :class:`setbound.Interval` (scalar functions) or
on :class:`setbound.Box` (vector functions; index the box to get Interval components):

* :func:`natural_inclusion` — ``f`` evaluated in interval arithmetic;
* :func:`centered_inclusion` — ``f(m) + [J]([x])·([x] − m)`` (mean-value form, m = mid [x]);
* :func:`taylor2_inclusion` — ``f(m) + J(m)([x] − m) + ½([x] − m)ᵀ[H]([x])([x] − m)``.

Point values ``f(m)`` and ``J(m)`` are evaluated on the degenerate interval ``[m, m]``, so the
results stay guaranteed enclosures (the interval arithmetic rounds outward). Use
``setbound.interval.{sqr, sqrt, exp, sin, cos}`` or the Interval methods of the same names;
``sqr`` is not ``x*x`` (it is ``[0, max²]`` when ``0 ∈ [x]``).

Vector functions ``f : ℝⁿ → ℝᵖ``: ``f(box)`` returns a Box or a sequence of p Intervals;
``jac(box)`` a p×n nested sequence of Intervals (or an IntervalMatrix); ``hess(box)`` a sequence
of p such n×n matrices.
"""
from __future__ import annotations

import numpy as np

from .errors import DimensionError, InvalidArgumentError
from .interval import Box, Interval, IntervalMatrix, sqr

__all__ = ["centered_inclusion", "natural_inclusion", "taylor2_inclusion"]


def _check_arg(x, *, bounded: bool):
    if isinstance(x, Interval):
        if x.is_empty:
            raise InvalidArgumentError("x: the interval is empty")
        if bounded and not (np.isfinite(x.lo) and np.isfinite(x.hi)):
            raise InvalidArgumentError("x: the interval must be bounded")
        return "scalar"
    if isinstance(x, Box):
        if len(x) == 0:
            raise DimensionError("x: the box has dimension 0")
        if x.is_empty:
            raise InvalidArgumentError("x: the box is empty")
        if bounded and not (np.all(np.isfinite(x.lo)) and np.all(np.isfinite(x.hi))):
            raise InvalidArgumentError("x: the box must be bounded")
        return "vector"
    raise InvalidArgumentError(f"x: expected a setbound.Interval or setbound.Box, got {type(x).__name__}")


def _components(v, what: str) -> list:
    if isinstance(v, Interval):
        return [v]
    if isinstance(v, Box):
        return [v[i] for i in range(len(v))]
    try:
        out = list(v)
    except TypeError:
        raise InvalidArgumentError(f"{what}: expected a Box or a sequence of Intervals, got {type(v).__name__}") from None
    for i, c in enumerate(out):
        if not isinstance(c, Interval):
            out[i] = Interval(float(c))
    return out


def _matrix(M, rows: int, cols: int, what: str) -> list:
    if isinstance(M, IntervalMatrix):
        lo, hi = np.asarray(M.lo), np.asarray(M.hi)
        M = [[Interval(lo[i, j], hi[i, j]) for j in range(lo.shape[1])] for i in range(lo.shape[0])]
    M = [list(r) for r in M]
    if len(M) != rows or any(len(r) != cols for r in M):
        shape = (len(M), len(M[0]) if M else 0)
        raise DimensionError(f"{what}: expected shape ({rows}, {cols}), got {shape}")
    return [[c if isinstance(c, Interval) else Interval(float(c)) for c in r] for r in M]


def natural_inclusion(f, x):
    """Natural inclusion: ``f`` evaluated in interval arithmetic on ``x``.

    Methods › Sets, intervals and LMI tools › Inclusion functions.

    Parameters
    ----------
    f : callable
        ``f(Interval) -> Interval`` or ``f(Box) -> Box`` (or a sequence of Intervals).
    x : Interval or Box
        The argument (scalar or vector function).

    Returns
    -------
    Interval or Box

    Examples
    --------
    >>> f = lambda x: x * x - 2 * x
    >>> print(setbound.inclusion.natural_inclusion(f, setbound.Interval(0.0, 1.0)))
    Interval(-2.0, 1.0)
    """
    _check_arg(x, bounded=False)
    return f(x)


def centered_inclusion(f, df, x):
    """Centered (mean-value) form ``f(m) + [J]([x])·([x] − m)``, ``m = mid [x]``.

    Methods › Sets, intervals and LMI tools › Inclusion functions.

    Parameters
    ----------
    f : callable
        The function, as for :func:`natural_inclusion`.
    df : callable
        An inclusion of ``f′`` (scalar) or of the Jacobian (vector: a p×n nested sequence of
        Intervals or an IntervalMatrix).
    x : Interval or Box
        The argument (scalar or vector function).

    Returns
    -------
    Interval or Box

    Examples
    --------
    >>> f = lambda x: x * x - 2 * x
    >>> df = lambda x: 2 * x - 2
    >>> r = setbound.inclusion.centered_inclusion(f, df, setbound.Interval(0.9, 1.1))
    >>> print(round(r.lo, 9), round(r.hi, 9))  # the natural form gives [-1.39, -0.59]
    -1.02 -0.98
    """
    kind = _check_arg(x, bounded=True)
    if kind == "scalar":
        m = Interval(x.mid)
        return f(m) + df(x) * (x - m)
    mid = np.asarray(x.center)
    M = Box(mid, mid)
    fm = _components(f(M), "f")
    n = len(x)
    J = _matrix(df(x), len(fm), n, "jacobian")
    d = [x[j] - Interval(mid[j]) for j in range(n)]
    out = []
    for i in range(len(fm)):
        s = fm[i]
        for j in range(n):
            s = s + J[i][j] * d[j]
        out.append(s)
    return _box(out)


def taylor2_inclusion(f, df, d2f, x):
    """Order-2 Taylor form ``f(m) + J(m)([x] − m) + ½([x] − m)ᵀ[H]([x])([x] − m)``.

    The quadratic term uses ``sqr`` on the diagonal (scalar case: ``½·sqr([x] − m)·[f″]([x])``).

    Parameters
    ----------
    f : callable
        The function, as for :func:`natural_inclusion`.
    df : callable
        Its derivative or Jacobian (evaluated at the midpoint).
    d2f : callable
        An inclusion of ``f″`` (scalar) or of the Hessians (vector: a sequence of p n×n matrices).
    x : Interval or Box
        The argument (scalar or vector function).

    Returns
    -------
    Interval or Box

    Examples
    --------
    >>> f = lambda x: x * x - 2 * x
    >>> r = setbound.inclusion.taylor2_inclusion(f, lambda x: 2 * x - 2, lambda x: setbound.Interval(2.0),
    ...                                          setbound.Interval(0.9, 1.1))
    >>> r.contains(-1.0) and r.hi - r.lo < 0.05
    True
    """
    kind = _check_arg(x, bounded=True)
    if kind == "scalar":
        m = Interval(x.mid)
        d = x - m
        return f(m) + df(m) * d + 0.5 * sqr(d) * d2f(x)
    mid = np.asarray(x.center)
    M = Box(mid, mid)
    fm = _components(f(M), "f")
    n, p = len(x), len(fm)
    Jm = _matrix(df(M), p, n, "jacobian")
    Hs = list(d2f(x))
    if len(Hs) != p:
        raise DimensionError(f"hessian count: expected {p} matrices, got {len(Hs)}")
    d = [x[j] - Interval(mid[j]) for j in range(n)]
    out = []
    for i in range(p):
        H = _matrix(Hs[i], n, n, "hessian")
        s = fm[i]
        for j in range(n):
            s = s + Jm[i][j] * d[j]
        q = Interval(0.0)
        for j in range(n):
            q = q + H[j][j] * sqr(d[j])
            for k in range(j + 1, n):
                q = q + (H[j][k] + H[k][j]) * (d[j] * d[k])
        out.append(s + 0.5 * q)
    return _box(out)


def _box(components: list) -> Box:
    lo = np.array([c.lo for c in components], dtype=float)
    hi = np.array([c.hi for c in components], dtype=float)
    return Box(lo, hi)
