"""``python -m setbound.demo``: a short tour of the set library, printed and plotted.

Until the estimator families land this is the main job (``make demo``). It shows three
things the estimators are built from, each checked as it runs:

1. the wrapping effect (thesis §1.2.7): a box rotated by π/4 again and again, re-boxed
   at every step, grows by √2 per step, while the zonotope image stays exact;
2. a guaranteed zonotopic tube on the 2-state example of papers.md §3.5 (A at δ = 0):
   exact prediction ``A X ⊕ W``, one strip per output with the segment-minimising λ
   (papers.md §5.1), Combastel reduction to 20 generators; the true state is checked to
   lie in the set at every step, under random and bang-bang (vertex) disturbances;
3. the tightest box around the ellipsoid of thesis Example 1.3/1.4, from (1.40).
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

from .interval import Box
from .sets import Ellipsoid, Strip, Zonotope


def wrapping_effect(steps: int = 8):
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
    """λ* = H Hᵀ c / (cᵀ H Hᵀ c + φ²) (papers.md §5.1)."""
    g = H @ (H.T @ c)
    return g / (c @ g + phi * phi)


def zonotopic_tube(steps: int, seed: int, vertex: bool):
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


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m setbound.demo", description=__doc__.split("\n")[0])
    parser.add_argument("--out", default="out/demo", help="directory for the figure (default out/demo)")
    parser.add_argument("--steps", type=int, default=50)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--no-plot", action="store_true", help="print only")
    args = parser.parse_args(argv)

    print("1. Wrapping effect (thesis §1.2.7): unit box rotated by pi/4")
    print("   step   re-boxed width   zonotope hull width")
    wrap = wrapping_effect()
    for k, wb, wz in wrap:
        print(f"   {k:4d}   {wb:14.4f}   {wz:19.4f}")

    print(f"\n2. Guaranteed zonotopic tube, papers §3.5 system, {args.steps} steps")
    ok = True
    tubes = {}
    for vertex in (False, True):
        lo, hi, x, inside = zonotopic_tube(args.steps, args.seed, vertex)
        tubes[vertex] = (lo, hi, x)
        kind = "bang-bang (vertex)" if vertex else "uniform random"
        width = (hi - lo).mean(axis=0)
        print(f"   {kind:20s} disturbances: true state inside at {inside.sum()}/{len(inside)} steps, "
              f"mean widths {width[0]:.4f}, {width[1]:.4f}")
        ok &= bool(inside.all())

    P = np.array([[1.0, 1.0], [1.0, 4.0]])
    E = Ellipsoid(P, [0.0, 0.0], 1.0)
    elo, ehi = E.bounding_box()
    print("\n3. Ellipsoid of thesis Ex. 1.3, (x-c)'P(x-c) <= 1 with P = [[1,1],[1,4]]")
    print(f"   tightest box (1.40): [{elo[0]:.4f}, {ehi[0]:.4f}] x [{elo[1]:.4f}, {ehi[1]:.4f}],"
          f" volume {E.volume:.4f} (= pi/sqrt(3) = {math.pi / math.sqrt(3):.4f})")

    if not args.no_plot:
        path = plot(Path(args.out), wrap, tubes, E)
        if path is not None:
            print(f"\nfigure written to {path}")
    if not ok:
        print("ERROR: the true state left the guaranteed set", file=sys.stderr)
        return 1
    return 0


def plot(out: Path, wrap, tubes, E) -> Path | None:
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:  # pragma: no cover - matplotlib is the 'plot' extra
        print("matplotlib is not installed (pip install setbound[plot]); no figure")
        return None
    out.mkdir(parents=True, exist_ok=True)
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.2))
    k = [r[0] for r in wrap]
    axes[0].semilogy(k, [r[1] for r in wrap], "o-", label="box, re-boxed each step")
    axes[0].semilogy(k, [r[2] for r in wrap], "s-", label="zonotope (exact image)")
    axes[0].set(title="Wrapping effect (rotation by π/4)", xlabel="step", ylabel="max width")
    axes[0].legend()
    lo, hi, x = tubes[True]
    t = np.arange(1, len(x) + 1)
    axes[1].fill_between(t, lo[:, 0], hi[:, 0], alpha=0.3, label="guaranteed bounds of $x_1$")
    axes[1].plot(t, x[:, 0], "k.-", ms=3, label="true $x_1$ (vertex disturbances)")
    axes[1].set(title="Zonotopic tube, papers §3.5", xlabel="k")
    axes[1].legend()
    th = np.linspace(0, 2 * np.pi, 400)
    L = np.linalg.cholesky(np.linalg.inv(E.P))
    pts = (L @ np.vstack([np.cos(th), np.sin(th)])) * math.sqrt(E.rho)
    axes[2].plot(pts[0], pts[1], label="ellipsoid")
    elo, ehi = E.bounding_box()
    axes[2].plot([elo[0], ehi[0], ehi[0], elo[0], elo[0]], [elo[1], elo[1], ehi[1], ehi[1], elo[1]],
                 "--", label="bounding box (1.40)")
    axes[2].set(title="Thesis Ex. 1.3", aspect="equal")
    axes[2].legend()
    fig.tight_layout()
    path = out / "sets.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


if __name__ == "__main__":
    raise SystemExit(main())
