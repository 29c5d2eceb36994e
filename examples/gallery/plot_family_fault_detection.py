"""
Guaranteed fault detection and isolation
========================================

A guaranteed estimator flags a reading that no state of the model can produce: with a sensor bias
injected at step 60, the alarm comes after the fault and never before it (no false alarm while the
model holds). A bank of estimators, one per fault hypothesis, isolates the fault by rejecting the
hypotheses the data contradict.

Method: :ref:`fault-detection`.
"""
import numpy as np

import setbound
from setbound import zonotopic
from setbound.fault import Fault, FaultBank, detect, nominal, sensor_bias, simulate_faulty, stuck_sensor

system = setbound.LinearSystem(A=[[0.0, -0.5], [1.0, 1.0]], C=[[-2.0, 1.0], [1.0, 1.0]],
                               E=[[0.02, 0.0, 0.0], [0.0, 0.0, 0.0]], F=[[0.0, 0.2, 0.0], [0.0, 0.0, 0.2]])
x0 = setbound.Zonotope([0.0, 0.0], 3.0 * np.eye(2))
sim = simulate_faulty(system, x0, 100, [Fault("sensor_bias", start=60, output=0, magnitude=0.8)], rng=24)

det = detect(zonotopic.SegmentMinEstimator(system, x0), sim.y)
print("alarm at step", det.alarm, "- delay", det.delay(60))
ax = det.plot(fault_start=60)  # the margin of each step; above 0: impossible reading

# %%
# Isolation: each hypothesis is rejected at the first reading its own model cannot produce.
bank = FaultBank(system, x0, [nominal(system, x0), sensor_bias(system, x0, 0, bound=2.0),
                              sensor_bias(system, x0, 1, bound=2.0), stuck_sensor(system, x0, 1)])
iso = bank.run(sim.y)
print(iso.table())
