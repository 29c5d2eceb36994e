"""Ellipsoids, zonotopes and strips (Methods › Sets, intervals and LMI tools › Ellipsoids, Methods › Sets, intervals and LMI tools › Intervals and interval arithmetic), through the C ABI.

* :class:`Ellipsoid` — ``E(P, c, rho) = {x : (x - c)ᵀ P (x - c) <= rho}``; ``rho`` is a
  *level*, not a squared radius, so ``(P, rho)`` and ``(tP, t rho)`` are the same set.
* :class:`Zonotope` — ``Z = p ⊕ H B^m = {p + H z : z in [-1, 1]^m}``.
* :class:`Strip` — ``S = {x : |cᵀx - y| <= phi}``.

Every constructor validates through the C library, so bad input raises the same
:class:`setbound.SetboundError` subclass and message (naming the argument: ``P``, ``c``,
``rho``, ``p``, ``H``, ``phi``, ...) as in C and C++. The objects are immutable: their arrays
are read-only copies. Exact linear operations (Minkowski sum, linear image, translation)
are plain numpy; everything else (bounds, volumes, support functions, membership,
reduction, strip intersection, interval images, change of shape) is computed by the C
library.
"""
from __future__ import annotations

import numpy as np

from ._native import as_f64, check, dptr, ffi, lib
from ._validate import INT_MAX, as_bool, as_choice, as_float, as_int, as_str
from .errors import DimensionError, InvalidArgumentError

__all__ = ["Ellipsoid", "Zonotope", "Strip", "interval_linear_map", "as_box", "as_zonotope", "as_ellipsoid"]

#: Reduction methods accepted by :meth:`Zonotope.reduce`.
REDUCTION_METHODS = {"combastel": lib.SB_REDUCE_COMBASTEL, "girard": lib.SB_REDUCE_GIRARD,
                     "pca": lib.SB_REDUCE_PCA}


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=np.float64, copy=True, order="C")
    a.flags.writeable = False
    return a


def _scalar(x, name: str) -> float:
    """A real number (not a string, bool or None); NaN and ±Inf pass to the library, which
    reports them (NotFiniteError) as it does to C callers."""
    return as_float(x, name, finite=False, nan=True)


def _batch(x, n: int, name: str):
    """A point/direction or a (k, n) batch of them; returns (2-D array, was_single)."""
    a = as_f64(x, name)
    if a.ndim == 1:
        if a.shape[0] != n:
            raise DimensionError(f"{name}: expected length {n} (or shape (k, {n})), got shape {a.shape}")
        return a.reshape(1, n), True
    return as_f64(a, name, shape=(None, n)), False


def _int_array(k: int):
    return ffi.new("int[]", max(k, 1))


class Strip:
    """A strip ``S = {x : |cᵀx - y| <= phi}`` (the states consistent with one bounded measurement).

    Parameters
    ----------
    c : array_like, shape (n,)
        Normal vector, not zero.
    y : float
        Measurement.
    phi : float
        Half-width, ``phi >= 0`` (measurement units).

    Examples
    --------
    >>> S = setbound.Strip([1.0, 0.0], 0.5, 0.25)
    >>> S.contains([[0.5, 9.0], [1.0, 0.0]])
    array([ True, False])
    """

    def __init__(self, c, y, phi):
        c = as_f64(c, "c", ndim=1)
        if c.shape[0] == 0:
            raise DimensionError("c: the strip normal must have at least one entry")
        self._c = _readonly(c)
        self._y = _scalar(y, "y")
        self._phi = _scalar(phi, "phi")
        # An empty batch validates c, y and phi in the library.
        check(lib.sb_strip_contains(self.n, dptr(self._c), self._y, self._phi, 0, ffi.NULL, 0.0, ffi.NULL))

    c = property(lambda self: self._c, doc="Normal vector c.")
    y = property(lambda self: self._y, doc="Measurement y.")
    phi = property(lambda self: self._phi, doc="Half-width phi (measurement units).")
    n = property(lambda self: int(self._c.shape[0]), doc="Dimension.")

    @property
    def width(self) -> float:
        """Euclidean distance between the two bounding hyperplanes, ``2 phi / ||c||``."""
        return 2.0 * self._phi / float(np.linalg.norm(self._c))

    def half_spaces(self):
        """``[(a1, b1), (a2, b2)]`` with ``S = {a1ᵀx <= b1} ∩ {a2ᵀx <= b2}``."""
        return [(self._c.copy(), self._y + self._phi), (-self._c, self._phi - self._y)]

    def contains(self, points, rel_tol: float = 1e-12):
        """Membership of a point or of each row of a batch.

        Parameters
        ----------
        points : array_like, shape (n,) or (k, n)
            One point or ``k`` points (rows).
        rel_tol : float, optional
            Relative tolerance on the boundary.

        Returns
        -------
        bool or ndarray of bool
            ``True`` where the point is in the strip.
        """
        X, single = _batch(points, self.n, "points")
        out = _int_array(X.shape[0])
        check(lib.sb_strip_contains(self.n, dptr(self._c), self._y, self._phi, X.shape[0], dptr(X),
                                    as_float(rel_tol, "rel_tol", lo=0.0), out))
        res = np.array([bool(out[i]) for i in range(X.shape[0])])
        return bool(res[0]) if single else res

    def __repr__(self) -> str:
        return f"Strip(c={self._c.tolist()}, y={self._y}, phi={self._phi})"


class Ellipsoid:
    """An ellipsoid ``E(P, c, rho) = {x : (x - c)ᵀ P (x - c) <= rho}``.

    ``rho`` is a *level*, not a squared radius: ``(P, rho)`` and ``(tP, t rho)`` describe the same
    set (Methods › Sets, intervals and LMI tools › Ellipsoids).

    Parameters
    ----------
    P : array_like, shape (n, n)
        Shape matrix, symmetric positive definite.
    center : array_like, shape (n,)
        Centre ``c``.
    rho : float
        Level ``rho > 0``.

    Raises
    ------
    NotSymmetricError, NotPositiveDefiniteError, DimensionError, NotFiniteError
        When ``P``, ``center`` or ``rho`` are not valid (the message names the argument).

    Examples
    --------
    >>> E = setbound.Ellipsoid(np.eye(2), [0.0, 0.0], 4.0)
    >>> lo, hi = E.bounding_box()
    >>> print(lo.round(6), hi.round(6))
    [-2. -2.] [2. 2.]
    >>> bool(E.contains([1.0, 1.0]))
    True
    """

    def __init__(self, P, center, rho):
        c = as_f64(center, "c", ndim=1)
        n = c.shape[0]
        if n == 0:
            raise DimensionError("c: the ellipsoid must have dimension >= 1")
        P = as_f64(P, "P", shape=(n, n))
        rho = _scalar(rho, "rho")
        check(lib.sb_ellipsoid_validate(n, dptr(P), dptr(c), rho))
        self._P, self._c, self._rho = _readonly(P), _readonly(c), rho

    P = property(lambda self: self._P, doc="Shape matrix P (read-only).")
    center = property(lambda self: self._c, doc="Centre c (read-only).")
    rho = property(lambda self: self._rho, doc="Level rho (not a squared radius).")
    n = property(lambda self: int(self._c.shape[0]), doc="Dimension.")

    def _args(self):
        return self.n, dptr(self._P), dptr(self._c), self._rho

    def bounding_box(self):
        """``(lo, hi)`` = ``c ∓ sqrt(rho diag(P⁻¹))`` (thesis (1.40)), rounded outward."""
        lo, hi = np.empty(self.n), np.empty(self.n)
        check(lib.sb_ellipsoid_bounding_box(*self._args(), dptr(lo), dptr(hi)))
        return lo, hi

    @property
    def volume(self) -> float:
        """``V_n rho^(n/2) / sqrt(det P)``."""
        return self._volume()[0]

    @property
    def log_volume(self) -> float:
        """Natural log of the volume (finite where the volume itself would overflow)."""
        return self._volume()[1]

    def _volume(self):
        v = ffi.new("double[2]")
        check(lib.sb_ellipsoid_volume(*self._args(), v, v + 1))
        return float(v[0]), float(v[1])

    def contains(self, points, rel_tol: float = 1e-12):
        """Membership of a point or of each row of a batch.

        Parameters
        ----------
        points : array_like, shape (n,) or (k, n)
            One point or ``k`` points (rows).
        rel_tol : float, optional
            Relative tolerance on the boundary.

        Returns
        -------
        bool or ndarray of bool
            ``True`` where the point is in the ellipsoid.
        """
        X, single = _batch(points, self.n, "points")
        out = _int_array(X.shape[0])
        check(lib.sb_ellipsoid_contains(*self._args(), X.shape[0], dptr(X), as_float(rel_tol, "rel_tol", lo=0.0), out))
        res = np.array([bool(out[i]) for i in range(X.shape[0])])
        return bool(res[0]) if single else res

    def support(self, d):
        """Support function ``h(d) = dᵀc + sqrt(rho dᵀP⁻¹d)``.

        Parameters
        ----------
        d : array_like, shape (n,) or (k, n)
            One direction or ``k`` directions (rows).

        Returns
        -------
        float or ndarray
            The support value(s).
        """
        D, single = _batch(d, self.n, "directions")
        out = np.empty(D.shape[0])
        check(lib.sb_ellipsoid_support(*self._args(), D.shape[0], dptr(D), dptr(out)))
        return float(out[0]) if single else out

    def affine_map(self, M, b=None) -> "Ellipsoid":
        """Image under ``x -> M x + b``.

        Parameters
        ----------
        M : array_like, shape (n, n)
            Square, invertible matrix.
        b : array_like, shape (n,), optional
            Translation (zero when omitted).

        Returns
        -------
        Ellipsoid
            The image ``E(M⁻ᵀPM⁻¹, Mc + b, rho)``.
        """
        n = self.n
        M = as_f64(M, "M", shape=(n, n))
        b = np.zeros(n) if b is None else as_f64(b, "b", shape=(n,))
        P_out, c_out, r_out = np.empty((n, n)), np.empty(n), ffi.new("double*")
        check(lib.sb_ellipsoid_affine_map(*self._args(), dptr(M), dptr(b), dptr(P_out), dptr(c_out), r_out))
        return Ellipsoid(P_out, c_out, r_out[0])

    def level_for_shape(self, P_new) -> float:
        """Smallest level ``rho'`` with ``E(P, c, rho) ⊆ E(P_new, c, rho')`` (rounded up, certified).

        This is the change of shape of Methods › Sets, intervals and LMI tools › Ellipsoids:
        ``rho' = rho · λ_max(P^(-1/2) P_new P^(-1/2))``.

        Parameters
        ----------
        P_new : array_like, shape (n, n)
            The new shape matrix (symmetric positive definite).

        Returns
        -------
        float
            The level ``rho'``.
        """
        P_new = as_f64(P_new, "P_new", shape=(self.n, self.n))
        r = ffi.new("double*")
        check(lib.sb_ellipsoid_level_for_shape(*self._args(), dptr(P_new), r))
        return float(r[0])

    def with_shape(self, P_new) -> "Ellipsoid":
        """The smallest ellipsoid of shape ``P_new`` and the same centre containing this one.

        Parameters
        ----------
        P_new : array_like, shape (n, n)
            The new shape matrix (symmetric positive definite).

        Returns
        -------
        Ellipsoid
            ``E(P_new, c, level_for_shape(P_new))``.
        """
        return Ellipsoid(P_new, self._c, self.level_for_shape(P_new))

    reshape = with_shape

    def __repr__(self) -> str:
        return f"Ellipsoid(n={self.n}, center={self._c.tolist()}, rho={self._rho})"


class Zonotope:
    """A zonotope ``Z = p ⊕ H B^m = {p + H z : z in [-1, 1]^m}``.

    Methods › Sets, intervals and LMI tools › Zonotopes. ``Z1 + Z2`` is the Minkowski sum and
    ``M @ Z`` the linear image, both exact.

    Parameters
    ----------
    center : array_like, shape (n,)
        Centre ``p``.
    generators : array_like, shape (n, m), optional
        Generator matrix ``H`` (columns are the generators; ``m`` may be 0). Default: no generator.

    Examples
    --------
    >>> Z = setbound.Zonotope([0.0, 0.0], [[1.0, 1.0], [0.0, 1.0]])
    >>> lo, hi = Z.interval_hull()
    >>> print(lo, hi)
    [-2. -1.] [2. 1.]
    >>> Z.volume
    4.0
    """

    # Make ``ndarray @ Zonotope`` defer to Zonotope.__rmatmul__ instead of broadcasting.
    __array_ufunc__ = None

    def __init__(self, center, generators=None):
        p = as_f64(center, "p", ndim=1)
        n = p.shape[0]
        if n == 0:
            raise DimensionError("p: the zonotope must have dimension >= 1")
        H = np.zeros((n, 0)) if generators is None else as_f64(generators, "H", ndim=2)
        if H.shape[0] != n:
            raise DimensionError(f"H: expected {n} rows (the length of p), got shape {H.shape}")
        H = np.ascontiguousarray(H)
        check(lib.sb_zonotope_validate(n, H.shape[1], dptr(p), dptr(H)))
        self._p, self._H = _readonly(p), _readonly(H)

    center = property(lambda self: self._p, doc="Centre p (read-only).")
    generators = property(lambda self: self._H, doc="Generator matrix H, n×m (read-only).")
    n = property(lambda self: int(self._p.shape[0]), doc="Dimension.")
    m = property(lambda self: int(self._H.shape[1]), doc="Number of generators.")

    @property
    def order(self) -> float:
        """m / n."""
        return self.m / self.n

    def _args(self):
        return self.n, self.m, dptr(self._p), dptr(self._H)

    # -- exact operations -------------------------------------------------------------
    def __add__(self, other):
        """Minkowski sum ``(p1 + p2) ⊕ [H1 H2] B``; a vector operand translates."""
        if isinstance(other, Zonotope):
            if other.n != self.n:
                raise DimensionError(f"other: expected a zonotope of dimension {self.n}, got {other.n}")
            return Zonotope(self._p + other._p, np.hstack([self._H, other._H]))
        return self.translate(other)

    __radd__ = __add__

    def translate(self, b) -> "Zonotope":
        """The zonotope moved by a vector.

        Parameters
        ----------
        b : array_like, shape (n,)
            Translation.

        Returns
        -------
        Zonotope
            ``(p + b) ⊕ H B^m``.
        """
        b = as_f64(b, "b", shape=(self.n,))
        return Zonotope(self._p + b, self._H)

    def linear_map(self, M) -> "Zonotope":
        """Linear image ``M Z = M p ⊕ M H B^m``.

        Parameters
        ----------
        M : array_like, shape (k, n)
            Any matrix with ``n`` columns.

        Returns
        -------
        Zonotope
            The image, of dimension ``k``.
        """
        M = as_f64(M, "M", shape=(None, self.n))
        if M.shape[0] == 0:
            raise DimensionError("M: expected at least one row")
        return Zonotope(M @ self._p, M @ self._H)

    def __rmatmul__(self, M):
        return self.linear_map(M)

    # -- computed by the library ------------------------------------------------------
    def interval_hull(self):
        """``(lo, hi)`` = ``p ∓ Σ_j |H_ij|``, rounded outward."""
        lo, hi = np.empty(self.n), np.empty(self.n)
        check(lib.sb_zonotope_interval_hull(*self._args(), dptr(lo), dptr(hi)))
        return lo, hi

    @property
    def volume(self) -> float:
        """Exact ``2^n Σ_S |det H_S|`` (refused with InvalidArgumentError if C(m, n) > 5e6)."""
        v = ffi.new("double*")
        check(lib.sb_zonotope_volume(*self._args(), v))
        return float(v[0])

    def pradius(self, P, return_vertex: bool = False):
        """Exact P-radius ``max_{s in {-1,1}^m} sᵀHᵀPHs`` (Methods › Zonotopic estimation › P-radius designs).

        Enumerates the vertices of the unit box: ``m <= 24``.

        Parameters
        ----------
        P : array_like, shape (n, n)
            Symmetric positive (semi)definite weight.
        return_vertex : bool, optional
            Also return the maximising ``s``.

        Returns
        -------
        float or (float, ndarray)
            The P-radius, and the maximising vertex when ``return_vertex``.
        """
        return_vertex = as_bool(return_vertex, "return_vertex")
        P = as_f64(P, "P", shape=(self.n, self.n))
        r = ffi.new("double*")
        s = np.empty(self.m)
        check(lib.sb_zonotope_pradius(*self._args(), dptr(P), r, dptr(s) if self.m else ffi.NULL))
        return (float(r[0]), s) if return_vertex else float(r[0])

    def support(self, d):
        """Support function ``h(d) = dᵀp + ||Hᵀd||_1``.

        Parameters
        ----------
        d : array_like, shape (n,) or (k, n)
            One direction or ``k`` directions (rows).

        Returns
        -------
        float or ndarray
            The support value(s).
        """
        D, single = _batch(d, self.n, "directions")
        out = np.empty(D.shape[0])
        check(lib.sb_zonotope_support(*self._args(), D.shape[0], dptr(D), dptr(out)))
        return float(out[0]) if single else out

    def contains(self, points, rel_tol: float = 1e-9):
        """Exact membership of a point or of each row of a batch (facet enumeration).

        Parameters
        ----------
        points : array_like, shape (n,) or (k, n)
            One point or ``k`` points (rows).
        rel_tol : float, optional
            Relative tolerance on the boundary.

        Returns
        -------
        bool or ndarray of bool
            ``True`` where the point is in the zonotope.
        """
        X, single = _batch(points, self.n, "points")
        out = _int_array(X.shape[0])
        check(lib.sb_zonotope_contains(*self._args(), X.shape[0], dptr(X), as_float(rel_tol, "rel_tol", lo=0.0), out))
        res = np.array([bool(out[i]) for i in range(X.shape[0])])
        return bool(res[0]) if single else res

    def reduce(self, limit: int, method: str = "combastel") -> "Zonotope":
        """Outer approximation with at most ``limit`` generators (order reduction).

        ``"combastel"``: keep the ``limit - n`` longest generators, box the rest ([Le2013]
        Property 3). ``"girard"``: keep the ``limit - n`` largest ``||g||_1 - ||g||_inf``,
        box the rest (Girard 2005). ``"pca"``: Girard's choice, the rest boxed in the
        eigenbasis of its Gram matrix (CORA's ``reduce(Z,'pca',order)``). Zero columns are
        dropped; the result always contains the zonotope (rounding included). See
        Methods › Zonotopic estimation › Order reduction.

        Parameters
        ----------
        limit : int
            Largest number of generators kept, ``>= n``.
        method : {"combastel", "girard", "pca"}, optional
            Which generators are kept.

        Returns
        -------
        Zonotope
            A zonotope containing this one with at most ``limit`` generators.
        """
        method = as_choice(method, "method", REDUCTION_METHODS)
        limit = as_int(limit, "limit", lo=None, hi=None)
        # clamped to a C int: any limit >= m gives the same result (nothing is sized by the
        # limit, only by min(limit, m)), and a limit < n is reported by the library
        limit = max(min(limit, INT_MAX), -INT_MAX - 1)
        cap = max(0, min(self.m, limit))  # limit < n is reported by the library
        H_out = np.empty((self.n, max(cap, 1)))
        m_out = ffi.new("int*", cap)
        check(lib.sb_zonotope_reduce(*self._args(), REDUCTION_METHODS[method], limit, m_out, dptr(H_out)))
        k = int(m_out[0])
        return Zonotope(self._p, H_out.ravel()[: self.n * k].reshape(self.n, k))

    def intersect_strip(self, strip: Strip, lam) -> "Zonotope":
        """The zonotope ``p̂(λ) ⊕ Ĥ(λ) B^(m+1)`` containing ``Z ∩ strip`` ([Le2013] Property 6).

        ``p̂ = p + λ (y - cᵀp)`` and ``Ĥ = [(I - λcᵀ) H, phi λ]``; the inclusion holds for every ``λ``
        (Methods › Zonotopic estimation › Estimator structure).

        Parameters
        ----------
        strip : Strip
            The strip of one measurement.
        lam : array_like, shape (n,)
            Correction gain ``λ``.

        Returns
        -------
        Zonotope
            The corrected zonotope (one more generator).
        """
        if not isinstance(strip, Strip):
            raise InvalidArgumentError(f"strip: expected a setbound.sets.Strip, got {type(strip).__name__}")
        if strip.n != self.n:
            raise DimensionError(f"c: the strip has dimension {strip.n}, the zonotope {self.n}")
        lam = as_f64(lam, "lambda", shape=(self.n,))
        p_out, H_out = np.empty(self.n), np.empty((self.n, self.m + 1))
        check(lib.sb_zonotope_intersect_strip(*self._args(), dptr(strip.c), strip.y, strip.phi, dptr(lam),
                                              dptr(p_out), dptr(H_out)))
        return Zonotope(p_out, H_out)

    def interval_linear_map(self, mid, rad) -> "Zonotope":
        """A zonotope containing ``A z`` for every ``A in [mid - rad, mid + rad]`` and ``z in Z``.

        Parameters
        ----------
        mid : array_like, shape (k, n)
            Midpoint of the interval matrix.
        rad : array_like, shape (k, n)
            Entrywise radius, ``>= 0``.

        Returns
        -------
        Zonotope
            See :func:`interval_linear_map`.
        """
        return interval_linear_map(mid, rad, self)

    def __repr__(self) -> str:
        return f"Zonotope(n={self.n}, m={self.m}, center={self._p.tolist()})"


def interval_linear_map(mid, rad, Z: Zonotope) -> Zonotope:
    """A zonotope containing the image of a zonotope by an interval matrix.

    ``[A] Z ⊆ mid p ⊕ [mid H, rs(rad |H|), diag(rad |p|)] B^(m+2k)``
    (Methods › Zonotopic estimation › Interval uncertainty).

    Parameters
    ----------
    mid : array_like, shape (k, n)
        Midpoint of the interval matrix ``[A]``.
    rad : array_like, shape (k, n)
        Entrywise radius, ``>= 0``.
    Z : Zonotope
        The zonotope mapped.

    Returns
    -------
    Zonotope

    Examples
    --------
    >>> Z = setbound.Zonotope([1.0, 0.0], np.eye(2))
    >>> out = setbound.sets.interval_linear_map(np.eye(2), 0.1 * np.eye(2), Z)
    >>> lo, hi = out.interval_hull()
    >>> print(np.round(lo, 6), np.round(hi, 6))
    [-0.2 -1.1] [2.2 1.1]
    """
    if not isinstance(Z, Zonotope):
        raise InvalidArgumentError(f"Z: expected a setbound.sets.Zonotope, got {type(Z).__name__}")
    mid = as_f64(mid, "mid", shape=(None, Z.n))
    k = mid.shape[0]
    if k == 0:
        raise DimensionError("mid: expected at least one row")
    rad = as_f64(rad, "rad", shape=(k, Z.n))
    p_out, H_out = np.empty(k), np.empty((k, Z.m + 2 * k))
    check(lib.sb_zonotope_interval_linear_map(k, Z.n, Z.m, dptr(mid), dptr(rad), dptr(Z.center),
                                              dptr(Z.generators), dptr(p_out), dptr(H_out)))
    return Zonotope(p_out, H_out)



# ---------------------------------------------------------------- conversions between set types
# Every estimator accepts any initial set (issue 24): the set it needs is a guaranteed enclosure
# of the one given (outward-rounded hulls; the ellipsoid through the corners of the hull with a
# relative margin that covers the rounding of its shape).

def _hull(X, name: str):
    from .interval import Box

    if isinstance(X, Box):
        return np.asarray(X.lo, dtype=float), np.asarray(X.hi, dtype=float)
    if isinstance(X, Zonotope):
        return X.interval_hull()
    if isinstance(X, Ellipsoid):
        return X.bounding_box()
    raise InvalidArgumentError(f"{name}: expected a setbound.Box, Zonotope or Ellipsoid, got {type(X).__name__}")


def as_box(X, name: str = "x0"):
    """A set as a :class:`~setbound.interval.Box`: a box unchanged, else its interval hull (outward rounded).

    Parameters
    ----------
    X : Box, Zonotope or Ellipsoid
        The set.
    name : str, optional
        Argument name used in error messages.

    Returns
    -------
    Box

    Examples
    --------
    >>> b = setbound.sets.as_box(setbound.Zonotope([0.0, 0.0], [[1.0, 1.0], [0.0, 1.0]]))
    >>> print(np.round(b.lo, 9), np.round(b.hi, 9))  # rounded outward by a few ulps
    [-2. -1.] [2. 1.]
    """
    name = as_str(name, "name")
    from .interval import Box

    if isinstance(X, Box):
        return X
    lo, hi = _hull(X, name)
    return Box(lo, hi, name=name)


def as_zonotope(X, name: str = "x0") -> Zonotope:
    """A set as a :class:`Zonotope` containing it: a zonotope unchanged, a box exactly, an ellipsoid by its bounding box.

    Parameters
    ----------
    X : Box, Zonotope or Ellipsoid
        The set.
    name : str, optional
        Argument name used in error messages.

    Returns
    -------
    Zonotope

    Examples
    --------
    >>> Z = setbound.sets.as_zonotope(setbound.Box([0.0, -1.0], [2.0, 1.0]))
    >>> Z.center.tolist(), Z.generators.tolist()
    ([1.0, 0.0], [[1.0, 0.0], [0.0, 1.0]])
    """
    name = as_str(name, "name")
    if isinstance(X, Zonotope):
        return X
    lo, hi = _hull(X, name)
    return Zonotope((lo + hi) / 2, np.diag((hi - lo) / 2))


def as_ellipsoid(X, name: str = "x0") -> Ellipsoid:
    """A set as an :class:`Ellipsoid` containing it.

    An ellipsoid is returned unchanged; a box or a zonotope is replaced by the ellipsoid through the
    corners of its interval hull, ``Σ (x_i − c_i)² / (n r_i²) ≤ 1`` (which contains the hull: each
    term is at most 1/n there). A flat coordinate (r_i = 0) gets a radius of 1e-9 of the hull's
    scale, so the shape stays positive definite.

    Parameters
    ----------
    X : Box, Zonotope or Ellipsoid
        The set.
    name : str, optional
        Argument name used in error messages.

    Returns
    -------
    Ellipsoid

    Examples
    --------
    >>> E = setbound.sets.as_ellipsoid(setbound.Box([-1.0, -1.0], [1.0, 1.0]))
    >>> bool(E.contains([1.0, 1.0]))  # the corners of the box are inside
    True
    """
    name = as_str(name, "name")
    if isinstance(X, Ellipsoid):
        return X
    lo, hi = _hull(X, name)
    n = lo.size
    c = (lo + hi) / 2
    r = (hi - lo) / 2 * (1 + 1e-12)
    scale = max(float(np.max(np.abs(np.concatenate([lo, hi])))), 1.0)
    r = np.maximum(r, 1e-9 * scale)
    return Ellipsoid(np.diag(1.0 / (n * r ** 2)), c, 1.0 + 1e-9)
