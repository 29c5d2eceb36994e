"""bench/bench_cora.py (docs/cora_comparison.md) in its quick mode on the alamo 2-D example.

The table's properties, which would fail if the bench (or a method) were wrong: IRadius is CORA's
RMS over time of the interval radius; every guaranteed method's mean IRadius is at least the best
one's and at least the exact hull's, and its sets contain the exact consistent-set hull at every
step (alamo has no printed true trajectory: the exact hull is the stronger check); methods that
cannot run are rows with a reason, not crashes; CORA's saved alamo values that the specification
marks reproducible (cora_observers.md §4.3, golden_final_interval_hull of
alamo2005_2d_cora_unittest.json) are all reproduced with convention="cora".
"""

import numpy as np
import pytest

import setbound.cora as cora

from bench_support import load_bench
from cora_support import DATA, needs_data


def _bench():
    return load_bench("bench_cora")


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("bench_cora")
    doc = tmp / "cora_comparison.md"
    doc.write_text("# title\n\nkept\n\n<!-- bench_cora:begin -->\nold\n<!-- bench_cora:end -->\n\nkept too\n")
    out = _bench().main(["--data", str(DATA), "--models", "alamo", "--quick", "--no-cpp", "--no-figure",
                         "--update-doc", str(doc)])
    return out, doc


@needs_data
def test_every_registered_name_has_a_row(quick):
    out, _ = quick
    rows = out["results"]["alamo"]["rows"]
    assert [r["alg"] for r in rows] == list(cora.algorithms())
    for r in rows:
        # ran, or a stated reason (an error message or why it is skipped)
        assert "mean_iradius" in r or r.get("error") or r.get("skipped"), r
    ran = [r["alg"] for r in rows if "mean_iradius" in r]
    assert {"FRad-A", "FRad-B", "FRad-C", "VolMin-A", "VolMin-B", "ESO-A", "ESO-B", "CZN-A", "CZN-B"} <= set(ran)


@needs_data
def test_iradius_ratios_and_the_exact_hull(quick):
    out, _ = quick
    res = out["results"]["alamo"]
    exact = res["exact"]["mean_iradius"]
    guaranteed = [r for r in res["rows"] if "mean_iradius" in r and r["guaranteed"]]
    assert len(guaranteed) >= 9
    best = min(r["mean_iradius"] for r in guaranteed)
    for r in guaranteed:
        assert r["mean_iradius"] / best >= 1.0
        assert np.mean(r["iradius"]) == pytest.approx(r["mean_iradius"])
        # the exact hull's ratio is at most every guaranteed method's
        assert exact <= r["mean_iradius"] * (1 + 1e-9), r["alg"]
        # ... because each set contains the exact hull at every step
        inside, total = r["exact_inside"]
        assert inside == total == res["N"], r["alg"]
        assert r["truth"] is None  # alamo has no printed true trajectory
        assert r["py_us"] > 0 and r["design_ms"] >= 0


@needs_data
def test_iradius_is_coras_rms_of_the_radius():
    bench = _bench()
    r = cora.observe(DATA / "alamo2005_2d_cora_unittest.json", "FRad-A")
    rad = 0.5 * (r.upper - r.lower)
    np.testing.assert_allclose(bench.iradius(r.lower, r.upper), np.sqrt((rad ** 2).mean(axis=0)))
    np.testing.assert_allclose(bench.iradius(r.lower, r.upper), r.iradius)


@needs_data
def test_coras_saved_values_and_the_document(quick):
    out, doc = quick
    s = out["golden_summary"]
    # alamo: the eight values of spec §4.3 that are reproducible from the data alone
    assert s["spec"]["V"] == 8 and s["spec_reproduced"]["V"] == 8
    assert s["total"] == 16 and s["reproduced"] >= 8
    text = doc.read_text()
    assert text.startswith("# title\n\nkept\n") and text.rstrip().endswith("kept too")
    assert "old" not in text and "| FRad-A |" in text and "[V] 8 of 8" in text


def test_within_tol_is_coras_rule():
    bench = _bench()
    assert bench.within_tol([1.0], [1.0 + 9e-7])
    assert bench.within_tol([1e4], [1e4 * (1 + 9e-7)])  # relative
    assert not bench.within_tol([1e-3], [1e-3 + 2e-6])


@needs_data
def test_truth_inside_on_a_model_with_a_printed_trajectory():
    # vehicle6 (6 states, 4 outputs, printed true states), first 15 steps: every guaranteed method
    # contains the true state at every step.
    out = _bench().main(["--data", str(DATA), "--models", "vehicle6", "--quick", "--steps", "15", "--no-cpp",
                         "--no-figure", "--no-golden"])
    rows = out["results"]["vehicle6"]["rows"]
    guaranteed = [r for r in rows if "mean_iradius" in r and r["guaranteed"]]
    assert len(guaranteed) >= 8
    best = min(r["mean_iradius"] for r in guaranteed)
    for r in guaranteed:
        inside, total = r["truth"]
        assert inside == total == 15, r["alg"]
        assert r["mean_iradius"] >= best
        exact = out["results"]["vehicle6"]["exact"]
        assert exact["mean_iradius"] <= r["mean_iradius"] * (1 + 1e-9), r["alg"]
    # VolMin-A is out of range at n_x = 6: skipped with the reason, not run
    assert "exponential" in next(r for r in rows if r["alg"] == "VolMin-A")["skipped"]


def test_cpp_rows_are_the_median_over_the_runs_of_the_program():
    # bench_cora_cpp runs --cpp-runs times: on the shared VM a run's medians jump between levels
    # (vehicle6 FRad-A: 19 and 31 µs in consecutive runs), the median over the runs does not.
    bench = _bench()
    base = {"model": "vehicle6", "alg": "FRad-A", "error": None}
    rows = [{**base, "median_us": m, "p90_us": 2 * m, "design_ms": 0.0} for m in (31.2, 19.1, 19.0, 31.6, 19.2)]
    rows.append({**base, "median_us": None, "p90_us": None, "design_ms": None, "error": "a failed run"})
    r = bench.median_row(rows)
    assert r["median_us"] == 19.2 and r["p90_us"] == 38.4 and r["runs_us"] == [31.2, 19.1, 19.0, 31.6, 19.2]
    with pytest.raises(SystemExit):
        bench.main(["--cpp-runs", "0", "--no-cpp"])
