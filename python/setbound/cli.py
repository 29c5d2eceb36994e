"""The ``setbound`` command line.

``setbound check FILE``          validate a job file without running it
``setbound run FILE [--out DIR]`` run it: a summary table, and with ``--out`` the results
                                  (NPZ and CSV of centre/lower/upper per estimator, JSON summary)
"""
from __future__ import annotations

import argparse
import csv
import json
import sys
from pathlib import Path

import numpy as np

from . import config
from .errors import SetboundError


def _summary(job, results):
    rows = []
    for r in results:
        t = r.trajectory
        w = t.width
        vol = t.volume if t.sets else np.full(len(t), np.nan)
        rows.append({
            "name": r.name,
            "method": r.method,
            "guaranteed": bool(t.guaranteed),
            "contains_truth": r.contained,
            "mean_width": float(np.mean(w)),
            "final_width": [float(v) for v in w[-1]],
            "final_volume": float(vol[-1]) if len(vol) else float("nan"),
            "design_time_s": r.design_time,
            "time_per_step_s": r.step_time,
        })
    return rows


def _table(rows) -> str:
    head = f"{'estimator':<22}{'truth inside':>13}{'mean width':>12}{'final width':>12}{'final volume':>14}" \
           f"{'design s':>10}{'ms/step':>9}"
    lines = [head, "-" * len(head)]
    for r in rows:
        inside = "n/a" if r["contains_truth"] is None else ("yes" if r["contains_truth"] else "NO")
        if not r["guaranteed"]:
            inside += "*"
        lines.append(f"{r['name']:<22}{inside:>13}{r['mean_width']:>12.4g}{max(r['final_width']):>12.4g}"
                     f"{r['final_volume']:>14.4g}{r['design_time_s']:>10.3f}{1e3 * r['time_per_step_s']:>9.3f}")
    if any(not r["guaranteed"] for r in rows):
        lines.append("* not a guaranteed method (Kalman: mean ± 3σ box)")
    return "\n".join(lines)


def _write(out: Path, job, results, rows):
    out.mkdir(parents=True, exist_ok=True)
    for r in results:
        t = r.trajectory
        arrays = {"center": t.center, "lower": t.lower, "upper": t.upper, "radius": t.radius, "volume":
                  t.volume if t.sets else np.full(len(t), np.nan)}
        if job.x_true is not None:
            arrays["x_true"] = job.x_true
        np.savez(out / f"{r.name}.npz", **arrays)
        with open(out / f"{r.name}.csv", "w", newline="") as fh:
            wr = csv.writer(fh)
            n = t.center.shape[1]
            wr.writerow(["k"] + [f"center{i}" for i in range(n)] + [f"lower{i}" for i in range(n)]
                        + [f"upper{i}" for i in range(n)])
            for k in range(len(t)):
                wr.writerow([k] + [repr(float(v)) for v in np.concatenate([t.center[k], t.lower[k], t.upper[k]])])
    with open(out / "summary.json", "w") as fh:
        json.dump({"title": job.title, "source": job.source, "steps": int(len(job.y)), "estimators": rows}, fh,
                  indent=2)


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="setbound", description="guaranteed (set-membership) state estimation")
    sub = p.add_subparsers(dest="command", required=True)
    c = sub.add_parser("check", help="validate a job file without running it")
    c.add_argument("file")
    r = sub.add_parser("run", help="run a job file")
    r.add_argument("file")
    r.add_argument("--out", help="directory for the results (NPZ, CSV, JSON)")
    a = p.parse_args(argv)
    try:
        job = config.load(a.file)
        if a.command == "check":
            print(f"{a.file}: ok — {job.title}: {type(job.system).__name__} (n_x = {job.system.nx}), "
                  f"{len(job.y)} steps, estimators: {', '.join(s.name for s in job.estimators)}")
            return 0
        results = config.run(job)
    except (SetboundError, ValueError) as exc:
        print(f"setbound: error: {exc}", file=sys.stderr)
        return 2
    rows = _summary(job, results)
    print(f"{job.title} ({len(job.y)} steps)")
    print(_table(rows))
    if a.out:
        _write(Path(a.out), job, results, rows)
        print(f"results written to {a.out}")
    failed = [r["name"] for r in rows if r["contains_truth"] is False]
    if failed:
        print(f"setbound: the true state left the set of: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
