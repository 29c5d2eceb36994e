"""Short guarantee campaign (docs/reliability.md): every guaranteed estimator on random systems
(n_x up to 8, stable, unstable and ill-conditioned, uniform and vertex disturbances), the true
state checked against the returned set at every step. `make campaign` runs the long version."""
import math

import numpy as np
import pytest

from setbound import campaign
from setbound.sets import Ellipsoid

# steps per estimator in CI (several hundred, n_x <= 3, cases of at most 150 steps, so that the
# whole file stays well under a minute; `make campaign` runs >= 100 000 steps with n_x <= 8)
CI_STEPS = 800


@pytest.fixture(scope="module")
def short_campaign():
    return campaign.run_campaign(steps=CI_STEPS, processes=2, seed0=0, max_nx=3, max_steps=150, time_limit=1.5)


@pytest.mark.parametrize("name", list(campaign.ESTIMATORS))
def test_no_containment_violation(short_campaign, name):
    s = short_campaign[name]
    assert not s["violations"], "containment violated: " + "; ".join(
        f"seed {v['seed']} step {v['step']} excess {v['excess']:.3e} ({v['reproduce']})" for v in s["violations"][:5])
    assert s["steps"] > 0, f"{name}: no step ran ({s['reasons']})"
    assert s["max_excess"] <= 0.0
    # fault-free data: an impossible reading reported by an estimator would be a false alarm
    assert s["false_alarms"] == 0
    assert s["undecided"] == 0  # every checked step was decided (parallelotope_excess)


def test_the_checks_detect_a_point_outside():
    # Positive controls: each check reports a point just outside its set, and accepts one just inside.
    P, c, rho = np.diag([4.0, 1.0]), np.array([1.0, -2.0]), 0.25
    z = np.zeros(2)
    inside, outside = c + np.array([0.25 * (1 - 1e-6), 0.0]), c + np.array([0.25 * (1 + 1e-6), 0.0])
    assert campaign.ellipsoid_excess(P, c, rho, inside, z) <= 0
    assert campaign.ellipsoid_excess(P, c, rho, outside, z) > 0
    assert Ellipsoid(P, c, rho).contains(inside)
    assert campaign.box_excess([0, 0], [1, 2], [1 + 1e-6, 1], z) > 0
    assert campaign.box_excess([0, 0], [1, 2], [1 - 1e-6, 1], z) <= 0
    G = np.array([[1.0, 1.0, 0.5], [0.0, 1.0, -0.5]])
    # a vertex of the zonotope and a point just beyond it along the same direction
    v = G @ np.array([1.0, 1.0, -1.0])
    assert campaign.zonotope_excess(z, G, v * (1 - 1e-6), z) <= 0
    assert campaign.zonotope_excess(z, G, v * (1 + 1e-6), z) > 0
    # the simulation-error allowance widens the set by exactly δ
    assert campaign.box_excess([0, 0], [1, 1], [1.5, 0.5], np.array([0.6, 0])) <= 0


def test_a_failed_zonotope_lp_is_decided_by_the_facets_or_left_undecided(monkeypatch):
    # A linprog that fails must not count as a violation: the exact facet test decides when it can
    # run, else the step is undecided (NaN), never a violation.
    import scipy.optimize

    class Failed:
        status, x = 4, None

    monkeypatch.setattr(scipy.optimize, "linprog", lambda *a, **k: Failed())
    G = np.array([[1.0, 1.0, 0.5], [0.0, 1.0, -0.5]])
    z = np.zeros(2)
    v = G @ np.array([1.0, 1.0, -1.0])
    far = 0.98 * v  # inside the zonotope, but its least-squares ξ leaves the unit box
    assert np.max(np.abs(np.linalg.lstsq(G, far, rcond=None)[0])) > 1
    assert campaign.zonotope_excess(z, G, far, z) <= 0  # decided by the facets
    assert campaign.zonotope_excess(z, G, v * (1 + 1e-6), z) > 0  # outside: still a violation
    monkeypatch.setattr(campaign.math, "comb", lambda *a: 10**9)  # facet test too large to run
    assert math.isnan(campaign.zonotope_excess(z, G, far, z))


def test_box_check_with_overflowed_or_nan_bounds():
    # A bound that overflowed to ±inf contains everything on its side (found by the campaign: the
    # LPV observer's box of a diverging case; the old check computed NaN and passed silently).
    z = np.zeros(2)
    inf = np.inf
    assert campaign.box_excess([-inf, 0], [inf, 1], [1e300, 0.5], z) <= 0
    assert campaign.box_excess([-inf, 0], [inf, 1], [1e300, 1 + 1e-6], z) > 0  # the finite row still counts
    assert campaign.box_excess([0, 0], [inf, 1], [-1e-3, 0.5], z) > 0  # below a finite lower end
    assert campaign.box_excess([0, 0], [inf, 1], [5.0, 0.5], z) <= 0
    # a NaN bound is never an answer
    assert campaign.box_excess([np.nan, 0], [1, 1], [0.5, 0.5], z) == np.inf


def test_simulation_error_bound_covers_the_rounding():
    # δ_k bounds |x_k(float64) − x_k(exact)|: compare with the same simulation in exact rationals.
    from fractions import Fraction

    rng = np.random.default_rng(3)
    n, N = 3, 30
    A = rng.standard_normal((n, n))
    A *= 0.9 / max(abs(np.linalg.eigvals(A)))  # Schur stable, so the tighter bound applies too
    E = rng.standard_normal((n, 2))
    W = rng.uniform(-1, 1, (N, 2))
    x = np.empty((N, n))
    x[0] = rng.standard_normal(n)
    for k in range(N - 1):
        x[k + 1] = A @ x[k] + E @ W[k]
    terms = np.abs(x) @ np.abs(A).T + np.abs(W) @ np.abs(E).T
    delta = campaign.simulation_error_bound(np.abs(A), terms, N, n + 2 + 2)
    stable = campaign._stable_error_bound(A, campaign._gamma(n + 2 + 2) * terms, N)
    assert stable is not None
    xe = [Fraction(v) for v in x[0]]
    for k in range(N - 1):
        xe = [sum(Fraction(A[i, j]) * xe[j] for j in range(n)) + sum(Fraction(E[i, j]) * Fraction(W[k, j])
                                                                      for j in range(2)) for i in range(n)]
        err = np.array([abs(float(xe[i] - Fraction(x[k + 1, i]))) for i in range(n)])
        assert np.all(err <= delta[k + 1]), (k, err, delta[k + 1])
        assert np.all(err <= stable[k + 1]), (k, err, stable[k + 1])
    # and it is a rounding-sized bound, not a vacuous one
    assert 0 < delta[1].max() < 1e-13 * (1 + np.abs(x).max())


def test_cases_are_reproducible_from_their_seed():
    a = campaign.run_case("interval_luenberger", 7, max_nx=3, max_steps=50)
    b = campaign.run_case("interval_luenberger", 7, max_nx=3, max_steps=50)
    assert (a.nx, a.family, a.disturbance, a.steps, a.status) == (b.nx, b.family, b.disturbance, b.steps, b.status)
    assert a.max_excess == b.max_excess or (math.isinf(a.max_excess) and math.isinf(b.max_excess))
    assert "--seed 7 --max-nx 3 --max-steps 50" in a.reproduce()


def test_random_systems_cover_the_families():
    rng = np.random.default_rng(0)
    fams, spans, nxs = set(), [], set()
    for _ in range(60):
        s = campaign.random_system(rng)
        fams.add(s.family)
        nxs.add(s.nx)
        rad = max(abs(np.linalg.eigvals(s.A)))
        assert (rad > 1) == s.family.endswith("unstable")
        if s.family.startswith("ill"):
            nz = np.abs(s.A[np.abs(s.A) > 0])
            spans.append(nz.max() / nz.min())
    assert fams == {"stable", "unstable", "ill_stable", "ill_unstable"}
    assert max(nxs) == 8 and min(nxs) == 1
    assert max(spans) > 1e6  # entries spanning about 1e-4 .. 1e4


def test_regression_badly_scaled_zonotope_on_its_boundary():
    # Volume-min, seed 3: the true x_0 is a corner of the initial box and on the edge of the first
    # strip (vertex noise); the corrected zonotope has generators of lengths 1e-17 … 1e-2 and the
    # containment LP alone reported t* = 1 + 5e-8. The exact facet test confirms containment.
    r = campaign.run_case("zono_volume_min", 3, max_nx=3)
    assert r.status == "ok" and r.steps > 100
    assert not r.violations, r.reproduce()


def test_regression_design_certified_by_raising_beta():
    # ell_online_vertex, seed 1 (n_x = 5, unstable): at the searched β the designed (P, L, σ)
    # missed its floating-point certificate in a block that raising σ does not reach, and the
    # design was refused ("could not be certified"). A searched β is now raised towards 1 as well
    # (βP only adds slack); the design must be certified and its estimator contain the truth.
    from setbound import ellipsoidal

    case = campaign.random_case("ell_online_vertex", 1)
    d = ellipsoidal.design_offline(case.system.linear_system())
    assert 0 < d.beta < 1 and d.sigma > 0
    r = campaign.run_case("ell_online_vertex", 1, max_steps=60)
    assert r.status == "ok" and r.steps > 0, r.reason
    assert not r.violations, r.reproduce()


def _ropo_case_sets(seed):
    # the sets, true states and simulation-error bounds of run_case("ropo", seed), as _run_zonotopic
    # builds them
    from setbound import parallelotope
    from setbound.sets import Zonotope
    from setbound.simulation import simulate

    case = campaign.random_case("ropo", seed)
    s = case.system
    rng = np.random.default_rng([seed, 1000 + campaign.ESTIMATORS["ropo"].index])
    system = s.linear_system()
    lo, hi = campaign._x0_box(s, rng)
    x0 = Zonotope(0.5 * (lo + hi), np.diag(0.5 * (hi - lo)))
    est = parallelotope.ParallelotopeEstimator(system, x0, reduction=case.options["reduction"])
    sim = simulate(system, x0, case.N, disturbance=case.disturbance, rng=rng)
    delta = campaign._delta(np.abs(s.A), sim.x, system.E, sim.omega, s.A)
    return s.nx, est.run(sim.y).sets, sim.x, delta


def test_regression_ropo_ill_conditioned_parallelotope_is_decided_exactly():
    # ROPO seed 22045 (n_x = 8, ill_stable, girard, vertex noise): the interval-hull recursion
    # diverges (rho(|A|) = 1.31 > 1 with one output; CORA's recursion in 60 digits does the same),
    # the parallelotope reaches 1e53 with cond(T) ~ 1e17-1e18. The general LP check failed from
    # step 204 on and reported 594 "violations" (excess inf). The exact parallelotope test decides
    # every step: the true state is inside at all 798 steps.
    r = campaign.run_case("ropo", 22045)
    assert r.status == "ok" and r.nx == 8 and r.family == "ill_stable"
    assert r.steps == 798 and r.unverified == 0 and r.undecided == 0
    assert not r.violations and r.max_excess <= 0, r.reproduce()
    n, sets, x, delta = _ropo_case_sets(22045)

    def excess(k, center_shift=0.0, scale=1.0):
        T, rad = campaign._parallelotope_and_box(sets[k].generators, n)
        assert np.linalg.cond(T) > (1e15 if k >= 150 else 1e3)
        return campaign.parallelotope_excess(sets[k].center + center_shift, T * scale, rad * scale, x[k], delta[k])

    for k in (150, 190, 204, 500, 797):
        assert excess(k) <= 0
    # The check stays honest on the same ill-conditioned sets: a set moved off the truth by 1.5
    # times its interval hull is flagged, and so are sets shrunk about their centre where the
    # truth lies near the boundary (vertex noise).
    for k in (150, 204, 797):
        T, rad = campaign._parallelotope_and_box(sets[k].generators, n)
        shift = 1.5 * (np.abs(T).sum(axis=1) + rad) * np.where(np.arange(n) % 2, 1.0, -1.0)
        assert excess(k, center_shift=shift) > 0
    assert excess(0, scale=1 - 1e-6) > 0
    assert excess(150, scale=0.9) > 0.09  # t* >= 1/0.9 up to δ
    assert excess(190, scale=0.1) > 0
    # and ROPO itself: the set with its rounding box contains the truth at every step
    assert all(excess(k) <= 0 for k in range(0, len(sets), 13))


def test_parallelotope_check_decides_each_way():
    z = np.zeros(2)
    # cond 1e12, no box: the float solve's residual cannot be certified, the exact solve decides
    T = np.array([[1.0, 1.0], [0.0, 1e-12]])
    assert campaign.parallelotope_excess(z, T, z, np.array([2.0, 1e-12]), z) <= 0
    assert campaign.parallelotope_excess(z, T, z, np.array([2.0, 1e-12 * (1 + 1e-6)]), z) > 0
    assert campaign.parallelotope_excess(z, T, z, np.array([2.0 + 1e-6, 1e-12]), z) > 0
    # a diamond plus a box (an octagon: |x1|, |x2| <= 1.5, |x1| + |x2| <= 2): points the diamond's
    # facet normals do not decide need the LP's point (inside) or its dual direction (outside)
    D = np.array([[0.5, 0.5], [-0.5, 0.5]])
    rad = np.array([0.5, 0.5])
    assert campaign.parallelotope_excess(z, D, rad, np.array([1.45, 0.5]), z) <= 0  # t* = 0.975
    assert campaign.parallelotope_excess(z, D, rad, np.array([1.6, 0.0]), z) == pytest.approx(1.6 / 1.5 - 1, rel=1e-6)
    assert campaign.parallelotope_excess(z, D, rad, np.array([1.2, 0.9]), z) > 0  # beyond |x1| + |x2| <= 2
    # the simulation-error box widens the set by exactly δ
    assert campaign.parallelotope_excess(z, D, rad, np.array([1.6, 0.0]), np.array([0.1, 0.0])) <= 0
    # a NaN set is never an answer; a flat parallelotope goes to the general zonotope test
    assert campaign.parallelotope_excess(z, np.full((2, 2), np.nan), z, z, z) == np.inf
    flat = np.array([[1.0, 0.0], [1.0, 0.0]])
    assert campaign.parallelotope_excess(z, flat, z, np.array([0.5, 0.5]), z) <= 0
    assert campaign.parallelotope_excess(z, flat, z, np.array([0.5, 0.0]), z) > 0
    # an undecided step (nan) is counted apart: neither contained nor a violation
    res = campaign.CaseResult("ropo", 0, 2, "stable", "uniform", "ok")
    campaign._record(res, 0, float("nan"))
    campaign._record(res, 1, -0.5)
    assert (res.steps, res.undecided, res.violations) == (1, 1, [])


@pytest.mark.parametrize("scale", [1e-30, 1e-6, 1.0, 1e20, 1e39])
def test_zonotope_excess_does_not_depend_on_the_sets_scale(scale):
    """The containment checker's LP is scaled row by row: a diverging plant (sets of 1e39, met by
    zono_obs_interval_A) and a tiny set get the excess of the unit one. x = (1.9, 1.9) needs
    ξ = (0.95, 0.95, 0.95) in c + [[1, 0, 1], [0, 1, 1]] ξ (t* = 0.95: inside), (2.1, 2.1) needs
    t* = 1.05 (outside); the least-squares certificate fails on both, so the LP decides. With HiGHS's
    absolute tolerance unscaled, 1e-30 called the outside point inside and 1e39 lost the size."""
    G = np.array([[1.0, 0.0, 1.0], [0.0, 1.0, 1.0]]) * scale
    c, delta = np.zeros(2), np.full(2, 1e-14 * scale)
    inside = campaign.zonotope_excess(c, G, np.array([1.9, 1.9]) * scale, delta)
    outside = campaign.zonotope_excess(c, G, np.array([2.1, 2.1]) * scale, delta)
    assert inside == pytest.approx(0.95 - (1 + campaign.TAU), abs=1e-8)
    assert outside == pytest.approx(1.05 - (1 + campaign.TAU), abs=1e-8)
