"""Saved states, pickling and deep copies of every estimator (docs/user_guide.md, "Saving and
restoring estimators"): a restored / unpickled / deep-copied estimator continues bit-for-bit
as the original; corrupted states and states of another design are refused with the estimator
unchanged; failed steps leave the state unchanged."""
import copy
import math
import pickle

import numpy as np
import pytest

import setbound as sb
from setbound import ellipsoidal as ell
from setbound import hinf, interval_observers as iobs, zonotopic as zono

from ell_examples import ex_me17, ex_me19, me19_inputs


def _wave(k, j):
    s = math.sin(1.3 * k + 0.7 * j + 0.1 * k * j)
    return (1.0 if s >= 0 else -1.0) if (k + j) % 5 == 0 else s


def _me17u(a_rad=0.0):
    A = np.array([[-0.8, 0.2], [-0.3, 0.1]])
    if a_rad:
        A = sb.IntervalMatrix(A - a_rad * np.eye(2), A + a_rad * np.eye(2))
    return sb.LinearSystem(A, [[-2.0, 1.0]], B=[[1.0], [0.5]], D=[[0.1]], E=[[-0.12, 0.0], [0.02, 0.0]],
                           F=[[0.0, 0.2]])


def _simulate(system, N):
    """Measurements and inputs of the true system (mid A) with deterministic disturbances."""
    A = np.asarray(system.A)
    x = np.zeros(system.nx)
    ys, us = [], []
    for k in range(N):
        w = np.array([_wave(k, j) for j in range(system.nw)])
        u = np.array([0.5 * math.cos(0.4 * k + j) for j in range(system.nu)])
        y = system.C @ x + system.F @ w + (system.D @ u if system.nu else 0.0)
        ys.append(y)
        us.append(u if system.nu else None)
        x = A @ x + system.E @ w + (system.B @ u if system.nu else 0.0)
    return ys, us


def _bits(values):
    return b"".join(np.ascontiguousarray(np.asarray(v, dtype=np.float64)).tobytes() for v in values)


class Case:
    """make() builds an estimator; step(est, i) does valid step i and returns its numbers;
    bad: functions (est, i) that must raise without changing the state."""

    def __init__(self, make, step, other=None, bad=()):
        self.make, self.step, self.other, self.bad = make, step, other, list(bad)


def _check(case: Case, k=4, N=5):
    a = case.make()
    for i in range(k):
        case.step(a, i)
    s = a.save_state()
    assert isinstance(s, bytes) and len(s) % 8 == 0
    pickled = pickle.dumps(a)
    twin = copy.deepcopy(a)
    ref = [_bits(case.step(a, i)) for i in range(k, k + N)]
    assert a.save_state() != s  # the state moved on

    # Fresh estimator of the same design, restored.
    b = case.make()
    b.restore_state(s)
    assert b.save_state() == s
    assert [_bits(case.step(b, i)) for i in range(k, k + N)] == ref
    # Unpickled and deep-copied estimators continue identically (and independently).
    c = pickle.loads(pickled)
    assert c.save_state() == s
    assert [_bits(case.step(c, i)) for i in range(k, k + N)] == ref
    assert twin.save_state() == s
    assert [_bits(case.step(twin, i)) for i in range(k, k + N)] == ref
    # Save → mutate → restore → continue.
    a.restore_state(s)
    assert [_bits(case.step(a, i)) for i in range(k, k + N)] == ref

    # Corrupted states: clear error naming the state, estimator unchanged.
    d = case.make()
    for i in range(k):
        case.step(d, i)
    before = d.save_state()
    vals = np.frombuffer(s, dtype="<f8")
    bad_states = {
        "truncated": s[:-8],
        "odd length": s[:-3],
        "empty": b"",
        "extra": s + np.zeros(1).tobytes(),
        "tag": np.concatenate([[vals[0] + 1], vals[1:]]).tobytes(),
        "version": np.concatenate([vals[:1], [7.0], vals[2:]]).tobytes(),
        "NaN": np.concatenate([vals[:-1], [np.nan]]).tobytes(),
        "fingerprint": np.concatenate([vals[:2], [vals[2] + 1], vals[3:]]).tobytes(),
    }
    if case.other is not None:
        bad_states["another design"] = case.other().save_state()
    for what, blob in bad_states.items():
        with pytest.raises(sb.InvalidArgumentError, match=r"^(.*: )?state"):
            d.restore_state(blob)
        assert d.save_state() == before, what
    with pytest.raises(sb.InvalidArgumentError, match="^state"):
        d.restore_state("not bytes")
    assert _bits(case.step(d, k)) == ref[0]

    # Failed steps leave the state unchanged; the next valid step is as if they never happened.
    e = case.make()
    for i in range(k):
        case.step(e, i)
    for bad in case.bad:
        before = e.save_state()
        with pytest.raises(sb.SetboundError):
            bad(e, k)
        assert e.save_state() == before, bad
    assert _bits(case.step(e, k)) == ref[0]


def _nan_first(v):
    v = np.array(v, dtype=float)
    v.flat[0] = np.nan
    return v


def _inf_first(v):
    v = np.array(v, dtype=float)
    v.flat[0] = np.inf
    return v


def _bad_yu(ys, us):
    # an infinite reading is an error for every estimator (NaN means "missing" where missing
    # readings are accepted)
    out = [lambda e, i: e.step(_inf_first(ys[i]), us[i]),
           lambda e, i: e.step(np.append(ys[i], 0.0), us[i])]
    if us[0] is not None:
        out.append(lambda e, i: e.step(ys[i], _nan_first(us[i])))
        out.append(lambda e, i: e.step(ys[i], np.zeros(len(us[i]) + 1)))
    return out


# ---- ellipsoidal ------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def me17u_designs():
    s = _me17u()
    return s, ell.design_offline(s, beta=0.7), ell.design_offline(s, beta=0.8)


def _ell_step(e, y, u):
    E = e.step(y, u)
    ls = e.last_step()
    return [E.P, E.center, [E.rho], ls["L"], [ls["beta"], float(ls["fallback"])]]


@pytest.mark.parametrize("kind", ["offline", "online", "scaled"])
def test_ellipsoidal_predictors(me17u_designs, kind):
    s, d1, d2 = me17u_designs
    ys, us = _simulate(s, 30)
    x0 = sb.Ellipsoid(np.eye(2), np.zeros(2), 4.0)

    def make(design=d1):
        if kind == "offline":
            return ell.OfflineEstimator(design, x0)
        return ell.OnlineEstimator(design, x0, scaling=(kind == "scaled"))

    _check(Case(make, lambda e, i: _ell_step(e, ys[i], us[i]), lambda: make(d2), _bad_yu(ys, us)), 6, 6)


def test_online_predictor_interval_a():
    s = _me17u(0.02)
    d1, d2 = ell.design_offline(s, beta=0.75), ell.design_offline(s, beta=0.85)
    ys, us = _simulate(s, 20)
    x0 = sb.Ellipsoid(np.eye(2), np.zeros(2), 4.0)
    _check(Case(lambda: ell.OnlineEstimator(d1, x0), lambda e, i: _ell_step(e, ys[i], us[i]),
                lambda: ell.OnlineEstimator(d2, x0), _bad_yu(ys, us)), 4, 5)


def test_improved_estimator(me17u_designs):
    s, d1, d2 = me17u_designs
    ys, us = _simulate(s, 20)
    x0 = sb.Ellipsoid(np.eye(2), np.zeros(2), 4.0)

    def step(e, i):
        E = e.step(ys[i], us[i])
        return [E.P, E.center, [E.rho], e.current.P]

    _check(Case(lambda: ell.ImprovedEstimator(d1, x0), step, lambda: ell.ImprovedEstimator(d2, x0),
                _bad_yu(ys, us)), 3, 4)
    # another correction option is another design
    _check(Case(lambda: ell.ImprovedEstimator(d1, x0, "ball_normalized", feedback="outer_bound"), step,
                lambda: ell.ImprovedEstimator(d1, x0, "fixed_shape", feedback="outer_bound")), 2, 3)


def test_descriptor_estimator():
    sys = ex_me19()
    d1, d2 = ell.design_offline(sys, beta=0.7), ell.design_offline(sys, beta=0.8)
    U = me19_inputs(20)
    Y = [np.array([math.sin(0.3 * k), 0.5 * math.cos(0.2 * k)]) for k in range(20)]
    us = list(U)
    x0 = sb.Ellipsoid(np.eye(3), np.zeros(3), 9.0)
    step = lambda e, i: _ell_step(e, Y[i], us[i])[:3]  # noqa: E731
    case = Case(lambda: ell.DescriptorEstimator(d1, x0), step, lambda: ell.DescriptorEstimator(d2, x0), _bad_yu(Y, us))
    _check(case, 3, 4)
    _check(case, 0, 3)  # saved before the first measurement


def test_kalman_filter():
    s = _me17u()
    ys, us = _simulate(s, 20)

    def step(e, i):
        m, G = e.step(ys[i], us[i])
        return [m, G]

    make = lambda w=1.0: ell.KalmanFilter(s, np.zeros(2), np.eye(2), w * np.eye(2))  # noqa: E731
    _check(Case(make, step, lambda: make(2.0), _bad_yu(ys, us)), 4, 5)
    # the Python-side mean/covariance follow the restored state
    a, b = make(), make()
    for i in range(3):
        a.step(ys[i], us[i])
    b.restore_state(a.save_state())
    assert np.array_equal(a.mean, b.mean) and np.array_equal(a.covariance, b.covariance)


# ---- zonotopic ---------------------------------------------------------------------------------

@pytest.mark.parametrize("a_rad", [0.0, 0.02])
@pytest.mark.parametrize("rule", ["segment", "volume", "pradius"])
def test_zonotopic_estimators(rule, a_rad):
    s = _me17u(a_rad)
    ys, us = _simulate(s, 30)
    x0 = sb.Zonotope(np.zeros(2), 2.0 * np.eye(2))

    def step(e, i):
        Z = e.step(ys[i], us[i])
        return [Z.center, Z.generators]

    if rule == "segment":
        make = lambda m=4: zono.SegmentMinEstimator(s, x0, max_generators=m, reduction="pca")  # noqa: E731
    elif rule == "volume":
        make = lambda m=4: zono.VolumeMinEstimator(s, x0, max_generators=m, reduction="girard")  # noqa: E731
    else:
        if a_rad:
            pytest.skip("the P-radius design needs a known A")
        design = zono.design_pradius(s)
        make = lambda m=4: zono.PRadiusEstimator(design, x0, max_generators=m)  # noqa: E731
    _check(Case(make, step, lambda: make(5), _bad_yu(ys, us)), 6, 6)


def test_zonotopic_reduction_is_part_of_the_state():
    s = _me17u()
    ys, us = _simulate(s, 20)
    x0 = sb.Zonotope(np.zeros(2), np.eye(2))
    a = zono.SegmentMinEstimator(s, x0, max_generators=3, reduction="pca")
    b = zono.SegmentMinEstimator(s, x0, max_generators=3)  # combastel
    for i in range(5):
        a.step(ys[i], us[i])
    b.restore_state(a.save_state())
    assert b.reduction == "pca"
    for i in range(5, 12):
        za, zb = a.step(ys[i], us[i]), b.step(ys[i], us[i])
        assert np.array_equal(za.generators, zb.generators) and np.array_equal(za.center, zb.center)


# ---- thesis observers ------------------------------------------------------------------------

def _ch2_plant(a12=0.2):
    return sb.Plant([[0.2, a12], [0.0, 0.5]], [[1.0, 0.0]], B=[[1.0], [1.0]], Fd=[[0.0], [0.1]], Z=[[0.1]])


def _plant_data(p, N):
    x = np.zeros(p.nx)
    ys, us = [], []
    for k in range(N):
        d = np.array([_wave(k, j) for j in range(p.nd)])
        v = np.array([_wave(k + 3, j) for j in range(p.nv)])
        u = np.array([0.5 * math.cos(0.3 * k + j) for j in range(p.nu)])
        ys.append(p.C @ x + p.Z @ v)
        us.append(u if p.nu else None)
        x = p.A @ x + p.F @ d + (p.B @ u if p.nu else 0.0)
    return ys, us


def _box_step(e, y, u, **kw):
    b = e.step(y, u, **kw)
    return [b.lo, b.hi]


def test_ellipsoidal_sm_observer():
    p1, p2 = _ch2_plant(), _ch2_plant(0.25)
    d1 = hinf.design_ellipsoidal_sm_observer(p1, np.ones(2))
    d2 = hinf.design_ellipsoidal_sm_observer(p2, np.ones(2))
    ys, us = _plant_data(p1, 20)

    def step(e, i):
        b = e.step(ys[i], us[i])
        return [b.lo, b.hi, e.center, [e.mu]]

    _check(Case(lambda: hinf.EllipsoidalSMObserver(d1, np.zeros(2), 2.0), step,
                lambda: hinf.EllipsoidalSMObserver(d2, np.zeros(2), 2.0), _bad_yu(ys, us)), 4, 6)
    # the Python-side centre, box and mu follow the restored state
    a, b = hinf.EllipsoidalSMObserver(d1, np.zeros(2), 2.0), hinf.EllipsoidalSMObserver(d1, np.zeros(2), 2.0)
    for i in range(3):
        a.step(ys[i], us[i])
    b.restore_state(a.save_state())
    assert np.array_equal(a.center, b.center) and a.mu == b.mu and np.array_equal(a.box.lo, b.box.lo)
    assert b.steps == 3


def _lpv_plant(z):
    A = [[[1, r], [0, 1]] for r in (0.05, 0.1)]
    B = [[[0], [r]] for r in (0.05, 0.1)]
    return hinf.LpvPlant(A, [[1.0, 0.0]], [[0.05], [0.1]], B=B, Fd=B, Z=[[z]])


def test_lpv_ellipsoidal_sm_observer():
    d1 = hinf.design_ellipsoidal_sm_observer_lpv(_lpv_plant(0.01), np.ones(2))
    d2 = hinf.design_ellipsoidal_sm_observer_lpv(_lpv_plant(0.02), np.ones(2))
    ys = [np.array([math.sin(0.2 * k)]) for k in range(20)]
    us = [np.array([0.3 * math.cos(0.1 * k)]) for k in range(20)]
    rho = [np.array([0.075 + 0.025 * math.sin(0.7 * k)]) for k in range(20)]

    def step(e, i):
        b = e.step(ys[i], us[i], rho[i])
        return [b.lo, b.hi, e.center, [e.mu]]

    bad = _bad_yu(ys, us) + [lambda e, i: e.step(ys[i], us[i], [np.nan]),
                             lambda e, i: e.step(ys[i], us[i], [5.0])]
    _check(Case(lambda: hinf.LPVEllipsoidalSMObserver(d1, np.zeros(2), 2.0), step,
                lambda: hinf.LPVEllipsoidalSMObserver(d2, np.zeros(2), 2.0), bad), 4, 6)


def _ex451():
    return sb.Plant([[-1.1267, -1.3503], [1.1095, 1.2673]], [[-0.2512, 0.1723]],
                    B=[[0.0951, -0.1977], [-0.2894, 0.1099]], Fd=[[-0.1606], [0.1254]], Z=[[-0.1542]])


@pytest.mark.parametrize("variant", ["tight", "wrapped"])
def test_interval_luenberger_observer(variant):
    p = _ex451()
    ys, us = _plant_data(p, 20)
    d = sb.Box([-0.5], [1.0])  # not centred: the centre offset is part of the state

    def make(r=3.0):
        return iobs.IntervalLuenbergerObserver(p, sb.Box(-r * np.ones(2), r * np.ones(2)), np.zeros(2), d,
                                               sb.Box([-1.0], [1.0]), variant=variant)

    _check(Case(make, lambda e, i: _box_step(e, ys[i], us[i]), lambda: make(4.0), _bad_yu(ys, us)), 4, 6)


def test_run_restarts_from_the_recorded_state_without_designing_again(monkeypatch):
    # An interval observer built without L designs its H∞ gain inside the library (seconds on
    # tank30). run() restarts from the state recorded at construction: building a twin (the old
    # reset) would design again on every run. Here building another one fails, so a run that
    # tried would raise.
    p = _ex451()
    ys, us = _plant_data(p, 12)
    obs = iobs.IntervalLuenbergerObserver(p, sb.Box(-3 * np.ones(2), 3 * np.ones(2)))
    x0_state = obs.save_state()

    def no_second_design(*args, **kwargs):
        raise AssertionError("the observer was built again")

    monkeypatch.setattr(iobs.IntervalLuenbergerObserver, "__init__", no_second_design)
    first = obs.run(ys, us)
    again = obs.run(ys, us)
    obs.reset()
    assert obs.save_state() == x0_state
    np.testing.assert_array_equal(first.lower, again.lower)
    np.testing.assert_array_equal(first.upper, again.upper)


def _h_box(x_box, k):  # module level: picklable
    r = 0.2 + 0.15 * math.sin(0.9 * k)
    c = 0.1 * math.cos(k)
    return sb.Box((c - r) * np.ones(2), (c + r) * np.ones(2))


def _nl_plant():
    return sb.Plant([[0.3, -0.7], [0.6, -0.5]], [[1.0, 0.0]], B=np.eye(2), Fd=np.eye(2), Z=[[1.0]])


def test_nonlinear_interval_observer_window():
    p = _nl_plant()
    ys = [np.array([math.sin(0.4 * k)]) for k in range(30)]
    us = [np.array([math.sin(0.1 * k), math.cos(0.2 * k)]) for k in range(30)]

    def make(window=4, h=_h_box):
        return iobs.NonlinearIntervalObserver(p, sb.Box(-2 * np.ones(2), 2 * np.ones(2)), np.zeros(2),
                                              sb.Box([-0.1], [0.1]), h, window=window)

    bad = _bad_yu(ys, us) + [lambda e, i: e.step(ys[i], us[i], h=sb.Box(-np.ones(3), np.ones(3))),
                             lambda e, i: e.step(ys[i], us[i], h=sb.Box([-np.inf, 0.0], [0.0, 0.0]))]
    # window 4, saved after 9 steps: the window has wrapped and radii have left it
    _check(Case(make, lambda e, i: _box_step(e, ys[i], us[i]), lambda: make(5), bad), 9, 8)


def test_nonlinear_observer_with_a_lambda_does_not_pickle():
    obs = iobs.NonlinearIntervalObserver(_nl_plant(), sb.Box(-2 * np.ones(2), 2 * np.ones(2)), np.zeros(2),
                                         sb.Box([-0.1], [0.1]), lambda xb, k: _h_box(xb, k), window=4)
    with pytest.raises(sb.InvalidArgumentError, match="^h: the nonlinearity callable cannot be pickled"):
        pickle.dumps(obs)
    # save_state still works, and the state restores into an observer given the callable again
    obs.step([0.1], [0.0, 0.0])
    other = iobs.NonlinearIntervalObserver(_nl_plant(), sb.Box(-2 * np.ones(2), 2 * np.ones(2)), np.zeros(2),
                                           sb.Box([-0.1], [0.1]), _h_box, window=4)
    other.restore_state(obs.save_state())
    assert np.array_equal(other.current().lo, obs.current().lo)
    assert other.steps == 1


def test_interval_invariant_observer():
    p = _ex451()
    ys, us = _plant_data(p, 20)

    def make(r=3.0):
        design = iobs.offline_error_sequence(p, sb.Box(-r * np.ones(2), r * np.ones(2)), np.zeros(2),
                                             sb.Box([-1.0], [1.0]), sb.Box([-1.0], [1.0]))
        return iobs.IntervalInvariantObserver(design)

    _check(Case(make, lambda e, i: _box_step(e, ys[i], us[i]), lambda: make(4.0), _bad_yu(ys, us)), 4, 6)


def test_state_of_another_kind_is_refused_by_name():
    s = _me17u()
    kf = ell.KalmanFilter(s, np.zeros(2), np.eye(2))
    z = zono.SegmentMinEstimator(s, sb.Zonotope(np.zeros(2), np.eye(2)))
    with pytest.raises(sb.InvalidArgumentError, match="state: .*KalmanFilter.*expected a saved ZonotopicEstimator"):
        z.restore_state(kf.save_state())


def test_designs_and_systems_pickle():
    s = _me17u()
    s2 = pickle.loads(pickle.dumps(s))
    assert np.array_equal(s2.A, s.A) and np.array_equal(s2.D, s.D)
    d = ell.design_offline(s, beta=0.7)
    d2 = pickle.loads(pickle.dumps(d))
    assert np.array_equal(d2.P, d.P) and np.array_equal(d2.L, d.L) and d2.sigma == d.sigma
    assert copy.deepcopy(d) is d  # immutable
