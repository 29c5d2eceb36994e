"""
EX-ME17: improved ellipsoidal correction against the Kalman filter
==================================================================

The two examples of [Merhy2017] (a stable and an unstable system): online ellipsoidal bounds, the
improved measurement-based correction and the Kalman filter's mean ± 3σ (not guaranteed, dotted),
with the true state, 10 steps from the Euclidean ball of radius √20 around (5, 5).

Methods: :ref:`ell-online`, :ref:`ell-improved`, :ref:`ell-kalman`.
Job files ``examples/me17_stable.toml`` and ``examples/me17_unstable.toml``.
"""
from pathlib import Path

from setbound import jobs, plotting

EXAMPLES = Path(globals().get("__file__", "plot.py")).resolve().parent.parent  # the repository's examples/

figs = []
for example, label in (("me17_stable.toml", "Example 1 (stable)"), ("me17_unstable.toml", "Example 2 (unstable)")):
    job = jobs.load(EXAMPLES / example)
    trajs = {r.name: r.trajectory for r in jobs.run(job, quiet=True)}
    figs.append(plotting.plot_bounds(trajs, x_true=job.x_true, title=f"EX-ME17, {label}: bounds"))
