"""Fault detection: the smallest detectable sensor bias and the detection delay of each estimator
family, with the exact consistent set as the limit (issue 24; docs/fault_detection.md).

EX-LE13 with a known A (papers.md §3.5: 2 states, 2 outputs, noise bound 0.2 on each output),
X0 = 3 B^2, uniform disturbances. A bias of size b appears on output y0 at step START and stays;
each detector runs on the record and its delay is the number of steps from START to its first
impossible reading (none within the WINDOW steps after START: not detected). The same seeds
(disturbance realisations) go to every method. A bias is "detected" by a method when it is
detected in at least 90 % of the seeds; the smallest such bias of the grid is reported.

The exact limit: the consistent set of all the data is empty from the first step k no state of
the model explains the readings y_0 … y_k: the LP "x_0 = c + G ξ, y_j = C x_j + F ω_j,
x_{j+1} = A x_j + E ω_j, ‖ξ‖∞ ≤ 1, ‖ω_j‖∞ ≤ 1" has no solution. It is solved by SciPy's HiGHS
(a bench-only dependency) with a binary search on k (feasibility only shrinks with more data).
(zonotopic.exact_hull answers the same question but computes every hull on the way, and on these
nearly infeasible records its LP reached its iteration limit: noted for the LP-engine issue.)
No guaranteed detector can alarm earlier, and every alarm of a guaranteed detector is at or
after it.

Prints a Markdown table and, with --write, replaces it in docs/fault_detection.md (between the
bench_faults markers) and writes docs/fault_detection.png.

    python bench/bench_faults.py [--seeds 8] [--write]
"""
from __future__ import annotations

import argparse
import datetime
import os
import platform
import statistics
import time
from pathlib import Path

import numpy as np

from setbound import LinearSystem
from setbound.ellipsoidal import ImprovedEstimator, OfflineEstimator, OnlineEstimator, design_offline
from setbound.fault import Fault, detect, simulate_faulty
from setbound.sets import Ellipsoid, Zonotope
from setbound.zonotopic import PRadiusEstimator, SegmentMinEstimator, VolumeMinEstimator, design_pradius

from doc_region import replace_region

ROOT = Path(__file__).resolve().parents[1]
START, WINDOW = 40, 30
BIASES = [0.02, 0.03, 0.05, 0.08, 0.12, 0.2, 0.3, 0.5, 0.8, 1.2, 2.0]


def le13() -> LinearSystem:
    A = np.array([[0.0, -0.5], [1.0, 1.0]])
    E = np.array([[-0.12, 0, 0], [0.02, 0, 0]])
    F = np.array([[0, 0.2, 0], [0, 0, 0.2]])
    return LinearSystem(A, [[-2.0, 1.0], [1.0, 1.0]], E=E, F=F)


def methods(s):
    X0 = Zonotope([0, 0], 3 * np.eye(2))
    E0 = Ellipsoid(np.eye(2), [0, 0], 18.0)  # the ball through the corners of X0
    dp, de = design_pradius(s, approach=2), design_offline(s)
    return X0, {
        "zonotopic: segment min": lambda: SegmentMinEstimator(s, X0),
        "zonotopic: volume min": lambda: VolumeMinEstimator(s, X0),
        "zonotopic: P-radius": lambda: PRadiusEstimator(dp, X0),
        "ellipsoidal: offline": lambda: OfflineEstimator(de, E0),
        "ellipsoidal: online": lambda: OnlineEstimator(de, E0),
        "ellipsoidal: improved": lambda: ImprovedEstimator(de, E0),
    }


def _feasible(s, X0, y, k) -> bool:
    """Whether some x_0 in X0 and disturbances in the unit box explain y_0 … y_k exactly."""
    from scipy.optimize import linprog

    n, m0, nw = s.nx, X0.generators.shape[1], s.nw
    nv = m0 + nw * (k + 1)
    rows, rhs = [], []
    # x_j = Φ_j [ξ; ω_0 … ω_{j-1}] + A^j c, built recursively
    Phi = np.zeros((n, nv))
    Phi[:, :m0] = X0.generators
    off = np.asarray(X0.center, dtype=float)
    for j in range(k + 1):
        row = s.C @ Phi
        row[:, m0 + nw * j: m0 + nw * (j + 1)] += s.F
        rows.append(row)
        rhs.append(y[j] - s.C @ off)
        Phi = s.A @ Phi
        Phi[:, m0 + nw * j: m0 + nw * (j + 1)] += s.E
        off = s.A @ off
    res = linprog(np.zeros(nv), A_eq=np.vstack(rows), b_eq=np.concatenate(rhs), bounds=[(-1, 1)] * nv,
                  method="highs")
    if res.status not in (0, 2):
        raise RuntimeError(f"HiGHS: {res.message}")
    return res.status == 0


def exact_alarm(s, X0, y) -> int | None:
    """The first step whose data no state of the model explains, or None."""
    N = len(y)
    if _feasible(s, X0, y, N - 1):
        return None
    lo, hi = 0, N - 1  # infeasible at hi; find the first infeasible k
    while lo < hi:
        mid = (lo + hi) // 2
        if _feasible(s, X0, y, mid):
            lo = mid + 1
        else:
            hi = mid
    return lo


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seeds", type=int, default=8)
    ap.add_argument("--write", action="store_true")
    args = ap.parse_args()
    s = le13()
    X0, makers = methods(s)
    names = list(makers) + ["exact consistent set (limit)"]
    N = START + WINDOW
    delays = {n: {b: [] for b in BIASES} for n in names}
    early = {n: 0 for n in names}  # alarms before the fault: must stay 0
    t0 = time.perf_counter()
    for b in BIASES:
        for seed in range(args.seeds):
            sim = simulate_faulty(s, X0, N, [Fault("sensor_bias", start=START, output=0, magnitude=b)], rng=seed)
            for n, make in makers.items():
                det = detect(make(), sim.y)
                early[n] += int(det.flagged[:START].any())
                delays[n][b].append(det.delay(START))
            a = exact_alarm(s, X0, sim.y)
            early[names[-1]] += int(a is not None and a < START)
            delays[names[-1]][b].append(None if a is None else a - START)
        print(f"bias {b:g}: done ({time.perf_counter() - t0:.0f} s)", flush=True)

    def rate(v):
        return sum(d is not None for d in v) / len(v)

    def median_delay(v):
        found = [d for d in v if d is not None]
        return statistics.median(found) if found else None

    cols = [b for b in BIASES if b >= 0.05]
    head = ("| method | smallest bias detected (≥ 90 %) | " + " | ".join(f"delay at {b:g}" for b in cols)
            + " | alarms before the fault |")
    lines = [head, "|" + "---|" * (3 + len(cols))]
    smallest = {}
    for n in names:
        det = [b for b in BIASES if rate(delays[n][b]) >= 0.9]
        smallest[n] = min(det) if det else None
        cells = []
        for b in cols:
            md, r = median_delay(delays[n][b]), rate(delays[n][b])
            cells.append("—" if md is None else f"{md:g}" + ("" if r >= 0.9 else f" ({100 * r:.0f} %)"))
        lines.append(f"| {n} | {'—' if smallest[n] is None else f'{smallest[n]:g}'} | " + " | ".join(cells)
                     + f" | {early[n]} |")
    cpu = platform.processor() or platform.machine()
    note = (f"\nMeasured {datetime.date.today().isoformat()} on {os.cpu_count()} cores ({cpu}, "
            f"{platform.python_implementation()} {platform.python_version()}): EX-LE13, bias on y0 from step "
            f"{START}, {args.seeds} seeds per bias, delay = median steps from the fault to the first alarm "
            f"(in brackets: the share of seeds detected within {WINDOW} steps when below 90 %); noise bound "
            f"of y0: 0.2. Command: `python bench/bench_faults.py --seeds {args.seeds} --write` "
            f"({time.perf_counter() - t0:.0f} s).\n")
    table = "\n".join(lines) + "\n" + note
    print(table)
    if args.write:
        doc = ROOT / "docs" / "fault_detection.md"
        doc.write_text(replace_region(doc.read_text(), "bench_faults", table))
        import matplotlib

        matplotlib.use("Agg")
        from matplotlib.figure import Figure

        fig = Figure(figsize=(10, 3.8))
        ax1, ax2 = fig.subplots(1, 2)
        for n in names:
            style = dict(lw=2.2, color="k", ls="--") if n == names[-1] else dict(lw=1.3)
            ax1.plot(BIASES, [rate(delays[n][b]) for b in BIASES], marker=".", label=n, **style)
            # the delay where at least half the seeds are detected (a median of a few is noise)
            md = [median_delay(delays[n][b]) if rate(delays[n][b]) >= 0.5 else None for b in BIASES]
            ax2.plot(BIASES, [np.nan if d is None else d for d in md], marker=".", label=n, **style)
        from matplotlib.ticker import NullFormatter

        for ax in (ax1, ax2):
            ax.set_xscale("log")
            ax.xaxis.set_minor_formatter(NullFormatter())
            ax.set_xlabel("sensor bias on y0 (noise bound 0.2)")
            ax.grid(alpha=0.3, which="both")
        ax1.set_ylabel(f"detected within {WINDOW} steps")
        ax2.set_ylabel("median delay (steps; ≥ 50 % detected)")
        ax1.legend(fontsize=7, loc="lower right")
        fig.suptitle(f"Guaranteed fault detection on EX-LE13: bias on y0 from step {START}, {args.seeds} seeds per "
                     "bias", fontsize=11)
        fig.subplots_adjust(left=0.07, right=0.98, bottom=0.15, top=0.88, wspace=0.25)
        fig.savefig(ROOT / "docs" / "fault_detection.png", dpi=110)
        print("written: docs/fault_detection.md, docs/fault_detection.png")


if __name__ == "__main__":
    main()
