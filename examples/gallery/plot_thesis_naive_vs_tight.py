"""
Thesis Fig 4.1: naive, wrapped and tight interval error recursions
==================================================================

On [Loukkas2018] Example 4.5.1: the naive recursion (4.15), which re-boxes ``A_o[e_k]`` at every
step, diverges although ``A_o`` is Schur (the wrapping effect); the thesis's formula (wrapped,
``[g_0] = E[w]`` boxed first) and the exact interval hull (tight) converge, tight ⊆ wrapped. The
point observer ``x̂_k`` is the same for all three.

Method: :ref:`iobs-recursions`. Built from ``examples/thesis_ex4_5_1.toml`` with its estimators
replaced (a job is a dict before :func:`setbound.jobs.from_dict`).
"""
import tomllib
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from setbound import jobs

EXAMPLES = Path(globals().get("__file__", "plot.py")).resolve().parent.parent  # the repository's examples/

doc = tomllib.loads((EXAMPLES / "thesis_ex4_5_1.toml").read_text())
doc["simulation"]["horizon"] = 30
doc.pop("plots", None)
doc["estimator"] = [{"method": "interval_luenberger", "variant": v, "name": v, "xhat0": [0, 0]}
                    for v in ("naive", "wrapped", "tight")]
job = jobs.from_dict(doc)
fig, ax = plt.subplots(figsize=(6.0, 3.6))
for r in jobs.run(job, quiet=True):
    ax.semilogy(np.arange(len(job.y)), r.trajectory.width.max(axis=1), "o-", ms=3, label=r.name)
ax.set(xlabel="k", ylabel="largest width of [x_k]", title="Thesis Fig 4.1: naive vs tight error boxes")
ax.legend(fontsize=8)
ax.grid(alpha=0.3, which="both")
