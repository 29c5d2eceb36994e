"""The zonotopic papers' example system EX-LE13 with a known A (papers.md §3.5), shared by the
tests of real measurement data, fault detection, initial sets and trajectories."""
import numpy as np

import setbound as sb


def ex_le13(dt=None) -> sb.LinearSystem:
    """EX-LE13 with A known: x+ = [0 -0.5; 1 1] x + [-0.12; 0.02] w, y = C x + 0.2 v (ω = [w; v1; v2])."""
    A = np.array([[0.0, -0.5], [1.0, 1.0]])
    E = np.array([[-0.12, 0, 0], [0.02, 0, 0]])
    F = np.array([[0, 0.2, 0], [0, 0, 0.2]])
    return sb.LinearSystem(A, [[-2.0, 1.0], [1.0, 1.0]], E=E, F=F, dt=dt)


#: EX-LE13 as the ``[system]`` table of a job file (the same model as :func:`ex_le13`).
LE13_JOB_SYSTEM = """
[system]
A = [[0, -0.5], [1, 1]]
C = [[-2, 1], [1, 1]]
E = [[-0.12, 0, 0], [0.02, 0, 0]]
F = [[0, 0.2, 0], [0, 0, 0.2]]
"""


def record(s, N, rng, vertex, x0=(1.0, 1.0), jump=None):
    """Truth and readings of ``s`` from ``x0`` (ω uniform in its box, or at its vertices);
    ``jump = (k, dx)``: the state jumps by dx before step k (a violation of the model, e.g. a hit
    on the plant)."""
    draw = (lambda n: rng.choice([-1.0, 1.0], n)) if vertex else (lambda n: rng.uniform(-1, 1, n))
    xs, ys = [], []
    x = np.array(x0, float)
    for k in range(N):
        if jump is not None and k == jump[0]:
            x = x + jump[1]
        w = draw(s.nw)
        xs.append(x.copy())
        ys.append(s.C @ x + s.F @ w)
        x = s.A @ x + s.E @ w
    return np.array(xs), np.array(ys)
