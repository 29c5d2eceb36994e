"""CORA's linear observer catalogue on CORA's benchmarks: accuracy (IRadius), speed, guarantee.

Writes the region ``bench_cora`` of docs/cora_comparison.md (with ``--update-doc``) and the figure
docs/img/cora_iradius.png. For every model (alamo 2-D, vehicle2, pedestrian4, vehicle6, tank30) and
every name of ``setbound.cora.algorithms()`` (whatever is registered when the script runs), run with
``setbound.cora.observe(model, alg)`` in setbound's convention (the guaranteed algorithms), it reports

* IRadius per dimension — CORA's ``performanceObserver`` definition: the root mean square over
  time of the interval radius of every returned set — its mean over the dimensions, and the mean's
  ratio to the best guaranteed method and to the exact consistent-set hull (where tractable);
* the time per step from Python (``CoraResult.seconds_per_step``, median of ``--reps`` runs) and in
  C++ (``bench/bench_cora_cpp``, median over repeated horizons), the design time, and how many
  steps contain the printed true state (3 decimals: tolerance 5e-4);
* the count of CORA's saved final hulls (``golden_final_interval_hull`` of the data files) that
  ``convention="cora"`` reproduces at CORA's rule (withinTol: |a − b| <= 1e-6 absolute or relative),
  and separately the values the specification marks [V] / [V-gain] (its §4.3).

A method that cannot run on a model (no design, infeasible design, refused model) gets a row with
the error message; a method whose cost is out of range for a model is skipped with the reason.

    python bench/bench_cora.py [--models alamo,vehicle2] [--reps 3] [--quick] [--cpp PATH | --cpp-json FILE
                               | --no-cpp] [--update-doc [FILE]] [--json FILE] [--no-figure]
"""
from __future__ import annotations

import argparse
import dataclasses
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import setbound.cora as cora
from setbound.benchmarks import load_cora
from setbound.zonotopic import exact_hull

sys.path.insert(0, str(Path(__file__).resolve().parent))
from doc_region import environment, load_text, marked, replace_region  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_DATA = Path(os.environ.get("SETBOUND_CORA_DATA", ROOT.parent / "shared" / "benchmarks" /
                                   "cora_linearSysDT_observe"))
MODELS = {  # short name: data file (stem)
    "alamo": "alamo2005_2d_cora_unittest",
    "vehicle2": "vehicle2_cora_unittest",
    "pedestrian4": "pedestrian4",
    "vehicle6": "vehicle6",
    "tank30": "tank30",
}
LABELS = {"alamo": "alamo 2-D", "vehicle2": "vehicle2", "pedestrian4": "pedestrian4", "vehicle6": "vehicle6",
          "tank30": "tank30"}
TRUTH_TOL = 5e-4  # the true trajectories are printed to 3 decimals
CORA_TOL = 1e-6
# The exact consistent-set hull costs 2 n_x LPs per step whose size grows with the step (every
# disturbance so far is a variable): computed when n_x · N is at most this (alamo 40, vehicle2 200,
# pedestrian4 960, vehicle6 2100, tank30 7050).
EXACT_MAX = 1000

# Methods whose cost is out of range for a model, with the reason (spec cora_observers.md, item 6
# of each method). Everything else registered runs.
def skip_reason(alg: str, n: int) -> str | None:
    if alg == "VolMin-A" and n > 2:
        return ("exact-volume LP over all (n−1)-subsets of the generators: exponential in n_x "
                "(spec §2.1; CORA's tests skip it too)")
    return None


# Spec §4.3: the saved values the re-implementation reproduced, by data file and golden key.
# "V": reproduced from the data alone; "V-gain": reproduced with CORA's saved SDPT3 gain.
_EIGHT = ["FRad-A", "FRad-B", "FRad-C", "VolMin-B", "ESO-A", "ESO-B", "CZN-A", "CZN-B"]
SPEC_V = {
    "alamo2005_2d_cora_unittest": {k: "V" for k in _EIGHT},
    "vehicle2_cora_unittest": {**{k: "V" for k in _EIGHT},
                               **{k: "V-gain" for k in ("PRad-A", "PRad-B", "PRad-C", "PRad-D", "PRad-E", "Nom-G",
                                                        "Hinf-G")}},
    "tank30": {**{f"{k} [tFinal==10]": "V" for k in ("FRad-A", "FRad-B", "FRad-C", "ESO-A", "ESO-B")},
               "ESO-A [else]": "V", "ESO-B [else]": "V"},
    "pedestrian4": {"FRad-A": "V", "ESO-A": "V", "ESO-B": "V"},
}


def within_tol(a, b, tol=CORA_TOL) -> bool:
    """CORA's withinTol (global/functions/matlab/validate/check/withinTol.m), elementwise, all."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    d = np.abs(a - b)
    with np.errstate(divide="ignore", invalid="ignore"):
        rel = d / np.minimum(np.abs(a), np.abs(b))
    return bool(np.all((d <= tol) | (rel <= tol)))


def short_error(e: BaseException) -> str:
    msg = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
    return (msg[:220] + "…") if len(msg) > 220 else msg


def saved_gains(data: Path) -> dict:
    path = data / "vehicle2_cora_saved_gains.json"
    if not path.is_file():
        return {}
    return {k: np.asarray(v["L"], float) for k, v in json.loads(path.read_text())["gains"].items()}


def truth_tolerance(model) -> np.ndarray:
    tol = np.full(len(model.y), TRUTH_TOL)
    if model.name == "pedestrian4":
        # The data's README: the printed truth leaves the noise bound of output 2 at step 217.
        tol[217:] = 3e-3
    return tol


def truth_inside(model, lower, upper) -> tuple[int, int] | None:
    if model.truth is None:
        return None
    tol = truth_tolerance(model)[:, None]
    inside = np.all((lower - tol <= model.truth) & (model.truth <= upper + tol), axis=1)
    return int(inside.sum()), len(inside)


def iradius(lower, upper) -> np.ndarray:
    """CORA's IRadius (performanceObserver.m, spec §4.1): RMS over time of the interval radius."""
    r = 0.5 * (np.asarray(upper) - np.asarray(lower))
    return np.sqrt(np.mean(r * r, axis=0))


def shortened(model, steps: int | None):
    """The model with only its first ``steps`` measurements (CORA's tFinal shortened)."""
    if steps is None or steps >= len(model.y):
        return model
    return dataclasses.replace(model, y=model.y[:steps], u=model.u[:steps],
                               truth=None if model.truth is None else model.truth[:steps])


def with_timeout(fn, timeout: float | None, what: str) -> dict:
    """``fn()`` (a dict) in a forked child that is stopped after ``timeout`` seconds: a design of
    minutes (tank30's 21 × 7 PRad-A SDPs) or an LP hull per step must not hold the whole run, and a C
    call cannot be interrupted from Python. None: in this process."""
    if not timeout:
        return fn()
    import multiprocessing as mp

    ctx = mp.get_context("fork")
    recv, send = ctx.Pipe(duplex=False)

    def child():
        try:
            send.send(fn())
        except BaseException as e:  # noqa: BLE001
            send.send({"error": short_error(e)})

    p = ctx.Process(target=child, daemon=True)
    p.start()
    send.close()
    out = recv.recv() if recv.poll(timeout) else None
    p.join(1 if out is not None else 0)
    if p.is_alive():
        p.terminate()
        p.join()
    if out is None:
        return {"skipped": f"{what} not finished within {timeout:g} s on this machine"}
    return out


# ---- one method on one model -----------------------------------------------------------------

def run_method(model, alg: str, reps: int, exact: dict | None = None, rep_budget: float = 15.0) -> dict:
    row = {"alg": alg, "n": model.system.nx}
    reason = skip_reason(alg, model.system.nx)
    if reason:
        return {**row, "skipped": reason}
    note = ""
    runs = []
    t_start = time.perf_counter()
    for _ in range(reps):
        if runs and time.perf_counter() - t_start > rep_budget:
            note = (note + "; " if note else "") + f"{len(runs)} Python run(s): each above {rep_budget:g} s"
            break
        try:
            r = cora.observe(model, alg)
        except Exception as e:  # noqa: BLE001 — every setbound error is a row, never a crash
            return {**row, "error": short_error(e)}
        runs.append(r)
    r = runs[-1]
    lower, upper = np.asarray(r.lower), np.asarray(r.upper)
    ir = iradius(lower, upper)
    guaranteed = bool(getattr(r, "guaranteed", True)) and not np.array_equal(lower, upper)
    exact_inside = None
    if exact and "lower" in exact:
        # A guaranteed set contains every state consistent with the data: the exact hull, every step.
        el, eu = exact["lower"], exact["upper"]
        slack = 1e-9 * (1 + np.maximum(np.abs(el), np.abs(eu)))
        inside = np.all((lower <= el + slack) & (eu - slack <= upper), axis=1)
        exact_inside = (int(inside.sum()), len(inside))
    return {**row, "note": note, "exact_inside": exact_inside, "iradius": ir.tolist(), "mean_iradius": float(ir.mean()),
            "py_us": 1e6 * statistics.median(x.seconds_per_step for x in runs),
            "design_ms": 1e3 * statistics.median(x.design_seconds for x in runs),
            "truth": truth_inside(model, lower, upper), "guaranteed": guaranteed,
            "final_lower": lower[-1].tolist(), "final_upper": upper[-1].tolist()}


def exact_reference(model, exact_max: int) -> dict | None:
    n, N = model.system.nx, len(model.y)
    if n * N > exact_max:
        return {"skipped": f"n_x·N = {n * N} > {exact_max}: 2 n_x LPs per step with every past disturbance "
                           "as a variable"}
    t0 = time.perf_counter()
    try:
        h = exact_hull(model.system, model.y, model.u, x0=model.x0)
    except Exception as e:  # noqa: BLE001
        return {"error": short_error(e)}
    ir = iradius(h.lower, h.upper)
    return {"iradius": ir.tolist(), "mean_iradius": float(ir.mean()), "seconds": time.perf_counter() - t0,
            "lower": np.asarray(h.lower), "upper": np.asarray(h.upper),
            "truth": truth_inside(model, np.asarray(h.lower), np.asarray(h.upper))}


# ---- CORA's saved values -----------------------------------------------------------------------

def golden_check(model, gains: dict, timeout: float | None = None) -> list[dict]:
    """Every saved final hull of the model, run with convention="cora" (and, for the names whose
    CORA gain is an SDP end point, with CORA's saved gain where there is one)."""
    out = []
    spec = SPEC_V.get(model.name, {})
    for key, (lo, hi) in model.golden.items():
        alg = key.split(" ")[0]
        steps = 20 if "[tFinal==10]" in key else None
        entry = {"key": key, "spec": spec.get(key, "")}
        if alg not in cora.algorithms():
            entry["own design"] = {"ok": False, "message": f"{alg} is not registered in setbound.cora"}
            out.append(entry)
            continue
        tries = [("own design", None)]
        if model.name.startswith("vehicle2") and alg in gains:
            tries.append(("CORA's saved gain", gains[alg]))
        for how, gain in tries:
            def check(alg=alg, gain=gain, steps=steps, lo=lo, hi=hi):
                try:
                    r = cora.observe(model, alg, convention="cora", gain=gain, steps=steps)
                except Exception as e:  # noqa: BLE001
                    return {"ok": False, "message": short_error(e)}
                err = max(np.abs(r.lower[-1] - lo).max(), np.abs(r.upper[-1] - hi).max())
                return {"ok": within_tol(r.lower[-1], lo) and within_tol(r.upper[-1], hi), "error": float(err)}
            res = with_timeout(check, timeout, "the run")
            entry[how] = res if "ok" in res else {"ok": False, "message": res.get("skipped") or res.get("error")}
        out.append(entry)
    return out


# ---- C++ -----------------------------------------------------------------------------------------

def cpp_figures(args, plan: dict[str, list[str]]) -> tuple[dict, dict | None]:
    """The C++ rows: ``bench_cora_cpp`` once per model, for the methods of ``plan[model file]`` (the
    ones the Python run did not skip: a design Python could not finish in time would not finish in
    C++ either). ``--cpp-json``: an earlier run's output instead."""
    if args.no_cpp:
        return {}, None
    if args.cpp_json:
        d = json.loads(Path(args.cpp_json).read_text())
        return {(r["model"], r["alg"]): r for r in d["rows"]}, d
    exe = Path(args.cpp) if args.cpp else ROOT / "build" / "bench" / "bench_cora_cpp"
    if not exe.is_file():
        print(f"bench_cora: no C++ program at {exe} (build it with -DSETBOUND_BUILD_BENCH=ON); "
              "C++ columns left empty", file=sys.stderr)
        return {}, None
    meta, runs = None, {}
    with tempfile.TemporaryDirectory() as tmp:
        # The program runs --cpp-runs times over all models: on a shared VM the per-run medians
        # jump between levels (host frequency, neighbours), the median over runs is stable.
        for _ in range(args.cpp_runs):
            for model, algs in plan.items():
                if not algs:
                    continue
                out = Path(tmp) / f"{model}.json"
                cmd = [str(exe), str(args.data), "--models", model, "--methods", ",".join(algs), "--json", str(out),
                       "--min-steps", str(args.cpp_min_steps), "--max-seconds", str(args.cpp_max_seconds)]
                print("running", " ".join(cmd), file=sys.stderr)
                subprocess.run(cmd, check=True)
                d = json.loads(out.read_text())
                if meta is None:
                    meta = {k: v for k, v in d.items() if k != "rows"}
                meta["loadavg_end"] = d["loadavg_end"]
                for r in d["rows"]:
                    runs.setdefault((r["model"], r["alg"]), []).append(r)
    if meta is None:
        return {}, None
    meta["runs"] = args.cpp_runs
    meta["rows"] = rows = [median_row(rs) for rs in runs.values()]
    if args.save_cpp_json:
        Path(args.save_cpp_json).write_text(json.dumps(meta, indent=1))
    return {(r["model"], r["alg"]): r for r in rows}, meta


def median_row(rs: list[dict]) -> dict:
    """One C++ row from the same (model, method) of several runs: the median of the per-run
    medians, 90th percentiles and design times (the runs' medians kept in ``runs_us``)."""
    row = dict(rs[0])
    ok = [r for r in rs if r.get("error") is None and r.get("median_us") is not None]
    if ok:
        for key in ("median_us", "p90_us", "design_ms"):
            row[key] = float(np.median([r[key] for r in ok]))
        row["runs_us"] = [r["median_us"] for r in ok]
    return row


# ---- report --------------------------------------------------------------------------------------

def fmt(v, f="{:.4g}"):
    return "—" if v is None or (isinstance(v, float) and not np.isfinite(v)) else f.format(v)


def md_cell(text: str) -> str:
    return text.replace("|", "\\|").replace("\n", " ")


def model_section(short, model, rows, exact, cpp, lines):
    n, N = model.system.nx, len(model.y)
    lines += [f"### {LABELS[short]} (`{model.name}`: n_x = {n}, n_y = {model.system.ny}, N = {N}, "
              f"zonotope order {model.zonotope_order:g}, {model.reduction_method})", ""]
    ran = [r for r in rows if "mean_iradius" in r]
    best = min((r["mean_iradius"] for r in ran if r["guaranteed"]), default=None)
    ex = exact.get("mean_iradius") if exact else None
    per_dim = n <= 6
    head = ["method"] + ([f"IRadius x{i + 1}" for i in range(n)] if per_dim else []) + [
        "mean IRadius", "ratio to best", "ratio to exact", "C++ µs/step", "Python µs/step", "design ms",
        "truth inside", "exact hull inside", "note"]
    lines += ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    if exact and "mean_iradius" in exact:
        t = exact["truth"]
        lines.append("| exact hull (LPs) | " + ("".join(f"{v:.4g} | " for v in exact["iradius"]) if per_dim else "")
                     + f"{ex:.4g} | {fmt(ex / best if best else None, '{:.3f}')} | 1.000 | — | "
                     f"{exact['seconds'] / N * 1e6:.0f} | — | {f'{t[0]}/{t[1]}' if t else '—'} | — | reference |")
    for r in rows:
        c = cpp.get((model.name, r["alg"]), {})
        if "mean_iradius" not in r:
            why = r.get("skipped") or r.get("error")
            tag = "skipped: " if "skipped" in r else "error: "
            lines.append(f"| {r['alg']} | " + ("— | " * n if per_dim else "") + "— | — | — | — | — | — | — | — | "
                         + md_cell(tag + why) + " |")
            continue
        t, e = r["truth"], r["exact_inside"]
        cpp_us = c.get("median_us")
        note = r.get("note", "")
        if c.get("error") and cpp_us is None:
            note = (note + "; " if note else "") + "C++: " + c["error"]
        elif c and c.get("steps_timed", 0) < c.get("horizon", 0):
            note = (note + "; " if note else "") + f"C++: first {c['steps_timed']} steps timed"
        if not r["guaranteed"]:
            note = (note + "; " if note else "") + "not a guaranteed set"
        lines.append(
            f"| {r['alg']} | " + ("".join(f"{v:.4g} | " for v in r["iradius"]) if per_dim else "")
            + f"{r['mean_iradius']:.4g} | {fmt(r['mean_iradius'] / best if best else None, '{:.3f}')} | "
            f"{fmt(r['mean_iradius'] / ex if ex else None, '{:.3f}')} | {fmt(cpp_us, '{:.2f}')} | "
            f"{r['py_us']:.1f} | {r['design_ms']:.1f} | {f'{t[0]}/{t[1]}' if t else '—'} | "
            f"{f'{e[0]}/{e[1]}' if e else '—'} | {md_cell(note)} |")
    if exact and "mean_iradius" not in exact:
        lines += ["", f"Exact hull: {exact.get('skipped') or 'error: ' + exact.get('error', '')}."]
    if not per_dim and ran:
        lines += ["", "IRadius per dimension (x1 … x{}):".format(n), ""]
        if exact and "iradius" in exact:
            lines.append(f"* exact hull: " + ", ".join(f"{v:.3g}" for v in exact["iradius"]))
        for r in ran:
            lines.append(f"* {r['alg']}: " + ", ".join(f"{v:.3g}" for v in r["iradius"]))
    lines.append("")


def golden_section(golden: dict, lines):
    total = ok_any = 0
    spec_n = {"V": 0, "V-gain": 0}
    spec_ok = {"V": 0, "V-gain": 0}
    body = []
    for name, entries in golden.items():
        for e in entries:
            total += 1
            own, saved = e.get("own design", {}), e.get("CORA's saved gain")
            ok = own.get("ok") or (saved or {}).get("ok")
            ok_any += bool(ok)
            if e["spec"]:
                spec_n[e["spec"]] += 1
                want = saved if e["spec"] == "V-gain" and saved is not None else own
                spec_ok[e["spec"]] += bool(want.get("ok"))

            def cell(d):
                if d is None:
                    return "—"
                if "message" in d:
                    return md_cell("error: " + d["message"])
                return ("yes" if d["ok"] else "no") + f" ({d['error']:.1e})"
            body.append(f"| {name} | {e['key']} | {e['spec'] or '—'} | {cell(own)} | {cell(saved)} |")
    lines += [f"**{ok_any} of {total}** saved final hulls reproduced at CORA's rule (withinTol 1e-6) with "
              f"`convention=\"cora\"`; of the values the specification marks reproducible (§4.3): "
              f"**[V] {spec_ok['V']} of {spec_n['V']}**, **[V-gain] {spec_ok['V-gain']} of {spec_n['V-gain']}** "
              "(with CORA's saved vehicle2 gain). In brackets the largest absolute difference of the final "
              "hull.", "",
              "| data | saved value | spec | reproduced (setbound's design) | with CORA's saved gain |",
              "|---|---|---|---|---|", *body, ""]
    return {"total": total, "reproduced": ok_any, "spec": spec_n, "spec_reproduced": spec_ok}


def targets_section(results, cpp, lines):
    """Issue 22's targets: every closed-form method ≤ 1 ms per step on tank30 and ≤ 20 µs on
    vehicle6 in C++ (closed form: no LP or SDP in the online step)."""
    closed_form = [a for a in cora.algorithms() if a not in ("VolMin-A", "CZN-A", "CZN-B")]
    for model, limit in (("tank30", 1000.0), ("vehicle6", 20.0)):
        if model not in results:
            continue
        met, missed, none = [], [], []
        for alg in closed_form:
            c = cpp.get((model, alg))
            if not c or c.get("median_us") is None:
                none.append(alg)
            elif c["median_us"] <= limit:
                met.append(f"{alg} {c['median_us']:.1f}")
            else:
                missed.append(f"{alg} {c['median_us']:.1f}")
        unit = "1 ms" if limit >= 1000 else f"{limit:g} µs"
        lines.append(f"* **{model}, ≤ {unit} per step in C++**: "
                     + ("met by every closed-form method timed" if not missed else "**not met** by " + ", ".join(missed))
                     + (f" (µs: {', '.join(met)})" if met else "")
                     + (f"; no C++ figure: {', '.join(none)}" if none else "") + ".")
    lines.append("")


def figure(results, cpp, path: Path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from matplotlib.ticker import NullFormatter

    shorts = list(results)
    cols = min(3, len(shorts))
    rows_ = (len(shorts) + cols) // cols  # one more panel for the legend
    fig, grid = plt.subplots(rows_, cols, figsize=(4.6 * cols, 3.6 * rows_), squeeze=False)
    panels = list(grid.flat)
    algs = sorted({r["alg"] for s in shorts for r in results[s]["rows"]})
    cmap = plt.get_cmap("tab20")
    colour = {a: cmap(i % 20) for i, a in enumerate(algs)}
    markers = "os^vD<>ph*Xd8P"
    for ax, s in zip(panels, shorts):
        res = results[s]
        for i, r in enumerate(res["rows"]):
            if "mean_iradius" not in r:
                continue
            c = cpp.get((res["file"], r["alg"]), {})
            x, filled = c.get("median_us"), True
            if x is None:  # no C++ figure: the Python time, open marker
                x, filled = r["py_us"], False
            m = markers[algs.index(r["alg"]) % len(markers)]
            ax.scatter([x], [r["mean_iradius"]], marker=m, s=45, label=r["alg"],
                       facecolors=colour[r["alg"]] if filled else "none", edgecolors=colour[r["alg"]])
        ex = res["exact"]
        if ex and "mean_iradius" in ex:
            ax.axhline(ex["mean_iradius"], color="k", ls="--", lw=0.8, label="exact hull")
        ax.set(xscale="log", yscale="log", title=LABELS[s], xlabel="time per step [µs] (C++; open: Python)",
               ylabel="mean IRadius")
        ax.xaxis.set_minor_formatter(NullFormatter())
        ax.yaxis.set_minor_formatter(NullFormatter())
        ax.grid(True, which="both", lw=0.3)
    handles = {}
    for ax in panels[:len(shorts)]:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(lab, h)
    for ax in panels[len(shorts):]:
        ax.axis("off")
    panels[len(shorts)].legend(list(handles.values()), list(handles), loc="center", ncol=2, fontsize=9,
                               frameon=False)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=90)
    plt.close(fig)


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", type=Path, default=DEFAULT_DATA)
    ap.add_argument("--models", default=",".join(MODELS), help=f"comma-separated, of {', '.join(MODELS)}")
    ap.add_argument("--reps", type=int, default=3, help="Python runs per method (median)")
    ap.add_argument("--quick", action="store_true",
                    help="one Python run, short C++ timing, no golden check on models not listed")
    ap.add_argument("--steps", type=int, help="use only the first STEPS measurements of every model "
                    "(the saved values are still checked on their own horizons)")
    ap.add_argument("--exact-max", type=int, default=EXACT_MAX, help="largest n_x·N for the exact hull")
    ap.add_argument("--cpp", help="the bench_cora_cpp program (default build/bench/bench_cora_cpp)")
    ap.add_argument("--cpp-json", help="use the JSON output of an earlier bench_cora_cpp run")
    ap.add_argument("--no-cpp", action="store_true", help="no C++ timing")
    ap.add_argument("--save-cpp-json", help="keep the C++ program's output (for --cpp-json)")
    ap.add_argument("--method-timeout", type=float, default=150.0,
                    help="seconds for one method on one model (design and runs; 0: no limit)")
    ap.add_argument("--rep-budget", type=float, default=15.0,
                    help="no further Python run of a method once its runs took this many seconds")
    ap.add_argument("--cpp-min-steps", type=int, default=400)
    ap.add_argument("--cpp-max-seconds", type=float, default=20.0)
    ap.add_argument("--cpp-runs", type=int, default=5,
                    help="runs of bench_cora_cpp; each row is the median over the runs (default 5)")
    ap.add_argument("--no-golden", action="store_true", help="skip the count of CORA's saved values")
    ap.add_argument("--update-doc", nargs="?", const=str(ROOT / "docs" / "cora_comparison.md"), default=None,
                    help="write the region bench_cora of this file (default docs/cora_comparison.md)")
    ap.add_argument("--figure", type=Path, default=ROOT / "docs" / "img" / "cora_iradius.png")
    ap.add_argument("--no-figure", action="store_true")
    ap.add_argument("--json", type=Path, help="also write the results as JSON")
    args = ap.parse_args(argv)
    if args.cpp_runs < 1:
        ap.error("--cpp-runs: must be >= 1")
    if args.quick:
        args.reps = 1
        args.cpp_min_steps, args.cpp_max_seconds, args.cpp_runs = 50, 2.0, 1
    shorts = [s.strip() for s in args.models.split(",") if s.strip()]
    unknown = [s for s in shorts if s not in MODELS]
    if unknown:
        ap.error(f"--models: unknown {', '.join(unknown)}; known: {', '.join(MODELS)}")

    started = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    load0 = os.getloadavg()
    gains = saved_gains(args.data)
    algs = list(cora.algorithms())
    results, golden = {}, {}
    for s in shorts:
        full = load_cora(args.data / f"{MODELS[s]}.json")
        model = shortened(full, args.steps)
        print(f"{s}: {len(algs)} methods", file=sys.stderr)
        exact = with_timeout(lambda: exact_reference(model, args.exact_max), args.method_timeout * 3 or None,
                             "exact hull")
        rows = []
        for alg in algs:
            t0 = time.perf_counter()
            row = with_timeout(lambda: run_method(model, alg, args.reps, exact, args.rep_budget),
                               args.method_timeout, "design and run")
            rows.append({"alg": alg, "n": model.system.nx, **row})
            r = rows[-1]
            print(f"  {alg:10s} {r.get('mean_iradius', float('nan')):10.4g} {time.perf_counter() - t0:7.1f} s "
                  f"{r.get('error') or r.get('skipped') or ''}", file=sys.stderr)
        if exact:
            exact.pop("lower", None), exact.pop("upper", None)
        results[s] = {"file": model.name, "rows": rows, "exact": exact, "n": model.system.nx, "N": len(model.y)}
        if not args.no_golden and full.golden:
            golden[model.name] = golden_check(full, gains, args.method_timeout)
    cpp, cpp_meta = cpp_figures(args, {res["file"]: [r["alg"] for r in res["rows"] if "skipped" not in r]
                                       for res in results.values()})
    load1 = os.getloadavg()

    lines = [f"Generated by `bench/bench_cora.py` ({' '.join(['--models', args.models] + (['--quick'] if args.quick else []) + (['--steps', str(args.steps)] if args.steps else []) + ['--reps', str(args.reps)])}) "
             f"on {started}, {environment()}; load average {load_text(load0)} at the "
             f"start, {load_text(load1)} at the end. Registered names: {', '.join(algs)}.",
             ""]
    if cpp_meta:
        lines += [f"C++: `bench/bench_cora_cpp` ({cpp_meta['date']}, {cpp_meta['hardware_threads']} hardware "
                  f"threads, vectorised for {cpp_meta['simd']}, load average {cpp_meta['loadavg_start']} at the "
                  f"start and {cpp_meta['loadavg_end']} at the end): median of at least {cpp_meta['min_steps']} "
                  f"steps each timed alone (whole horizons repeated, at most {cpp_meta['max_seconds']} s per "
                  "method)" + (f", then the median over {cpp_meta['runs']} runs of the program"
                               if cpp_meta.get("runs", 1) > 1 else "") + "; design outside the clock.", ""]
    else:
        lines += ["C++: not run (no `bench_cora_cpp`); the C++ columns are empty.", ""]
    lines += ["Python: `setbound.cora.observe(model, alg)` (setbound's convention), median of "
              f"{args.reps} run(s) of the wall time of the run divided by the steps (one C call per step "
              "and the Python loop), design time (the offline gain or LMI design) separately. IRadius: "
              "RMS over time of the radius of the interval hull of every returned set (CORA's "
              "`performanceObserver`), per dimension and its mean; ratios are of the mean, to the best "
              "guaranteed method of the model and to the exact consistent-set hull. Truth inside: steps "
              f"whose printed true state (3 decimals) lies in the set within {TRUTH_TOL:g} "
              "(pedestrian4: 3e-3 from step 217 on, where the printed state leaves the noise bound; data README).",
              ""]
    if {"tank30", "vehicle6"} & set(results):
        lines += ["## Targets", ""]
        targets_section(results, cpp, lines)
    lines += ["## Accuracy and speed per model", ""]
    for s in shorts:
        model = shortened(load_cora(args.data / f"{MODELS[s]}.json"), args.steps)
        model_section(s, model, results[s]["rows"], results[s]["exact"], cpp, lines)
    if not args.no_figure:
        try:
            figure(results, cpp, args.figure)
            rel = os.path.relpath(args.figure, Path(args.update_doc).parent if args.update_doc else ROOT / "docs")
            lines += [f"![mean IRadius against time per step]({rel})", ""]
        except ImportError:
            pass
    golden_summary = None
    if golden:
        lines += ["## CORA's saved values", ""]
        golden_summary = golden_section(golden, lines)

    body = "\n".join(lines).rstrip() + "\n"
    print(body)
    if args.update_doc:
        out = Path(args.update_doc)
        old = out.read_text() if out.exists() else "# CORA's observer catalogue: comparison\n"
        text = replace_region(old, "bench_cora", body.rstrip())
        if text is None:
            text = old.rstrip() + "\n\n" + marked("bench_cora", body.rstrip()) + "\n"
        out.write_text(text)
    payload = {"results": results, "golden": golden, "golden_summary": golden_summary,
               "cpp": {f"{k[0]}/{k[1]}": v for k, v in cpp.items()}, "markdown": body}
    if args.json:
        args.json.write_text(json.dumps(payload, indent=1, default=float))
    return payload


if __name__ == "__main__":
    main()
