"""Test-only reference for the LMI solver tests: the same problem solved by CVXPY + Clarabel,
and the feasibility check of a returned point."""
import numpy as np
import pytest


def solve_with_clarabel(c, blocks, eq=None, logdet=None):
    """min c·x − log det G(x) s.t. F0 + Σ x_i Fs[i] ⪰ 0 for every block, Aeq x = beq.
    Returns (CVXPY status, optimal value, x)."""
    cp = pytest.importorskip("cvxpy")
    pytest.importorskip("clarabel")
    m = len(c)
    x = cp.Variable(m)
    cons = []
    for F0, Fs in blocks:
        expr = F0 + sum(x[i] * Fs[i] for i in range(m) if np.any(Fs[i]))
        cons.append((expr + expr.T) / 2 >> 0)
    if eq is not None:
        cons.append(eq[0] @ x == eq[1])
    obj = c @ x
    if logdet is not None:
        G = logdet[0] + sum(x[i] * logdet[1][i] for i in range(m) if np.any(logdet[1][i]))
        obj = obj - cp.log_det((G + G.T) / 2)
    prob = cp.Problem(cp.Minimize(obj), cons)
    prob.solve(solver=cp.CLARABEL)
    return prob.status, prob.value, x.value


def assert_feasible(blocks, x, tol=1e-7):
    """Every block F0 + Σ x_i Fs[i] has λ_min ≥ −tol·max(1, |F|)."""
    for F0, Fs in blocks:
        F = F0 + np.einsum("i,ijk->jk", x, Fs)
        assert np.linalg.eigvalsh(F).min() >= -tol * max(1.0, np.abs(F).max())
