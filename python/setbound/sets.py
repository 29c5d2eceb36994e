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

__all__ = ["Ellipsoid", "Zonotope", "Strip", "ConstrainedZonotope", "Emptiness", "interval_linear_map", "as_box",
           "as_zonotope", "as_ellipsoid", "as_constrained_zonotope"]

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



# ---------------------------------------------------------------- constrained zonotopes

#: Reductions accepted by :meth:`ConstrainedZonotope.reduce`.
CZONO_REDUCTIONS = {"limits": lib.SB_CZONO_REDUCE_LIMITS, "cora": lib.SB_CZONO_REDUCE_CORA,
                    "remove_zero": lib.SB_CZONO_REMOVE_ZERO, "eliminate": lib.SB_CZONO_ELIMINATE,
                    "rescale": lib.SB_CZONO_RESCALE}
#: Zonotope reductions of the lifted set (keyword ``technique``).
CZONO_TECHNIQUES = {"girard": lib.SB_REDUCE_GIRARD, "pca": lib.SB_REDUCE_PCA}


class Emptiness:
    """The emptiness test of a constrained zonotope (:meth:`ConstrainedZonotope.emptiness`).

    Parameters
    ----------
    empty : bool
        True only with a verified certificate.
    conclusive : bool
        False when the LP could decide neither way (the set is then treated as not empty).
    certificate : ndarray, shape (n_c,)
        A ``y`` with ``yᵀb − ‖Aᵀy‖₁ ≥ margin > 0`` when empty (zeros otherwise): no ``ξ`` in the
        unit box satisfies ``Aξ = b``, since ``yᵀAξ ≤ ‖Aᵀy‖₁ < yᵀb``.
    margin : float
        The certified lower bound of ``yᵀb − ‖Aᵀy‖₁`` (0 when not empty).
    """

    __slots__ = ("empty", "conclusive", "certificate", "margin")

    def __init__(self, empty, conclusive, certificate, margin):
        self.empty, self.conclusive, self.certificate, self.margin = bool(empty), bool(conclusive), certificate, margin

    def __bool__(self) -> bool:
        return self.empty

    def __repr__(self) -> str:
        return f"Emptiness(empty={self.empty}, conclusive={self.conclusive}, margin={self.margin:.3g})"


class ConstrainedZonotope:
    """A constrained zonotope ``Z = {c + Gξ + diag(r)η : Aξ = b, ‖ξ‖∞ ≤ 1, ‖η‖∞ ≤ 1}``.

    Scott, Raimondo, Marseglia and Braatz, "Constrained zonotopes: a new tool for set-based
    estimation and fault detection", Automatica 69 (2016). The equality constraints make the
    intersection with a measurement exact, so the sets of :mod:`setbound.constrained_zonotopic`
    track the exact consistent set. ``r ≥ 0`` is the *rounding box*: the library keeps every
    operation an outer bound after floating-point rounding by collecting the rounding errors
    there (a few ulps of the set's size; zero for a set built from exact data).

    ``M @ Z`` is the linear image, ``Z + W`` the Minkowski sum (``W`` a zonotope, a constrained
    zonotope or a vector), ``Z & W`` the intersection. Queries (:meth:`interval_hull`,
    :meth:`support`, :meth:`contains`, :meth:`emptiness`) are certified: the hull contains the
    exact hull, and "empty" or "not a member" are reported only with a verified certificate.

    Parameters
    ----------
    center : array_like, shape (n,)
        Centre ``c``.
    generators : array_like, shape (n, n_g), optional
        Generator matrix ``G`` (default: none).
    A : array_like, shape (n_c, n_g), optional
        Constraint matrix (default: no constraint).
    b : array_like, shape (n_c,), optional
        Constraint vector.
    rounding : array_like, shape (n,), optional
        The rounding box ``r ≥ 0`` (default: zero).

    Examples
    --------
    >>> from setbound.sets import ConstrainedZonotope
    >>> Z = ConstrainedZonotope([0.0, 0.0], np.eye(2), [[1.0, 1.0]], [1.0])  # ξ1 + ξ2 = 1
    >>> lo, hi = Z.interval_hull()
    >>> print(np.round(lo, 9) + 0.0, np.round(hi, 9) + 0.0)
    [0. 0.] [1. 1.]
    >>> bool(Z.contains([0.5, 0.5])), bool(Z.contains([0.0, 0.0]))
    (True, False)
    """

    __array_ufunc__ = None

    def __init__(self, center, generators=None, A=None, b=None, rounding=None):
        c = as_f64(center, "c", ndim=1)
        n = c.shape[0]
        if n == 0:
            raise DimensionError("c: the constrained zonotope must have dimension >= 1")
        G = np.zeros((n, 0)) if generators is None else as_f64(generators, "G", ndim=2)
        if G.shape[0] != n:
            raise DimensionError(f"G: expected {n} rows (the length of c), got shape {G.shape}")
        ng = G.shape[1]
        if A is None:
            if b is not None:
                raise InvalidArgumentError("b: given without A")
            A, b = np.zeros((0, ng)), np.zeros(0)
        else:
            A = as_f64(A, "A", ndim=2)
            if A.shape[1] != ng:
                raise DimensionError(f"A: expected {ng} columns (one per generator), got shape {A.shape}")
            if b is None:
                raise InvalidArgumentError("b: required with A")
            b = as_f64(b, "b", ndim=1)
            if b.shape[0] != A.shape[0]:
                raise DimensionError(f"b: expected length {A.shape[0]} (the rows of A), got {b.shape[0]}")
        r = np.zeros(n) if rounding is None else as_f64(rounding, "r", shape=(n,))
        G, A, b, r = (np.ascontiguousarray(x, dtype=np.float64) for x in (G, A, b, r))
        check(lib.sb_czono_validate(n, ng, A.shape[0], dptr(c), dptr(G), dptr(A), dptr(b), dptr(r)))
        self._c, self._G, self._A, self._b, self._r = (_readonly(x) for x in (c, G, A, b, r))

    center = property(lambda self: self._c, doc="Centre c (read-only).")
    generators = property(lambda self: self._G, doc="Generator matrix G, n × n_g (read-only).")
    A = property(lambda self: self._A, doc="Constraint matrix A, n_c × n_g (read-only).")
    b = property(lambda self: self._b, doc="Constraint vector b, n_c (read-only).")
    rounding = property(lambda self: self._r, doc="Rounding box r ≥ 0, n (read-only).")
    n = property(lambda self: int(self._c.shape[0]), doc="Dimension.")
    ng = property(lambda self: int(self._G.shape[1]), doc="Number of generators.")
    nc = property(lambda self: int(self._A.shape[0]), doc="Number of constraints.")

    # -- construction --------------------------------------------------------------------
    @classmethod
    def from_zonotope(cls, Z) -> "ConstrainedZonotope":
        """A zonotope (or a box, an ellipsoid by its bounding box) as a constrained zonotope with no constraint.

        Parameters
        ----------
        Z : Zonotope, Box or Ellipsoid

        Returns
        -------
        ConstrainedZonotope

        Examples
        --------
        >>> from setbound.sets import ConstrainedZonotope
        >>> ConstrainedZonotope.from_zonotope(setbound.Box([0, 0], [2, 2])).nc
        0
        """
        Z = as_zonotope(Z, "Z")
        return cls(Z.center, Z.generators)

    @classmethod
    def from_bounds(cls, lo, hi) -> "ConstrainedZonotope":
        """The box ``[lo, hi]`` (an interval hull) as a constrained zonotope.

        Parameters
        ----------
        lo, hi : array_like, shape (n,)
            Lower and upper ends, ``lo ≤ hi``.

        Returns
        -------
        ConstrainedZonotope

        Examples
        --------
        >>> from setbound.sets import ConstrainedZonotope
        >>> ConstrainedZonotope.from_bounds([0, -1], [2, 1]).center.tolist()
        [1.0, 0.0]
        """
        from .interval import Box

        return cls.from_zonotope(Box(lo, hi, name="lo"))

    def _args(self):
        return (self.n, self.ng, self.nc, dptr(self._c), dptr(self._G), dptr(self._A), dptr(self._b),
                dptr(self._r))

    @staticmethod
    def _result(fn, args, n: int, ng_cap: int, nc_cap: int) -> "ConstrainedZonotope":
        """Calls a set-returning C function with output buffers of the given capacities (grown and
        called again if the library says they are too small)."""
        for _ in range(2):
            ngp, ncp = ffi.new("int*", ng_cap), ffi.new("int*", nc_cap)
            c, r = np.empty(n), np.empty(n)
            G, A, b = np.empty(max(n * ng_cap, 1)), np.empty(max(nc_cap * ng_cap, 1)), np.empty(max(nc_cap, 1))
            status = fn(*args, ngp, ncp, dptr(c), dptr(G), dptr(A), dptr(b), dptr(r))
            if status == lib.SB_ERR_BUFFER_TOO_SMALL:
                ng_cap, nc_cap = int(ngp[0]), int(ncp[0])
                continue
            check(status)
            ng, nc = int(ngp[0]), int(ncp[0])
            out = ConstrainedZonotope.__new__(ConstrainedZonotope)
            out._c, out._r = _readonly(c), _readonly(r)
            out._G = _readonly(G[:n * ng].reshape(n, ng))
            out._A = _readonly(A[:nc * ng].reshape(nc, ng))
            out._b = _readonly(b[:nc])
            return out
        check(status)

    # -- exact operations (outer bounds after rounding) ---------------------------------------
    def linear_map(self, M) -> "ConstrainedZonotope":
        """The image ``M Z`` (``M``: k × n).

        Parameters
        ----------
        M : array_like, shape (k, n)

        Returns
        -------
        ConstrainedZonotope

        Examples
        --------
        >>> from setbound.sets import ConstrainedZonotope
        >>> Z = ConstrainedZonotope.from_bounds([-1, -1], [1, 1])
        >>> (np.array([[1.0, 1.0]]) @ Z).interval_hull()[1].round(9).tolist()
        [2.0]
        """
        M = as_f64(M, "K", ndim=2)
        if M.shape[1] != self.n:
            raise DimensionError(f"K: expected shape (k, {self.n}), got {M.shape}")
        k = M.shape[0]
        c, G, r = np.empty(k), np.empty((k, self.ng)), np.empty(k)
        check(lib.sb_czono_linear_map(*self._args(), k, dptr(np.ascontiguousarray(M)), dptr(c), dptr(G), dptr(r)))
        out = ConstrainedZonotope.__new__(ConstrainedZonotope)
        out._c, out._G, out._A, out._b, out._r = _readonly(c), _readonly(G), self._A, self._b, _readonly(r)
        return out

    def __rmatmul__(self, M):
        return self.linear_map(M)

    def translate(self, v) -> "ConstrainedZonotope":
        """``Z + v`` (a Minkowski sum with a point).

        Parameters
        ----------
        v : array_like, shape (n,)

        Returns
        -------
        ConstrainedZonotope

        Examples
        --------
        >>> from setbound.sets import ConstrainedZonotope
        >>> ConstrainedZonotope.from_bounds([0], [1]).translate([1.0]).interval_hull()[0].round(9).tolist()
        [1.0]
        """
        v = as_f64(v, "v", shape=(self.n,))
        return self.minkowski_sum(ConstrainedZonotope(v))

    def minkowski_sum(self, other) -> "ConstrainedZonotope":
        """``Z ⊕ W`` with ``W`` a constrained zonotope, a zonotope or a box (exact).

        Parameters
        ----------
        other : ConstrainedZonotope, Zonotope or Box

        Returns
        -------
        ConstrainedZonotope

        Examples
        --------
        >>> from setbound.sets import ConstrainedZonotope
        >>> Z = ConstrainedZonotope.from_bounds([0, 0], [1, 1]).minkowski_sum(setbound.Zonotope([0, 0], np.eye(2)))
        >>> Z.interval_hull()[1].round(9).tolist()
        [2.0, 2.0]
        """
        W = as_constrained_zonotope(other, "other")
        if W.n != self.n:
            raise DimensionError(f"other: expected a set of dimension {self.n}, got {W.n}")
        return self._result(lib.sb_czono_minkowski_sum, (*self._args(), *W._args()[1:]), self.n,
                            self.ng + W.ng, self.nc + W.nc)

    def __add__(self, other):
        if isinstance(other, (ConstrainedZonotope, Zonotope)) or type(other).__name__ == "Box":
            return self.minkowski_sum(other)
        return self.translate(other)

    __radd__ = __add__

    def intersect(self, other, R=None) -> "ConstrainedZonotope":
        """The generalized intersection ``{x ∈ Z : R x ∈ W}`` (Scott et al. 2016, eq. 13), exact.

        Parameters
        ----------
        other : ConstrainedZonotope, Zonotope or Box
            ``W``, in ``R^k``.
        R : array_like, shape (k, n), optional
            Default: the identity (plain intersection, ``k = n``).

        Returns
        -------
        ConstrainedZonotope

        Examples
        --------
        >>> from setbound.sets import ConstrainedZonotope
        >>> Z = ConstrainedZonotope.from_bounds([0, 0], [2, 2])
        >>> Z.intersect(setbound.Box([1, 1], [3, 3])).interval_hull()[0].round(9).tolist()
        [1.0, 1.0]
        """
        W = as_constrained_zonotope(other, "other")
        if R is None:
            if W.n != self.n:
                raise DimensionError(f"other: expected a set of dimension {self.n} (or give R), got {W.n}")
            Rp = ffi.NULL
        else:
            R = np.ascontiguousarray(as_f64(R, "R", shape=(W.n, self.n)))
            Rp = dptr(R)
        return self._result(lib.sb_czono_intersect, (*self._args(), W.n, *W._args()[1:], Rp), self.n,
                            self.ng + W.ng + W.n, self.nc + W.nc + W.n)

    def __and__(self, other):
        return self.intersect(other)

    def intersect_output(self, C, y, V) -> "ConstrainedZonotope":
        """The states consistent with a measurement: ``{x ∈ Z : y − C x ∈ V}`` (exact).

        Parameters
        ----------
        C : array_like, shape (n_y, n)
            Output matrix.
        y : array_like, shape (n_y,)
            The measurement (minus any known feed-through).
        V : Zonotope, Box or ConstrainedZonotope
            The noise set in ``R^{n_y}``.

        Returns
        -------
        ConstrainedZonotope

        Examples
        --------
        >>> from setbound.sets import ConstrainedZonotope
        >>> Z = ConstrainedZonotope.from_bounds([-1, -1], [1, 1])
        >>> X = Z.intersect_output([[1.0, 0.0]], [0.5], setbound.Box([-0.1], [0.1]))
        >>> X.interval_hull()[0].round(9).tolist()
        [0.4, -1.0]
        """
        V = as_constrained_zonotope(V, "V")
        y = as_f64(y, "y", shape=(V.n,))
        Y = V.linear_map(-np.eye(V.n)).translate(y)  # y − V
        return self.intersect(Y, C)

    def intersect_strip(self, strip) -> "ConstrainedZonotope":
        """``Z ∩ {x : |hᵀx − y| ≤ σ}``: one constraint and one generator more (exact).

        Parameters
        ----------
        strip : Strip

        Returns
        -------
        ConstrainedZonotope

        Examples
        --------
        >>> from setbound.sets import ConstrainedZonotope, Strip
        >>> Z = ConstrainedZonotope.from_bounds([-1, -1], [1, 1]).intersect_strip(Strip([1.0, 1.0], 1.5, 0.1))
        >>> Z.interval_hull()[0].round(9).tolist()
        [0.4, 0.4]
        """
        if not isinstance(strip, Strip):
            raise InvalidArgumentError(f"strip: expected a setbound.Strip, got {type(strip).__name__}")
        if strip.c.shape[0] != self.n:
            raise DimensionError(f"strip: expected dimension {self.n}, got {strip.c.shape[0]}")
        return self._result(lib.sb_czono_intersect_strip, (*self._args(), dptr(strip.c), strip.y, strip.phi),
                            self.n, self.ng + 1, self.nc + 1)

    def intersect_halfspace(self, h, d) -> "ConstrainedZonotope":
        """``Z ∩ {x : hᵀx ≤ d}``: one constraint and one slack generator more (exact).

        Parameters
        ----------
        h : array_like, shape (n,)
        d : float

        Returns
        -------
        ConstrainedZonotope

        Examples
        --------
        >>> from setbound.sets import ConstrainedZonotope
        >>> Z = ConstrainedZonotope.from_bounds([-1, -1], [1, 1]).intersect_halfspace([1.0, 0.0], 0.0)
        >>> Z.interval_hull()[1].round(9).tolist()
        [0.0, 1.0]
        """
        h = np.ascontiguousarray(as_f64(h, "h", shape=(self.n,)))
        return self._result(lib.sb_czono_intersect_halfspace, (*self._args(), dptr(h), _scalar(d, "d")), self.n,
                            self.ng + 1, self.nc + 1)

    def reduce(self, method: str = "limits", *, technique: str = "girard", order: float = 20.0,
               max_generators: int | None = None, max_constraints: int | None = None) -> "ConstrainedZonotope":
        """A smaller constrained zonotope containing this one.

        Parameters
        ----------
        method : {"limits", "cora", "remove_zero", "eliminate", "rescale"}, optional
            ``"limits"`` (Scott's constraint elimination to ``max_constraints`` rows, then the
            lift reduction to ``max_generators`` generators; the estimators' bounded mode),
            ``"cora"`` (CORA's ``conZonotope/reduce``: the lifted zonotope reduced to order
            ``order``), ``"remove_zero"`` (zero rows dropped, exact), ``"eliminate"`` (Scott's
            rescaling and elimination only) or ``"rescale"`` (interval bounds of ξ mapped back to
            the unit box, no elimination).
        technique : {"girard", "pca"}, optional
            Zonotope reduction of the lifted set.
        order : float, optional
            ``"cora"``: at most ``order·n + n_c`` generators (≥ 1).
        max_generators, max_constraints : int, optional
            ``"limits"``/``"eliminate"``: defaults ``20 n + max_constraints`` and ``4 n``.

        Returns
        -------
        ConstrainedZonotope

        Examples
        --------
        >>> from setbound.sets import ConstrainedZonotope, Strip
        >>> Z = ConstrainedZonotope.from_bounds([-1, -1], [1, 1])
        >>> for k in range(6):
        ...     Z = Z.intersect_strip(Strip([1.0, 0.3 * k], 0.0, 0.5))
        >>> R = Z.reduce("limits", max_constraints=2, max_generators=6)
        >>> R.nc <= 2 and R.ng <= 6
        True
        """
        method = as_choice(method, "method", CZONO_REDUCTIONS)
        technique = as_choice(technique, "technique", CZONO_TECHNIQUES)
        order = _scalar(order, "order")
        mc = 4 * self.n if max_constraints is None else as_int(max_constraints, "max_constraints", lo=0,
                                                                hi=lib.SB_CZN_MAX_SIZE)
        mg = 20 * self.n + mc if max_generators is None else as_int(max_generators, "max_generators", lo=0,
                                                                    hi=lib.SB_CZN_MAX_SIZE)
        return self._result(lib.sb_czono_reduce, (*self._args(), CZONO_REDUCTIONS[method], CZONO_TECHNIQUES[technique],
                                                  order, mg, mc), self.n, self.ng, self.nc)

    # -- certified queries -------------------------------------------------------------------
    def interval_hull(self):
        """The interval hull (2n LPs), outward rounded: it contains the exact hull.

        Returns
        -------
        lo, hi : ndarray, shape (n,)
            ``lo = +inf``, ``hi = −inf`` when the set is certified empty.

        Examples
        --------
        >>> from setbound.sets import ConstrainedZonotope
        >>> ConstrainedZonotope.from_bounds([0, 1], [2, 3]).interval_hull()[1].round(9).tolist()
        [2.0, 3.0]
        """
        lo, hi = np.empty(self.n), np.empty(self.n)
        check(lib.sb_czono_interval_hull(*self._args(), dptr(lo), dptr(hi), ffi.NULL))
        return lo, hi

    def support(self, d):
        """Certified upper bound of ``max_{x ∈ Z} dᵀx`` (−inf when certified empty).

        Parameters
        ----------
        d : array_like, shape (n,) or (k, n)
            One direction or a batch.

        Returns
        -------
        float or ndarray, shape (k,)

        Examples
        --------
        >>> from setbound.sets import ConstrainedZonotope
        >>> round(ConstrainedZonotope.from_bounds([0, 0], [1, 1]).support([1.0, 1.0]), 9)
        2.0
        """
        D, single = _batch(d, self.n, "directions")
        D = np.ascontiguousarray(D)
        v = np.empty(D.shape[0])
        check(lib.sb_czono_support(*self._args(), D.shape[0], dptr(D), dptr(v)))
        return float(v[0]) if single else v

    def contains(self, points):
        """Membership: False only when a point is certified outside.

        Parameters
        ----------
        points : array_like, shape (n,) or (k, n)

        Returns
        -------
        bool or ndarray of bool, shape (k,)

        Examples
        --------
        >>> from setbound.sets import ConstrainedZonotope
        >>> ConstrainedZonotope.from_bounds([0, 0], [1, 1]).contains([[0.5, 0.5], [2.0, 0.0]]).tolist()
        [True, False]
        """
        X, single = _batch(points, self.n, "points")
        X = np.ascontiguousarray(X)
        out = _int_array(X.shape[0])
        check(lib.sb_czono_contains(*self._args(), X.shape[0], dptr(X), out))
        res = np.array([bool(out[k]) for k in range(X.shape[0])])
        return bool(res[0]) if single else res

    def emptiness(self) -> Emptiness:
        """The emptiness test with its certificate (Scott et al. 2016 §5, the fault-detection test).

        Returns
        -------
        Emptiness

        Examples
        --------
        >>> from setbound.sets import ConstrainedZonotope
        >>> Z = ConstrainedZonotope([0.0], [[1.0, 1.0]], [[1.0, 1.0]], [3.0])  # ξ1 + ξ2 = 3: impossible
        >>> e = Z.emptiness()
        >>> e.empty, bool(e.margin > 0)
        (True, True)
        """
        empty, conclusive, margin = ffi.new("int*"), ffi.new("int*"), ffi.new("double*")
        cert = np.zeros(max(self.nc, 1))
        check(lib.sb_czono_emptiness(*self._args(), empty, conclusive, dptr(cert), margin))
        return Emptiness(empty[0], conclusive[0], cert[:self.nc].copy(), float(margin[0]))

    @property
    def is_empty(self) -> bool:
        """Certified empty (:meth:`emptiness`)."""
        return self.emptiness().empty

    @property
    def volume(self) -> float:
        """Volume: the hull's length for ``n = 1``, the area of the (exact) polygon for ``n = 2``
        (up to the LPs' rounding, not certified), NaN for ``n ≥ 3`` (the exact volume of a polytope
        is not computed: it would enumerate vertices).

        Returns
        -------
        float

        Examples
        --------
        >>> from setbound.sets import ConstrainedZonotope
        >>> round(ConstrainedZonotope.from_bounds([0, 0], [2, 1]).volume, 9)
        2.0
        """
        if self.n == 1:
            lo, hi = self.interval_hull()
            return float(max(hi[0] - lo[0], 0.0))
        if self.n > 2:
            return float("nan")
        V = self.projection(0, 1)
        if len(V) < 3:
            return 0.0
        x, y = V[:, 0], V[:, 1]
        return float(0.5 * abs(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)))

    def projection(self, i: int = 0, j: int = 1, max_vertices: int = 4096) -> np.ndarray:
        """Vertices of the projection onto coordinates ``(i, j)`` (counter-clockwise), for plots.

        Found by LP support points until every edge is a facet: exact up to the LP's rounding,
        not certified (use :meth:`interval_hull` or :meth:`support` for guarantees).

        Parameters
        ----------
        i, j : int, optional
            The coordinates (distinct).
        max_vertices : int, optional
            Capacity (≥ 4).

        Returns
        -------
        ndarray, shape (k, 2)
            ``k = 0`` when the set is certified empty.

        Examples
        --------
        >>> from setbound.sets import ConstrainedZonotope
        >>> ConstrainedZonotope.from_bounds([0, 0], [1, 1]).projection().round(9).tolist()
        [[1.0, 0.0], [1.0, 1.0], [0.0, 1.0], [0.0, 0.0]]
        """
        i = as_int(i, "i", lo=0, hi=self.n - 1)
        j = as_int(j, "j", lo=0, hi=self.n - 1)
        cap = as_int(max_vertices, "max_vertices", lo=4, hi=1 << 20)
        nv = ffi.new("int*", cap)
        V = np.empty((cap, 2))
        check(lib.sb_czono_projection_polygon(*self._args(), i, j, nv, dptr(V)))
        return V[:int(nv[0])].copy()

    def __repr__(self) -> str:
        return f"ConstrainedZonotope(n={self.n}, generators={self.ng}, constraints={self.nc})"


def as_constrained_zonotope(X, name: str = "x0") -> ConstrainedZonotope:
    """A set as a :class:`ConstrainedZonotope`: unchanged, or a zonotope/box exactly, an ellipsoid by its bounding box.

    Parameters
    ----------
    X : ConstrainedZonotope, Zonotope, Box or Ellipsoid
        The set.
    name : str, optional
        Argument name used in error messages.

    Returns
    -------
    ConstrainedZonotope

    Examples
    --------
    >>> setbound.sets.as_constrained_zonotope(setbound.Box([0.0], [1.0])).ng
    1
    """
    if isinstance(X, ConstrainedZonotope):
        return X
    Z = as_zonotope(X, as_str(name, "name"))
    return ConstrainedZonotope(Z.center, Z.generators)


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
    if isinstance(X, ConstrainedZonotope):
        lo, hi = X.interval_hull()
        if not np.all(lo <= hi):
            raise InvalidArgumentError(f"{name}: the constrained zonotope is empty")
        return lo, hi
    raise InvalidArgumentError(f"{name}: expected a setbound.Box, Zonotope, ConstrainedZonotope or Ellipsoid, got "
                               f"{type(X).__name__}")


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
