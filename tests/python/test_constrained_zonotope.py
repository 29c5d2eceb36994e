"""Constrained zonotopes through the C ABI and Python (issue 21): the set operations against
independent computations (scipy's HiGHS for hulls, support values and emptiness; sampling for
images, sums and intersections), the reductions contain their input (LP check), the projection
polygon, and bad input named through Python."""
import numpy as np
import pytest
from scipy.optimize import linprog

import setbound as sb
from setbound.errors import DimensionError, InvalidArgumentError, NotFiniteError, SetboundError
from setbound.sets import ConstrainedZonotope, Strip


def highs_support(Z: ConstrainedZonotope, d):
    """max dᵀx over Z with scipy's HiGHS (variables ξ and the rounding box's η); None if infeasible."""
    n, m, q = Z.n, Z.ng, Z.nc
    G = np.hstack([Z.generators, np.diag(Z.rounding)])
    A = np.hstack([Z.A, np.zeros((q, n))])
    res = linprog(-(G.T @ d), A_eq=A if q else None, b_eq=Z.b if q else None, bounds=[(-1, 1)] * (m + n),
                  method="highs")
    if res.status == 2:
        return None
    assert res.status == 0, res.message
    return float(d @ Z.center - res.fun)


def random_czono(rng, n, m, q, feasible=True):
    G = rng.standard_normal((n, m))
    A = rng.standard_normal((q, m))
    xi = rng.uniform(-0.9, 0.9, m) if feasible else rng.uniform(-1, 1, m) * 3
    b = A @ xi
    return ConstrainedZonotope(rng.standard_normal(n), G, A, b), xi


def sample(Z: ConstrainedZonotope, rng, k):
    """Points of Z: random feasible ξ found by LPs with random objectives (vertices of the ξ set)
    mixed convexly."""
    pts = []
    for _ in range(k):
        g = rng.standard_normal(Z.ng)
        res = linprog(g, A_eq=Z.A if Z.nc else None, b_eq=Z.b if Z.nc else None, bounds=[(-1, 1)] * Z.ng,
                      method="highs")
        pts.append(res.x)
    W = rng.dirichlet(np.ones(k), size=k)
    return np.array([Z.center + Z.generators @ (w @ np.array(pts)) for w in W])


@pytest.mark.parametrize("seed", range(12))
def test_hull_and_support_agree_with_highs_and_are_outer(seed):
    rng = np.random.default_rng(seed)
    n, m, q = int(rng.integers(1, 5)), int(rng.integers(2, 9)), int(rng.integers(0, 4))
    Z, _ = random_czono(rng, n, m, q)
    lo, hi = Z.interval_hull()
    for i in range(n):
        e = np.eye(n)[i]
        h_hi, h_lo = highs_support(Z, e), -highs_support(Z, -e)
        assert hi[i] >= h_hi - 1e-12 * (1 + abs(h_hi)) and hi[i] <= h_hi + 1e-7 * (1 + abs(h_hi))
        assert lo[i] <= h_lo + 1e-12 * (1 + abs(h_lo)) and lo[i] >= h_lo - 1e-7 * (1 + abs(h_lo))
    D = rng.standard_normal((5, n))
    v = Z.support(D)
    for k in range(5):
        ref = highs_support(Z, D[k])
        assert ref - 1e-12 * (1 + abs(ref)) <= v[k] <= ref + 1e-7 * (1 + abs(ref))


@pytest.mark.parametrize("seed", range(10))
def test_emptiness_agrees_with_highs_and_certificate_verifies(seed):
    rng = np.random.default_rng(100 + seed)
    n, m, q = 2, int(rng.integers(2, 7)), int(rng.integers(1, 4))
    Z, _ = random_czono(rng, n, m, q, feasible=bool(seed % 2))
    res = linprog(np.zeros(m), A_eq=Z.A, b_eq=Z.b, bounds=[(-1, 1)] * m, method="highs")
    e = Z.emptiness()
    if res.status == 2:  # HiGHS: infeasible
        assert e.empty and e.margin > 0
        y = e.certificate
        assert y @ Z.b - np.abs(Z.A.T @ y).sum() > 0  # the certificate proves it independently
        lo, hi = Z.interval_hull()
        assert np.all(lo == np.inf) and np.all(hi == -np.inf)
        assert Z.support(np.ones(n)) == -np.inf
    else:
        assert not e.empty
        assert np.all(e.certificate == 0)


@pytest.mark.parametrize("seed", range(6))
def test_images_sums_and_intersections_contain_sampled_points(seed):
    rng = np.random.default_rng(200 + seed)
    Z, _ = random_czono(rng, 3, 5, 2)
    W, _ = random_czono(rng, 3, 4, 1)
    P = sample(Z, rng, 12)
    Q = sample(W, rng, 12)
    assert Z.contains(P).all() and W.contains(Q).all()
    M = rng.standard_normal((2, 3))
    MZ = M @ Z
    assert MZ.n == 2 and MZ.nc == Z.nc and MZ.contains(P @ M.T).all()
    S = Z + W
    assert S.ng == Z.ng + W.ng and S.nc == Z.nc + W.nc
    assert S.contains(P + Q).all()
    assert (Z + sb.Zonotope(np.zeros(3), np.eye(3))).contains(P + rng.uniform(-1, 1, P.shape)).all()
    T = Z.translate([1.0, 2.0, 3.0])
    assert T.contains(P + [1.0, 2.0, 3.0]).all()
    # Intersection: points of Z inside a half-space / strip / box stay members; points cut off leave.
    h = rng.standard_normal(3)
    d = float(np.median(P @ h))
    H = Z.intersect_halfspace(h, d)
    assert H.contains(P[P @ h <= d - 1e-9]).all()
    assert not H.contains(P[P @ h > d + 1e-6]).any()
    st = Strip(h, d, 0.3)
    Sz = Z.intersect_strip(st)
    inside = np.abs(P @ h - d) <= 0.3 - 1e-9
    assert Sz.contains(P[inside]).all() and not Sz.contains(P[np.abs(P @ h - d) > 0.3 + 1e-6]).any()
    lo, hi = Z.interval_hull()
    mid = (lo + hi) / 2
    B = sb.Box(mid - 0.2 * (hi - lo), mid + 0.2 * (hi - lo))
    I = Z & B
    inb = np.all((P >= B.lo) & (P <= B.hi), axis=1)
    assert I.contains(P[inb]).all() and not I.contains(P[~np.all((P >= B.lo - 1e-6) & (P <= B.hi + 1e-6), axis=1)]).any()
    # generalized intersection with R: {x ∈ Z : R x ∈ W2}
    R = rng.standard_normal((2, 3))
    W2 = ConstrainedZonotope.from_bounds(np.median(P @ R.T, axis=0) - 0.5, np.median(P @ R.T, axis=0) + 0.5)
    GI = Z.intersect(W2, R)
    ok = W2.contains(P @ R.T)
    assert GI.contains(P[ok]).all()


def test_intersect_output_is_the_set_consistent_with_the_reading():
    Z = ConstrainedZonotope.from_bounds([-1, -1], [1, 1])
    X = Z.intersect_output([[1.0, 1.0]], [0.5], sb.Box([-0.1], [0.1]))
    lo, hi = X.interval_hull()
    # x1 + x2 ∈ [0.4, 0.6] within the square: x1 ∈ [-0.6, 1]
    np.testing.assert_allclose(lo, [-0.6, -0.6], atol=1e-9)
    np.testing.assert_allclose(hi, [1.0, 1.0], atol=1e-9)
    assert X.contains([0.25, 0.25]) and not X.contains([0.5, 0.5])


@pytest.mark.parametrize("method", ["limits", "cora", "eliminate", "rescale", "remove_zero"])
@pytest.mark.parametrize("seed", range(4))
def test_every_reduction_contains_its_input(method, seed):
    rng = np.random.default_rng(300 + seed)
    Z = ConstrainedZonotope.from_bounds([-1, -1, -1], [1, 1, 1])
    for k in range(8):  # eight strips: 8 rows, 11 generators
        Z = Z.intersect_strip(Strip(rng.standard_normal(3), rng.normal(0, 0.3), 0.8))
    Z = Z + ConstrainedZonotope(np.zeros(3), np.zeros((3, 1)), np.zeros((1, 1)), [0.0])  # a zero row
    R = Z.reduce(method, order=2.0, max_constraints=3, max_generators=9, technique="pca" if seed % 2 else "girard")
    assert R.ng <= Z.ng and R.nc <= Z.nc
    if method == "limits":
        assert R.nc <= 3 and R.ng <= 9
    if method == "eliminate":
        assert R.nc <= 3
    if method == "remove_zero":
        assert R.nc == Z.nc - 1
    # LP check: h_R(d) >= h_Z(d) in many directions (containment of convex sets), and hulls nest.
    D = rng.standard_normal((40, 3))
    for d in D:
        assert highs_support(R, d) >= highs_support(Z, d) - 1e-9
    assert R.contains(sample(Z, rng, 10)).all()


def test_rescale_tightens_what_a_row_implies_and_leaves_loose_rows_alone():
    # ξ0 + 0.1 ξ1 = 0.2 with |ξ1| <= 1 forces ξ0 into [0.1, 0.3]: Scott's rescaling maps that
    # interval back to the box, so generator 0 shrinks to a tenth and the centre moves by 0.2
    # (up to the outward rounding). Rows that imply nothing beyond the box (0.5 ξ0 + 0.5 ξ1 = 0,
    # and ξ1's own range from the first row is the whole box) leave the set as it was: the pass
    # that would tighten them is skipped, and skipping must not lose a tightening that exists.
    Z = ConstrainedZonotope([0.0, 0.0], np.eye(2), [[1.0, 0.1]], [0.2])
    R = Z.reduce("rescale")
    assert R.generators[0, 0] == pytest.approx(0.1, abs=1e-12) and R.generators[0, 0] >= 0.1
    assert R.center[0] == pytest.approx(0.2, abs=1e-12)
    np.testing.assert_array_equal(R.generators[:, 1], [0.0, 1.0])
    lo, hi = R.interval_hull()
    assert lo[0] <= 0.1 <= lo[0] + 1e-9 and hi[0] - 1e-9 <= 0.3 <= hi[0]
    loose = ConstrainedZonotope([1.0, -1.0], np.eye(2), [[0.5, 0.5]], [0.0])
    L = loose.reduce("rescale")
    np.testing.assert_array_equal(L.generators, loose.generators)
    np.testing.assert_array_equal(L.center, loose.center)
    np.testing.assert_array_equal(L.A, loose.A)


def test_projection_polygon_is_the_exact_polygon():
    # The square cut by x1 + x2 <= 1: a pentagon with vertices (1,-1), (1,0), (0,1), (-1,1), (-1,-1).
    Z = ConstrainedZonotope.from_bounds([-1, -1, -5], [1, 1, 5]).intersect_halfspace([1.0, 1.0, 0.0], 1.0)
    V = Z.projection(0, 1)
    expected = {(1.0, -1.0), (1.0, 0.0), (0.0, 1.0), (-1.0, 1.0), (-1.0, -1.0)}
    assert {tuple(np.round(v, 7)) for v in V} == expected and len(V) == 5
    # counter-clockwise: positive signed area
    x, y = V[:, 0], V[:, 1]
    assert 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y) == pytest.approx(3.5)
    # a random set: every vertex is a point of the set, the polygon holds sampled points, and its
    # support in random directions equals the set's (HiGHS)
    rng = np.random.default_rng(7)
    W, _ = random_czono(rng, 3, 7, 2)
    P = W.projection(2, 0)
    assert len(P) >= 3
    for d in rng.standard_normal((20, 2)):
        d3 = np.zeros(3)
        d3[2], d3[0] = d
        assert np.max(P @ d) == pytest.approx(highs_support(W, d3), rel=1e-7, abs=1e-9)
    empty = ConstrainedZonotope([0.0, 0.0], np.eye(2), [[1.0, 1.0]], [3.0])
    assert empty.projection().shape == (0, 2)
    point = ConstrainedZonotope([1.0, 2.0])
    assert point.projection().tolist() == [[1.0, 2.0]]


def test_bad_input_is_named():
    with pytest.raises(NotFiniteError, match="G"):
        ConstrainedZonotope([0.0, 0.0], [[1.0, np.nan], [0.0, 1.0]])
    with pytest.raises(DimensionError, match="A: expected 2 columns"):
        ConstrainedZonotope([0.0, 0.0], np.eye(2), [[1.0, 1.0, 1.0]], [0.0])
    with pytest.raises(DimensionError, match="b: expected length 1"):
        ConstrainedZonotope([0.0, 0.0], np.eye(2), [[1.0, 1.0]], [0.0, 1.0])
    with pytest.raises(InvalidArgumentError, match="r: the rounding radii must be >= 0"):
        ConstrainedZonotope([0.0, 0.0], np.eye(2), rounding=[-1.0, 0.0])
    with pytest.raises(InvalidArgumentError, match="b: required with A"):
        ConstrainedZonotope([0.0], [[1.0]], [[1.0]])
    Z = ConstrainedZonotope.from_bounds([0, 0], [1, 1])
    with pytest.raises(InvalidArgumentError, match="method"):
        Z.reduce("fast")
    with pytest.raises(InvalidArgumentError, match="max_constraints"):
        Z.reduce("limits", max_constraints=-2)
    with pytest.raises(InvalidArgumentError, match="max_generators"):
        Z.reduce("limits", max_generators=2**40)
    with pytest.raises(InvalidArgumentError, match="order"):
        Z.reduce("cora", order=0.5)
    with pytest.raises(InvalidArgumentError, match="max_generators: must be >= n"):
        Z.reduce("limits", max_constraints=1, max_generators=2)
    with pytest.raises(NotFiniteError, match="directions"):
        Z.support([np.nan, 1.0])
    with pytest.raises(DimensionError, match="points"):
        Z.contains([1.0, 2.0, 3.0])
    with pytest.raises(InvalidArgumentError, match="j"):
        Z.projection(0, 0)
    with pytest.raises(DimensionError, match="K"):
        np.eye(3) @ Z
    with pytest.raises(NotFiniteError, match="d"):
        Z.intersect_halfspace([1.0, 0.0], np.inf)
    with pytest.raises(SetboundError, match="c2|other"):
        Z + ConstrainedZonotope([0.0, 0.0, 0.0])
