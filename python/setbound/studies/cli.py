"""``setbound study FILE ...`` (the subcommand's body; the parser is in :mod:`setbound.cli`).

Exit codes as the other commands: 0 done; 1 a true state left a guaranteed set, a case crashed
or raised, or a case was recorded twice with different results; 2 invalid input (the study file,
the options, an output folder of another study, a scheduler that cannot be reached).
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

__all__ = ["study_command", "check_line"]


def check_line(path) -> str | None:
    """For ``setbound check``: validates the ``[study]`` section of ``path`` when it has one and
    returns a line describing the grid (None: no ``[study]``)."""
    import tomllib

    with open(path, "rb") as fh:
        if "study" not in tomllib.load(fh):
            return None
    from ..jobs.study import load_study

    st = load_study(path)
    params = ", ".join(f"{p} ({len(v)})" for p, v in st.parameters.items()) or "none"
    return (f"study: {st.size} cases — {len(st.seeds)} seeds × parameters {params} × estimators "
            f"{', '.join(st.estimators)}")


def study_command(a) -> int:
    """Runs ``setbound study`` with the parsed arguments ``a``; returns the exit code."""
    from .engine import SchedulerUnreachable
    from .study import run_one_case, run_study
    from .summary import NondeterminismError, format_summary

    if a.case is not None:
        rec = run_one_case(a.file, a.case)
        print(json.dumps(rec, indent=1, sort_keys=True, default=str))
        return 0 if rec.get("status") in ("ok", "failed") and rec.get("contained") is not False else 1
    try:
        res = run_study(a.file, out=a.out, scheduler=a.scheduler, scheduler_file=a.scheduler_file,
                        processes=a.processes, resume=a.resume, timeout=a.timeout, chunk_seconds=a.chunk_seconds,
                        plots=not a.no_plots, quiet=bool(getattr(a, "quiet", False)))
    except SchedulerUnreachable as exc:
        print(f"setbound: error: {exc}", file=sys.stderr)
        return 2
    except NondeterminismError as exc:
        print(f"setbound: error: {exc}", file=sys.stderr)
        return 1
    s = res.summary
    print(f"{Path(a.file).name}: {res.cases} cases ({res.already} already recorded, {res.stats.records} run now"
          f" in {res.stats.seconds:.1f} s)")
    print(format_summary(s))
    if s.torn:
        print(f"{s.torn} torn last line(s) ignored (their cases were run again)")
    for r in s.crashed:
        print(f"CRASHED {r['key']}: {r.get('reason', '')}; reproduce: {r.get('reproduce', '')}", file=sys.stderr)
    for r in s.errors:
        print(f"ERROR {r['key']}: {r.get('reason', '')}", file=sys.stderr)
    if s.leaked:
        print(f"setbound: the true state left the set in {len(s.leaked)} case(s), e.g. {s.leaked[0]}", file=sys.stderr)
    print(f"results written to {res.out}")
    return 0 if res.ok else 1
