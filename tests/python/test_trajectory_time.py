"""Time-aware, unambiguous results (issue 24 point 5): every trajectory row carries its time
(``t``: the step, ``k·dt`` of the system, ``t=`` of run, or the time of a python-control
``TimeResponseData``), ``to_pandas`` is indexed by time with 0-based state names, ``plot`` marks
guaranteed methods, ``contains`` tests the set itself (``in_bounds`` the interval bounds), and
plots name the states 0-based as Python and the command line do."""
import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest

import setbound
from setbound import LinearSystem, Trajectory
from setbound.ellipsoidal import ImprovedEstimator, KalmanFilter, OnlineEstimator, design_offline
from setbound.sets import Ellipsoid, Zonotope
from setbound.simulation import simulate
from setbound.zonotopic import SegmentMinEstimator
from zono_examples import ex_le13 as le13




X0 = Zonotope([0, 0], 3 * np.eye(2))


def test_rows_carry_their_time():
    sim = simulate(le13(), X0, 20, rng=1)
    traj = SegmentMinEstimator(le13(), X0).run(sim.y)
    np.testing.assert_array_equal(traj.t, np.arange(20.0))  # no sampling time: the step
    np.testing.assert_array_equal(traj.k, np.arange(20))
    traj = SegmentMinEstimator(le13(dt=0.05), X0).run(sim.y)
    np.testing.assert_allclose(traj.t, 0.05 * np.arange(20))
    t = 10.0 + 0.5 * np.arange(20)
    traj = SegmentMinEstimator(le13(), X0).run(sim.y, t=t)
    np.testing.assert_array_equal(traj.t, t)
    est = SegmentMinEstimator(le13(), X0)
    est.step(sim.y[0])
    before = est.save_state()
    with pytest.raises(setbound.DimensionError, match="^t: expected 20 time values"):
        est.run(sim.y, t=t[:5])
    assert est.save_state() == before  # a failed run leaves the estimator as it was
    # predictors and filters alike: row k is about x_k, at the same time
    d = design_offline(le13(dt=0.05))
    pred = OnlineEstimator(d, Ellipsoid(np.eye(2), [0, 0], 18.0)).run(sim.y)
    filt = ImprovedEstimator(d, Ellipsoid(np.eye(2), [0, 0], 18.0)).run(sim.y)
    np.testing.assert_array_equal(pred.t, filt.t)
    assert pred.contains(sim.x).all() and filt.contains(sim.x).all()


def test_time_response_data_is_a_measurement_source():
    control = pytest.importorskip("control")
    s = le13()
    ss = control.ss(s.A, np.hstack([s.E]), s.C, s.F, 0.1, inputs=["w[0]", "w[1]", "w[2]"])
    rng = np.random.default_rng(3)
    W = rng.uniform(-1, 1, (3, 40))
    resp = control.forced_response(ss, T=0.1 * np.arange(40), U=W, X0=[0.5, -0.5])
    est = SegmentMinEstimator(ss, X0)
    traj = est.run(resp)
    np.testing.assert_allclose(traj.t, 0.1 * np.arange(40))
    assert traj.contains(np.asarray(resp.states).T).all()
    same = est.run(np.asarray(resp.outputs).T)
    np.testing.assert_array_equal(same.lower, traj.lower)
    # an estimator made from a StateSpace pickles (its construction arguments are recorded)
    import pickle

    clone = pickle.loads(pickle.dumps(est))
    np.testing.assert_array_equal(clone.run(resp).upper, traj.upper)


def test_to_pandas_is_indexed_by_time_with_named_states():
    pd = pytest.importorskip("pandas")
    sim = simulate(le13(dt=0.2), X0, 15, rng=2)
    y = sim.y.copy()
    y[7, 0] += 5.0
    traj = SegmentMinEstimator(le13(dt=0.2), X0).run(y)
    df = traj.to_pandas()
    assert isinstance(df, pd.DataFrame) and df.index.name == "t"
    np.testing.assert_allclose(df.index.values, 0.2 * np.arange(15))
    assert list(df.columns[:4]) == ["k", "x0_lower", "x0_center", "x0_upper"]
    np.testing.assert_array_equal(df["x1_upper"].values, traj.upper[:, 1])
    assert df["flagged"].tolist() == [k == 7 for k in range(15)]
    assert df.attrs["guaranteed"] is True
    named = traj.to_pandas(names=["position", "speed"])
    assert "speed_lower" in named.columns
    with pytest.raises(ValueError, match="names"):
        traj.to_pandas(names=["a"])
    kf = KalmanFilter(le13(), [0, 0], np.eye(2)).run(sim.y).to_pandas()
    assert kf.attrs["guaranteed"] is False and "flagged" not in kf.columns


def test_contains_tests_the_set_and_in_bounds_the_box():
    # the corner of the bounding box of a disc is in the box, not in the disc
    E = Ellipsoid(np.eye(2), [0.0, 0.0], 1.0)
    lo, hi = E.bounding_box()
    traj = Trajectory(np.zeros((1, 2)), lo[None, :], hi[None, :], [E])
    corner = np.array([[0.95, 0.95]])
    assert traj.in_bounds(corner).tolist() == [True]
    assert traj.contains(corner).tolist() == [False]
    assert traj.contains(np.array([[0.5, 0.5]])).tolist() == [True]
    boxes = Trajectory(np.zeros((1, 2)), lo[None, :], hi[None, :], [])
    assert boxes.contains(corner).tolist() == [True]  # no sets: the bounds


def test_plot_marks_guaranteed_methods_and_states_are_zero_based():
    sim = simulate(le13(dt=0.1), X0, 30, rng=4)
    traj = SegmentMinEstimator(le13(dt=0.1), X0).run(sim.y)
    fig = traj.plot(x_true=sim.x, name="segment")
    ax = fig.axes[0]
    assert ax.get_xlabel() == "t" and ax.get_ylabel() == "$x_{0}$"
    labels = [t.get_text() for a in fig.axes for leg in ([a.get_legend()] if a.get_legend() else [])
              for t in leg.get_texts()]
    assert any("segment (guaranteed)" in s for s in labels)
    kf = KalmanFilter(le13(), [0, 0], np.eye(2)).run(sim.y)
    fig = kf.plot()
    labels = [t.get_text() for a in fig.axes for leg in ([a.get_legend()] if a.get_legend() else [])
              for t in leg.get_texts()]
    assert any("not guaranteed" in s for s in labels)
    assert fig.axes[0].get_xlabel() == "t"


def test_projection_plot_draws_a_strip_only_over_sets_that_used_it():
    from setbound.plotting import plot_projections

    s = le13()
    sim = simulate(s, X0, 12, rng=6)
    y = sim.y.copy()
    y[5, 1] = np.nan  # output 1 missing at step 5
    d = design_offline(s)
    filt = SegmentMinEstimator(s, X0).run(y)
    pred = OnlineEstimator(d, Ellipsoid(np.eye(2), [0, 0], 18.0)).run(y)
    assert filt.filter is True and pred.filter is False

    def strip_labels(fig):
        return [t.get_text() for a in fig.axes if a.get_legend() for t in a.get_legend().get_texts()
                if "strips" in t.get_text()] + [c.get_label() for a in fig.axes for c in a.collections
                                                 if "strips" in str(c.get_label())]

    both = plot_projections({"segment": filt, "online": pred}, steps=[5], system=s, y=y, x_true=sim.x)
    assert any("used by segment)" in lab for lab in strip_labels(both))
    only_pred = plot_projections({"online": pred}, steps=[5], system=s, y=y, x_true=sim.x)
    assert not strip_labels(only_pred)  # the predictor's set of x_5 has not used y_5


def test_a_step_result_says_which_time_it_bounds():
    """``current_k``/``current_t``: the set the last ``step()`` returned bounds x_k with k the
    trajectory row holding the same set, for predictors, filters and the thesis observers."""
    from setbound import interval_observers
    from setbound.interval import Box

    s = le13(dt=0.05)
    sim = simulate(s, X0, 12, rng=2)
    d = design_offline(s)
    E0 = Ellipsoid(np.eye(2), [0, 0], 18.0)
    for est, is_filter in [(OnlineEstimator(d, E0), False), (ImprovedEstimator(d, E0), True),
                           (SegmentMinEstimator(s, X0), True), (KalmanFilter(s, [0, 0], np.eye(2)), True),
                           (interval_observers.IntervalLuenbergerObserver(s, Box([-3, -3], [3, 3])), False)]:
        traj = est.run(sim.y)
        est.reset()
        assert est.current_k == (None if is_filter else 0)
        for j in range(8):
            out = est.step(sim.y[j])
            k = est.current_k
            assert k == (j if is_filter else j + 1), type(est).__name__
            assert est.current_t == pytest.approx(0.05 * k)
            if isinstance(out, tuple):  # Kalman: (mean, covariance)
                np.testing.assert_allclose(out[0], traj.center[k])
            elif isinstance(out, Box):
                np.testing.assert_array_equal(out.lo, traj.lower[k])
            else:  # the step's set is the trajectory's row k
                np.testing.assert_allclose(out.center, traj.sets[k].center)
