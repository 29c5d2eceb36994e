"""
Thesis §4.6.3: the nonlinear interval observer
==============================================

[Loukkas2018] Figs 4.12–4.13: bounds of x1 and x2 from the nonlinear interval observer
(``h = δ(sin(0.5k·x2), sin(0.3k))``, ``[h] = [−0.8, 0.8]²``, gain from LMI 4.46) with the true
state (δ = 0.8, ``x_0 = (2, −2)``, observer start (−2, 2)).

Method: :ref:`iobs-nonlinear`. Job file ``examples/thesis_ex4_6_3.toml``.
"""
from pathlib import Path

from setbound import jobs, plotting

EXAMPLES = Path(globals().get("__file__", "plot.py")).resolve().parent.parent  # the repository's examples/

job = jobs.load(EXAMPLES / "thesis_ex4_6_3.toml")
trajs = {r.name: r.trajectory for r in jobs.run(job, quiet=True)}
fig = plotting.plot_bounds(trajs, x_true=job.x_true, title="Thesis §4.6.3: nonlinear interval observer")
