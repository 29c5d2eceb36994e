"""The outputs of a run, shared by ``setbound run/compare`` (:mod:`setbound.cli`) and ``setbound
demo`` (:mod:`setbound.demo`): the summary rows and table, the result files (NPZ, CSV,
``summary.json``) and the plots. It sits below both, so neither imports the other for them.
"""
from __future__ import annotations

import csv
import json
import re
from pathlib import Path

import numpy as np

from .jobs.registry import ESTIMATORS

__all__ = ["summary_rows", "format_table", "write_results", "write_plots", "user_message", "leaked"]

# "sb_zono_pradius_design: design_pradius: no beta ..." -> "no beta ...": the C function a message
# passed through, and the C++/Python function that raised it, are the library's business; the
# user reads the argument and the reason. Argument names ("max_generators: ...") stay.
_PREFIX = re.compile(r"^(?P<type>[A-Z][A-Za-z]*Error: )?(?P<names>(?:[A-Za-z_][A-Za-z0-9_.]*(?:\(\))?: )+)")
_API_MODULES = ("ellipsoidal", "zonotopic", "hinf", "lmi", "interval_observers", "invariant", "inclusion", "interval",
                "sets", "system", "plant", "simulation", "trajectory")
_FUNCTIONS: set = set()


def _function_names() -> set:
    """Names of the functions and classes of setbound's API modules (the prefixes to drop)."""
    if not _FUNCTIONS:
        import importlib

        for m in _API_MODULES:
            mod = importlib.import_module(f"setbound.{m}")
            _FUNCTIONS.update(n for n, v in vars(mod).items()
                              if callable(v) and getattr(v, "__module__", "").startswith("setbound"))
    return _FUNCTIONS


def user_message(exc_or_text) -> str:
    """An error for the user: without the names of the C, C++ and Python functions it passed
    through (``sb_*``, ``design_pradius``); an argument or key name in front is kept.

    Parameters
    ----------
    exc_or_text : Exception or str
        The error.

    Returns
    -------
    str
    """
    text = exc_or_text if isinstance(exc_or_text, str) else str(exc_or_text)
    m = _PREFIX.match(text)
    if not m:
        return text
    names = [n[:-2] for n in re.findall(r"[A-Za-z_][A-Za-z0-9_.]*(?:\(\))?: ", m.group("names"))]
    internal = _function_names()
    kept = [n for n in names if not (n.startswith("sb_") or n.rstrip("()") in internal)]
    return (m.group("type") or "") + "".join(f"{n}: " for n in kept) + text[m.end():]


def summary_rows(job, results) -> list[dict]:
    """One dictionary per estimator result: the content of the table and of ``summary.json``.

    Parameters
    ----------
    job : Job
        The job.
    results : list of Result
        Its results.

    Returns
    -------
    list of dict
    """
    rows = []
    for r in results:
        row = {"name": r.name, "method": r.method, "family": ESTIMATORS[r.method].family,
               "ok": r.ok, "error": None if r.error is None else user_message(r.error)}
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
                # impossible readings (setbound.measurement); None: the method does not test them
                "flagged_steps": None if t.status is None else int(np.count_nonzero(t.flagged)),
                "first_flagged_step": (None if t.status is None or not t.flagged.any()
                                       else int(np.flatnonzero(t.flagged)[0])),
            })
            start = getattr(job, "fault_start", None)
            if start is not None and t.status is not None:  # a detector of the injected fault
                after = np.flatnonzero(t.flagged[start:])
                row["alarm_step"] = int(start + after[0]) if after.size else None
                row["detection_delay"] = int(after[0]) if after.size else None
                row["alarms_before_fault"] = int(np.count_nonzero(t.flagged[:start]))
        else:
            row.update({"guaranteed": ESTIMATORS[r.method].guaranteed, "contains_truth": None,
                        "design_time_s": r.design_time})
        rows.append(row)
    return rows


def _g(v, width):
    return f"{'—':>{width}}" if v is None or (isinstance(v, float) and not np.isfinite(v)) else f"{v:>{width}.4g}"


def format_table(rows) -> str:
    """The summary table as text (widths: the largest component; ``†``: final, not ρ∞, volume).

    Parameters
    ----------
    rows : list of dict
        From :func:`summary_rows`.

    Returns
    -------
    str
    """
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
            notes.add("* not a guaranteed method, the truth is not checked (Kalman: mean ± 3σ box; CORA's code "
                      "under convention = \"cora\")")
        vol = _g(r["steady_volume"], 11)
        if r["steady_volume_kind"] == "final":
            vol += "†"
            notes.add("† final volume (the method has no design steady state); otherwise the design's ρ∞ volume")
        else:
            vol += " "
        lines.append(f"{r['name']:<20}{inside:>13}{max(r['mean_width']):>12.4g}{max(r['final_width']):>12.4g}"
                     f"{vol:>12}{r['design_time_s']:>10.3f}{1e3 * r['time_per_step_s']:>9.3f}")
    lines += sorted(notes)
    for r in rows:
        if r["ok"] and r.get("flagged_steps"):
            lines.append(f"! {r['name']}: readings no state of the model can produce at {r['flagged_steps']} step"
                         f"{'s' if r['flagged_steps'] != 1 else ''} (first: step {r['first_flagged_step']}); they were "
                         f"not used (status and margin in {r['name']}.npz)")
    for r in rows:
        if r["ok"] and "detection_delay" in r:
            lines.append(f"alarm: {r['name']}: " + ("no alarm" if r["alarm_step"] is None else
                                                   f"step {r['alarm_step']} (delay {r['detection_delay']})"))
    return "\n".join(lines)


def write_results(out: Path, job, results, rows, *, extra: dict | None = None) -> list[Path]:
    """Writes ``<name>.npz`` and ``<name>.csv`` per estimator that ran and ``summary.json``.

    Parameters
    ----------
    out : Path
        Output folder.
    job : Job
        The job.
    results : list of Result
        Its results.
    rows : list of dict
        From :func:`summary_rows`.
    extra : dict, optional
        Added to ``summary.json``.

    Returns
    -------
    list of Path
    """
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
        if t.status is not None:  # what each step did with each reading (setbound.measurement)
            arrays["status"], arrays["margin"] = t.status, t.margin
        np.savez(out / f"{r.name}.npz", **arrays)
        with open(out / f"{r.name}.csv", "w", newline="") as fh:
            wr = csv.writer(fh)
            n = t.center.shape[1]
            times = t.times  # the time of each row (the job's time, else k)
            wr.writerow(["k", "t"] + [f"center{i}" for i in range(n)] + [f"lower{i}" for i in range(n)]
                        + [f"upper{i}" for i in range(n)])
            for k in range(len(t)):
                wr.writerow([k, repr(float(times[k]))]
                            + [repr(float(v)) for v in np.concatenate([t.center[k], t.lower[k], t.upper[k]])])
        written += [out / f"{r.name}.npz", out / f"{r.name}.csv"]
    doc = {"title": job.title, "source": job.source, "steps": int(len(job.y)), "estimators": rows}
    if getattr(job, "faults", None):
        doc["faults"] = [{"kind": f.kind, "start": f.start, "output": f.output, "input": f.input,
                          "magnitude": f.magnitude} for f in job.faults]
    iso = getattr(job, "isolation", None)
    if iso is not None:
        doc["isolation"] = {"hypotheses": iso.names, "rejected_at": iso.rejected_at,
                            "consistent_at_end": iso.consistent_at_end}
    doc.update(extra or {})
    with open(out / "summary.json", "w") as fh:
        json.dump(doc, fh, indent=2)
    written.append(out / "summary.json")
    return written


def write_plots(out: Path, job, results, *, prefix: str = "") -> list[Path]:
    """Writes the plots of the results that ran: ``bounds.png``, ``widths.png``,
    ``widths_relative.png`` (to ``[plots] reference`` or the first guaranteed estimator; only
    with two or more estimators), ``volume.png`` (when some result has sets), ``margins.png``
    (the detectors' margins and alarms, when a fault is injected or a reading was flagged) and
    ``projections.png`` (n_x ≥ 2).

    Parameters
    ----------
    out : Path
        Output folder.
    job : Job
        The job.
    results : list of Result
        Its results.
    prefix : str, optional
        Prefix of the file names.

    Returns
    -------
    list of Path
    """
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
    detectors = [r for r in ok if r.trajectory.status is not None]
    if detectors and (getattr(job, "faults", None) or any(r.trajectory.flagged.any() for r in detectors)):
        paths.append(plotting.save_png(plotting.plot_margins({r.name: r.trajectory for r in detectors},
                                                             fault_start=job.fault_start, title=title),
                                       out / f"{prefix}margins.png"))
    N, n = ok[0].trajectory.center.shape
    if n >= 2:
        steps = job.plots.steps or sorted({0, N // 2, N - 1})
        fig = plotting.plot_projections(trajs, steps=steps, dims=job.plots.dims, x_true=job.x_true,
                                        system=job.system, y=job.y, u=job.u, title=title)
        paths.append(plotting.save_png(fig, out / f"{prefix}projections.png"))
    return paths


def leaked(rows) -> list[str]:
    """Names of the estimators whose guaranteed set lost the true state.

    Parameters
    ----------
    rows : list of dict
        From :func:`summary_rows`.

    Returns
    -------
    list of str
    """
    return [r["name"] for r in rows if r["contains_truth"] is False]
