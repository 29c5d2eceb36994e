"""A zero row of C (issue 26 point 6): an output that measures only noise (plus D u) says nothing
about x; every zonotopic estimator skips its strip. Volume minimisation used to fail at the
first step (a strip cannot have a zero normal). Skipping is exact: the run equals, bit for bit,
the run of the same system without that output, and it contains the true state. (C++:
ZonotopicZeroRowOfC.*)"""
import math

import numpy as np
import pytest

import setbound as sb
from setbound import zonotopic as zono


def _wave(k, j):
    s = math.sin(1.3 * k + 0.7 * j + 0.1 * k * j)
    return (1.0 if s >= 0 else -1.0) if (k + j) % 5 == 0 else s


A = np.array([[-0.8, 0.2], [-0.3, 0.1]])
B = np.array([[1.0], [0.5]])
E = np.array([[-0.12, 0.0, 0.0], [0.02, 0.0, 0.0]])
C2 = np.array([[-2.0, 1.0], [0.0, 0.0]])       # output 2: y2 = 0.5 u + 0.3 w3
D2 = np.array([[0.1], [0.5]])
F2 = np.array([[0.0, 0.2, 0.0], [0.0, 0.0, 0.3]])


def _run(N=30):
    x = np.zeros(2)
    xs, ys, us = [], [], []
    for k in range(N):
        w = np.array([_wave(k, j) for j in range(3)])
        u = np.array([0.5 * math.cos(0.4 * k)])
        xs.append(x)
        ys.append(C2 @ x + D2 @ u + F2 @ w)
        us.append(u)
        x = A @ x + B @ u + E @ w
    return np.array(xs), np.array(ys), np.array(us)


@pytest.mark.parametrize("rule", ["volume", "segment"])
def test_zero_row_of_c_is_skipped(rule):
    full = sb.LinearSystem(A, C2, B=B, D=D2, E=E, F=F2)
    reduced = sb.LinearSystem(A, C2[:1], B=B, D=D2[:1], E=E, F=F2[:1])
    cls = zono.VolumeMinEstimator if rule == "volume" else zono.SegmentMinEstimator
    x0 = sb.Zonotope(np.zeros(2), 2.0 * np.eye(2))
    xs, ys, us = _run()
    a = cls(full, x0, max_generators=5).run(ys, us)
    b = cls(reduced, x0, max_generators=5).run(ys[:, :1], us)
    assert a.lower.tobytes() == b.lower.tobytes() and a.upper.tobytes() == b.upper.tobytes()
    assert a.center.tobytes() == b.center.tobytes()
    for Za, Zb in zip(a.sets, b.sets):
        assert np.asarray(Za.generators).tobytes() == np.asarray(Zb.generators).tobytes()
    assert np.all(a.lower <= xs) and np.all(xs <= a.upper)
