"""
Thesis Chapter 3: LPV observers (Example 1 and the quasi-LPV Lorenz system)
===========================================================================

[Loukkas2018] §3.6. Example 1: bounds of the LPV ellipsoidal-invariant-set observer (Algorithm 3,
vertex gains with a common ``P``) with the scheduling ``ρ_k = 0.075 + 0.025 sin(0.1k)`` (a choice:
the thesis shows its profile only in Fig 3.4). Example 2: the discrete Lorenz model in quasi-LPV
form (``ρ1 = x1`` measured, ``ρ2 = 10``), ``w_k = (2 sin(0.04k), 0)``, ``u = 10``.

Method: :ref:`hinf-lpv`. Job files ``examples/thesis_ch3_ex1.toml`` and
``examples/thesis_ch3_ex2_lorenz.toml``.
"""
from pathlib import Path

from setbound import jobs, plotting

EXAMPLES = Path(globals().get("__file__", "plot.py")).resolve().parent.parent  # the repository's examples/

job = jobs.load(EXAMPLES / "thesis_ch3_ex1.toml")
trajs = {r.name: r.trajectory for r in jobs.run(job, quiet=True)}
fig = plotting.plot_bounds(trajs, x_true=job.x_true, title="Thesis Ch. 3 Ex 1: LPV observer bounds")

# %%
job = jobs.load(EXAMPLES / "thesis_ch3_ex2_lorenz.toml")
trajs = {r.name: r.trajectory for r in jobs.run(job, quiet=True)}
fig = plotting.plot_bounds(trajs, x_true=job.x_true, title="Thesis Ch. 3 Ex 2: quasi-LPV Lorenz")
