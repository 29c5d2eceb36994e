"""The command line end to end: `setbound check/run/compare/demo` on every example file, the
files they write, the summary's contents, and the progress bar."""
import io
import json
import re
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("matplotlib")

from setbound import cli, config, demo  # noqa: E402
from setbound.progress import Progress, set_quiet, track  # noqa: E402
from setbound.zonotopic import MAX_GENERATORS  # noqa: E402  (the job files use the API's bound)

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "examples").glob("*.toml"))
PLOTS = {"bounds.png", "widths.png", "volume.png"}


def test_there_are_examples():
    assert len(EXAMPLES) >= 4


def _png_ok(path: Path):
    assert path.is_file(), path
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert path.stat().st_size > 5_000


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_example_runs_end_to_end(path, tmp_path, capsys):
    assert cli.main(["check", str(path)]) == 0
    assert "ok" in capsys.readouterr().out
    out = tmp_path / "out"
    assert cli.main(["--quiet", "run", str(path), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    job = config.load(path)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["steps"] == len(job.y)
    assert [e["name"] for e in summary["estimators"]] == [s.name for s in job.estimators]
    for e in summary["estimators"]:
        assert e["ok"], e
        assert e["name"] in text
        if e["guaranteed"]:
            assert e["contains_truth"] is True, e
        else:
            assert e["contains_truth"] is None
        z = np.load(out / f"{e['name']}.npz")
        assert z["center"].shape == (len(job.y), job.system.nx)
        np.testing.assert_array_equal(z["x_true"], job.x_true)
        w = z["upper"] - z["lower"]
        assert np.all(w >= 0)
        # the table is computed from the trajectory that was written
        np.testing.assert_allclose(e["mean_width"], w.mean(axis=0), rtol=1e-12)
        np.testing.assert_allclose(e["final_width"], w[-1], rtol=1e-12)
        upto = len(job.y) if job.fault_start is None else job.fault_start  # an injected fault voids the model
        inside = np.all(((z["lower"] <= z["x_true"]) & (z["x_true"] <= z["upper"]))[:upto])
        if e["guaranteed"]:
            assert inside
        # steady-state volume: the design's rho_inf volume where the method has one, else the last set's
        if e["steady_volume_kind"] == "final":
            assert e["steady_volume"] == pytest.approx(z["volume"][-1], rel=1e-12)
        elif e["steady_volume_kind"] == "rho_inf":
            assert e["method"] in ("offline", "descriptor")
            # rho_k -> rho_inf monotonically, so the last volume lies between the first and rho_inf's
            v = z["volume"]
            assert min(v[0], e["steady_volume"]) * (1 - 1e-9) <= v[-1] <= max(v[0], e["steady_volume"]) * (1 + 1e-9)
        assert e["design_time_s"] >= 0 and e["time_per_step_s"] > 0
        rows = (out / f"{e['name']}.csv").read_text().splitlines()
        assert len(rows) == len(job.y) + 1
        assert rows[0].split(",")[:3] == ["k", "t", "center0"]
        last = np.array(rows[-1].split(","), float)
        assert last[1] == z["t"][-1]  # the row's time (the job's time, as in the npz)
        np.testing.assert_allclose(last[2:2 + job.system.nx], z["center"][-1])
    for name in PLOTS | ({"projections.png"} if job.system.nx >= 2 else set()):
        _png_ok(out / name)
    assert (out / "widths_relative.png").is_file() == (len(job.estimators) > 1)


def test_run_without_plots_and_default_out(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    path = ROOT / "examples" / "me17_stable.toml"
    assert cli.main(["run", str(path), "--no-plots", "--quiet"]) == 0
    out = tmp_path / "out" / "me17_stable"
    assert (out / "summary.json").is_file()
    assert not list(out.glob("*.png"))


def test_compare_one_file_with_filter(tmp_path, capsys):
    path = ROOT / "examples" / "bc14_3state.toml"
    out = tmp_path / "cmp"
    assert cli.main(["compare", str(path), "--estimators", "offline,segment_min", "--out", str(out), "-q"]) == 0
    text = capsys.readouterr().out
    summary = json.loads((out / "summary.json").read_text())
    assert [e["name"] for e in summary["estimators"]] == ["offline", "segment_min"]
    assert "online" not in text.split("---")[-1]
    for name in PLOTS | {"widths_relative.png", "projections.png"}:
        _png_ok(out / name)


def test_compare_several_files_of_one_system(tmp_path, capsys):
    src = (ROOT / "examples" / "me17_stable.toml").read_text()
    other = tmp_path / "other.toml"  # the same system, other estimators (and its own, ignored, data)
    other.write_text(src.split("[[estimator]]")[0].replace("seed = 17", "seed = 99")
                     + '[[estimator]]\nmethod = "online"\n[[estimator]]\nmethod = "segment_min"\n')
    out = tmp_path / "cmp"
    assert cli.main(["compare", str(ROOT / "examples" / "me17_stable.toml"), str(other), "--out", str(out), "-q"]) == 0
    names = [e["name"] for e in json.loads((out / "summary.json").read_text())["estimators"]]
    assert names == ["online", "improved", "kalman", "other_online", "segment_min"]
    a, b = np.load(out / "online.npz"), np.load(out / "other_online.npz")
    # same data (the first file's) and same method: the same trajectory
    np.testing.assert_array_equal(a["lower"], b["lower"])


def test_compare_rejects_different_systems_and_unknown_filter(tmp_path, capsys):
    ex = ROOT / "examples"
    assert cli.main(["compare", str(ex / "me17_stable.toml"), str(ex / "me17_unstable.toml"),
                     "--out", str(tmp_path)]) == 2
    assert "different system" in capsys.readouterr().err
    assert cli.main(["compare", str(ex / "me17_stable.toml"), "--estimators", "nope", "--out", str(tmp_path)]) == 2
    assert "--estimators: nope" in capsys.readouterr().err


def test_failed_design_is_listed_not_fatal(tmp_path, capsys):
    """An undetectable pair makes every design fail: each is listed with its reason, exit code 1."""
    text = """
[system]
A = [[1.2, 0], [0, 0.5]]
C = [[0, 1]]
E = [[0.1, 0], [0, 0.1]]
F = [[0, 0.1]]
[initial]
center = [0, 0]
rho = 1.0
[simulation]
horizon = 5
[[estimator]]
method = "offline"
[[estimator]]
method = "pradius"
[[estimator]]
method = "segment_min"
"""
    p = tmp_path / "bad.toml"
    p.write_text(text)
    assert cli.main(["run", str(p), "--out", str(tmp_path / "o"), "-q"]) == 1
    out = capsys.readouterr().out
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    rows = {e["name"]: e for e in summary["estimators"]}
    assert not rows["offline"]["ok"] and "NotDetectable" in rows["offline"]["error"]
    assert not rows["pradius"]["ok"] and rows["pradius"]["error"]
    assert rows["segment_min"]["ok"]  # needs no design: still runs (the set just grows)
    assert out.count("FAILED") == 2
    assert not (tmp_path / "o" / "offline.npz").exists()


def test_demo_short_horizon(tmp_path, capsys):
    out = tmp_path / "demo"
    assert cli.main(["demo", "--out", str(out), "--steps", "6", "-q"]) == 0
    text = capsys.readouterr().out
    summary = json.loads((out / "summary.json").read_text())
    assert summary["steps"] == 6
    methods = {e["method"] for e in summary["estimators"]}
    assert {"offline", "online", "scaled", "improved", "segment_min", "volume_min", "pradius", "kalman"} <= methods
    for e in summary["estimators"]:
        assert e["name"] in text
        if e["ok"]:
            assert (out / f"{e['name']}.npz").is_file()
            if e["guaranteed"]:
                assert e["contains_truth"] is True
        else:  # a design without solution on this system: "not applicable" with the reason
            assert e["error"] and f"not applicable: {e['name']} — its design has no solution" in text
    assert summary["not_applicable"]["pradius"].startswith("its design has no solution for the demo system: no beta")
    assert "FAILED" not in text and "sb_" not in text and "design_pradius" not in text
    for name in PLOTS | {"widths_relative.png", "projections.png"}:
        _png_ok(out / name)


def test_demo_job_is_package_data_and_thesis_hook(monkeypatch, request):
    job, skipped = demo.demo_job(steps=3)
    assert len(job.y) == 3 and job.system.nx == 3
    THESIS = list(demo.THESIS_OBSERVERS)
    # the hook: methods listed in THESIS_OBSERVERS are added when registered, else reported
    # (the registries are shared dicts: their contents are restored after the test)
    for d in (config.ESTIMATORS, config.METHODS):
        request.addfinalizer(lambda d=d, saved=dict(d): (d.clear(), d.update(saved)))
    config.register_estimator("thesis_test", "test", dict(config.ESTIMATORS["segment_min"].options),
                              config.ESTIMATORS["segment_min"].build,
                              description="a stand-in")
    monkeypatch.setattr(demo, "THESIS_OBSERVERS", ["not_registered_yet", "thesis_test"])
    job2, skipped2 = demo.demo_job(steps=3)
    assert skipped2 == ["not_registered_yet"]
    base = [e.name for e in job.estimators if e.method not in THESIS]
    assert [e.name for e in job2.estimators] == base + ["thesis_test"]


class _Tty(io.StringIO):
    def isatty(self):
        return True


def test_progress_bar_only_on_a_terminal():
    tty, pipe = _Tty(), io.StringIO()
    for stream in (tty, pipe):
        with Progress(10, "work", stream=stream, min_interval=0.0) as bar:
            for _ in range(10):
                bar.update()
        assert bar.count == 10
    assert pipe.getvalue() == ""
    text = tty.getvalue()
    assert "work [" in text and "10/10" in text and text.endswith("\n")
    quiet = _Tty()
    assert list(track(range(5), stream=quiet, quiet=True)) == list(range(5))
    assert quiet.getvalue() == ""
    set_quiet(True)
    try:
        silent = _Tty()
        with Progress(3, stream=silent, min_interval=0.0) as bar:
            bar.update(3)
        assert silent.getvalue() == ""
    finally:
        set_quiet(False)


def test_chunked_run_equals_one_run():
    """run_trajectory (the progress-bar path) joins chunks into the same trajectory as one run()."""
    from setbound import ellipsoidal

    job = config.load(ROOT / "examples" / "me17_stable.toml")
    for spec in job.estimators:
        kind = config.ESTIMATORS[spec.method]
        whole = kind.build(job, spec.options)[0].run(job.y, job.u)
        parts = config.run_trajectory(kind.build(job, spec.options)[0], job.y, job.u, chunk=3, quiet=True)
        np.testing.assert_array_equal(whole.lower, parts.lower)
        np.testing.assert_array_equal(whole.upper, parts.upper)
        assert len(parts.sets) == len(whole.sets) and parts.guaranteed == whole.guaranteed
        if isinstance(kind.build(job, spec.options)[0], ellipsoidal.KalmanFilter):
            np.testing.assert_array_equal(whole.covariance, parts.covariance)


def test_run_draws_progress_on_a_terminal_only(tmp_path, monkeypatch, capsys):
    path = ROOT / "examples" / "me17_stable.toml"
    tty = _Tty()
    monkeypatch.setattr("sys.stderr", tty)
    assert cli.main(["run", str(path), "--no-plots", "--out", str(tmp_path / "a")]) == 0
    text = tty.getvalue()
    for name in ("online", "improved", "kalman"):
        assert f"{name} [" in text and "10/10" in text
    tty2 = _Tty()
    monkeypatch.setattr("sys.stderr", tty2)
    assert cli.main(["run", str(path), "--no-plots", "--quiet", "--out", str(tmp_path / "b")]) == 0
    assert tty2.getvalue() == ""
    # the chunked (progress) run gives the same numbers as the plain one
    a, b = np.load(tmp_path / "a" / "online.npz"), np.load(tmp_path / "b" / "online.npz")
    np.testing.assert_array_equal(a["lower"], b["lower"])


# ---------------------------------------------------------------- hostile job files (issue 26 points 4, 5)
HARD = """
[system]
A = [[0.5, 0.1], [0, 0.7]]
B = [[0], [1]]
C = [[1, 0]]
E = [[0.1, 0], [0, 0.1]]
F = [[0, 0.1]]
[initial]
lower = [-1, -1]
upper = [1, 1]
[simulation]
horizon = 20
seed = 1
inputs = ["sin(t)"]
[[estimator]]
method = "segment_min"
"""
NONLINEAR = (ROOT / "examples" / "thesis_ex4_6_3.toml").read_text()
DATA = HARD.replace('[simulation]\nhorizon = 20\nseed = 1\ninputs = ["sin(t)"]\n', "[data]\nfile = 'd.csv'\n")
DATA = DATA.replace("B = [[0], [1]]\n", "")
CSV_OK = "y0,x0,x1\n" + "0.1,0,0\n" * 4


def _cli(tmp_path, text, csv=None, command="check"):
    """``setbound <command> job.toml`` in this process: (exit code, stdout, stderr). An exception
    escaping main() would be the traceback these tests exclude."""
    import contextlib

    p = tmp_path / "job.toml"
    p.write_text(text)
    if csv is not None:
        (tmp_path / "d.csv").write_text(csv)
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = cli.main(["--quiet", command, str(p)] + (["--out", str(tmp_path / "out"), "--no-plots"]
                                                        if command == "run" else []))
    return code, out.getvalue(), err.getvalue()


def _inputs(expr):
    return HARD.replace('inputs = ["sin(t)"]', f'inputs = ["{expr}"]')


HOSTILE = [
    ("1/0 input", _inputs("1/0"), None, r"simulation\.inputs\[0\]: division by zero"),
    ("0**-1", _inputs("0**-1"), None, r"simulation\.inputs\[0\]: division by zero"),
    ("10**10**10", _inputs("10**10**10"), None, r"simulation\.inputs\[0\]: overflow"),
    ("2**1024", _inputs("2**1024"), None, r"simulation\.inputs\[0\]: overflow"),
    ("400 digits", _inputs("9" * 400), None, r"simulation\.inputs\[0\]: a number in .* is beyond the floating-point range .*: an integer of 400 digits"),
    ("(-1)**0.5", _inputs("(-1)**0.5"), None, r"simulation\.inputs\[0\]: an invalid operation"),
    ("100000 minus", _inputs("-" * 100_000 + "1"), None, r"simulation\.inputs\[0\]: the expression is 100001 characters"),
    ("100000 terms", _inputs("+".join(["1"] * 100_000)), None, r"simulation\.inputs\[0\]: the expression is \d+ characters"),
    ("1/(t-2) at t = 2", _inputs("1/(t-2)"), None, r"simulation\.inputs\[0\]: division by zero at step k = 2 \(t = 2\)"),
    ("nested 3000", HARD.replace("A = [[0.5, 0.1], [0, 0.7]]", "A = " + "[" * 3000 + "1" + "]" * 3000), None,
     r"job\.toml: line 3 \(A\): arrays or tables nested too deeply"),
    ("nested 5000", HARD.replace("A = [[0.5, 0.1], [0, 0.7]]", "A = " + "[" * 5000 + "1" + "]" * 5000), None,
     r"job\.toml: line 3 \(A\): arrays or tables nested too deeply"),
    ("nested 30", HARD.replace("A = [[0.5, 0.1], [0, 0.7]]", "A = " + "[" * 30 + "1" + "]" * 30), None,
     r"system\.A(\[0\])+: nested too deeply"),
    ("time.start list", HARD.replace("seed = 1", "seed = 1\ntime = {start = [1]}"), None,
     r"simulation\.time\.start: expected a number"),
    ("time.start string", HARD.replace("seed = 1", 'seed = 1\ntime = {start = "abc"}'), None,
     r"simulation\.time\.start: expected a number"),
    ("seed -1", HARD.replace("seed = 1", "seed = -1"), None, r"simulation\.seed: expected an integer in \[0, "),
    ("max_generators 2**63-1", HARD.replace('method = "segment_min"', 'method = "segment_min"\nmax_generators = '
                                            + str(2**63 - 1)), None,
     r"estimator\[0\]\.max_generators: expected an integer in \[1, " + str(MAX_GENERATORS) + r"\]"),
    ("h = 0.1/(k-2)", NONLINEAR.replace('h = ["p*sin(0.5*k*x2)"', 'h = ["0.1/(k-2)"'), None,
     r"system\.h\[0\]: division by zero at step k = 2"),
    ("horizon 1e8", HARD.replace("horizon = 20", "horizon = 100000000"), None,
     r"simulation\.horizon: 100000000 steps would need about [\d.]+ GiB of memory .* available"),
    ("horizon string", HARD.replace("horizon = 20", 'horizon = "200"'), None,
     r"simulation\.horizon: expected an integer .* got '200'"),
    ("string in matrix", HARD.replace("A = [[0.5, 0.1], [0, 0.7]]", 'A = [[0.5, "0.1"], [0, 0.7]]'), None,
     r"system\.A\[0\]\[1\]: expected a number, got the string '0\.1'"),
    ("boolean in matrix", HARD.replace("A = [[0.5, 0.1], [0, 0.7]]", "A = [[true, 0.1], [0, 0.7]]"), None,
     r"system\.A\[0\]\[0\]: expected a number, got True"),
    ("metod", HARD.replace('method = "segment_min"', 'metod = "segment_min"'), None,
     r"estimator\[0\]\.metod: unknown key \(did you mean 'method'\?\)"),
    ("horizont", HARD.replace("horizon = 20", "horizont = 20"), None,
     r"simulation\.horizont: unknown key \(did you mean 'horizon'\?\)"),
    ("segment_mn", HARD.replace('method = "segment_min"', 'method = "segment_mn"'), None,
     r"estimator\[0\]\.method: unknown method 'segment_mn' \(did you mean 'segment_min'\?\)"),
    ("x0 outside", HARD.replace("seed = 1", "seed = 1\nx0 = [5, 5]"), None,
     r"simulation\.x0: component 0 = 5 is outside the initial box \[-1, 1\]"),
    ("overflowing simulation", HARD.replace("A = [[0.5, 0.1], [0, 0.7]]", "A = [[1e100, 0], [0, 0.7]]"), None,
     r"simulation: the simulated (state|output) is not finite from step k = \d+"),
    ("kalman cov0 shape", HARD.replace('method = "segment_min"', 'method = "kalman"\ncov0 = [[1, 0, 0]]'), None,
     r"estimator\[0\]\.cov0: expected shape \(2, 2\), got \(1, 3\)"),
    ("xhat0 shape", HARD.replace('method = "segment_min"', 'method = "interval_luenberger"\nxhat0 = [0, 0, 0]'), None,
     r"estimator\[0\]\.xhat0: expected shape \(2,\), got \(3,\)"),
    ("400-digit horizon", HARD.replace("horizon = 20", "horizon = " + "9" * 400), None,
     r"simulation\.horizon: an integer of 400 digits is far outside the allowed range"),
    ("5000-digit integer", HARD.replace("horizon = 20", "horizon = " + "9" * 5000), None,
     r"job\.toml: not valid TOML \('Exceeds the limit \(4300 digits\)"),
    ("semicolon csv", DATA, "y0;x0;x1\n3.39;0.00;0\n", r"data\.file: d\.csv, row 1: .* separated by ';'"),
    ("ragged csv", DATA, "y0,x0,x1\n1,0,0\n1,0,0\n1,0,0\n1,0\n", r"data\.file: d\.csv, row 5: 2 columns, the header has 3"),
    ("text in csv", DATA, "y0,x0,x1\n1,0,0\nabc,0,0\n", r"data\.file: d\.csv, row 3, column y0: 'abc' is not a number"),
    ("too many y", DATA, "y0,y1\n1,2\n", r"data\.y: d\.csv has 2 y columns, the system has 1 outputs"),
    ("unknown column", DATA, "y0,speed\n1,2\n", r"data\.file: d\.csv, row 1: unknown column 'speed'"),
    ("gap in columns", DATA, "y0,x0,x2\n1,0,0\n", r"data\.file: d\.csv, row 1: the column x1 is missing"),
    ("x outside initial", DATA, "y0,x0,x1\n1,5,0\n", r"data\.x: component 0 = 5 is outside the initial box"),
    ("inputs for no-input system", DATA, "y0,u0\n1,2\n", r"data\.u: d\.csv has 1 u column, the system has 0 inputs"),
    ("unknown [data] key", DATA.replace("file = 'd.csv'", "file = 'd.csv'\ny = [1]"), CSV_OK,
     r"data\.y: unknown key"),
]


@pytest.mark.parametrize("name, text, csv, message", HOSTILE, ids=[h[0] for h in HOSTILE])
def test_hostile_job_files_exit_2_naming_the_key(name, text, csv, message, tmp_path):
    code, out, err = _cli(tmp_path, text, csv)
    assert code == 2, (out, err)
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("setbound: error: "), err
    assert re.search(message, lines[0]), lines[0]


def test_the_data_base_is_valid(tmp_path):
    code, out, err = _cli(tmp_path, DATA, CSV_OK)
    assert code == 0, err


@pytest.mark.parametrize("command", ["check", "run"])
def test_run_refuses_the_same_files_as_check(command, tmp_path):
    code, _, err = _cli(tmp_path, HARD.replace("seed = 1", "seed = 1\nx0 = [5, 5]"), command=command)
    assert code == 2 and "simulation.x0: component 0 = 5 is outside" in err


def test_check_does_not_simulate_the_horizon(tmp_path, monkeypatch):
    """`check` validates a 10⁷-step job without simulating it (it took 118 s): a trial of the
    first 64 steps; `run` simulates the whole horizon."""
    import setbound.simulation as sim

    seen = []
    real = sim.simulate

    def spy(system, x0, N, **kw):
        seen.append(N)
        return real(system, x0, N, **kw)

    monkeypatch.setattr(sim, "simulate", spy)
    code, out, err = _cli(tmp_path, HARD.replace("horizon = 20", "horizon = 10000000"))
    assert code == 0, err
    assert "10000000 steps" in out and seen == [64]
    code, out, err = _cli(tmp_path, HARD, command="run")
    assert code == 0, err
    assert seen == [64, 20]


def test_check_trial_meets_a_failing_state_expression(tmp_path):
    """A nonlinear h failing at k = 2 is refused by `check`, naming the key and the step."""
    code, _, err = _cli(tmp_path, NONLINEAR.replace('h = ["p*sin(0.5*k*x2)"', 'h = ["0.1/(k-2)"'))
    assert code == 2 and "system.h[0]: division by zero at step k = 2" in err


def test_cli_entry_point_never_prints_a_traceback(tmp_path):
    """The installed entry point (python -m setbound) on hostile files: exit 2, one line."""
    import subprocess
    import sys

    for text in (_inputs("1/0"), HARD.replace("A = [[0.5, 0.1], [0, 0.7]]", "A = " + "[" * 5000 + "1" + "]" * 5000)):
        p = tmp_path / "job.toml"
        p.write_text(text)
        r = subprocess.run([sys.executable, "-m", "setbound", "check", str(p)], capture_output=True, text=True,
                           timeout=120)
        assert r.returncode == 2, r.stderr
        assert "Traceback" not in r.stderr and r.stderr.startswith("setbound: error: ")


def test_version(capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main(["--version"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    assert re.match(r"setbound \S+ \(C library \S+", out), out


def test_user_messages_drop_internal_function_names():
    from setbound.report import user_message

    assert user_message("InfeasibleError: design_pradius: no beta") == "InfeasibleError: no beta"
    assert user_message("sb_zonotopic_create: max_generators: expected") == "max_generators: expected"
    assert user_message("system.A: expected shape (n, 2)") == "system.A: expected shape (n, 2)"
    assert user_message("estimator[0].beta: expected") == "estimator[0].beta: expected"


def test_compare_names_the_file_with_the_error(tmp_path, capsys):
    good, bad = tmp_path / "good.toml", tmp_path / "bad.toml"
    good.write_text(HARD)
    bad.write_text(HARD.replace("horizon = 20", 'horizon = "x"'))
    assert cli.main(["-q", "compare", str(good), str(bad), "--out", str(tmp_path / "o"), "--no-plots"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"setbound: error: {bad}: simulation.horizon: expected an integer") and "Traceback" not in err
