"""Studies (issue 23) without an external cluster: the [study] grid and its errors, the result
store (torn lines, resume, refusal of other options, duplicates), pickling of task arguments and
results, the serial path and the embedded LocalCluster, `setbound study` on the command line.
The external-cluster scenarios (killed worker, killed driver, crashing case) are in
test_study_cluster.py."""
from __future__ import annotations

import json
import os
import pickle
import subprocess
import sys
import time
from pathlib import Path

import pytest

from setbound import campaign, cli
from setbound.jobs import ConfigError
from setbound.jobs.study import load_study
from setbound.studies import (Engine, NondeterminismError, ResultStore, StoreError, run_cases, run_chunk,
                              run_one_case, run_study)
from setbound.studies.tasks import study_case

from study_support import STUDY, records, without_timing, write_study

REPO = Path(__file__).resolve().parents[2]


# ---------------------------------------------------------------- the grid
def test_grid_expands_seeds_parameters_and_estimators(tmp_path):
    st = load_study(write_study(tmp_path / "s.toml", seeds=3))
    cases = list(st.cases())
    # segment_min: 3 seeds × noise_scale (2) × max_generators (2); kalman has no max_generators: 3 × 2
    assert st.size == len(cases) == 3 * 4 + 3 * 2
    assert [c["i"] for c in cases] == list(range(len(cases)))
    assert len({c["key"] for c in cases}) == len(cases)
    assert {c["seed"] for c in cases} == {100, 101, 102}  # seeds = 3 starts at simulation.seed
    kal = [c for c in cases if c["estimator"] == "kalman"]
    assert all(set(c["params"]) == {"noise_scale"} for c in kal)
    seg = [c for c in cases if c["estimator"] == "segment_min"]
    assert {(c["params"]["noise_scale"], c["params"]["max_generators"]) for c in seg} == {
        (0.5, 4), (0.5, 8), (2.0, 4), (2.0, 8)}


def _study_file(tmp_path, study_lines: str, name: str = "bad.toml", **fmt) -> str:
    text = STUDY.format(seeds=2, horizon=10).split("[study]")[0] + study_lines
    p = tmp_path / name
    p.write_text(text)
    return str(p)


@pytest.mark.parametrize("lines,key", [
    ("[study]\nseeds = 2\n[study.parameters]\nnoise_level = [1.0]\n", "study.parameters.noise_level"),
    ("[study]\n[study.parameters]\nhorizon = []\n", "study.parameters.horizon"),
    ("[study]\n[study.parameters]\nhorizon = [10, 0]\n", "study.parameters.horizon[1]"),
    ("[study]\n[study.parameters]\nhorizon = 10\n", "study.parameters.horizon"),
    ("[study]\n[study.parameters]\nnoise_scale = [1.0, -2.0]\n", "study.parameters.noise_scale[1]"),
    ("[study]\n[study.parameters]\nmax_generators = [4, 0]\n", "study.parameters.max_generators[1]"),
    ("[study]\n[study.parameters]\n\"kalman.max_generators\" = [4]\n", "study.parameters.kalman.max_generators"),
    ("[study]\n[study.parameters]\n\"nope.nsigma\" = [4]\n", "study.parameters.nope.nsigma"),
    ("[study]\n[study.parameters]\n\"simulation.disturbance\" = [\"uniform\", \"wild\"]\n",
     "study.parameters.simulation.disturbance[1]"),
    ("[study]\n[study.parameters]\n\"simulation.seed\" = [1]\n", "study.parameters.simulation.seed"),
    ("[study]\nseeds = 0\n", "study.seeds"),
    ("[study]\nseeds = [1, 1]\n", "study.seeds"),
    ("[study]\nseeds = 1.5\n", "study.seeds"),
    ("[study]\nseeds = {start = 3}\n", "study.seeds.count"),
    ("[study]\nsedes = 3\n", "study.sedes"),
    ("[study]\nestimators = [\"segment_min\", \"offline\"]\n", "study.estimators[1]"),
    ("[study]\nestimators = []\n", "study.estimators"),
    ("[study]\nexact_hull = 1\n", "study.exact_hull"),
])
def test_study_file_errors_name_the_key(tmp_path, lines, key):
    with pytest.raises(ConfigError) as ei:
        load_study(_study_file(tmp_path, lines))
    assert str(ei.value).startswith(key + ":"), str(ei.value)


def test_study_must_be_a_table(tmp_path):
    p = tmp_path / "t.toml"
    p.write_text("study = 3\n" + STUDY.format(seeds=2, horizon=10).split("[study]")[0])
    with pytest.raises(ConfigError, match="^study: expected a table"):
        load_study(p)


def test_unknown_parameter_suggests_the_closest(tmp_path):
    with pytest.raises(ConfigError, match="did you mean 'noise_scale'"):
        load_study(_study_file(tmp_path, "[study]\n[study.parameters]\nnoise_scal = [1.0]\n"))


def test_study_needs_a_simulation(tmp_path):
    text = STUDY.format(seeds=2, horizon=10).replace("[simulation]\nhorizon = 10\nseed = 100\n",
                                                       "[data]\nfile = \"y.csv\"\n")
    (tmp_path / "y.csv").write_text("y0\n0.1\n0.2\n")
    (tmp_path / "d.toml").write_text(text)
    with pytest.raises(ConfigError, match=r"^study: needs a \[simulation\]"):
        load_study(tmp_path / "d.toml")


def test_noise_scale_scales_the_disturbance_and_cases_are_deterministic(tmp_path):
    st = load_study(write_study(tmp_path / "s.toml", seeds=1))
    ctx = st.context()
    by = {(c["estimator"], c["params"].get("noise_scale"), c["params"].get("max_generators")): c for c in st.cases()}
    small = study_case(ctx, by[("segment_min", 0.5, 8)])
    large = study_case(ctx, by[("segment_min", 2.0, 8)])
    assert small["status"] == large["status"] == "ok" and small["contained"] and large["contained"]
    assert small["steps"] == 40
    # four times the disturbance bounds: wider sets (the initial box is the same)
    assert large["mean_width"] > 1.5 * small["mean_width"]
    again = study_case(ctx, by[("segment_min", 0.5, 8)])
    assert without_timing(again) == without_timing(small)


# ---------------------------------------------------------------- task arguments and results
def test_task_arguments_and_results_round_trip_through_pickle(tmp_path):
    st = load_study(write_study(tmp_path / "s.toml", seeds=1))
    ctx, cases = st.context(), list(st.cases())[:3]
    assert pickle.loads(pickle.dumps(ctx)) == ctx
    assert pickle.loads(pickle.dumps(cases)) == cases
    res = run_chunk("setbound.studies.tasks:study_case", ctx, cases)
    back = pickle.loads(pickle.dumps(res))
    assert back == res and len(res["records"]) == 3
    for r in res["records"]:
        json.dumps(r, allow_nan=False)  # plain JSON data: no numpy, no cffi object
    # the campaign's task as well
    crec = campaign.campaign_case({"max_nx": 2, "max_steps": 20}, {"i": 0, "key": "k", "estimator": "pradius",
                                                                   "seed": 3})
    assert pickle.loads(pickle.dumps(crec)) == crec and crec["reproduce"].startswith("python -m setbound.campaign")
    json.dumps(crec)


def test_a_raising_case_is_recorded_and_the_chunk_goes_on(tmp_path):
    st = load_study(write_study(tmp_path / "s.toml", seeds=1))
    cases = list(st.cases())[:2]
    bad = dict(cases[0], estimator="nonexistent")
    res = run_chunk("setbound.studies.tasks:study_case", st.context(), [bad, cases[1]])
    assert res["records"][0]["status"] == "error" and res["records"][0]["key"] == bad["key"]
    assert res["records"][1]["status"] == "ok"


# ---------------------------------------------------------------- store
def test_torn_last_line_is_redone_and_resume_runs_only_the_missing(tmp_path):
    path = write_study(tmp_path / "s.toml", seeds=2)
    out = tmp_path / "out"
    first = run_study(path, out=out, processes=1, plots=False, quiet=True)
    assert first.cases == 12 and first.stats.records == 12 and first.already == 0
    part = out / "results" / "part-00000.jsonl"
    lines = part.read_bytes().split(b"\n")[:-1]
    # the driver killed in the middle of writing the last line, and of the one before
    torn_key = json.loads(lines[-1])["key"]
    part.write_bytes(b"\n".join(lines[:-1]) + b"\n" + lines[-1][: len(lines[-1]) // 2])
    again = run_study(path, out=out, processes=1, plots=False, quiet=True)
    assert again.already == 11 and again.stats.records == 1
    new = [json.loads(x) for x in (out / "results" / "part-00001.jsonl").read_bytes().split(b"\n")[:-1]]
    assert [r["key"] for r in new] == [torn_key]
    assert again.summary.torn == 1 and again.summary.cases == 12
    # nothing missing: a third run runs nothing
    third = run_study(path, out=out, processes=1, plots=False, quiet=True)
    assert third.stats.records == 0 and third.summary.cases == 12


def test_resume_with_other_options_is_refused(tmp_path):
    path = write_study(tmp_path / "s.toml", seeds=1)
    out = tmp_path / "out"
    run_study(path, out=out, processes=1, plots=False, quiet=True)
    write_study(tmp_path / "s.toml", seeds=2)
    with pytest.raises(StoreError, match=r"^out: .*other options"):
        run_study(path, out=out, processes=1, plots=False, quiet=True)
    with pytest.raises(StoreError, match="already holds results"):
        write_study(tmp_path / "s.toml", seeds=1)
        run_study(path, out=out, processes=1, plots=False, quiet=True, resume=False)
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "x.txt").write_text("mine")
    with pytest.raises(StoreError, match="not empty and holds no manifest"):
        run_study(path, out=tmp_path / "other", processes=1, plots=False, quiet=True)


def test_duplicates_must_be_identical(tmp_path):
    path = write_study(tmp_path / "s.toml", seeds=1)
    out = tmp_path / "out"
    run_study(path, out=out, processes=1, plots=False, quiet=True)
    rec = records(out)[0]
    extra = out / "results" / "part-00007.jsonl"
    extra.write_text(json.dumps(dict(rec, seconds=99.0)) + "\n")  # same result, other timing: fine
    res = run_study(path, out=out, processes=1, plots=False, quiet=True)
    assert res.summary.duplicates == 1 and res.summary.cases == 6
    extra.write_text(json.dumps(dict(rec, mean_width=rec["mean_width"] * 1.001)) + "\n")
    with pytest.raises(NondeterminismError, match=rec["key"].replace("[", r"\[")):
        run_study(path, out=out, processes=1, plots=False, quiet=True)


def test_a_damaged_middle_line_is_an_error_naming_the_file(tmp_path):
    st = {"kind": "t", "options": {}}
    store = ResultStore(tmp_path / "o", st)
    store.append([{"i": 0, "key": "a"}, {"i": 1, "key": "b"}])
    store.close()
    p = store.files()[0]
    p.write_bytes(b'{"i": 0, "key": "a"}\n{garbage\n{"i": 1, "key": "b"}\n')
    with pytest.raises(StoreError, match=r"part-00000.jsonl: line 2"):
        list(ResultStore(tmp_path / "o", st).records())


# ---------------------------------------------------------------- engines
def test_serial_and_embedded_cluster_give_the_same_records(tmp_path):
    path = write_study(tmp_path / "s.toml", seeds=4)  # 24 cases
    serial = run_study(path, out=tmp_path / "a", processes=1, quiet=True)
    t0 = time.monotonic()
    par = run_study(path, out=tmp_path / "b", processes=2, quiet=True, timeout=60)
    assert time.monotonic() - t0 < 120
    a = sorted((without_timing(r) for r in records(tmp_path / "a")), key=lambda r: r["i"])
    b = sorted((without_timing(r) for r in records(tmp_path / "b")), key=lambda r: r["i"])
    assert len(a) == 24 and a == b
    assert all(r["status"] == "ok" for r in a)
    assert all(r["contained"] for r in a if r["method"] == "segment_min")
    assert all(r["contained"] is None for r in a if r["method"] == "kalman")  # not a guaranteed method
    timing = ("us_per_step_median", "design_s_median")
    assert [{k: v for k, v in r.items() if k not in timing} for r in serial.summary.rows] == \
        [{k: v for k, v in r.items() if k not in timing} for r in par.summary.rows]
    for name in ("summary.csv", "summary.json", "widths.png", "containment.png", "width_vs_noise_scale.png",
                 "width_vs_max_generators.png", "manifest.json"):
        assert (tmp_path / "b" / name).stat().st_size > 0, name
    man = json.loads((tmp_path / "b" / "manifest.json").read_text())
    assert man["schema"] == 1 and man["kind"] == "study" and man["options"]["cases"] == 24


def test_chunking_and_back_pressure():
    # 400 cases of ~1 ms with chunks of ~0.05 s (at most 20 cases): far fewer tasks than cases, and
    # the case iterator is pulled lazily, one chunk ahead of the saved records at most
    pulled, saved, ahead = [0], [], []

    def cases():
        for i in range(400):
            pulled[0] += 1
            ahead.append(pulled[0] - len(saved))
            yield {"i": i, "key": str(i), "seconds": 0.001}

    stats = run_cases("setbound.studies.tasks:busy_case", cases(), saved.extend, chunk_seconds=0.05, max_chunk=20)
    assert stats.records == 400 and sorted(r["i"] for r in saved) == list(range(400))
    assert max(ahead) <= 20
    assert 20 <= stats.tasks < 60


def test_engine_options_are_checked():
    with pytest.raises(ValueError, match="^scheduler_file: give one of"):
        Engine(scheduler="tcp://127.0.0.1:1", scheduler_file="x")
    with pytest.raises(ValueError, match="^processes:"):
        Engine(processes=0)
    with pytest.raises(ValueError, match="^timeout:"):
        Engine(timeout=-1)
    with pytest.raises(ValueError, match="^task:"):
        run_cases("setbound.nothing:here", [], lambda r: None)


# ---------------------------------------------------------------- command line
def test_cli_study_run_resume_and_case(tmp_path, capsys):
    path = write_study(tmp_path / "s.toml", seeds=1)
    out = tmp_path / "out"
    assert cli.main(["--quiet", "study", path, "--processes", "1", "--out", str(out), "--no-plots"]) == 0
    text = capsys.readouterr().out
    assert "6 cases (0 already recorded, 6 run now" in text and "segment_min" in text
    assert cli.main(["--quiet", "study", path, "--processes", "1", "--out", str(out), "--no-plots"]) == 0
    assert "6 cases (6 already recorded, 0 run now" in capsys.readouterr().out
    key = records(out)[0]["key"]
    assert cli.main(["study", path, "--case", key]) == 0
    rec = json.loads(capsys.readouterr().out)
    assert without_timing(rec) == without_timing(records(out)[0])
    assert cli.main(["study", path, "--case", "estimator=x;seed=1"]) == 2
    assert "case: no case" in capsys.readouterr().err
    assert cli.main(["check", path]) == 0
    assert "study: 6 cases" in capsys.readouterr().out


def test_cli_study_errors_exit_2(tmp_path, capsys):
    bad = _study_file(tmp_path, "[study]\n[study.parameters]\nnoise_level = [1.0]\n")
    assert cli.main(["study", bad, "--processes", "1", "--out", str(tmp_path / "o")]) == 2
    assert "setbound: error: study.parameters.noise_level: unknown parameter" in capsys.readouterr().err
    assert cli.main(["check", bad]) == 2
    assert "study.parameters.noise_level" in capsys.readouterr().err


def test_run_one_case_reproduces_a_record(tmp_path):
    path = write_study(tmp_path / "s.toml", seeds=1)
    st = load_study(path)
    c = list(st.cases())[-1]
    assert without_timing(run_one_case(path, c["key"])) == without_timing(study_case(st.context(), c))


def test_example_study_is_valid():
    st = load_study(REPO / "examples" / "study_noise_sweep.toml")
    assert st.size >= 60


def test_campaign_serial_path_runs_in_process(monkeypatch):
    # processes=1: no cluster, the cases run in this process (the patched function is called here)
    calls = []
    real = campaign.run_case

    def counting(*a, **kw):
        calls.append(a[:2])
        return real(*a, **kw)

    monkeypatch.setattr(campaign, "run_case", counting)
    s = campaign.run_campaign(["interval_luenberger"], steps=100, processes=1, max_nx=2, max_steps=40)
    r = s["interval_luenberger"]
    assert r["steps"] >= 100 and not r["violations"] and r["crashed"] == []
    assert r["seeds"][0] == 0 and r["systems"] == r["seeds"][1] + 1 == len(calls)  # seeds 0 .. k, each once
    assert sorted(seed for _, seed in calls) == list(range(len(calls)))


def test_campaign_cli_flags_keep_working(tmp_path):
    out = tmp_path / "c.json"
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(REPO / "python"), os.environ.get("PYTHONPATH", "")])}
    p = subprocess.run([sys.executable, "-m", "setbound.campaign", "--estimator", "interval_luenberger", "--steps", "200",
                        "--processes", "1", "--seed0", "5", "--max-nx", "2", "--max-steps", "40", "--time-limit", "30",
                        "--json", str(out)], capture_output=True, text=True, timeout=120, env=env)
    assert p.returncode == 0, p.stderr
    doc = json.loads(out.read_text())
    assert doc["estimators"]["interval_luenberger"]["seeds"][0] == 5
    assert doc["estimators"]["interval_luenberger"]["steps"] >= 200


def test_campaign_checkpoints_every_case_and_resumes_where_it_stopped(tmp_path, monkeypatch):
    from setbound.studies.store import StoreError

    out = tmp_path / "campaign"
    kw = dict(processes=1, max_nx=2, max_steps=30)
    first = campaign.run_campaign(["interval_luenberger"], steps=60, out=out, **kw)["interval_luenberger"]
    lines = [ln for p in sorted((out / "results").glob("part-*.jsonl")) for ln in p.read_text().splitlines()]
    assert len(lines) == first["systems"] > 1 and first["resumed_cases"] == 0  # one line per finished case

    calls = []
    real = campaign.run_case

    def counting(*a, **k):
        calls.append(a[1])
        return real(*a, **k)

    monkeypatch.setattr(campaign, "run_case", counting)
    second = campaign.run_campaign(["interval_luenberger"], steps=150, out=out, resume=True, **kw)["interval_luenberger"]
    assert second["resumed_cases"] == first["systems"]
    assert min(calls) == first["systems"] and len(calls) == second["systems"] - first["systems"]  # only new seeds ran
    assert len(list((out / "results").glob("part-*.jsonl"))) == 2  # the resume wrote a part of its own
    monkeypatch.setattr(campaign, "run_case", real)
    fresh = campaign.run_campaign(["interval_luenberger"], steps=150, **kw)["interval_luenberger"]
    for key in ("systems", "steps", "unverified", "families", "max_excess", "seeds", "false_alarms"):
        assert second[key] == fresh[key], key  # resuming changes nothing but the time
    # a resume already past its target runs nothing
    calls.clear()
    monkeypatch.setattr(campaign, "run_case", counting)
    again = campaign.run_campaign(["interval_luenberger"], steps=100, out=out, resume=True, **kw)["interval_luenberger"]
    assert calls == [] and again["steps"] == second["steps"]
    # refused: results there without resume, and a resume whose cases would differ
    with pytest.raises(StoreError, match="already holds results"):
        campaign.run_campaign(["interval_luenberger"], steps=10, out=out, **kw)
    with pytest.raises(StoreError, match="max_nx"):
        campaign.run_campaign(["interval_luenberger"], steps=10, out=out, resume=True, processes=1, max_nx=3, max_steps=30)


def test_campaign_cli_resume_needs_out():
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(REPO / "python"), os.environ.get("PYTHONPATH", "")])}
    p = subprocess.run([sys.executable, "-m", "setbound.campaign", "--resume"], capture_output=True, text=True,
                       timeout=60, env=env)
    assert p.returncode == 2 and "--resume needs --out" in p.stderr


def test_study_modules_document_their_public_names():
    # test_docs walks the top-level modules; the studies package's own modules are checked here
    import importlib

    from test_docs import _undocumented

    mods = ["setbound.studies." + m for m in ("engine", "executor", "store", "study", "summary", "tasks", "cli")]
    missing = [n for m in mods for n in _undocumented(importlib.import_module(m))]
    missing += _undocumented(importlib.import_module("setbound.jobs.study"))
    assert not missing, missing


def test_exact_hull_ratio_is_at_least_one(tmp_path):
    # every guaranteed estimator's hull contains the exact one: mean width ratio >= 1
    text = STUDY.format(seeds=2, horizon=15).split("[study]")[0] + (
        "[study]\nseeds = 2\nestimators = [\"segment_min\"]\nexact_hull = true\n"
        "[study.parameters]\nmax_generators = [3, 12]\n")
    (tmp_path / "h.toml").write_text(text)
    res = run_study(tmp_path / "h.toml", out=tmp_path / "o", processes=1, plots=False, quiet=True)
    recs = records(tmp_path / "o")
    assert len(recs) == 4 and all(r["status"] == "ok" for r in recs)
    ratios = {r["params"]["max_generators"]: r["hull_ratio"] for r in recs if r["seed"] == 100}
    assert all(v >= 1 - 1e-9 for v in ratios.values()), ratios
    assert ratios[3] >= ratios[12] - 1e-9  # fewer generators: a coarser set
    assert res.summary.rows[0]["hull_ratio"] >= 1 - 1e-9
