"""
The wrapping effect: boxes against zonotopes
============================================

The unit box rotated by π/4 again and again ([Loukkas2018] Fig 1.4). Re-boxing the image at every
step grows the width by √2 per step — the wrapping effect of interval arithmetic; the zonotope
image is exact, and its interval hull stays bounded.

Methods: :ref:`sets-intervals`, :ref:`sets-zonotopes`.
"""
import math

import matplotlib.pyplot as plt
import numpy as np

import setbound

c = math.sqrt(0.5)
R = np.array([[c, -c], [c, c]])  # rotation by π/4
box = setbound.Box([-1.0, -1.0], [1.0, 1.0])
zono = setbound.Zonotope([0.0, 0.0], np.eye(2))
rows = []
for k in range(11):
    lo, hi = zono.interval_hull()
    rows.append((k, float(box.width.max()), float((hi - lo).max())))
    box = R @ box  # interval image: the box of the rotated box
    zono = R @ zono  # exact image

fig, ax = plt.subplots(figsize=(6.0, 3.6))
k = [r[0] for r in rows]
ax.semilogy(k, [r[1] for r in rows], "o-", label="box, re-boxed at every step")
ax.semilogy(k, [r[2] for r in rows], "s-", label="zonotope (exact image), its hull")
ax.semilogy(k, [2 * math.sqrt(2) ** i for i in k], "k:", lw=0.8, label=r"$2\cdot\sqrt{2}^{\,k}$")
ax.set(xlabel="rotations by π/4", ylabel="largest width", title="Wrapping effect (thesis Fig 1.4)")
ax.grid(alpha=0.3, which="both")
ax.legend(fontsize=8)
