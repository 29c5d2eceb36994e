"""Studies and campaigns on a distributed engine (Dask, issue 23).

One concept per module::

    engine    Engine: embedded LocalCluster, an existing scheduler, the caller's client, or serial
    executor  run_cases / run_chunk: chunking, back-pressure, crashed cases
    store     ResultStore: manifest + append-only JSON-lines results, torn lines, resume
    tasks     study_case, busy_case: what workers run (plain data in, plain data out)
    summary   summarize, format_summary, write_summary, write_study_plots (from the files)
    study     run_study, run_one_case: `setbound study FILE`

The grid of a study is the ``[study]`` section of a job file (:mod:`setbound.jobs.study`). The
guarantee campaign (:mod:`setbound.campaign`) runs on :func:`run_cases` as well.
"""
from __future__ import annotations

from .engine import Engine, SchedulerUnreachable, default_processes
from .executor import RunStats, run_cases, run_chunk
from .store import ResultStore, StoreError
from .study import StudyResult, run_one_case, run_study
from .summary import NondeterminismError, StudySummary, format_summary, summarize

__all__ = ["Engine", "SchedulerUnreachable", "default_processes", "RunStats", "run_cases", "run_chunk",
           "ResultStore", "StoreError", "StudyResult", "run_study", "run_one_case", "NondeterminismError",
           "StudySummary", "format_summary", "summarize"]
