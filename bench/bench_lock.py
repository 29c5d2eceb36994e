"""Cost of the per-object lock of the Python wrappers (issue 26 point 2).

    .venv/bin/python bench/bench_lock.py [--steps 20000] [--runs 21]

Every public method of a class that holds a mutable C handle runs under the object's own
``threading.RLock`` (setbound._state.ThreadSafe). This measures what that adds to one call of
a cheap step, where it weighs most: the interval Luenberger observer and the Kalman filter
(a few µs per step), and a ThreadSafe method that does nothing (the wrapper and lock alone). "without" calls the same method unlocked through its
``__wrapped__`` attribute (what the class did before), "with" calls it normally; runs of both
alternate so that a change of the machine's load hits both alike. Reported: the median over
``--runs`` runs of the time per step, and the difference (the lock's cost). Also the bare cost
of ``with lock:`` on an RLock, for scale. Timings are never asserted in tests.
"""
from __future__ import annotations

import argparse
import datetime
import os
import platform
import statistics
import threading
import time

import numpy as np

import setbound as sb
from setbound import ellipsoidal, interval_observers as iobs
from setbound._state import ThreadSafe


def cpu_name() -> str:
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def per_step(fn, steps: int) -> float:
    """Seconds per call of fn() over `steps` calls."""
    t0 = time.perf_counter()
    for _ in range(steps):
        fn()
    return (time.perf_counter() - t0) / steps


def compare(name: str, obj, args, steps: int, runs: int) -> tuple[float, float]:
    locked = getattr(obj, "step")
    unlocked_fn = type(obj).step.__wrapped__  # the method as it was before the lock

    def unlocked():
        return unlocked_fn(obj, *args)

    def with_lock():
        return locked(*args)

    per_step(with_lock, steps // 10)  # warm-up
    per_step(unlocked, steps // 10)
    w, wo = [], []
    for _ in range(runs):
        wo.append(per_step(unlocked, steps))
        w.append(per_step(with_lock, steps))
    mw, mwo = statistics.median(w), statistics.median(wo)
    diffs = sorted(a - b for a, b in zip(w, wo))
    # medians, and the fastest runs (load on the machine only ever adds time)
    print(f"{name:28s} median: without {mwo * 1e6:8.3f} µs, with {mw * 1e6:8.3f} µs, lock {(mw - mwo) * 1e9:6.0f} ns "
          f"(paired: {statistics.median(diffs) * 1e9:.0f} ns);  fastest: without {min(wo) * 1e6:8.3f} µs, "
          f"with {min(w) * 1e6:8.3f} µs, lock {(min(w) - min(wo)) * 1e9:6.0f} ns")
    return mwo, mw


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--steps", type=int, default=20000, help="steps per timed run")
    ap.add_argument("--runs", type=int, default=21, help="timed runs of each variant")
    a = ap.parse_args()

    print(f"{datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC; {cpu_name()}, "
          f"{os.cpu_count()} logical CPUs; Python {platform.python_version()}; setbound {sb.__version__}")
    print(f"median of {a.runs} runs of {a.steps} steps each")

    A = np.array([[0.5, 0.1], [0.0, 0.4]])
    p = sb.Plant(A, [[1.0, 0.0]], B=[[1.0], [0.0]], F=[[0.1], [0.1]], Z=[[0.1]])
    obs = iobs.IntervalLuenbergerObserver(p, sb.Box([-1, -1], [1, 1]), np.zeros(2), sb.Box([-1], [1]),
                                          sb.Box([-1], [1]))
    y, u = np.array([0.01]), np.zeros(1)
    compare("IntervalLuenbergerObserver", obs, (y, u), a.steps, a.runs)

    S = sb.LinearSystem(A, [[1.0, 0.0]], B=[[1.0], [0.0]], E=np.diag([0.1, 0.1]), F=[[0.0, 0.1]])
    kf = ellipsoidal.KalmanFilter(S, np.zeros(2), np.eye(2))
    compare("KalmanFilter", kf, (y, u), a.steps, a.runs)

    class Noop(ThreadSafe):
        """The wrapper alone: a locked method that does nothing."""

        def step(self):
            return None

    compare("ThreadSafe no-op method", Noop(), (), a.steps, a.runs)

    lock = threading.RLock()

    def bare():
        with lock:
            pass

    def nothing():
        pass

    b = [per_step(bare, a.steps) for _ in range(a.runs)]
    n = [per_step(nothing, a.steps) for _ in range(a.runs)]
    print(f"{'with RLock: (bare)':28s} median {(statistics.median(b) - statistics.median(n)) * 1e9:.0f} ns, fastest "
          f"{(min(b) - min(n)) * 1e9:.0f} ns above an empty call")
    print(f"load average when done: {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
