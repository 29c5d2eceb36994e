"""Benchmark of the bundled LMI solver (issue 3) against CVXPY+Clarabel, CVXPY+SCS and
Clarabel called directly, on the same problems in the same run.

    SETBOUND_LIBRARY=build/libsetbound.so PYTHONPATH=python python3 bench/bench_lmi.py [--reps 50]

The 32-block problem (b) is also timed with threads=2 (SolverOptions::threads, OpenMP over the
blocks). Problems: (a) online-sized (4 blocks up to 7×7, 12 variables), (b) 32 blocks of 7×7 with 20
variables, (c) maxdet (−log det of a 4×4 affine G with 8 variables, 9 LMI blocks).
Reported: median wall time per solve from Python (ours through setbound.lmi.Problem, the
competitors end to end), our C++-measured solve time, Clarabel's own solve time,
iterations, ratios, and which issue-3 targets are met. Timings are never asserted in tests.
With --iterations: only the total iteration counts over seeded random families, ours against
Clarabel's (the measure behind the solver's step rule, docs/benchmarks.md "LMI solver").
"""
from __future__ import annotations

import argparse
import time

import numpy as np
import scipy.sparse as sp

from setbound import lmi


def sym(rng, n):
    A = rng.standard_normal((n, n))
    return (A + A.T) / 2


def random_lmi(seed, sizes, m):
    """Strictly feasible (x0 interior) and bounded (c from a strictly dual-feasible Z0)."""
    rng = np.random.default_rng(seed)
    x0 = rng.standard_normal(m)
    c = np.zeros(m)
    blocks = []
    for n in sizes:
        Fs = np.array([sym(rng, n) for _ in range(m)])
        F0 = -np.einsum("i,ijk->jk", x0, Fs) + np.eye(n) * (0.5 + rng.random())
        R = rng.standard_normal((n, n))
        c += np.einsum("ijk,jk->i", Fs, R @ R.T + 0.1 * np.eye(n))
        blocks.append((F0, Fs))
    return c, blocks


def maxdet_problem(seed, n=4, m=8):
    rng = np.random.default_rng(seed)
    c, blocks = random_lmi(seed + 1, [3] * 8, m)
    one = np.ones((1, 1))
    Gs = np.array([sym(rng, n) for _ in range(m)])
    G0 = np.eye(n) * 2.0
    return 0.1 * c, blocks, (G0, Gs)


def median_time(fn, reps):
    ts = []
    out = None
    for _ in range(reps):
        t = time.perf_counter()
        out = fn()
        ts.append(time.perf_counter() - t)
    return float(np.median(ts)), out


# ---- ours ---------------------------------------------------------------------------------
def bench_ours(c, blocks, logdet, reps, threads=1):
    p = lmi.Problem(len(c))
    p.set_objective(c)
    p.set_options(threads=threads)
    for F0, Fs in blocks:
        p.add_block(F0, Fs)
    if logdet is not None:
        p.set_logdet(*logdet)
    p.solve(duals=False)  # setup
    cpp = []

    def run():
        r = p.solve(duals=False)
        cpp.append(r.solve_time)
        return r

    t, r = median_time(run, reps)
    return {"time": t, "cpp": float(np.median(cpp)), "iters": r.iterations, "obj": r.objective, "status": r.status}


# ---- CVXPY --------------------------------------------------------------------------------
def cvxpy_problem(c, blocks, logdet):
    import cvxpy as cp

    m = len(c)
    x = cp.Variable(m)
    cons = []
    for F0, Fs in blocks:
        expr = F0 + sum(x[i] * Fs[i] for i in range(m))
        cons.append((expr + expr.T) / 2 >> 0)
    obj = c @ x
    if logdet is not None:
        G = logdet[0] + sum(x[i] * logdet[1][i] for i in range(m))
        obj = obj - cp.log_det((G + G.T) / 2)
    return cp.Problem(cp.Minimize(obj), cons)


def bench_cvxpy(c, blocks, logdet, solver, reps):
    import cvxpy as cp

    iters = []

    def run():
        prob = cvxpy_problem(c, blocks, logdet)  # end to end: modelling + canonicalisation + solve
        prob.solve(solver=getattr(cp, solver))
        iters.append(prob.solver_stats.num_iters)
        return prob

    t, prob = median_time(run, reps)
    return {"time": t, "iters": iters[-1], "obj": prob.value, "status": prob.status}


# ---- Clarabel directly --------------------------------------------------------------------
def svec(M):
    """Clarabel's PSD-triangle vectorisation: upper triangle by columns, off-diagonals ×√2."""
    n = M.shape[0]
    out = []
    for j in range(n):
        for i in range(j + 1):
            out.append(M[i, j] * (1.0 if i == j else np.sqrt(2.0)))
    return np.array(out)


def bench_clarabel(c, blocks, reps):
    import clarabel

    m = len(c)
    A = np.vstack([-np.column_stack([svec(Fi) for Fi in Fs]) for _, Fs in blocks])
    b = np.concatenate([svec(F0) for F0, _ in blocks])
    cones = [clarabel.PSDTriangleConeT(F0.shape[0]) for F0, _ in blocks]
    P = sp.csc_matrix((m, m))
    Acsc = sp.csc_matrix(A)
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    own = []

    def run():
        s = clarabel.DefaultSolver(P, c, Acsc, b, cones, settings)
        sol = s.solve()
        own.append(sol.solve_time)
        return sol

    t, sol = median_time(run, reps)
    return {"time": t, "own": float(np.median(own)), "iters": sol.iterations, "obj": sol.obj_val, "status": str(sol.status)}


def census_families():
    """Seeded random families for the iteration census (none of them is (a), (b) or (c)):
    'small' and 'large' as random_lmi; 'scaled' with variables scaled over three decades, F0's
    margin from 0.01 to 3 and c from a low-rank dual point (optimal points near the boundary)."""
    rng = np.random.default_rng(123)
    small = []
    for i in range(60):
        sizes = [int(rng.integers(2, 9)) for _ in range(int(rng.integers(1, 6)))]
        small.append(random_lmi(1000 + i, sizes, int(rng.integers(3, 14))))
    large = []
    for i in range(12):
        sizes = [int(rng.integers(4, 9)) for _ in range(int(rng.integers(16, 40)))]
        large.append(random_lmi(2000 + i, sizes, int(rng.integers(10, 25))))
    rng = np.random.default_rng(777)
    scaled = []
    for i in range(60):
        sizes = [int(rng.integers(3, 9)) for _ in range(int(rng.integers(1, 6)))]
        m = int(rng.integers(2, 14))
        x0 = rng.standard_normal(m)
        sc = 10 ** rng.uniform(-1.5, 1.5, m)
        c = np.zeros(m)
        blocks = []
        for n in sizes:
            Fs = np.array([sym(rng, n) * sc[j] for j in range(m)])
            F0 = -np.einsum("i,ijk->jk", x0, Fs) + np.eye(n) * 10 ** rng.uniform(-2, 0.5)
            R = rng.standard_normal((n, int(rng.integers(1, n + 1))))
            c += np.einsum("ijk,jk->i", Fs, R @ R.T + 1e-3 * np.eye(n))
            blocks.append((F0, Fs))
        scaled.append((c, blocks))
    return {"small (60: 1-5 blocks of 2-8, 3-13 vars)": small,
            "large (12: 16-39 blocks of 4-8, 10-24 vars)": large,
            "scaled (60: 1-5 blocks of 3-8, 2-13 vars)": scaled}


def iteration_census():
    """Total iterations of ours and of Clarabel (called directly, same data) per family."""
    print(f"  {'family':<46}{'ours':>8}{'clarabel':>10}  not optimal (ours / clarabel)")
    for name, family in census_families().items():
        ours = theirs = bad_ours = bad_theirs = 0
        for c, blocks in family:
            o = bench_ours(c, blocks, None, 1)
            r = bench_clarabel(c, blocks, 1)
            ours += o["iters"]
            theirs += r["iters"]
            bad_ours += o["status"] != "optimal"
            bad_theirs += r["status"] != "Solved"
        print(f"  {name:<46}{ours:>8}{theirs:>10}  {bad_ours} / {bad_theirs}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--reps", type=int, default=50)
    ap.add_argument("--cvxpy-reps", type=int, default=50)
    ap.add_argument("--iterations", action="store_true",
                    help="only the iteration census over seeded random families (ours and Clarabel)")
    args = ap.parse_args()
    if args.iterations:
        iteration_census()
        return

    problems = {
        "(a) online 4 blocks 7/7/5/3, 12 vars": (*random_lmi(1, [7, 7, 5, 3], 12), None),
        "(b) 32 blocks 7x7, 20 vars": (*random_lmi(2, [7] * 32, 20), None),
        "(c) maxdet G 4x4, 8 vars, 8 blocks 3x3": maxdet_problem(3),
    }
    rows = []
    results = {}
    for name, (c, blocks, logdet) in problems.items():
        res = {"ours": bench_ours(c, blocks, logdet, args.reps)}
        if len(blocks) >= 16:  # SolverOptions::threads pays off from a few dozen blocks
            res["ours, 2 threads"] = bench_ours(c, blocks, logdet, args.reps, threads=2)
        res["cvxpy+clarabel"] = bench_cvxpy(c, blocks, logdet, "CLARABEL", args.cvxpy_reps)
        res["cvxpy+scs"] = bench_cvxpy(c, blocks, logdet, "SCS", args.cvxpy_reps)
        if logdet is None:
            res["clarabel"] = bench_clarabel(c, blocks, args.reps)
        results[name] = res
        o = res["ours"]
        print(f"\n{name}")
        print(f"  {'solver':<18}{'median/solve':>14}{'iters':>7}{'objective':>20}  status     ratio vs ours")
        print(f"  {'ours (Python)':<18}{o['time']*1e3:>11.3f} ms{o['iters']:>7}{o['obj']:>20.10g}  {o['status']:<10}")
        print(f"  {'ours (C++ time)':<18}{o['cpp']*1e3:>11.3f} ms")
        if "ours, 2 threads" in res:
            o2 = res["ours, 2 threads"]
            print(f"  {'ours, 2 threads':<18}{o2['time']*1e3:>11.3f} ms{o2['iters']:>7}{o2['obj']:>20.10g}  {o2['status']:<10}")
            print(f"  {'  (C++ time)':<18}{o2['cpp']*1e3:>11.3f} ms")
        for k in ("clarabel", "cvxpy+clarabel", "cvxpy+scs"):
            if k not in res:
                continue
            r = res[k]
            print(f"  {k:<18}{r['time']*1e3:>11.3f} ms{r['iters']:>7}{r['obj']:>20.10g}  {r['status']:<10} {r['time']/o['time']:8.1f}x")
            if k == "clarabel":
                print(f"  {'clarabel (own)':<18}{r['own']*1e3:>11.3f} ms{'':>27}             {r['own']/o['time']:8.1f}x")
    a = results["(a) online 4 blocks 7/7/5/3, 12 vars"]
    b = results["(b) 32 blocks 7x7, 20 vars"]
    print("\nTargets (issue 3):")
    checks = [
        ("(a) <= 0.2 ms median from Python", a["ours"]["time"] <= 2e-4, f"{a['ours']['time']*1e3:.3f} ms"),
        ("(b) <= 2 ms median from Python, serial", b["ours"]["time"] <= 2e-3, f"{b['ours']['time']*1e3:.3f} ms"),
        ("(b) <= 2 ms median from Python, threads=2 (both cores)", b["ours, 2 threads"]["time"] <= 2e-3,
         f"{b['ours, 2 threads']['time']*1e3:.3f} ms"),
        (">= 5x faster than Clarabel's own solve time on (a)", a["clarabel"]["own"] >= 5 * a["ours"]["time"],
         f"{a['clarabel']['own']/a['ours']['time']:.1f}x"),
        (">= 100x faster than CVXPY+Clarabel end to end on (a)", a["cvxpy+clarabel"]["time"] >= 100 * a["ours"]["time"],
         f"{a['cvxpy+clarabel']['time']/a['ours']['time']:.1f}x"),
    ]
    for text, ok, val in checks:
        print(f"  [{'met' if ok else 'NOT met'}] {text}: {val}")


if __name__ == "__main__":
    main()
