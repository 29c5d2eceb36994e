"""Missing and impossible readings through Python (issue 24, setbound.measurement), for the
zonotopic family (segment minimisation, volume minimisation, P-radius; the observers of CORA's
catalogue: Bravo, Wang, Combastel, fixed strip weights, fixed propagation gain) and the ellipsoidal
family (offline, online, scaled predictors, the improved filter; Kalman): NaN outputs and
``step(None)`` are skipped with the truth kept inside, an impossible reading is never used and
is handled by ``on_inconsistency`` ("flag", "raise", "reset"), ``run()`` starts from the initial
set, and bad options are refused by name."""
import pickle

import numpy as np
import pytest

import setbound
from setbound import InconsistentMeasurementError, LinearSystem
from setbound.measurement import INCONSISTENT, MISSING, USED, MeasurementCheck
from setbound.ellipsoidal import (DescriptorEstimator, ImprovedEstimator, KalmanFilter, OfflineEstimator,
                                  OnlineEstimator, design_offline)
from setbound.sets import Ellipsoid, Zonotope
from setbound.zonotopic import (BravoEstimator, CombastelObserver, PRadiusEstimator, PropagationObserver,
                                SegmentMinEstimator, StripGainEstimator, VolumeMinEstimator, WangEstimator,
                                design_pradius, exact_hull)
from zono_examples import LE13_JOB_SYSTEM, ex_le13 as le13, record


X0 = Zonotope([0, 0], 3 * np.eye(2))
E0 = Ellipsoid(np.eye(2), [0, 0], 18.0)  # the ball around the box X0: contains it
_DESIGNS = {}


def ell_design(s):
    key = id(s)
    if key not in _DESIGNS:
        _DESIGNS[key] = (s, design_offline(s))
    return _DESIGNS[key][1]


def make(kind, s, **kw):
    if kind == "segment":
        return SegmentMinEstimator(s, X0, **kw)
    if kind == "volume":
        return VolumeMinEstimator(s, X0, **kw)
    if kind == "pradius":
        return PRadiusEstimator(design_pradius(s, approach=2), X0, **kw)
    observers = {"bravo": BravoEstimator, "wang": WangEstimator, "combastel": CombastelObserver}
    if kind in observers:
        return observers[kind](s, X0, **kw)
    if kind in ("strip_gain", "propagation"):
        K = s.C.T @ np.linalg.inv(s.C @ s.C.T + np.eye(s.ny))
        if kind == "strip_gain":
            return StripGainEstimator(s, X0, K, all_strips=False, **kw)
        return PropagationObserver(s, X0, 0.5 * s.A @ K, **kw)
    if "reset_set" in kw and isinstance(kw["reset_set"], Zonotope):
        Z = kw["reset_set"]
        kw["reset_set"] = Ellipsoid(np.eye(2), Z.center, float(np.sum(np.abs(Z.generators)) ** 2))
    d = ell_design(s)
    if kind == "offline":
        return OfflineEstimator(d, E0, **kw)
    if kind == "online":
        return OnlineEstimator(d, E0, **kw)
    if kind == "scaled":
        return OnlineEstimator(d, E0, scaling=True, **kw)
    return ImprovedEstimator(d, E0, **kw)


ZONOTOPIC = ["segment", "volume", "pradius", "bravo", "wang", "combastel", "strip_gain", "propagation"]
ELLIPSOIDAL = ["offline", "online", "scaled", "improved"]
KINDS = ZONOTOPIC + ELLIPSOIDAL


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("vertex", [False, True])
def test_twenty_percent_missing_keeps_the_truth_and_contains_the_exact_hull(kind, vertex, rng):
    s = le13()
    xs, ys = record(s, 80, rng, vertex)
    mask = rng.random(ys.shape) < 0.2
    ys[mask] = np.nan
    traj = make(kind, s).run(ys)
    assert all(Z.contains(x, 1e-9) for Z, x in zip(traj.sets, xs))
    np.testing.assert_array_equal(traj.status == MISSING, mask)
    np.testing.assert_array_equal(traj.status == USED, ~mask)
    assert not traj.flagged.any()
    assert np.isnan(traj.margin[mask]).all() and (traj.margin[~mask] <= 0).all()
    hull = exact_hull(s, ys, x0=X0)  # the exact hull of the data actually used
    assert np.all(traj.lower <= hull.lower + 1e-6) and np.all(traj.upper >= hull.upper - 1e-6)


def test_step_none_is_a_prediction(rng):
    s = le13()
    est = SegmentMinEstimator(s, X0)
    Z = est.step(None)
    np.testing.assert_allclose(Z.center, [0, 0])
    np.testing.assert_allclose(np.abs(Z.generators).sum(axis=1), [3, 3])  # x_0's prior, unchanged
    chk = est.last_check
    assert isinstance(chk, MeasurementCheck)
    assert chk.missing.all() and not chk.flagged and np.isnan(chk.margin).all()


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("glitch", [5.0, 1e3, 1e12])
def test_a_glitch_is_flagged_and_the_truth_stays_inside(kind, glitch, rng):
    s = le13()
    xs, ys = record(s, 50, rng, vertex=True)
    ys[20, 0] += glitch
    traj = make(kind, s).run(ys)
    assert np.flatnonzero(traj.flagged).tolist() == [20]
    assert traj.status[20].tolist() == [INCONSISTENT, USED]
    assert traj.margin[20, 0] > 0
    assert all(Z.contains(x, 1e-9) for Z, x in zip(traj.sets, xs))
    assert np.all(traj.lower <= traj.upper)


@pytest.mark.parametrize("kind", ["segment", "online", "improved", "wang", "propagation"])
def test_raise_names_the_step_and_leaves_the_estimator_unchanged(kind, rng):
    s = le13()
    xs, ys = record(s, 30, rng, vertex=False)
    ys[12, 1] -= 50
    est = make(kind, s, on_inconsistency="raise")
    for k in range(12):
        est.step(ys[k])
    before = est.save_state()
    with pytest.raises(InconsistentMeasurementError, match=r"step 12: output 1: the reading"):
        est.step(ys[12])
    assert est.save_state() == before
    with pytest.raises(InconsistentMeasurementError):
        est.run(ys)


@pytest.mark.parametrize("kind", ["segment", "improved"])
def test_reset_restarts_from_the_reset_set(kind, rng):
    # The model is violated (the state jumps at step 15): the prediction no longer holds the
    # state, the readings are impossible for it. "flag" loses the truth; "reset" restarts from
    # the wide set, uses the readings of that step, and holds the truth from then on.
    s = le13()
    xs, ys = record(s, 40, rng, vertex=True, jump=(15, np.array([6.0, -6.0])))
    flagged = make(kind, s).run(ys)
    assert flagged.flagged[15] and not flagged.sets[15].contains(xs[15])
    wide = Zonotope([0, 0], 20 * np.eye(2))
    est = make(kind, s, on_inconsistency="reset", reset_set=wide)
    traj = est.run(ys)
    assert np.flatnonzero(traj.resets).tolist() == [15]
    assert traj.flagged[15]
    assert all(Z.contains(x, 1e-9) for Z, x in zip(traj.sets, xs))
    # the policy survives pickling (the construction arguments are recorded)
    clone = pickle.loads(pickle.dumps(est))
    assert clone.on_inconsistency == "reset"
    np.testing.assert_array_equal(clone.run(ys).lower, traj.lower)


@pytest.mark.parametrize("kind", ["segment", "online", "improved"])
def test_run_twice_gives_the_same_result_and_reset_restarts(kind, rng):
    s = le13()
    xs, ys = record(s, 40, rng, vertex=False)
    ys[5, 0] = np.nan
    est = make(kind, s)
    a, b = est.run(ys), est.run(ys)
    np.testing.assert_array_equal(a.lower, b.lower)
    np.testing.assert_array_equal(a.upper, b.upper)
    est.reset()
    first = est.step(ys[0])
    row = 0 if kind in ZONOTOPIC or kind == "improved" else 1  # a predictor's step gives x_1
    np.testing.assert_array_equal(first.center, a.sets[row].center)


def test_ellipsoidal_options_are_refused_by_name():
    s = le13()
    d = ell_design(s)
    with pytest.raises(setbound.InvalidArgumentError, match="^on_inconsistency"):
        OnlineEstimator(d, E0, on_inconsistency="ignore")
    with pytest.raises(setbound.InvalidArgumentError, match="^reset_set"):
        ImprovedEstimator(d, E0, reset_set=E0)
    with pytest.raises(setbound.InvalidArgumentError, match="^reset_set: expected a setbound.Box, Zonotope, ConstrainedZonotope or Ellipsoid"):
        OfflineEstimator(d, E0, on_inconsistency="reset", reset_set=[0.0, 0.0])
    with pytest.raises(setbound.DimensionError, match="^reset_set"):
        OfflineEstimator(d, E0, on_inconsistency="reset", reset_set=Ellipsoid(np.eye(3), [0, 0, 0], 1.0))
    with pytest.raises(setbound.NotFiniteError, match="y: entry 0 is inf"):
        OfflineEstimator(d, E0).step([np.inf, 0.0])


def test_kalman_filter_corrects_with_the_outputs_present(rng):
    s = le13()
    xs, ys = record(s, 30, rng, vertex=False)
    ys[rng.random(ys.shape) < 0.2] = np.nan
    kf = KalmanFilter(s, [0.0, 0.0], np.eye(2))
    traj = kf.run(ys)
    assert np.isfinite(traj.center).all()
    kf.reset()
    m, G = kf.step(None)  # nothing measured: the prior, unchanged
    np.testing.assert_array_equal(m, [0.0, 0.0])
    np.testing.assert_array_equal(G, np.eye(2))


def test_descriptor_estimator_refuses_missing_readings_and_says_why():
    Ed = np.array([[1.0, 0.0], [0.0, 0.0]])
    ds = setbound.DescriptorSystem(Ed, [[0.5, 0.1], [0.2, -1.0]], [[0.0, 1.0]], D=[[0.1], [0.0]], F=[[0.1]])
    est = DescriptorEstimator(design_offline(ds), Ellipsoid(np.eye(2), [0, 0], 9.0))
    with pytest.raises(setbound.NotFiniteError, match="row 1, output 0 is NaN .*DescriptorEstimator needs every output"):
        est.run(np.array([[0.1], [np.nan]]))


def test_bad_options_and_readings_are_refused_by_name():
    s = le13()
    with pytest.raises(setbound.InvalidArgumentError, match="^on_inconsistency"):
        SegmentMinEstimator(s, X0, on_inconsistency="ignore")
    with pytest.raises(setbound.InvalidArgumentError, match="^reset_set"):
        SegmentMinEstimator(s, X0, reset_set=X0)  # only with "reset"
    with pytest.raises(setbound.DimensionError, match="^reset_set"):
        SegmentMinEstimator(s, X0, on_inconsistency="reset", reset_set=Zonotope([0, 0, 0], np.eye(3)))
    with pytest.raises(setbound.InvalidArgumentError, match="reset_set"):
        SegmentMinEstimator(s, X0, on_inconsistency="reset", reset_set=Zonotope([0, 0], np.ones((2, 500))))
    est = SegmentMinEstimator(s, X0)
    with pytest.raises(setbound.NotFiniteError, match="y: entry 1 is inf"):
        est.step([0.0, np.inf])


def test_exact_hull_skips_missing_outputs_and_refuses_infinity(rng):
    s = le13()
    xs, ys = record(s, 12, rng, vertex=False)
    full = exact_hull(s, ys, x0=X0)
    ys[5:, 1] = np.nan
    part = exact_hull(s, ys, x0=X0)
    assert np.all(part.lower <= full.lower + 1e-6) and np.all(part.upper >= full.upper - 1e-6)
    assert np.all(part.lower <= xs + 1e-6) and np.all(xs <= part.upper + 1e-6)
    ys[3, 0] = np.inf
    with pytest.raises(setbound.NotFiniteError, match="y: row 3 has an infinite entry"):
        exact_hull(s, ys, x0=X0)


JOB = LE13_JOB_SYSTEM + """
[initial]
center = [0, 0]
generators = [[3, 0], [0, 3]]
[data]
file = "run.csv"
[[estimator]]
method = "segment_min"
[[estimator]]
name = "strict"
method = "segment_min"
on_inconsistency = "raise"
[[estimator]]
method = "offline"
"""


def test_job_file_with_missing_cells_and_a_glitch(tmp_path, rng):
    """A CSV with empty cells and a glitch: the zonotopic and the ellipsoidal method skip both and
    keep the truth, the "raise" one stops with the step named."""
    from setbound import config
    from setbound.report import format_table, summary_rows

    s = le13()
    xs, ys = record(s, 30, rng, vertex=True)
    ys[12, 0] += 4.0
    lines = ["y0,y1,x0,x1"]
    for k in range(30):
        cells = [repr(float(v)) for v in ys[k]] + [repr(float(v)) for v in xs[k]]
        if k in (5, 6):
            cells[1] = ""  # not measured
        if k == 7:
            cells[0] = "nan"
        lines.append(",".join(cells))
    (tmp_path / "run.csv").write_text("\n".join(lines) + "\n")
    (tmp_path / "job.toml").write_text(JOB)
    job = config.load(tmp_path / "job.toml")
    assert np.isnan(job.y[5, 1]) and np.isnan(job.y[7, 0])
    zono, strict, offline = config.run(job, keep_going=True)
    assert zono.ok and zono.contained
    assert np.flatnonzero(zono.trajectory.flagged).tolist() == [12]
    assert not strict.ok and "step 12: output 0" in strict.error
    assert offline.ok and offline.contained
    assert np.flatnonzero(offline.trajectory.flagged).tolist() == [12]
    assert offline.trajectory.status[5, 1] == MISSING
    rows = summary_rows(job, [zono, strict, offline])
    assert rows[0]["flagged_steps"] == 1 and rows[0]["first_flagged_step"] == 12
    assert "at 1 step (first: step 12)" in format_table(rows)
    # an infinite reading, or a missing input or state, is refused with the file, row and column
    (tmp_path / "run.csv").write_text("y0,y1,x0,x1\n0,inf,0,0\n")
    with pytest.raises(config.ConfigError, match=r"run\.csv, row 2, column y1: not a finite number"):
        config.load(tmp_path / "job.toml")
    (tmp_path / "run.csv").write_text("y0,y1,x0,x1\n0,1,,0\n")
    with pytest.raises(config.ConfigError, match=r"run\.csv, row 2, column x0: .* is not a number"):
        config.load(tmp_path / "job.toml")
