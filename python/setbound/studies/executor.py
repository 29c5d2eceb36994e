"""Running many cases on an :class:`~setbound.studies.engine.Engine`: :func:`run_cases`.

A *task* is a module-level function ``f(context, case) -> record`` of an importable module, named
``"package.module:function"``; ``context`` and ``case`` are plain data (names, seeds, option
dicts, lists, arrays) and the record a JSON-able dict. The worker builds every C object itself:
no cffi object is ever pickled. :func:`run_chunk` is what a worker runs: the task on a list of
cases (one chunk), each case timed, a Python exception of a case kept as that case's record
(``status = "error"``) rather than losing the chunk.

The driver (:func:`run_cases`):

* cuts the cases into chunks of about ``chunk_seconds`` of work (the first chunks hold one case;
  then the size follows the measured time per case), so that 10 ms cases do not pay a scheduler
  round trip each;
* keeps at most ``max_in_flight`` chunks submitted (default twice the cluster's threads) and pulls
  the next cases only then (back-pressure: millions of cases are never all in memory);
* hands each finished chunk's records to ``sink`` (e.g. the result store, which writes and fsyncs
  them) and then releases the future;
* a finished chunk whose result cannot be fetched within 10 s (it was held by a worker that died
  since) is submitted again: its records were never saved, so nothing is recorded twice;
* a chunk whose worker died (Dask retries it on other workers first, up to the scheduler's
  ``distributed.scheduler.allowed-failures``, then raises ``KilledWorker``) is split into single
  cases; a single case that meets ``KilledWorker`` is run once more *alone* (nothing else in
  flight, so a case that only shared a worker with the culprit is not blamed), and if it still
  kills its worker it is recorded with ``status = "crashed"`` and its reproduction command. The
  other cases complete.
"""
from __future__ import annotations

import importlib
import itertools
import time
from collections import deque
from dataclasses import dataclass

from .._validate import as_bool, as_float, as_int, as_str
from ..progress import Progress

__all__ = ["run_cases", "run_chunk", "resolve_task", "RunStats", "CASE_FIELDS"]

#: The fields of a case copied into a crash or error record (those present).
CASE_FIELDS = ("i", "key", "estimator", "seed", "params")


def resolve_task(task: str):
    """The function named ``"module:function"``."""
    task = as_str(task, "task")
    mod, sep, name = task.partition(":")
    if not sep or not mod or not name:
        raise ValueError(f"task: expected 'module:function', got {task!r}")
    try:
        fn = getattr(importlib.import_module(mod), name)
    except (ImportError, AttributeError) as exc:
        raise ValueError(f"task: cannot import {task!r} ({exc})") from None
    if not callable(fn):
        raise ValueError(f"task: {task!r} is not a function")
    return fn


def _ident(case) -> dict:
    return {k: case[k] for k in CASE_FIELDS if isinstance(case, dict) and k in case}


def run_chunk(task: str, context, cases) -> dict:
    """Runs ``task`` on each case of the chunk (in a worker, or in the caller on the serial path).
    Returns ``{"records": [...], "seconds": wall time}``; each record gets ``seconds`` (its case's
    wall time) unless the task set it.

    Parameters
    ----------
    task : str
        ``"module:function"``.
    context : object
        Passed to the task.
    cases : list of dict
        The chunk.

    Returns
    -------
    dict
    """
    fn = resolve_task(task)
    out = []
    t0 = time.perf_counter()
    for case in cases:
        t = time.perf_counter()
        try:
            rec = fn(context, case)
        except Exception as exc:  # noqa: BLE001  a bug or a bad case: recorded, the chunk goes on
            rec = {**_ident(case), "status": "error", "reason": f"{type(exc).__name__}: {exc}"}
        rec.setdefault("seconds", time.perf_counter() - t)
        out.append(rec)
    return {"records": out, "seconds": time.perf_counter() - t0}


@dataclass
class RunStats:
    """What :func:`run_cases` did: ``records`` handed to the sink, ``tasks`` submitted,
    ``crashed`` cases, ``errors`` (cases whose task raised), ``worker_deaths`` (chunks lost to a
    dead worker and split), ``seconds`` of wall time.

    Parameters
    ----------
    records, tasks, crashed, errors, worker_deaths : int, optional
        Counts (see above).
    seconds : float, optional
        Wall time.
    """

    records: int = 0
    tasks: int = 0
    crashed: int = 0
    errors: int = 0
    worker_deaths: int = 0
    seconds: float = 0.0


class _Chunker:
    """Cuts the case stream into chunks of about ``target`` seconds (see the module docstring)."""

    def __init__(self, cases, target: float, max_chunk: int):
        self.it = iter(cases)
        self.retry = deque()   # single cases of a chunk whose worker died
        self.again = deque()   # whole chunks whose result was lost with a dead worker
        self.quarantine = deque()  # single cases that met a dead worker: run alone next
        self.target, self.max_chunk = target, max_chunk
        self.per_case = None
        self.exhausted = False

    def observe(self, seconds: float, n: int) -> None:
        if n <= 0:
            return
        per = max(seconds / n, 1e-7)
        self.per_case = per if self.per_case is None else 0.7 * self.per_case + 0.3 * per

    def size(self) -> int:
        if self.per_case is None:
            return 1
        return max(1, min(self.max_chunk, int(self.target / self.per_case)))

    def next(self) -> list:
        if self.again:
            return self.again.popleft()
        if self.retry:
            return [self.retry.popleft()]
        if self.exhausted:
            return []
        chunk = list(itertools.islice(self.it, self.size()))
        if not chunk:
            self.exhausted = True
        return chunk


def run_cases(task: str, cases, sink, *, context=None, engine=None, total: int | None = None,
              chunk_seconds: float = 1.0, max_in_flight: int | None = None, max_chunk: int = 10_000,
              reproduce=None, label: str = "", quiet: bool = False, poll: float = 5.0) -> RunStats:
    """Runs ``task`` (``"module:function"``) on every case of the iterable ``cases`` (dicts) on
    ``engine`` (an entered :class:`~setbound.studies.engine.Engine`; None: serially in this
    process) and calls ``sink(records)`` in this process for each finished chunk (see the module
    docstring). ``reproduce(case)`` gives the command recorded with a crashed case. ``total``: the
    number of cases, for the progress bar. Returns :class:`RunStats`.

    Parameters
    ----------
    task : str
        ``"module:function"`` called as ``function(context, case)``.
    cases : iterable of dict
        The cases.
    sink : callable
        ``sink(records)``, called in this process.
    context : object, optional
        Passed to every task (sent once to the workers).
    engine : Engine, optional
        An entered engine (None: serially in this process).
    total : int, optional
        Number of cases (for the progress bar).
    chunk_seconds : float, optional
        Target work per task.
    max_in_flight : int, optional
        Chunks submitted at once (default: from the engine's threads).
    max_chunk : int, optional
        Largest number of cases per chunk.
    reproduce : callable, optional
        ``reproduce(case) -> str``, the command recorded with a crashed case.
    label : str, optional
        Progress-bar label.
    quiet : bool, optional
        No progress bar.
    poll : float, optional
        Seconds between checks of the running tasks.

    Returns
    -------
    RunStats
    """
    task = as_str(task, "task")
    resolve_task(task)  # a wrong name fails here, not in every worker
    chunk_seconds = as_float(chunk_seconds, "chunk_seconds", lo=0)
    max_chunk = as_int(max_chunk, "max_chunk", lo=1, hi=10**7)
    poll = as_float(poll, "poll", lo=0, lo_open=True, hi=3600)
    if max_in_flight is not None:
        max_in_flight = as_int(max_in_flight, "max_in_flight", lo=1, hi=10**6)
    if total is not None:
        total = as_int(total, "total", lo=0)
    label = as_str(label, "label")
    quiet = as_bool(quiet, "quiet")
    stats = RunStats()
    chunker = _Chunker(cases, chunk_seconds, max_chunk)
    t0 = time.perf_counter()
    client = None if engine is None else engine.client
    with Progress(total, label, quiet=quiet) as bar:
        def save(res, n_cases):
            recs = res["records"]
            chunker.observe(res["seconds"], n_cases)
            stats.errors += sum(1 for r in recs if r.get("status") == "error")
            sink(recs)
            stats.records += len(recs)
            bar.update(len(recs))

        if client is None:
            while True:
                chunk = chunker.next()
                if not chunk:
                    break
                stats.tasks += 1
                save(run_chunk(task, context, chunk), len(chunk))
        else:
            _distributed(client, engine, task, context, chunker, save, stats, max_in_flight, reproduce, bar,
                         poll)
    stats.seconds = time.perf_counter() - t0
    return stats


def _crash_record(case, reason: str, reproduce) -> dict:
    rec = {**_ident(case), "status": "crashed", "reason": reason}
    rec["reproduce"] = reproduce(case) if reproduce is not None else ""
    return rec


def _distributed(client, engine, task, context, chunker, save, stats, max_in_flight, reproduce, bar, poll):
    from distributed import KilledWorker, wait

    limit = max_in_flight or 2 * (engine.threads if engine is not None else 1)
    gather_timeout = 10.0
    regathered = set()
    requeued = {}
    pending = {}
    isolated = None  # the future of a quarantined case running alone
    down_since = None
    try:
        while True:
            if chunker.quarantine and not pending:
                # nothing else in flight: if it kills its worker now, it is the culprit
                case = chunker.quarantine.popleft()
                isolated = client.submit(run_chunk, task, context, [case], pure=False)
                stats.tasks += 1
                pending[isolated] = [case]
            while len(pending) < limit and not chunker.quarantine and isolated is None:
                chunk = chunker.next()
                if not chunk:
                    break
                fut = client.submit(run_chunk, task, context, chunk, pure=False)
                stats.tasks += 1
                pending[fut] = chunk
            if not pending:
                break
            try:
                with client.as_current():  # wait() asks for "the" client: ours, not a default one
                    done, _ = wait(list(pending), timeout=poll, return_when="FIRST_COMPLETED")
            except TimeoutError:
                if client.status != "running":
                    down_since = down_since or time.monotonic()
                    if time.monotonic() - down_since > (engine.timeout if engine is not None else 30.0):
                        raise ConnectionError(f"scheduler: lost the connection to {client.scheduler.address} "
                                              f"(client {client.status}); rerun to resume") from None
                else:
                    down_since = None
                continue
            for fut in done:
                chunk = pending.pop(fut)
                alone = fut is isolated
                if alone:
                    isolated = None
                if fut.status == "finished":
                    try:
                        # a result held by a worker that died meanwhile: the gather would wait for
                        # the connect timeout (30 s by default); run the chunk again instead
                        # (the second time, wait: a large result on a slow network is not lost)
                        res = fut.result(timeout=None if id(chunk) in regathered else gather_timeout)
                    except TimeoutError:
                        fut.release()
                        regathered.add(id(chunk))  # the list object stays alive in the queue
                        chunker.again.append(chunk)
                        continue
                    fut.release()
                    regathered.discard(id(chunk))
                    requeued.pop(id(chunk), None)
                    save(res, len(chunk))
                    continue
                if fut.status != "error":
                    # finished when wait() returned, then "lost" with the worker that held the
                    # result (or cancelled): its records were never saved, run the chunk again
                    fut.release()
                    requeued[id(chunk)] = requeued.get(id(chunk), 0) + 1
                    if requeued[id(chunk)] > 5:
                        raise ConnectionError(f"scheduler: a task was lost 5 times in a row (status {fut.status}, "
                                              f"client {client.status}); rerun to resume")
                    chunker.again.append(chunk)
                    continue
                exc = fut.exception()
                fut.release()
                if isinstance(exc, KilledWorker):
                    stats.worker_deaths += 1
                    if len(chunk) > 1:  # find the case that kills its worker: one at a time
                        chunker.retry.extend(chunk)
                    elif not alone:
                        # it may have shared a dying worker with the culprit: run it alone
                        chunker.quarantine.append(chunk[0])
                    else:
                        stats.crashed += 1
                        save({"records": [_crash_record(chunk[0], f"killed its worker repeatedly ({exc})",
                                                        reproduce)], "seconds": 0.0}, 0)
                    continue
                raise exc if exc is not None else RuntimeError(f"task {fut.key}: failed without an exception")
    finally:
        for fut in pending:
            fut.release()
