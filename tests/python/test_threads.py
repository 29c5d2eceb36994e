"""Concurrency from Python (issue 8): cffi releases the GIL during C calls, so independent
estimator objects really run at the same time on several threads. They must give bit-for-bit
the results of sequential use, and the library's last-error message (read by the bindings right
after a failing call) is per thread."""
from __future__ import annotations

import threading

import numpy as np

import setbound as sb
from setbound import Box, Ellipsoid, LinearSystem, Plant, Zonotope
from setbound import ellipsoidal, hinf, interval_observers as iobs, zonotopic
from setbound._native import ffi, last_error, lib

A = np.array([[0.5, 0.1], [0.0, 0.4]])
B = np.array([[1.0], [0.0]])
C = np.array([[1.0, 0.0]])
E = np.diag([0.1, 0.1])
F = np.array([[0.0, 0.1]])
N = 20


def data():
    rng = np.random.default_rng(5)
    x = np.array([0.3, -0.2])
    ys, us = [], []
    for _ in range(N):
        w = rng.uniform(-1, 1, 2)
        u = rng.standard_normal(1) * 0.1
        ys.append(C @ x + F @ w)
        us.append(u)
        x = A @ x + B @ u + E @ w
    return np.array(ys), np.array(us)


def run(family):
    y, u = data()
    S = LinearSystem(A, C, B=B, E=E, F=F)
    out = []
    if family == "ellipsoidal":
        est = ellipsoidal.OnlineEstimator(ellipsoidal.design_offline(S), Ellipsoid(np.eye(2), np.zeros(2), 1.0))
        for k in range(N):
            e = est.step(y[k], u[k])
            out += [e.P, e.center, np.array([e.rho])]
    elif family == "zonotopic":
        est = zonotopic.SegmentMinEstimator(S, Zonotope(np.zeros(2), np.eye(2)), max_generators=8)
        for k in range(N):
            z = est.step(y[k], u[k])
            out += [z.center, z.generators]
    elif family == "kalman":
        kf = ellipsoidal.KalmanFilter(S, np.zeros(2), np.eye(2))
        for k in range(N):
            m, P = kf.step(y[k], u[k])
            out += [m, P]
    elif family == "interval":
        p = Plant(A, C, B=B, F=[[0.1], [0.1]], Z=[[0.1]])
        obs = iobs.IntervalLuenbergerObserver(p, Box([-1, -1], [1, 1]), np.zeros(2), Box([-1], [1]), Box([-1], [1]))
        for k in range(N):
            b = obs.step(y[k], u[k])
            out += [b.lo, b.hi]
    elif family == "hinf":
        p = Plant(A, C, B=B, F=[[0.1], [0.1]], Z=[[0.1]])
        d = hinf.design_ellipsoidal_sm_observer(p, [1.0, 1.0])
        obs = hinf.EllipsoidalSMObserver(d, np.zeros(2), 2.0)
        for k in range(N):
            b = obs.step(y[k], u[k])
            out += [b.lo, b.hi]
    return [np.ascontiguousarray(a, dtype=float).tobytes() for a in out]


FAMILIES = ("ellipsoidal", "zonotopic", "kalman", "interval", "hinf")


def test_independent_estimators_on_threads_match_sequential_bit_for_bit():
    reference = {f: run(f) for f in FAMILIES}
    results, errors = {}, []
    barrier = threading.Barrier(4)

    def worker(t):
        try:
            barrier.wait()
            for i in range(len(FAMILIES)):
                f = FAMILIES[(t + i) % len(FAMILIES)]
                results[(t, f)] = run(f)
        except Exception as exc:  # noqa: BLE001 - reported below
            errors.append(exc)

    threads = [threading.Thread(target=worker, args=(t,)) for t in range(4)]
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    assert not errors, errors
    for (t, f), r in results.items():
        assert r == reference[f], f"{f} on thread {t} differs from the sequential run"
    assert len(results) == 4 * len(FAMILIES)


def test_last_error_is_per_thread():
    """Thread A provokes a NaN error, thread B a dimension error, over and over at the same time;
    each sees its own message (the exception text comes from the library's last error)."""
    barrier = threading.Barrier(2)
    bad = []

    def a():
        barrier.wait()
        for _ in range(500):
            try:
                Ellipsoid(np.eye(1), [np.nan], 1.0)
                bad.append("A: no error")
            except sb.NotFiniteError as exc:
                if not str(exc).startswith("sb_ellipsoid_validate: c"):
                    bad.append(f"A: {exc}")

    def b():
        barrier.wait()
        for _ in range(500):
            rc = lib.sb_box_volume(-3, ffi.NULL, ffi.NULL, ffi.NULL)
            msg = last_error()
            if rc != lib.SB_ERR_DIMENSION or not msg.startswith("sb_box_volume: ") or "-3" not in msg:
                bad.append(f"B: {msg}")

    ts = [threading.Thread(target=a), threading.Thread(target=b)]
    for t in ts:
        t.start()
    for t in ts:
        t.join()
    assert not bad, bad[:5]
