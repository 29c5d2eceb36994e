"""The main job: ``setbound demo`` (``make demo``, ``python -m setbound.demo``).

The built-in default job — EX-BC14, the 3-state example of [BenChabane2014] §5 (Methods › Ellipsoidal estimation › Examples), shipped inside the package as ``setbound/data/demo_bc14.toml`` so it works from a
wheel — is run under every estimator that applies to it: the ellipsoidal offline, online,
scaled and improved estimators, the zonotopic segment-minimisation, volume-minimisation and
P-radius estimators, and the Kalman filter as the (not guaranteed) contrast. An estimator
whose design has no solution on this system (infeasible, not detectable) is listed as "not
applicable" with the reason, as are the thesis observers for other kinds of systems; another
failure is a FAILED row of the table; the demo does not stop.
The summary table is printed and the results, ``summary.json`` and the plots are written to
``out/demo/``. The exit code is 1 if the true state ever leaves a guaranteed set.

The module also keeps two small illustrations of the set library used by the gallery:
:func:`wrapping_effect` (thesis §1.2.7) and :func:`zonotopic_tube` (a hand-written
zonotopic estimator on the EX-LE13 system of [Le2013] §5).
"""
from __future__ import annotations

import argparse
import math
import sys
import tomllib
from importlib import resources
from pathlib import Path

import numpy as np

from . import jobs
from .interval import Box
from .report import format_table, leaked, summary_rows, write_plots, write_results
from .sets import Strip, Zonotope

#: The package resource holding the demo job.
DEMO_JOB = "demo_bc14.toml"

#: Estimator methods (names registered in :data:`setbound.config.ESTIMATORS`) appended to the
#: demo job when they are registered (methods not registered are skipped and listed as such).
#: The thesis observers see the demo's unit-box model through :meth:`setbound.Plant.from_linear_system`:
#: in EX-BC14 the ω components 0–2 drive only the state (d = columns of E) and 3–4 only the
#: output (v = columns of F), so the thesis plant is x⁺ = A x + B u + E₀₋₂ d, y = C x + F₃₋₄ v with
#: d, v in unit boxes — exactly the demo system; its (A, C) is detectable (A is not Schur).
THESIS_OBSERVERS: list[str] = ["interval_luenberger", "interval_invariant", "ellipsoidal_sm"]

#: Thesis observers that do not apply to the demo system, with the reason (printed by the demo).
THESIS_NOT_APPLICABLE: dict[str, str] = {
    "lpv_sm": "Ch. 3 LPV observer: the demo system is LTI (no scheduling parameter)",
    "nonlinear_interval": "Ch. 4 nonlinear observer: the demo system has no nonlinearity h(p, x, k)",
    "invariant_tube": "Ch. 1 Algorithm 1 tube: for autonomous systems without an input or observer",
}


def wrapping_effect(steps: int = 8):
    """Rows ``(k, width of the re-boxed box, width of the zonotope's hull)`` for a unit box rotated
    by π/4 ``k`` times: re-boxing wraps (×√2 per step), the zonotope image is exact.

    Parameters
    ----------
    steps : int, optional
        Number of rotations.

    Returns
    -------
    list of tuple

    Examples
    --------
    >>> rows = setbound.demo.wrapping_effect(2)
    >>> [(k, round(box, 6), round(zono, 6)) for k, box, zono in rows]
    [(1, 2.828427, 2.828427), (2, 4.0, 2.0)]
    """
    theta = math.pi / 4
    R = np.array([[math.cos(theta), math.sin(theta)], [-math.sin(theta), math.cos(theta)]])
    box = Box([-1.0, -1.0], [1.0, 1.0])
    zono = Zonotope([0.0, 0.0], np.eye(2))
    rows = []
    for k in range(1, steps + 1):
        box = R @ box  # exact hull of the image, then re-boxed: wraps
        zono = R @ zono  # exact image
        lo, hi = zono.interval_hull()
        rows.append((k, float(np.max(box.width)), float(np.max(hi - lo))))
    return rows


def segment_min_lambda(H: np.ndarray, c: np.ndarray, phi: float) -> np.ndarray:
    """λ* = H Hᵀ c / (cᵀ H Hᵀ c + φ²) (Methods › Zonotopic estimation › Segment minimisation).

    Parameters
    ----------
    H : ndarray, shape (n, m)
        Generators.
    c : ndarray, shape (n,)
        Strip normal.
    phi : float
        Strip half-width.

    Returns
    -------
    ndarray, shape (n,)
    """
    g = H @ (H.T @ c)
    return g / (c @ g + phi * phi)


def zonotopic_tube(steps: int, seed: int, vertex: bool):
    """A hand-written guaranteed zonotopic tube on the EX-LE13 system of [Le2013] §5 (A at δ = 0): exact
    prediction, one strip per output with the segment-minimising λ, Combastel reduction to 20
    generators. Returns ``(lower, upper, x_true, inside)`` per step.

    Parameters
    ----------
    steps : int
        Horizon.
    seed : int
        Seed.
    vertex : bool
        Vertex (±1) disturbances instead of uniform ones.

    Returns
    -------
    lower : ndarray
    upper : ndarray
    x_true : ndarray
    inside : ndarray
    """
    A = np.array([[0.0, -0.5], [1.0, 1.0]])
    Fw = np.array([[-0.12], [0.02]])
    C = np.array([[-2.0, 1.0], [1.0, 1.0]])
    phi = np.array([0.2, 0.2])
    rng = np.random.default_rng(seed)
    draw = (lambda n: rng.choice([-1.0, 1.0], size=n)) if vertex else (lambda n: rng.uniform(-1, 1, n))
    x = rng.uniform(-3.0, 3.0, 2)
    X = Zonotope([0.0, 0.0], 3.0 * np.eye(2))
    W = Zonotope([0.0, 0.0], Fw)
    lows, highs, truth, inside = [], [], [], []
    for _ in range(steps):
        x = A @ x + Fw @ draw(1)
        y = C @ x + phi * draw(2)
        X = A @ X + W
        for i in range(2):
            lam = segment_min_lambda(X.generators, C[i], phi[i])
            X = X.intersect_strip(Strip(C[i], y[i], phi[i]), lam)
        X = X.reduce(20, method="combastel")
        lo, hi = X.interval_hull()
        lows.append(lo)
        highs.append(hi)
        truth.append(x.copy())
        inside.append(bool(X.contains(x)))
    return np.array(lows), np.array(highs), np.array(truth), np.array(inside)


def demo_job(steps: int | None = None):
    """The demo job (a :class:`setbound.config.Job`), with ``steps`` overriding the horizon and the
    registered :data:`THESIS_OBSERVERS` appended. Returns ``(job, skipped)``: the thesis
    observers not registered yet.

    Parameters
    ----------
    steps : int, optional
        Horizon.

    Returns
    -------
    job : Job
    skipped : list of str
    """
    doc = tomllib.loads(resources.files("setbound").joinpath("data", DEMO_JOB).read_text(encoding="utf-8"))
    if steps is not None:
        if not (isinstance(steps, int) and steps >= 1):
            raise jobs.ConfigError(f"--steps: must be a positive integer, got {steps!r}")
        doc["simulation"]["horizon"] = steps
        doc.get("plots", {}).pop("steps", None)
    skipped = []
    for method in THESIS_OBSERVERS:
        if method in jobs.ESTIMATORS:
            doc["estimator"].append({"method": method})
        else:
            skipped.append(method)
    return jobs.from_dict(doc, source=f"setbound/data/{DEMO_JOB}"), skipped


#: Library errors meaning "this method's design has no solution for this system".
_INAPPLICABLE = ("InfeasibleError: ", "NotDetectableError: ")


def _inapplicable(error: str | None) -> bool:
    return bool(error) and error.startswith(_INAPPLICABLE)


def _why_not(error: str) -> str:
    kind, _, reason = error.partition(": ")
    what = "its design has no solution for the demo system" if kind == "InfeasibleError" else \
        "the demo system is not detectable the way it needs"
    return f"{what}: {reason}"


def run_demo(out: Path = Path("out/demo"), steps: int | None = None, plots: bool = True) -> int:
    """Runs the main job, prints the table, writes results and plots to ``out``; returns the
    exit code (1 if the true state left a guaranteed set).

    Parameters
    ----------
    out : Path, optional
        Output folder.
    steps : int, optional
        Horizon.
    plots : bool, optional
        Write the plots.

    Returns
    -------
    int
    """
    job, skipped = demo_job(steps)
    print(f"setbound demo — {len(job.estimators)} estimators on the 3-state example of Methods › Ellipsoidal estimation › Examples")
    results = jobs.run(job, keep_going=True)
    rows = summary_rows(job, results)
    # a method whose design has no solution on this system (P-radius approach 1: an output that
    # cannot detect the unstable modes alone) does not apply to it; that is not a failure of the demo
    inapplicable = {r["name"]: _why_not(r["error"]) for r in rows if not r["ok"] and _inapplicable(r["error"])}
    print(f"{job.title} ({len(job.y)} steps)")
    print(format_table([r for r in rows if r["name"] not in inapplicable]))
    if skipped:
        print(f"thesis observers not registered yet (skipped): {', '.join(skipped)}")
    for name, why in inapplicable.items():
        print(f"not applicable: {name} — {why}")
    for method, why in THESIS_NOT_APPLICABLE.items():
        print(f"not applicable: {method} — {why}")
    out = Path(out)
    write_results(out, job, results, rows, extra={"skipped": skipped,
                                                  "not_applicable": {**inapplicable, **THESIS_NOT_APPLICABLE}})
    if plots:
        for p in write_plots(out, job, results):
            print(f"  {p}")
    print(f"results written to {out}")
    lost = leaked(rows)
    if lost:
        print(f"ERROR: the true state left the guaranteed set of: {', '.join(lost)}", file=sys.stderr)
        return 1
    return 0


def main(argv: list[str] | None = None) -> int:
    """``python -m setbound.demo [--out DIR] [--steps N] [--no-plots]`` (same as ``setbound demo``).

    Parameters
    ----------
    argv : list of str, optional
        Arguments.

    Returns
    -------
    int
    """
    from .errors import SetboundError
    from .progress import set_quiet

    parser = argparse.ArgumentParser(prog="python -m setbound.demo", description="the main job of setbound")
    parser.add_argument("--out", default="out/demo", help="directory for the results (default out/demo)")
    parser.add_argument("--steps", type=int, default=None, help="horizon (default 50)")
    parser.add_argument("--no-plots", action="store_true", help="write no PNG files")
    parser.add_argument("--quiet", "-q", action="store_true", help="no progress bars")
    args = parser.parse_args(argv)
    set_quiet(args.quiet)
    try:
        return run_demo(Path(args.out), args.steps, plots=not args.no_plots)
    except (SetboundError, ValueError) as exc:
        print(f"setbound demo: error: {exc}", file=sys.stderr)
        return 2
    finally:
        set_quiet(False)


if __name__ == "__main__":
    raise SystemExit(main())
