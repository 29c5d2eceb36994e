"""Ellipsoids, zonotopes and strips through the Python layer (spec papers.md §0.1, thesis.md §1, §3.3)."""
import itertools
import math

import numpy as np
import pytest
import scipy.linalg
from scipy.spatial import ConvexHull

from setbound import errors
from setbound.sets import Ellipsoid, Strip, Zonotope, interval_linear_map


# ---- helpers -------------------------------------------------------------------------------

def random_spd(rng, n, floor=0.1):
    A = rng.standard_normal((n, n))
    return A @ A.T + floor * np.eye(n)


def ellipsoid_samples(E, rng, k, boundary=False):
    """Points of E: c + sqrt(rho) L^-T u, ||u|| <= 1 (P = L L^T)."""
    u = rng.standard_normal((k, E.n))
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    if not boundary:
        u *= rng.uniform(0, 1, (k, 1)) ** (1.0 / E.n)
    L = np.linalg.cholesky(E.P)
    return E.center + math.sqrt(E.rho) * scipy.linalg.solve_triangular(L.T, u.T, lower=False).T


def quad(E, X):
    D = np.atleast_2d(X) - E.center
    return np.einsum("ki,ij,kj->k", D, E.P, D)


def zonotope_samples(Z, rng, k, vertices=False):
    S = rng.uniform(-1, 1, (k, Z.m))
    if vertices:
        S = np.sign(S)
    return Z.center + S @ Z.generators.T


def all_vertices(Z):
    S = np.array(list(itertools.product([-1.0, 1.0], repeat=Z.m)))
    return Z.center + S @ Z.generators.T


def random_zonotope(rng, n, m):
    return Zonotope(2 * rng.standard_normal(n), rng.standard_normal((n, m)))


def assert_support_dominates(outer, inner, rng, ndir=300):
    D = rng.standard_normal((ndir, inner.n))
    ho, hi = outer.support(D), inner.support(D)
    assert np.all(hi <= ho + 1e-10 * (1 + np.abs(ho)))


# ---- ellipsoids: exact values --------------------------------------------------------------

def test_unit_ball_volumes_are_vn():
    assert Ellipsoid(np.eye(2), np.zeros(2), 1.0).volume == pytest.approx(math.pi, rel=1e-14)
    assert Ellipsoid(np.eye(3), np.ones(3), 1.0).volume == pytest.approx(4 * math.pi / 3, rel=1e-14)
    # rho is a level: the semi-axes scale by sqrt(rho), the area by rho in 2-D.
    E = Ellipsoid(np.diag([1 / 9, 4.0]), np.zeros(2), 2.5)
    assert E.volume == pytest.approx(math.pi * 3 * 0.5 * 2.5, rel=1e-13)
    assert E.log_volume == pytest.approx(math.log(E.volume), rel=1e-13)
    assert Ellipsoid(7 * E.P, E.center, 7 * E.rho).volume == pytest.approx(E.volume, rel=1e-13)


def test_thesis_example_13_bounding_box_from_inverse():
    # thesis §3.3: c = 0, P = [[1, 1], [1, 4]], rho = 1; (1.40) needs diag(P^-1) = (4/3, 1/3).
    P = np.array([[1.0, 1.0], [1.0, 4.0]])
    E = Ellipsoid(P, [0.0, 0.0], 1.0)
    lo, hi = E.bounding_box()
    np.testing.assert_allclose(hi, [math.sqrt(4 / 3), math.sqrt(1 / 3)], rtol=1e-13)
    np.testing.assert_allclose(lo, -hi, rtol=0)
    assert abs(hi[0] - 1.0) > 0.1 and abs(hi[1] - 0.5) > 0.05  # not the (wrong) printed box
    Pinv = np.linalg.inv(P)
    for i in range(2):
        x = Pinv[:, i] / math.sqrt(Pinv[i, i])  # c + rho^1/2 P^-1 e_i / sqrt((P^-1)_ii)
        assert quad(E, x)[0] == pytest.approx(1.0, rel=1e-13)
        assert x[i] == pytest.approx(hi[i], rel=1e-12)
        assert -x[i] == pytest.approx(lo[i], rel=1e-12)
        assert E.support(np.eye(2)[i]) == pytest.approx(hi[i], rel=1e-13)


def test_bounding_box_contains_samples(rng):
    for n in range(1, 6):
        E = Ellipsoid(random_spd(rng, n), 3 * rng.standard_normal(n), rng.uniform(0.1, 5))
        lo, hi = E.bounding_box()
        X = ellipsoid_samples(E, rng, 500, boundary=True)
        assert np.all(X >= lo) and np.all(X <= hi)


def test_contains_and_support(rng):
    E = Ellipsoid(random_spd(rng, 3), rng.standard_normal(3), 2.0)
    X = ellipsoid_samples(E, rng, 400)
    assert E.contains(X).all()
    out = E.center + 1.001 * (ellipsoid_samples(E, rng, 100, boundary=True) - E.center)
    assert not E.contains(out).any()
    assert E.contains(E.center) is True
    D = rng.standard_normal((50, 3))
    h = E.support(D)
    expected = D @ E.center + np.sqrt(E.rho * np.einsum("ki,ij,kj->k", D, np.linalg.inv(E.P), D))
    np.testing.assert_allclose(h, expected, rtol=1e-12)
    B = ellipsoid_samples(E, rng, 300, boundary=True)
    assert np.all(B @ D.T <= h + 1e-10)


def test_affine_map_maps_samples_and_scales_volume(rng):
    for n in (2, 3, 4):
        E = Ellipsoid(random_spd(rng, n), rng.standard_normal(n), rng.uniform(0.5, 3))
        M = rng.standard_normal((n, n)) + 2 * np.eye(n)
        b = rng.standard_normal(n)
        F = E.affine_map(M, b)
        assert F.volume == pytest.approx(abs(np.linalg.det(M)) * E.volume, rel=1e-10)
        X = ellipsoid_samples(E, rng, 200, boundary=True)
        np.testing.assert_allclose(quad(F, X @ M.T + b), F.rho, rtol=1e-9)


def test_with_shape_contains_original_and_is_tight(rng):
    for n in (1, 2, 3, 5):
        E = Ellipsoid(random_spd(rng, n), rng.standard_normal(n), rng.uniform(0.2, 4))
        Pn = random_spd(rng, n)
        F = E.with_shape(Pn)
        lam_max = scipy.linalg.eigh(Pn, E.P, eigvals_only=True).max()  # independent solver
        assert F.rho >= E.rho * lam_max
        assert F.rho <= E.rho * lam_max * (1 + 1e-9)
        np.testing.assert_array_equal(F.P, Pn)
        assert F.contains(ellipsoid_samples(E, rng, 500, boundary=True), rel_tol=0.0).all()
    E = Ellipsoid(np.eye(2), [0, 0], 3.0)
    assert E.reshape(np.diag([2.0, 5.0])).rho == pytest.approx(15.0, rel=1e-12)
    assert E.level_for_shape(np.diag([2.0, 5.0])) >= 15.0


# ---- zonotopes -----------------------------------------------------------------------------

def test_zonotope_volume_exact_values_and_hulls(rng):
    assert Zonotope([1, 1, 1], np.diag([0.5, 2.0, 3.0])).volume == pytest.approx(24.0, rel=1e-14)
    H = rng.standard_normal((4, 4))
    assert Zonotope(np.zeros(4), H).volume == pytest.approx(16 * abs(np.linalg.det(H)), rel=1e-11)
    assert Zonotope(np.zeros(3), rng.standard_normal((3, 2))).volume == 0.0
    # Independent volume: the convex hull of all 2^m vertices (qhull), in 2-D and 3-D.
    for n, m in [(2, 3), (2, 6), (3, 4), (3, 6)]:
        Z = random_zonotope(rng, n, m)
        assert Z.volume == pytest.approx(ConvexHull(all_vertices(Z)).volume, rel=1e-9)


def test_zonotope_volume_scales_by_det_and_refuses_huge_enumerations(rng):
    Z = random_zonotope(rng, 3, 6)
    M = rng.standard_normal((3, 3))
    assert (M @ Z).volume == pytest.approx(abs(np.linalg.det(M)) * Z.volume, rel=1e-10)
    with pytest.raises(errors.InvalidArgumentError, match="H:"):
        _ = random_zonotope(rng, 10, 60).volume


def test_zonotope_support_hull_and_minkowski_sum(rng):
    A, B = random_zonotope(rng, 3, 5), random_zonotope(rng, 3, 2)
    S = A + B
    assert S.m == 7 and S.order == pytest.approx(7 / 3)
    D = rng.standard_normal((100, 3))
    np.testing.assert_allclose(S.support(D), A.support(D) + B.support(D), rtol=1e-12, atol=1e-12)
    V = all_vertices(A)
    np.testing.assert_allclose(A.support(D), (V @ D.T).max(axis=0), rtol=1e-12, atol=1e-12)
    lo, hi = A.interval_hull()
    assert np.all(lo <= V.min(axis=0)) and np.all(hi >= V.max(axis=0))
    np.testing.assert_allclose(hi, V.max(axis=0), rtol=1e-12)
    T = A.translate([1, 2, 3])
    np.testing.assert_array_equal(T.center, A.center + [1, 2, 3])
    np.testing.assert_array_equal((A + np.array([1.0, 2, 3])).center, T.center)


def test_pradius_simple_cases_and_vertex(rng):
    assert Zonotope([0, 0], np.eye(2)).pradius(np.eye(2)) == pytest.approx(2.0)
    assert Zonotope([1, 1], np.diag([3, 0.5])).pradius(np.diag([2, 7])) == pytest.approx(18 + 1.75)
    Z = random_zonotope(rng, 3, 9)
    P = random_spd(rng, 3)
    r, s = Z.pradius(P, return_vertex=True)
    V = all_vertices(Z) - Z.center
    brute = np.einsum("ki,ij,kj->k", V, P, V).max()
    assert r == pytest.approx(brute, rel=1e-12)
    assert set(np.abs(s)) == {1.0}
    e = Z.generators @ s
    assert e @ P @ e == pytest.approx(r, rel=1e-12)
    X = zonotope_samples(Z, rng, 500) - Z.center
    assert np.all(np.einsum("ki,ij,kj->k", X, P, X) <= r * (1 + 1e-12))


@pytest.mark.parametrize("method", ["combastel", "girard", "pca"])
def test_reduction_contains_the_original(rng, method):
    for n in (2, 3):
        Z = random_zonotope(rng, n, 5 * n)
        for limit in range(n, 5 * n, 2):
            R = Z.reduce(limit, method=method)
            assert R.m <= limit
            np.testing.assert_array_equal(R.center, Z.center)
            assert_support_dominates(R, Z, rng)
            X = np.vstack([zonotope_samples(Z, rng, 100), zonotope_samples(Z, rng, 100, vertices=True)])
            assert R.contains(X).all()
        assert Z.reduce(5 * n + 3, method=method).m == 5 * n  # unchanged when m <= limit


def test_reduction_to_n_is_the_interval_hull(rng):
    Z = random_zonotope(rng, 3, 8)
    for method in ("combastel", "girard"):
        R = Z.reduce(3, method)
        np.testing.assert_allclose(R.generators, np.diag(np.abs(Z.generators).sum(axis=1)), rtol=1e-14)


def test_strip_family_contains_intersection_for_random_lambda(rng):
    for trial in range(20):
        n, m = 2 + trial % 2, 3 + trial % 4
        Z = random_zonotope(rng, n, m)
        c = rng.standard_normal(n)
        S = Strip(c, float(c @ zonotope_samples(Z, rng, 1)[0]), rng.uniform(0.05, 0.6))
        lam = rng.standard_normal(n) * (3.0 if trial % 3 == 0 else 0.3)
        R = Z.intersect_strip(S, lam)
        assert R.m == m + 1
        X = zonotope_samples(Z, rng, 3000)
        X = X[S.contains(X)]
        assert len(X) > 10
        assert R.contains(X).all()
    # Exact case: [-1, 1]^2 ∩ {|x1 - 0.5| <= 0.1} with lambda = e1 is [0.4, 0.6] x [-1, 1].
    R = Zonotope([0, 0], np.eye(2)).intersect_strip(Strip([1, 0], 0.5, 0.1), [1, 0])
    lo, hi = R.interval_hull()
    np.testing.assert_allclose(lo, [0.4, -1], atol=1e-14)
    np.testing.assert_allclose(hi, [0.6, 1], atol=1e-14)


def test_interval_linear_map_contains_every_image(rng):
    for trial in range(10):
        n, k, m = 2, 2 + trial % 2, 2 + trial % 3
        Z = random_zonotope(rng, n, m)
        mid = rng.standard_normal((k, n))
        rad = 0.2 * np.abs(rng.standard_normal((k, n)))
        R = interval_linear_map(mid, rad, Z)
        assert R.m == m + 2 * k
        for s in range(100):
            vertex = s % 2 == 0
            T = rng.uniform(-1, 1, (k, n))
            A = mid + rad * (np.sign(T) if vertex else T)
            x = A @ zonotope_samples(Z, rng, 1, vertices=vertex)[0]
            assert R.contains(x)
            D = rng.standard_normal((5, k))
            assert np.all(D @ x <= R.support(D) + 1e-10)
    R2 = Z.interval_linear_map(mid, rad)
    np.testing.assert_array_equal(R2.generators, interval_linear_map(mid, rad, Z).generators)


def test_strip_contains_width_and_half_spaces(rng):
    S = Strip([3, 4], 1.0, 0.5)
    assert S.width == pytest.approx(0.2)
    assert S.contains([0.5, 0.0]) and S.contains([0.0, 0.125])
    assert not S.contains([0.0, 0.0])
    X = rng.standard_normal((500, 2))
    (a1, b1), (a2, b2) = S.half_spaces()
    np.testing.assert_array_equal(S.contains(X, rel_tol=0.0), (X @ a1 <= b1) & (X @ a2 <= b2))


def test_objects_are_immutable():
    Z = Zonotope([0, 0], np.eye(2))
    with pytest.raises(ValueError):
        Z.generators[0, 0] = 5.0
    E = Ellipsoid(np.eye(2), [0, 0], 1.0)
    with pytest.raises(ValueError):
        E.P[0, 0] = 5.0


# ---- bad input -----------------------------------------------------------------------------

NAN = float("nan")
BAD_INPUTS = [
    ("non-PD P", lambda: Ellipsoid([[1, 2], [2, 1]], [0, 0], 1), errors.NotPositiveDefiniteError, "P:"),
    ("non-symmetric P", lambda: Ellipsoid([[2, 1], [0, 2]], [0, 0], 1), errors.NotSymmetricError, "P:"),
    ("NaN P", lambda: Ellipsoid([[NAN, 0], [0, 1]], [0, 0], 1), errors.NotFiniteError, "P:"),
    ("NaN centre", lambda: Ellipsoid(np.eye(2), [0, NAN], 1), errors.NotFiniteError, "c:"),
    ("P wrong shape", lambda: Ellipsoid(np.eye(3), [0, 0], 1), errors.DimensionError, "P:"),
    ("negative rho", lambda: Ellipsoid(np.eye(2), [0, 0], -1), errors.InvalidArgumentError, "rho:"),
    ("infinite rho", lambda: Ellipsoid(np.eye(2), [0, 0], math.inf), errors.NotFiniteError, "rho:"),
    ("singular M", lambda: Ellipsoid(np.eye(2), [0, 0], 1).affine_map([[1, 2], [2, 4]]),
     errors.InvalidArgumentError, "M:"),
    ("indefinite P_new", lambda: Ellipsoid(np.eye(2), [0, 0], 1).with_shape([[1, 2], [2, 1]]),
     errors.NotPositiveDefiniteError, "P_new:"),
    ("points wrong length", lambda: Ellipsoid(np.eye(2), [0, 0], 1).contains([1, 2, 3]),
     errors.DimensionError, "points:"),
    ("NaN generator", lambda: Zonotope([0, 0], [[1, NAN], [0, 1]]), errors.NotFiniteError, "H:"),
    ("NaN zonotope centre", lambda: Zonotope([NAN, 0], np.eye(2)), errors.NotFiniteError, "p:"),
    ("H wrong rows", lambda: Zonotope([0, 0], np.eye(3)), errors.DimensionError, "H:"),
    ("s < n", lambda: Zonotope([0, 0, 0], np.ones((3, 5))).reduce(2), errors.InvalidArgumentError, "limit:"),
    ("girard s < n", lambda: Zonotope([0, 0, 0], np.ones((3, 5))).reduce(1, "girard"),
     errors.InvalidArgumentError, "limit:"),
    ("unknown method", lambda: Zonotope([0, 0], np.eye(2)).reduce(2, "svd"), errors.InvalidArgumentError, "method:"),
    ("non-PD P-radius P", lambda: Zonotope([0, 0], np.eye(2)).pradius([[1, 2], [2, 1]]),
     errors.NotPositiveDefiniteError, "P:"),
    ("negative phi", lambda: Strip([1, 0], 0, -0.1), errors.InvalidArgumentError, "phi:"),
    ("zero strip normal", lambda: Strip([0, 0], 0, 0.1), errors.InvalidArgumentError, "c:"),
    ("NaN measurement", lambda: Strip([1, 0], NAN, 0.1), errors.NotFiniteError, "y:"),
    ("lambda wrong shape", lambda: Zonotope([0, 0], np.eye(2)).intersect_strip(Strip([1, 0], 0, 1), [1, 2, 3]),
     errors.DimensionError, "lambda:"),
    ("negative rad", lambda: interval_linear_map(np.eye(2), -np.ones((2, 2)), Zonotope([0, 0], np.eye(2))),
     errors.InvalidArgumentError, "rad:"),
    ("rad wrong shape", lambda: interval_linear_map(np.eye(2), np.ones((2, 3)), Zonotope([0, 0], np.eye(2))),
     errors.DimensionError, "rad:"),
    ("too many P-radius generators", lambda: Zonotope([0, 0], np.ones((2, 25))).pradius(np.eye(2)),
     errors.InvalidArgumentError, "H:"),
]


@pytest.mark.parametrize("what,call,cls,name", BAD_INPUTS, ids=[b[0] for b in BAD_INPUTS])
def test_bad_input_raises_named_error(what, call, cls, name):
    with pytest.raises(cls) as info:
        call()
    assert name in str(info.value)
    assert isinstance(info.value, errors.SetboundError)


# ---- property test (hypothesis): every over-approximation keeps every sample ------------

from hypothesis import given, settings, strategies as st  # noqa: E402
from hypothesis.extra.numpy import arrays  # noqa: E402

_finite = st.floats(-5, 5, allow_nan=False, allow_infinity=False)


@settings(max_examples=60, deadline=None, derandomize=True)
@given(
    H=arrays(np.float64, st.tuples(st.just(2), st.integers(1, 9)), elements=_finite),
    p=arrays(np.float64, (2,), elements=_finite),
    lam=arrays(np.float64, (2,), elements=_finite),
    seed=st.integers(0, 2**32 - 1),
)
def test_property_reduction_and_strip_family_keep_samples(H, p, lam, seed):
    rng = np.random.default_rng(seed)
    Z = Zonotope(p, H)
    X = np.vstack([zonotope_samples(Z, rng, 60), zonotope_samples(Z, rng, 60, vertices=True)])
    for method in ("combastel", "girard", "pca"):
        for limit in (2, 3, 4):
            assert Z.reduce(limit, method).contains(X).all()
    c = rng.standard_normal(2)
    S = Strip(c, float(c @ X[0]), 0.3)
    inside = X[S.contains(X)]
    assert Z.intersect_strip(S, lam).contains(inside).all()
