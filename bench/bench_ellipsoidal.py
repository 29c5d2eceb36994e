"""Ellipsoidal estimators: per-step time of every method, design time and the Kalman step,
on the 3-state example of papers.md §1.4 (EX-BC14) and on random 6-state systems, from Python.

Medians over >= 200 steps (each step timed on its own, after a short warm-up). Prints a
Markdown table and, with --write, replaces it in the "Ellipsoidal estimators" section of
docs/benchmarks.md (between the bench_ellipsoidal markers; the commentary around them stays). The C++-side figures come from bench/bench_ellipsoidal_cpp (built with
-DSETBOUND_BUILD_BENCH=ON); pass its output file with --cpp to merge them into the table.

    python bench/bench_ellipsoidal.py [--steps 300] [--write] [--cpp FILE]
"""
from __future__ import annotations

import argparse
import math
import os
import platform
import statistics
import time
from pathlib import Path

import numpy as np

import setbound as sb
from setbound import ellipsoidal as ell
from setbound.simulation import simulate

from doc_region import write_region

ROOT = Path(__file__).resolve().parents[1]


def bc14():
    return sb.LinearSystem([[1, 0, 0.2], [0, 0.8, 1], [0, 0, 1]], [[1, 0, 2], [0, -1, 1]],
                           E=[[0.1, 0, 0, 0, 0], [0, 0.05, 0, 0, 0], [0, 0, 0.05, 0, 0]],
                           F=[[0, 0, 0, 0.15, 0], [0, 0, 0, 0, 0.15]])


class SplitMix64:
    """The generator bench_ellipsoidal_cpp.cpp uses too (splitmix64, uniform from the top 53 bits,
    Box-Muller normals), so that both programs time the same random system."""

    def __init__(self, seed):
        self.state = seed & 0xFFFFFFFFFFFFFFFF

    def next(self):
        self.state = (self.state + 0x9E3779B97F4A7C15) & 0xFFFFFFFFFFFFFFFF
        z = self.state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & 0xFFFFFFFFFFFFFFFF
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & 0xFFFFFFFFFFFFFFFF
        return z ^ (z >> 31)

    def uniform(self):
        return (self.next() >> 11) * 2.0**-53

    def normal(self):
        u1, u2 = self.uniform(), self.uniform()
        return math.sqrt(-2.0 * math.log(1.0 - u1)) * math.cos(6.283185307179586 * u2)

    def normals(self, rows, cols):
        return np.array([[self.normal() for _ in range(cols)] for _ in range(rows)])


def random6(seed):
    """A random detectable 6-state system, 2 outputs, 6 disturbances (4 state, 2 output); the same
    draws as random6() in bench_ellipsoidal_cpp.cpp."""
    g = SplitMix64(seed)
    while True:
        A = g.normals(6, 6)
        A *= 0.9 / max(abs(np.linalg.eigvals(A)))
        C = g.normals(2, 6)
        E = np.hstack([0.1 * g.normals(6, 4), np.zeros((6, 2))])
        F = np.hstack([np.zeros((2, 4)), 0.1 * np.eye(2)])
        s = sb.LinearSystem(A, C, E=E, F=F)
        if s.is_detectable():
            return s


def per_step_ms(make, y, warmup=5):
    est = make()
    times = []
    for k in range(y.shape[0]):
        t0 = time.perf_counter()
        est.step(y[k])
        times.append(time.perf_counter() - t0)
    return 1e3 * statistics.median(times[warmup:])


def bench_system(label, s, steps):
    x0 = sb.Ellipsoid(np.eye(s.nx), np.zeros(s.nx), 1.0)
    t0 = time.perf_counter()
    d = ell.design_offline(s)
    design_s = time.perf_counter() - t0
    y = simulate(s, x0, steps, rng=1).y
    rows = [(label, "offline design (logdet, β search)", 1e3 * design_s, "once")]
    for name, make in [
        ("offline step (§1.1)", lambda: ell.OfflineEstimator(d, x0)),
        ("online vertex step (§1.2)", lambda: ell.OnlineEstimator(d, x0)),
        ("online scaled step (§1.3)", lambda: ell.OnlineEstimator(d, x0, scaling=True)),
        ("online vertex step, solve every step", lambda: ell.OnlineEstimator(d, x0, reuse_tolerance=0.0)),
        ("online scaled step, solve every step", lambda: ell.OnlineEstimator(d, x0, scaling=True, reuse_tolerance=0.0)),
        ("improved step (online + correction, §6)", lambda: ell.ImprovedEstimator(d, x0)),
        ("Kalman step (§2.3)", lambda: ell.KalmanFilter(s, np.zeros(s.nx), np.eye(s.nx))),
    ]:
        rows.append((label, name, per_step_ms(make, y), f"median of {steps - 5}"))
    return rows


def table(rows, cpp):
    out = ["| system | what | Python ms | C++ ms | |", "|---|---|---:|---:|---|"]
    for sysname, what, ms, note in rows:
        c = cpp.get((sysname, what.split(" (")[0]))
        out.append(f"| {sysname} | {what} | {ms:.3f} | {'' if c is None else f'{c:.3f}'} | {note} |")
    return "\n".join(out)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--write", action="store_true")
    ap.add_argument("--cpp", help="output of bench_ellipsoidal_cpp (lines: system<TAB>what<TAB>ms)")
    a = ap.parse_args()
    rows = bench_system("EX-BC14 (n=3, n_y=2, n_ω=5)", bc14(), a.steps)
    rows += bench_system("random 6-state (n_y=2, n_ω=6)", random6(6), a.steps)
    cpp = {}
    if a.cpp:
        for line in Path(a.cpp).read_text().splitlines():
            parts = line.split("\t")
            if len(parts) == 3:
                cpp[(parts[0], parts[1])] = float(parts[2])
    md = table(rows, cpp)
    head = (f"Measured {time.strftime('%Y-%m-%d')} on {platform.machine()} ({os.cpu_count()} cores, "
            f"{platform.python_implementation()} {platform.python_version()}), setbound {sb.__version__}; "
            f"per-step medians, each step timed alone.")
    print(head)
    print(md)
    if a.write:
        # Only the generated head and table are replaced; the commentary around them stays.
        body = f"{head}\n\n{md}"
        write_region(ROOT / "docs" / "benchmarks.md", "bench_ellipsoidal", body, "Ellipsoidal estimators",
                     empty="# Benchmarks\n")


if __name__ == "__main__":
    main()
