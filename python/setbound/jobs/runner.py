"""Running the estimators of a validated :class:`~setbound.jobs.model.Job`."""
from __future__ import annotations

import time

import numpy as np

from ..errors import SetboundError
from .model import EstimatorSpec, Job, Result
from .registry import ESTIMATORS

__all__ = ["run", "run_estimator", "run_trajectory"]


def _concat(parts):
    from ..trajectory import Trajectory

    if len(parts) == 1:
        return parts[0]
    t = Trajectory(np.vstack([p.center for p in parts]), np.vstack([p.lower for p in parts]),
                   np.vstack([p.upper for p in parts]), [s for p in parts for s in p.sets],
                   guaranteed=all(p.guaranteed for p in parts))
    for name in ("status", "margin", "resets"):
        if all(getattr(p, name) is not None for p in parts):
            setattr(t, name, np.concatenate([getattr(p, name) for p in parts]))
    if all(hasattr(p, "covariance") for p in parts):
        t.covariance = np.concatenate([p.covariance for p in parts])
    return t


def run_trajectory(estimator, y, u=None, *, label: str = "", quiet: bool = False, chunk: int | None = None):
    """``estimator.run(y, u)`` with a progress bar (see :mod:`setbound.progress`) when stderr is a
    terminal: then in chunks (``chunk`` rows, default N/50). The first chunk starts from the
    initial set and the others continue from the current state (``run(..., reset=False)``), so
    the chunks join into the same trajectory as one call. An estimator whose ``resumable``
    attribute is False is run in one call.

    Parameters
    ----------
    estimator : estimator object
        Any estimator with ``run``.
    y : ndarray, shape (N, n_y)
        Measurements.
    u : ndarray, shape (N, n_u), optional
        Inputs.
    label : str, optional
        Progress-bar label.
    quiet : bool, optional
        No progress bar.
    chunk : int, optional
        Rows per chunk.

    Returns
    -------
    Trajectory
    """
    from ..progress import Progress

    N = len(y)
    with Progress(N, label, quiet=quiet) as bar:
        if not bar.enabled and chunk is None:
            return estimator.run(y, u)  # nothing to draw: one call
        if not getattr(estimator, "resumable", True):
            # a run that cannot continue another (setbound.jobs.cora: CORA's runners process the
            # whole record at once): one call, the bar jumps to the end
            traj = estimator.run(y, u)
            bar.update(N)
            return traj
        if chunk is None:
            chunk = max(1, -(-N // 50))
        parts = []
        for a in range(0, N, chunk):
            b = min(N, a + chunk)
            parts.append(estimator.run(y[a:b], None if u is None else u[a:b], reset=(a == 0)))
            bar.update(b - a)
    return _concat(parts)


def run_estimator(job: Job, spec: EstimatorSpec, *, keep_going: bool = False, quiet: bool = False) -> Result:
    """Builds and runs one estimator of ``job``. With ``keep_going`` a library error (an
    infeasible design, an undetectable pair, …) is returned in :attr:`Result.error` instead of
    raised.

    Parameters
    ----------
    job : Job
        The job.
    spec : EstimatorSpec
        The estimator.
    keep_going : bool, optional
        Return a library error in the Result instead of raising.
    quiet : bool, optional
        No progress output.

    Returns
    -------
    Result
    """
    if job.y is None:
        raise ValueError("job: loaded for checking only (simulate=False); load it with simulate=True to run it")
    kind = ESTIMATORS[spec.method]
    t0 = time.perf_counter()
    try:
        est, design = kind.build(job, spec.options)
        t1 = time.perf_counter()
        traj = run_trajectory(est, job.y, job.u, label=spec.name, quiet=quiet)
        t2 = time.perf_counter()
        if job.t is not None and len(job.t) == len(traj.center):
            traj.t = np.asarray(job.t, dtype=float)  # the job's time of each row
    except SetboundError as exc:
        if not keep_going:
            raise
        return Result(spec.name, spec.method, None, time.perf_counter() - t0, float("nan"), None,
                      error=f"{type(exc).__name__}: {exc}")
    contained = None
    if job.x_true is not None and traj.guaranteed:
        # with an injected fault the model no longer holds from its start: the guarantee (and the
        # check) covers the steps before it
        upto = len(job.x_true) if job.fault_start is None else job.fault_start
        contained = bool(np.all(traj.in_bounds(job.x_true)[:upto]))
    # a design shared with an earlier estimator of the job: report what it took to compute
    shared = max((dt for d, dt in job.designs.values() if d is design), default=0.0) if design is not None else 0.0
    res = Result(spec.name, spec.method, traj, max(t1 - t0, shared), (t2 - t1) / max(1, len(job.y)), contained,
                 design=design)
    if kind.steady_volume is not None and design is not None:
        res.steady_volume, res.steady_volume_kind = float(kind.steady_volume(design, traj)), "rho_inf"
    elif traj.sets:
        v = traj.volume
        if len(v) and np.isfinite(v[-1]):
            res.steady_volume, res.steady_volume_kind = float(v[-1]), "final"
    return res


def run(job: Job, *, keep_going: bool = False, quiet: bool = False) -> list[Result]:
    """Runs every estimator of ``job`` in order (see :func:`run_estimator`), then the isolation
    bank of its ``[[hypothesis]]`` tables (``job.isolation``).

    Parameters
    ----------
    job : Job
        The job.
    keep_going : bool, optional
        Report a failing estimator in its Result instead of raising.
    quiet : bool, optional
        No progress output.

    Returns
    -------
    list of Result
    """
    results = [run_estimator(job, spec, keep_going=keep_going, quiet=quiet) for spec in job.estimators]
    if job.hypotheses and job.y is not None:
        from ..fault import FaultBank
        from .linear import zonotopic_initial

        job.isolation = FaultBank(job.system, zonotopic_initial(job.initial), job.hypotheses).run(job.y, job.u)
    return results
