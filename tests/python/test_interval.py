"""Interval analysis through the Python bindings (thesis §1, §3.1, §3.2, §7 item 1).

Exact reference values, outward rounding checked with exact rational arithmetic (Fraction),
randomised enclosure of sampled points (also with infinite ends), inclusion isotonicity, real
matrix × box against the vertex images, interval matrices, and the error classes/messages.
"""
from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from setbound.errors import (
    DimensionError,
    InvalidArgumentError,
    NotFiniteError,
    SetboundError,
)
from setbound.interval import (
    Box,
    Interval,
    IntervalMatrix,
    abs_,
    cos,
    exp,
    power,
    reciprocal,
    sin,
    sqr,
    sqrt,
)

INF = math.inf
PI = math.pi


def I(lo, hi):  # noqa: E743 - the thesis's notation
    return Interval(lo, hi)


# ---- thesis §3.1 (all exact) -----------------------------------------------------------------

def test_table_3_1_scalar_rows():
    assert I(-2, 4) + I(1, 3) == I(-1, 7)
    assert I(0, 7) - I(1, 2) == I(-2, 6)
    assert I(-2, 1) * I(3, 4) == I(-8, 4)
    assert I(6, 12) / I(2, 3) == I(2, 6)
    assert I(-1, 2).intersect(I(0, 4)) == I(0, 2)
    assert I(-2, 1).hull(I(2, 6)) == I(-2, 6)
    x = I(3, 8)
    assert x - x == I(-5, 5)  # dependency effect
    y = I(1, 2)
    assert y / y == I(0.5, 2)


def test_table_3_1_box_rows_and_example_1_2():
    assert Box([0, 1], [1, 3]) + Box([-2, 5], [4, 6]) == Box([-2, 6], [5, 9])
    assert Box([0, 2], [1, 3]) - Box([-2, -3], [0, -1]) == Box([0, 3], [3, 6])
    assert Box([0, 1], [5, 3]).intersect(Box([3, 2], [4, 6])) == Box([3, 2], [4, 3])
    assert Box([-2, 0], [1, 3]).hull(Box([2, 1], [6, 4])) == Box([-2, 0], [6, 4])
    x = Box([2, 2], [6, 4])
    assert x.volume == 8
    np.testing.assert_array_equal(x.width, [4, 2])
    assert x.max_width == 4 and x.max_radius == 2
    np.testing.assert_array_equal(x.center, [4, 3])
    m, d = x.split()
    np.testing.assert_array_equal(m, [4, 3])
    assert d == Box([-2, -1], [2, 1])
    assert x[0] == I(2, 6) and x.norm() == 6


def test_table_3_1_interval_matrix_rows():
    M = IntervalMatrix([[0, 2], [1, -1]], [[1, 3], [2, 4]])
    assert M @ Box([1, 0], [2, 3]) == Box([0, -2], [11, 16])
    A = IntervalMatrix([[-1, 0], [2, -2]], [[1, 3], [6, 0]])
    np.testing.assert_array_equal(A.lo, [[-1, 0], [2, -2]])
    np.testing.assert_array_equal(A.hi, [[1, 3], [6, 0]])
    np.testing.assert_array_equal(A.mid, [[0, 1.5], [4, -1]])
    np.testing.assert_array_equal(A.rad, [[1, 1.5], [2, 1]])
    assert A.norm() == 8
    assert A[1, 0] == I(2, 6)


def test_reciprocal_and_division_extended_cases():
    assert reciprocal(I(0, 0)).is_empty
    assert reciprocal(I(2, 4)) == I(0.25, 0.5)
    assert reciprocal(I(0, 2)) == I(0.5, INF)
    assert reciprocal(I(-4, 0)) == I(-INF, -0.25)
    assert reciprocal(I(-1, 1)) == Interval.entire()
    assert reciprocal(I(2, INF)) == I(0, 0.5)
    assert (I(1, 2) / I(0, 0)).is_empty
    assert I(0, 2) / I(0, 4) == I(0, INF)
    assert I(-2, -1) / I(-4, 0) == I(0.25, INF)
    assert 1 / I(2, 4) == I(0.25, 0.5)
    assert I(2, 4) ** -1 == I(0.25, 0.5)
    assert power(I(-2, 3), 3) == I(-8, 27)
    assert I(-2, 3) ** 2 == I(0, 9)


# ---- thesis §3.2 ----------------------------------------------------------------------------

def test_inclusion_functions_x2_minus_x():
    x = I(2, 4)
    assert sqr(x) - x == I(0, 14)
    assert x * (x - 1) == I(2, 12)


def test_four_forms_of_x2_plus_2x():
    x = I(-1, 1)
    assert sqr(x) == I(0, 1) and x * x == I(-1, 1)
    assert sqr(x) + 2 * x == I(-2, 3)
    assert x * (x + 2) == I(-3, 3)
    assert x * x + 2 * x == I(-3, 3)
    assert sqr(x + 1) - 1 == I(-1, 3)


def test_x2_plus_sin_x_natural_centered_taylor():
    x = I(2 * PI / 3, 4 * PI / 3)
    c = Interval(PI)
    nat = sqr(x) + sin(x)
    assert nat.lo == pytest.approx(3.52046, abs=1e-5) and nat.hi == pytest.approx(18.41199, abs=1e-5)
    fc = sqr(c) + sin(c)
    cen = fc + (2 * x + cos(x)) * (x - PI)
    assert (cen.lo, cen.hi) == pytest.approx((1.62022, 18.11899), abs=1e-5)
    tay = fc + (2 * c + cos(c)) * (x - PI) + 0.5 * sqr(x - PI) * (2 - sin(x))
    assert (tay.lo, tay.hi) == pytest.approx((4.33706, 16.97362), abs=1e-5)


# ---- outward rounding: exact rationals ------------------------------------------------------

def _contains_exact(iv: Interval, q: Fraction) -> bool:
    if iv.is_empty:
        return False
    above = iv.lo == -INF or Fraction(iv.lo) <= q
    below = iv.hi == INF or q <= Fraction(iv.hi)
    return above and below


def test_outward_rounding_encloses_exact_rationals(rng):
    s = Interval(0.1) + Interval(0.2)
    assert _contains_exact(s, Fraction(0.1) + Fraction(0.2))
    assert s.lo < s.hi and np.nextafter(s.lo, INF) == s.hi
    for _ in range(2000):
        a = float(rng.uniform(-1e3, 1e3) * 10.0 ** rng.integers(-20, 20))
        b = float(rng.uniform(-1e3, 1e3) * 10.0 ** rng.integers(-20, 20))
        A, B = Interval(a), Interval(b)
        fa, fb = Fraction(a), Fraction(b)
        for got, exact in ((A + B, fa + fb), (A - B, fa - fb), (A * B, fa * fb), (A / B, fa / fb)):
            assert _contains_exact(got, exact), (a, b, got)
            # tight: at most one ulp wide, and degenerate exactly when the result is a double
            assert got.hi <= np.nextafter(got.lo, INF)
            assert (got.lo == got.hi) == (Fraction(got.lo) == exact)
        r = sqrt(Interval(abs(a)))
        assert Fraction(r.lo) ** 2 <= Fraction(abs(a)) <= Fraction(r.hi) ** 2


def test_elementary_functions_enclose_high_precision_values(rng):
    mpmath = pytest.importorskip("mpmath")
    mpmath.mp.prec = 200
    funcs = [(exp, mpmath.exp), (sin, mpmath.sin), (cos, mpmath.cos)]
    for _ in range(500):
        t = float(rng.uniform(-30, 30))
        for f, ref in funcs:
            iv = f(Interval(t))
            v = ref(mpmath.mpf(t))
            assert mpmath.mpf(iv.lo) <= v <= mpmath.mpf(iv.hi), (f.__name__, t, iv)


# ---- randomised enclosure of sampled points and isotonicity --------------------------------

def _random_interval(rng) -> Interval:
    a, b = sorted(rng.uniform(-10, 10, 2))
    kind = rng.integers(8)
    return [Interval(a), I(-INF, b), I(a, INF), I(0, abs(a)), I(-abs(a), 0),
            Interval.entire(), I(a, b), I(a, b)][kind]


def _sample(rng, x: Interval) -> float:
    lo = x.lo if math.isfinite(x.lo) else min(x.hi, 0.0) - 1e6
    hi = x.hi if math.isfinite(x.hi) else max(x.lo, 0.0) + 1e6
    k = rng.integers(5)
    return lo if k == 0 else hi if k == 1 else float(lo + (hi - lo) * rng.uniform())


BINARY = [
    ("add", lambda a, b: a + b, lambda a, b: Fraction(a) + Fraction(b)),
    ("sub", lambda a, b: a - b, lambda a, b: Fraction(a) - Fraction(b)),
    ("mul", lambda a, b: a * b, lambda a, b: Fraction(a) * Fraction(b)),
    ("div", lambda a, b: a / b, lambda a, b: Fraction(a) / Fraction(b)),
]


@pytest.mark.parametrize("name,op,exact", BINARY, ids=[b[0] for b in BINARY])
def test_sampled_points_of_binary_ops_are_enclosed(rng, name, op, exact):
    for _ in range(400):
        x, y = _random_interval(rng), _random_interval(rng)
        z = op(x, y)
        for _ in range(5):
            a, b = _sample(rng, x), _sample(rng, y)
            if name == "div" and b == 0:
                continue
            assert _contains_exact(z, exact(a, b)), (x, y, a, b, z)


UNARY = [
    ("neg", lambda x: -x, lambda t: Fraction(-t)),
    ("recip", reciprocal, lambda t: 1 / Fraction(t)),
    ("sqr", sqr, lambda t: Fraction(t) ** 2),
    ("abs", abs_, lambda t: abs(Fraction(t))),
    ("pow3", lambda x: x ** 3, lambda t: Fraction(t) ** 3),
    ("pow-2", lambda x: x ** -2, lambda t: 1 / Fraction(t) ** 2),
]


@pytest.mark.parametrize("name,op,exact", UNARY, ids=[u[0] for u in UNARY])
def test_sampled_points_of_exact_functions_are_enclosed(rng, name, op, exact):
    for _ in range(400):
        x = _random_interval(rng)
        z = op(x)
        for _ in range(5):
            t = _sample(rng, x)
            if name in ("recip", "pow-2") and t == 0:
                continue
            assert _contains_exact(z, exact(t)), (x, t, z)


def test_sampled_points_of_libm_functions_are_enclosed(rng):
    mpmath = pytest.importorskip("mpmath")
    mpmath.mp.prec = 120
    for f, ref in ((exp, mpmath.exp), (sin, mpmath.sin), (cos, mpmath.cos), (sqrt, mpmath.sqrt)):
        for _ in range(300):
            x = _random_interval(rng)
            z = f(x)
            for _ in range(5):
                t = _sample(rng, x)
                if f is sqrt and t < 0:
                    continue
                v = ref(mpmath.mpf(t))
                assert z.lo == -INF or mpmath.mpf(z.lo) <= v, (f.__name__, x, t, z)
                assert z.hi == INF or v <= mpmath.mpf(z.hi), (f.__name__, x, t, z)


def test_inclusion_isotonicity(rng):
    ops = [lambda a, b: a + b, lambda a, b: a - b, lambda a, b: a * b, lambda a, b: a / b,
           lambda a, b: a.hull(b), lambda a, b: a.intersect(b)]
    funcs = [sqr, sqrt, exp, sin, cos, abs_, reciprocal, lambda x: -x, lambda x: x ** 3]
    for _ in range(500):
        X, Y = _random_interval(rng), _random_interval(rng)
        a, b = sorted((_sample(rng, X), _sample(rng, X)))
        c, d = sorted((_sample(rng, Y), _sample(rng, Y)))
        x, y = I(a, b), I(c, d)
        assert x.subset(X) and y.subset(Y)
        for op in ops:
            assert op(x, y).subset(op(X, Y)), (x, X, y, Y)
        for f in funcs:
            assert f(x).subset(f(X)), (x, X)


# ---- boxes and matrices ---------------------------------------------------------------------

def _exact_row_products(M, p):
    return [sum(Fraction(float(M[i, j])) * Fraction(float(p[j])) for j in range(M.shape[1]))
            for i in range(M.shape[0])]


def test_matrix_times_box_is_hull_of_vertex_images(rng):
    for _ in range(60):
        p, n = rng.integers(1, 4), rng.integers(1, 5)
        M = rng.uniform(-3, 3, (p, n))
        lo = rng.uniform(-2, 0, n)
        hi = lo + rng.uniform(0, 2, n)
        x = Box(lo, hi)
        y = M @ x
        # the exact hull, from the exact images of all 2^n vertices (Fractions)
        ex_lo = [None] * p
        ex_hi = [None] * p
        for v in range(2 ** n):
            corner = [hi[j] if (v >> j) & 1 else lo[j] for j in range(n)]
            img = _exact_row_products(M, corner)
            ex_lo = [q if e is None else min(e, q) for e, q in zip(ex_lo, img)]
            ex_hi = [q if e is None else max(e, q) for e, q in zip(ex_hi, img)]
        for i in range(p):
            assert Fraction(y.lo[i]) <= ex_lo[i] and ex_hi[i] <= Fraction(y.hi[i])
            # and it is the hull up to the outward rounding
            assert float(ex_lo[i]) - y.lo[i] <= 1e-12 * (1 + abs(y.lo[i]))
            assert y.hi[i] - float(ex_hi[i]) <= 1e-12 * (1 + abs(y.hi[i]))
        c, r = x.center, x.radius
        np.testing.assert_allclose(y.lo, M @ c - np.abs(M) @ r, atol=1e-12)
        np.testing.assert_allclose(y.hi, M @ c + np.abs(M) @ r, atol=1e-12)


def test_interval_matrix_vertices_and_sampled_products(rng):
    for _ in range(40):
        r, c = rng.integers(1, 4), rng.integers(1, 4)
        a, b = rng.uniform(-2, 2, (r, c)), rng.uniform(-2, 2, (r, c))
        b = np.where(rng.uniform(size=(r, c)) < 0.3, a, b)  # some certain entries
        M = IntervalMatrix(np.minimum(a, b), np.maximum(a, b))
        V = M.vertices()
        assert V.shape == (2 ** M.uncertain_count, r, c)
        assert len({v.tobytes() for v in V}) == V.shape[0]
        assert all(M.contains(v) for v in V)
        assert np.all((V == M.lo) | (V == M.hi))
        xlo = rng.uniform(-2, 0, c)
        x = Box(xlo, xlo + rng.uniform(0, 2, c))
        y = M @ x
        N = rng.uniform(-2, 2, (c, 2))
        MN = M @ N
        np.testing.assert_allclose(MN.mid, M.mid @ N, atol=1e-13)
        np.testing.assert_allclose(MN.rad, M.rad @ np.abs(N), atol=1e-13)
        for _ in range(10):
            S = M.lo + (M.hi - M.lo) * rng.uniform(size=(r, c))
            S = np.clip(S, M.lo, M.hi)
            pt = np.clip(x.lo + (x.hi - x.lo) * rng.uniform(size=c), x.lo, x.hi)
            for i, q in enumerate(_exact_row_products(S, pt)):
                assert Fraction(y.lo[i]) <= q <= Fraction(y.hi[i])
            SN = [[sum(Fraction(S[i, k]) * Fraction(N[k, j]) for k in range(c)) for j in range(2)]
                  for i in range(r)]
            for i in range(r):
                for j in range(2):
                    assert Fraction(MN.lo[i, j]) <= SN[i][j] <= Fraction(MN.hi[i, j])
            yv = M @ pt
            for i, q in enumerate(_exact_row_products(S, pt)):
                assert Fraction(yv.lo[i]) <= q <= Fraction(yv.hi[i])


def test_box_helpers_and_scaling():
    b = Box.from_center_radius([0.1], [0.2])
    assert Fraction(b.lo[0]) <= Fraction(0.1) - Fraction(0.2)
    assert Fraction(b.hi[0]) >= Fraction(0.1) + Fraction(0.2)
    assert -2 * Box([0, -1], [1, 3]) == Box([-2, -6], [0, 2])
    assert np.float64(2) * Box([0], [1]) == Box([0], [2])
    assert Box([0, 0], [1, 1]).intersect(Box([2, 0], [3, 1])).is_empty
    assert Box([0, 0], [1, 1]).contains([1, 0.5])
    assert not Box([0, 0], [1, 1]).contains([1.5, 0.5])
    assert Box([0, 0], [1, 1]).subset(Box([-1, 0], [1, 2]))
    M = IntervalMatrix.from_mid_rad([[0, 1.5], [4, -1]], [[1, 1.5], [2, 1]])
    np.testing.assert_array_equal(M.lo, [[-1, 0], [2, -2]])


# ---- errors: class and message naming the argument -----------------------------------------

@pytest.mark.parametrize(
    "make,cls,prefix",
    [
        (lambda: Interval(2, 1, name="d"), InvalidArgumentError, "d:"),
        (lambda: Interval(math.nan, 1), NotFiniteError, "interval:"),
        (lambda: Interval(INF, INF), InvalidArgumentError, "interval:"),
        (lambda: I(0, 1) + math.nan, NotFiniteError, "other:"),
        (lambda: Box([0, 2], [1, 1]), InvalidArgumentError, "box component 1:"),
        (lambda: Box([0, math.nan], [1, 1], name="x0"), NotFiniteError, "x0 component 1:"),
        (lambda: Box([0, 0], [1, 1, 1]), DimensionError, "box:"),
        (lambda: Box.from_center_radius([0, 0], [1, -1]), InvalidArgumentError, "box:"),
        (lambda: np.ones((2, 3)) @ Box([0, 0], [1, 1]), DimensionError, "M:"),
        (lambda: np.array([[1.0, math.inf]]) @ Box([0, 0], [1, 1]), NotFiniteError,
         "sb_matrix_mul_box: M:"),
        (lambda: IntervalMatrix([[0, 3]], [[1, 2]]), InvalidArgumentError, "M entry (0, 1):"),
        (lambda: IntervalMatrix([[0, 1]], [[1, 2], [3, 4]]), DimensionError, "M:"),
        (lambda: IntervalMatrix(np.zeros((3, 7)), np.ones((3, 7))).vertices(),
         InvalidArgumentError, "sb_imatrix_vertices: M:"),
        (lambda: IntervalMatrix([[-INF, 0]], [[0, 1]]).vertices(), NotFiniteError,
         "sb_imatrix_vertices: M:"),
        (lambda: IntervalMatrix([[0, 0]], [[1, 1]]) @ np.ones(3), DimensionError, "v:"),
        (lambda: IntervalMatrix([[0, 0]], [[1, 1]]) @ np.array([1.0, math.nan]), NotFiniteError,
         "v:"),
        (lambda: Box([0], [1]) * math.inf, NotFiniteError, "a:"),
        (lambda: I(1, 2) ** 0.5, InvalidArgumentError, "n:"),
        (lambda: Box([0, 0], [1, 1]) + Box([0], [1]), DimensionError, "rhs:"),
    ],
)
def test_bad_inputs_raise_named_errors(make, cls, prefix):
    with pytest.raises(cls) as info:
        make()
    assert isinstance(info.value, SetboundError)
    assert str(info.value).startswith(prefix), str(info.value)


def test_c_abi_errors_reach_python_with_status():
    from setbound._native import ffi, lib

    lo = np.array([0.0, 1.0])
    hi = np.array([1.0, 0.5])
    out = np.empty(2)
    p = ffi.cast("double*", ffi.from_buffer(out))
    q = ffi.cast("double*", ffi.from_buffer(lo))
    h = ffi.cast("double*", ffi.from_buffer(hi))
    assert lib.sb_interval_unary(lib.SB_IV_SQRT, 2, q, h, p, p) == lib.SB_ERR_INVALID_ARGUMENT
    assert lib.sb_interval_binary(42, 2, q, q, q, q, p, p) == lib.SB_ERR_INVALID_ARGUMENT
    assert lib.sb_interval_binary(lib.SB_IV_ADD, 2, ffi.NULL, q, q, q, p, p) == \
        lib.SB_ERR_INVALID_ARGUMENT
    count = ffi.new("int*", 1)
    mlo = np.zeros((2, 2))
    mhi = np.ones((2, 2))
    assert lib.sb_imatrix_vertices(2, 2, ffi.cast("double*", ffi.from_buffer(mlo)),
                                   ffi.cast("double*", ffi.from_buffer(mhi)), count,
                                   ffi.NULL) == lib.SB_ERR_BUFFER_TOO_SMALL
    assert count[0] == 16


def test_outward_rounding_near_underflow_and_overflow(rng):
    """Subnormal and overflowing results fall back to safe outward steps: still enclosing."""
    big = np.finfo(float).max
    cases = [(1e-160, 1e-160), (3e-200, -7e-170), (1e-300, 3.0), (5e-324, 0.5), (big, 2.0),
             (-big, big), (1e-310, 1e10), (2.5e-308, 1e-16)]
    for _ in range(300):
        cases.append((float(rng.uniform(-1, 1) * 10.0 ** rng.integers(-320, -280)),
                      float(rng.uniform(-1, 1) * 10.0 ** rng.integers(-30, 30))))
    for a, b in cases:
        A, B = Interval(a), Interval(b)
        fa, fb = Fraction(a), Fraction(b)
        for got, exact in ((A + B, fa + fb), (A - B, fa - fb), (A * B, fa * fb)):
            assert _contains_exact(got, exact), (a, b, got)
        if b != 0:
            assert _contains_exact(A / B, fa / fb), (a, b, A / B)
        if a > 0:
            r = sqrt(A)
            assert Fraction(r.lo) ** 2 <= fa <= Fraction(r.hi) ** 2
    s = Interval(big) + Interval(big)
    assert s.lo == big and s.hi == INF
