"""
Ellipsoidal estimators in a few lines
=====================================

A guaranteed ellipsoidal estimator straight from the classes, without a job file: a linear system
with unit-box disturbances, the offline LMI design of [BenChabane2014] (shape ``P``, gain ``L``,
level recursion ``ρ⁺ ≤ βρ + σ``), a simulation, then the offline and the online estimators on the
same measurements. The true state is inside every set.

Methods: :ref:`ell-offline`, :ref:`ell-online`.
"""
import numpy as np

import setbound
from setbound import ellipsoidal, plotting, simulation

system = setbound.LinearSystem(A=[[1.0, 0.0, 0.2], [0.0, 0.8, 1.0], [0.0, 0.0, 1.0]],
                               C=[[1.0, 0.0, 2.0], [0.0, -1.0, 1.0]],
                               E=np.hstack([np.diag([0.1, 0.05, 0.05]), np.zeros((3, 2))]),
                               F=np.hstack([np.zeros((2, 3)), 0.15 * np.eye(2)]))
x0 = setbound.Ellipsoid(np.eye(3), np.zeros(3), 2.0)
design = ellipsoidal.design_offline(system)  # minimum steady-state volume
print(f"beta = {design.beta:.4f}, steady-state level rho_inf = {design.rho_inf:.4f}")

sim = simulation.simulate(system, x0, 40, rng=7)
trajs = {"offline": ellipsoidal.OfflineEstimator(design, x0).run(sim.y),
         "online": ellipsoidal.OnlineEstimator(design, x0).run(sim.y)}
print({name: bool(t.contains(sim.x).all()) for name, t in trajs.items()})
fig = plotting.plot_bounds(trajs, x_true=sim.x, title="Offline and online ellipsoidal bounds")
