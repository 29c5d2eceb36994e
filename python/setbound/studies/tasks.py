"""The tasks workers run (module-level functions of plain data; see
:mod:`setbound.studies.executor`).

* :func:`study_case`: one case of a ``[study]`` (one estimator on one seed with one set of
  parameter values): the job document of the case is built, loaded and run in the worker.
* :func:`busy_case`: a case that spins the CPU for ``case["seconds"]`` and returns a value that
  depends only on the case (for measuring the machinery: ``bench/bench_study.py``, tests).

The guarantee campaign's task is :func:`setbound.campaign.campaign_case`.
"""
from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

__all__ = ["study_case", "busy_case", "TIMING_FIELDS"]

#: Record fields that measure time (left out when two runs of a case are compared).
TIMING_FIELDS = frozenset({"seconds", "us_per_step", "design_s"})


def _finite(v):
    v = float(v)
    return v if math.isfinite(v) else None


def study_case(context: dict, case: dict) -> dict:
    """Runs one study case; returns its record: the case (``i``, ``key``, ``estimator``, ``seed``,
    ``params``), ``method``, ``status`` (``"ok"``, or ``"failed"`` with ``reason`` when the library
    refused the design or a step), ``steps``, ``guaranteed``, ``contained`` (the true state inside
    the set at every step; None for a non-guaranteed method), ``mean_width`` (over steps and
    components of upper − lower), ``final_width`` (mean over components at the last step),
    ``hull_ratio`` (mean width over the exact hull's, when the study asks for it), ``us_per_step``
    and ``design_s``."""
    from ..jobs import from_dict, run_estimator
    from ..jobs.study import apply_case
    from ..report import user_message

    doc = apply_case(context["doc"], case["estimator"], case["seed"], case["params"])
    job = from_dict(doc, base=Path(context["base"]))
    spec = job.estimators[0]
    res = run_estimator(job, spec, keep_going=True, quiet=True)
    rec = {"i": case["i"], "key": case["key"], "estimator": case["estimator"], "seed": case["seed"],
           "params": case["params"], "method": spec.method, "steps": int(job.horizon)}
    if not res.ok:
        rec.update(status="failed", reason=user_message(res.error), design_s=res.design_time)
        return rec
    w = np.asarray(res.trajectory.width, float)
    rec.update(status="ok", guaranteed=bool(res.trajectory.guaranteed), contained=res.contained,
               mean_width=_finite(np.mean(w)), final_width=_finite(np.mean(w[-1])),
               us_per_step=res.step_time * 1e6, design_s=res.design_time)
    if context.get("exact_hull"):
        from ..sets import as_zonotope
        from ..zonotopic import exact_hull

        try:
            h = exact_hull(job.system, job.y, job.u, x0=as_zonotope(job.initial))
            we = np.mean(np.asarray(h.upper) - np.asarray(h.lower))
            rec["hull_ratio"] = _finite(np.mean(w) / we) if we > 0 else None
        except Exception as exc:  # noqa: BLE001  the reference failed: say why, keep the case
            rec["hull_ratio"] = None
            rec["hull_error"] = f"{type(exc).__name__}: {user_message(exc)}"
    return rec


def busy_case(context, case: dict) -> dict:
    """Spins for ``case["seconds"]`` of CPU time (a case of known cost); the record's ``value``
    depends only on ``case["i"]``."""
    t_end = time.thread_time() + float(case.get("seconds", 0.0))
    x = 0
    while time.thread_time() < t_end:
        x += 1
    return {"i": case["i"], "key": case["key"], "status": "ok", "value": (case["i"] * 2654435761) % 2**32}
