"""Inclusion functions (thesis §1.2.8, spec §3.1–§3.2): the worked examples to the printed
decimals, and randomized enclosure checks with random expression trees built from
+ − × / sqr sin cos exp sqrt (hypothesis)."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from setbound.errors import DimensionError, InvalidArgumentError
from setbound.inclusion import centered_inclusion, natural_inclusion, taylor2_inclusion
from setbound.interval import Box, Interval, IntervalMatrix, cos, exp, sin, sqr, sqrt

PI = math.pi


def close(x: Interval, lo: float, hi: float, tol: float) -> bool:
    return abs(x.lo - lo) <= tol and abs(x.hi - hi) <= tol


def test_section31_table():
    assert Interval(-2, 4) + Interval(1, 3) == Interval(-1, 7)
    assert Interval(0, 7) - Interval(1, 2) == Interval(-2, 6)
    assert Interval(-2, 1) * Interval(3, 4) == Interval(-8, 4)
    assert Interval(6, 12) / Interval(2, 3) == Interval(2, 6)
    assert Interval(-1, 2).intersect(Interval(0, 4)) == Interval(0, 2)
    assert Interval(-2, 1).hull(Interval(2, 6)) == Interval(-2, 6)
    assert Interval(3, 8) - Interval(3, 8) == Interval(-5, 5)
    assert Interval(1, 2) / Interval(1, 2) == Interval(0.5, 2)


def test_section32_polynomial_forms():
    x = Interval(2, 4)
    assert natural_inclusion(lambda t: sqr(t) - t, x) == Interval(0, 14)
    assert natural_inclusion(lambda t: t * (t - 1), x) == Interval(2, 12)
    x = Interval(-1, 1)
    assert natural_inclusion(lambda t: sqr(t) + 2 * t, x) == Interval(-2, 3)
    assert natural_inclusion(lambda t: t * (t + 2), x) == Interval(-3, 3)
    assert natural_inclusion(lambda t: t * t + 2 * t, x) == Interval(-3, 3)
    assert natural_inclusion(lambda t: sqr(t + 1) - 1, x) == Interval(-1, 3)
    assert sqr(x) == Interval(0, 1)


def test_section32_square_plus_sine():
    x = Interval(2 * PI / 3, 4 * PI / 3)
    f = lambda t: sqr(t) + sin(t)  # noqa: E731
    df = lambda t: 2 * t + cos(t)  # noqa: E731
    d2f = lambda t: 2 - sin(t)  # noqa: E731
    tol = 1e-5  # printed to 5 decimals (rounded or truncated: 3.520465 is printed 3.52046)
    assert close(natural_inclusion(f, x), 3.52046, 18.41199, tol)
    assert close(df(x), 3.18879, 7.87758, tol)
    assert close(centered_inclusion(f, df, x), 1.62022, 18.11899, tol)
    assert close(d2f(x), 1.13397, 2.86603, tol)
    assert close(taylor2_inclusion(f, df, d2f, x), 4.33706, 16.97362, tol)
    fmin = f(Interval(x.lo)).hull(f(Interval(x.hi)))
    assert close(fmin, 5.25251, 16.67994, tol)


def test_elementary_interior_extrema():
    assert sin(Interval(1, 2)).hi == 1.0
    assert sin(Interval(4, 5)).lo == -1.0
    assert cos(Interval(3, 3.5)).lo == -1.0
    assert cos(Interval(-0.5, 0.25)).hi == 1.0
    assert sqr(Interval(-1, 2)) == Interval(0, 4)


# --------------------------------------------------------------------------- random trees
# A node evaluates (value, d/dx, d²/dx²) over floats or Intervals: forward mode, second order.

class Num:
    """Adapter: the same tree code for floats (math) and Intervals (setbound.interval)."""

    def __init__(self, interval: bool):
        self.iv = interval

    def c(self, v):
        return Interval(v) if self.iv else v

    def sqr(self, a):
        return sqr(a) if self.iv else a * a

    def sin(self, a):
        return sin(a) if self.iv else math.sin(a)

    def cos(self, a):
        return cos(a) if self.iv else math.cos(a)

    def exp(self, a):
        return exp(a) if self.iv else math.exp(a)

    def sqrt(self, a):
        return sqrt(a) if self.iv else math.sqrt(a)


def ev(tree, x, N: Num):
    """tree: nested tuples; returns (f, f', f'')."""
    op = tree[0]
    z = N.c(0.0)
    if op == "x":
        return x, N.c(1.0), z
    if op == "c":
        return N.c(tree[1]), z, z
    if op in ("+", "-", "*", "/"):
        a, b = ev(tree[1], x, N), ev(tree[2], x, N)
        if op == "+":
            return a[0] + b[0], a[1] + b[1], a[2] + b[2]
        if op == "-":
            return a[0] - b[0], a[1] - b[1], a[2] - b[2]
        if op == "*":
            return a[0] * b[0], a[1] * b[0] + a[0] * b[1], a[2] * b[0] + 2 * a[1] * b[1] + a[0] * b[2]
        # a / (b² + 1): domain-safe division
        q = (N.sqr(b[0]) + 1, 2 * b[0] * b[1], 2 * N.sqr(b[1]) + 2 * b[0] * b[2])
        r = N.c(1.0) / q[0]
        inv = (r, z - q[1] * N.sqr(r), 2 * N.sqr(q[1]) * N.sqr(r) * r - q[2] * N.sqr(r))
        return a[0] * inv[0], a[1] * inv[0] + a[0] * inv[1], a[2] * inv[0] + 2 * a[1] * inv[1] + a[0] * inv[2]
    a = ev(tree[1], x, N)

    def chain(g, g1, g2):
        return g, g1 * a[1], g2 * N.sqr(a[1]) + g1 * a[2]

    if op == "sqr":
        return chain(N.sqr(a[0]), 2 * a[0], N.c(2.0))
    if op == "sin":
        return chain(N.sin(a[0]), N.cos(a[0]), z - N.sin(a[0]))
    if op == "cos":
        return chain(N.cos(a[0]), z - N.sin(a[0]), z - N.cos(a[0]))
    if op == "exp":
        e = N.exp(a[0])
        return chain(e, e, e)
    # sqrt(a² + 1)
    s = (N.sqr(a[0]) + 1, 2 * a[0] * a[1], 2 * N.sqr(a[1]) + 2 * a[0] * a[2])
    rt = N.sqrt(s[0])
    return (rt, 0.5 * s[1] / rt, 0.5 * s[2] / rt - 0.25 * N.sqr(s[1]) / (rt * s[0]))


leaves = st.one_of(st.just(("x",)), st.floats(-2, 2).map(lambda c: ("c", c)))
trees = st.recursive(
    leaves,
    lambda ch: st.one_of(
        st.tuples(st.sampled_from(["+", "-", "*", "/"]), ch, ch),
        st.tuples(st.sampled_from(["sqr", "sin", "cos", "sqrt"]), ch),
        st.tuples(st.just("exp"), leaves),
    ),
    max_leaves=6,
)


@settings(max_examples=60, deadline=None)
@given(tree=trees, c=st.floats(-3, 3), w=st.floats(0, 1.5), ts=st.lists(st.floats(0, 1), min_size=15, max_size=15))
def test_random_scalar_forms_enclose(tree, c, w, ts):
    x = Interval(c - w, c + w)
    NI = Num(True)
    f = lambda s: ev(tree, s, NI)[0]  # noqa: E731
    df = lambda s: ev(tree, s, NI)[1]  # noqa: E731
    d2f = lambda s: ev(tree, s, NI)[2]  # noqa: E731
    forms = {"natural": natural_inclusion(f, x), "centered": centered_inclusion(f, df, x),
             "taylor2": taylor2_inclusion(f, df, d2f, x)}
    for t in [0.0, 1.0] + ts:
        p = x.lo + t * (x.hi - x.lo)
        v = ev(tree, p, Num(False))[0]
        for name, r in forms.items():
            assert r.contains(v), f"{name} {r} misses f({p}) = {v} for {tree}"
    # the test's forward-mode derivative is right (so the forms got correct inputs)
    h = 1e-6
    d = ev(tree, c, Num(False))[1]
    fd = (ev(tree, c + h, Num(False))[0] - ev(tree, c - h, Num(False))[0]) / (2 * h)
    assert abs(d - fd) <= 1e-4 * max(1.0, abs(fd))


def vf(x):
    a, b = x[0], x[1]
    return [a * b + sin(a), exp(0.5 * b) - sqr(a), sqrt(sqr(a) + 1) * cos(b)]


def vf_point(a, b):
    return np.array([a * b + math.sin(a), math.exp(0.5 * b) - a * a, math.sqrt(a * a + 1) * math.cos(b)])


def vjac(x):
    a, b = x[0], x[1]
    s = sqrt(sqr(a) + 1)
    return [[b + cos(a), a], [-2 * a, 0.5 * exp(0.5 * b)], [a / s * cos(b), 0 - s * sin(b)]]


def vhess(x):
    a, b = x[0], x[1]
    s = sqrt(sqr(a) + 1)
    z = Interval(0.0)
    return [[[z - sin(a), 1], [1, z]],
            [[-2, z], [z, 0.25 * exp(0.5 * b)]],
            [[cos(b) / (s * sqr(s)), z - a / s * sin(b)], [z - a / s * sin(b), z - s * cos(b)]]]


@settings(max_examples=40, deadline=None)
@given(c=st.tuples(st.floats(-2, 2), st.floats(-2, 2)), r=st.tuples(st.floats(0, 0.8), st.floats(0, 0.8)),
       seed=st.integers(0, 2**31))
def test_random_vector_forms_enclose(c, r, seed):
    x = Box(np.subtract(c, r), np.add(c, r))
    forms = {"natural": natural_inclusion(lambda b: Box([t.lo for t in vf(b)], [t.hi for t in vf(b)]), x),
             "centered": centered_inclusion(vf, vjac, x), "taylor2": taylor2_inclusion(vf, vjac, vhess, x)}
    g = np.random.default_rng(seed)
    for _ in range(20):
        p = x.lo + g.random(2) * (x.hi - x.lo)
        v = vf_point(*p)
        for name, b in forms.items():
            assert b.contains(v), f"{name} {b} misses {v}"


def test_vector_forms_accept_interval_matrix_and_tighten():
    x = Box([0.4, -0.3], [0.42, -0.28])
    jm = lambda b: IntervalMatrix([[t.lo for t in row] for row in vjac(b)], [[t.hi for t in row] for row in vjac(b)])  # noqa: E731
    cen = centered_inclusion(vf, jm, x)
    tay = taylor2_inclusion(vf, vjac, vhess, x)
    nat = natural_inclusion(vf, x)
    assert np.sum(tay.width) < sum(t.width for t in nat)
    assert np.sum(cen.width) < sum(t.width for t in nat)


def test_bad_input():
    f = lambda t: t  # noqa: E731
    with pytest.raises(InvalidArgumentError, match="^x: .*bounded"):
        centered_inclusion(f, f, Interval(0, math.inf))
    with pytest.raises(InvalidArgumentError, match="^x: .*empty"):
        taylor2_inclusion(f, f, f, Interval.empty())
    with pytest.raises(InvalidArgumentError, match="^x: "):
        natural_inclusion(f, 3.0)
    with pytest.raises(DimensionError, match="^jacobian"):
        centered_inclusion(vf, lambda b: [[1, 2]], Box([0, 0], [1, 1]))
