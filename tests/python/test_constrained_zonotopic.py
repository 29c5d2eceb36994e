"""The constrained-zonotope estimators CZN-A / CZN-B through Python and the C ABI (issue 21).

Expected values from outside: CORA's saved final hulls (../shared/benchmarks/
cora_linearSysDT_observe/*_cora_unittest.json, key golden_final_interval_hull, CORA v2026.0.1's
testLong_linearSysDT_observe_01_vehicle.m and test_linearSysDT_observe_02_2dim.m), CORA's rule
|a − b| <= 1e-6. Everything else is a property: equality with the exact consistent set without
reduction, containment of the exact hull and of the true state with reduction (random and vertex
disturbances), bit-for-bit continuation after save/restore."""
import pickle

import numpy as np
import pytest

import setbound as sb
import setbound.cora as cora
from setbound.benchmarks import load_cora
from setbound.constrained_zonotopic import ConstrainedZonotopicEstimator
from setbound.errors import DimensionError, InconsistentMeasurementError, InvalidArgumentError, NotFiniteError
from setbound.measurement import INCONSISTENT, USED
from setbound.sets import ConstrainedZonotope
from setbound.zonotopic import SegmentMinEstimator, exact_hull

from zono_examples import ex_le13, record
from cora_support import DATA, needs_data

CORA_TOL = 1e-6


def random_system(rng, nx):
    A = rng.standard_normal((nx, nx))
    A *= rng.uniform(0.5, 0.98) / max(abs(np.linalg.eigvals(A)))
    ny = int(rng.integers(1, nx + 1))
    C = rng.standard_normal((ny, nx))
    nw = nx
    E = np.hstack([0.1 * rng.standard_normal((nx, nw)), np.zeros((nx, ny))])
    F = np.hstack([np.zeros((ny, nw)), 0.1 * np.eye(ny)])
    return sb.LinearSystem(A, C, E=E, F=F)


@needs_data
@pytest.mark.parametrize("name", ["alamo2005_2d_cora_unittest", "vehicle2_cora_unittest"])
@pytest.mark.parametrize("alg", ["CZN-A", "CZN-B"])
def test_coras_saved_final_hulls(name, alg):
    b = load_cora(DATA / f"{name}.json")
    r = cora.observe(b, alg, convention="cora")
    lo, hi = b.golden[alg]
    err = max(np.abs(r.lower[-1] - lo).max(), np.abs(r.upper[-1] - hi).max())
    assert err < CORA_TOL, (alg, name, r.lower[-1], r.upper[-1])
    # and the set is guaranteed: it contains CORA's (exact up to CORA's rounding) hull
    assert np.all(r.lower[-1] <= lo + 1e-9) and np.all(r.upper[-1] >= hi - 1e-9)


def highs_exact_hull(s, ys, x0):
    """The interval hull of the states consistent with y_0..y_k, by scipy's HiGHS (an LP engine
    independent of the library): variables ξ_0 (x_0 = c_0 + G_0 ξ_0) and ω_0..ω_k, all in [−1, 1];
    x_j = A^j x_0 + Σ_{i<j} A^{j−1−i} E ω_i and y_j = C x_j + F ω_j for j <= k."""
    from scipy.optimize import linprog

    n, nw, m0 = s.nx, s.nw, x0.generators.shape[1]
    lo, hi = np.empty((len(ys), n)), np.empty((len(ys), n))
    for k in range(len(ys)):
        nv = m0 + (k + 1) * nw
        # x_j = M_j v + a_j (affine in the variables v = (ξ_0, ω_0..ω_k))
        M, a = np.zeros((n, nv)), x0.center.copy()
        M[:, :m0] = x0.generators
        rows, rhs = [], []
        for j in range(k + 1):
            Fj = np.zeros((s.ny, nv))
            Fj[:, m0 + j * nw:m0 + (j + 1) * nw] = s.F
            rows.append(s.C @ M + Fj)
            rhs.append(ys[j] - s.C @ a)
            if j < k:
                Ej = np.zeros((n, nv))
                Ej[:, m0 + j * nw:m0 + (j + 1) * nw] = s.E
                M, a = s.A @ M + Ej, s.A @ a
        Aeq, beq = np.vstack(rows), np.concatenate(rhs)
        for i in range(n):
            for sgn in (1.0, -1.0):
                r = linprog(-sgn * M[i], A_eq=Aeq, b_eq=beq, bounds=[(-1, 1)] * nv, method="highs",
                            options={"primal_feasibility_tolerance": 1e-10, "dual_feasibility_tolerance": 1e-10})
                assert r.status == 0, r.message
                # r.fun = min −sgn·M_i v: the bound is a_i − r.fun (upper) or a_i + r.fun (lower)
                if sgn > 0:
                    hi[k, i] = a[i] - r.fun
                else:
                    lo[k, i] = a[i] + r.fun
    return lo, hi


@pytest.mark.parametrize("seed", range(22))
def test_without_reduction_it_is_the_exact_consistent_set(seed):
    rng = np.random.default_rng(seed)
    if seed == 0:
        s = ex_le13()  # the zonotopic papers' example
    else:
        s = random_system(rng, int(rng.integers(2, 5)))
    x0 = sb.Box(-np.ones(s.nx), np.ones(s.nx))
    truth = rng.uniform(-0.9, 0.9, s.nx)
    xs, ys = record(s, 25 if seed == 0 else 15, rng, vertex=bool(seed % 2), x0=truth)
    Z0 = sb.sets.as_zonotope(x0)
    lo_h, hi_h = highs_exact_hull(s, ys, Z0)  # the exact hull by HiGHS, independent of the library
    # and the library's own reference (interior-point LPs over the whole record: accurate to about
    # 1e-7, and slow for 4 states, so on the papers' example only)
    ref = exact_hull(s, ys, x0=Z0) if seed == 0 else None
    for correction in ("CZN-A", "CZN-B"):
        t = ConstrainedZonotopicEstimator(s, x0, correction=correction, reduction="none").run(ys)
        scale = np.maximum(1.0, np.maximum(np.abs(lo_h), np.abs(hi_h)))
        np.testing.assert_array_less(np.abs(t.lower - lo_h) / scale, 1e-8)
        np.testing.assert_array_less(np.abs(t.upper - hi_h) / scale, 1e-8)
        if ref is not None:
            np.testing.assert_array_less(np.abs(t.lower - ref.lower) / scale, 1e-6)
            np.testing.assert_array_less(np.abs(t.upper - ref.upper) / scale, 1e-6)
        assert t.contains(xs).all()


@pytest.mark.parametrize("mode", [("CZN-A", "limits"), ("CZN-B", "limits"), ("CZN-A", "cora"), ("CZN-B", "cora")])
def test_reduced_sets_contain_the_exact_hull_and_the_truth(mode):
    correction, reduction = mode
    steps = 0
    for seed in range(4):
        rng = np.random.default_rng(1000 + seed)
        s = ex_le13() if seed == 0 else random_system(rng, int(rng.integers(2, 5)))
        x0 = sb.Box(-np.ones(s.nx), np.ones(s.nx))
        for vertex in (False, True):
            # Short runs against the exact hull (its LPs grow with the record) ...
            xs, ys = record(s, 30, rng, vertex=vertex, x0=rng.uniform(-0.9, 0.9, s.nx))
            ref = exact_hull(s, ys, x0=sb.sets.as_zonotope(x0))
            est = ConstrainedZonotopicEstimator(s, x0, correction=correction, reduction=reduction, order=3)
            t = est.run(ys)
            # the reference's interior-point LPs are accurate to about 1e-7 (see the test above)
            tol = 1e-7 * np.maximum(1.0, np.abs(ref.lower) + np.abs(ref.upper))
            assert np.all(t.lower <= ref.lower + tol) and np.all(t.upper >= ref.upper - tol)
            assert t.contains(xs).all()
            # ... and longer ones against the truth (>= 2 000 steps per mode in all). CORA's mode
            # never removes a constraint (its LPs grow with the record): many shorter runs there.
            runs, N = (1, 260) if reduction == "limits" else (6, 45)
            for _ in range(runs):
                xs, ys = record(s, N, rng, vertex=vertex, x0=rng.uniform(-0.9, 0.9, s.nx))
                t = est.run(ys, keep_sets=False)
                assert t.sets is None or not t.sets
                assert t.in_bounds(xs).all()
                steps += len(ys)
            if reduction == "limits":
                assert est.max_constraints == 4 * s.nx and est.max_generators == 24 * s.nx
    assert steps >= 2000


def test_bounded_mode_keeps_the_sizes_and_is_tighter_than_segment_minimisation():
    rng = np.random.default_rng(5)
    s = ex_le13()
    xs, ys = record(s, 200, rng, vertex=True, x0=(0.5, -0.5))
    est = ConstrainedZonotopicEstimator(s, sb.Box([-3, -3], [3, 3]))
    t = est.run(ys)
    assert max(S.nc for S in t.sets) <= 8 and max(S.ng for S in t.sets) <= 48
    z = SegmentMinEstimator(s, sb.Box([-3, -3], [3, 3])).run(ys)
    assert np.mean(t.upper - t.lower) < np.mean(z.upper - z.lower)
    assert t.contains(xs).all()


def test_missing_glitch_and_jointly_inconsistent_readings():
    s = ex_le13()
    rng = np.random.default_rng(3)
    xs, ys = record(s, 30, rng, vertex=False, x0=(0.2, 0.1))
    ys = ys.copy()
    ys[5, 0] = np.nan          # missing
    ys[9, 1] += 50.0           # a glitch: impossible alone
    est = ConstrainedZonotopicEstimator(s, sb.Box([-3, -3], [3, 3]))
    t = est.run(ys)
    assert t.status[9, 1] == INCONSISTENT and t.status[9, 0] == USED
    assert t.contains(xs).all()
    with pytest.raises(InconsistentMeasurementError, match="step 9"):
        ConstrainedZonotopicEstimator(s, sb.Box([-3, -3], [3, 3]), on_inconsistency="raise").run(ys)
    r = ConstrainedZonotopicEstimator(s, sb.Box([-3, -3], [3, 3]), on_inconsistency="reset",
                                      reset_set=sb.Box([-5, -5], [5, 5])).run(ys)
    assert r.resets[9] and r.contains(xs).all()
    # Jointly impossible: two outputs of one state each possible, together not (x known exactly,
    # readings pulled apart within each one's predicted range but inconsistent together).
    S2 = sb.LinearSystem([[0.5]], [[1.0], [1.0]], E=[[0.0, 0.0, 0.0]], F=[[0.0, 0.1, 0.0], [0.0, 0.0, 0.1]])
    e2 = ConstrainedZonotopicEstimator(S2, sb.Box([-1], [1]))
    e2.step([0.9, -0.9])
    chk = e2.last_check
    assert np.all(chk.status == INCONSISTENT) and np.all(np.isnan(chk.margin))


def test_save_restore_and_pickle_continue_bit_for_bit():
    s = ex_le13()
    rng = np.random.default_rng(11)
    _, ys = record(s, 40, rng, vertex=True)
    a = ConstrainedZonotopicEstimator(s, sb.Box([-2, -2], [2, 2]), correction="CZN-B")
    for y in ys[:20]:
        a.step(y)
    blob = a.save_state()
    b = ConstrainedZonotopicEstimator(s, sb.Box([-1, -1], [1, 1]), correction="CZN-B")  # another x0 is fine
    b.restore_state(blob)
    c = pickle.loads(pickle.dumps(a))
    for y in ys[20:]:
        Sa, Sb, Sc = a.step(y), b.step(y), c.step(y)
        for S in (Sb, Sc):
            np.testing.assert_array_equal(S.generators, Sa.generators)
            np.testing.assert_array_equal(S.A, Sa.A)
            np.testing.assert_array_equal(S.b, Sa.b)
    assert a.steps == b.steps == 40
    other = ConstrainedZonotopicEstimator(s, sb.Box([-2, -2], [2, 2]), correction="CZN-A")
    with pytest.raises(InvalidArgumentError, match="state"):
        other.restore_state(blob)
    bad = bytearray(blob)
    bad[-8:] = np.array([np.nan]).tobytes()
    with pytest.raises(InvalidArgumentError, match="state"):
        b.restore_state(bytes(bad))
    assert b.steps == 40  # unchanged


@needs_data
@pytest.mark.parametrize("name", ["pedestrian4", "vehicle6"])
def test_truth_of_coras_benchmarks_stays_inside(name):
    b = load_cora(DATA / f"{name}.json")
    t = ConstrainedZonotopicEstimator(b.system, b.x0).run(b.y, b.u, keep_sets=False)
    # The truth is given to 3 decimals (5e-4), and CORA's readings themselves leave the noise bound
    # (pedestrian4, step 217: |y_1 - C_1 x| = 0.10295 > 0.1; vehicle6: by up to 6.2e-3). A set that
    # uses such a reading exactly (the hull before the reduction does) may exclude the rounded truth
    # by that excess, no more.
    D = 0.0 if b.system.D is None or b.u is None else b.u @ np.asarray(b.system.D).T
    excess = np.max(np.abs(b.y - b.truth @ b.system.C.T - D) - np.abs(b.system.F).sum(axis=1), initial=0.0)
    assert t.in_bounds(b.truth, tol=5e-4 + max(excess, 0.0)).all()


def test_bad_input_is_named():
    s = ex_le13()
    x0 = sb.Box([-1, -1], [1, 1])
    with pytest.raises(InvalidArgumentError, match="correction"):
        ConstrainedZonotopicEstimator(s, x0, correction="CZN-C")
    with pytest.raises(InvalidArgumentError, match="reduction"):
        ConstrainedZonotopicEstimator(s, x0, reduction="some")
    with pytest.raises(InvalidArgumentError, match="order"):
        ConstrainedZonotopicEstimator(s, x0, reduction="cora", order=0.5)
    with pytest.raises(InvalidArgumentError, match="max_constraints"):
        ConstrainedZonotopicEstimator(s, x0, max_constraints=-3)
    with pytest.raises(InvalidArgumentError, match="max_generators"):
        ConstrainedZonotopicEstimator(s, x0, max_generators=2**40)
    with pytest.raises(InvalidArgumentError, match="max_generators: must be >= n_x"):
        ConstrainedZonotopicEstimator(s, x0, max_constraints=4, max_generators=3)
    with pytest.raises(DimensionError, match="x0"):
        ConstrainedZonotopicEstimator(s, sb.Box([-1], [1]))
    with pytest.raises(InvalidArgumentError, match="system"):
        ConstrainedZonotopicEstimator(sb.LinearSystem(sb.IntervalMatrix.from_mid_rad(s.A, 0.01 * np.ones((2, 2))),
                                                      s.C, E=s.E, F=s.F), x0)
    est = ConstrainedZonotopicEstimator(s, x0)
    with pytest.raises(DimensionError, match="y"):
        est.step([1.0, 2.0, 3.0])
    with pytest.raises(NotFiniteError, match="y"):
        est.step([np.inf, 0.0])
    assert est.steps == 0
    with pytest.raises(InvalidArgumentError, match="reset_set"):
        ConstrainedZonotopicEstimator(s, x0, reset_set=x0)


@pytest.mark.parametrize("correction", ["CZN-A", "CZN-B"])
def test_prediction_is_the_set_the_next_step_corrects(correction):
    # sb_czonotopic_prediction: the initial set before the first step; after k steps A X_{k-1} ⊕ E B
    # for x_k, whose exact intersection with the output set y_k − F B has the hull the run reports
    # for step k (taken before the reduction; CZN-B's strips are the same set, F diagonal per output).
    rng = np.random.default_rng(12)
    s = random_system(rng, 3)
    X0 = sb.Box([-1, -1, -1], [1, 1, 1])
    xs, ys = record(s, 15, rng, vertex=True, x0=(0.5, -0.5, 0.2))
    traj = ConstrainedZonotopicEstimator(s, X0, correction=correction).run(ys, keep_sets=False)
    est = ConstrainedZonotopicEstimator(s, X0, correction=correction)
    lo, hi = est.prediction.interval_hull()
    np.testing.assert_allclose(np.c_[lo, hi], np.c_[-np.ones(3), np.ones(3)], atol=1e-12)
    E = s.E[:, np.any(s.E != 0, axis=0)]
    V = sb.Zonotope(np.zeros(s.ny), s.F[:, np.any(s.F != 0, axis=0)])
    for k in range(1, len(ys)):
        X = est.step(ys[k - 1])
        P = est.prediction
        assert (P.n, est.steps) == (3, k)
        scale = 1.0 + np.abs(np.c_[traj.lower[k], traj.upper[k]]).max()
        np.testing.assert_allclose(np.c_[P.interval_hull()], np.c_[(s.A @ X + sb.Zonotope(np.zeros(3), E)).interval_hull()],
                                   atol=1e-9 * scale)
        corrected = P.intersect_output(s.C, ys[k], V)
        np.testing.assert_allclose(np.c_[corrected.interval_hull()], np.c_[traj.lower[k], traj.upper[k]],
                                   atol=1e-8 * scale)
        assert corrected.contains(xs[k][None, :]).all()


@pytest.mark.parametrize("reduction", ["limits", "none"])
def test_rounding_box_does_not_wrap_through_a_stable_A(reduction):
    # A stable A (spectral radius 0.95) whose |A| has row sums near 5: mapping the rounding box as a
    # box would grow it about 4x per step (1e+90 after 300 steps, seen 2026-11-27); it must stay at
    # the level of the rounding itself, and the hull must stay bounded.
    th = 1.0
    R = 0.95 * np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
    T = np.array([[1.0, 3.0], [0.0, 1.0]])
    A = T @ R @ np.linalg.inv(T)
    assert np.abs(A).sum(axis=1).max() > 3.0
    s = sb.LinearSystem(A, [[1.0, 0.0]], E=[[0.05, 0.0], [0.05, 0.0]], F=[[0.0, 0.1]])
    rng = np.random.default_rng(4)
    N = 300 if reduction == "limits" else 60
    xs, ys = record(s, N, rng, vertex=True, x0=(0.1, 0.2))
    t = ConstrainedZonotopicEstimator(s, sb.Box([-1, -1], [1, 1]), reduction=reduction).run(ys)
    assert t.contains(xs).all()
    assert max(S.rounding.max() for S in t.sets) < 1e-10
    assert np.all(np.isfinite(t.upper - t.lower))


def _skewed_system():
    # stable, but A = T R T⁻¹ with a skewed T: ‖|A|‖ > 1, where axis-aligned boxes wrap
    th = 1.0
    R = 0.95 * np.array([[np.cos(th), -np.sin(th)], [np.sin(th), np.cos(th)]])
    T = np.array([[1.0, 3.0], [0.0, 1.0]])
    return sb.LinearSystem(T @ R @ np.linalg.inv(T), [[1.0, 0.0]], E=[[0.05, 0.0], [0.05, 0.0]], F=[[0.0, 0.1]])


@pytest.fixture(scope="module")
def skewed_runs():
    """The skewed system over 150 steps (vertex disturbances): the truth, the exact hull (no
    reduction), segment minimisation and the bounded mode with its default (Girard) and with PCA."""
    s = _skewed_system()
    xs, ys = record(s, 150, np.random.default_rng(4), vertex=True, x0=(0.1, 0.2))
    X0 = sb.Box([-1, -1], [1, 1])
    runs = {"exact": ConstrainedZonotopicEstimator(s, X0, reduction="none").run(ys, keep_sets=False),
            "default": ConstrainedZonotopicEstimator(s, X0).run(ys, keep_sets=False),
            "pca": ConstrainedZonotopicEstimator(s, X0, technique="pca").run(ys, keep_sets=False),
            "segment_min": SegmentMinEstimator(s, X0).run(ys)}
    return xs, {k: np.mean((t.upper - t.lower)[1:], axis=0) for k, t in runs.items()}, runs


def test_bounded_mode_stays_guaranteed_on_a_skewed_system(skewed_runs):
    xs, mean, runs = skewed_runs
    for name in ("default", "pca", "exact"):
        assert runs[name].contains(xs).all(), name
    assert np.all(mean["exact"] <= mean["default"] + 1e-9)  # the exact hull is the tightest


def test_bounded_mode_is_tighter_than_segment_minimisation_on_a_skewed_system(skewed_runs):
    # The reduction guided by the hull LPs' multipliers (2026-11-28): 1.23x / 1.31x the exact hull
    # here (1.004x / 1.006x with the gain, below), where boxing by Girard's size criterion in the
    # lift wrapped to 3.1x in x_1 and lost to segment minimisation (0.29 / 0.16 mean widths).
    _, mean, _ = skewed_runs
    assert np.all(mean["default"] <= mean["segment_min"])
    assert np.all(mean["default"] <= 1.4 * mean["exact"])


@needs_data
@pytest.mark.parametrize("name", ["vehicle6", "vehicle2_cora_unittest"])
def test_bounded_mode_is_tighter_than_segment_minimisation_on_cora_records(name):
    # Issue 21: tighter than every zonotopic method. Before CZN-A's new rows were written with the
    # least-squares gain (2026-11-28), the bounded mode drifted on vehicle6: x6's width grew from
    # 5.8 (step 25) to 46 (step 325) while segment minimisation settles at 9.4, 2.07 times its
    # mean width over the record and 3.7 times over the last 50 steps; on vehicle2 it was 0.98.
    b = load_cora(DATA / f"{name}.json")
    cz = ConstrainedZonotopicEstimator(b.system, b.x0).run(b.y, b.u, keep_sets=False)
    seg = SegmentMinEstimator(b.system, b.x0, **b.estimator_options()).run(b.y, b.u)
    w_cz, w_seg = cz.upper - cz.lower, seg.upper - seg.lower
    assert np.all(w_cz.mean(axis=0) <= 0.95 * w_seg.mean(axis=0))
    tail = len(b.y) // 3  # no drift: the last third as well
    assert w_cz[-tail:].sum() <= 0.95 * w_seg[-tail:].sum()
    if b.truth is not None:
        assert cz.contains(b.truth, tol=5e-4).all()


def test_bounded_mode_meets_the_accuracy_target_on_a_skewed_system(skewed_runs):
    # Issue 21's target, mean width <= 1.05x the exact hull with the default limits (8 rows, 48
    # generators): 1.004x / 1.006x since CZN-A's new rows are written with the least-squares gain;
    # before (2026-11-28) 1.23x / 1.31x, an xfail.
    _, mean, _ = skewed_runs
    assert np.all(mean["default"] <= 1.05 * mean["exact"])


@needs_data
@pytest.mark.parametrize("name, steps, factor", [("vehicle2_cora_unittest", 100, 1.01), ("vehicle6", 100, 1.05)])
def test_default_limits_meet_the_accuracy_target_on_coras_records(name, steps, factor):
    # Issue 21's target (mean hull width <= 1.05x the exact consistent set's, default limits). Since
    # the reduction absorbs generators into a basis of the set's own columns instead of boxing them on
    # the axes (2026-11-29): vehicle2 1.002 (was 1.19), vehicle6 ~1.01 over 80-200 steps (was 1.335
    # over 80 steps, 1.46 over 200). pedestrian4 is not here: 1.12 (was 1.19), still above the target.
    b = load_cora(DATA / f"{name}.json")
    Y, U = b.y[:steps], b.u[:steps]
    exact = ConstrainedZonotopicEstimator(b.system, b.x0, reduction="none").run(Y, U, keep_sets=False)
    bounded = ConstrainedZonotopicEstimator(b.system, b.x0).run(Y, U, keep_sets=False)
    assert np.all(bounded.lower <= exact.lower + 1e-9) and np.all(bounded.upper >= exact.upper - 1e-9)
    assert np.mean(bounded.upper - bounded.lower) <= factor * np.mean(exact.upper - exact.lower)
