"""Fuzz of the job-file path through the command line (issue 26 point 4): mutations of the
example job files — wrong types, huge integers, hostile expressions, arrays nested thousands
deep, unknown keys, broken CSV data files — are given to ``setbound check``. Whatever the
mutation, the command never raises (no traceback), and it either accepts the file (exit 0) or
refuses it with exit 2 and one line ``setbound: error: <key>: <what>``. The number of cases is
printed at the end of the session (conftest.py)."""
from __future__ import annotations

import contextlib
import io
import math
import re
import tomllib
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from fuzz_support import count, fuzz
from setbound import cli

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = sorted((ROOT / "examples").glob("*.toml")) + [ROOT / "python/setbound/data/demo_bc14.toml"]
DOCS = {p.name: tomllib.loads(p.read_text()) for p in EXAMPLES}
NAMES = sorted(DOCS)
ERROR_LINE = re.compile(r"^setbound: error: [^\s:][^:]*: \S.*$")


# ------------------------------------------------------------ a minimal TOML writer (inline tables)
class Raw(str):
    """TOML text written as it is (an integer too long for Python's int-to-str conversion)."""


def _toml_value(v) -> str:
    if isinstance(v, Raw):
        return str.__str__(v)
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"').replace("\n", "\\n") + '"'
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_toml_key(k)} = {_toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(type(v))


def _toml_key(k: str) -> str:
    return k if re.fullmatch(r"[A-Za-z0-9_-]+", k) else _toml_value(k)


def to_toml(doc: dict) -> str:
    return "".join(f"{_toml_key(k)} = {_toml_value(v)}\n" for k, v in doc.items())


# ------------------------------------------------------------ hostile values
HOSTILE_EXPRESSIONS = ["1/0", "0**-1", "10**10**10", "2**1024", "9" * 400, "(-1)**0.5", "log(-1)", "sqrt(-t)",
                       "-" * 100_000 + "1", "+".join(["1"] * 100_000), "1/(t-2)", "exp(1000*t)", "t.real",
                       "__import__('os')", "(" * 300 + "1" + ")" * 300, "", "sin(", "t**t**t**t", "1e999",
                       "abs(t, t)", "x1 + y", "0/0"]
HOSTILE_SCALARS = ["abc", "0.1", "200", "", True, False, -1, 0, 2**63 - 1, -(2**63), 10**400, Raw("9" * 5000),
                   Raw("-" + "1" * 4400), 1e308, -1e308, math.inf,
                   -math.inf, math.nan, 0.5, [1], [], {"start": [1]}, [[1, 2], [3]], ["0.1", True]]
CSV_BODIES = ["y0;y1\n3.39;0.00\n", "y0,y1,x0,x1\n1,2,3,4\n1,2\n", "y0,y1,y2\n1,2,3\n", "foo,y0\n1,2\n",
              "y0,y1\nabc,1\n", "y0,y1\nnan,1\n", "", "y0,y1\n", "y1,y0,y0\n1,2,3\n", "y0,y2\n1,2\n",
              "\x00\x01\x02", "y0,y1\n" + "1,2\n" * 50, "y0,y1,u0,u1,x0,x1,x2\n" + "0,0,0,0,0,0,0\n" * 5,
              "y0,y1,x0,x1,x2\n" + "0,0,5,5,5\n" * 3, 'y0,y1\n"1,2\n']


def _paths(doc, prefix=()):
    """Every (path, value) of the document, tables and arrays included."""
    out = []
    if isinstance(doc, dict):
        for k, v in doc.items():
            out.append((prefix + (k,), v))
            out.extend(_paths(v, prefix + (k,)))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            out.append((prefix + (i,), v))
            out.extend(_paths(v, prefix + (i,)))
    return out


def _set(doc, path, value):
    for p in path[:-1]:
        doc = doc[p]
    doc[path[-1]] = value


def _delete(doc, path):
    for p in path[:-1]:
        doc = doc[p]
    if isinstance(doc, dict):
        del doc[path[-1]]
    else:
        doc.pop(path[-1])


def _copy(x):
    if isinstance(x, Raw):
        return x
    if isinstance(x, dict):
        return {k: _copy(v) for k, v in x.items()}
    if isinstance(x, list):
        return [_copy(v) for v in x]
    return x


@st.composite
def mutated_job(draw):
    """(TOML text, CSV text or None) of a mutated example."""
    doc = _copy(DOCS[draw(st.sampled_from(NAMES))])
    csv = None
    deep = None
    for _ in range(draw(st.integers(1, 3))):
        paths = _paths(doc)
        op = draw(st.sampled_from(["value", "value", "expression", "delete", "unknown", "misspell", "data",
                                   "deep", "huge"]))
        if op in ("value", "expression", "huge", "delete", "deep") and not paths:
            continue
        if op == "value":
            path, _ = draw(st.sampled_from(paths))
            _set(doc, path, _copy(draw(st.sampled_from(HOSTILE_SCALARS))))
        elif op == "expression":
            exprs = draw(st.lists(st.sampled_from(HOSTILE_EXPRESSIONS), min_size=1, max_size=3))
            where = draw(st.sampled_from(["inputs", "h", "scheduling", "any"]))
            if where == "inputs" and isinstance(doc.get("simulation"), dict):
                doc["simulation"]["inputs"] = exprs
            elif where in ("h", "scheduling") and isinstance(doc.get("system"), dict):
                doc["system"][where] = exprs
            else:
                path, _ = draw(st.sampled_from(paths))
                _set(doc, path, exprs[0])
        elif op == "huge":
            path, _ = draw(st.sampled_from(paths))
            _set(doc, path, draw(st.sampled_from([2**63 - 1, 10**7, 10**8, 2**31, 2**31 - 1])))
        elif op == "delete":
            path, _ = draw(st.sampled_from(paths))
            _delete(doc, path)
        elif op in ("unknown", "misspell"):
            tables = [(p, v) for p, v in [((), doc)] + paths if isinstance(v, dict)]
            path, tab = draw(st.sampled_from(tables))
            if op == "misspell" and tab:
                k = draw(st.sampled_from(sorted(tab)))
                tab[k[:-1] if len(k) > 1 else k + "x"] = tab.pop(k)
            else:
                tab[draw(st.sampled_from(["metod", "horizont", "colour", "Ä", "x" * 300]))] = 1
        elif op == "data":
            doc.pop("simulation", None)
            doc["data"] = {"file": "d.csv"}
            csv = draw(st.sampled_from(CSV_BODIES))
        elif op == "deep":  # arrays nested thousands deep, put in as text (the writer above recurses)
            path, _ = draw(st.sampled_from(paths))
            _set(doc, path, "@@DEEP@@")
            deep = draw(st.sampled_from([20, 3000, 5000]))
    text = to_toml(doc)
    if deep is not None:
        text = text.replace('"@@DEEP@@"', "[" * deep + "1" + "]" * deep)
    return text, csv


def run_check(tmp: Path, text: str, csv: str | None):
    job = tmp / "job.toml"
    job.write_text(text)
    if csv is not None:
        (tmp / "d.csv").write_text(csv)
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = cli.main(["--quiet", "check", str(job)])  # an exception here is the traceback we exclude
    return code, out.getvalue(), err.getvalue()


def test_examples_pass_check(tmp_path):
    for name in NAMES:
        code, out, err = run_check(tmp_path, to_toml(DOCS[name]), None)
        assert code == 0, (name, err)


@fuzz(800)
@given(case=mutated_job())
def test_fuzz_job_files_through_the_cli(case, tmp_path_factory):
    count("test_fuzz_jobs")
    text, csv = case
    tmp = tmp_path_factory.mktemp("fuzzjob")
    code, out, err = run_check(tmp, text, csv)
    assert "Traceback" not in err and "Traceback" not in out
    assert code in (0, 2), (code, err, text[:2000])
    if code == 2:
        lines = err.strip().splitlines()
        assert len(lines) == 1 and ERROR_LINE.match(lines[0]), (err, text[:2000])
        assert " sb_" not in lines[0], lines[0]  # no internal C function names
    else:
        assert ": ok — " in out


@pytest.mark.parametrize("name", NAMES)
def test_unknown_key_names_the_closest(name, tmp_path):
    doc = _copy(DOCS[name])
    doc["simulation" if "simulation" in doc else "data"]["horizont"] = 5
    code, _, err = run_check(tmp_path, to_toml(doc), None)
    assert code == 2 and "horizont: unknown key (did you mean 'horizon'?)" in err
