"""CORA's ROPO (setbound.parallelotope) and the Rauch–Tung–Striebel smoother (setbound.point).

No saved CORA values exist for either (spec §4.4 class 5): ROPO is checked by properties
(containment of the truth on random systems and on CORA's vehicle6 / pedestrian4 data, ROPO ⊇ the
exact consistent-set hull, the cora convention's S' indexing), RTS against the Kalman filter and a
hand-computed scalar smoother.
"""
import pickle

import numpy as np
import pytest

import setbound
import setbound.cora as cora
from setbound.benchmarks import load_cora
from setbound.errors import (DimensionError, InconsistentMeasurementError, InvalidArgumentError,
                             NotPositiveDefiniteError, SetboundError)
from setbound.parallelotope import ParallelotopeEstimator
from setbound.point import rts_smooth

from cora_support import DATA, needs_data, assert_truth_inside



def _random_system(rng, trial):
    n, ny = 2 + trial % 3, 1 + trial % 2
    A = rng.normal(size=(n, n)) / np.sqrt(n)
    A *= (1.05 if trial % 2 else 0.9) / np.max(np.abs(np.linalg.eigvals(A)))
    C = rng.normal(size=(ny, n))
    E = np.hstack([0.05 * np.eye(n), np.zeros((n, ny))])
    F = np.hstack([np.zeros((ny, n)), 0.1 * np.eye(ny)])
    B = rng.normal(size=(n, 1))
    return setbound.LinearSystem(A, C, B=B, E=E, F=F)


def _simulate(rng, sys, N, vertex):
    n = sys.nx
    x = rng.choice([-1.0, 1.0], size=n) if vertex else rng.uniform(-1, 1, n)
    X, Y, U = np.empty((N, n)), np.empty((N, sys.ny)), rng.normal(size=(N, 1))
    for k in range(N):
        w = rng.choice([-1.0, 1.0], size=sys.nw) if vertex else rng.uniform(-1, 1, sys.nw)
        X[k] = x
        Y[k] = sys.C @ x + sys.F @ w
        x = sys.A @ x + sys.B @ U[k] + sys.E @ w
    return X, Y, U


# ---- ROPO -----------------------------------------------------------------------------------------

@pytest.mark.parametrize("reduction", ["girard", "pca"])
@pytest.mark.parametrize("vertex", [False, True], ids=["random", "vertex"])
def test_ropo_contains_the_truth_on_random_systems(reduction, vertex):
    rng = np.random.default_rng(2027)
    for trial in range(20):
        sys = _random_system(rng, trial)
        X, Y, U = _simulate(rng, sys, 40, vertex)
        est = ParallelotopeEstimator(sys, setbound.Box(-np.ones(sys.nx), np.ones(sys.nx)), reduction=reduction)
        t = est.run(Y, U)
        assert t.filter is True
        assert t.contains(X, tol=0.0).all(), (reduction, trial)
        assert not t.flagged.any()
        theta, T, r = est.parallelotope
        assert T.shape == (sys.nx, sys.nx) and np.all(r >= 0)


def test_ropo_contains_the_exact_hull():
    rng = np.random.default_rng(7)
    for trial in range(4):
        sys = _random_system(rng, trial)
        X, Y, U = _simulate(rng, sys, 10, trial % 2 == 1)
        x0 = setbound.Box(-np.ones(sys.nx), np.ones(sys.nx))
        h = setbound.exact_hull(sys, Y, U, x0=setbound.sets.as_zonotope(x0, "x0"))
        for reduction in ("girard", "pca"):
            t = ParallelotopeEstimator(sys, x0, reduction=reduction).run(Y, U)
            tol = 1e-8 * (1 + np.abs(h.lower) + np.abs(h.upper))
            assert np.all(t.lower <= h.lower + tol) and np.all(t.upper >= h.upper - tol), (trial, reduction)


def test_ropo_cora_convention_starts_from_r0():
    rng = np.random.default_rng(3)
    sys = _random_system(rng, 1)
    X, Y, U = _simulate(rng, sys, 12, False)
    x0 = setbound.Zonotope(np.zeros(sys.nx), 0.5 * np.ones((sys.nx, 1)))  # fewer generators than n
    est = ParallelotopeEstimator(sys, x0, convention="cora", reduction="pca")
    t = est.run(Y, U)
    np.testing.assert_array_equal(t.sets[0].generators, x0.generators)  # row 0: R0 itself, y_0 unused
    assert (t.status[0] == setbound.measurement.UNUSED).all()
    assert all(z.generators.shape == (sys.nx, sys.nx) for z in t.sets[1:])
    with pytest.raises(InvalidArgumentError, match="on_inconsistency"):
        ParallelotopeEstimator(sys, x0, convention="cora", on_inconsistency="raise")


def test_ropo_inconsistent_readings_and_missing_outputs():
    rng = np.random.default_rng(5)
    sys = _random_system(rng, 0)
    x0 = setbound.Box(-np.ones(sys.nx), np.ones(sys.nx))
    est = ParallelotopeEstimator(sys, x0, on_inconsistency="raise")
    est.step([0.0], [0.0])
    saved = est.save_state()
    with pytest.raises(InconsistentMeasurementError, match="step 1: output 0"):
        est.step([1e3], [0.0])
    assert est.save_state() == saved
    flag = ParallelotopeEstimator(sys, x0)
    flag.step([0.0], [0.0])
    flag.step([1e3], [0.0])
    assert flag.last_check.status[0] == setbound.measurement.INCONSISTENT
    reset = ParallelotopeEstimator(sys, x0, on_inconsistency="reset")
    reset.step([1e3], [0.0])
    assert reset.last_check.reset
    flag.step(None, [0.0])
    assert flag.last_check.status[0] == setbound.measurement.MISSING


def test_ropo_state_pickle_and_reset():
    rng = np.random.default_rng(4)
    sys = _random_system(rng, 2)
    X, Y, U = _simulate(rng, sys, 12, True)
    for convention in ("setbound", "cora"):
        est = ParallelotopeEstimator(sys, setbound.Box(-np.ones(sys.nx), np.ones(sys.nx)), reduction="pca",
                                     convention=convention)
        full = est.run(Y, U)
        est.run(Y[:5], U[:5])
        saved = est.save_state()
        clone = pickle.loads(pickle.dumps(est))
        rest = est.run(Y[5:], U[5:], reset=False)
        np.testing.assert_array_equal(rest.upper, full.upper[5:])
        np.testing.assert_array_equal(rest.center, full.center[5:])
        clone.restore_state(saved)
        np.testing.assert_array_equal(clone.run(Y[5:], U[5:], reset=False).lower, rest.lower)
        est.reset()
        assert est.steps == 0


def test_ropo_bad_input_is_named():
    sys = setbound.LinearSystem([[0.9, 0.1], [0.0, 0.8]], [[1.0, 0.0]], E=[[0.1, 0.0], [0.0, 0.0]], F=[[0.0, 0.1]])
    x0 = setbound.Box([-1, -1], [1, 1])
    with pytest.raises(InvalidArgumentError, match="reduction"):
        ParallelotopeEstimator(sys, x0, reduction="combastel")
    with pytest.raises(InvalidArgumentError, match="convention"):
        ParallelotopeEstimator(sys, x0, convention="matlab")
    with pytest.raises(InvalidArgumentError, match="on_inconsistency"):
        ParallelotopeEstimator(sys, x0, on_inconsistency="ignore")
    with pytest.raises(DimensionError, match="x0"):
        ParallelotopeEstimator(sys, setbound.Box([-1], [1]))
    exact = setbound.LinearSystem([[0.9, 0.1], [0.0, 0.8]], [[1.0, 0.0]], E=[[0.1], [0.0]], F=[[0.0]])
    with pytest.raises(InvalidArgumentError, match="F"):
        ParallelotopeEstimator(exact, x0, convention="cora")
    interval = setbound.LinearSystem(setbound.IntervalMatrix.from_mid_rad([[0.9, 0.1], [0.0, 0.8]],
                                                                           [[0.01, 0.0], [0.0, 0.0]]),
                                     [[1.0, 0.0]], E=[[0.1, 0.0], [0.0, 0.0]], F=[[0.0, 0.1]])
    with pytest.raises(InvalidArgumentError, match="system"):
        ParallelotopeEstimator(interval, x0)
    est = ParallelotopeEstimator(sys, x0)
    with pytest.raises(DimensionError, match="y"):
        est.step([0.0, 1.0])
    with pytest.raises(SetboundError, match="y"):
        est.step([np.inf])
    with pytest.raises(InvalidArgumentError, match="no step"):
        est.current_set()
    assert est.steps == 0


@needs_data
@pytest.mark.parametrize("name", ["vehicle6", "pedestrian4"])
@pytest.mark.parametrize("reduction", ["girard", "pca"])
def test_ropo_true_trajectories_stay_inside(name, reduction):
    b = load_cora(DATA / f"{name}.json")
    t = ParallelotopeEstimator(b.system, b.x0, reduction=reduction).run(b.y, b.u)
    assert_truth_inside(name, b.truth, t.lower, t.upper)


@needs_data
@pytest.mark.parametrize("name,reduction", [(m, "girard") for m in ("vehicle6", "pedestrian4", "vehicle2_cora_unittest",
                                                                     "alamo2005_2d_cora_unittest", "tank30")]
                         + [("vehicle6", "pca"), ("alamo2005_2d_cora_unittest", "pca")])
def test_ropo_guaranteed_step_is_coras_step_plus_rounding(name, reduction):
    """With y_0 missing both conventions index time alike (S'): the guaranteed recursion (outward
    rounded, rounding box) must then be CORA's arithmetic to rounding (and contain it, girard). PCA is
    compared only where its basis is not fixed by rounding (pedestrian4, vehicle2 and tank30 have
    near-isotropic reduced blocks: CORA's PCA chaos)."""
    b = load_cora(DATA / f"{name}.json")
    y = b.y.copy()
    y[0] = np.nan
    a = ParallelotopeEstimator(b.system, b.x0, reduction=reduction).run(y, b.u)
    c = ParallelotopeEstimator(b.system, b.x0, reduction=reduction, convention="cora").run(b.y, b.u)
    scale = 1 + np.maximum(np.abs(c.lower), np.abs(c.upper))
    assert np.max(np.maximum(np.abs(a.lower - c.lower), np.abs(a.upper - c.upper)) / scale) < 1e-9
    if reduction == "girard":  # (a PCA basis itself moves with the rounding of the columns it boxes)
        assert np.all(a.lower <= c.lower + 1e-12 * scale) and np.all(a.upper >= c.upper - 1e-12 * scale)


@needs_data
def test_ropo_by_coras_name():
    b = load_cora(DATA / "vehicle6.json")
    r = cora.observe(b, "ROPO", steps=60)
    t = ParallelotopeEstimator(b.system, b.x0, reduction=b.reduction_method).run(b.y[:60], b.u[:60])
    np.testing.assert_array_equal(r.lower, t.lower)
    rc = cora.observe(b, "ROPO", convention="cora", steps=60)
    # row 0 is the hull of R0 itself (y_0 unused), then CORA's recursion
    np.testing.assert_allclose(rc.lower[0], b.x0.center - np.abs(b.x0.generators).sum(axis=1), rtol=1e-13)
    assert not np.array_equal(rc.lower[1:], r.lower[1:])
    assert "ROPO" in cora.algorithms()


# ---- Rauch–Tung–Striebel --------------------------------------------------------------------------

def _kalman_last(sys, x0, P0, Sw, Sv, Y, U):
    n, ny = sys.nx, sys.ny
    E = np.hstack([np.eye(n), np.zeros((n, ny))])
    F = np.hstack([np.zeros((ny, n)), np.eye(ny)])
    W = np.block([[Sw, np.zeros((n, ny))], [np.zeros((ny, n)), Sv]])
    ks = setbound.LinearSystem(sys.A, sys.C, B=sys.B, D=sys.D, E=E, F=F)
    kf = setbound.ellipsoidal.KalmanFilter(ks, x0, P0, omega_cov=W)
    for k in range(len(Y)):
        kf.step(Y[k], U[k])
    return kf.mean, kf.covariance


def test_rts_last_state_is_the_kalman_filters_and_smoothing_shrinks_the_covariance():
    rng = np.random.default_rng(11)
    for trial in range(8):
        sys = _random_system(rng, trial)
        X, Y, U = _simulate(rng, sys, 30, False)
        n = sys.nx
        Sw = 0.33 ** 2 * sys.E @ sys.E.T + 1e-4 * np.eye(n)
        Sv = 0.33 ** 2 * sys.F @ sys.F.T
        P0 = 0.33 ** 2 * np.eye(n)
        r = rts_smooth(sys, np.zeros(n), P0, Sw, Sv, Y, U)
        mean, cov = _kalman_last(sys, np.zeros(n), P0, Sw, Sv, Y, U)
        np.testing.assert_allclose(r.smoothed[-1], mean, rtol=0, atol=1e-12)
        np.testing.assert_allclose(r.smoothed_cov[-1], cov, rtol=0, atol=1e-12)
        np.testing.assert_array_equal(r.smoothed[-1], r.filtered[-1])
        tr_s = np.trace(r.smoothed_cov, axis1=1, axis2=2)
        tr_f = np.trace(r.filtered_cov, axis1=1, axis2=2)
        assert np.all(tr_s <= tr_f * (1 + 1e-12)), trial
        assert np.all(tr_s[:-1] < tr_f[:-1]), trial  # strictly better before the last step


def test_rts_scalar_two_steps_by_hand():
    # x+ = x + w, y = x + v, Σ_w = Σ_v = P0 = 1, x0 = 0, y = (1, 2): forward x̂ = (0.5, 1.4),
    # P = (0.5, 0.6), M_1 = 1.5; backward J_0 = 1/3, x^s_0 = 0.5 + 0.9/3 = 0.8, P^s_0 = 0.5 − 0.9/9 = 0.4.
    sys = setbound.LinearSystem([[1.0]], [[1.0]], E=[[0.0]], F=[[0.0]])
    r = rts_smooth(sys, [0.0], [[1.0]], [[1.0]], [[1.0]], [[1.0], [2.0]])
    np.testing.assert_allclose(r.filtered[:, 0], [0.5, 1.4], atol=1e-15)
    np.testing.assert_allclose(r.smoothed[:, 0], [0.8, 1.4], atol=1e-15)
    np.testing.assert_allclose(r.smoothed_cov[:, 0, 0], [0.4, 0.6], atol=1e-15)
    # CORA's indexing: x̂_0 = x0, y_0 unused: x̂_1 = 4/3, x^s_0 = 2/3.
    c = rts_smooth(sys, [0.0], [[1.0]], [[1.0]], [[1.0]], [[1.0], [2.0]], use_first_measurement=False)
    np.testing.assert_allclose(c.smoothed[:, 0], [2 / 3, 4 / 3], atol=1e-15)


def test_rts_bad_input_is_named():
    sys = setbound.LinearSystem([[1.0]], [[1.0]], E=[[0.0]], F=[[0.0]])
    Y = np.zeros((3, 1))
    with pytest.raises(DimensionError, match="x0"):
        rts_smooth(sys, [0.0, 0.0], [[1.0]], [[1.0]], [[1.0]], Y)
    with pytest.raises(NotPositiveDefiniteError, match="Sigma_v"):
        rts_smooth(sys, [0.0], [[1.0]], [[1.0]], [[0.0]], Y)
    with pytest.raises(NotPositiveDefiniteError, match="P0"):
        rts_smooth(sys, [0.0], [[-1.0]], [[1.0]], [[1.0]], Y)
    with pytest.raises(DimensionError, match="Sigma_w"):
        rts_smooth(sys, [0.0], [[1.0]], np.eye(2), [[1.0]], Y)
    with pytest.raises(DimensionError, match="y"):
        rts_smooth(sys, [0.0], [[1.0]], [[1.0]], [[1.0]], np.zeros((3, 2)))
    with pytest.raises(SetboundError, match="y"):
        rts_smooth(sys, [0.0], [[1.0]], [[1.0]], [[1.0]], [[0.0], [np.inf]])
    with pytest.raises(InvalidArgumentError, match="use_first_measurement"):
        rts_smooth(sys, [0.0], [[1.0]], [[1.0]], [[1.0]], Y, use_first_measurement="yes")


@needs_data
@pytest.mark.parametrize("alg", ["Rauch-Tung-Striebel", "RTS"])
def test_rts_by_coras_name_returns_points(alg):
    b = load_cora(DATA / "vehicle6.json")
    r = cora.observe(b, alg, steps=50)
    np.testing.assert_array_equal(r.lower, r.upper)
    assert r.sets == []
    # Point estimates, not sets: the smoothed states are close to the truth but not claimed to contain it.
    assert np.sqrt(np.mean((r.lower - b.truth[:50]) ** 2)) < 1.0
    with pytest.raises(InvalidArgumentError, match="takes no options"):
        cora.observe(b, alg, steps=5, reduction="pca")


def _ropo_case_22045():
    # the system, initial set and readings of the guarantee campaign's ROPO case seed 22045
    # (n_x = 8, ill-conditioned stable, one output, vertex noise; python -m setbound.campaign
    # --estimator ropo --seed 22045)
    from setbound import campaign
    from setbound.simulation import simulate

    case = campaign.random_case("ropo", 22045)
    s = case.system
    rng = np.random.default_rng([22045, 1000 + campaign.ESTIMATORS["ropo"].index])
    system = s.linear_system()
    lo, hi = campaign._x0_box(s, rng)
    x0 = setbound.Zonotope(0.5 * (lo + hi), np.diag(0.5 * (hi - lo)))
    sim = simulate(system, x0, case.N, disturbance=case.disturbance, rng=rng)
    return s, system, x0, sim


def test_ropo_girard_divergence_on_a_stable_system_is_the_method():
    """Campaign case seed 22045: A is Schur stable (ρ(A) = 0.92) but ρ(|A|) = 1.31 (a diagonal
    similarity spreads the entries over 1e-4 … 1e4) and one output. Girard's order-1 reduction
    replaces the predicted set by its interval hull at every step, so the one strip per step cannot
    stop the box from growing: the parallelotope grows by ≈ 1.17 per step to 1e53 (cond(T) ~ 1e17).
    This is CORA's recursion itself, not its rounding: the Cora convention (CORA's arithmetic) and
    the guaranteed one grow alike, and CORA's recursion in 60-digit arithmetic gives the same
    widths. PCA's oriented box keeps the set bounded on the same data. (Containment at every step:
    tests/python/test_campaign.py, decided exactly.)"""
    import mpmath as mp

    s, system, x0, sim = _ropo_case_22045()
    assert max(abs(np.linalg.eigvals(s.A))) < 0.95 < 1.3 < max(abs(np.linalg.eigvals(np.abs(s.A))))
    width = {}
    for red in ("girard", "pca"):
        for conv in ("setbound", "cora"):
            t = ParallelotopeEstimator(system, x0, reduction=red, convention=conv).run(sim.y)
            width[red, conv] = np.array([np.abs(Z.generators).sum(axis=1).max() for Z in t.sets])
    g, gc = width["girard", "setbound"], width["girard", "cora"]
    assert g[200] > 1e14 and g[-1] > 1e50
    rate = (g[300] / g[100]) ** (1 / 200)
    assert 1.1 < rate < 1.25 and abs((gc[300] / gc[100]) ** (1 / 200) / rate - 1) < 1e-3
    assert np.all(np.abs(g[100:] / gc[100:] - 1) < 0.05)
    for conv in ("setbound", "cora"):
        assert width["pca", conv][100:].max() < 1e3

    # CORA's priv_observe_ROPO recursion (S' indexing, girard) in 60 digits
    mp.mp.dps = 60
    n = s.nx
    A, E = mp.matrix(s.A.tolist()), mp.matrix(system.E.tolist())
    sig = mp.mpf(float(np.abs(system.F).sum()))
    p = mp.matrix([mp.mpf(float(v)) / sig for v in system.C[0]])
    th, G = mp.matrix(x0.center.tolist()), mp.matrix(x0.generators.tolist())
    for k in range(1, 121):
        th, Gp = A * th, A * G
        T = mp.zeros(n, n)
        for i in range(n):  # reduce(·, 'girard', 1): the interval hull
            T[i, i] = sum(abs(Gp[i, j]) for j in range(Gp.cols)) + sum(abs(E[i, j]) for j in range(E.cols))
        c = mp.mpf(float(sim.y[k, 0])) / sig
        dots = []
        for j in range(n):
            if (p.T * T[:, j])[0] < 0:
                T[:, j] = -T[:, j]
            dots.append((p.T * T[:, j])[0])
        d = (p.T * th)[0] - c
        E0p, E0n = d + sum(dots), d - sum(dots)
        rop, ron = min(1, E0p), min(1, -E0n)
        pn, cn = 2 * p / (rop + ron), 2 / (rop + ron) * (c + (rop - ron) / 2)
        for j in range(n):
            rp, rn = (1, 1) if dots[j] == 0 else (min(1, (1 - E0n) / dots[j] - 1), min(1, (1 + E0p) / dots[j] - 1))
            th += (rp - rn) / 2 * T[:, j]
            T[:, j] *= (rp + rn) / 2
        vals = [(pn.T * (p / (p.T * p)[0]))[0]] + [(pn.T * T[:, j])[0] for j in range(n)]
        best = max(range(n + 1), key=lambda i: (vals[i], -i))  # the first maximiser
        if best > 0:
            tj = T[:, best - 1]
            kap = 1 / (pn.T * tj)[0]
            th = th + kap * tj * (cn - (pn.T * th)[0])
            G = mp.zeros(n, n)
            for j in range(n):
                G[:, j] = kap * tj if j == best - 1 else T[:, j] - kap * (pn.T * T[:, j])[0] * tj
        else:
            G = T
        if k in (60, 120):
            w = max(sum(abs(G[i, j]) for j in range(n)) for i in range(n))
            assert abs(float(w) / gc[k] - 1) < 1e-6, (k, float(w), gc[k])
    assert gc[120] > 1e9
