"""Shared pieces of the study tests: small study files and a task that kills its worker.

This module is imported by the Dask workers of tests/python/test_study_cluster.py (their
PYTHONPATH holds tests/python), so its task is a module-level function of plain data like the
package's own."""
from __future__ import annotations

import json
import os

from setbound.studies.tasks import TIMING_FIELDS, study_case

# 2 states, two cheap estimators (zonotopic, Kalman): a case takes
# about 10-30 ms (horizon 40), or about 100 ms with the horizon the slow variant sets.
STUDY = """
title = "study test"
[system]
A = [[0.9, 0.2], [0.0, 0.7]]
C = [[1.0, 0.0]]
E = [[0.05, 0.0], [0.0, 0.05]]
F = [[0.0, 0.1]]
[initial]
lower = [-1.0, -1.0]
upper = [1.0, 1.0]
[simulation]
horizon = {horizon}
seed = 100
[[estimator]]
method = "segment_min"
[[estimator]]
method = "kalman"
[study]
seeds = {seeds}
[study.parameters]
noise_scale = [0.5, 2.0]
max_generators = [4, 8]
"""


def write_study(path, *, seeds: int = 10, horizon: int = 40) -> str:
    """A study file of ``seeds`` × (segment_min: 2 × 2 values; kalman: 2 values) cases:
    6 · seeds cases (60 with the default)."""
    path.write_text(STUDY.format(seeds=seeds, horizon=horizon))
    return str(path)


def crash_on(context: dict, case: dict) -> dict:
    """:func:`setbound.studies.tasks.study_case`, except that the cases named in
    ``context["crash_keys"]`` end their worker process at once (as a segfault would)."""
    if case["key"] in context["crash_keys"]:
        os._exit(17)
    return study_case(context, case)


def records(out) -> list:
    """Every complete record of the folder ``out`` (all part files, torn last lines left out)."""
    recs = []
    for p in sorted((out / "results").glob("part-*.jsonl")):
        for line in p.read_bytes().split(b"\n")[:-1]:
            recs.append(json.loads(line))
    return recs


def without_timing(rec: dict) -> dict:
    """The record without its timing fields (what two runs of a case must agree on)."""
    return {k: v for k, v in rec.items() if k not in TIMING_FIELDS}
