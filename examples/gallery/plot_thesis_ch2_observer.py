"""
Thesis Chapter 2: the ellipsoidal-invariant-set observer
========================================================

[Loukkas2018] §2.5, Figs 2.3–2.5: bounds ``x̂_k ± ē∞·√μ_k`` of the Chapter 2 observer (Algorithm 2,
γ and L from LMI 2.35, λ from the refinement 2.36) and, for comparison, of the Chapter 4 interval
Luenberger observer on the same data; then the scaling ``μ_k`` and the error sets. Uniform random
d, v (the thesis does not give its profiles).

Methods: :ref:`hinf-algorithm2`, :ref:`hinf-online`, :ref:`hinf-covariance`.
Job file ``examples/thesis_ch2_sec2_5.toml``.
"""
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from setbound import hinf, jobs, plotting

EXAMPLES = Path(globals().get("__file__", "plot.py")).resolve().parent.parent  # the repository's examples/

job = jobs.load(EXAMPLES / "thesis_ch2_sec2_5.toml")
res = {r.name: r for r in jobs.run(job, quiet=True)}
fig = plotting.plot_bounds({n: r.trajectory for n, r in res.items()}, x_true=job.x_true,
                           title="Thesis Ch. 2 §2.5: bounds (Fig 2.3)")

# %%
# The scaling ``μ_(k+1) = (1 − λ)μ_k + λ`` of the error ellipsoid goes from ``μ_0`` (the corners of
# ``[e_0]``) down to 1 (Fig 2.4): the error set is then the invariant ellipsoid ``{eᵀPe ≤ c̄}``.
tr = res["ellipsoidal-sm"].trajectory
fig, ax = plt.subplots(figsize=(6.0, 3.6))
ax.plot(np.arange(len(tr.mu)), tr.mu, "o-", ms=3)
ax.axhline(1.0, color="k", ls=":", lw=0.8)
ax.set(xlabel="k", ylabel=r"$\mu_k$", title=r"Thesis Ch. 2: $\mu_k \to 1$ (Fig 2.4)")
ax.grid(alpha=0.3)

# %%
# The estimation errors (crosses: the transient, while ``μ_k > 1.01``), the invariant ellipsoid and
# the Chebyshev ellipsoid ``{eᵀV⁻¹e ≤ t²}``, t = 3 (2.41: probabilistic, reporting only) (Fig 2.5).
design = res["ellipsoidal-sm"].design
e = job.x_true - tr.center
late = np.asarray(tr.mu) <= 1.01
fig, ax = plt.subplots(figsize=(5.2, 4.4))
ax.plot(e[late, 0], e[late, 1], ".", color="k", ms=3, label=r"$e_k$, $\mu_k \leq 1.01$")
ax.plot(e[~late, 0], e[~late, 1], "x", color="0.5", ms=4, label=r"$e_k$ in the transient")
pts = plotting.ellipse_points(design.P, np.zeros(2), design.cbar)
ax.plot(pts[:, 0], pts[:, 1], color="C0", label=r"invariant $\{e^TPe \leq \bar c\}$")
Vi, t2, prob = hinf.chebyshev_error_ellipsoid(design.V, 3.0)
pts = plotting.ellipse_points(Vi, np.zeros(2), t2)
ax.plot(pts[:, 0], pts[:, 1], color="C3", ls="--", label=f"Chebyshev, t = 3 (P ≥ {prob:.2f})")
ax.set(xlabel="e1", ylabel="e2", title="Thesis Ch. 2: error sets (Fig 2.5)")
ax.legend(fontsize=7)
ax.grid(alpha=0.3)
