"""
Zonotopic estimators and the exact hull
=======================================

Zonotopic filters on a 2-state system with one output: segment minimisation ([Alamo2005]), the
P-radius gains of [Le2013], and the exact interval hull of the consistent states (linear programs
per step) that every guaranteed hull contains.

Methods: :ref:`zono-segment`, :ref:`zono-pradius`, :ref:`zono-exact`.
"""
import numpy as np

import setbound
from setbound import plotting, simulation, zonotopic

system = setbound.LinearSystem(A=[[0.0, -0.5], [1.0, 1.0]], C=[[-2.0, 1.0]],
                               E=[[0.02, 0.0], [0.0, 0.0]], F=[[0.0, 0.2]])
x0 = setbound.Zonotope([0.0, 0.0], 3.0 * np.eye(2))
sim = simulation.simulate(system, x0, 30, rng=3)

design = zonotopic.design_pradius(system)
trajs = {"segment_min": zonotopic.SegmentMinEstimator(system, x0).run(sim.y),
         "pradius": zonotopic.PRadiusEstimator(design, x0).run(sim.y)}
hull = setbound.exact_hull(system, sim.y, x0=x0)
print({name: bool(t.contains(sim.x).all()) for name, t in trajs.items()})
print("hull inside the segment-min bounds:",
      bool(np.all(trajs["segment_min"].lower <= hull.lower + 1e-9) and np.all(hull.upper <= trajs["segment_min"].upper + 1e-9)))
fig = plotting.plot_widths(trajs, title="Zonotopic bound widths")

# %%
# The sets at three steps, projected on the plane, with the measurement strips of ``y_k``.
fig = plotting.plot_projections(trajs, steps=[0, 5, 29], x_true=sim.x, system=system, y=sim.y,
                                title="Zonotopes and measurement strips")
