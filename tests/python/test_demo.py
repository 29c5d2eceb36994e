"""The main job (make demo) runs; the set-library illustrations kept in setbound.demo hold."""
import math

import numpy as np
import pytest

from setbound import demo


def test_wrapping_effect_box_grows_zonotope_does_not():
    rows = demo.wrapping_effect(steps=6)
    box_widths = [r[1] for r in rows]
    zono_widths = [r[2] for r in rows]
    # Re-boxing a rotated box multiplies its width by sqrt(2) each step (thesis §1.2.7) ...
    for k, w in enumerate(box_widths, start=1):
        assert w == pytest.approx(2.0 * math.sqrt(2.0) ** k, rel=1e-9)
    # ... the zonotope is the exact image: a square of side 2 rotated, hull width 2 or 2·sqrt(2).
    for k, w in enumerate(zono_widths, start=1):
        assert w == pytest.approx(2.0 * (math.sqrt(2.0) if k % 2 else 1.0), rel=1e-9)


@pytest.mark.parametrize("vertex", [False, True])
def test_tube_contains_truth_and_stays_bounded(vertex):
    lo, hi, x, inside = demo.zonotopic_tube(steps=60, seed=3, vertex=vertex)
    assert inside.all()
    assert np.all(lo <= x + 1e-12) and np.all(x <= hi + 1e-12)
    # Bounded: after the transient the widths stay well below the initial box (width 6).
    assert np.max(hi[20:] - lo[20:]) < 2.0


def test_main_runs_the_main_job(tmp_path, capsys):
    """`python -m setbound.demo` is the main job (the same as `setbound demo`, tested with its plots
    in test_cli.py): every estimator of the demo job is in the table."""
    assert demo.main(["--out", str(tmp_path), "--steps", "4", "--no-plots", "-q"]) == 0
    out = capsys.readouterr().out
    job, _ = demo.demo_job(steps=4)
    for spec in job.estimators:
        assert spec.name in out
    assert "(4 steps)" in out
    assert (tmp_path / "summary.json").is_file()


def test_demo_reports_inapplicable_methods_in_user_terms(tmp_path, capsys):
    """P-radius approach 1 has no solution on the demo system: listed as "not applicable" with the
    reason, not as a failure; no message carries the name of a C or C++ function."""
    assert demo.main(["--out", str(tmp_path), "--steps", "4", "--no-plots", "-q"]) == 0
    out = capsys.readouterr().out
    line = next(ln for ln in out.splitlines() if ln.startswith("not applicable: pradius "))
    assert "its design has no solution for the demo system" in line and "approach 2" in line
    for method in demo.THESIS_NOT_APPLICABLE:
        assert f"not applicable: {method} — " in out
    assert "FAILED" not in out and "sb_" not in out and "design_pradius" not in out
    assert not list(tmp_path.glob("*.png"))


def test_demo_runs_the_thesis_observers():
    """The applicable thesis observers are in the demo job (through Plant.from_linear_system on
    the papers' 3-state system) and contain the true state; the others are listed with a reason."""
    from setbound import config

    job, skipped = demo.demo_job(steps=25)
    names = [e.method for e in job.estimators]
    registered = [m for m in demo.THESIS_OBSERVERS if m in config.ESTIMATORS]
    assert "interval_luenberger" in registered and "interval_invariant" in registered
    assert set(registered) <= set(names) and set(skipped) == set(demo.THESIS_OBSERVERS) - set(registered)
    for spec in job.estimators:
        if spec.method in registered:
            r = config.run_estimator(job, spec, quiet=True)
            assert r.ok and r.contained is True, (spec.name, r.error)
            assert r.trajectory.width.max() < 1e3  # bounded on the detectable demo system
    assert set(demo.THESIS_NOT_APPLICABLE) & set(demo.THESIS_OBSERVERS) == set()
