"""One system model, any initial set (issue 24 point 4): the thesis designs and observers take
the library's LinearSystem (and give the same numbers as with the equivalent Plant), systems that
cannot be converted are refused with the reason, Plant's state-disturbance matrix cannot be
mistaken for LinearSystem's F, every family takes a box, a zonotope or an ellipsoid as its initial
set (a guaranteed enclosure), and so do simulate and job files; a bad reading in row 20 is
reported as row 20."""
import numpy as np
import pytest

import setbound
from setbound import Box, LinearSystem, Plant, ellipsoidal, hinf, interval_observers, zonotopic
from setbound.measurement import MISSING
from setbound.plant import as_plant
from setbound.sets import Ellipsoid, Zonotope, as_box, as_ellipsoid, as_zonotope
from setbound.simulation import simulate
from zono_examples import LE13_JOB_SYSTEM, ex_le13 as le13




def test_thesis_functions_take_a_linear_system_with_the_plants_numbers():
    s = le13()
    p = Plant.from_linear_system(s)
    assert p.nd == 1 and p.nv == 2 and np.array_equal(p.Fd, [[-0.12], [0.02]])
    np.testing.assert_array_equal(as_plant(s).Z, p.Z)
    g1, g2 = hinf.hinf_observer_gain(s), hinf.hinf_observer_gain(p)
    np.testing.assert_array_equal(g1.L, g2.L)
    assert g1.gamma == g2.gamma
    d1 = hinf.design_ellipsoidal_sm_observer(s)
    d2 = hinf.design_ellipsoidal_sm_observer(p, np.ones(3))
    np.testing.assert_array_equal(d1.L, d2.L)
    np.testing.assert_array_equal(d1.P, d2.P)
    sim = simulate(s, Box([-3, -3], [3, 3]), 40, rng=5)
    a = interval_observers.IntervalLuenbergerObserver(s, Box([-3, -3], [3, 3])).run(sim.y)
    b = interval_observers.IntervalLuenbergerObserver(p, Box([-3, -3], [3, 3]), [0.0, 0.0],
                                                      (-np.ones(1), np.ones(1)), (-np.ones(2), np.ones(2))).run(sim.y)
    np.testing.assert_array_equal(a.lower, b.lower)
    np.testing.assert_array_equal(a.upper, b.upper)
    assert a.contains(sim.x).all()
    o = hinf.EllipsoidalSMObserver(d1, Box([-3, -3], [3, 3])).run(sim.y)
    assert o.contains(sim.x).all()


def test_unconvertible_systems_and_confusable_names_are_refused_with_the_reason():
    shared = LinearSystem([[0.5, 0.0], [0.0, 0.5]], [[1.0, 0.0]], E=[[0.1], [0.0]], F=[[0.1]])
    with pytest.raises(setbound.DimensionError, match="plant: cannot use this LinearSystem .* drive both"):
        hinf.hinf_observer_gain(shared)
    with pytest.raises(setbound.DimensionError, match="plant: .*D must be zero"):
        interval_observers.IntervalLuenbergerObserver(
            LinearSystem([[0.5]], [[1.0]], B=[[1.0]], D=[[1.0]], E=[[0.1, 0]], F=[[0, 0.1]]), Box([-1], [1]))
    with pytest.raises(setbound.InvalidArgumentError, match="^F: a Plant's state-disturbance matrix is passed as Fd"):
        Plant([[0.5, 0.0], [0.0, 0.5]], [[1.0, 0.0]], F=[[0.1], [0.0]], Z=[[0.1]])
    with pytest.raises(setbound.InvalidArgumentError, match="F: .*Fd"):
        hinf.LpvPlant([np.eye(2)], [[1.0, 0.0]], [[0.0]], F=[np.eye(2)], Z=[[0.1]])
    with pytest.raises(setbound.InvalidArgumentError, match="plant: expected a setbound.Plant, a setbound.LinearSystem"):
        interval_observers.IntervalLuenbergerObserver("A", Box([-1], [1]))
    with pytest.raises(setbound.InvalidArgumentError, match="mu0"):
        hinf.EllipsoidalSMObserver(hinf.design_ellipsoidal_sm_observer(le13()), [0.0, 0.0])


@pytest.mark.parametrize("kind", ["box", "zonotope", "ellipsoid"])
def test_every_family_takes_any_initial_set(kind):
    s = le13()
    X = {"box": Box([-2, -1], [2, 1]), "zonotope": Zonotope([0, 0], [[2, 0.5], [0, 1]]),
         "ellipsoid": Ellipsoid(np.eye(2), [0, 0], 4.0)}[kind]
    sim = simulate(s, X, 50, rng=2, disturbance="vertex")
    d = ellipsoidal.design_offline(s)
    runs = [zonotopic.SegmentMinEstimator(s, X).run(sim.y),
            zonotopic.VolumeMinEstimator(s, X).run(sim.y),
            ellipsoidal.OnlineEstimator(d, X).run(sim.y),
            ellipsoidal.ImprovedEstimator(d, X).run(sim.y),
            interval_observers.IntervalLuenbergerObserver(s, X).run(sim.y),
            hinf.EllipsoidalSMObserver(hinf.design_ellipsoidal_sm_observer(s), X).run(sim.y)]
    for traj in runs:
        assert traj.contains(sim.x).all()


def test_conversions_are_guaranteed_enclosures():
    rng = np.random.default_rng(0)
    B = Box([-2.0, 0.5, -1.0], [1.0, 0.5, 3.0])  # one flat coordinate
    E = as_ellipsoid(B)
    corners = np.array([[a, b, c] for a in (B.lo[0], B.hi[0]) for b in (B.lo[1], B.hi[1])
                        for c in (B.lo[2], B.hi[2])])
    assert E.contains(corners).all()
    Z = Zonotope([0.0, 1.0], rng.normal(size=(2, 5)))
    EZ = as_ellipsoid(Z)
    pts = Z.center + (Z.generators @ rng.choice([-1.0, 1.0], size=(5, 200))).T
    assert EZ.contains(pts).all()
    El = Ellipsoid([[2.0, 0.5], [0.5, 1.0]], [1.0, -1.0], 3.0)
    ZE, BE = as_zonotope(El), as_box(El)
    d = rng.normal(size=(200, 2))
    L = np.linalg.cholesky(El.P)
    boundary = El.center + np.sqrt(El.rho) * np.linalg.solve(L.T, (d / np.linalg.norm(d, axis=1)[:, None]).T).T
    assert ZE.contains(boundary * (1 - 1e-12) + El.center * 1e-12).all()
    assert all(BE.contains(p) for p in boundary * (1 - 1e-12) + El.center * 1e-12)
    assert as_zonotope(Z) is Z and as_ellipsoid(El) is El
    with pytest.raises(setbound.InvalidArgumentError, match="x0: expected a setbound.Box, Zonotope, ConstrainedZonotope or Ellipsoid"):
        as_zonotope([0, 1])


def test_simulate_and_job_files_take_a_box(tmp_path):
    from setbound import config

    s = le13()
    sim = simulate(s, Box([-1, -1], [1, 1]), 10, rng=1)
    assert np.all(np.abs(sim.x[0]) <= 1)
    corner = simulate(s, Box([-1, -1], [1, 1]), 3, rng=1, disturbance="vertex")
    assert np.all(np.abs(corner.x[0]) == 1)  # a vertex start: a corner of the box
    (tmp_path / "job.toml").write_text(LE13_JOB_SYSTEM + """
[initial]
lower = [-2, -2]
upper = [2, 2]
[simulation]
horizon = 30
[[estimator]]
method = "segment_min"
[[estimator]]
method = "improved"
[[estimator]]
method = "kalman"
""")
    job = config.load(tmp_path / "job.toml")
    for r in config.run(job):
        assert r.ok and r.contained in (True, None)


def test_an_infinite_reading_is_reported_with_its_row():
    s = le13()
    sim = simulate(s, Box([-1, -1], [1, 1]), 30, rng=1)
    y = sim.y.copy()
    y[20, 1] = np.inf
    for est in (zonotopic.SegmentMinEstimator(s, Box([-3, -3], [3, 3])),
                ellipsoidal.OfflineEstimator(ellipsoidal.design_offline(s), Box([-3, -3], [3, 3])),
                interval_observers.IntervalLuenbergerObserver(s, Box([-3, -3], [3, 3]))):
        with pytest.raises(setbound.NotFiniteError, match="y: row 20, output 1 is inf"):
            est.run(y)
    y[20, 1] = np.nan  # a missing reading: accepted, and the row says so
    traj = interval_observers.IntervalLuenbergerObserver(s, Box([-3, -3], [3, 3])).run(y)
    assert traj.status[20, 1] == MISSING and traj.contains(sim.x).all()
