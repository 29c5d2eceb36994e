"""Job files (setbound.config) and the command line (setbound.cli): every example runs end to
end, and malformed files give messages that name the key."""
import json
from pathlib import Path

import numpy as np
import pytest

from setbound import cli, config

EXAMPLES = sorted((Path(__file__).resolve().parents[2] / "examples").glob("*.toml"))


def test_there_are_examples():
    assert len(EXAMPLES) >= 4


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_example_runs_end_to_end(path, tmp_path, capsys):
    assert cli.main(["check", str(path)]) == 0
    assert "ok" in capsys.readouterr().out
    out = tmp_path / "out"
    assert cli.main(["run", str(path), "--out", str(out)]) == 0
    text = capsys.readouterr().out
    job = config.load(path)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["steps"] == len(job.y)
    assert [e["name"] for e in summary["estimators"]] == [s.name for s in job.estimators]
    for e in summary["estimators"]:
        assert e["name"] in text
        if e["guaranteed"]:
            assert e["contains_truth"] is True, e
        z = np.load(out / f"{e['name']}.npz")
        assert z["center"].shape == (len(job.y), job.system.nx)
        assert np.all(z["lower"] <= z["upper"])
        assert (out / f"{e['name']}.csv").read_text().count("\n") == len(job.y) + 1


BASE = """
[system]
A = [[0.5, 0.1], [0, 0.7]]
C = [[1, 0]]
E = [[0.1, 0], [0, 0.1]]
F = [[0, 0.1]]
[initial]
center = [0, 0]
rho = 1.0
[simulation]
horizon = 5
[[estimator]]
method = "offline"
"""


def load_text(tmp_path, text):
    p = tmp_path / "job.toml"
    p.write_text(text)
    return config.load(p)


def test_base_is_valid(tmp_path):
    job = load_text(tmp_path, BASE)
    assert job.y.shape == (5, 1)


@pytest.mark.parametrize("edit, message", [
    (lambda t: t.replace("A = [[0.5, 0.1], [0, 0.7]]", "A = [[0.5, 0.1], [0]]"), r"system\.A: expected a numeric"),
    (lambda t: t.replace("A = [[0.5, 0.1], [0, 0.7]]", "A = [[0.5, 0.1, 0], [0, 0.7, 0]]"), r"system\.A: must be square"),
    (lambda t: t.replace("C = [[1, 0]]", "C = [[1, 0, 0]]"), r"system\.C: expected shape"),
    (lambda t: t.replace("C = [[1, 0]]\n", ""), r"system\.C: missing"),
    (lambda t: t.replace("F = [[0, 0.1]]", 'F = "zero"'), r"system\.F: expected a numeric"),
    (lambda t: t.replace("[system]", "[system]\nAA = 1"), r"system\.AA: unknown key"),
    (lambda t: t.replace("[system]", '[system]\nkind = "nonlinear"'), r"system\.kind"),
    (lambda t: t.replace("rho = 1.0", "rho = -1.0"), r"initial\.rho: must be a positive"),
    (lambda t: t.replace("center = [0, 0]", "center = [0, 0, 0]"), r"initial\.center: expected shape"),
    (lambda t: t.replace("horizon = 5", "horizon = 0"), r"simulation\.horizon"),
    (lambda t: t.replace("horizon = 5", 'horizon = 5\ndisturbance = "laplace"'), r"simulation\.disturbance"),
    (lambda t: t.replace('method = "offline"', 'method = "magic"'), r"estimator\[0\]\.method: unknown method"),
    (lambda t: t.replace('method = "offline"', 'method = "offline"\nspeed = 3'), r"estimator\[0\]\.speed: unknown key"),
    (lambda t: t.replace('method = "offline"', 'method = "descriptor"'), r"estimator\[0\]\.method: 'descriptor' does not apply"),
    (lambda t: t.replace("[[estimator]]\nmethod = \"offline\"\n", ""), r"estimator: at least one"),
    (lambda t: t.replace("[simulation]\nhorizon = 5\n", ""), r"job: exactly one of \[simulation\] and \[data\]"),
    (lambda t: t + "[data]\nfile = 'x.csv'\n", r"job: exactly one of"),
    (lambda t: t.replace("A = [[0.5, 0.1], [0, 0.7]]", "A = [[0.5, nan], [0, 0.7]]"), r"system\.A: contains a non-finite"),
    (lambda t: t.replace("[[estimator]]", "[[estimator]]\nmethod = \"online\"\n[[estimator]]\nname = \"online\""),
     r"estimator\[1\]\.name: duplicate"),
    (lambda t: t.replace("[simulation]\nhorizon = 5\n", "[data]\nfile = 'missing.csv'\n"), r"data\.file: no such file"),
    (lambda t: t.replace("horizon = 5", "horizon = 5\ninputs = ['sin(t)']"), r"simulation\.inputs: the system has no input"),
    (lambda t: t + "extra = 1\n", None),  # a key inside [[estimator]] (TOML puts it there)
    (lambda t: "title = 3\n[system\n", r"not valid TOML"),
])
def test_malformed_files_name_the_key(tmp_path, edit, message):
    text = edit(BASE)
    if message is None:  # 'extra' lands in the last table
        message = r"estimator\[0\]\.extra: unknown key"
    with pytest.raises(config.ConfigError, match=message):
        load_text(tmp_path, text)


def test_cli_reports_errors_with_exit_code_2(tmp_path, capsys):
    p = tmp_path / "bad.toml"
    p.write_text(BASE.replace("rho = 1.0", "rho = 'big'"))
    assert cli.main(["check", str(p)]) == 2
    assert "initial.rho" in capsys.readouterr().err


def test_expressions_of_t(tmp_path):
    t = np.linspace(0, 1, 5)
    np.testing.assert_allclose(config.eval_expression("0.5*sin(t) + 1", t, "k"), 0.5 * np.sin(t) + 1)
    np.testing.assert_allclose(config.eval_expression("-2*cos(pi*t)**2", t, "k"), -2 * np.cos(np.pi * t) ** 2)
    for bad in ("__import__('os')", "t.real", "x + 1", "lambda: 1", "[1, 2]"):
        with pytest.raises(config.ConfigError, match="k:"):
            config.eval_expression(bad, t, "k")


def test_data_files(tmp_path):
    rng = np.random.default_rng(0)
    y = rng.standard_normal((7, 1))
    np.savez(tmp_path / "run.npz", y=y)
    job = load_text(tmp_path, BASE.replace("[simulation]\nhorizon = 5\n", "[data]\nfile = 'run.npz'\n"))
    np.testing.assert_array_equal(job.y, y)
    assert job.x_true is None
    (tmp_path / "run.csv").write_text("y0,x0,x1\n" + "\n".join(f"{v},0,0" for v in y[:, 0]) + "\n")
    job = load_text(tmp_path, BASE.replace("[simulation]\nhorizon = 5\n", "[data]\nfile = 'run.csv'\n"))
    np.testing.assert_allclose(job.y, y)
    assert job.x_true.shape == (7, 2)
