"""Missing and impossible readings in the thesis observers through Python (issue 24; C++
``thesis/reading_screen.hpp``): the H∞ set-membership observer, the interval Luenberger,
nonlinear and invariant observers, all built from the same ``LinearSystem`` (EX-LE13). NaN
outputs and ``step(None)`` keep the truth inside, an impossible reading is flagged, raised or
reset, runs are repeatable and the policy pickles; job files take ``on_inconsistency``."""
import pickle

import numpy as np
import pytest

from setbound import Box, InconsistentMeasurementError, Plant, hinf
from setbound import interval_observers as io
from setbound.measurement import INCONSISTENT, MISSING, USED, MeasurementCheck
from setbound.zonotopic import exact_hull
from zono_examples import LE13_JOB_SYSTEM, ex_le13 as le13, record

KINDS = ["sm", "luenberger", "nonlinear", "invariant"]
X0 = Box([-3.0, -3.0], [3.0, 3.0])
_CACHE = {}


def make(kind, **kw):
    s = le13()
    if kind == "sm":
        if "sm" not in _CACHE:
            _CACHE["sm"] = hinf.design_ellipsoidal_sm_observer(s)
        return hinf.EllipsoidalSMObserver(_CACHE["sm"], X0, **kw)
    if kind == "luenberger":
        return io.IntervalLuenbergerObserver(s, X0, **kw)
    if kind == "nonlinear":
        # x⁺ = A x + h with [h] = E[ω_0] (F = I): the same plant in the nonlinear observer's form
        p = Plant(s.A, s.C, Fd=np.eye(2), Z=s.F[:, 1:])
        return io.NonlinearIntervalObserver(p, X0, [0.0, 0.0], h=Box([-0.12, -0.02], [0.12, 0.02]), **kw)
    if "inv" not in _CACHE:
        _CACHE["inv"] = io.offline_error_sequence(s, X0, [0.0, 0.0])
    return io.IntervalInvariantObserver(_CACHE["inv"], **kw)


def contains(traj, xs, rows=None):
    """Every (selected) row's box holds the true state (the interval observers' set is the box; the
    H∞ observer's box is the hull of its ellipsoid)."""
    rows = range(len(xs)) if rows is None else rows
    return all(np.all(traj.lower[k] <= xs[k] + 1e-9) and np.all(xs[k] <= traj.upper[k] + 1e-9) for k in rows)


def missing_record(vertex):
    """50 steps with 20 % of the readings missing and the exact hull of the data left (one LP
    run per disturbance kind, shared by the observers)."""
    if ("rec", vertex) not in _CACHE:
        rng = np.random.default_rng(40 + vertex)
        s = le13()
        xs, ys = record(s, 50, rng, vertex)
        mask = rng.random(ys.shape) < 0.2
        ys[mask] = np.nan
        _CACHE["rec", vertex] = (xs, ys, mask, exact_hull(s, ys, x0=X0))
    return _CACHE["rec", vertex]


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("vertex", [False, True])
def test_twenty_percent_missing_keeps_the_truth_and_contains_the_exact_hull(kind, vertex):
    xs, ys, mask, hull = missing_record(vertex)  # hull: the exact consistent set of the data used
    traj = make(kind).run(ys)
    assert contains(traj, xs)
    np.testing.assert_array_equal(traj.status == MISSING, mask)
    np.testing.assert_array_equal(traj.status == USED, ~mask)
    assert not traj.flagged.any()
    assert np.all(traj.lower <= hull.lower + 1e-6) and np.all(traj.upper >= hull.upper - 1e-6)


@pytest.mark.parametrize("kind", KINDS)
def test_step_none_is_an_interval_prediction(kind):
    est = make(kind)
    b = est.step(None)
    chk = est.last_check
    assert isinstance(chk, MeasurementCheck) and chk.missing.all() and not chk.flagged
    s = le13()
    # every point of [x_0] (the interval observers' set) maps inside; for the H∞ observer its
    # ellipsoid's image (a point of it: the centre) does
    pts = [np.array([a, c]) for a in (-3, 3) for c in (-3, 3)] if kind != "sm" else [np.zeros(2)]
    for x in pts:
        for d in (-1.0, 1.0):
            xn = s.A @ x + s.E[:, 0] * d
            assert b.contains(xn)


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("glitch", [5.0, 1e3, 1e12])
def test_a_glitch_is_flagged_and_the_truth_stays_inside(kind, glitch, rng):
    s = le13()
    xs, ys = record(s, 50, rng, vertex=True)
    ys[20, 0] += glitch
    traj = make(kind).run(ys)
    assert np.flatnonzero(traj.flagged).tolist() == [20]
    assert traj.status[20].tolist() == [INCONSISTENT, USED]
    assert traj.margin[20, 0] > 0
    assert contains(traj, xs)
    assert np.all(traj.lower <= traj.upper)


@pytest.mark.parametrize("kind", KINDS)
def test_raise_names_the_step_and_leaves_the_observer_unchanged(kind, rng):
    s = le13()
    xs, ys = record(s, 30, rng, vertex=False)
    ys[12, 1] -= 50
    est = make(kind, on_inconsistency="raise")
    for k in range(12):
        est.step(ys[k])
    before = est.save_state()
    with pytest.raises(InconsistentMeasurementError, match=r"step 12: output 1: the reading"):
        est.step(ys[12])
    assert est.save_state() == before
    with pytest.raises(InconsistentMeasurementError):
        est.run(ys)


@pytest.mark.parametrize("kind", KINDS)
def test_reset_restarts_from_the_reset_set_and_pickles(kind, rng):
    # the state jumps before step 15 (a violation of the model): "flag" loses the truth, "reset"
    # restarts from the wide set with that step's readings and holds the truth afterwards
    s = le13()
    xs, ys = record(s, 40, rng, vertex=True, jump=(15, np.array([6.0, -6.0])))
    flagged = make(kind).run(ys)
    assert flagged.flagged[15]
    assert not contains(flagged, xs)
    wide = Box([-20.0, -20.0], [20.0, 20.0])
    est = make(kind, on_inconsistency="reset", reset_set=wide)
    traj = est.run(ys)
    assert np.flatnonzero(traj.resets).tolist() == [15]
    assert contains(traj, xs, rows=[k for k in range(40) if k != 15])  # x_15 jumped out of every prediction
    clone = pickle.loads(pickle.dumps(est))
    assert clone.on_inconsistency == "reset"
    np.testing.assert_array_equal(clone.run(ys).lower, traj.lower)


@pytest.mark.parametrize("kind", KINDS)
def test_run_twice_gives_the_same_result_and_states_restore_after_a_restart(kind, rng):
    s = le13()
    xs, ys = record(s, 40, rng, vertex=False)
    ys[5, 0] = np.nan
    ys[6, :] = np.nan
    est = make(kind)
    a, b = est.run(ys), est.run(ys)
    np.testing.assert_array_equal(a.lower, b.lower)
    np.testing.assert_array_equal(a.upper, b.upper)
    est.reset()
    for k in range(7):
        est.step(ys[k])
    state = est.save_state()
    other = make(kind)
    other.restore_state(state)
    for k in range(7, 40):
        np.testing.assert_array_equal(est.step(ys[k]).lo, other.step(ys[k]).lo)


def test_policy_options_are_refused_by_name():
    with pytest.raises(ValueError, match="^on_inconsistency"):
        make("luenberger", on_inconsistency="ignore")
    with pytest.raises(ValueError, match="^reset_set"):
        make("sm", reset_set=X0)  # only with on_inconsistency="reset"
    with pytest.raises(ValueError, match="^reset_set"):
        make("invariant", on_inconsistency="reset", reset_set=Box([-1.0], [1.0]))
    est = make("nonlinear")
    with pytest.raises(ValueError, match="inf"):
        est.step([np.inf, 0.0])


JOB = LE13_JOB_SYSTEM + """
[initial]
center = [0, 0]
generators = [[3, 0], [0, 3]]

[simulation]
horizon = 80
seed = 24
disturbance = "uniform"

[[fault]]
kind = "sensor_bias"
output = 0
start = 40
magnitude = 3.0

[[estimator]]
method = "interval_luenberger"

[[estimator]]
method = "interval_invariant"
on_inconsistency = "reset"

[[estimator]]
method = "ellipsoidal_sm"
on_inconsistency = "flag"
"""


def test_job_file_runs_the_thesis_observers_on_a_faulty_sensor(tmp_path):
    """A sensor bias of 15 noise bounds from step 40: each thesis observer raises its first alarm
    at or after the fault, none before (their readings are tested as in every other family)."""
    from setbound import config

    (tmp_path / "job.toml").write_text(JOB)
    job = config.load(tmp_path / "job.toml")
    results = config.run(job, keep_going=True)
    assert len(results) == 3
    for r in results:
        assert r.ok, r.error
        flagged = np.flatnonzero(r.trajectory.flagged)
        assert flagged.size and flagged[0] >= 40, (r.name, flagged)
    bad = JOB.replace('on_inconsistency = "flag"', 'on_inconsistency = "ignore"')
    (tmp_path / "bad.toml").write_text(bad)
    with pytest.raises(config.ConfigError, match="on_inconsistency"):
        config.load(tmp_path / "bad.toml")
