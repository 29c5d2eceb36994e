"""
Thesis Example 4.5.1: interval observers and their error sets
=============================================================

[Loukkas2018] Figs 4.5–4.6: bounds of the interval Luenberger observer (tight and the thesis's
wrapped formula) and of the invariant-set observer (λ = 11, μ = 2, ε = 0.01: the box sequence
``[s_k]`` up to k*, then Φ_k*'s box), with the true state from ``x_0 = (1, 1)``; then the polyhedral
invariant set Φ_0 between the ellipsoids Ψ̄⁺(μ) and Ψ̄(μ) of the H∞ design (LMI 4.13), the inflated
set λΦ_0 ⊇ [e_0] and the error box at k*.

Methods: :ref:`iobs-luenberger`, :ref:`iobs-invariant`. Job file ``examples/thesis_ex4_5_1.toml``.
"""
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from setbound import jobs, plotting

EXAMPLES = Path(globals().get("__file__", "plot.py")).resolve().parent.parent  # the repository's examples/

job = jobs.load(EXAMPLES / "thesis_ex4_5_1.toml")
res = {r.name: r for r in jobs.run(job, quiet=True)}
fig = plotting.plot_bounds({n: r.trajectory for n, r in res.items()}, x_true=job.x_true,
                           title="Thesis Ex 4.5.1: interval observers (Fig 4.5)")

# %%
D = res["invariant"].design
V = D.phi0_vertices.T


def closed(points):
    """The polygon through 2-D points, ordered by angle around their mean, closed."""
    c = points.mean(axis=0)
    points = points[np.argsort(np.arctan2(points[:, 1] - c[1], points[:, 0] - c[0]))]
    return np.vstack([points, points[:1]])


fig, axes = plt.subplots(1, 2, figsize=(9.6, 4.4))
for ax in axes:
    for level, style, label in ((D.c_out, "--", r"$\bar\Psi(\mu)$"), (D.c_in, ":", r"$\bar\Psi^+(\mu)$")):
        pts = plotting.ellipse_points(D.P, np.zeros(2), level)
        ax.plot(pts[:, 0], pts[:, 1], ls=style, lw=1.2, zorder=3, label=label)
    ax.plot(*closed(V).T, color="C1", lw=1.5, label=r"$\Phi_0$")
    ax.plot(*closed(D.inflation * V).T, color="C4", lw=1, label=rf"$\lambda\Phi_0$, $\lambda = {D.inflation:g}$")
    for lo, hi, style in ((D.lower[0], D.upper[0], dict(color="k", lw=0.8, ls="-.", label="[e_0]")),
                          (D.lower[-1], D.upper[-1], dict(color="C3", lw=1.5, label=rf"$[s_{{k^*}}]$, $k^* = {D.k_star}$"))):
        ax.plot([lo[0], hi[0], hi[0], lo[0], lo[0]], [lo[1], lo[1], hi[1], hi[1], lo[1]], **style)
    ax.set(xlabel="e1", ylabel="e2")
    ax.grid(alpha=0.3)
r = 1.3 * np.abs(V).max(axis=0)
axes[1].set(xlim=(-r[0], r[0]), ylim=(-r[1], r[1]), title="zoom on Φ_0")
axes[0].set(title="Thesis Ex 4.5.1: error sets (Fig 4.6)")
axes[0].legend(fontsize=7, loc="upper right")
