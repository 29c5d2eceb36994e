"""Thesis Chapter 1 invariant sets through the Python bindings (spec §3.3–3.6, §7 items 2–4):
ellipsoid box (1.40), polytopes, Φ_v between the ellipsoids (§3.5), Algorithm 1 (§3.6) on
Example 1.5 and random 3-D/4-D systems, and bad input. Independent references: numpy/scipy
(frequency gridding for the H∞ norm, eigen-decompositions), CVXPY + Clarabel for the BRL γ."""
from __future__ import annotations

import itertools

import numpy as np
import pytest
import scipy.linalg as sla

import setbound.invariant as inv
from setbound.errors import DimensionError, InvalidArgumentError, NotPositiveDefiniteError, SetboundError
from setbound.interval import Box

A15 = np.array([[0.2, 0.2], [-0.2, 0.5]])
E15 = np.array([[0.0], [1.0]])


def corners(wbar):
    return np.array(list(itertools.product(*[(-w, w) for w in wbar])))


def random_spd(n, rng, cond=20.0):
    Q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    return Q @ np.diag(np.exp(rng.uniform(0, np.log(cond), n))) @ Q.T


def random_schur(n, rng, rho=0.7):
    A = rng.uniform(-1, 1, (n, n))
    return A * rho / np.max(np.abs(np.linalg.eigvals(A)))


def hinf_grid(A, E, N=20000):
    n = A.shape[0]
    best = 0.0
    for w in np.linspace(0, np.pi, N + 1):
        G = np.linalg.solve(np.exp(1j * w) * np.eye(n) - A, E)
        best = max(best, np.linalg.svd(G, compute_uv=False)[0])
    return best


def random_points(V, rng, k):
    W = rng.exponential(size=(k, V.shape[0]))
    W[rng.random(W.shape) < 0.7] = 0.0
    W[np.arange(k), rng.integers(0, V.shape[0], k)] += 1.0
    return (W / W.sum(axis=1, keepdims=True)) @ V


# --------------------------------------------------------------------------- (1.40)

def test_ellipsoid_bounding_box_attained(rng):
    P = np.array([[1.0, 1.0], [1.0, 4.0]])  # Ex 1.3/1.4
    for t in range(10):
        Pt = P if t == 0 else random_spd(2 + t % 3, rng, 50)
        n = Pt.shape[0]
        c = np.zeros(n) if t == 0 else rng.standard_normal(n)
        rho = 1.0 if t == 0 else 0.3 + t
        b = inv.ellipsoid_bounding_box(Pt, c, rho)
        Pinv = np.linalg.inv(Pt)
        h = np.sqrt(rho * np.diag(Pinv))
        tol = 1e-12 * (1 + h.max() + np.abs(c).max())
        np.testing.assert_allclose(b.hi, c + h, rtol=0, atol=tol)
        np.testing.assert_allclose(b.lo, c - h, rtol=0, atol=tol)
        assert np.all(b.hi >= c + h - 1e-15) and np.all(b.lo <= c - h + 1e-15)
        for i in range(n):
            xs = c + np.sqrt(rho) * Pinv[:, i] / np.sqrt(Pinv[i, i])
            assert abs((xs - c) @ Pt @ (xs - c) - rho) <= 1e-10 * rho
            assert abs(xs[i] - (c[i] + h[i])) <= 1e-10 * (1 + h[i])
    with pytest.raises(NotPositiveDefiniteError, match="P:"):
        inv.ellipsoid_bounding_box([[1, 2], [2, 1]], [0, 0], 1.0)
    with pytest.raises(InvalidArgumentError, match="rho:"):
        inv.ellipsoid_bounding_box(P, [0, 0], -1.0)


# --------------------------------------------------------------------------- polytopes

def test_polytope_operations(rng):
    for n in (2, 3, 4):
        pts = rng.uniform(-1, 1, (10 + 5 * n, n))
        P = inv.Polytope(pts)
        assert P.contains(pts).all()
        assert not P.contains(2 * np.ones(n))
        np.testing.assert_allclose(np.linalg.norm(P.H, axis=1), 1.0, atol=1e-12)
        Q = inv.Polytope.from_halfspaces(P.H, P.b, pts.mean(axis=0))
        assert Q.num_vertices == P.num_vertices and Q.contains_polytope(P) and P.contains_polytope(Q)
        R = inv.Polytope(rng.uniform(-1, 1, (2 * n + 3, n)))
        S = P + R
        box = Box(-0.3 * np.ones(n), 0.5 * np.ones(n))
        T = P.minkowski_sum(box)
        M = rng.uniform(-1, 1, (n, n)) + 2 * np.eye(n)
        L = P.linear_map(M)
        for d in rng.standard_normal((20, n)):
            h = lambda X: np.max(X @ d)  # noqa: E731
            assert abs(h(S.vertices) - h(P.vertices) - h(R.vertices)) <= 1e-12
            assert abs(h(T.vertices) - h(P.vertices) - np.sum(np.maximum(d, 0) * 0.5 - np.minimum(d, 0) * 0.3)) <= 1e-12
            assert abs(h(L.vertices) - h(P.vertices @ M.T)) <= 1e-12
            assert abs(h(P.scaled(2.5).vertices) - 2.5 * h(P.vertices)) <= 1e-12
        bb = P.bounding_box()
        np.testing.assert_array_equal(bb.lo, pts.min(axis=0))
        np.testing.assert_array_equal(bb.hi, pts.max(axis=0))
        assert P.max_vertex_norm() == pytest.approx(np.linalg.norm(pts, axis=1).max(), rel=1e-15)
    poly = inv.Polytope(rng.uniform(-1, 1, (30, 2))).plot_data()
    np.testing.assert_array_equal(poly[0], poly[-1])
    u, v = poly[1:-1] - poly[:-2], poly[2:] - poly[1:-1]
    assert np.all(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0] > 0)  # convex, counter-clockwise
    with pytest.raises(InvalidArgumentError, match="points:"):
        inv.Polytope([[0, 0], [1, 1], [2, 2]])
    with pytest.raises(InvalidArgumentError, match="box"):
        inv.Polytope([[0, 0], [1, 0], [0, 1]]).minkowski_sum(Box.empty(2))


# --------------------------------------------------------------------------- §3.5

def check_between(Phi, P, c_in, c_out):
    V = Phi.vertices
    assert np.all(np.einsum("ij,jk,ik->i", V, P, V) <= c_out)
    L = np.linalg.cholesky(np.linalg.inv(P))
    supp = np.sqrt(c_in * np.sum((Phi.H @ L) ** 2, axis=1))
    assert np.all(supp <= Phi.b)


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_polyhedral_rpi_random(n, rng):
    for ratio in (1.5, 1.15):
        P = random_spd(n, rng, 30)
        c_in, c_out = 0.7, 0.7 * ratio
        Phi = inv.polyhedral_rpi_between_ellipsoids(P, c_in, c_out)
        check_between(Phi, P, c_in, c_out)
        D = rng.standard_normal((300, n))
        q = np.einsum("ij,jk,ik->i", D, P, D)
        assert Phi.contains(D * np.sqrt(c_in / q)[:, None], tol=0.0).all()
        assert not Phi.contains(D * np.sqrt(c_out / q)[:, None] * 1.0000001, tol=0.0).any()


def brl_cvxpy(A, E):
    cp = pytest.importorskip("cvxpy")
    n, m = E.shape
    P = cp.Variable((n, n), symmetric=True)
    g = cp.Variable()
    M = cp.bmat([[-P + np.eye(n), np.zeros((n, m)), A.T @ P], [np.zeros((m, n)), -g * np.eye(m), E.T @ P],
                 [P @ A, P @ E, -P]])
    prob = cp.Problem(cp.Minimize(g), [(M + M.T) / 2 << 0, P >> 1e-8 * np.eye(n)])
    prob.solve(solver=cp.CLARABEL)
    return np.sqrt(g.value)


def test_example15_algorithm1():
    eps = 4.4e-3
    res = inv.mrpi_outer_shrinking(A15, E15, [1.0], mu=1.2, eps=eps, stop="shrinking_index")
    # γ of the BRL = the H∞ norm of (A, E, I, 0) (frequency gridding) = CVXPY + Clarabel's optimum
    hinf = hinf_grid(A15, E15)
    assert hinf * (1 - 1e-9) <= res.gamma <= hinf * (1 + 1e-4)
    assert res.gamma == pytest.approx(brl_cvxpy(A15, E15), rel=1e-4)
    # β from the pair (AᵀPA, P), scipy
    beta = np.sqrt(sla.eigh(A15.T @ res.P @ A15, res.P, eigvals_only=True).max())
    assert res.beta == pytest.approx(beta, rel=1e-8)
    K = res.k_star
    assert res.shrinking_index[K] <= eps < res.shrinking_index[K - 1]
    lam = np.linalg.eigvalsh(res.P)
    np.testing.assert_allclose(res.shrinking_index, beta ** np.arange(K + 1) * np.sqrt(1.2 * lam.max() / lam.min()),
                               rtol=1e-8)
    check_shrinking(res, A15, E15, np.array([1.0]), np.random.default_rng(1))


def check_shrinking(res, A, E, wbar, rng):
    K = res.k_star
    n = A.shape[0]
    D = corners(wbar)
    check_between(res.phi0, res.P, res.c_in, res.c_out)
    omega = np.zeros(n)
    Ai = np.eye(n)
    for k in range(K + 1):
        Phi = res.sets[k]
        if k:
            assert res.sets[k - 1].contains_polytope(Phi), f"not nested at {k}"
        img = (Phi.vertices @ A.T)[:, None, :] + (D @ E.T)[None, :, :]
        assert Phi.contains(img.reshape(-1, n)).all(), f"not RPI at {k}"
        X = random_points(Phi.vertices, rng, 100)
        W = rng.uniform(-1, 1, (100, len(wbar))) * wbar
        assert Phi.contains(X @ A.T + W @ E.T).all()
        bb = Phi.bounding_box()
        assert np.all(res.boxes[k].lo <= bb.lo + 1e-12) and np.all(res.boxes[k].hi >= bb.hi - 1e-12)
        assert np.all(res.boxes[k].hi >= omega) and np.all(res.boxes[k].lo <= -omega)
        # Ω_k ⊆ Φ_k (sampled sums with corner disturbances)
        for _ in range(30):
            x = np.zeros(n)
            Ap = np.eye(n)
            for _i in range(k):
                x += Ap @ E @ (rng.choice([-1.0, 1.0], len(wbar)) * wbar)
                Ap = Ap @ A
            assert Phi.contains(x)
        omega += np.abs(Ai @ E) @ wbar
        Ai = Ai @ A
    # simulation: x_k ∈ Φ_min(k, k*) for random / bang-bang disturbances from vertices / random x_0
    for trial in range(10):
        x = res.phi0.vertices[trial % res.phi0.num_vertices] if trial % 2 else random_points(res.phi0.vertices, rng, 1)[0]
        for k in range(K + 25):
            assert res.sets[min(k, K)].contains(x), f"trial {trial} step {k}"
            assert res.boxes[min(k, K)].contains(x)
            w = (np.sign(rng.uniform(-1, 1, len(wbar))) if trial < 5 else rng.uniform(-1, 1, len(wbar))) * wbar
            x = A @ x + E @ w


def test_stop_rule_guarantee_and_box_variant(rng):
    for n, m in ((3, 2), (4, 1)):
        A = random_schur(n, rng, 0.5)
        E = rng.uniform(-1, 1, (n, m))
        wbar = rng.uniform(0.3, 1.0, m)
        res = inv.mrpi_outer_shrinking(A, E, wbar, mu=2.5, eps=0.05)
        K = res.k_star
        assert res.radius_bound[K] <= 0.05 < res.radius_bound[K - 1]
        lam = np.linalg.eigvalsh(res.P)
        np.testing.assert_allclose(res.radius_bound[0], np.sqrt(res.c_out / lam.min()), rtol=1e-12)
        AkV = res.phi0.vertices @ np.linalg.matrix_power(A, K).T
        assert np.linalg.norm(AkV, axis=1).max() <= 0.05  # A^{k*}Φ_0 ⊆ 𝔹(ε)
        check_shrinking(res, A, E, wbar, rng)
        box = inv.mrpi_outer_shrinking(A, E, wbar, phi0=res.phi0, P=res.P, c_out=res.c_out, eps=0.05,
                                       mu=2.5, boxes_only=True)
        assert box.k_star == K and box.sets is None and box.P is None
        for b1, b2 in zip(box.boxes, res.boxes):
            np.testing.assert_array_equal(b1.lo, b2.lo)
            np.testing.assert_array_equal(b1.hi, b2.hi)


def test_bad_input():
    P = np.eye(2)
    with pytest.raises(InvalidArgumentError, match="c_out:"):
        inv.polyhedral_rpi_between_ellipsoids(P, 2.0, 1.0)
    with pytest.raises(InvalidArgumentError, match="c_in:"):
        inv.polyhedral_rpi_between_ellipsoids(P, 0.0, 1.0)
    with pytest.raises(NotPositiveDefiniteError, match="P:"):
        inv.polyhedral_rpi_between_ellipsoids([[1, 0], [0, -1]], 1.0, 2.0)
    with pytest.raises(DimensionError, match="P:"):
        inv.polyhedral_rpi_between_ellipsoids(np.ones((2, 3)), 1.0, 2.0)
    phi = inv.polyhedral_rpi_between_ellipsoids(P, 1.0, 2.0)
    unstable = np.array([[1.1, 0], [0, 0.5]])
    with pytest.raises(InvalidArgumentError, match="A:"):
        inv.mrpi_outer_shrinking(unstable, E15, [1.0], phi0=phi, P=P, c_out=2.0, eps=0.1)
    with pytest.raises(SetboundError, match="A:"):
        inv.mrpi_outer_shrinking(unstable, E15, [1.0], eps=0.1)
    for eps in (0.0, -1.0):
        with pytest.raises(InvalidArgumentError, match="eps:"):
            inv.mrpi_outer_shrinking(A15, E15, [1.0], eps=eps)
    with pytest.raises(InvalidArgumentError, match="delta:"):
        inv.mrpi_outer_shrinking(A15, E15, phi0=phi, P=P, c_out=2.0, eps=0.1, delta=Box.empty(1))
    with pytest.raises(InvalidArgumentError, match="delta:"):
        inv.mrpi_outer_shrinking(A15, E15, phi0=phi, P=P, c_out=2.0, eps=0.1, delta=Box([1.0], [2.0]))
    with pytest.raises(NotPositiveDefiniteError, match="P:"):
        inv.mrpi_outer_shrinking(A15, E15, [1.0], phi0=phi, P=[[1, 0], [0, -1]], c_out=2.0, eps=0.1)
    with pytest.raises(InvalidArgumentError, match="mu:"):
        inv.mrpi_outer_shrinking(A15, E15, [1.0], mu=1.0, eps=0.1)
    with pytest.raises(InvalidArgumentError, match="stop:"):
        inv.mrpi_outer_shrinking(A15, E15, [1.0], eps=0.1, stop="never")
    with pytest.raises(DimensionError, match="E:"):
        inv.mrpi_outer_shrinking(A15, np.ones((3, 1)), [1.0], eps=0.1)
