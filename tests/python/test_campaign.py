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
