"""
EX-BC14: offline, online and scaled ellipsoidal estimators
==========================================================

The example of [BenChabane2014] (a 3-state system, two outputs): bounds of the three states under
the offline, online and scaled ellipsoidal estimators and, for comparison, the P-radius zonotopic
estimator of [Le2013] (approach 2; approach 1 is infeasible on this system), with the true state
(uniform disturbances, seed 2014). This recomputes the paper's Figs 1–6 and its Table 2 as curves.

Methods: :ref:`ell-offline`, :ref:`ell-online`, :ref:`ell-scaled`, :ref:`zono-pradius`.
The job file is ``examples/bc14_3state.toml`` of the repository.
"""
from pathlib import Path

from setbound import jobs, plotting

EXAMPLES = Path(globals().get("__file__", "plot.py")).resolve().parent.parent  # the repository's examples/ (the build runs scripts from their folder)

job = jobs.load(EXAMPLES / "bc14_3state.toml")
job.estimators = [s for s in job.estimators if s.name in ("offline", "online", "scaled", "pradius2")]
results = jobs.run(job, quiet=True)
trajs = {r.name: r.trajectory for r in results}
print({r.name: r.contained for r in results})

# %%
# Bounds of the three states; every guaranteed estimator contains the true state at every step.
fig = plotting.plot_bounds(trajs, x_true=job.x_true, title="EX-BC14: bounds of x1, x2, x3")

# %%
# Bound widths divided by the offline method's (Figs 4–6). Online equals offline at steady state
# for the β-optimised design; scaling is never tighter than online.
fig = plotting.plot_widths(trajs, reference="offline", title="EX-BC14: widths relative to offline")

# %%
# The volume of the sets over time ([BenChabane2014] Table 2 as a curve): the ellipsoidal volumes
# converge to their steady state. The paper's printed values are not reproducible from its data
# (see :ref:`ell-examples`); no fixed-shape volume falls below the minimum-volume design's.
fig = plotting.plot_volume(trajs, title="EX-BC14: volume of the sets")

# %%
# Not a paper figure: the sets projected on (x1, x2) at k = 0, 5, 49 — ellipses and the exact
# polygon of the projected zonotope — with the true state and the measurement strips of ``y_k``.
fig = plotting.plot_projections(trajs, steps=[0, 5, 49], dims=(0, 1), x_true=job.x_true, system=job.system,
                                y=job.y, title="EX-BC14: sets projected on (x1, x2)")
