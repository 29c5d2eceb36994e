"""
EX-ME19: ellipsoidal estimation for a descriptor system
=======================================================

The example of [Merhy2019]: a descriptor system ``E x⁺ = A x + B u + D w`` with a singular ``E``,
inputs ``u = (0.5 sin t + 1, −2 cos t)``, ``t ∈ [0, 5π]``. Bounds of the three states with the
true state, and the volume of the estimation set decreasing to its steady value.

Method: :ref:`ell-descriptor`. Job file ``examples/me19_descriptor.toml``.
"""
from pathlib import Path

from setbound import jobs, plotting

EXAMPLES = Path(globals().get("__file__", "plot.py")).resolve().parent.parent  # the repository's examples/

job = jobs.load(EXAMPLES / "me19_descriptor.toml")
trajs = {r.name: r.trajectory for r in jobs.run(job, quiet=True)}
fig = plotting.plot_bounds(trajs, x_true=job.x_true, t=job.t, title="EX-ME19: bounds of x1, x2, x3")

# %%
fig = plotting.plot_volume(trajs, t=job.t, title="EX-ME19: volume of the estimation set")
