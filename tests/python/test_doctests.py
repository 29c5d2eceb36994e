"""The ``Examples`` sections of the package's docstrings run as printed (doctest), so the API
reference of the documentation site (``make docs``) shows examples that work.

Every module of setbound is collected (private ones too: their docstrings reach the site through
the public classes that inherit from them). The examples see ``np`` (numpy) and ``setbound``
already imported, as in the site's pages.
"""
from __future__ import annotations

import doctest
import importlib
import pkgutil

import numpy as np
import pytest

import setbound

SKIP = {"setbound.__main__"}  # runs the command line when imported


def _modules():
    names = ["setbound"]
    for m in pkgutil.walk_packages(setbound.__path__, "setbound."):
        if m.name in SKIP or m.name.endswith("libsetbound"):
            continue
        names.append(m.name)
    return names


MODULES = _modules()


def _tests(name):
    mod = importlib.import_module(name)
    finder = doctest.DocTestFinder(exclude_empty=True)
    return [t for t in finder.find(mod, name, globs={"np": np, "setbound": setbound}) if t.examples]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples_run(name, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # examples that write files write them here
    monkeypatch.setenv("MPLBACKEND", "Agg")
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    for test in _tests(name):
        runner.run(test)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{result.failed} docstring example(s) of {name} failed (output above)"


def test_the_api_has_examples():
    # the main classes and functions carry an Examples section that runs
    count = sum(len(t.examples) for name in MODULES for t in _tests(name))
    assert count >= 220, f"only {count} doctest examples in the package (there were 227 in 82 docstrings)"
