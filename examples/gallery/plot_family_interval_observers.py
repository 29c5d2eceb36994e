"""
Interval and ellipsoidal-invariant-set observers (thesis)
=========================================================

The observers of [Loukkas2018] on one plant ``x⁺ = A x + F d``, ``y = C x + Z v``: the interval
Luenberger observer (Chapter 4; the error box follows the exact interval recursion) and the
ellipsoidal-invariant-set observer (Chapter 2; the error stays in ``{eᵀPe ≤ μ_k c̄}``).
Both are one-step predictors built from an H∞ gain.

Methods: :ref:`iobs-luenberger`, :ref:`hinf-algorithm2`, :ref:`hinf-online`.
"""
import numpy as np

import setbound
from setbound import hinf, plotting

plant = setbound.Plant([[0.5, 0.2], [-0.1, 0.6]], [[1.0, 0.0]], Fd=0.1 * np.eye(2), Z=[[0.1]])
x0 = setbound.Box([-1.0, -1.0], [1.0, 1.0])

# a simulation inside the bounds: |d_i| <= 1, |v| <= 1 (unit boxes)
rng = np.random.default_rng(5)
N = 40
x = np.empty((N, 2))
y = np.empty((N, 1))
x[0] = [0.8, -0.6]
for k in range(N):
    y[k] = plant.C @ x[k] + plant.Z @ rng.uniform(-1, 1, 1)
    if k + 1 < N:
        x[k + 1] = plant.A @ x[k] + plant.F @ rng.uniform(-1, 1, 2)

luenberger = setbound.IntervalLuenbergerObserver(plant, x0)
design = hinf.design_ellipsoidal_sm_observer(plant)
sm = hinf.EllipsoidalSMObserver(design, x0)
trajs = {"interval Luenberger": luenberger.run(y), "ellipsoidal SM": sm.run(y)}
print({name: bool(t.in_bounds(x).all()) for name, t in trajs.items()})
fig = plotting.plot_bounds(trajs, x_true=x, title="Thesis observers on one plant")
