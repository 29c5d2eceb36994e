"""CORA's observer names in job files and in ``setbound compare`` (issue 22): ``method = "<CORA name>"``
for every name of ``setbound.cora.algorithms()``, with ``convention``, ``gain`` and the method's own
options (setbound.jobs.cora). The job runs through the same runner as ``setbound.cora.observe``,
so the sets must be the same numbers; a CORA JSON model written as a job file with its data gives
``observe``'s sets on that file."""
from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from fuzz_support import count, fuzz

import setbound.cora as cora
from setbound import cli, jobs
from setbound.jobs.cora import CORA_METHODS, cora_model

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "cora_vehicle2.toml"
SHARED = ROOT.parent / "shared" / "benchmarks" / "cora_linearSysDT_observe"
ERROR_LINE = re.compile(r"^setbound: error: [^\s:][^:]*: \S.*$")

# A small 2-state system with one output (E = [G_W, 0], F = [0, G_V], as CORA's W and V) and a
# gain that makes A - L C stable (a valid weight for the strip methods as well).
SYSTEM = {"A": [[0.9, 0.2], [-0.1, 0.7]], "B": [[0.1], [0.05]], "C": [[1.0, 0.5]],
          "E": [[0.05, 0.0, 0.0], [0.0, 0.05, 0.0]], "F": [[0.0, 0.0, 0.1]]}
GAIN = [[0.4], [0.1]]
NAMES = list(cora.algorithms())


def _doc(estimators, *, horizon=15, disturbance="uniform", seed=3):
    return {"title": "cora-jobs", "system": dict(SYSTEM), "initial": {"lower": [-1.0, -1.0], "upper": [1.0, 1.0]},
            "simulation": {"horizon": horizon, "seed": seed, "disturbance": disturbance,
                           "inputs": ["sin(t)"]},
            "estimator": estimators}


def _needs_gain(name: str, convention: str = "setbound") -> bool:
    return cora.gain_requirement(name, convention) is not None


def _table(name: str, convention: str = "setbound") -> dict:
    tab = {"method": name, "convention": convention}
    if _needs_gain(name, convention):
        tab["gain"] = GAIN
    return tab


def _runs(name: str) -> list[str]:
    row = CORA_METHODS.get(name)
    return list(row.conventions) if row is not None else ["setbound"]


def _observe_on_job(job, spec):
    """setbound.cora.observe on the job's model (cora_model), with the spec's options."""
    o = spec.options
    model = cora_model(job.system, job.initial, job.y, job.u, name=job.title,
                       zonotope_order=o.get("zonotope_order") or 20.0, constant_input=job.constant_input)
    opts = {k: v for k, v in o.items() if v is not None and k not in ("convention", "gain", "zonotope_order")}
    return cora.observe(model, spec.method, convention=o["convention"],
                        gain=None if o.get("gain") is None else np.asarray(o["gain"], float), **opts)


def test_every_cora_name_is_a_job_method():
    assert NAMES and set(NAMES) <= set(jobs.ESTIMATORS)
    for name in NAMES:
        kind = jobs.ESTIMATORS[name]
        assert {"convention", "gain"} <= set(kind.options)
        assert kind.options["convention"] == "setbound"


@pytest.mark.parametrize("name", NAMES)
def test_every_cora_name_runs_from_a_job_and_equals_observe(name):
    """Each name (each convention it runs with) from a job: the sets are observe's, the guaranteed
    ones contain the simulated truth, the others are marked as not guaranteed."""
    for convention in _runs(name):
        job = jobs.from_dict(_doc([_table(name, convention)]))
        res = jobs.run_estimator(job, job.estimators[0], quiet=True)
        assert res.ok, res.error
        t = res.trajectory
        ref = _observe_on_job(job, job.estimators[0])
        np.testing.assert_array_equal(t.lower, ref.lower)
        np.testing.assert_array_equal(t.upper, ref.upper)
        assert t.lower.shape == (15, 2) and np.all(t.lower <= t.upper)
        row = CORA_METHODS.get(name)
        guaranteed = row is not None and convention in row.guaranteed
        assert t.guaranteed == guaranteed
        assert res.contained is (True if guaranteed else None), (name, convention)


@pytest.mark.parametrize("name", [n for n in NAMES if CORA_METHODS.get(n) and CORA_METHODS[n].guaranteed])
@pytest.mark.parametrize("disturbance", ["uniform", "vertex"])
def test_guaranteed_cora_names_contain_the_truth_in_jobs(name, disturbance):
    """Random and vertex disturbances: the job's guarantee check finds the truth in every set."""
    job = jobs.from_dict(_doc([_table(name)], horizon=40, disturbance=disturbance, seed=11))
    res = jobs.run_estimator(job, job.estimators[0], quiet=True)
    assert res.ok, res.error
    assert res.contained is True
    assert np.all(res.trajectory.in_bounds(job.x_true))


def test_convention_cora_passes_through():
    """FRad-B differs between the conventions (CORA's covariance applies A and W twice), and each
    convention's job gives that convention's observe."""
    job = jobs.from_dict(_doc([{"method": "FRad-B"}, {"method": "FRad-B", "name": "b-cora", "convention": "cora"}]))
    a, b = jobs.run(job, quiet=True)
    ra = _observe_on_job(job, job.estimators[0])
    rb = cora.observe(cora_model(job.system, job.initial, job.y, job.u), "FRad-B", convention="cora")
    np.testing.assert_array_equal(a.trajectory.upper, ra.upper)
    np.testing.assert_array_equal(b.trajectory.upper, rb.upper)
    assert not np.array_equal(a.trajectory.upper, b.trajectory.upper)


def test_gain_and_options_pass_through():
    """A given gain replaces the design (PRad-E), and the class options reach the estimator
    (FRad-A with 3 generators is wider than with CORA's order 20)."""
    job = jobs.from_dict(_doc([{"method": "PRad-E"}, {"method": "PRad-E", "name": "given", "gain": GAIN},
                               {"method": "FRad-A"}, {"method": "FRad-A", "name": "small", "max_generators": 3},
                               {"method": "FRad-A", "name": "order1", "zonotope_order": 1}]))
    designed, given, frad, small, order1 = jobs.run(job, quiet=True)
    m = cora_model(job.system, job.initial, job.y, job.u)
    np.testing.assert_array_equal(given.trajectory.upper, cora.observe(m, "PRad-E", gain=np.array(GAIN)).upper)
    assert not np.array_equal(given.trajectory.upper, designed.trajectory.upper)
    np.testing.assert_array_equal(small.trajectory.upper, cora.observe(m, "FRad-A", max_generators=3).upper)
    assert np.all(small.trajectory.width >= frad.trajectory.width - 1e-12)
    assert np.any(small.trajectory.width > frad.trajectory.width + 1e-9)
    # zonotope_order = 1: n_x generators, as max_generators = 2
    np.testing.assert_array_equal(order1.trajectory.upper, cora.observe(m, "FRad-A", max_generators=2).upper)
    assert all(s.m <= 2 + job.system.nx for s in order1.trajectory.sets)


def _check(tmp_path, doc) -> tuple[int, str]:
    from test_fuzz_jobs import to_toml

    path = tmp_path / "job.toml"
    path.write_text(to_toml(doc))
    import contextlib
    import io

    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = cli.main(["--quiet", "check", str(path)])
    return code, err.getvalue().strip()


@pytest.mark.parametrize("table,key,message", [
    ({"method": "FRad-Z"}, "estimator[0].method", "did you mean 'FRad-"),
    ({"method": "frad-b"}, "estimator[0].method", "FRad-B"),
    ({"method": "FRad-B", "gain": GAIN}, "estimator[0].gain", "FRad-B takes no observer gain"),
    ({"method": "PRad-E", "gain": [[0.4, 0.1]]}, "estimator[0].gain", "expected shape (2, 1), got (1, 2)"),
    ({"method": "PRad-E", "gain": [[0.4], ["x"]]}, "estimator[0].gain[1][0]", "expected a number"),
    ({"method": "PRad-E", "gain": [[0.4], [float("nan")]]}, "estimator[0].gain[1][0]", "not a finite number"),
    ({"method": "PRad-E", "gain": 0.4}, "estimator[0].gain", "expected shape"),
    ({"method": "FRad-B", "convention": "CORA"}, "estimator[0].convention", "'setbound', 'cora'"),
    ({"method": "FRad-B", "convention": 1}, "estimator[0].convention", "setbound"),
    # the reason comes from the one rule setbound.cora.prepare applies (register_algorithm's gain_required)
    ({"method": "PRad-C", "convention": "cora"}, "estimator[0].gain", "PRad-C needs a given gain (n_x x n_y) with convention = 'cora': CORA's PRad-C design cannot"),
    ({"method": "Hinf-G", "convention": "cora"}, "estimator[0].gain", "Hinf-G needs a given gain (n_x x n_y) with convention = 'cora': CORA's design is a feasibility SDP"),
    ({"method": "Hinf-G", "convention": "cora", "gain": GAIN, "variant": "wrapped"}, "estimator[0].variant",
     "CORA's recursion"),
    ({"method": "ESO-C", "convention": "cora"}, "estimator[0].convention", "ESO-C cannot run"),
    ({"method": "ESO-D", "convention": "cora"}, "estimator[0].convention", "ESO-D cannot be reproduced"),
    ({"method": "ESO-A", "ellipsoids": "inner"}, "estimator[0].ellipsoids", "not be guaranteed"),
    ({"method": "FRad-A", "zonotope_order": 10, "max_generators": 5}, "estimator[0].max_generators", "not both"),
    ({"method": "CZN-A", "zonotope_order": 10, "order": 5}, "estimator[0].order", "not both"),
    ({"method": "FRad-A", "max_generators": 0}, "estimator[0].max_generators", "[1,"),
    ({"method": "FRad-A", "reduction": "limits"}, "estimator[0].reduction", "combastel"),
    ({"method": "FRad-B", "reductoin": "pca"}, "estimator[0].reductoin", "did you mean 'reduction'"),
    ({"method": "ESO-B", "max_generators": 5}, "estimator[0].max_generators", "unknown key"),
])
def test_bad_cora_tables_are_refused_naming_the_key(table, key, message, tmp_path):
    code, err = _check(tmp_path, _doc([table]))
    assert code == 2, err
    assert ERROR_LINE.match(err), err
    assert err.startswith(f"setbound: error: {key}: "), err
    assert message in err, err


@fuzz(300)
@given(data=st.data())
def test_fuzz_the_keys_of_every_cora_name(data, tmp_path_factory):
    """Hostile values on every key of every CORA name (and on two at once): `setbound check` accepts
    the file or refuses it in one line naming the key, never a traceback."""
    from test_fuzz_jobs import HOSTILE_SCALARS, run_check, to_toml

    count("test_cora_jobs_fuzz")
    name = data.draw(st.sampled_from(NAMES))
    keys = sorted(jobs.ESTIMATORS[name].options)
    values = st.sampled_from([*HOSTILE_SCALARS, GAIN, [[0.1, 0.2]], [[0.1], [0.2], [0.3]], "cora", "setbound", "pca",
                              "girard", "inner", 20, 1.5, 10**6, None])
    tab = _table(name)
    for key in data.draw(st.lists(st.sampled_from(keys), min_size=1, max_size=2, unique=True)):
        v = data.draw(values)
        if v is None:
            tab.pop(key, None)
        else:
            tab[key] = v
    code, out, err = run_check(tmp_path_factory.mktemp("corafuzz"), to_toml(_doc([tab])), None)
    assert "Traceback" not in err + out
    assert code in (0, 2), (code, err, tab)
    if code == 2:
        lines = err.strip().splitlines()
        assert len(lines) == 1 and ERROR_LINE.match(lines[0]), err
        # the key of the estimator, or the file when the value is not TOML (a 5000-digit integer)
        assert lines[0].startswith("setbound: error: estimator[0]") or "not valid TOML" in lines[0], lines[0]
    else:
        assert ": ok — " in out


def test_unknown_name_lists_the_cora_names(tmp_path):
    code, err = _check(tmp_path, _doc([{"method": "VolMin-Z"}]))
    assert code == 2
    for name in NAMES:
        assert name in err


def test_a_name_registered_later_runs_with_the_common_keys():
    """Generic over the registry: a CORA name a family registers (here a test runner built on FRad-A's
    class) becomes a job method with convention and gain, reported as not guaranteed (no row)."""
    from setbound.jobs.cora import register_cora_names
    from setbound.jobs.registry import METHODS
    from setbound.zonotopic import SegmentMinEstimator

    seen = {}

    def runner(model, *, convention, gain, **options):
        seen.update(convention=convention, gain=gain, options=options)
        est = SegmentMinEstimator(model.system, model.x0, **model.estimator_options())

        def run():
            t = est.run(model.y, model.u)
            return t.lower, t.upper, t.sets
        return run

    cora.register_algorithm("Test-X", runner, summary="a test", accepts_gain=True)
    try:
        assert register_cora_names() == ["Test-X"]
        assert register_cora_names() == []  # registered once
        job = jobs.from_dict(_doc([{"method": "Test-X", "convention": "cora", "gain": GAIN}]))
        res = jobs.run_estimator(job, job.estimators[0], quiet=True)
        assert seen["convention"] == "cora" and np.array_equal(seen["gain"], GAIN) and seen["options"] == {}
        assert res.ok and res.trajectory.guaranteed is False and res.contained is None
        with pytest.raises(jobs.ConfigError, match=r"estimator\[0\]\.max_generators: unknown key"):
            jobs.from_dict(_doc([{"method": "Test-X", "max_generators": 4}]))
    finally:
        cora._ALGORITHMS.pop("Test-X", None)
        jobs.ESTIMATORS.pop("Test-X", None)
        METHODS.pop("Test-X", None)


def test_progress_bar_path_runs_the_record_once():
    """run_trajectory's chunked path (a terminal) runs a CORA name in one call: the same sets."""
    job = jobs.from_dict(_doc([{"method": "FRad-B"}]))
    kind = jobs.ESTIMATORS["FRad-B"]
    est = kind.build(job, job.estimators[0].options)[0]
    whole = est.run(job.y, job.u)
    parts = jobs.run_trajectory(kind.build(job, job.estimators[0].options)[0], job.y, job.u, chunk=4, quiet=True)
    np.testing.assert_array_equal(whole.upper, parts.upper)
    # other data than the job's: prepared again on that record
    short = est.run(job.y[:5], job.u[:5])
    np.testing.assert_array_equal(short.upper, whole.upper[:5])
    with pytest.raises(ValueError, match="reset"):
        est.run(job.y, job.u, reset=False)


def test_omega_centre_is_the_constant_column():
    """A job with a non-centred [system.omega]: the offset column is the model's constant column
    (CORA's W and V centres), no extra column is added, and the sets contain the truth."""
    doc = _doc([{"method": "FRad-B"}, {"method": "PRad-E", "convention": "cora"}])
    doc["system"]["omega"] = {"lower": [0.0, -1.0, -0.5], "upper": [2.0, 1.0, 0.5]}
    job = jobs.from_dict(doc)
    assert job.constant_input
    m = cora_model(job.system, job.initial, job.y, job.u, constant_input=True)
    assert m.system.nu == job.system.nu and np.array_equal(m.u, job.u)
    res = jobs.run(job, keep_going=True, quiet=True)
    assert res[0].ok and res[0].contained is True
    # CORA's intersection-free PRad-E has no constant term c; the omega centre is W's, not c: it runs
    assert res[1].ok and res[1].contained is True


# ---------------------------------------------------------------- a CORA model file as a job file
def _write_cora_job(tmp_path: Path, json_file: Path, estimators, steps: int):
    """A job file with the model of a CORA JSON file and its measured data (CSV), as a CORA user
    writes it: W and V as E = [G_W, 0], F = [0, G_V] (centres zero in these files)."""
    from test_fuzz_jobs import to_toml

    d = json.loads(json_file.read_text())
    m = cora.as_model(json_file)
    s = m.system
    nu = s.nu - 1  # the model's last input is CORA's constant
    assert np.all(s.B[:, -1] == 0) and np.all(s.D == 0)  # c and the centres are zero in these files
    system = {"A": s.A.tolist(), "C": s.C.tolist(), "E": s.E.tolist(), "F": s.F.tolist()}
    if nu:
        system["B"] = s.B[:, :nu].tolist()
    k = min(steps, len(m.y))
    cols = [f"y{i}" for i in range(s.ny)] + [f"u{i}" for i in range(nu)]
    rows = np.hstack([m.y[:k], m.u[:k, :nu]])
    (tmp_path / "data.csv").write_text(",".join(cols) + "\n" + "".join(",".join(repr(float(v)) for v in r) + "\n"
                                                                       for r in rows))
    doc = {"title": json_file.stem, "system": system,
           "initial": {"center": m.x0.center.tolist(), "generators": np.asarray(m.x0.generators).tolist()},
           "data": {"file": "data.csv"}, "estimator": estimators}
    path = tmp_path / "job.toml"
    path.write_text(to_toml(doc))
    return path, m, d, k


@pytest.mark.skipif(not (SHARED / "vehicle2_cora_unittest.json").is_file(), reason="CORA benchmark data not here")
def test_cora_model_file_as_job_gives_observe_sets(tmp_path):
    """vehicle2 (CORA's unit-test model: an input, order 100, PCA): every name from a job file with
    the file's data equals observe on the JSON file, in both conventions (CORA's saved gains where
    one must be given: vehicle2_cora_saved_gains.json, key gains)."""
    f = SHARED / "vehicle2_cora_unittest.json"
    gains = json.loads((SHARED / "vehicle2_cora_saved_gains.json").read_text())["gains"]
    tables, calls = [], []
    for name in NAMES:
        for convention in _runs(name):
            tab = {"method": name, "name": f"{name}-{convention}", "convention": convention}
            row = CORA_METHODS.get(name)
            if row is not None and row.family in ("zonotopic", "constrained_zonotopic"):
                tab["zonotope_order"] = 100
            if row is not None and row.family in ("zonotopic", "parallelotope"):
                tab["reduction"] = "pca"
            if row is not None and row.family == "constrained_zonotopic":
                tab["technique"] = "pca"
            gain = None
            if _needs_gain(name, convention):
                gain = gains[name]["L"]
                tab["gain"] = gain
            tables.append(tab)
            calls.append((name, convention, gain, {"technique": "pca"} if "technique" in tab else {}))
    path, m, _, k = _write_cora_job(tmp_path, f, tables, steps=30)
    job = jobs.load(path)
    results = jobs.run(job, keep_going=True, quiet=True)
    for res, (name, convention, gain, opts) in zip(results, calls):
        assert res.ok, (res.name, res.error)
        ref = cora.observe(f, name, convention=convention, steps=k,
                           gain=None if gain is None else np.asarray(gain), **opts)
        np.testing.assert_array_equal(res.trajectory.lower, ref.lower, err_msg=res.name)
        np.testing.assert_array_equal(res.trajectory.upper, ref.upper, err_msg=res.name)


@pytest.mark.skipif(not (SHARED / "alamo2005_2d_cora_unittest.json").is_file(), reason="CORA benchmark data not here")
def test_cora_saved_hull_from_a_job_file(tmp_path):
    """The whole alamo2005 record from a job file, FRad-A in CORA's convention: CORA's saved final
    hull (alamo2005_2d_cora_unittest.json, golden_final_interval_hull.values["FRad-A"], CORA's unit
    test tolerance 1e-6)."""
    f = SHARED / "alamo2005_2d_cora_unittest.json"
    path, m, d, k = _write_cora_job(tmp_path, f, [{"method": "FRad-A", "convention": "cora"}], steps=10**6)
    assert k == len(m.y)
    res = jobs.run(jobs.load(path), quiet=True)[0]
    lo, hi = m.golden["FRad-A"]
    np.testing.assert_allclose(res.trajectory.lower[-1], lo, atol=1e-6)
    np.testing.assert_allclose(res.trajectory.upper[-1], hi, atol=1e-6)


# ---------------------------------------------------------------- the command line
def test_compare_with_cora_names_in_the_file_and_on_the_command_line(tmp_path, capsys):
    """`setbound compare` keeps CORA names of the file, adds CORA names the file does not run (with
    their defaults), and refuses a name that is neither."""
    out = tmp_path / "cmp"
    code = cli.main(["--quiet", "compare", str(EXAMPLE), "--estimators", "FRad-A,Hinf-G-cora,FRad-B,VolMin-B",
                     "--out", str(out), "--no-plots"])
    assert code == 0, capsys.readouterr().err
    summary = json.loads((out / "summary.json").read_text())
    rows = {e["name"]: e for e in summary["estimators"]}
    # the file's (by name or method: FRad-B keeps FRad-B-cora too), then the added one
    assert list(rows) == ["FRad-A", "FRad-B", "FRad-B-cora", "Hinf-G-cora", "VolMin-B"]
    assert rows["VolMin-B"]["method"] == "VolMin-B" and rows["VolMin-B"]["contains_truth"] is True
    assert rows["Hinf-G-cora"]["guaranteed"] is False and rows["Hinf-G-cora"]["contains_truth"] is None
    assert rows["FRad-A"]["contains_truth"] is True
    text = capsys.readouterr().out
    assert "n/a*" in text  # the non-guaranteed row is marked
    code = cli.main(["--quiet", "compare", str(EXAMPLE), "--estimators", "FRad-A,Frad-B", "--out", str(out)])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "--estimators: Frad-B not among" in err and "FRad-B" in err
    # PRad-C added with defaults runs setbound's design of the paper's condition (convention
    # "setbound"); its sets contain the simulated truth
    code = cli.main(["--quiet", "compare", str(EXAMPLE), "--estimators", "PRad-C", "--out", str(out), "--no-plots"])
    assert code == 0, capsys.readouterr().err
    rows = {e["name"]: e for e in json.loads((out / "summary.json").read_text())["estimators"]}
    assert rows["PRad-C"]["ok"] and rows["PRad-C"]["contains_truth"] is True


def test_compare_two_files_with_cora_names(tmp_path, capsys):
    """Two files of one system: setbound's kinds in one, CORA names in the other."""
    from test_fuzz_jobs import to_toml

    a, b = tmp_path / "a.toml", tmp_path / "b.toml"
    a.write_text(to_toml(_doc([{"method": "segment_min"}, {"method": "czn_a"}])))
    b.write_text(to_toml(_doc([{"method": "FRad-A", "max_generators": 20, "reduction": "combastel"},
                               {"method": "CZN-A"}], seed=99)))
    out = tmp_path / "cmp"
    assert cli.main(["--quiet", "compare", str(a), str(b), "--out", str(out), "--no-plots"]) == 0
    rows = {e["name"]: e for e in json.loads((out / "summary.json").read_text())["estimators"]}
    assert set(rows) == {"segment_min", "czn_a", "FRad-A", "CZN-A"}
    assert all(r["ok"] and r["contains_truth"] is True for r in rows.values())
    z = {n: np.load(out / f"{n}.npz") for n in rows}
    # FRad-A with setbound's settings is segment_min, CZN-A in setbound's convention is czn_a: same
    # algorithm and options, up to the model's constant input column (a zero column of B)
    np.testing.assert_allclose(z["FRad-A"]["upper"], z["segment_min"]["upper"], rtol=0, atol=1e-12)
    np.testing.assert_allclose(z["CZN-A"]["upper"], z["czn_a"]["upper"], rtol=0, atol=1e-12)


def test_the_example_runs_and_equals_observe(tmp_path, capsys):
    """examples/cora_vehicle2.toml: every estimator runs, the guaranteed ones contain the truth, and
    two of them equal observe on the job's model."""
    assert cli.main(["--quiet", "run", str(EXAMPLE), "--out", str(tmp_path / "ex"), "--no-plots"]) == 0
    summary = json.loads((tmp_path / "ex" / "summary.json").read_text())
    assert len(summary["estimators"]) >= 8
    for e in summary["estimators"]:
        assert e["ok"], e
        assert e["contains_truth"] is (True if e["guaranteed"] else None), e
    job = jobs.load(EXAMPLE)
    for spec in job.estimators:
        if spec.name in ("FRad-B-cora", "PRad-D"):
            z = np.load(tmp_path / "ex" / f"{spec.name}.npz")
            ref = _observe_on_job(job, spec)
            np.testing.assert_array_equal(z["upper"], ref.upper)


def test_zonotope_order_beyond_the_generator_bound_fails_naming_it():
    """zonotope_order x n_x above the API's generator bound: the estimator fails (a FAILED row with
    keep_going), naming zonotope_order, before any work."""
    from setbound.zonotopic import MAX_GENERATORS

    job = jobs.from_dict(_doc([{"method": "FRad-B", "zonotope_order": MAX_GENERATORS}]))
    res = jobs.run_estimator(job, job.estimators[0], keep_going=True, quiet=True)
    assert not res.ok and "zonotope_order" in res.error


def test_interval_a_only_for_the_names_that_take_it():
    """A job with system.A_radius: FRad-A and VolMin-A run on the interval A (the truth, simulated
    with a matrix of [A] drawn at every step, stays inside); the other names fail naming the system
    instead of using the midpoint (which would not be guaranteed)."""
    doc = _doc([{"method": "FRad-A"}, {"method": "VolMin-A"}, {"method": "Hinf-G"}, {"method": "ESO-B"}],
               horizon=30)
    doc["system"]["A_radius"] = [[0.0, 0.0], [0.0, 0.05]]
    doc["simulation"]["A_choice"] = "uniform"
    job = jobs.from_dict(doc)
    fa, va, hg, eb = jobs.run(job, keep_going=True, quiet=True)
    assert fa.ok and fa.contained is True and va.ok and va.contained is True
    for r in (hg, eb):
        assert not r.ok and "system.A_radius is not supported" in r.error


def test_zonotopic_names_take_the_screening_policy_under_setbounds_convention():
    """Every zonotopic CORA name runs on setbound.zonotopic.ZonotopicObserver, whose screening
    policy is a job key (convention "setbound"; CORA tests nothing, so "cora" refuses the key), and
    use_first_measurement belongs to the kinds segment_min / volume_min, not to CORA's names."""
    names = ["FRad-A", "VolMin-A", "VolMin-B", "FRad-B", "FRad-C"]
    job = jobs.from_dict(_doc([{"method": n, "name": n, "on_inconsistency": "raise"} for n in names], horizon=20))
    for r in jobs.run(job, keep_going=True, quiet=True):
        assert r.ok and r.contained is True, (r.name, r.error)
    with pytest.raises(jobs.ConfigError, match="on_inconsistency"):
        jobs.from_dict(_doc([{"method": "FRad-A", "convention": "cora", "on_inconsistency": "raise"}]))
    with pytest.raises(jobs.ConfigError, match="use_first_measurement"):
        jobs.from_dict(_doc([{"method": "FRad-A", "use_first_measurement": False}]))
