"""Thesis Ch. 1-3 H-infinity set-membership observers (setbound.hinf) against CVXPY
(Clarabel, SCS fallback) and by their guarantees (thesis.md §4, §5, §7)."""
import numpy as np
import pytest

import setbound
from setbound import Plant
from setbound import hinf

cp = pytest.importorskip("cvxpy")


# ----------------------------------------------------------------------------- references

def _solve(prob):
    for solver in ("CLARABEL", "SCS"):
        try:
            prob.solve(solver=solver)
            if prob.status in ("optimal", "optimal_inaccurate"):
                return
        except cp.SolverError:
            pass
    raise RuntimeError("cvxpy: no solver succeeded")


def cvx_gain(As, Fs, C, Z, Q):
    """Reference LMI (2.35)/(3.13): min g, common P, one U_i per vertex."""
    n, ny = C.shape[1], C.shape[0]
    m = Fs[0].shape[1] + Z.shape[1]
    P = cp.Variable((n, n), symmetric=True)
    g = cp.Variable()
    cons = [P >> 1e-8 * np.eye(n)]
    for A, F in zip(As, Fs):
        U = cp.Variable((n, ny))
        PE = cp.hstack([P @ F, -U @ Z]) if F.shape[1] else -U @ Z
        M = cp.bmat([[-P + Q, np.zeros((n, m)), A.T @ P - C.T @ U.T],
                     [np.zeros((m, n)), -g * np.eye(m), PE.T],
                     [P @ A - U @ C, PE, -P]])
        cons.append((M + M.T) / 2 << 0)
    prob = cp.Problem(cp.Minimize(g), cons)
    _solve(prob)
    return g.value


def cvx_refine(P, Aos, Es, g):
    """Reference (2.36)/(3.20): max log det Q with P, g, L fixed."""
    n = P.shape[0]
    Q = cp.Variable((n, n), symmetric=True)
    cons = []
    for Ao, E in zip(Aos, Es):
        m = E.shape[1]
        M = cp.bmat([[Ao.T @ P @ Ao - P + Q, Ao.T @ P @ E], [E.T @ P @ Ao, E.T @ P @ E - g * np.eye(m)]])
        cons.append((M + M.T) / 2 << 0)
    prob = cp.Problem(cp.Maximize(cp.log_det(Q)), cons)
    _solve(prob)
    return Q.value


def hinf_norm(A, E):
    w = np.linspace(0, np.pi, 4001)
    n = A.shape[0]
    vals = [np.linalg.svd(np.linalg.solve(np.exp(1j * x) * np.eye(n) - A, E), compute_uv=False)[0] for x in w]
    k = int(np.argmax(vals))
    from scipy.optimize import minimize_scalar
    r = minimize_scalar(lambda x: -np.linalg.svd(np.linalg.solve(np.exp(1j * x) * np.eye(n) - A, E), compute_uv=False)[0],
                        bounds=(w[max(k - 1, 0)], w[min(k + 1, len(w) - 1)]), method="bounded",
                        options={"xatol": 1e-12})
    return max(vals[k], -r.fun)


def lam_min(Q, P):
    from scipy.linalg import eigh
    return eigh(Q, P, eigvals_only=True).min()


# ----------------------------------------------------------------------------- examples

def ch2_plant():
    return Plant([[0.2, 0.2], [0, 0.5]], [[1, 0]], B=[[1], [1]], Fd=[[0], [0.1]], Z=[[0.1]])


def ch3_ex1():
    A = [[[1, r], [0, 1]] for r in (0.05, 0.1)]
    B = [[[0], [r]] for r in (0.05, 0.1)]
    return hinf.LpvPlant(A, [[1, 0]], [[0.05], [0.1]], B=B, Fd=B, Z=[[0.01]])


TS, SIG, ETA = 0.08, 1.0, 10.0


def lorenz_A(r1, r2):
    return np.array([[1 - TS * SIG, TS * SIG, 0], [0, 1 - TS * ETA, -TS * r1], [0, TS * r1, 1 - TS * r2]])


def ch3_ex2():
    theta = np.array([[-1, 9], [-1, 11], [1, 9], [1, 11]], float)
    A = [lorenz_A(*t) for t in theta]
    B = [np.array([[0], [TS * t[0]], [0]]) for t in theta]
    return hinf.LpvPlant(A, [[1, 0, 0]], theta, B=B, Fd=B, Z=[[0.0]])


def random_plant(rng, n, ny):
    A = rng.standard_normal((n, n))
    A *= rng.uniform(0.5, 1.2) / max(abs(np.linalg.eigvals(A)))
    return Plant(A, rng.standard_normal((ny, n)), B=rng.standard_normal((n, 1)),
                 Fd=0.3 * rng.standard_normal((n, 1)), Z=0.1 * np.eye(ny))


# ----------------------------------------------------------------------------- LMIs vs CVXPY

def test_brl_gamma_is_hinf_norm_ex15():
    A = np.array([[0.2, 0.2], [-0.2, 0.5]])
    E = np.array([[0.0], [1.0]])
    b = hinf.brl_ellipsoidal_rpi(A, E, [1.0])
    assert b.gamma == pytest.approx(hinf_norm(A, E), rel=1e-5)
    assert b.level == pytest.approx(np.linalg.eigvalsh(b.P).max() * b.g, rel=1e-9)
    # Ψ invariant: boundary × disturbance corners
    Lc = np.linalg.cholesky(b.P)
    for t in np.linspace(0, 2 * np.pi, 400):
        x = np.linalg.solve(Lc.T, [np.cos(t), np.sin(t)]) * np.sqrt(b.level)
        for w in (-1, 1):
            xp = A @ x + E[:, 0] * w
            assert xp @ b.P @ xp <= b.level * (1 + 1e-9)


def test_gain_ch2_against_cvxpy():
    p = ch2_plant()
    h = hinf.hinf_observer_gain(p)
    ref = cvx_gain([p.A], [p.F], p.C, p.Z, np.eye(2))
    assert h.g == pytest.approx(ref, rel=1e-4)
    assert max(abs(np.linalg.eigvals(p.A - h.L @ p.C))) < 1
    assert np.allclose(h.P @ h.L, h.U, atol=1e-9 * np.abs(h.U).max())
    # Non-unique L and P: check the LMI itself (Schur form with the returned L).
    Ao, E = p.A - h.L @ p.C, p.error_input(h.L)
    M = np.block([[Ao.T @ h.P @ Ao - h.P + np.eye(2), Ao.T @ h.P @ E], [E.T @ h.P @ Ao, E.T @ h.P @ E - h.g * np.eye(2)]])
    assert np.linalg.eigvalsh(M).max() <= 1e-9 * np.abs(M).max()


def test_gain_random_systems_against_cvxpy():
    rng = np.random.default_rng(1)
    done = 0
    while done < 4:
        p = random_plant(rng, int(rng.integers(2, 5)), int(rng.integers(1, 3)))
        try:
            h = hinf.hinf_observer_gain(p)
        except setbound.NotDetectableError:
            continue
        Q = np.diag(rng.uniform(0.5, 2.0, p.nx))
        hq = hinf.hinf_observer_gain(p, Q)
        assert h.g == pytest.approx(cvx_gain([p.A], [p.F], p.C, p.Z, np.eye(p.nx)), rel=1e-4)
        assert hq.g == pytest.approx(cvx_gain([p.A], [p.F], p.C, p.Z, Q), rel=1e-4)
        done += 1


def test_refine_and_algorithm2_ch2_against_cvxpy():
    p = ch2_plant()
    d = hinf.design_ellipsoidal_sm_observer(p, [1.0, 1.0])
    assert len(d.passes) == 2
    for ps in d.passes:
        # γ of each pass: the minimum of (2.35) with that pass's input Q.
        assert ps.g == pytest.approx(cvx_gain([p.A], [p.F], p.C, p.Z, ps.Q_input), rel=1e-4)
        # refinement (2.36) with this pass's P, L, g: log det optimum is unique → compare Q and λ.
        Ao, E = p.A - ps.L @ p.C, p.error_input(ps.L)
        Qc = cvx_refine(ps.P, [Ao], [E], ps.g)
        assert np.linalg.slogdet(ps.Q_refined)[1] == pytest.approx(np.linalg.slogdet(Qc)[1], abs=1e-4)
        assert ps.lambda_refined == pytest.approx(lam_min(Qc, ps.P), rel=1e-3)
        assert ps.lambda_input == pytest.approx(lam_min(ps.Q_input, ps.P), rel=1e-9)
    # pass 2 input: Q = V⁻¹ with A_o V A_oᵀ − V = −E diag(w̄²/3) Eᵀ (pass-1 gain)
    from scipy.linalg import solve_discrete_lyapunov
    L1 = d.passes[0].L
    V = solve_discrete_lyapunov(p.A - L1 @ p.C, p.error_input(L1) @ np.diag([1 / 3, 1 / 3]) @ p.error_input(L1).T)
    assert np.allclose(np.linalg.inv(V), d.passes[1].Q_input, rtol=1e-8)
    assert 0 < d.lambda_ <= 1
    assert d.cbar == pytest.approx(d.g * 2 / d.lambda_, rel=1e-12)
    assert np.allclose(d.e_inf, np.sqrt(d.cbar * np.diag(np.linalg.inv(d.P))), rtol=1e-10)
    # μ0 (2.72 with γ_ε = 1) and from the box corners of [−1, 1] × {0}
    assert hinf.mu0_from_ball(d, 1.0) == pytest.approx(max(1, np.linalg.eigvalsh(d.P).max() / d.cbar), rel=1e-12)
    assert hinf.mu0_from_box(d, [-1, 0], [1, 0]) == pytest.approx(max(1, d.P[0, 0] / d.cbar), rel=1e-12)
    # public refine / error-rpi / covariance helpers agree with the design
    Q2, lam2 = hinf.refine_dissipation_matrix(p, d.P, d.L, d.g)
    assert lam2 == pytest.approx(d.lambda_refined, rel=1e-6)
    _, lamd = hinf.refine_dissipation_matrix(p, d.P, d.L, d.g, route="direct")
    assert lamd >= lam2 * (1 - 1e-6)
    r = hinf.ellipsoidal_error_rpi(d.P, d.Q_refined, d.g, [1.0, 1.0])
    assert r.lambda_ == pytest.approx(lam_min(d.Q_refined, d.P), rel=1e-9)
    Vh, Qh = hinf.covariance_dissipation_matrix(p.A - L1 @ p.C, p.error_input(L1), np.eye(2) / 3)
    assert np.allclose(Vh, V, rtol=1e-9)
    S, lvl, pr = hinf.chebyshev_error_ellipsoid(Vh, 3.0)
    assert lvl == 9 and pr == pytest.approx(1 - 2 / 9)


def test_lpv_gain_and_algorithm3_ex2_against_cvxpy():
    lp = ch3_ex2()
    W = 4 / 3 * np.eye(2)
    h = hinf.hinf_observer_gain(lp)
    assert h.L.shape == (4, 3, 1)
    assert h.g == pytest.approx(cvx_gain(lp.A, lp.F, lp.C, lp.Z, np.eye(3)), rel=1e-4)
    d = hinf.design_ellipsoidal_sm_observer_lpv(lp, [2.0, 0.0], W=W)
    for ps in d.passes:
        assert ps.g == pytest.approx(cvx_gain(lp.A, lp.F, lp.C, lp.Z, ps.Q_input), rel=1e-4)
        assert ps.lambda_ == pytest.approx(max(ps.lambda_input, ps.lambda_refined), rel=1e-6)
        for i in range(4):
            assert max(abs(np.linalg.eigvals(lp.A[i] - ps.L[i] @ lp.C))) < 1
    # V = mean V_i (3.60) from the pass-1 gains; Q = V⁻¹ is the pass-2 input
    from scipy.linalg import solve_discrete_lyapunov
    Vs = []
    for i in range(4):
        Li = d.passes[0].L[i]
        E = np.hstack([lp.F[i], -Li @ lp.Z])
        Vs.append(solve_discrete_lyapunov(lp.A[i] - Li @ lp.C, E @ W @ E.T))
    assert np.allclose(np.linalg.inv(np.mean(Vs, axis=0)), d.passes[1].Q_input, rtol=1e-7)


def test_lpv_refine_ex1_against_cvxpy():
    lp = ch3_ex1()
    d = hinf.design_ellipsoidal_sm_observer_lpv(lp, [1.0, 1.0])
    for ps in d.passes:
        assert ps.g == pytest.approx(cvx_gain(lp.A, lp.F, lp.C, lp.Z, ps.Q_input), rel=1e-4)
        Aos = [lp.A[i] - ps.L[i] @ lp.C for i in range(2)]
        Es = [np.hstack([lp.F[i], -ps.L[i] @ lp.Z]) for i in range(2)]
        Qc = cvx_refine(ps.P, Aos, Es, ps.g)
        assert np.linalg.slogdet(ps.Q_refined)[1] == pytest.approx(np.linalg.slogdet(Qc)[1], abs=1e-3)
        Qr, lam = hinf.refine_dissipation_matrix(lp, ps.P, ps.L, ps.g)
        assert lam == pytest.approx(ps.lambda_refined, rel=1e-6)


def test_lpv_gain_random_against_cvxpy():
    rng = np.random.default_rng(4)
    for _ in range(3):
        n = 2
        A0 = rng.standard_normal((n, n)) * 0.4
        A1 = rng.standard_normal((n, n)) * 0.1
        C = np.array([[1.0, 0.0]])
        lp = hinf.LpvPlant([A0 - A1, A0 + A1], C, [[-1], [1]], Fd=[0.2 * np.eye(n)[:, :1]] * 2, Z=[[0.1]])
        try:
            h = hinf.hinf_observer_gain(lp)
        except (setbound.NotDetectableError, setbound.InfeasibleError):
            continue
        assert h.g == pytest.approx(cvx_gain(lp.A, lp.F, lp.C, lp.Z, np.eye(n)), rel=1e-4)


# ----------------------------------------------------------------------------- containment

def simulate_lti(p, d, x0, xhat0, mu0, T, mode, rng, u_fn=lambda k: 0.0):
    obs = hinf.EllipsoidalSMObserver(d, xhat0, mu0)
    x = np.array(x0, float)
    xs, ys, us = [x.copy()], [], []
    for k in range(T):
        w = (rng.uniform(-1, 1, p.m) if mode == "uniform" else rng.choice([-1.0, 1.0], p.m)) * d_wbar(d)
        u = np.full(p.nu, u_fn(k))
        ys.append(p.C @ x + p.Z @ w[p.nd:])
        us.append(u)
        x = p.A @ x + p.B @ u + p.F @ w[:p.nd]
        xs.append(x.copy())
    tr = obs.run(np.array(ys), np.array(us))
    check_traj(d, np.array(xs), tr)
    return tr


def d_wbar(d):
    return d._wbar


def check_traj(d, xs, tr):
    mu0 = tr.mu[0]
    assert len(tr) == len(xs) - 1  # N measurements: rows x_0 … x_{N-1} (the library's convention)
    for k, x in enumerate(xs[:len(tr)]):
        e = x - tr.center[k]
        assert e @ d.P @ e <= tr.mu[k] * d.cbar * (1 + 1e-9), k
        assert np.all(tr.lower[k] <= x) and np.all(x <= tr.upper[k]), k
        assert tr.sets[k].contains(x) if hasattr(tr.sets[k], "contains") else True
        closed = 1 + (1 - d.lambda_) ** k * (mu0 - 1)
        assert tr.mu[k] == pytest.approx(closed, rel=1e-7)


def design_with_wbar(fn, plant, wbar, **kw):
    d = fn(plant, wbar, **kw)
    d._wbar = np.asarray(wbar, float)
    return d


@pytest.mark.parametrize("mode", ["uniform", "vertex"])
def test_containment_ch2(mode):
    p = ch2_plant()
    d = design_with_wbar(hinf.design_ellipsoidal_sm_observer, p, [1.0, 1.0])
    mu0 = hinf.mu0_from_box(d, [-1, 0], [1, 0])
    rng = np.random.default_rng(2)
    for trial in range(5):
        x0 = [rng.choice([-1.0, 1.0]) if mode == "vertex" else rng.uniform(-1, 1), 0.0]
        simulate_lti(p, d, x0, [0, 0], mu0, 60, mode, rng, u_fn=lambda k: 1.0 if k < 9 else 0.0)


def test_containment_random_lti_20_systems():
    rng = np.random.default_rng(20)
    done = 0
    while done < 20:
        n, ny = int(rng.integers(2, 5)), int(rng.integers(1, 3))
        p = random_plant(rng, n, ny)
        wbar = rng.uniform(0.2, 1.0, p.m)
        try:
            d = design_with_wbar(hinf.design_ellipsoidal_sm_observer, p, wbar)
        except setbound.NotDetectableError:
            continue
        done += 1
        mu0 = hinf.mu0_from_box(d, -np.ones(n), np.ones(n))
        for mode in ("uniform", "vertex"):
            x0 = rng.choice([-1.0, 1.0], n) if mode == "vertex" else rng.uniform(-1, 1, n)
            simulate_lti(p, d, x0, np.zeros(n), mu0, 50, mode, rng, u_fn=lambda k: np.sin(0.3 * k))


def simulate_lpv(lp, d, x0, xhat0, mu0, T, w_fn, rho_fn, u_fn, A_fn=None):
    obs = hinf.LPVEllipsoidalSMObserver(d, xhat0, mu0)
    x = np.array(x0, float)
    xs, ys, us, rs = [x.copy()], [], [], []
    for k in range(T):
        rho = np.atleast_1d(rho_fn(k, x))
        w = w_fn(k)
        u = np.atleast_1d(u_fn(k))
        a = lp.weights(rho)
        A = sum(ai * Ai for ai, Ai in zip(a, lp.A)) if A_fn is None else A_fn(rho)
        B = sum(ai * Bi for ai, Bi in zip(a, lp.B))
        F = sum(ai * Fi for ai, Fi in zip(a, lp.F))
        ys.append(lp.C @ x + lp.Z @ w[lp.nd:])
        us.append(u)
        rs.append(rho)
        x = A @ x + B @ u + F @ w[:lp.nd]
        xs.append(x.copy())
    tr = obs.run(np.array(ys), np.array(us), rho=np.array(rs))
    check_traj(d, np.array(xs), tr)
    return tr, np.array(xs)


@pytest.mark.parametrize("mode", ["uniform", "vertex"])
def test_containment_lpv_ex1(mode):
    lp = ch3_ex1()
    d = design_with_wbar(hinf.design_ellipsoidal_sm_observer_lpv, lp, [1.0, 1.0])
    mu0 = hinf.mu0_from_box(d, [-0.1, -2.0], [0.1, -2.0])  # e0 = x0 - 0 with x0(2) = -2 (§5.8)
    rng = np.random.default_rng(3)
    for trial in range(4):
        w_fn = (lambda k: rng.uniform(-1, 1, 2)) if mode == "uniform" else (lambda k: rng.choice([-1.0, 1.0], 2))
        rho_fn = (lambda k, x: rng.uniform(0.05, 0.1)) if mode == "uniform" else (lambda k, x: rng.choice([0.05, 0.1]))
        simulate_lpv(lp, d, [rng.uniform(-0.1, 0.1), -2.0], [0, 0], mu0, 80, w_fn, rho_fn,
                     lambda k: 10.0 if k < 10 else 0.0, A_fn=lambda r: np.array([[1, r[0]], [0, 1]]))


@pytest.mark.parametrize("mode", ["sine", "uniform", "vertex"])
def test_containment_lorenz_ex2(mode):
    lp = ch3_ex2()
    d = design_with_wbar(hinf.design_ellipsoidal_sm_observer_lpv, lp, [2.0, 0.0], W=4 / 3 * np.eye(2))
    mu0 = hinf.mu0_from_box(d, [0, 0, -0.5], [0, 0, 0.5])
    rng = np.random.default_rng(5)
    for x3 in (-0.5, 0.5, rng.uniform(-0.5, 0.5)):
        if mode == "sine":
            w_fn = lambda k: np.array([2 * np.sin(0.5 * TS * k), 0.0])
        elif mode == "uniform":
            w_fn = lambda k: np.array([rng.uniform(-2, 2), 0.0])
        else:
            w_fn = lambda k: np.array([rng.choice([-2.0, 2.0]), 0.0])
        # quasi-LPV: ρ1 = x1 kept in [−1, 1] (clipped), ρ2 = 10
        tr, xs = simulate_lpv(lp, d, [0.5, 0, x3], [0.5, 0, 0], mu0, 120, w_fn,
                              lambda k, x: np.array([np.clip(x[0], -1, 1), 10.0]), lambda k: 10.0,
                              A_fn=lambda r: lorenz_A(r[0], r[1]))
    assert tr.guaranteed


def test_containment_random_lpv_20_systems():
    rng = np.random.default_rng(21)
    done = 0
    while done < 20:
        n = int(rng.integers(2, 4))
        L = int(rng.integers(1, 3))
        N = 2 ** L
        lo, hi = -np.ones(L), np.ones(L)
        theta = np.array([[hi[j] if (i >> j) & 1 else lo[j] for j in range(L)] for i in range(N)])
        rng.shuffle(theta)
        A0 = rng.standard_normal((n, n))
        A0 *= 0.8 / max(abs(np.linalg.eigvals(A0)))
        Aj = [0.1 * rng.standard_normal((n, n)) for _ in range(L)]
        A = [A0 + sum(t[j] * Aj[j] for j in range(L)) for t in theta]
        B = [rng.standard_normal((n, 1))] * N
        F = [0.3 * rng.standard_normal((n, 1))] * N
        C = rng.standard_normal((1, n))
        lp = hinf.LpvPlant(A, C, theta, B=B, Fd=F, Z=[[0.1]])
        wbar = np.array([0.5, 0.5])
        try:
            d = design_with_wbar(hinf.design_ellipsoidal_sm_observer_lpv, lp, wbar)
        except (setbound.NotDetectableError, setbound.InfeasibleError):
            continue
        done += 1
        mu0 = hinf.mu0_from_box(d, -np.ones(n), np.ones(n))
        for mode in ("uniform", "vertex"):
            if mode == "uniform":
                w_fn = lambda k: rng.uniform(-1, 1, 2) * wbar
                rho_fn = lambda k, x: rng.uniform(-1, 1, L)
            else:
                w_fn = lambda k: rng.choice([-1.0, 1.0], 2) * wbar
                rho_fn = lambda k, x: rng.choice([-1.0, 1.0], L)
            x0 = rng.uniform(-1, 1, n) if mode == "uniform" else rng.choice([-1.0, 1.0], n)
            simulate_lpv(lp, d, x0, np.zeros(n), mu0, 40, w_fn, rho_fn, lambda k: np.cos(0.2 * k))


# ----------------------------------------------------------------------------- bad input

def test_bad_input_messages():
    bad = Plant([[0.2, 0], [0, 1.2]], [[1, 0]], B=[[1], [1]], Fd=[[0], [0.1]], Z=[[0.1]])
    with pytest.raises(setbound.NotDetectableError, match=r"A, C: the pair \(A, C\) is not detectable"):
        hinf.hinf_observer_gain(bad)
    with pytest.raises(setbound.NotDetectableError):
        hinf.design_ellipsoidal_sm_observer(bad, [1, 1])
    p = ch2_plant()
    with pytest.raises(setbound.DimensionError, match="wbar"):
        hinf.design_ellipsoidal_sm_observer(p, [1, 1, 1])
    with pytest.raises(setbound.NotFiniteError, match="^.*wbar"):
        hinf.design_ellipsoidal_sm_observer(p, [1, np.nan])
    with pytest.raises(setbound.NotPositiveDefiniteError, match="Q"):
        hinf.hinf_observer_gain(p, -np.eye(2))
    with pytest.raises(setbound.InfeasibleError, match="A: not Schur stable"):
        hinf.brl_ellipsoidal_rpi([[1.2, 0], [0, 0.1]], [[0], [1]], [1])
    d = hinf.design_ellipsoidal_sm_observer(p, [1, 1])
    obs = hinf.EllipsoidalSMObserver(d, [0, 0], 1.5)
    obs.step([0.3], [1.0])
    c, mu = obs.center, obs.mu
    with pytest.raises(setbound.NotFiniteError, match="y"):
        obs.step([np.inf], [1.0])  # (NaN: a missing reading)
    with pytest.raises(setbound.DimensionError, match="y"):
        obs.step([1.0, 2.0], [1.0])
    with pytest.raises(setbound.NotFiniteError):
        obs.run(np.array([[0.1], [np.inf]]), np.ones((2, 1)))
    assert np.array_equal(obs.center, c) and obs.mu == mu and obs.steps == 1
    # LPV: ρ outside the polytope names rho; the observer is unchanged
    lp = ch3_ex1()
    dl = hinf.design_ellipsoidal_sm_observer_lpv(lp, [1, 1])
    ol = hinf.LPVEllipsoidalSMObserver(dl, [0, 0], 2.0)
    ol.step([0.0], [10.0], rho=[0.07])
    c = ol.center
    with pytest.raises(setbound.InvalidArgumentError, match=r"rho: \(0.2\) is outside the scheduling polytope"):
        ol.step([0.0], [10.0], rho=[0.2])
    with pytest.raises(setbound.InvalidArgumentError, match="rho"):
        ol.run(np.zeros((3, 1)), np.ones((3, 1)), rho=np.array([[0.06], [0.07], [0.5]]))
    assert np.array_equal(ol.center, c) and ol.steps == 1
    with pytest.raises(setbound.InvalidArgumentError, match="rho"):
        hinf.polytopic_weights([[0, 0], [2, 0], [0, 2]], [1.5, 1.5])
    with pytest.raises(setbound.DimensionError, match="theta"):
        hinf.LpvPlant([np.eye(2)], [[1, 0]], [[0], [1]])


def test_polytopic_weights_orders_and_lp():
    rng = np.random.default_rng(6)
    th_box = np.array([[-1, 9], [-1, 11], [1, 9], [1, 11]], float)
    th_ex1 = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)  # Ex 3.1 order
    tri = np.array([[0, 0], [2, 0], [0, 2]], float)
    for _ in range(20):
        for th in (th_box, th_ex1, tri):
            a = rng.dirichlet(np.ones(len(th)))
            rho = a @ th
            w = hinf.polytopic_weights(th, rho)
            assert w.min() >= 0 and w.sum() == pytest.approx(1, abs=1e-12)
            assert np.allclose(w @ th, rho, atol=1e-7)
