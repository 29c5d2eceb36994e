"""The summary of a study, rebuilt from its result files: :func:`summarize`, :func:`format_summary`,
:func:`write_summary`, :func:`write_study_plots`.

The records are de-duplicated on the case key; a case recorded twice must have the same result
both times (timing fields aside): a difference is a determinism failure across workers and is
reported as an error naming the case and the field. Only a digest of each record is kept for that
check, so the memory is a few dozen bytes per case plus the widths the plots draw.
"""
from __future__ import annotations

import csv
import hashlib
import json
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .tasks import TIMING_FIELDS

__all__ = ["summarize", "format_summary", "write_summary", "write_study_plots", "StudySummary",
           "NondeterminismError"]


class NondeterminismError(ValueError):
    """A case was recorded twice with different results."""


def _digest(rec: dict) -> bytes:
    core = {k: v for k, v in rec.items() if k not in TIMING_FIELDS}
    return hashlib.blake2b(json.dumps(core, sort_keys=True, default=str).encode(), digest_size=16).digest()


@dataclass
class _Group:
    cases: int = 0
    ok: int = 0
    failed: int = 0
    crashed: int = 0
    errors: int = 0
    checked: int = 0
    contained: int = 0
    widths: list = field(default_factory=list)
    finals: list = field(default_factory=list)
    ratios: list = field(default_factory=list)
    us: list = field(default_factory=list)
    design: list = field(default_factory=list)

    def add(self, r: dict) -> None:
        self.cases += 1
        st = r.get("status")
        if st == "ok":
            self.ok += 1
            if r.get("contained") is not None:
                self.checked += 1
                self.contained += bool(r["contained"])
            for name, lst in (("mean_width", self.widths), ("final_width", self.finals), ("hull_ratio", self.ratios),
                              ("us_per_step", self.us), ("design_s", self.design)):
                v = r.get(name)
                if isinstance(v, (int, float)) and math.isfinite(v):
                    lst.append(float(v))
        elif st == "failed":
            self.failed += 1
        elif st == "crashed":
            self.crashed += 1
        else:
            self.errors += 1

    def row(self, estimator: str, parameter: str, value) -> dict:
        def mean(v):  # sorted: the same value whatever order the workers finished in
            return float(np.mean(sorted(v))) if v else None

        def med(v):
            return float(np.median(v)) if v else None

        return {"estimator": estimator, "parameter": parameter, "value": value, "cases": self.cases, "ok": self.ok,
                "failed": self.failed, "crashed": self.crashed, "errors": self.errors,
                "containment_rate": self.contained / self.checked if self.checked else None,
                "mean_width": mean(self.widths), "median_width": med(self.widths),
                "final_width": mean(self.finals), "hull_ratio": mean(self.ratios),
                "us_per_step_median": med(self.us), "design_s_median": med(self.design)}


@dataclass
class StudySummary:
    """``rows`` (one per estimator, then one per estimator, parameter and value), ``cases`` (distinct
    cases recorded), ``duplicates`` (identical repeats ignored), ``torn`` (torn last lines
    skipped), ``leaked`` (keys of cases whose true state left a guaranteed set), ``crashed`` and
    ``errors`` (the records of crashed cases and of cases whose task raised), and per estimator the
    mean widths (``widths``) and the swept values (``by_param``) the plots draw.

    Parameters
    ----------
    rows : list of dict
        Table rows.
    cases, duplicates, torn : int
        Counts (see above).
    leaked, crashed, errors : list
        See above.
    widths, by_param : dict
        Data of the plots.
    """

    rows: list
    cases: int
    duplicates: int
    torn: int
    leaked: list
    crashed: list
    errors: list
    widths: dict
    by_param: dict


def summarize(store) -> StudySummary:
    """Reads every record of ``store`` (a :class:`~setbound.studies.store.ResultStore`) once.

    Parameters
    ----------
    store : ResultStore
        The output folder.

    Returns
    -------
    StudySummary
    """
    seen: dict = {}
    groups: dict = {}
    widths: dict = {}
    by_param: dict = {}
    dup = 0
    leaked, crashed, errors = [], [], []
    for r in store.records():
        d = _digest(r)
        k = r["key"]
        if k in seen:
            if seen[k] != d:
                raise NondeterminismError(f"results: case {k} was recorded twice with different results (the "
                                          f"task is not deterministic across workers, or the folder mixes runs)")
            dup += 1
            continue
        seen[k] = d
        est = r.get("estimator", "")
        groups.setdefault((est, "", None), _Group()).add(r)
        for p, v in (r.get("params") or {}).items():
            groups.setdefault((est, p, json.dumps(v)), _Group()).add(r)
        st = r.get("status")
        if st == "ok":
            if r.get("contained") is False:
                leaked.append(k)
            w = r.get("mean_width")
            if isinstance(w, (int, float)) and math.isfinite(w):
                widths.setdefault(est, []).append(float(w))
                for p, v in (r.get("params") or {}).items():
                    by_param.setdefault(p, {}).setdefault(est, []).append((v, float(w)))
        elif st == "crashed":
            crashed.append(r)
        elif st != "failed":
            errors.append(r)
    rows = [g.row(e, p, None if v is None else json.loads(v))
            for (e, p, v), g in sorted(groups.items(), key=lambda kv: (kv[0][0], kv[0][1], _order(kv[0][2])))]
    return StudySummary(rows, len(seen), dup, store.torn, leaked, crashed, errors, widths, by_param)


def _order(v):
    if v is None:
        return (0, 0, "")
    x = json.loads(v)
    return (1, x, "") if isinstance(x, (int, float)) and not isinstance(x, bool) else (2, 0, v)


def _fmt(v, width: int, spec: str = ".4g") -> str:
    if v is None:
        return f"{'—':>{width}}"
    if isinstance(v, float):
        return f"{v:>{width}{spec}}"
    return f"{str(v):>{width}}"


def format_summary(summary: StudySummary) -> str:
    """The summary table as text: one row per estimator (all its cases), then per parameter value.

    Parameters
    ----------
    summary : StudySummary
        The summary.

    Returns
    -------
    str
    """
    head = (f"{'estimator':<18}{'parameter':<24}{'cases':>7}{'ok':>6}{'fail':>5}{'crash':>6}{'inside':>8}"
            f"{'mean width':>12}{'final width':>12}{'hull ratio':>11}{'µs/step':>9}{'design s':>9}")
    lines = [head, "-" * len(head)]
    for r in summary.rows:
        par = "(all)" if not r["parameter"] else f"{r['parameter']}={json.dumps(r['value'])}"
        rate = None if r["containment_rate"] is None else f"{100 * r['containment_rate']:.1f}%"
        lines.append(f"{r['estimator'][:17]:<18}{par[:23]:<24}{r['cases']:>7}{r['ok']:>6}{r['failed']:>5}"
                     f"{r['crashed'] + r['errors']:>6}{_fmt(rate, 8)}{_fmt(r['mean_width'], 12)}"
                     f"{_fmt(r['final_width'], 12)}{_fmt(r['hull_ratio'], 11)}"
                     f"{_fmt(r['us_per_step_median'], 9, '.3g')}{_fmt(r['design_s_median'], 9, '.3g')}")
    return "\n".join(lines)


_COLUMNS = ("estimator", "parameter", "value", "cases", "ok", "failed", "crashed", "errors", "containment_rate",
            "mean_width", "median_width", "final_width", "hull_ratio", "us_per_step_median", "design_s_median")


def write_summary(out, summary: StudySummary, extra: dict | None = None) -> list:
    """Writes ``summary.csv`` (the rows) and ``summary.json`` (rows, counts, the leaked and crashed
    cases with their reproduction commands); returns the paths."""
    out = Path(out)
    with open(out / "summary.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=_COLUMNS)
        w.writeheader()
        for r in summary.rows:
            w.writerow({k: ("" if r[k] is None else json.dumps(r[k]) if k == "value" else r[k]) for k in _COLUMNS})
    doc = {"cases": summary.cases, "duplicates": summary.duplicates, "torn_lines": summary.torn,
           "leaked": summary.leaked, "crashed": summary.crashed, "errors": summary.errors, "rows": summary.rows,
           **(extra or {})}
    (out / "summary.json").write_text(json.dumps(doc, indent=1, default=str))
    return [out / "summary.csv", out / "summary.json"]


def write_study_plots(out, summary: StudySummary) -> list:
    """``widths.png`` (distribution of the mean width per estimator), ``width_vs_<parameter>.png``
    (mean width against each swept parameter, per estimator, with the 10–90 % band) and
    ``containment.png`` (containment rate per estimator). Returns the paths written."""
    from ..plotting import save_png
    from matplotlib.figure import Figure

    out = Path(out)
    paths = []
    if summary.widths:
        names = sorted(summary.widths)
        fig = Figure(figsize=(1.6 + 1.3 * len(names), 4))
        ax = fig.add_subplot()
        ax.boxplot([summary.widths[n] for n in names], showfliers=True)
        ax.set_xticks(range(1, len(names) + 1), names, rotation=20)
        ax.set_ylabel("mean width (per case)")
        if all(min(summary.widths[n]) > 0 for n in names):
            ax.set_yscale("log")
        ax.set_title("distribution of the mean bound width")
        fig.tight_layout()
        paths.append(save_png(fig, out / "widths.png"))
    for p, per_est in summary.by_param.items():
        numeric = all(isinstance(v, (int, float)) and not isinstance(v, bool) for lst in per_est.values()
                      for v, _ in lst)
        fig = Figure(figsize=(6, 4))
        ax = fig.add_subplot()
        labels = sorted({json.dumps(v) for lst in per_est.values() for v, _ in lst},
                        key=lambda s: (json.loads(s) if numeric else s))
        for est, lst in sorted(per_est.items()):
            xs, mid, lo, hi = [], [], [], []
            for i, lab in enumerate(labels):
                ws = [w for v, w in lst if json.dumps(v) == lab]
                if ws:
                    xs.append(json.loads(lab) if numeric else i)
                    mid.append(np.mean(ws))
                    lo.append(np.quantile(ws, 0.1))
                    hi.append(np.quantile(ws, 0.9))
            ax.plot(xs, mid, "o-", label=est)
            ax.fill_between(xs, lo, hi, alpha=0.15)
        if not numeric:
            ax.set_xticks(range(len(labels)), labels)
        ax.set_xlabel(p)
        ax.set_ylabel("mean width")
        ax.legend(fontsize=8)
        ax.set_title(f"mean width against {p}")
        safe = "".join(ch if ch.isalnum() or ch in "-_" else "_" for ch in p)
        fig.tight_layout()
        paths.append(save_png(fig, out / f"width_vs_{safe}.png"))
    overall = [r for r in summary.rows if not r["parameter"]]
    if overall:
        fig = Figure(figsize=(1.6 + 1.3 * len(overall), 3.5))
        ax = fig.add_subplot()
        rates = [100 * r["containment_rate"] if r["containment_rate"] is not None else 0.0 for r in overall]
        ax.bar(range(len(overall)), rates, color=["tab:green" if v == 100 else "tab:red" for v in rates])
        for k, r in enumerate(overall):
            if r["containment_rate"] is None:  # not a guaranteed method, or no truth known
                ax.text(k, 2, "n/a", ha="center", va="bottom")
            elif r["containment_rate"] < 1:
                ax.text(k, rates[k] + 1, f"{rates[k]:.1f} %", ha="center", va="bottom")
        ax.set_xticks(range(len(overall)), [r["estimator"] for r in overall], rotation=20)
        ax.set_ylim(0, 105)
        ax.set_ylabel("truth contained (% of cases)")
        ax.set_title("containment rate (guaranteed methods)")
        fig.tight_layout()
        paths.append(save_png(fig, out / "containment.png"))
    return paths
