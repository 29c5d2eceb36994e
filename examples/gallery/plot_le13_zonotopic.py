"""
EX-LE13: zonotopic estimators with an interval matrix
=====================================================

The example of [Le2013] (inspired from [Alamo2005]): bounds of x1 under segment minimisation,
volume minimisation and the P-radius estimators (approaches 1 and 2) with an interval ``A``
(``a22 ∈ [0.7, 1.3]``, drawn at every step) and at most 20 generators.

Methods: :ref:`zono-segment`, :ref:`zono-volume`, :ref:`zono-pradius`, :ref:`zono-interval`.
Job file ``examples/le13_interval.toml``.
"""
from pathlib import Path

from setbound import jobs, plotting

EXAMPLES = Path(globals().get("__file__", "plot.py")).resolve().parent.parent  # the repository's examples/

job = jobs.load(EXAMPLES / "le13_interval.toml")
trajs = {r.name: r.trajectory for r in jobs.run(job, quiet=True)}
fig = plotting.plot_bounds(trajs, x_true=job.x_true, components=[0], title="EX-LE13: bounds of x1",
                           figsize=(7.5, 3.6))

# %%
# Bound widths relative to segment minimisation (below 1: tighter).
fig = plotting.plot_widths(trajs, reference="segment_min", title="EX-LE13: widths relative to segment minimisation")

# %%
# The zonotope volume over time: the P-radius approach 2 close to volume minimisation, both below
# approach 1 and segment minimisation, as the paper reports.
fig = plotting.plot_volume(trajs, title="EX-LE13: zonotope volume")
