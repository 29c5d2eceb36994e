"""The ``setbound`` command line (installed as a console script; also ``python -m setbound``).

``setbound check FILE``
    validate a job file (see :mod:`setbound.jobs`) without running it: everything ``run``
    validates (the sections, the estimators' options, the data file, the true initial state
    inside the initial set, the memory the run needs), with a trial of the first 64 steps of
    the simulation instead of the whole horizon.
``setbound run FILE [--out DIR]``
    run it: print a summary table, write into ``DIR`` (default ``out/<file stem>``) the NPZ and
    CSV of centre/lower/upper per estimator, ``summary.json`` and the plots (PNG).
``setbound compare FILE... [--estimators a,b,c] [--out DIR]``
    the same system under several estimators — from several files describing the same system
    (the data of the first file are used for all), or one file with an estimator filter
    (names or methods; a registered method the files do not run, e.g. a CORA name such as
    ``FRad-B``, is added with its default options) —: one table and overlaid plots (default
    ``out/compare``).
``setbound study FILE [--scheduler ADDR | --scheduler-file PATH] [--processes N] [--out DIR] [--resume | --no-resume]``
    a study: the job's ``[study]`` grid (seeds × parameter values × estimators, see
    :mod:`setbound.jobs.study`) on a Dask cluster (embedded by default, see
    :mod:`setbound.studies`), the per-case records and the summary in ``DIR`` (default
    ``out/<file stem>``); an existing folder of the same study is resumed. ``--case KEY`` runs one
    case here and prints its record.
``setbound demo [--out DIR] [--steps N]``
    the main job: the built-in 3-state example with every applicable estimator
    (see :mod:`setbound.demo`), written to ``out/demo``.

The summary table has one row per estimator: containment of the true state (when known),
mean and final bound widths, the steady-state volume (the design's ``ρ∞`` volume where the
method has one, else the final volume, marked ``†``), design time and time per step.
Estimators that could not be designed (infeasible LMI, …) are listed with the reason.

Exit codes: 0 success; 1 the true state left a guaranteed set, or (``run``/``compare``) an
estimator failed; 2 invalid input (job file, data file, arguments): one line on stderr,
``setbound: error: <key>: <what>``, never a traceback; 3 an internal error (a bug of setbound,
reported in one line). ``setbound --version`` prints the package and C library versions. ``--quiet`` silences the progress bars
(they are drawn only when stderr is a terminal anyway).
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

from . import jobs
from .errors import SetboundError
from .progress import set_quiet
from .jobs.faults import fault_lines
from .report import format_table, leaked, summary_rows, user_message, write_plots, write_results

__all__ = ["main", "summary_rows", "format_table", "write_results", "write_plots", "load_compare"]


def _report(job, results, out, *, plots: bool, extra=None) -> int:
    rows = summary_rows(job, results)
    print(f"{job.title} ({len(job.y)} steps)")
    print(format_table(rows))
    for line in fault_lines(job):
        print(line)
    if out is not None:
        write_results(out, job, results, rows, extra=extra)
        if plots and job.plots.enabled:
            write_plots(out, job, results)
        print(f"results written to {out}")
    lost = leaked(rows)
    if lost:
        print(f"setbound: the true state left the set of: {', '.join(lost)}", file=sys.stderr)
        return 1
    return 0


def _same_system(a, b) -> bool:
    if type(a) is not type(b):
        return False
    names = ("A", "A_rad", "B", "C", "D", "E", "F")
    for nm in names:
        x, y = getattr(a, nm, None), getattr(b, nm, None)
        if (x is None) != (y is None):
            return False
        if x is not None and (np.shape(x) != np.shape(y) or not np.array_equal(x, y)):
            return False
    return True


def load_compare(files, estimators: str | None = None):
    """The job of ``setbound compare``: the first file's system, initial set and data, with the
    estimators of every file (renamed ``<file stem>:<name>`` when names clash), filtered by
    ``estimators`` (comma-separated names or methods; a registered method that no file runs, such
    as a CORA name, is added with its default options). Raises ConfigError when the files describe
    different systems or a name of the filter is neither an estimator of the files nor a method.

    Parameters
    ----------
    files : list of str or Path
        Job files.
    estimators : str, optional
        Comma-separated estimator names or methods.

    Returns
    -------
    Job
    """
    loaded = []
    for f in files:
        try:
            loaded.append(jobs.load(f))
        except jobs.ConfigError as exc:  # several files: say which one
            if len(files) == 1 or str(exc).startswith(str(f)):
                raise
            raise jobs.ConfigError(f"{f}: {exc}") from None
    job = loaded[0]
    specs, seen = [], set()
    for f, j in zip(files, loaded):
        if j is not job and not _same_system(job.system, j.system):
            raise jobs.ConfigError(f"{f}: describes a different system than {files[0]} (compare needs one system)")
        for s in j.estimators:
            name = s.name if s.name not in seen else f"{Path(f).stem}:{s.name}"
            if name in seen:
                continue
            seen.add(name)
            specs.append(jobs.EstimatorSpec(s.method, name.replace(":", "_"), s.options))
    if estimators:
        want = [w.strip() for w in estimators.split(",") if w.strip()]
        absent = [w for w in want if not any(w in (s.name, s.method) for s in specs)]
        unknown = [w for w in absent if w not in jobs.ESTIMATORS]
        if unknown:
            from .jobs.schema import closest

            raise jobs.ConfigError(f"--estimators: {', '.join(unknown)} not among "
                                   f"{', '.join(s.name for s in specs)} nor a registered method"
                                   f"{closest(unknown[0], [*(s.name for s in specs), *jobs.ESTIMATORS])} "
                                   f"(methods: {', '.join(jobs.ESTIMATORS)})")
        # a method the files do not run (e.g. a CORA name): added with its default options
        added = [jobs.estimator_spec({"method": w}, f"--estimators {w}", job.system_kind, job.system) for w in absent]
        specs = [s for s in specs if s.name in want or s.method in want]
        taken = {s.name for s in specs}
        specs += [a for a in added if a.name not in taken]
    job.estimators = specs
    if job.plots.reference not in {s.name for s in specs}:
        job.plots.reference = None
    return job


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version as dist_version

    from ._native import version as library_version

    try:
        pkg = dist_version("setbound")
    except PackageNotFoundError:
        pkg = "unknown"
    try:
        lib = library_version()
    except Exception as exc:  # noqa: BLE001  (--version must work even when the library does not load)
        lib = f"not loaded ({user_message(exc)})"
    return f"setbound {pkg} (C library {lib})"


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="setbound", description="guaranteed (set-membership) state estimation",
                                epilog="exit codes: 0 success; 1 the true state left a guaranteed set or an "
                                       "estimator failed; 2 invalid input (job file, data file, arguments); "
                                       "3 an internal error (a bug)")
    p.add_argument("--version", action="version", version=_version())
    p.add_argument("--quiet", "-q", action="store_true", help="no progress bars")
    sub = p.add_subparsers(dest="command", required=True)
    c = sub.add_parser("check", help="validate a job file without running it")
    c.add_argument("file")
    r = sub.add_parser("run", help="run a job file: table, results and plots")
    r.add_argument("file")
    r.add_argument("--out", help="directory for the results (default out/<file stem>)")
    r.add_argument("--no-plots", action="store_true", help="write no PNG files")
    r.add_argument("--quiet", "-q", action="store_true", default=argparse.SUPPRESS, help="no progress bars")
    m = sub.add_parser("compare", help="one system under several estimators: one table, overlaid plots")
    m.add_argument("files", nargs="+", metavar="FILE")
    m.add_argument("--estimators", help="comma-separated estimator names or methods to keep (a method no file "
                                        "runs, e.g. a CORA name, is added)")
    m.add_argument("--out", default="out/compare", help="directory for the results (default out/compare)")
    m.add_argument("--no-plots", action="store_true", help="write no PNG files")
    m.add_argument("--quiet", "-q", action="store_true", default=argparse.SUPPRESS, help="no progress bars")
    s = sub.add_parser("study", help="a study: the [study] grid of a job file on a Dask cluster")
    s.add_argument("file")
    s.add_argument("--out", help="directory for the results (default out/<file stem>)")
    where = s.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="ADDR", help="an existing Dask scheduler (tcp://HOST:PORT)")
    where.add_argument("--scheduler-file", metavar="PATH", help="an existing Dask scheduler's file")
    where.add_argument("--processes", type=int, help="worker processes of the embedded cluster (default: one per "
                                                      "core; 1: serially in this process)")
    s.add_argument("--timeout", type=float, default=30.0, help="seconds to reach the scheduler (default 30)")
    s.add_argument("--resume", dest="resume", action="store_true", default=True,
                   help="continue the study in --out (the default)")
    s.add_argument("--no-resume", dest="resume", action="store_false", help="refuse a folder that holds results")
    s.add_argument("--chunk-seconds", type=float, default=1.0, help="target work per task (default 1 s)")
    s.add_argument("--case", metavar="KEY", help="run this one case here and print its record")
    s.add_argument("--no-plots", action="store_true", help="write no PNG files")
    s.add_argument("--quiet", "-q", action="store_true", default=argparse.SUPPRESS, help="no progress bars")
    d = sub.add_parser("demo", help="the main job: the 3-state example under every estimator")
    d.add_argument("--out", default="out/demo", help="directory for the results (default out/demo)")
    d.add_argument("--steps", type=int, default=None, help="horizon (default: the example's 50 steps)")
    d.add_argument("--no-plots", action="store_true", help="write no PNG files")
    d.add_argument("--quiet", "-q", action="store_true", default=argparse.SUPPRESS, help="no progress bars")
    return p


def _check(path) -> int:
    job = jobs.load(path, simulate=False)
    mib = job.memory_estimate / 1024 ** 2
    print(f"{path}: ok — {job.title}: {type(job.system).__name__} (n_x = {job.system.nx}), {job.horizon} steps, "
          f"estimators: {', '.join(s.name for s in job.estimators)} (run needs about {mib:.0f} MiB)")
    from .studies.cli import check_line

    line = check_line(path)  # a [study] section: validated too
    if line:
        print(line)
    return 0


def main(argv=None) -> int:
    """Entry point of the ``setbound`` command; returns the exit code (see the module docstring).

    Parameters
    ----------
    argv : list of str, optional
        Arguments (default: ``sys.argv[1:]``).

    Returns
    -------
    int
    """
    a = _parser().parse_args(argv)
    set_quiet(bool(getattr(a, "quiet", False)))
    try:
        if a.command == "demo":
            from . import demo

            return demo.run_demo(out=Path(a.out), steps=a.steps, plots=not a.no_plots)
        if a.command == "compare":
            job = load_compare(a.files, a.estimators)
            results = jobs.run(job, keep_going=True)
            code = _report(job, results, Path(a.out), plots=not a.no_plots, extra={"files": list(a.files)})
            return code or (1 if any(not r.ok for r in results) else 0)
        if a.command == "check":
            return _check(a.file)
        if a.command == "study":
            from .studies.cli import study_command

            return study_command(a)
        job = jobs.load(a.file)
        results = jobs.run(job, keep_going=True)
        out = Path(a.out) if a.out else Path("out") / Path(a.file).stem
        code = _report(job, results, out, plots=not a.no_plots)
        return code or (1 if any(not r.ok for r in results) else 0)
    except (SetboundError, ValueError) as exc:
        print(f"setbound: error: {user_message(exc)}", file=sys.stderr)
        return 2
    except OSError as exc:  # writing the results (a read-only or full disk, a file where a directory goes)
        print(f"setbound: error: {exc.filename or 'output'}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    except (RecursionError, MemoryError) as exc:
        print(f"setbound: error: input: too large or too deeply nested to process ({type(exc).__name__})",
              file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("setbound: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # noqa: BLE001  a bug of setbound: say so, without a traceback for the user
        print(f"setbound: internal error (a bug; please report it with the job file): {type(exc).__name__}: "
              f"{user_message(exc)}", file=sys.stderr)
        return 3
    finally:
        set_quiet(False)


if __name__ == "__main__":
    sys.exit(main())
