"""Interoperability: python-control StateSpace in (setbound.system.from_statespace) and pandas out
(Trajectory.to_dataframe)."""
import sys

import numpy as np
import pytest

from setbound import InvalidArgumentError, LinearSystem, Trajectory, Zonotope
from setbound.simulation import simulate
from setbound.system import from_statespace
from setbound.zonotopic import SegmentMinEstimator

try:
    import control
except ImportError as exc:  # pragma: no cover - control is in the test extra
    control = None
    CONTROL_REASON = f"python-control cannot be imported: {exc}"
else:
    CONTROL_REASON = ""

needs_control = pytest.mark.skipif(control is None, reason=CONTROL_REASON)

A = np.array([[0.0, -0.5], [1.0, 1.0]])
Fw = np.array([[-0.12], [0.02]])
C = np.array([[-2.0, 1.0], [1.0, 1.0]])


@needs_control
def test_from_statespace_disturbance_inputs_and_noise():
    ss = control.ss(A, np.hstack([Fw, [[1.0], [0.0]]]), C, np.zeros((2, 2)), dt=0.1)
    s = from_statespace(ss, disturbance_inputs=[0], output_noise=[0.2, 0.3])
    assert isinstance(s, LinearSystem)
    np.testing.assert_array_equal(s.A, A)
    np.testing.assert_array_equal(s.C, C)
    np.testing.assert_array_equal(s.E, np.hstack([Fw, np.zeros((2, 2))]))
    np.testing.assert_array_equal(s.F, np.hstack([np.zeros((2, 1)), np.diag([0.2, 0.3])]))
    np.testing.assert_array_equal(s.B, [[1.0], [0.0]])  # input 1 stays a known input
    assert s.nu == 1 and s.nw == 3


@needs_control
def test_from_statespace_explicit_E_F_and_estimation_is_guaranteed():
    ss = control.ss(A, np.zeros((2, 1)), C, np.zeros((2, 1)), True)  # dt=True: discrete, unspecified period
    s = from_statespace(ss, E=np.hstack([Fw, np.zeros((2, 2))]), F=np.hstack([np.zeros((2, 1)), 0.2 * np.eye(2)]))
    assert s.nu == 1
    x0 = Zonotope([0.0, 0.0], 3 * np.eye(2))
    u = np.zeros((30, 1))
    for kind in ("uniform", "vertex"):
        sim = simulate(s, x0, 30, disturbance=kind, rng=4, u=u)
        traj = SegmentMinEstimator(s, x0).run(sim.y, u)
        assert traj.contains(sim.x).all()


@needs_control
def test_from_statespace_rejects_continuous_time_and_missing_disturbances():
    with pytest.raises(InvalidArgumentError, match="ss: must be a discrete-time system"):
        from_statespace(control.ss(A, Fw, C, 0), disturbance_inputs=[0])
    with pytest.raises(InvalidArgumentError, match="ss: no disturbance given"):
        from_statespace(control.ss(A, Fw, C, 0, dt=1))
    with pytest.raises(InvalidArgumentError, match="disturbance_inputs: input index 3"):
        from_statespace(control.ss(A, Fw, C, 0, dt=1), disturbance_inputs=[3])
    with pytest.raises(InvalidArgumentError, match="ss: expected a control.StateSpace"):
        from_statespace(object(), output_noise=0.1)


def _traj():
    rng = np.random.default_rng(1)
    c = rng.normal(size=(5, 2))
    sets = [Zonotope(ck, 0.5 * np.eye(2)) for ck in c]
    return Trajectory(c, c - 0.5, c + 0.5, sets)


def test_to_dataframe():
    pd = pytest.importorskip("pandas")
    t = _traj()
    df = t.to_dataframe(t=np.linspace(0, 1, 5))
    assert isinstance(df, pd.DataFrame)
    assert list(df.columns) == ["t", "center0", "center1", "lower0", "lower1", "upper0", "upper1", "volume", "radius"]
    assert df.index.name == "k" and len(df) == 5
    np.testing.assert_array_equal(df[["upper0", "upper1"]].to_numpy(), t.upper)
    np.testing.assert_allclose(df["volume"], 1.0)  # a 1 x 1 square
    assert df.attrs["guaranteed"] is True
    with pytest.raises(ValueError, match="t: expected 5"):
        t.to_dataframe(t=[0, 1])


def test_to_dataframe_without_pandas(monkeypatch):
    monkeypatch.setitem(sys.modules, "pandas", None)  # makes `import pandas` fail
    with pytest.raises(ImportError, match="needs pandas.*pip install pandas"):
        _traj().to_dataframe()


@needs_control
def test_statespace_accepted_where_a_system_is_expected():
    """A discrete-time StateSpace whose disturbance inputs are labelled 'w…' goes straight into the
    estimators, designs and the simulator (setbound.system.as_system), with the same results as
    the converted LinearSystem; without such labels the error says what to do."""
    from setbound import ellipsoidal, zonotopic

    Bfull = np.hstack([[[1.0], [0.0]], Fw, np.zeros((2, 2))])
    Dfull = np.hstack([np.zeros((2, 2)), 0.2 * np.eye(2)])
    ss = control.ss(A, Bfull, C, Dfull, dt=1.0, inputs=["u", "w[0]", "w[1]", "w[2]"])
    ref = from_statespace(ss, disturbance_inputs=[1, 2, 3])
    sim = simulate(ss, Zonotope(np.zeros(2), 2 * np.eye(2)), 30, rng=5, u=np.ones((30, 1)))
    sim_ref = simulate(ref, Zonotope(np.zeros(2), 2 * np.eye(2)), 30, rng=5, u=np.ones((30, 1)))
    np.testing.assert_array_equal(sim.y, sim_ref.y)
    t = SegmentMinEstimator(ss, Zonotope(np.zeros(2), 2 * np.eye(2))).run(sim.y, sim.u)
    t_ref = SegmentMinEstimator(ref, Zonotope(np.zeros(2), 2 * np.eye(2))).run(sim.y, sim.u)
    np.testing.assert_array_equal(t.lower, t_ref.lower)
    assert np.all(t.contains(sim.x, 1e-9))
    d = ellipsoidal.design_offline(ss, beta=0.5)
    np.testing.assert_allclose(d.P, ellipsoidal.design_offline(ref, beta=0.5).P)
    assert zonotopic.design_pradius(ss, approach=2) is not None
    with pytest.raises(InvalidArgumentError, match="labelled 'w"):
        ellipsoidal.design_offline(control.ss(A, Fw, C, 0, dt=1.0))
