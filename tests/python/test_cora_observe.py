"""setbound.cora.observe: CORA's observers by CORA's names on CORA's model files.

The saved final hulls are CORA's (../shared/benchmarks/cora_linearSysDT_observe, the
`golden_final_interval_hull` of each file, CORA v2026.0.1 unit tests); CORA's rule is
|a − b| <= 1e-6."""

import numpy as np
import pytest

import setbound.cora as cora
from setbound.benchmarks import load_cora
from setbound.errors import InvalidArgumentError

from cora_support import DATA, needs_data

CORA_TOL = 1e-6


def _final_difference(r, golden):
    lo, hi = golden
    return max(np.abs(r.lower[-1] - lo).max(), np.abs(r.upper[-1] - hi).max())


@needs_data
def test_frad_a_by_name_from_the_json_path_reproduces_coras_hull():
    path = DATA / "alamo2005_2d_cora_unittest.json"
    r = cora.observe(path, "FRad-A")
    b = load_cora(path)
    assert r.lower.shape == (len(b.y), 2) and len(r.sets) == len(b.y)
    assert _final_difference(r, b.golden["FRad-A"]) < CORA_TOL
    # The same through the loaded benchmark, and CORA's IRadius is the RMS of the radius over time.
    r2 = cora.observe(b, "FRad-A")
    np.testing.assert_array_equal(r.lower, r2.lower)
    rad = 0.5 * (r.upper - r.lower)
    np.testing.assert_allclose(r.iradius, np.sqrt((rad ** 2).mean(axis=0)))
    assert r.mean_iradius == pytest.approx(r.iradius.mean())
    assert r.seconds_per_step > 0 and r.design_seconds >= 0 and r.dt == b.dt


@needs_data
def test_steps_shortens_the_run():
    r = cora.observe(DATA / "tank30.json", "FRad-A", steps=20)
    b = load_cora(DATA / "tank30.json")
    assert r.lower.shape == (20, 30)
    assert _final_difference(r, b.golden["FRad-A [tFinal==10]"]) < CORA_TOL


def test_unknown_names_and_options_are_named():
    with pytest.raises(InvalidArgumentError, match="alg: unknown CORA observer 'FRad-Z'"):
        cora.observe("x.json", "FRad-Z")
    with pytest.raises(InvalidArgumentError, match="convention"):
        cora.observe("x.json", "FRad-A", convention="matlab")
    with pytest.raises(InvalidArgumentError, match="gain: FRad-A has no observer gain"):
        cora.observe("x.json", "FRad-A", gain=np.zeros((2, 1)))
    with pytest.raises(InvalidArgumentError, match="model: expected a CORA-format JSON path"):
        cora.observe(42, "FRad-A")
    with pytest.raises(InvalidArgumentError, match="registered already"):
        cora.register_algorithm("FRad-A", lambda m, **k: None, summary="again")
    with pytest.raises(InvalidArgumentError, match="gain_required: expected a dict"):
        cora.register_algorithm("Test-G", lambda m, **k: None, summary="x", accepts_gain=True, gain_required=["cora"])
    with pytest.raises(InvalidArgumentError, match="gain_required: expected .* got 'matlab'"):
        cora.register_algorithm("Test-G", lambda m, **k: None, summary="x", accepts_gain=True,
                                gain_required={"matlab": "why"})
    with pytest.raises(InvalidArgumentError, match="gain_required: only for a method that accepts a gain"):
        cora.register_algorithm("Test-G", lambda m, **k: None, summary="x", gain_required={"cora": "why"})
    assert "Test-G" not in cora.algorithms()


@needs_data
def test_bad_steps_and_unknown_option_are_named():
    with pytest.raises(InvalidArgumentError, match="steps"):
        cora.observe(DATA / "alamo2005_2d_cora_unittest.json", "FRad-A", steps=0)
    with pytest.raises(TypeError, match="colour"):
        cora.observe(DATA / "alamo2005_2d_cora_unittest.json", "FRad-A", colour="red")
