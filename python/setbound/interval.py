"""Guaranteed interval analysis: scalar intervals, boxes and interval matrices.

Thin numpy classes over the C ABI section "intervals, boxes, interval matrices" of
``setbound.h`` (thesis §1). Every arithmetic result is computed by the C library with outward
rounding that stays exact when the operation is exact, so it contains the exact real result:
``Interval(-2, 4) + Interval(1, 3)`` is exactly ``[-1, 7]`` and ``Interval(0.1) + Interval(0.2)``
encloses the real number 0.1 + 0.2 (of the two doubles).

Intervals may have infinite ends; the empty interval is ``(+inf, -inf)``. Bad input raises a
:class:`setbound.SetboundError` subclass whose message starts with the argument name.

Only trivial properties (mid, rad, width, magnitudes, membership tests) are evaluated with
numpy; they follow the C++ definitions (``rad`` is rounded up so that ``mid ± rad`` encloses).
"""
from __future__ import annotations

import math

import numpy as np

from ._native import as_f64, check, dptr, ffi, lib
from ._validate import INT_MAX, as_int, as_str, check_memory
from .errors import DimensionError, InvalidArgumentError, NotFiniteError

__all__ = [
    "Interval", "Box", "IntervalMatrix",
    "sqr", "sqrt", "exp", "sin", "cos", "abs_", "reciprocal", "power",
]

_INF = math.inf
_BINARY = {
    "add": lib.SB_IV_ADD, "sub": lib.SB_IV_SUB, "mul": lib.SB_IV_MUL, "div": lib.SB_IV_DIV,
    "intersect": lib.SB_IV_INTERSECT, "hull": lib.SB_IV_HULL,
}
_UNARY = {
    "neg": lib.SB_IV_NEG, "recip": lib.SB_IV_RECIP, "sqr": lib.SB_IV_SQR,
    "sqrt": lib.SB_IV_SQRT, "exp": lib.SB_IV_EXP, "sin": lib.SB_IV_SIN, "cos": lib.SB_IV_COS,
    "abs": lib.SB_IV_ABS,
}


# ---- validation and raw vectorised calls --------------------------------------------------

def _check_ends(lo: np.ndarray, hi: np.ndarray, name: str, allow_empty: bool = True,
                label: str = "entry") -> None:
    """Same rules and message shapes as the C++ Interval::validate."""
    lo_f, hi_f = lo.ravel(), hi.ravel()
    def where(k: int) -> str:
        if lo.ndim == 0:
            return ""
        if lo.ndim == 1:
            return f" {label} {k}"
        return " entry (" + ", ".join(str(int(t)) for t in np.unravel_index(k, lo.shape)) + ")"

    bad = np.flatnonzero(np.isnan(lo_f) | np.isnan(hi_f))
    if bad.size:
        k = int(bad[0])
        raise NotFiniteError(f"{name}{where(k)}: interval end is NaN ([{lo_f[k]}, {hi_f[k]}])")
    empty = (lo_f == _INF) & (hi_f == -_INF)
    bad = np.flatnonzero((lo_f > hi_f) & ~empty)
    if bad.size:
        k = int(bad[0])
        raise InvalidArgumentError(
            f"{name}{where(k)}: lower end {lo_f[k]} is greater than upper end {hi_f[k]}")
    bad = np.flatnonzero(~empty & ((lo_f == _INF) | (hi_f == -_INF)))
    if bad.size:
        k = int(bad[0])
        raise InvalidArgumentError(f"{name}{where(k)}: [{lo_f[k]}, {hi_f[k]}] contains no real number")
    if not allow_empty and empty.any():
        k = int(np.flatnonzero(empty)[0])
        raise InvalidArgumentError(f"{name}{where(k)}: empty interval in a matrix")


def _binary(op: str, alo, ahi, blo, bhi) -> tuple[np.ndarray, np.ndarray]:
    alo, ahi, blo, bhi = (np.ascontiguousarray(a, dtype=np.float64).ravel()
                          for a in (alo, ahi, blo, bhi))
    n = alo.size
    lo, hi = np.empty(n), np.empty(n)
    check(lib.sb_interval_binary(_BINARY[op], n, dptr(alo), dptr(ahi), dptr(blo), dptr(bhi),
                                 _out(lo), _out(hi)))
    return lo, hi


def _unary(op: str, xlo, xhi) -> tuple[np.ndarray, np.ndarray]:
    xlo, xhi = (np.ascontiguousarray(a, dtype=np.float64).ravel() for a in (xlo, xhi))
    n = xlo.size
    lo, hi = np.empty(n), np.empty(n)
    check(lib.sb_interval_unary(_UNARY[op], n, dptr(xlo), dptr(xhi), _out(lo), _out(hi)))
    return lo, hi


def _out(a: np.ndarray):
    """Writable double* into a C-contiguous float64 array (NULL when empty)."""
    if a.size == 0:
        return ffi.NULL
    return ffi.cast("double*", ffi.from_buffer(a, require_writable=True))


def _mid(lo, hi):
    """Overflow-safe midpoint with the IEEE 1788 conventions for unbounded intervals."""
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    with np.errstate(invalid="ignore"):
        m = np.clip(0.5 * lo + 0.5 * hi, lo, hi)
    m = np.where(np.isneginf(lo) & np.isposinf(hi), 0.0, m)
    m = np.where(np.isneginf(lo) & ~np.isposinf(hi), -np.finfo(float).max, m)
    m = np.where(~np.isneginf(lo) & np.isposinf(hi), np.finfo(float).max, m)
    return np.where(lo > hi, np.nan, m)


def _rad(lo, hi):
    """Radius rounded up so that [mid − rad, mid + rad] ⊇ [lo, hi]."""
    m = _mid(lo, hi)
    with np.errstate(invalid="ignore", over="ignore"):
        r = np.maximum(m - lo, hi - m)
        short = (m - r > lo) | (m + r < hi)
        r = np.where(short, np.nextafter(r, _INF), r)
    return np.where(np.asarray(lo) > np.asarray(hi), np.nan, r)


def _width(lo, hi):
    """hi − lo rounded up (exact when the difference is representable)."""
    lo, hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    with np.errstate(invalid="ignore", over="ignore"):
        w = hi - lo
        # TwoSum error of w = hi + (−lo): step up when the rounded difference is too small.
        bb = w - hi
        err = (hi - (w - bb)) + (-lo - bb)
        w = np.where(np.isfinite(err) & (err > 0), np.nextafter(w, _INF), w)
    return np.where(lo > hi, np.nan, w)


# ---- scalar intervals ---------------------------------------------------------------------

class Interval:
    """A closed interval ``[lo, hi]`` of reals; ``Interval(x)`` is ``[x, x]``.

    Arithmetic (``+ - * /``, powers) is interval arithmetic with outward rounding, so the result
    contains every value of the real operation on the operands (Methods › Sets, intervals and LMI
    tools › Intervals and interval arithmetic).

    Parameters
    ----------
    lo : float
        Lower end.
    hi : float, optional
        Upper end (default: ``lo``).
    name : str, optional
        Argument name used in error messages.

    Examples
    --------
    >>> x = setbound.Interval(-1.0, 2.0)
    >>> print(x * x, setbound.interval.sqr(x))
    Interval(-2.0, 4.0) Interval(0.0, 4.0)
    """

    __slots__ = ("_lo", "_hi")
    __array_ufunc__ = None  # let numpy scalars defer to our reflected operators

    def __init__(self, lo, hi=None, *, name: str = "interval"):
        name = as_str(name, "name")  # a label for the messages
        try:
            lo = float(lo)
            hi = lo if hi is None else float(hi)
        except (TypeError, ValueError) as exc:
            raise InvalidArgumentError(f"{name}: interval ends must be numbers ({exc})") from None
        _check_ends(np.asarray(lo), np.asarray(hi), name)
        self._lo, self._hi = lo, hi

    @classmethod
    def _raw(cls, lo: float, hi: float) -> "Interval":
        obj = cls.__new__(cls)
        obj._lo, obj._hi = float(lo), float(hi)
        return obj

    @classmethod
    def empty(cls) -> "Interval":
        """The empty interval, encoded (+inf, −inf)."""
        return cls._raw(_INF, -_INF)

    @classmethod
    def entire(cls) -> "Interval":
        """The whole real line (−inf, +inf)."""
        return cls._raw(-_INF, _INF)

    lo = property(lambda self: self._lo, doc="lower end (inf)")
    hi = property(lambda self: self._hi, doc="upper end (sup)")

    @property
    def is_empty(self) -> bool:
        """True for the empty interval."""
        return self._lo > self._hi

    @property
    def mid(self) -> float:
        """Midpoint (eq. 1.6; overflow-safe, IEEE 1788 conventions for unbounded intervals)."""
        return float(_mid(self._lo, self._hi))

    @property
    def rad(self) -> float:
        """Radius (eq. 1.7), rounded up so that [mid − rad, mid + rad] ⊇ [x]."""
        return float(_rad(self._lo, self._hi))

    @property
    def width(self) -> float:
        """Width hi − lo, rounded up."""
        return float(_width(self._lo, self._hi))

    @property
    def mag(self) -> float:
        """Magnitude ``max |t|`` over the interval (NaN when empty).

        Returns
        -------
        float
        """
        return math.nan if self.is_empty else max(abs(self._lo), abs(self._hi))

    @property
    def mig(self) -> float:
        """Mignitude ``min |t|`` over the interval (0 when it contains 0; NaN when empty).

        Returns
        -------
        float
        """
        if self.is_empty:
            return math.nan
        if self._lo <= 0 <= self._hi:
            return 0.0
        return min(abs(self._lo), abs(self._hi))

    # set operations
    def contains(self, x) -> bool:
        """Membership of a number, or inclusion of an interval.

        Parameters
        ----------
        x : float or Interval
            A number or an interval.

        Returns
        -------
        bool
        """
        if isinstance(x, Interval):
            return x.subset(self)
        return bool(self._lo <= float(x) <= self._hi)

    __contains__ = contains

    def subset(self, other: "Interval") -> bool:
        """True when this interval is included in ``other`` (the empty set is in every interval).

        Parameters
        ----------
        other : Interval
            The other interval.

        Returns
        -------
        bool
        """
        return self.is_empty or (other._lo <= self._lo and self._hi <= other._hi)

    def intersect(self, other) -> "Interval":
        """The intersection with ``other`` (empty when disjoint).

        Parameters
        ----------
        other : Interval or float
            The other interval.

        Returns
        -------
        Interval
        """
        return self._bin("intersect", other)

    def hull(self, other) -> "Interval":
        """The interval hull of the union with ``other``.

        Parameters
        ----------
        other : Interval or float
            The other interval.

        Returns
        -------
        Interval
        """
        return self._bin("hull", other)

    # arithmetic through the C ABI
    def _bin(self, op: str, other, reflected: bool = False) -> "Interval":
        o = _as_interval(other, "other")
        if o is None:
            return NotImplemented
        a, b = (o, self) if reflected else (self, o)
        lo, hi = _binary(op, a._lo, a._hi, b._lo, b._hi)
        return Interval._raw(lo[0], hi[0])

    def _un(self, op: str) -> "Interval":
        lo, hi = _unary(op, self._lo, self._hi)
        return Interval._raw(lo[0], hi[0])

    def __add__(self, o): return self._bin("add", o)
    def __radd__(self, o): return self._bin("add", o, True)
    def __sub__(self, o): return self._bin("sub", o)
    def __rsub__(self, o): return self._bin("sub", o, True)
    def __mul__(self, o): return self._bin("mul", o)
    def __rmul__(self, o): return self._bin("mul", o, True)
    def __truediv__(self, o): return self._bin("div", o)
    def __rtruediv__(self, o): return self._bin("div", o, True)
    def __neg__(self): return self._un("neg")
    def __pos__(self): return self
    def __abs__(self): return self._un("abs")

    def __pow__(self, n):
        return power(self, n)  # integer powers only (checked there: not floats, not bools)

    def reciprocal(self) -> "Interval":
        """1/[x], with the extended cases of thesis eq. 1.28 (1/[0, 0] is empty)."""
        return self._un("recip")
    def sqr(self) -> "Interval":
        """{t² : t ∈ [x]} (not [x]·[x])."""
        return self._un("sqr")
    def sqrt(self) -> "Interval":
        """{√t : t ∈ [x], t ≥ 0}, rounded outward."""
        return self._un("sqrt")
    def exp(self) -> "Interval":
        """{exp t : t ∈ [x]}, rounded outward."""
        return self._un("exp")
    def sin(self) -> "Interval":
        """{sin t : t ∈ [x]}, rounded outward."""
        return self._un("sin")
    def cos(self) -> "Interval":
        """{cos t : t ∈ [x]}, rounded outward."""
        return self._un("cos")
    def abs(self) -> "Interval":
        """The interval ``{abs(t) : t ∈ [x]}``.

        Returns
        -------
        Interval
        """
        return self._un("abs")

    def __eq__(self, other):
        if not isinstance(other, Interval):
            return NotImplemented
        return (self.is_empty and other.is_empty) or (self._lo == other._lo and self._hi == other._hi)

    def __hash__(self):
        return hash(("empty",) if self.is_empty else (self._lo, self._hi))

    def __iter__(self):
        return iter((self._lo, self._hi))

    def __repr__(self):
        return "Interval.empty()" if self.is_empty else f"Interval({self._lo!r}, {self._hi!r})"


def _as_interval(x, name: str) -> Interval | None:
    if isinstance(x, Interval):
        return x
    if isinstance(x, (int, float, np.floating, np.integer)):
        return Interval(float(x), name=name)
    return None


def _require_interval(x, name: str) -> Interval:
    iv = _as_interval(x, name)
    if iv is None:
        raise InvalidArgumentError(f"{name}: expected an Interval or a number, got {type(x).__name__}")
    return iv


def sqr(x) -> Interval:
    """The interval ``{t² : t ∈ [x]}`` — ``[0, max²]`` when ``0 ∈ [x]`` (not ``[x]·[x]``).

    Parameters
    ----------
    x : Interval or float
        The argument (a number is the degenerate interval ``[x, x]``).

    Returns
    -------
    Interval

    Examples
    --------
    >>> setbound.interval.sqr(setbound.Interval(-1.0, 2.0))
    Interval(0.0, 4.0)
    """
    return _require_interval(x, "x").sqr()


def sqrt(x) -> Interval:
    """The interval ``{√t : t ∈ [x], t ≥ 0}``, rounded outward.

    Parameters
    ----------
    x : Interval or float
        The argument (a number is the degenerate interval ``[x, x]``).

    Returns
    -------
    Interval

    Examples
    --------
    >>> setbound.interval.sqrt(setbound.Interval(4.0, 9.0))
    Interval(2.0, 3.0)
    """
    return _require_interval(x, "x").sqrt()


def exp(x) -> Interval:
    """The interval ``{exp t : t ∈ [x]}``, rounded outward.

    Parameters
    ----------
    x : Interval or float
        The argument (a number is the degenerate interval ``[x, x]``).

    Returns
    -------
    Interval

    Examples
    --------
    >>> setbound.interval.exp(setbound.Interval(0.0, 0.0)).contains(1.0)
    True
    """
    return _require_interval(x, "x").exp()


def sin(x) -> Interval:
    """The interval ``{sin t : t ∈ [x]}``, rounded outward.

    Parameters
    ----------
    x : Interval or float
        The argument (a number is the degenerate interval ``[x, x]``).

    Returns
    -------
    Interval

    Examples
    --------
    >>> setbound.interval.sin(setbound.Interval(0.0, 3.2)).contains(1.0)
    True
    """
    return _require_interval(x, "x").sin()


def cos(x) -> Interval:
    """The interval ``{cos t : t ∈ [x]}``, rounded outward.

    Parameters
    ----------
    x : Interval or float
        The argument (a number is the degenerate interval ``[x, x]``).

    Returns
    -------
    Interval

    Examples
    --------
    >>> setbound.interval.cos(setbound.Interval(-0.1, 0.1)).contains(1.0)
    True
    """
    return _require_interval(x, "x").cos()


def abs_(x) -> Interval:
    """The interval ``{abs(t) : t ∈ [x]}`` (named ``abs_`` so as not to shadow the builtin).

    Parameters
    ----------
    x : Interval or float
        The argument (a number is the degenerate interval ``[x, x]``).

    Returns
    -------
    Interval

    Examples
    --------
    >>> setbound.interval.abs_(setbound.Interval(-3.0, 1.0))
    Interval(0.0, 3.0)
    """
    return _require_interval(x, "x").abs()


def reciprocal(x) -> Interval:
    """The interval ``1/[x]``, with the extended cases of the thesis, eq. (1.28) (``1/[0, 0]`` is empty).

    Parameters
    ----------
    x : Interval or float
        The argument (a number is the degenerate interval ``[x, x]``).

    Returns
    -------
    Interval

    Examples
    --------
    >>> setbound.interval.reciprocal(setbound.Interval(2.0, 4.0))
    Interval(0.25, 0.5)
    """
    return _require_interval(x, "x").reciprocal()


def power(x, n: int) -> Interval:
    """Integer power ``{t^n : t ∈ [x]}``; a negative ``n`` is the reciprocal of the positive power.

    Parameters
    ----------
    x : Interval or float
        The argument.
    n : int
        The exponent.

    Returns
    -------
    Interval

    Examples
    --------
    >>> setbound.interval.power(setbound.Interval(-2.0, 1.0), 3)
    Interval(-8.0, 1.0)
    """
    iv = _require_interval(x, "x")
    n = as_int(n, "n", lo=-INT_MAX - 1, hi=INT_MAX)  # a C int exponent (the work does not grow with it)
    lo, hi = np.empty(1), np.empty(1)
    a, b = np.array([iv.lo]), np.array([iv.hi])
    check(lib.sb_interval_pow(1, dptr(a), dptr(b), int(n), _out(lo), _out(hi)))
    return Interval._raw(lo[0], hi[0])


# ---- boxes --------------------------------------------------------------------------------

class Box:
    """A box (interval vector) ``[lo, hi] ⊂ ℝⁿ``.

    Methods › Sets, intervals and LMI tools › Intervals and interval arithmetic. ``M @ box`` is the
    interval image by a real matrix, ``box + box`` the Minkowski sum; both are rounded outward.

    Parameters
    ----------
    lo, hi : array_like, shape (n,)
        Lower and upper corners (``lo <= hi``).
    name : str, optional
        Argument name used in error messages.

    Examples
    --------
    >>> b = setbound.Box([-1.0, 0.0], [1.0, 2.0])
    >>> b.contains([0.5, 1.0])
    True
    >>> print(np.array([[1.0, 1.0], [0.0, 1.0]]) @ b)
    Box(lo=[-1.0, 0.0], hi=[3.0, 2.0])
    """

    __array_ufunc__ = None  # make ``M @ box`` and ``2.0 * box`` reach our reflected operators

    def __init__(self, lo, hi, *, name: str = "box"):
        name = as_str(name, "name")  # a label for the messages
        lo = as_f64(lo, f"{name} (lo)", ndim=1).copy()
        hi = as_f64(hi, f"{name} (hi)", ndim=1).copy()
        if lo.shape != hi.shape:
            raise DimensionError(
                f"{name}: lower corner has {lo.size} entries but upper corner has {hi.size}")
        _check_ends(lo, hi, name, label="component")
        self._set(lo, hi)

    def _set(self, lo: np.ndarray, hi: np.ndarray) -> None:
        if (lo > hi).any():  # canonical empty box
            lo, hi = np.full(lo.shape, _INF), np.full(hi.shape, -_INF)
        lo.flags.writeable = False
        hi.flags.writeable = False
        self._lo, self._hi = lo, hi

    @classmethod
    def _raw(cls, lo, hi) -> "Box":
        obj = cls.__new__(cls)
        obj._set(np.array(lo, dtype=np.float64), np.array(hi, dtype=np.float64))
        return obj

    @classmethod
    def from_center_radius(cls, center, radius, *, name: str = "box") -> "Box":
        """The box ``center ± radius``, corners rounded outward by the C library.

        Parameters
        ----------
        center : array_like, shape (n,)
            Centre.
        radius : array_like, shape (n,)
            Radius of each component, ``>= 0``.
        name : str, optional
            Argument name used in error messages.

        Returns
        -------
        Box
        """
        name = as_str(name, "name")  # a label for the messages
        c = as_f64(center, f"{name} (center)", ndim=1)
        r = as_f64(radius, f"{name} (radius)", shape=(c.size,))
        if np.isnan(c).any() or np.isnan(r).any() or not np.isfinite(c).all():
            raise NotFiniteError(f"{name}: centre must be finite and radius must not be NaN")
        if (r < 0).any():
            k = int(np.flatnonzero(r < 0)[0])
            raise InvalidArgumentError(f"{name}: radius entry {k} is {r[k]}; it must be >= 0")
        lo, hi = _binary("add", c, c, -r, r)
        return cls._raw(lo, hi)

    @classmethod
    def empty(cls, n: int) -> "Box":
        """The empty box of dimension ``n``.

        Parameters
        ----------
        n : int
            Dimension, ``>= 0`` (refused when its 16 bytes per component exceed half the machine's
            memory).

        Returns
        -------
        Box
        """
        n = as_int(n, "n", lo=0)
        check_memory("n", n, 16.0 * n)
        return cls._raw(np.full(n, _INF), np.full(n, -_INF))

    lo = property(lambda self: self._lo, doc="Lower ends (read-only array).")
    hi = property(lambda self: self._hi, doc="Upper ends (read-only array).")

    def __len__(self) -> int:
        return self._lo.size

    @property
    def is_empty(self) -> bool:
        """True when some component is empty."""
        return bool((self._lo > self._hi).any())

    @property
    def center(self) -> np.ndarray:
        """Midpoint vector (also ``mid``)."""
        return _mid(self._lo, self._hi)

    mid = center

    @property
    def radius(self) -> np.ndarray:
        """Radius vector, rounded up (also ``rad``)."""
        return _rad(self._lo, self._hi)

    rad = radius

    @property
    def width(self) -> np.ndarray:
        """Width vector 𝕎 (eq. 1.13)."""
        return _width(self._lo, self._hi)

    @property
    def max_width(self) -> float:
        """w = max_i width_i (eq. 1.12)."""
        return float(self.width.max()) if len(self) else 0.0

    @property
    def max_radius(self) -> float:
        """r = max_i rad_i (eq. 1.14)."""
        return float(self.radius.max()) if len(self) else 0.0

    @property
    def volume(self) -> float:
        """Π_i width_i (eq. 1.17), a guaranteed upper bound computed by the C library."""
        out = ffi.new("double*")
        check(lib.sb_box_volume(len(self), dptr(self._lo), dptr(self._hi), out))
        return float(out[0])

    def norm(self) -> float:
        """The norm ``max_i mag([x_i])`` (largest magnitude of a component).

        Returns
        -------
        float
        """
        if len(self) == 0:
            return 0.0
        return float(np.maximum(np.abs(self._lo), np.abs(self._hi)).max())

    def split(self) -> tuple[np.ndarray, "Box"]:
        """Midpoint–radius form [x] ⊆ m + [Δx], [Δx] = [−rad, rad] (eqs. 1.15–1.16)."""
        r = self.radius
        return self.center, Box._raw(-r, r)

    def __getitem__(self, i) -> Interval:
        return Interval._raw(self._lo[i], self._hi[i])

    def contains(self, point) -> bool:
        """True when a point lies in the box.

        Parameters
        ----------
        point : array_like, shape (n,)
            The point.

        Returns
        -------
        bool
        """
        p = as_f64(point, "point", shape=(len(self),))
        return bool(((self._lo <= p) & (p <= self._hi)).all())

    __contains__ = contains

    def subset(self, other: "Box") -> bool:
        """True when this box is included in ``other``.

        Parameters
        ----------
        other : Box
            The other box.

        Returns
        -------
        bool
        """
        other = self._same(other, "other")
        return self.is_empty or bool(((other._lo <= self._lo) & (self._hi <= other._hi)).all())

    def _same(self, other, name: str) -> "Box":
        if not isinstance(other, Box):
            raise InvalidArgumentError(f"{name}: expected a Box, got {type(other).__name__}")
        if len(other) != len(self):
            raise DimensionError(f"{name}: box has {len(other)} components, expected {len(self)}")
        return other

    def _bin(self, op: str, other, name: str = "other") -> "Box":
        other = self._same(other, name)
        lo, hi = _binary(op, self._lo, self._hi, other._lo, other._hi)
        return Box._raw(lo, hi)

    def intersect(self, other: "Box") -> "Box":
        """Componentwise intersection with ``other``.

        Parameters
        ----------
        other : Box
            The other box.

        Returns
        -------
        Box
        """
        return self._bin("intersect", other)

    def hull(self, other: "Box") -> "Box":
        """The smallest box containing both boxes.

        Parameters
        ----------
        other : Box
            The other box.

        Returns
        -------
        Box
        """
        return self._bin("hull", other)

    def __add__(self, other):
        return self._bin("add", other, "rhs") if isinstance(other, Box) else NotImplemented

    def __sub__(self, other):
        return self._bin("sub", other, "rhs") if isinstance(other, Box) else NotImplemented

    def __neg__(self):
        lo, hi = _unary("neg", self._lo, self._hi)
        return Box._raw(lo, hi)

    def __mul__(self, a):
        if not isinstance(a, (int, float, np.floating, np.integer)):
            return NotImplemented
        a = float(a)
        if math.isnan(a) or math.isinf(a):
            raise NotFiniteError(f"a: scalar factor is {a}; it must be finite")
        n = len(self)
        lo, hi = _binary("mul", self._lo, self._hi, np.full(n, a), np.full(n, a))
        return Box._raw(lo, hi)

    __rmul__ = __mul__

    def __rmatmul__(self, M):
        """M @ box for a real matrix: the hull [Mc − |M|r, Mc + |M|r], enclosed under rounding."""
        if isinstance(M, (Box, IntervalMatrix)):
            return NotImplemented
        M = as_f64(M, "M", ndim=2)
        if M.shape[1] != len(self):
            raise DimensionError(
                f"M: matrix has {M.shape[1]} columns but the box has {len(self)} components")
        ylo, yhi = np.empty(M.shape[0]), np.empty(M.shape[0])
        check(lib.sb_matrix_mul_box(M.shape[0], M.shape[1], dptr(M), dptr(self._lo),
                                    dptr(self._hi), _out(ylo), _out(yhi)))
        return Box._raw(ylo, yhi)

    def __eq__(self, other):
        if not isinstance(other, Box):
            return NotImplemented
        return len(self) == len(other) and (
            (self.is_empty and other.is_empty)
            or (np.array_equal(self._lo, other._lo) and np.array_equal(self._hi, other._hi)))

    __hash__ = None

    def __repr__(self):
        return f"Box(lo={self._lo.tolist()}, hi={self._hi.tolist()})"


# ---- interval matrices --------------------------------------------------------------------

class IntervalMatrix:
    """An interval matrix ``[M] = [lo, hi]`` (entrywise bounds).

    Methods › Sets, intervals and LMI tools › Interval matrices. As the ``A`` of a
    :class:`~setbound.system.LinearSystem` it describes a system whose matrix is any (possibly
    time-varying) element of ``[M]``.

    Parameters
    ----------
    lo, hi : array_like, shape (p, q)
        Entrywise lower and upper bounds.
    name : str, optional
        Argument name used in error messages.

    Examples
    --------
    >>> M = setbound.IntervalMatrix.from_mid_rad([[1.0, 0.0], [0.0, 0.5]], [[0.0, 0.0], [0.0, 0.1]])
    >>> M.contains(np.array([[1.0, 0.0], [0.0, 0.55]]))
    True
    """

    __array_ufunc__ = None

    def __init__(self, lo, hi, *, name: str = "M"):
        name = as_str(name, "name")  # a label for the messages
        lo = as_f64(lo, f"{name} (lo)", ndim=2).copy()
        hi = as_f64(hi, f"{name} (hi)", ndim=2).copy()
        if lo.shape != hi.shape:
            raise DimensionError(
                f"{name}: lower bound is {lo.shape[0]}x{lo.shape[1]} but upper bound is "
                f"{hi.shape[0]}x{hi.shape[1]}")
        _check_ends(lo, hi, name, allow_empty=False)
        lo.flags.writeable = False
        hi.flags.writeable = False
        self._lo, self._hi = lo, hi

    @classmethod
    def from_mid_rad(cls, mid, rad, *, name: str = "M") -> "IntervalMatrix":
        """The interval matrix ``mid ± rad``, corners rounded outward by the C library.

        Parameters
        ----------
        mid : array_like, shape (p, q)
            Midpoint.
        rad : array_like, shape (p, q)
            Entrywise radius, ``>= 0``.
        name : str, optional
            Argument name used in error messages.

        Returns
        -------
        IntervalMatrix
        """
        name = as_str(name, "name")  # a label for the messages
        m = as_f64(mid, f"{name} (mid)", ndim=2)
        r = as_f64(rad, f"{name} (rad)", shape=m.shape)
        if not np.isfinite(m).all() or np.isnan(r).any():
            raise NotFiniteError(f"{name}: midpoint must be finite and radius must not be NaN")
        if (r < 0).any():
            raise InvalidArgumentError(f"{name}: radius entries must be >= 0")
        lo, hi = _binary("add", m, m, -r, r)
        return cls(lo.reshape(m.shape), hi.reshape(m.shape), name=name)

    lo = property(lambda self: self._lo, doc="Lower ends (read-only matrix).")
    hi = property(lambda self: self._hi, doc="Upper ends (read-only matrix).")
    shape = property(lambda self: self._lo.shape, doc="Shape (rows, cols).")

    @property
    def mid(self) -> np.ndarray:
        """Midpoint matrix mid[A]."""
        return _mid(self._lo, self._hi)

    @property
    def rad(self) -> np.ndarray:
        """Radius matrix rad[A] (rounded up)."""
        return _rad(self._lo, self._hi)

    @property
    def width(self) -> np.ndarray:
        """Entrywise widths."""
        return _width(self._lo, self._hi)

    @property
    def uncertain_count(self) -> int:
        """q, the number of entries with lo < hi; vertices() returns 2^q matrices."""
        return int((self._lo < self._hi).sum())

    def __getitem__(self, ij) -> Interval:
        return Interval._raw(self._lo[ij], self._hi[ij])

    def contains(self, N) -> bool:
        """True when a real matrix lies in ``[M]``.

        Parameters
        ----------
        N : array_like, shape (p, q)
            The matrix.

        Returns
        -------
        bool
        """
        N = as_f64(N, "N", shape=self.shape)
        return bool(((self._lo <= N) & (N <= self._hi)).all())

    __contains__ = contains

    def vertices(self) -> np.ndarray:
        """vert[M] as an array of shape (2^q, rows, cols). Uncertain entries are numbered in
        row-major order; in vertex v, entry k is at its upper end iff bit k of v is set."""
        r, c = self.shape
        count = ffi.new("int*", 0)
        status = lib.sb_imatrix_vertices(r, c, dptr(self._lo), dptr(self._hi), count, ffi.NULL)
        if status != lib.SB_ERR_BUFFER_TOO_SMALL:
            check(status)  # a real error (q too large, unbounded entries); OK only if 2^q = 0
        out = np.empty((count[0], r, c))
        check(lib.sb_imatrix_vertices(r, c, dptr(self._lo), dptr(self._hi), count, _out(out)))
        return out

    def norm(self) -> float:
        """The norm ``max_i Σ_j mag([m_ij])`` (largest row sum of magnitudes), rounded up.

        Returns
        -------
        float
        """
        out = ffi.new("double*")
        check(lib.sb_imatrix_norm(*self.shape, dptr(self._lo), dptr(self._hi), out))
        return float(out[0])

    def __matmul__(self, other):
        """[M] @ Box → Box (Remark 1.2); [M] @ vector → Box; [M] @ real matrix → IntervalMatrix
        (centre mid[M]N, radius rad[M]|N|)."""
        r, c = self.shape
        if isinstance(other, Box):
            xlo, xhi = other.lo, other.hi
            name = "x"
        elif isinstance(other, IntervalMatrix):
            return NotImplemented
        else:
            a = as_f64(other, "N")
            if a.ndim == 2:
                if a.shape[0] != c:
                    raise DimensionError(
                        f"N: has {a.shape[0]} rows but the interval matrix has {c} columns")
                Rlo, Rhi = np.empty((r, a.shape[1])), np.empty((r, a.shape[1]))
                check(lib.sb_imatrix_mul_matrix(r, c, a.shape[1], dptr(self._lo), dptr(self._hi),
                                                dptr(a), _out(Rlo), _out(Rhi)))
                result = IntervalMatrix.__new__(IntervalMatrix)
                Rlo.flags.writeable = False
                Rhi.flags.writeable = False
                result._lo, result._hi = Rlo, Rhi
                return result
            if a.ndim != 1:
                raise DimensionError(f"v: expected a vector or a matrix, got shape {a.shape}")
            if not np.isfinite(a).all():
                raise NotFiniteError("v: all entries must be finite")
            xlo = xhi = a
            name = "v"
        if len(xlo) != c:
            raise DimensionError(
                f"{name}: has {len(xlo)} entries but the interval matrix has {c} columns")
        ylo, yhi = np.empty(r), np.empty(r)
        check(lib.sb_imatrix_mul_box(r, c, dptr(self._lo), dptr(self._hi), dptr(xlo), dptr(xhi),
                                     _out(ylo), _out(yhi)))
        return Box._raw(ylo, yhi)

    def __repr__(self):
        return f"IntervalMatrix(lo={self._lo.tolist()}, hi={self._hi.tolist()})"
