"""
Thesis Example 1.5: outer approximation of the minimal RPI set (Algorithm 1)
============================================================================

[Loukkas2018] Figs 1.11–1.12: the polyhedral RPI set Φ_v between the ellipsoids Ψ̄⁺(μ) and Ψ̄(μ) of
the bounded-real-lemma matrix ``P``, the iterates ``Φ_k = AΦ_(k−1) ⊕ EΔ`` (grey) down to ``Φ_k*``
(stop when the shrinking index ``ρ̄_k ≤ ε = 4.4·10⁻³``) and a simulated trajectory started in
``[x_0] ⊆ Φ_v``. μ = 1.05 is a choice: the thesis does not state it.

Methods: :ref:`inv-brl`, :ref:`inv-polyhedral`, :ref:`inv-algorithm1`.
Job file ``examples/thesis_ex1_5.toml``.
"""
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from setbound import jobs, plotting

EXAMPLES = Path(globals().get("__file__", "plot.py")).resolve().parent.parent  # the repository's examples/

job = jobs.load(EXAMPLES / "thesis_ex1_5.toml")
d = jobs.run(job, quiet=True)[0].design

fig, ax = plt.subplots(figsize=(5.2, 4.4))
for level, style, label in ((d.c_out, "--", r"$\bar\Psi(\mu)$"), (d.c_in, ":", r"$\bar\Psi^+(\mu)$")):
    pts = plotting.ellipse_points(d.P, np.zeros(2), level)
    ax.plot(pts[:, 0], pts[:, 1], ls=style, lw=1.2, zorder=3, label=label)
for k, S in enumerate(d.sets):
    V = S.plot_data()
    if k == 0:
        ax.plot(V[:, 0], V[:, 1], color="C1", lw=1.5, label=r"$\Phi_0 = \Phi_v$")
    elif k == d.k_star:
        ax.plot(V[:, 0], V[:, 1], color="C3", lw=1.5, label=rf"$\Phi_{{k^*}}$, $k^*={d.k_star}$")
    else:
        ax.plot(V[:, 0], V[:, 1], color="0.6", lw=0.5)
ax.plot(job.x_true[:, 0], job.x_true[:, 1], ".", color="k", ms=3, label="x_k (simulation)")
ax.set(xlabel="x1", ylabel="x2", title="Thesis Ex 1.5: Algorithm 1 (Fig 1.11)")
ax.legend(fontsize=7, loc="upper right")
ax.grid(alpha=0.3)

# %%
# The shrinking index of Algorithm 1 against k (Fig 1.12); the iteration stops at the first k
# with ``ρ̄_k ≤ ε``.
fig, ax = plt.subplots(figsize=(6.0, 3.6))
k = np.arange(len(d.shrinking_index))
ax.semilogy(k, d.shrinking_index, "o-", ms=3, label=r"$\bar\rho_k$")
ax.axhline(4.4e-3, color="k", ls=":", lw=0.8, label=r"$\varepsilon = 4.4\cdot10^{-3}$")
ax.set(xlabel="k", ylabel="shrinking index", title=f"Thesis Ex 1.5: shrinking index (β = {d.beta:.4f})")
ax.legend(fontsize=8)
ax.grid(alpha=0.3, which="both")
