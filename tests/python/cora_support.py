"""What the tests on CORA's benchmark data share: where the data is, the tolerance of its printed
truth, and the containment check against that truth (tests of setbound.cora, the zonotopic,
ellipsoidal, parallelotopic and constrained-zonotopic catalogues, ESO-D, the CORA bench)."""
import os
from pathlib import Path

import numpy as np
import pytest

#: ../shared/benchmarks/cora_linearSysDT_observe (or $SETBOUND_CORA_DATA): CORA's models,
#: measurements, true trajectories and saved hulls.
DATA = Path(os.environ.get("SETBOUND_CORA_DATA",
                           Path(__file__).resolve().parents[3] / "shared" / "benchmarks" / "cora_linearSysDT_observe"))
needs_data = pytest.mark.skipif(not DATA.is_dir(), reason=f"benchmark data not found at {DATA}")
TRUTH_TOL = 5e-4  # the true trajectories are printed to 3 decimals


def truth_tolerance(name: str, steps: int) -> np.ndarray:
    """Per-step tolerance of the printed truth: TRUTH_TOL, and 3e-3 from step 217 of pedestrian4
    (the data's README: its printed truth leaves the noise bound of output 2 there by 0.00295)."""
    tol = np.full(steps, TRUTH_TOL)
    if name == "pedestrian4":
        tol[217:] = 3e-3
    return tol


def steps_outside(name: str, truth, lower, upper) -> np.ndarray:
    """The steps at which the truth leaves [lower, upper] by more than its printed precision."""
    truth, lower, upper = (np.asarray(a, float) for a in (truth, lower, upper))
    tol = truth_tolerance(name, len(truth))[:, None]
    inside = np.all((lower - tol <= truth) & (truth <= upper + tol), axis=1)
    return np.flatnonzero(~inside)


def assert_truth_inside(name: str, truth, lower, upper) -> None:
    out = steps_outside(name, truth, lower, upper)
    assert out.size == 0, f"{name}: truth outside at steps {out[:10]}"
