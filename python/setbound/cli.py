"""The ``setbound`` command line (installed as a console script; also ``python -m setbound``).

``setbound check FILE``
    validate a job file (see :mod:`setbound.config`) without running it.
``setbound run FILE [--out DIR]``
    run it: print a summary table, write into ``DIR`` (default ``out/<file stem>``) the NPZ and
    CSV of centre/lower/upper per estimator, ``summary.json`` and the plots (PNG).
``setbound compare FILE... [--estimators a,b,c] [--out DIR]``
    the same system under several estimators — from several files describing the same system
    (the data of the first file are used for all), or one file with an estimator filter
    (names or methods) —: one table and overlaid plots (default ``out/compare``).
``setbound demo [--out DIR] [--steps N]``
    the main job: the built-in 3-state example with every applicable estimator
    (see :mod:`setbound.demo`), written to ``out/demo``.

The summary table has one row per estimator: containment of the true state (when known),
mean and final bound widths, the steady-state volume (the design's ``ρ∞`` volume where the
method has one, else the final volume, marked ``†``), design time and time per step.
Estimators that could not be designed (infeasible LMI, …) are listed with the reason.

Exit codes: 0 success; 1 the true state left a guaranteed set, or (``run``/``compare``) an
estimator failed; 2 invalid input (job file, arguments). ``--quiet`` silences the progress bars
(they are drawn only when stderr is a terminal anyway).
"""
from __future__ import annotations

import argparse
import csv
import json
import sys
from pathlib import Path

import numpy as np

from . import config
from .errors import SetboundError
from .progress import set_quiet

__all__ = ["main", "summary_rows", "format_table", "write_results", "write_plots", "load_compare"]


def summary_rows(job, results) -> list[dict]:
    """One dictionary per estimator result: the content of the table and of ``summary.json``."""
    rows = []
    for r in results:
        row = {"name": r.name, "method": r.method, "family": config.ESTIMATORS[r.method].family,
               "ok": r.ok, "error": r.error}
        if r.ok:
            t = r.trajectory
            w = t.width
            row.update({
                "guaranteed": bool(t.guaranteed),
                "contains_truth": r.contained,
                "mean_width": [float(v) for v in np.mean(w, axis=0)],
                "final_width": [float(v) for v in w[-1]],
                "steady_volume": None if not np.isfinite(r.steady_volume) else float(r.steady_volume),
                "steady_volume_kind": r.steady_volume_kind,
                "final_volume": float(t.volume[-1]) if t.sets and np.isfinite(t.volume[-1]) else None,
                "design_time_s": r.design_time,
                "time_per_step_s": r.step_time,
            })
        else:
            row.update({"guaranteed": config.ESTIMATORS[r.method].guaranteed, "contains_truth": None,
                        "design_time_s": r.design_time})
        rows.append(row)
    return rows


def _g(v, width):
    return f"{'—':>{width}}" if v is None or (isinstance(v, float) and not np.isfinite(v)) else f"{v:>{width}.4g}"


def format_table(rows) -> str:
    """The summary table as text (widths: the largest component; ``†``: final, not ρ∞, volume)."""
    head = (f"{'estimator':<20}{'truth inside':>13}{'mean width':>12}{'final width':>12}{'ss volume':>12}"
            f"{'design s':>10}{'ms/step':>9}")
    lines = [head, "-" * len(head)]
    notes = set()
    for r in rows:
        if not r["ok"]:
            lines.append(f"{r['name']:<20}{'FAILED':>13}  {r['error']}")
            continue
        inside = "n/a" if r["contains_truth"] is None else ("yes" if r["contains_truth"] else "NO")
        if not r["guaranteed"]:
            inside += "*"
            notes.add("* not a guaranteed method (Kalman: mean ± 3σ box)")
        vol = _g(r["steady_volume"], 11)
        if r["steady_volume_kind"] == "final":
            vol += "†"
            notes.add("† final volume (the method has no design steady state); otherwise the design's ρ∞ volume")
        else:
            vol += " "
        lines.append(f"{r['name']:<20}{inside:>13}{max(r['mean_width']):>12.4g}{max(r['final_width']):>12.4g}"
                     f"{vol:>12}{r['design_time_s']:>10.3f}{1e3 * r['time_per_step_s']:>9.3f}")
    lines += sorted(notes)
    return "\n".join(lines)


def write_results(out: Path, job, results, rows, *, extra: dict | None = None) -> list[Path]:
    """Writes ``<name>.npz`` and ``<name>.csv`` per estimator that ran and ``summary.json``."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for r in results:
        if not r.ok:
            continue
        t = r.trajectory
        arrays = {"center": t.center, "lower": t.lower, "upper": t.upper, "radius": t.radius,
                  "volume": t.volume if t.sets else np.full(len(t), np.nan), "y": job.y}
        if job.x_true is not None:
            arrays["x_true"] = job.x_true
        if job.t is not None:
            arrays["t"] = job.t
        np.savez(out / f"{r.name}.npz", **arrays)
        with open(out / f"{r.name}.csv", "w", newline="") as fh:
            wr = csv.writer(fh)
            n = t.center.shape[1]
            wr.writerow(["k"] + [f"center{i}" for i in range(n)] + [f"lower{i}" for i in range(n)]
                        + [f"upper{i}" for i in range(n)])
            for k in range(len(t)):
                wr.writerow([k] + [repr(float(v)) for v in np.concatenate([t.center[k], t.lower[k], t.upper[k]])])
        written += [out / f"{r.name}.npz", out / f"{r.name}.csv"]
    doc = {"title": job.title, "source": job.source, "steps": int(len(job.y)), "estimators": rows}
    doc.update(extra or {})
    with open(out / "summary.json", "w") as fh:
        json.dump(doc, fh, indent=2)
    written.append(out / "summary.json")
    return written


def write_plots(out: Path, job, results, *, prefix: str = "") -> list[Path]:
    """Writes the plots of the results that ran: ``bounds.png``, ``widths.png``,
    ``widths_relative.png`` (to ``[plots] reference`` or the first guaranteed estimator; only
    with two or more estimators), ``volume.png`` (when some result has sets) and
    ``projections.png`` (n_x ≥ 2)."""
    from . import plotting

    ok = [r for r in results if r.ok]
    if not ok:
        return []
    trajs = {r.name: r.trajectory for r in ok}
    out = Path(out)
    title = job.title
    paths = [plotting.save_png(plotting.plot_bounds(trajs, x_true=job.x_true, t=job.t, title=title),
                               out / f"{prefix}bounds.png"),
             plotting.save_png(plotting.plot_widths(trajs, t=job.t), out / f"{prefix}widths.png")]
    ref = job.plots.reference if job.plots.reference in trajs else \
        next((r.name for r in ok if r.trajectory.guaranteed), None)
    if ref is not None and len(trajs) > 1:
        paths.append(plotting.save_png(plotting.plot_widths(trajs, reference=ref, t=job.t),
                                       out / f"{prefix}widths_relative.png"))
    if any(r.trajectory.sets for r in ok):
        paths.append(plotting.save_png(plotting.plot_volume(trajs, t=job.t), out / f"{prefix}volume.png"))
    N, n = ok[0].trajectory.center.shape
    if n >= 2:
        steps = job.plots.steps or sorted({0, N // 2, N - 1})
        fig = plotting.plot_projections(trajs, steps=steps, dims=job.plots.dims, x_true=job.x_true,
                                        system=job.system, y=job.y, u=job.u, title=title)
        paths.append(plotting.save_png(fig, out / f"{prefix}projections.png"))
    return paths


def _report(job, results, out, *, plots: bool, extra=None) -> int:
    rows = summary_rows(job, results)
    print(f"{job.title} ({len(job.y)} steps)")
    print(format_table(rows))
    if out is not None:
        write_results(out, job, results, rows, extra=extra)
        if plots and job.plots.enabled:
            write_plots(out, job, results)
        print(f"results written to {out}")
    leaked = [r["name"] for r in rows if r["contains_truth"] is False]
    if leaked:
        print(f"setbound: the true state left the set of: {', '.join(leaked)}", file=sys.stderr)
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
    ``estimators`` (comma-separated names or methods). Raises ConfigError when the files describe
    different systems or the filter selects nothing."""
    jobs = [config.load(f) for f in files]
    job = jobs[0]
    specs, seen = [], set()
    for f, j in zip(files, jobs):
        if j is not job and not _same_system(job.system, j.system):
            raise config.ConfigError(f"{f}: describes a different system than {files[0]} (compare needs one system)")
        for s in j.estimators:
            name = s.name if s.name not in seen else f"{Path(f).stem}:{s.name}"
            if name in seen:
                continue
            seen.add(name)
            specs.append(config.EstimatorSpec(s.method, name.replace(":", "_"), s.options))
    if estimators:
        want = [w.strip() for w in estimators.split(",") if w.strip()]
        unknown = [w for w in want if not any(w in (s.name, s.method) for s in specs)]
        if unknown:
            raise config.ConfigError(f"--estimators: {', '.join(unknown)} not among "
                                     f"{', '.join(s.name for s in specs)}")
        specs = [s for s in specs if s.name in want or s.method in want]
    job.estimators = specs
    if job.plots.reference not in {s.name for s in specs}:
        job.plots.reference = None
    return job


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="setbound", description="guaranteed (set-membership) state estimation")
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
    m.add_argument("--estimators", help="comma-separated estimator names or methods to keep")
    m.add_argument("--out", default="out/compare", help="directory for the results (default out/compare)")
    m.add_argument("--no-plots", action="store_true", help="write no PNG files")
    m.add_argument("--quiet", "-q", action="store_true", default=argparse.SUPPRESS, help="no progress bars")
    d = sub.add_parser("demo", help="the main job: the 3-state example under every estimator")
    d.add_argument("--out", default="out/demo", help="directory for the results (default out/demo)")
    d.add_argument("--steps", type=int, default=None, help="horizon (default: the example's 50 steps)")
    d.add_argument("--no-plots", action="store_true", help="write no PNG files")
    d.add_argument("--quiet", "-q", action="store_true", default=argparse.SUPPRESS, help="no progress bars")
    return p


def main(argv=None) -> int:
    """Entry point of the ``setbound`` command; returns the exit code."""
    a = _parser().parse_args(argv)
    set_quiet(bool(getattr(a, "quiet", False)))
    try:
        if a.command == "demo":
            from . import demo

            return demo.run_demo(out=Path(a.out), steps=a.steps, plots=not a.no_plots)
        if a.command == "compare":
            job = load_compare(a.files, a.estimators)
            results = config.run(job, keep_going=True)
            code = _report(job, results, Path(a.out), plots=not a.no_plots, extra={"files": list(a.files)})
            return code or (1 if any(not r.ok for r in results) else 0)
        job = config.load(a.file)
        if a.command == "check":
            print(f"{a.file}: ok — {job.title}: {type(job.system).__name__} (n_x = {job.system.nx}), "
                  f"{len(job.y)} steps, estimators: {', '.join(s.name for s in job.estimators)}")
            return 0
        results = config.run(job, keep_going=True)
        out = Path(a.out) if a.out else Path("out") / Path(a.file).stem
        code = _report(job, results, out, plots=not a.no_plots)
        return code or (1 if any(not r.ok for r in results) else 0)
    except (SetboundError, ValueError) as exc:
        print(f"setbound: error: {exc}", file=sys.stderr)
        return 2
    finally:
        set_quiet(False)


if __name__ == "__main__":
    sys.exit(main())
