"""Running a study file (a job file with ``[study]``, :mod:`setbound.jobs.study`): :func:`run_study`,
the engine of ``setbound study FILE``, and :func:`run_one_case` (``setbound study FILE --case KEY``).
"""
from __future__ import annotations

import shlex
from dataclasses import dataclass, field
from pathlib import Path

from .._validate import as_bool, as_float, as_str
from ..jobs.study import load_study
from .engine import Engine
from .executor import RunStats, run_cases
from .store import ResultStore, is_done
from .summary import StudySummary, summarize, write_study_plots, write_summary
from .tasks import study_case

__all__ = ["run_study", "run_one_case", "StudyResult", "STUDY_TASK"]

#: The task of a study case (see :mod:`setbound.studies.executor`).
STUDY_TASK = "setbound.studies.tasks:study_case"


@dataclass
class StudyResult:
    """What :func:`run_study` did: the output folder, the number of cases of the grid, the cases
    run now (``stats.records``; the others were already recorded), the summary rebuilt from the
    files and the files written.

    Parameters
    ----------
    out : Path
        Output folder.
    cases : int
        Cases of the grid.
    already : int
        Cases recorded before this run.
    stats : RunStats
        What this run did.
    summary : StudySummary
        The summary.
    files : list of Path, optional
        Files written.
    """

    out: Path
    cases: int
    already: int
    stats: RunStats
    summary: StudySummary
    files: list = field(default_factory=list)

    @property
    def ok(self) -> bool:
        """No case left its guaranteed set, crashed or raised."""
        return not (self.summary.leaked or self.summary.crashed or self.summary.errors)


def _reproducer(source: str):
    def reproduce(case) -> str:
        return f"setbound study {shlex.quote(source)} --case {shlex.quote(case['key'])}"
    return reproduce


def run_study(path, *, out=None, client=None, scheduler=None, scheduler_file=None, processes=None,
              resume: bool = True, timeout: float = 30.0, chunk_seconds: float = 1.0, plots: bool = True,
              quiet: bool = False, sink=None) -> StudyResult:
    """Runs the study file ``path`` and writes into ``out`` (default ``out/<file stem>``): the
    manifest, the per-case records (``results/part-*.jsonl``), ``summary.csv``/``summary.json``
    and the plots (``widths.png``, ``width_vs_<parameter>.png``, ``containment.png``).

    Engine (:class:`~setbound.studies.engine.Engine`): ``client`` (yours, left open),
    ``scheduler`` (``tcp://HOST:PORT``), ``scheduler_file``, or an embedded LocalCluster of
    ``processes`` workers (default: one per core); ``processes=1`` runs serially in this process.
    ``timeout``: seconds to reach a scheduler. ``resume``: an existing output folder of the same
    study is continued (only the missing cases run); False refuses a folder that holds results.
    ``chunk_seconds``: target work per task. ``sink(records)``: also called with each batch saved
    (after it is on disk).

    Parameters
    ----------
    path : str or Path
        The study file.
    out : str or Path, optional
        Output folder.
    client, scheduler, scheduler_file, processes : optional
        The engine (see above).
    resume : bool, optional
        Continue an existing output folder.
    timeout : float, optional
        Seconds to reach a scheduler.
    chunk_seconds : float, optional
        Target work per task.
    plots : bool, optional
        Write the plots.
    quiet : bool, optional
        No progress output.
    sink : callable, optional
        Called with each batch saved.

    Returns
    -------
    StudyResult
    """
    source = str(as_str(path, "path") if not isinstance(path, Path) else path)
    resume = as_bool(resume, "resume")
    plots = as_bool(plots, "plots")
    quiet = as_bool(quiet, "quiet")
    timeout = as_float(timeout, "timeout", lo=0, lo_open=True, hi=86400)
    chunk_seconds = as_float(chunk_seconds, "chunk_seconds", lo=0, hi=86400)
    study = load_study(source)
    out = Path(out) if out is not None else Path("out") / Path(source).stem
    n = study.size
    manifest = {"kind": "study", "options": {"fingerprint": study.fingerprint(), "cases": n},
                "source": source, "parameters": list(study.parameters), "estimators": study.estimators}
    engine = Engine(client=client, scheduler=scheduler, scheduler_file=scheduler_file, processes=processes,
                    timeout=timeout)
    with ResultStore(out, manifest, resume=resume) as store:
        bits = store.done(n)
        already = sum(bin(b).count("1") for b in bits)
        todo = (c for c in study.cases() if not is_done(bits, c["i"]))
        stats = RunStats()
        if already < n:
            def save(records):
                store.append(records)
                if sink is not None:
                    sink(records)

            with engine:
                stats = run_cases(STUDY_TASK, todo, save, context=study.context(), engine=engine, total=n - already,
                                  chunk_seconds=chunk_seconds, reproduce=_reproducer(source), label="cases",
                                  quiet=quiet)
        store.close()
        summary = summarize(store)
    extra = {"source": source, "engine": engine.where, "ran_now": stats.records, "seconds": round(stats.seconds, 3)}
    files = write_summary(out, summary, extra)
    if plots:
        files += write_study_plots(out, summary)
    return StudyResult(out, n, already, stats, summary, files)


def run_one_case(path, key: str) -> dict:
    """Runs the case ``key`` of the study file ``path`` in this process (no cluster, nothing
    written) and returns its record: the reproduction of a crashed or failed case.

    Parameters
    ----------
    path : str or Path
        The study file.
    key : str
        The case key.

    Returns
    -------
    dict
    """
    key = as_str(key, "key")
    study = load_study(path)
    for case in study.cases():
        if case["key"] == key:
            return study_case(study.context(), case)
    example = next(study.cases())["key"]
    raise ValueError(f"case: no case {key!r} in this study (keys look like {example!r})")
