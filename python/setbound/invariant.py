"""Thesis Chapter 1 invariant sets (Loukkas 2018; Methods › Invariant sets).

* :class:`Polytope` — a full-dimensional polytope with its vertices and its H-rep
  ``{x : H x <= b}`` (Qhull hulls in the C library).
* :func:`ellipsoid_bounding_box` (1.40), :func:`expanded_ellipsoid_levels` (1.57–1.58),
  :func:`polyhedral_rpi_between_ellipsoids` (Methods › Invariant sets), :func:`contraction_rate` (β),
  :func:`mrpi_outer_shrinking` (Algorithm 1, with a box-only variant).

``eps`` of Algorithm 1 is always a *radius*: the stop rule guarantees ``A^k Φ_0 ⊆ {‖x‖₂ ≤ eps}``
(rules ``"radius"`` and ``"vertex_norm"``) or bounds the shrinking index (``"shrinking_index"``).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ._native import as_f64, check, dptr, ffi, lib
from ._validate import as_bool, as_choice, as_float, as_int
from .errors import DimensionError, InvalidArgumentError
from .interval import Box

__all__ = [
    "MrpiResult",
    "Polytope",
    "contraction_rate",
    "ellipsoid_bounding_box",
    "expanded_ellipsoid_levels",
    "mrpi_outer_shrinking",
    "polyhedral_rpi_between_ellipsoids",
]

_STOP_RULES = {"radius": 0, "shrinking_index": 1, "vertex_norm": 2}
#: Upper bound of ``max_vertices`` of :func:`polyhedral_rpi_between_ellipsoids`.
MAX_VERTICES = 1_000_000
#: Upper bound of ``max_iterations`` of :func:`mrpi_outer_shrinking`.
MAX_ITERATIONS = 100_000


def _dims(dims) -> tuple[int, int]:
    """A pair of coordinate indices (ints, not floats or bools)."""
    try:
        i, j = dims
    except (TypeError, ValueError):
        raise InvalidArgumentError(f"dims: expected a pair of coordinate indices, got {dims!r}") from None
    return as_int(i, "dims[0]", lo=0), as_int(j, "dims[1]", lo=0)


def _square(x, name: str, n: int | None = None) -> np.ndarray:
    a = as_f64(x, name, ndim=2)
    if a.shape[0] != a.shape[1] or (n is not None and a.shape[0] != n):
        want = f"({n}, {n})" if n is not None else "square"
        raise DimensionError(f"{name}: expected shape {want}, got {a.shape}")
    return a


def _wrap(handle) -> "Polytope":
    obj = Polytope.__new__(Polytope)
    obj._handle = ffi.gc(handle, lib.sb_polytope_free)
    obj._load()
    return obj


class Polytope:
    """A bounded full-dimensional convex polytope, by its vertices and by ``{x : H x <= b}``.

    ``vertices`` is (p × n), one per row; the rows of ``H`` have unit norm.

    Parameters
    ----------
    points : array_like, shape (q, n)
        Points whose convex hull is the polytope (they must span ℝⁿ).

    Examples
    --------
    >>> P = setbound.Polytope([[0, 0], [1, 0], [0, 1]])
    >>> P.contains([[0.2, 0.2], [1.0, 1.0]]).tolist()
    [True, False]
    """

    def __init__(self, points):
        pts = as_f64(points, "points", ndim=2)
        out = ffi.new("sb_polytope**")
        check(lib.sb_polytope_from_vertices(pts.shape[1], pts.shape[0], dptr(pts), out))
        self._handle = ffi.gc(out[0], lib.sb_polytope_free)
        self._load()

    @classmethod
    def from_vertices(cls, points) -> "Polytope":
        """The convex hull of the rows of ``points`` (they must span ℝⁿ).

        Parameters
        ----------
        points : array_like, shape (q, n)
            The points.

        Returns
        -------
        Polytope
        """
        return cls(points)

    @classmethod
    def from_halfspaces(cls, H, b, interior) -> "Polytope":
        """The bounded polytope ``{x : H x <= b}``.

        Parameters
        ----------
        H : array_like, shape (f, n)
            Facet normals.
        b : array_like, shape (f,)
            Offsets.
        interior : array_like, shape (n,)
            A point strictly inside.

        Returns
        -------
        Polytope
        """
        Ha = as_f64(H, "H", ndim=2)
        m, n = Ha.shape
        ba = as_f64(b, "b", shape=(m,))
        c = as_f64(interior, "interior", shape=(n,))
        out = ffi.new("sb_polytope**")
        check(lib.sb_polytope_from_halfspaces(n, m, dptr(Ha), dptr(ba), dptr(c), out))
        return _wrap(out[0])

    @classmethod
    def from_box(cls, box: Box) -> "Polytope":
        """A box as a polytope (2n facets, 2^n vertices).

        Parameters
        ----------
        box : Box
            The box.

        Returns
        -------
        Polytope

        Examples
        --------
        >>> setbound.Polytope.from_box(setbound.Box([0, 0], [1, 2])).vertices.shape
        (4, 2)
        """
        lo, hi = np.asarray(box.lo), np.asarray(box.hi)
        n = lo.size
        corners = np.array([[hi[i] if (k >> i) & 1 else lo[i] for i in range(n)] for k in range(1 << n)])
        return cls(corners)

    def _load(self) -> None:
        n, nv, nf = ffi.new("int*"), ffi.new("int*"), ffi.new("int*")
        check(lib.sb_polytope_sizes(self._handle, n, nv, nf))
        self._n = n[0]
        V = np.empty((nv[0], n[0]))
        H = np.empty((nf[0], n[0]))
        b = np.empty(nf[0])
        check(lib.sb_polytope_get(self._handle, dptr(V), dptr(H), dptr(b)))
        for a in (V, H, b):
            a.flags.writeable = False
        self._V, self._H, self._b = V, H, b

    dimension = property(lambda self: self._n, doc="State dimension n.")
    vertices = property(lambda self: self._V, doc="vertices, one per row (p × n)")
    H = property(lambda self: self._H, doc="facet normals (m × n, unit rows)")
    b = property(lambda self: self._b, doc="facet offsets (m)")
    num_vertices = property(lambda self: self._V.shape[0], doc="Number of vertices.")
    num_facets = property(lambda self: self._H.shape[0], doc="Number of facets (rows of H).")

    def contains(self, points, tol: float = 1e-9):
        """Membership ``H x <= b + tol`` of a point or of each row of a batch.

        Parameters
        ----------
        points : array_like, shape (n,) or (k, n)
            One point or ``k`` points.
        tol : float, optional
            Tolerance, finite and >= 0.

        Returns
        -------
        bool or ndarray of bool
        """
        tol = as_float(tol, "tol", lo=0.0)
        p = as_f64(points, "points")
        single = p.ndim == 1
        p2 = np.ascontiguousarray(p.reshape(1, -1) if single else p)
        if p2.ndim != 2 or p2.shape[1] != self._n:
            raise DimensionError(f"points: expected {self._n} columns, got shape {p.shape}")
        inside = np.zeros(p2.shape[0], dtype=np.intc)
        check(lib.sb_polytope_contains(self._handle, p2.shape[0], dptr(p2), tol,
                                       ffi.cast("int*", inside.ctypes.data)))
        return bool(inside[0]) if single else inside.astype(bool)

    def contains_polytope(self, other: "Polytope", tol: float = 1e-9) -> bool:
        """Inclusion ``other ⊆ self`` (every vertex of ``other`` in ``self``).

        Parameters
        ----------
        other : Polytope
            The other polytope.
        tol : float, optional
            Tolerance, finite and >= 0.

        Returns
        -------
        bool
        """
        return bool(np.all(self.contains(other.vertices, tol)))

    def linear_map(self, M) -> "Polytope":
        """The image ``M·P`` (vertices mapped, hull recomputed).

        Parameters
        ----------
        M : array_like, shape (n, n)
            The matrix.

        Returns
        -------
        Polytope
        """
        Ma = as_f64(M, "M", ndim=2)
        if Ma.shape[1] != self._n:
            raise DimensionError(f"M: expected {self._n} columns, got shape {Ma.shape}")
        out = ffi.new("sb_polytope**")
        check(lib.sb_polytope_linear_map(self._handle, Ma.shape[0], dptr(Ma), out))
        return _wrap(out[0])

    def minkowski_sum(self, other) -> "Polytope":
        """The Minkowski sum ``self ⊕ other``.

        Parameters
        ----------
        other : Polytope or Box
            The other set.

        Returns
        -------
        Polytope

        Examples
        --------
        >>> P = setbound.Polytope.from_box(setbound.Box([0, 0], [1, 1]))
        >>> S = P.minkowski_sum(setbound.Box([-1, -1], [1, 1]))
        >>> bool(S.contains([1.9, -0.9]))
        True
        """
        out = ffi.new("sb_polytope**")
        if isinstance(other, Polytope):
            check(lib.sb_polytope_minkowski_sum(self._handle, other._handle, out))
        elif isinstance(other, Box):
            lo = as_f64(other.lo, "box (lo)", shape=(self._n,))
            hi = as_f64(other.hi, "box (hi)", shape=(self._n,))
            check(lib.sb_polytope_minkowski_box(self._handle, dptr(lo), dptr(hi), out))
        else:
            raise InvalidArgumentError(f"other: expected a Polytope or a Box, got {type(other).__name__}")
        return _wrap(out[0])

    def __add__(self, other):
        return self.minkowski_sum(other)

    def scaled(self, a: float) -> "Polytope":
        """The polytope ``a·P``.

        Parameters
        ----------
        a : float
            Finite factor.

        Returns
        -------
        Polytope
        """
        out = ffi.new("sb_polytope**")
        check(lib.sb_polytope_scale(self._handle, as_float(a, "a"), out))
        return _wrap(out[0])

    def bounding_box(self) -> Box:
        """The exact interval hull (from the vertices)."""
        lo, hi = np.empty(self._n), np.empty(self._n)
        check(lib.sb_polytope_bounding_box(self._handle, dptr(lo), dptr(hi)))
        return Box(lo, hi)

    def max_vertex_norm(self) -> float:
        """The largest Euclidean norm of a vertex (the ‖Φ‖ of thesis (4.33))."""
        r = ffi.new("double*")
        check(lib.sb_polytope_max_vertex_norm(self._handle, r))
        return r[0]

    def plot_data(self, dims=(0, 1)) -> np.ndarray:
        """Closed polygon (rows, first = last) of the projection onto two coordinates, counter-clockwise.

        Parameters
        ----------
        dims : (int, int), optional
            The coordinates.

        Returns
        -------
        ndarray, shape (q + 1, 2)
        """
        i, j = _dims(dims)
        if not (0 <= i < self._n and 0 <= j < self._n and i != j):
            raise InvalidArgumentError(f"dims: two distinct coordinates in [0, {self._n}) required, got {dims}")
        pts = sorted(set(map(tuple, self._V[:, [i, j]])))
        if len(pts) < 3:
            return np.array(pts + pts[:1])

        def cross(o, a, b):
            return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

        lower, upper = [], []
        for p in pts:  # Andrew's monotone chain
            while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
                lower.pop()
            lower.append(p)
        for p in reversed(pts):
            while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
                upper.pop()
            upper.append(p)
        hull = lower[:-1] + upper[:-1]
        return np.array(hull + hull[:1])

    def __repr__(self) -> str:
        return f"Polytope(n={self._n}, vertices={self.num_vertices}, facets={self.num_facets})"


def ellipsoid_bounding_box(P, c, rho: float) -> Box:
    """The tightest box ``c ± sqrt(diag(rho P⁻¹))`` around ``{(x−c)ᵀP(x−c) <= rho}`` (thesis (1.40); outward rounded).

    Methods › Invariant sets › Ellipsoid bounding box.

    Parameters
    ----------
    P : array_like, shape (n, n)
        Shape (symmetric positive definite).
    c : array_like, shape (n,)
        Centre.
    rho : float
        Level, > 0.

    Returns
    -------
    Box

    Examples
    --------
    The ellipse of [Loukkas2018] Example 1.3 (the box comes from ``P⁻¹``, not from ``P``):

    >>> b = setbound.invariant.ellipsoid_bounding_box([[1.0, 1.0], [1.0, 4.0]], [0.0, 0.0], 1.0)
    >>> print(np.round(b.hi, 6))
    [1.154701 0.57735 ]
    """
    rho = as_float(rho, "rho", lo=0.0, lo_open=True)
    Pa = _square(P, "P")
    n = Pa.shape[0]
    ca = as_f64(c, "c", shape=(n,))
    lo, hi = np.empty(n), np.empty(n)
    check(lib.sb_ellipsoid_bounding_box(n, dptr(Pa), dptr(ca), float(rho), dptr(lo), dptr(hi)))
    return Box(lo, hi)


def expanded_ellipsoid_levels(P, gamma: float, wbar_sq: float, mu: float) -> tuple[float, float]:
    """The levels ``(c_in, c_out)`` of the ellipsoids ``Ψ̄⁺(μ)`` and ``Ψ̄(μ)`` (thesis (1.57)–(1.58); Methods › Invariant sets › Polyhedral RPI set between ellipsoids).

    Parameters
    ----------
    P : array_like, shape (n, n)
        BRL matrix.
    gamma : float
        BRL level γ.
    wbar_sq : float
        ``w̄ᵀw̄``.
    mu : float
        Expansion factor, > 1.

    Returns
    -------
    (float, float)

    Examples
    --------
    >>> c_in, c_out = setbound.invariant.expanded_ellipsoid_levels(np.eye(2), 1.0, 1.0, 2.0)
    >>> c_in < c_out
    True
    """
    Pa = _square(P, "P")
    ci, co = ffi.new("double*"), ffi.new("double*")
    check(lib.sb_expanded_ellipsoid_levels(Pa.shape[0], dptr(Pa), as_float(gamma, "gamma"), as_float(wbar_sq, "wbar_sq"),
                                           as_float(mu, "mu"), ci, co))
    return ci[0], co[0]


def polyhedral_rpi_between_ellipsoids(P, c_in: float, c_out: float, *, max_vertices: int | None = None) -> Polytope:
    """A polytope ``Φ`` with ``{xᵀPx <= c_in} ⊆ Φ ⊆ {xᵀPx <= c_out}`` (certified; Methods › Invariant sets › Polyhedral RPI set between ellipsoids).

    Parameters
    ----------
    P : array_like, shape (n, n)
        Shape.
    c_in, c_out : float
        Levels, ``0 < c_in < c_out``.
    max_vertices : int, optional
        ``None`` (the library's 10000) or in ``[1, MAX_VERTICES]`` (1000000: the vertex
        enumeration's time and memory grow with it).

    Returns
    -------
    Polytope

    Examples
    --------
    >>> Phi = setbound.invariant.polyhedral_rpi_between_ellipsoids(np.eye(2), 1.0, 2.0)
    >>> bool(np.all(np.sum(Phi.vertices ** 2, axis=1) <= 2.0 + 1e-9))
    True
    """
    c_in, c_out = as_float(c_in, "c_in"), as_float(c_out, "c_out")
    maxv = 0 if max_vertices is None else as_int(max_vertices, "max_vertices", lo=1, hi=MAX_VERTICES)  # C: 0 = default
    Pa = _square(P, "P")
    out = ffi.new("sb_polytope**")
    check(lib.sb_polyhedral_rpi(Pa.shape[0], dptr(Pa), c_in, c_out, maxv, out))
    return _wrap(out[0])


def contraction_rate(A, P) -> float:
    """The smallest ``β`` with ``AᵀPA ≼ β²P`` (``‖Ax‖_P ≤ β‖x‖_P``).

    Parameters
    ----------
    A : array_like, shape (n, n)
        The matrix.
    P : array_like, shape (n, n)
        Symmetric positive definite weight.

    Returns
    -------
    float

    Examples
    --------
    >>> round(setbound.invariant.contraction_rate(0.5 * np.eye(2), np.eye(2)), 6)
    0.5
    """
    Aa = _square(A, "A")
    Pa = _square(P, "P", Aa.shape[0])
    beta = ffi.new("double*")
    check(lib.sb_contraction_rate(Aa.shape[0], dptr(Aa), dptr(Pa), beta))
    return beta[0]


@dataclass
class MrpiResult:
    """Output of Algorithm 1 (index ``k = 0 … k_star``; Methods › Invariant sets › Algorithm 1).

    Parameters
    ----------
    k_star : int
        Last iteration.
    beta : float
        Contraction rate of ``A`` in the ``P`` norm.
    boxes : list of Box
        Exact, outward-rounded interval hulls of the ``Φ_k``.
    sets : list of Polytope or None
        The ``Φ_k`` (None for ``boxes_only``).
    radius_bound : ndarray
        ``β^k sqrt(c_out/λ_min(P))``.
    vertex_radius : ndarray
        ``max_v ‖A^k v‖`` over the vertices of ``Φ_0``.
    shrinking_index : ndarray
        ``β^k sqrt(μ λ_max(P)/λ_min(P))``.
    phi0 : Polytope
        The starting set.
    P : ndarray, optional
        BRL matrix (Algorithm 1 from the data only).
    gamma, c_in, c_out, mu : float, optional
        BRL level, ellipsoid levels and expansion factor (from the data only).
    """

    k_star: int
    beta: float
    boxes: list  # Box per k: exact, outward-rounded interval hulls of Φ_k
    sets: list | None  # Polytope per k (None for boxes_only)
    radius_bound: np.ndarray  # β^k sqrt(c_out/λ_min(P))
    vertex_radius: np.ndarray  # max_v ‖A^k v‖ over the vertices of Φ_0
    shrinking_index: np.ndarray  # β^k sqrt(μ λ_max(P)/λ_min(P))
    phi0: Polytope = field(repr=False)
    # Algorithm 1 from the data only:
    P: np.ndarray | None = field(default=None, repr=False)
    gamma: float | None = None
    c_in: float | None = None
    c_out: float | None = None
    mu: float | None = None

    @property
    def final_set(self):
        """Φ_{k*} (None for boxes_only results)."""
        return None if self.sets is None else self.sets[-1]


def _collect(handle, n: int, mu: float | None) -> MrpiResult:
    h = ffi.gc(handle, lib.sb_mrpi_free)
    nn, ks, beta, has_sets, has_design = (ffi.new("int*"), ffi.new("int*"), ffi.new("double*"),
                                          ffi.new("int*"), ffi.new("int*"))
    check(lib.sb_mrpi_info(h, nn, ks, beta, has_sets, has_design))
    K = ks[0] + 1
    rb, vr, si = np.empty(K), np.empty(K), np.empty(K)
    check(lib.sb_mrpi_sequences(h, dptr(rb), dptr(vr), dptr(si)))
    lo, hi = np.empty((K, n)), np.empty((K, n))
    check(lib.sb_mrpi_boxes(h, dptr(lo), dptr(hi)))
    boxes = [Box(lo[k], hi[k]) for k in range(K)]

    def set_k(k):
        out = ffi.new("sb_polytope**")
        check(lib.sb_mrpi_set(h, k, out))
        return _wrap(out[0])

    phi0 = set_k(0)
    sets = [phi0] + [set_k(k) for k in range(1, K)] if has_sets[0] else None
    res = MrpiResult(k_star=ks[0], beta=beta[0], boxes=boxes, sets=sets, radius_bound=rb, vertex_radius=vr,
                     shrinking_index=si, phi0=phi0)
    if has_design[0]:
        P = np.empty((n, n))
        g, ci, co = ffi.new("double*"), ffi.new("double*"), ffi.new("double*")
        check(lib.sb_mrpi_design(h, dptr(P), g, ci, co))
        res.P, res.gamma, res.c_in, res.c_out, res.mu = P, g[0], ci[0], co[0], mu
    return res


def mrpi_outer_shrinking(A, E, wbar=None, *, eps: float, mu: float = 2.0, stop: str = "radius",
                         phi0: Polytope | None = None, P=None, c_out: float | None = None,
                         delta: Box | None = None, boxes_only: bool = False,
                         max_iterations: int | None = None) -> MrpiResult:
    """Algorithm 1 of [Loukkas2018]: ``Φ_{k+1} = AΦ_k ⊕ EΔ`` until the stop rule holds (Methods › Invariant sets › Algorithm 1).

    * From the data (``phi0`` None): BRL (1.48) → Φ_v between Ψ̄⁺(μ) and Ψ̄(μ) (μ > 1) → shrinking
      with ``Δ = [−wbar, wbar]``; the result also carries P, γ, c_in, c_out.
    * From a given ``phi0`` inside ``{xᵀPx <= c_out}`` (``P`` a Lyapunov/BRL matrix of A):
      Δ = ``delta`` (a Box containing 0) or ``[−wbar, wbar]``; ``mu`` only enters the
      shrinking index.

    Parameters
    ----------
    A : array_like, shape (n, n)
        Schur-stable matrix.
    E : array_like, shape (n, m)
        Disturbance matrix.
    wbar : array_like, shape (m,), optional
        Bounds of ``|w_i|``.
    eps : float
        Stop radius.
    mu : float, optional
        Expansion factor.
    stop : {"radius", "shrinking_index", "vertex_norm"}, optional
        ``β^k·sqrt(c_out/λ_min(P)) <= eps`` (rigorous), the thesis's shrinking index (Ex 1.5), or
        ``max ‖A^k v‖ <= eps``.
    phi0 : Polytope, optional
        Starting set.
    P : array_like, optional
        Lyapunov/BRL matrix with ``phi0``.
    c_out : float, optional
        Level with ``phi0``.
    delta : Box, optional
        Disturbance box (containing 0).
    boxes_only : bool, optional
        Keep the interval hulls only (faster).
    max_iterations : int, optional
        ``None`` (the library's 500) or in ``[1, MAX_ITERATIONS]`` (100000; every iteration is a
        Minkowski sum).

    Returns
    -------
    MrpiResult

    Examples
    --------
    [Loukkas2018] Example 1.5 with the interval hulls only:

    >>> res = setbound.invariant.mrpi_outer_shrinking([[0.2, 0.2], [-0.2, 0.5]], [[0.0], [1.0]], [1.0],
    ...                                               eps=1e-3, boxes_only=True)
    >>> bool(res.boxes[-1].subset(res.boxes[0])), res.k_star > 0
    (True, True)
    """
    stop = as_choice(stop, "stop", _STOP_RULES)
    eps = as_float(eps, "eps")
    mu = as_float(mu, "mu")
    boxes_only = as_bool(boxes_only, "boxes_only")
    maxit = 0 if max_iterations is None else as_int(max_iterations, "max_iterations", lo=1, hi=MAX_ITERATIONS)
    c_out = None if c_out is None else as_float(c_out, "c_out")
    Aa = _square(A, "A")
    n = Aa.shape[0]
    Ea = as_f64(E, "E", ndim=2)
    if Ea.shape[0] != n:
        raise DimensionError(f"E: expected {n} rows (the size of A), got shape {Ea.shape}")
    m = Ea.shape[1]
    out = ffi.new("sb_mrpi**")
    if phi0 is None:
        if wbar is None:
            raise InvalidArgumentError("wbar: required when phi0 is not given (Algorithm 1 from the data)")
        w = as_f64(wbar, "wbar", shape=(m,))
        check(lib.sb_mrpi_algorithm1(n, m, dptr(Aa), dptr(Ea), dptr(w), mu, eps, _STOP_RULES[stop],
                                     maxit, int(boxes_only), out))
        return _collect(out[0], n, mu)
    if not isinstance(phi0, Polytope):
        raise InvalidArgumentError(f"phi0: expected a Polytope, got {type(phi0).__name__}")
    if P is None or c_out is None:
        raise InvalidArgumentError("P: P and c_out are required with phi0")
    Pa = _square(P, "P", n)
    if delta is None:
        if wbar is None:
            raise InvalidArgumentError("delta: give delta (a Box) or wbar")
        w = as_f64(wbar, "wbar", shape=(m,))
        dlo, dhi = -w, w.copy()
    else:
        dlo = as_f64(delta.lo, "delta (lo)", shape=(m,))
        dhi = as_f64(delta.hi, "delta (hi)", shape=(m,))
    dlo, dhi = np.ascontiguousarray(dlo), np.ascontiguousarray(dhi)
    check(lib.sb_mrpi_shrinking(n, m, dptr(Aa), dptr(Ea), dptr(dlo), dptr(dhi), phi0._handle, dptr(Pa),
                                c_out, eps, _STOP_RULES[stop], mu, maxit, int(boxes_only), out))
    return _collect(out[0], n, None)
