"""setbound.lmi: the Python contract of issue 3, the reusable Problem, errors, maxdet against
closed forms, and the spec's LMIs (papers.md §1.1/§1.4, §3.2, §6; thesis.md §4.2) against
an independent solver (CVXPY + Clarabel) on the very same LMI data."""
import itertools

import numpy as np
import pytest

from lmi_reference import assert_feasible, solve_with_clarabel
from setbound import lmi
from setbound.errors import (
    DimensionError,
    InvalidArgumentError,
    NotFiniteError,
    NotSymmetricError,
)


# ---- helpers ------------------------------------------------------------------------------
def affine_block(m, fn):
    """(F0, Fs) of a symmetric matrix affine in x, from its values at 0 and the unit vectors."""
    F0 = np.asarray(fn(np.zeros(m)), dtype=float)
    Fs = np.array([np.asarray(fn(e), dtype=float) - F0 for e in np.eye(m)])
    assert np.allclose(F0, F0.T) and np.allclose(Fs, Fs.transpose(0, 2, 1))
    return F0, Fs


def smat(v, n):
    """Symmetric n×n matrix from its n(n+1)/2 lower-triangle entries (column order)."""
    S = np.zeros((n, n))
    k = 0
    for j in range(n):
        for i in range(j, n):
            S[i, j] = S[j, i] = v[k]
            k += 1
    return S


# ---- contract and API -----------------------------------------------------------------------
def test_solve_contract_known_optimum():
    # [[x, 1], [1, 1]] ⪰ 0  ⇔  x ≥ 1 (Schur complement).
    r = lmi.solve([1.0], [(np.array([[0.0, 1], [1, 1]]), np.array([[[1.0, 0], [0, 0]]]))])
    assert r.status == "optimal"
    assert r.x.shape == (1,)
    assert r.x[0] == pytest.approx(1.0, abs=1e-7)
    assert r.objective == pytest.approx(1.0, abs=1e-7)
    assert r.iterations > 0 and r.solve_time > 0
    assert abs(r.margin) < 1e-6  # optimum on the boundary
    for name in ("status", "x", "objective", "iterations", "margin", "solve_time"):
        assert hasattr(r, name)


def test_statuses_infeasible_unbounded_max_iterations():
    one = np.ones((1, 1))
    r = lmi.solve([1.0], [(-one, one[None]), (-one, -one[None])])  # x ≥ 1 and x ≤ −1
    assert r.status == "infeasible"
    assert np.isnan(r.x).all()
    z1, z2 = r.Z[0][0, 0], r.Z[1][0, 0]
    # normalised so that hᵀz = −1; the dual residual of a certificate is within the solver's
    # feasibility tolerance (1e-8, lmi/solver.hpp)
    assert -z1 - z2 == pytest.approx(-1.0) and z1 - z2 == pytest.approx(0.0, abs=1e-8)
    assert z1 >= 0 and z2 >= 0
    r = lmi.solve([-1.0], [(one, -one[None] * 0 + one[None] * 0 + np.array([[[1.0]]]))])  # x ≥ −1, min −x
    assert r.status == "unbounded"
    assert -r.x[0] == pytest.approx(-1.0)
    rng = np.random.default_rng(0)
    A = rng.standard_normal((6, 6))
    A = A + A.T
    r = lmi.solve([1.0], [(-A, np.eye(6)[None])], max_iter=2)
    assert r.status in ("max_iterations", "inaccurate")
    assert r.iterations == 2 and np.isfinite(r.x).all()


def test_problem_reuse_update_and_tolerances():
    rng = np.random.default_rng(1)
    p = lmi.Problem(1)
    p.set_objective([1.0])
    A = rng.standard_normal((5, 5))
    A = A + A.T
    b = p.add_block(-A, np.eye(5)[None])
    for k in range(5):
        A = rng.standard_normal((5, 5))
        A = A + A.T
        p.update_block(b, -A, np.eye(5)[None])
        r = p.solve(duals=False)
        assert r.status == "optimal"
        assert r.objective == pytest.approx(np.linalg.eigvalsh(A).max(), rel=1e-7, abs=1e-8)
    p.set_options(tol=1e-10, max_iter=80)
    r = p.solve()
    assert r.status == "optimal" and r.relative_gap <= 1e-10
    assert r.objective == pytest.approx(np.linalg.eigvalsh(A).max(), rel=1e-9, abs=1e-10)
    # Dual of min t s.t. tI − A ⪰ 0: tr Z = 1 and tr(A Z) = λ_max.
    assert np.trace(r.Z[0]) == pytest.approx(1.0, abs=1e-8)
    assert np.sum(A * r.Z[0]) == pytest.approx(np.linalg.eigvalsh(A).max(), rel=1e-7)
    assert p.margin(r.x + 1.0) == pytest.approx(1.0 + r.x[0] - np.linalg.eigvalsh(A).max(), abs=1e-9)


def test_feasibility_mode_and_gevp():
    # Lyapunov LMI P − AᵀPA ≻ 0, P ≻ I for a stable A: a certified point.
    A = np.array([[0.5, 1.0], [0.0, 0.8]])
    blocks = [affine_block(3, lambda v: smat(v, 2) - A.T @ smat(v, 2) @ A),
              affine_block(3, lambda v: smat(v, 2) - np.eye(2))]
    p = lmi.Problem(3)
    for F0, Fs in blocks:
        p.add_block(F0, Fs)
    r = p.solve(feasibility=True)
    assert r.status == "optimal" and r.margin > 0 and r.ok
    P = smat(r.x, 2)
    assert np.linalg.eigvalsh(P - A.T @ P @ A).min() > 0
    # GEVP: min λ s.t. λI − diag(1 + x, 2 − x) ⪰ 0 with |x| ≤ 3: λ* = 1.5.
    q = lmi.Problem(1)
    one = np.ones((1, 1))
    q.add_block(3 * one, one[None])
    q.add_block(3 * one, -one[None])
    lam, res = q.gevp((np.diag([1.0, 2.0]), np.diag([1.0, -1.0])[None]), (np.eye(2), np.zeros((1, 2, 2))), tol=1e-8)
    assert lam == pytest.approx(1.5, abs=1e-6)
    assert res.status == "optimal"
    assert res.dual_objective <= 1.5 + 1e-12  # certified-infeasible lower end
    assert lam - max(1 + res.x[0], 2 - res.x[0]) > 0  # the certified point works at λ


def test_errors_name_the_argument():
    I2 = np.eye(2)
    Fs = np.stack([I2, I2])
    with pytest.raises(NotSymmetricError, match="F0"):
        lmi.solve([1.0, 0.0], [(np.array([[1.0, 2], [0, 1]]), Fs)])
    bad = Fs.copy()
    bad[1, 0, 1] = 3.0
    with pytest.raises(NotSymmetricError, match=r"Fs\[1\]"):
        lmi.solve([1.0, 0.0], [(I2, bad)])
    with pytest.raises(NotFiniteError, match="F0"):
        lmi.solve([1.0, 0.0], [(np.array([[np.nan, 0], [0, 1]]), Fs)])
    with pytest.raises(NotFiniteError, match="c"):
        lmi.solve([np.inf, 0.0], [(I2, Fs)])
    with pytest.raises(DimensionError, match="Fs"):
        lmi.solve([1.0, 0.0, 0.0], [(I2, Fs)])
    with pytest.raises(DimensionError):
        lmi.solve([1.0, 0.0], [(np.ones((2, 3)), Fs)])
    with pytest.raises(DimensionError, match="c"):
        lmi.solve([], [(I2, Fs)])
    with pytest.raises(InvalidArgumentError, match="blocks"):
        lmi.solve([1.0, 0.0], [])
    with pytest.raises(InvalidArgumentError, match="blocks"):
        lmi.solve([1.0, 0.0], [I2])
    with pytest.raises(DimensionError, match="Aeq"):
        lmi.solve([1.0, 0.0], [(I2, Fs)], eq=(np.ones((1, 3)), [1.0]))
    with pytest.raises(DimensionError, match="beq"):
        lmi.solve([1.0, 0.0], [(I2, Fs)], eq=(np.ones((1, 2)), [1.0, 2.0]))
    with pytest.raises(NotSymmetricError, match="G0"):
        lmi.solve([1.0, 0.0], [(I2, Fs)], logdet=(np.array([[1.0, 2], [0, 1]]), Fs))
    with pytest.raises(DimensionError, match="num_vars"):
        lmi.Problem(0)
    p = lmi.Problem(2)
    with pytest.raises(InvalidArgumentError, match="index"):
        p.update_block(0, I2, Fs)
    with pytest.raises(InvalidArgumentError, match="blocks"):
        p.solve()


def test_threads_option_matches_serial_and_checks_its_value():
    """``threads`` splits each solve over the blocks (the library is built with OpenMP); the
    result is the serial one to rounding, for linear and maxdet problems, and it survives
    set_options. Bad values are refused by name."""
    import sys

    sys.path.insert(0, str(__import__("pathlib").Path(__file__).resolve().parents[2] / "bench"))
    from bench_lmi import maxdet_problem, random_lmi

    assert lmi.threads_available()
    c, blocks = random_lmi(7, [7] * 24 + [3] * 4, 14)
    r1 = lmi.solve(c, blocks)
    r2 = lmi.solve(c, blocks, threads=2)
    assert r1.status == r2.status == "optimal"
    assert abs(r1.iterations - r2.iterations) <= 1
    assert r2.objective == pytest.approx(r1.objective, rel=1e-8, abs=1e-8)
    # x is only determined to about sqrt(gap) along flat directions; objective and feasibility decide
    assert np.linalg.norm(r2.x - r1.x) <= 1e-3 * max(1.0, np.linalg.norm(r1.x))
    for F0, Fs in blocks:
        assert np.linalg.eigvalsh(F0 + np.einsum("i,ijk->jk", r2.x, Fs))[0] >= 0
    assert r2.margin > 0
    p = lmi.Problem(len(c))
    p.set_objective(c)
    for F0, Fs in blocks:
        p.add_block(F0, Fs)
    p.set_options(threads=2)
    p.set_options(tol=1e-8)  # keeps threads
    r3 = p.solve()
    assert r3.status == "optimal" and r3.objective == pytest.approx(r1.objective, rel=1e-7)
    cm, bm, logdet = maxdet_problem(3)
    m1 = lmi.solve(cm, bm, logdet=logdet)
    m2 = lmi.solve(cm, bm, logdet=logdet, threads=2)
    assert m1.status == m2.status == "optimal"
    assert m2.objective == pytest.approx(m1.objective, rel=1e-7, abs=1e-8)
    for bad in (0, -2, 1000):
        with pytest.raises(InvalidArgumentError, match="threads"):
            p.set_options(threads=bad)
    for bad in (1.5, "2", True):
        with pytest.raises(InvalidArgumentError, match="threads"):
            lmi.solve(c, blocks, threads=bad)


# ---- maxdet -----------------------------------------------------------------------------
def test_maxdet_closed_form_x_below_s():
    rng = np.random.default_rng(3)
    R = rng.standard_normal((3, 3))
    S = R @ R.T + np.eye(3)
    m = 6
    G = affine_block(m, lambda v: smat(v, 3))
    blk = affine_block(m, lambda v: S - smat(v, 3))
    r = lmi.solve(np.zeros(m), [blk], logdet=G)
    assert r.status == "optimal"
    assert np.allclose(smat(r.x, 3), S, atol=1e-6 * np.linalg.norm(S))
    assert r.objective == pytest.approx(-np.log(np.linalg.det(S)), abs=1e-6)


@pytest.mark.parametrize("seed", range(10))
def test_maxdet_matches_independent_solver(seed):
    rng = np.random.default_rng(100 + seed)
    m, n = int(rng.integers(2, 5)), int(rng.integers(2, 4))
    one = np.ones((1, 1))
    blocks = []
    for i in range(m):  # −1 ≤ x_i ≤ 1 keeps the problem bounded
        e = np.zeros((m, 1, 1))
        e[i] = 1
        blocks += [(one.copy(), e), (one.copy(), -e)]
    Gs = np.array([(lambda A: (A + A.T) / 2)(rng.standard_normal((n, n))) for _ in range(m)])
    G0 = np.eye(n) * (1 + np.abs(Gs).sum(axis=0).max())  # G ≻ 0 on the whole box
    c = rng.standard_normal(m)
    r = lmi.solve(c, blocks, logdet=(G0, Gs))
    status, value, _ = solve_with_clarabel(c, blocks, logdet=(G0, Gs))
    assert status == "optimal"
    assert r.status == "optimal"
    assert r.objective == pytest.approx(value, rel=1e-6, abs=1e-6)
    assert_feasible(blocks, r.x)


# ---- the spec's LMIs against the independent solver -------------------------------------
def test_ex_bc14_offline_design_vertex_blocks():
    """papers.md §1.1 Theorem 1 at β = 0.8 for EX-BC14 (§1.4), P ⪰ I, min σ."""
    A = np.array([[1, 0, 0.2], [0, 0.8, 1], [0, 0, 1]])
    E = np.zeros((3, 5))
    E[0, 0], E[1, 1], E[2, 2] = 0.1, 0.05, 0.05
    C = np.array([[1, 0, 2], [0, -1, 1]])
    F = np.zeros((2, 5))
    F[0, 3] = F[1, 4] = 0.15
    beta, m = 0.8, 6 + 6 + 1

    def parts(v):
        return smat(v[:6], 3), v[6:12].reshape(3, 2), v[12]

    blocks = []
    for w in itertools.product([-1.0, 1.0], repeat=4):
        w = np.array(w + (1.0,))  # ± symmetry (§0.2): last component fixed to +1

        def lmi_fn(v, w=w):
            P, Y, s = parts(v)
            top = np.block([[beta * P, np.zeros((3, 1))], [np.zeros((1, 3)), np.array([[s]])]])
            low = np.hstack([P @ A - Y @ C, ((P @ E - Y @ F) @ w)[:, None]])
            return np.block([[top, low.T], [low, P]])

        blocks.append(affine_block(m, lmi_fn))
    blocks.append(affine_block(m, lambda v: parts(v)[0] - np.eye(3)))
    c = np.zeros(m)
    c[12] = 1.0
    r = lmi.solve(c, blocks)
    status, value, _ = solve_with_clarabel(c, blocks)
    assert status == "optimal" and r.status == "optimal"
    assert r.objective == pytest.approx(value, rel=1e-6)
    assert r.margin > -1e-7
    assert_feasible(blocks, r.x)


def test_pradius_lmi_9_ex_le13():
    """papers.md §3.2 LMI (9), EX-LE13 data (§3.5), strip 1, β = 0.6: max τ."""
    G = [np.array([[0, -0.5], [1, 0.7]]), np.array([[0, -0.5], [1, 1.3]])]
    Fw = np.array([[-0.12], [0.02]])
    psi, phi, ci, beta = 0.0148, 0.2, np.array([[-2.0], [1.0]]), 0.6
    m = 3 + 2 + 1  # P, Y, τ

    def parts(v):
        return smat(v[:3], 2), v[3:5].reshape(2, 1), v[5]

    blocks = []
    for Gj in G:
        def lmi9(v, Gj=Gj):
            P, Y, _ = parts(v)
            last = np.vstack([Gj.T @ P - Gj.T @ ci @ Y.T, Fw.T @ P - Fw.T @ ci @ Y.T, phi * Y.T])
            D = np.zeros((4, 4))
            D[:2, :2] = beta * P
            D[2, 2] = (Fw.T @ Fw)[0, 0]
            D[3, 3] = phi**2
            return np.block([[D, last], [last.T, P]])
        blocks.append(affine_block(m, lmi9))
    blocks.append(affine_block(m, lambda v: (1 - beta) * parts(v)[0] / (phi**2 + psi) - parts(v)[2] * np.eye(2)))
    blocks.append(affine_block(m, lambda v: np.array([[parts(v)[2]]])))
    c = np.zeros(m)
    c[5] = -1.0  # maximise τ
    r = lmi.solve(c, blocks)
    status, value, _ = solve_with_clarabel(c, blocks)
    assert status == "optimal" and r.status == "optimal"
    assert r.objective == pytest.approx(value, rel=1e-6)
    assert -r.objective > 0  # τ > 0: a usable design
    assert_feasible(blocks, r.x)


def test_improved_correction_lmi_L_small_case():
    """papers.md §6.3 (L) + (C1), 3-D coupled-noise check of §6.5, option C (P' ⪰ I)."""
    C = np.array([[1.0, 0, 2], [0, -1, 1]])
    F = np.array([[0, 0, 0, 0.15, 0.05], [0, 0, 0, 0.05, 0.15]])
    P = np.array([[3, 0.5, 0.2], [0.5, 2, 0.1], [0.2, 0.1, 1.5]])
    rho, cc, yt = 2.0, np.array([0.1, -0.2, 0.05]), np.array([0.3, -0.1])
    n, ny, nw = 3, 2, 5
    m = 6 + 3 + 3 + 1 + 1 + nw  # P', z, H, τ, ρ', μ

    def parts(v):
        return (smat(v[:6], 3), v[6:9], smat(v[9:12], 2), v[12], v[13], v[14:19])

    def L(v):
        Pp, z, H, tau, rp, mu = parts(v)
        b11 = tau * P + C.T @ H @ C
        b21 = (-tau * cc @ P - yt @ H @ C)[None, :]
        b22 = np.array([[rp - tau * rho - mu.sum() + tau * cc @ P @ cc + yt @ H @ yt]])
        return np.block([[b11, b21.T, Pp], [b21, b22, -z[None, :]], [Pp, -z[:, None], Pp]])

    blocks = [affine_block(m, L),
              affine_block(m, lambda v: np.diag(parts(v)[5]) - F.T @ parts(v)[2] @ F),  # (C1)
              affine_block(m, lambda v: parts(v)[0] - np.eye(3)),                        # P' ⪰ I
              affine_block(m, lambda v: np.array([[parts(v)[3]]]))]                      # τ ≥ 0
    blocks += [affine_block(m, lambda v, i=i: np.array([[parts(v)[5][i]]])) for i in range(nw)]  # μ ≥ 0
    c = np.zeros(m)
    c[13] = 1.0  # min ρ'
    r = lmi.solve(c, blocks)
    status, value, _ = solve_with_clarabel(c, blocks)
    assert status == "optimal" and r.status == "optimal"
    assert r.objective == pytest.approx(value, rel=1e-6, abs=1e-8)
    assert_feasible(blocks, r.x)


def test_hinf_gain_lmi_thesis_4_2():
    """thesis.md §4.2 LMI (2.35) with Q = I on the §4.8 data: min g = γ²."""
    A = np.array([[0.2, 0.2], [0, 0.5]])
    F = np.array([[0.0], [0.1]])
    C = np.array([[1.0, 0.0]])
    Z = np.array([[0.1]])
    Q = np.eye(2)
    m = 3 + 2 + 1  # P, U, g

    def parts(v):
        return smat(v[:3], 2), v[3:5].reshape(2, 1), v[5]

    def neg_lmi(v):  # −(2.35) ⪰ 0
        P, U, g = parts(v)
        PFUZ = np.hstack([P @ F, -U @ Z])
        M = np.block([[-P + Q, np.zeros((2, 2)), A.T @ P - C.T @ U.T],
                      [np.zeros((2, 2)), -g * np.eye(2), PFUZ.T],
                      [P @ A - U @ C, PFUZ, -P]])
        return -M

    blocks = [affine_block(m, neg_lmi), affine_block(m, lambda v: parts(v)[0] - 1e-6 * np.eye(2))]
    c = np.zeros(m)
    c[5] = 1.0
    r = lmi.solve(c, blocks)
    status, value, _ = solve_with_clarabel(c, blocks)
    assert status == "optimal" and r.status == "optimal"
    assert r.objective == pytest.approx(value, rel=1e-6)
    P, U, g = parts(r.x)
    Lg = np.linalg.solve(P, U)
    assert np.abs(np.linalg.eigvals(A - Lg @ C)).max() < 1  # Schur stable observer
