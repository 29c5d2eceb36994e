"""Regenerates the gallery: the figures of the papers (papers.md lists them per paper),
recomputed from the job files of ``examples/`` with setbound's plotting functions, plus the
wrapping-effect figure of the thesis (Fig 1.4).

    python docs/gallery/make_gallery.py [--out docs/gallery]

Each figure is listed in FIGURES with its caption; docs/gallery/README.md indexes them (the
script rewrites the index between its markers). Random data come from each example's seed, so
a rerun reproduces the images (up to matplotlib version differences).
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path


ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))

from setbound import config, plotting  # noqa: E402
from setbound.demo import wrapping_effect  # noqa: E402
from setbound.progress import track  # noqa: E402

DPI = 80


def _run(example: str, keep=None):
    job = config.load(ROOT / "examples" / example)
    if keep is not None:
        job.estimators = [s for s in job.estimators if s.name in keep]
    results = config.run(job, keep_going=True)
    failed = [f"{r.name}: {r.error}" for r in results if not r.ok]
    if failed:
        raise SystemExit(f"{example}: estimators failed: {failed}")
    return job, {r.name: r.trajectory for r in results}


def fig_bc14(out: Path):
    job, trajs = _run("bc14_3state.toml", keep=["offline", "online", "scaled", "pradius2"])
    yield "bc14_bounds.png", plotting.plot_bounds(trajs, x_true=job.x_true, title="EX-BC14: bounds of x1, x2, x3"), \
        "[BenChabane2014] Figs 1–3 (papers.md §1.4): bounds of the three states under the offline, online and " \
        "scaled ellipsoidal estimators and the P-radius zonotopic estimator of [Le2013] (approach 2; approach 1 " \
        "is infeasible on this system), with the true state (uniform disturbances, seed 2014)."
    yield "bc14_widths_relative.png", plotting.plot_widths(
        trajs, reference="offline", title="EX-BC14: bound widths relative to the offline method"), \
        "[BenChabane2014] Figs 4–6: bound widths divided by the offline method's. Online equals offline at steady " \
        "state for the β-optimised design; scaling is never tighter than online (papers.md §1.3)."
    yield "bc14_volume.png", plotting.plot_volume(trajs, title="EX-BC14: volume of the sets"), \
        "[BenChabane2014] Table 2 as a curve: the volume of the estimation sets over time; the ellipsoidal " \
        "volumes converge to their steady state (papers.md §1.4 explains why the printed values are not " \
        "reproducible; no fixed-shape volume falls below the minimum-volume design's)."
    yield "bc14_projections.png", plotting.plot_projections(
        trajs, steps=[0, 5, 49], dims=(0, 1), x_true=job.x_true, system=job.system, y=job.y,
        title="EX-BC14: sets projected on (x1, x2)"), \
        "Not a paper figure: the sets of the same run projected on (x1, x2) at k = 0, 5, 49 — ellipses and the " \
        "exact polygon of the projected zonotope — with the true state and the measurement strips of y_k " \
        "(their section through the true state)."


def fig_me17(out: Path):
    for example, tag, label in (("me17_stable.toml", "me17a", "Example 1 (stable)"),
                                ("me17_unstable.toml", "me17b", "Example 2 (unstable)")):
        job, trajs = _run(example)
        yield f"{tag}_bounds.png", plotting.plot_bounds(trajs, x_true=job.x_true,
                                                        title=f"EX-ME17, {label}: bounds"), \
            f"[Merhy2017] {label} (papers.md §2.5): online ellipsoidal bounds, the improved measurement-based " \
            "correction and the Kalman filter's mean ± 3σ (not guaranteed, dotted) with the true state, 10 steps " \
            "from the Euclidean ball of radius √20 around (5, 5)."


def fig_le13(out: Path):
    job, trajs = _run("le13_interval.toml")
    yield "le13_bounds_x1.png", plotting.plot_bounds(trajs, x_true=job.x_true, components=[0],
                                                     title="EX-LE13: bounds of x1", figsize=(7.5, 3.6)), \
        "[Le2013] (papers.md §3.5): bounds of x1 under segment minimisation, volume minimisation and the P-radius " \
        "estimators (approaches 1 and 2), interval A (a22 ∈ [0.7, 1.3], drawn at every step), 20 generators."
    yield "le13_widths_relative.png", plotting.plot_widths(
        trajs, reference="segment_min", title="EX-LE13: bound widths relative to segment minimisation"), \
        "[Le2013]: bound widths relative to segment minimisation (below 1: tighter)."
    yield "le13_volume.png", plotting.plot_volume(trajs, title="EX-LE13: zonotope volume"), \
        "[Le2013]: zonotope volume over time — the P-radius approach 2 close to volume minimisation, both below " \
        "approach 1 and segment minimisation, as the paper reports."


def fig_me19(out: Path):
    job, trajs = _run("me19_descriptor.toml")
    yield "me19_bounds.png", plotting.plot_bounds(trajs, x_true=job.x_true, t=job.t,
                                                  title="EX-ME19: bounds of x1, x2, x3"), \
        "[Merhy2019] (papers.md §4.2): bounds of the three states of the descriptor system (singular E) with the " \
        "inputs u = (0.5 sin t + 1, −2 cos t), t ∈ [0, 5π], and the true state."
    yield "me19_volume.png", plotting.plot_volume(trajs, t=job.t, title="EX-ME19: volume of the estimation set"), \
        "[Merhy2019]: the volume of the estimation set decreasing to its steady value."


def fig_wrapping(out: Path):
    from matplotlib.figure import Figure

    rows = wrapping_effect(steps=10)
    fig = Figure(figsize=(6.0, 3.6))
    ax = fig.subplots()
    fig.subplots_adjust(left=0.14, right=0.97, bottom=0.15, top=0.9)
    k = [r[0] for r in rows]
    ax.semilogy(k, [r[1] for r in rows], "o-", label="box, re-boxed at every step")
    ax.semilogy(k, [r[2] for r in rows], "s-", label="zonotope (exact image), its hull")
    ax.semilogy(k, [2 * math.sqrt(2) ** i for i in k], "k:", lw=0.8, label=r"$2\cdot\sqrt{2}^{\,k}$")
    ax.set(xlabel="rotations by π/4", ylabel="largest width", title="Wrapping effect (thesis §1.2.7, Fig 1.4)")
    from matplotlib.ticker import LogLocator, NullFormatter, ScalarFormatter

    ax.yaxis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
    ax.yaxis.set_major_formatter(ScalarFormatter())
    ax.yaxis.set_minor_formatter(NullFormatter())
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    yield "thesis_wrapping.png", fig, \
        "Thesis Fig 1.4 (§1.2.7): the unit box rotated by π/4 again and again. Re-boxing the image at every " \
        "step grows the width by √2 per step (the wrapping effect); the zonotope image is exact."


# ---------------------------------------------------------------- thesis figures (thesis.md)
def _fig(nrows=1, ncols=1, size=(6.0, 3.6)):
    from matplotlib.figure import Figure

    fig = Figure(figsize=size)
    axes = fig.subplots(nrows, ncols, squeeze=False)
    return fig, axes


def _poly(ax, V, **kw):
    """A closed polygon through the 2-D points V (rows), ordered by angle around their mean."""
    import numpy as np

    V = np.asarray(V, float)
    c = V.mean(axis=0)
    V = V[np.argsort(np.arctan2(V[:, 1] - c[1], V[:, 0] - c[0]))]
    V = np.vstack([V, V[:1]])
    ax.plot(V[:, 0], V[:, 1], **kw)


def _ellipse(ax, P, level, center=(0.0, 0.0), **kw):
    """The curve {x : (x − c)ᵀ P (x − c) = level} (2-D)."""
    import numpy as np

    th = np.linspace(0, 2 * np.pi, 200)
    L = np.linalg.cholesky(np.linalg.inv(np.asarray(P, float)))
    pts = np.asarray(center)[:, None] + math.sqrt(level) * L @ np.vstack([np.cos(th), np.sin(th)])
    ax.plot(pts[0], pts[1], **kw)


def _box(ax, lo, hi, **kw):
    ax.plot([lo[0], hi[0], hi[0], lo[0], lo[0]], [lo[1], lo[1], hi[1], hi[1], lo[1]], **kw)


def fig_thesis_ex1_5(out: Path):
    import numpy as np

    job, trajs = _run("thesis_ex1_5.toml")
    res = config.run(job, keep_going=True, quiet=True)[0]
    d = res.design
    fig, axes = _fig(1, 1, (5.2, 4.4))
    ax = axes[0, 0]
    _ellipse(ax, d.P, d.c_out, color="C0", lw=1.2, ls="--", zorder=3, label=r"$\bar\Psi(\mu)$")
    _ellipse(ax, d.P, d.c_in, color="C2", lw=1.2, ls=":", zorder=3, label=r"$\bar\Psi^+(\mu)$")
    for k, S in enumerate(d.sets):
        V = S.plot_data()  # closed polygon
        style = dict(color="C1", lw=1.5, label=r"$\Phi_0 = \Phi_v$") if k == 0 else \
            dict(color="C3", lw=1.5, label=rf"$\Phi_{{k^*}}$, $k^*={d.k_star}$") if k == d.k_star else \
            dict(color="0.6", lw=0.5)
        ax.plot(V[:, 0], V[:, 1], **style)
    ax.plot(job.x_true[:, 0], job.x_true[:, 1], ".", color="k", ms=3, label="x_k (simulation)")
    ax.set(xlabel="x1", ylabel="x2", title="Thesis Ex 1.5: Algorithm 1 (Fig 1.11)")
    ax.legend(fontsize=7, loc="upper right")
    ax.grid(alpha=0.3)
    yield "thesis_ex1_5_sets.png", fig, \
        "Thesis Fig 1.11 (Ex 1.5, thesis.md §3.6): the polyhedral RPI set Φ_v between the ellipsoids Ψ̄⁺(μ) and " \
        f"Ψ̄(μ) of the BRL matrix P (LMI 1.48), the iterates Φ_k = AΦ_(k−1) ⊕ EΔ (grey) down to Φ_k* (k* = {d.k_star}, " \
        "stop when the shrinking index ρ̄_k ≤ ε = 4.4·10⁻³) and a simulated trajectory started in [x_0] ⊆ Φ_v. " \
        "μ = 1.05 is a choice: the thesis does not state it."
    fig, axes = _fig()
    ax = axes[0, 0]
    k = np.arange(len(d.shrinking_index))
    ax.semilogy(k, d.shrinking_index, "o-", ms=3, label=r"$\bar\rho_k = \beta^k\sqrt{\mu\lambda_{max}(P)/\lambda_{min}(P)}$")
    ax.axhline(4.4e-3, color="k", ls=":", lw=0.8, label=r"$\varepsilon = 4.4\cdot10^{-3}$")
    ax.set(xlabel="k", ylabel="shrinking index", title="Thesis Ex 1.5: shrinking index (Fig 1.12)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    yield "thesis_ex1_5_rho.png", fig, \
        f"Thesis Fig 1.12: the shrinking index ρ̄_k of Algorithm 1 against k (β = {d.beta:.4f} from the BRL P); " \
        f"the iteration stops at k* = {d.k_star}, the first k with ρ̄_k ≤ ε."


def fig_thesis_ch2(out: Path):
    import numpy as np

    job, trajs = _run("thesis_ch2_sec2_5.toml")
    res = {r.name: r for r in config.run(job, keep_going=True, quiet=True)}
    yield "thesis_ch2_bounds.png", plotting.plot_bounds(
        trajs, x_true=job.x_true, title="Thesis Ch. 2 §2.5: bounds (Fig 2.3)"), \
        "Thesis Fig 2.3 (§2.5, thesis.md §4.8): bounds x̂_k ± ē∞·√μ_k of the Ch. 2 ellipsoidal-invariant-set " \
        "observer (Algorithm 2, γ and L from LMI 2.35, λ from the refinement 2.36) and, for comparison, of the Ch. 4 " \
        "interval Luenberger observer on the same data; uniform random d, v (the thesis does not give its profiles)."
    tr = res["ellipsoidal-sm"].trajectory  # a quiet run is one call: it keeps the mu_k of the observer
    fig, axes = _fig()
    ax = axes[0, 0]
    ax.plot(np.arange(len(tr.mu)), tr.mu, "o-", ms=3)
    ax.axhline(1.0, color="k", ls=":", lw=0.8)
    ax.set(xlabel="k", ylabel=r"$\mu_k$", title=r"Thesis Ch. 2 §2.5: $\mu_k \to 1$ (Fig 2.4)")
    ax.grid(alpha=0.3)
    yield "thesis_ch2_mu.png", fig, \
        "Thesis Fig 2.4: the scaling μ_k of the error ellipsoid, μ_(k+1) = (1 − λ)μ_k + λ, from μ_0 (the corners of " \
        "[e_0]) down to 1 — the error set then is the invariant ellipsoid {eᵀPe ≤ c̄}."
    from setbound import hinf

    design = res["ellipsoidal-sm"].design
    fig, axes = _fig(1, 1, (5.2, 4.4))
    ax = axes[0, 0]
    e = job.x_true - tr.center
    late = np.asarray(tr.mu) <= 1.01
    ax.plot(e[late, 0], e[late, 1], ".", color="k", ms=3, label=r"$e_k = x_k - \hat x_k$, $\mu_k \leq 1.01$")
    ax.plot(e[~late, 0], e[~late, 1], "x", color="0.5", ms=4, label=r"$e_k$ in the transient ($\mu_k > 1.01$)")
    _ellipse(ax, design.P, design.cbar, color="C0", label=r"invariant $\{e^TPe \leq \bar c\}$")
    Vi, t2, prob = hinf.chebyshev_error_ellipsoid(design.V, 3.0)
    _ellipse(ax, Vi, t2, color="C3", ls="--", label=f"Chebyshev, t = 3 (P ≥ {prob:.2f})")
    ax.set(xlabel="e1", ylabel="e2", title="Thesis Ch. 2 §2.5: error sets (Fig 2.5)")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    yield "thesis_ch2_ellipses.png", fig, \
        "Thesis Fig 2.5: the estimation errors of the simulation (crosses: the transient, while μ_k > 1.01 and the " \
        "guaranteed set is the larger {eᵀPe ≤ μ_k c̄}), the invariant ellipsoid {eᵀPe ≤ c̄} " \
        "and the Chebyshev ellipsoid {eᵀV⁻¹e ≤ t²}, t = 3 (2.41, probabilistic: it holds with probability ≥ " \
        "1 − n/t², reporting only)."


def fig_thesis_ch3(out: Path):
    job, trajs = _run("thesis_ch3_ex1.toml")
    yield "thesis_ch3_ex1_bounds.png", plotting.plot_bounds(
        trajs, x_true=job.x_true, title="Thesis Ch. 3 Ex 1: LPV observer bounds"), \
        "Thesis Ch. 3 Ex 1 (§3.6.1, thesis.md §5.8): bounds of the LPV ellipsoidal-invariant-set observer " \
        "(Algorithm 3, vertex gains L_1, L_2 with a common P) with the scheduling ρ_k = 0.075 + 0.025 sin(0.1k) " \
        "(a choice: the thesis shows its profile only in Fig 3.4)."
    job, trajs = _run("thesis_ch3_ex2_lorenz.toml")
    yield "thesis_ch3_lorenz_bounds.png", plotting.plot_bounds(
        trajs, x_true=job.x_true, title="Thesis Ch. 3 Ex 2: quasi-LPV Lorenz"), \
        "Thesis Ch. 3 Ex 2 (§3.6.2): the discrete Lorenz model in quasi-LPV form (ρ1 = x1 measured, ρ2 = 10), " \
        "w_k = (2 sin(0.04k), 0), u = 10; bounds of the LPV observer with W = (4/3)I₂ (thesis.md §5.8)."


def fig_thesis_naive(out: Path):
    import numpy as np
    import tomllib

    doc = tomllib.loads((ROOT / "examples" / "thesis_ex4_5_1.toml").read_text())
    doc["simulation"]["horizon"] = 30
    doc.pop("plots", None)
    doc["estimator"] = [{"method": "interval_luenberger", "variant": v, "name": v, "xhat0": [0, 0]}
                        for v in ("naive", "wrapped", "tight")]
    job = config.from_dict(doc)
    res = config.run(job, keep_going=True, quiet=True)
    fig, axes = _fig()
    ax = axes[0, 0]
    for r in res:
        ax.semilogy(np.arange(len(job.y)), r.trajectory.width.max(axis=1), "o-", ms=3, label=r.name)
    ax.set(xlabel="k", ylabel="largest width of [x_k]", title="Thesis Fig 4.1: naive vs tight error boxes (Ex 4.5.1)")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3, which="both")
    yield "thesis_naive_vs_tight.png", fig, \
        "Thesis Fig 4.1 (thesis.md §6.2) on Ex 4.5.1: the naive recursion (4.15), which re-boxes A_o[e_k] at every " \
        "step, diverges although A_o is Schur (wrapping effect); the thesis's formula (wrapped, [g_0] = E[w] boxed " \
        "first) and the exact interval hull (tight) converge, tight ⊆ wrapped. Same point observer x̂_k for all three."


def fig_thesis_ex4_5_1(out: Path):
    import numpy as np

    job, trajs = _run("thesis_ex4_5_1.toml")
    yield "thesis_ex4_5_1_bounds.png", plotting.plot_bounds(
        trajs, x_true=job.x_true, title="Thesis Ex 4.5.1: interval observers (Fig 4.5)"), \
        "Thesis Fig 4.5 (Ex 4.5.1, thesis.md §6.4): bounds of the interval Luenberger observer (tight and the " \
        "thesis's wrapped formula) and of the invariant-set observer of §6.3 (λ = 11, μ = 2, ε = 0.01: the box " \
        "sequence [s_k] up to k*, then Φ_k*'s box), with the true state from x_0 = (1, 1); uniform random d, v."
    res = {r.name: r for r in config.run(job, keep_going=True, quiet=True)}
    D = res["invariant"].design
    fig, axes = _fig(1, 2, (9.6, 4.4))
    V = D.phi0_vertices.T
    for j, ax in enumerate(axes[0]):
        _ellipse(ax, D.P, D.c_out, color="C0", ls="--", lw=1.2, zorder=3, label=r"$\bar\Psi(\mu)$")
        _ellipse(ax, D.P, D.c_in, color="C2", ls=":", lw=1.2, zorder=3, label=r"$\bar\Psi^+(\mu)$")
        _poly(ax, V, color="C1", lw=1.5, label=r"$\Phi_0$")
        _poly(ax, D.inflation * V, color="C4", lw=1, label=rf"$\lambda\Phi_0$, $\lambda = {D.inflation:g}$")
        _box(ax, D.lower[0], D.upper[0], color="k", lw=0.8, ls="-.", label="[e_0]")
        _box(ax, D.lower[-1], D.upper[-1], color="C3", lw=1.5, label=rf"$[s_{{k^*}}]$, $k^* = {D.k_star}$")
        ax.set(xlabel="e1", ylabel="e2")
        ax.grid(alpha=0.3)
    r = 1.3 * np.abs(V).max(axis=0)
    axes[0, 1].set(xlim=(-r[0], r[0]), ylim=(-r[1], r[1]), title="zoom on Φ_0")
    axes[0, 0].set(title="Thesis Ex 4.5.1: error sets (Fig 4.6)")
    axes[0, 0].legend(fontsize=7, loc="upper right")
    yield "thesis_ex4_5_1_sets.png", fig, \
        "Thesis Fig 4.6: the polyhedral invariant set Φ_0 between the ellipsoids Ψ̄⁺(μ) and Ψ̄(μ) (μ = 2) of the " \
        "H∞ design (LMI 4.13), the inflated set λΦ_0 ⊇ [e_0] (λ = 11) and the box of the error at k*, the first k " \
        "where the shrunken set is within ε = 0.01 of the mRPI set (thesis.md §6.3)."


def fig_thesis_nonlinear(out: Path):
    job, trajs = _run("thesis_ex4_6_3.toml")
    yield "thesis_nonlinear_bounds.png", plotting.plot_bounds(
        trajs, x_true=job.x_true, title="Thesis §4.6.3: nonlinear interval observer (Figs 4.12-4.13)"), \
        "Thesis Figs 4.12–4.13 (§4.6.3, thesis.md §6.6): bounds of x1 and x2 from the nonlinear interval observer " \
        "(h = δ(sin(0.5k·x2), sin(0.3k)), [h] = [−0.8, 0.8]², gain from LMI 4.46) with the true state (δ = 0.8, " \
        "x_0 = (2, −2), observer start (−2, 2))."


THESIS_FIGURES = [fig_thesis_ex1_5, fig_thesis_ch2, fig_thesis_ch3, fig_thesis_naive, fig_thesis_ex4_5_1,
                  fig_thesis_nonlinear]
FIGURES = [fig_bc14, fig_me17, fig_le13, fig_me19, fig_wrapping] + THESIS_FIGURES
BEGIN, END = "<!-- gallery:begin -->", "<!-- gallery:end -->"


def _index_entries(text: str) -> dict:
    """``name -> caption`` of the entries between the index markers."""
    body = text.split(BEGIN, 1)[1].split(END, 1)[0] if BEGIN in text else ""
    out = {}
    for block in body.split("### ")[1:]:
        lines = block.strip("\n").split("\n")
        name = lines[0].strip()
        caption = "\n".join(line for line in lines[1:] if line.strip() and not line.startswith("![")).strip()
        out[name] = caption
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--out", default=str(Path(__file__).resolve().parent))
    p.add_argument("--only", default=None,
                   help="regenerate only the figure functions whose name contains this (e.g. thesis); the other "
                        "entries of the index are kept as they are")
    a = p.parse_args(argv)
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    entries = []
    chosen = [f for f in FIGURES if a.only is None or a.only in f.__name__]
    for make in track(chosen, label="gallery"):
        for name, fig, caption in make(out):
            plotting.save_png(fig, out / name, dpi=DPI)
            entries.append((name, caption))
            print(f"{out / name}  ({(out / name).stat().st_size // 1024} kB)")
    index = out / "README.md"
    text = index.read_text() if index.exists() else f"# Gallery\n\n{BEGIN}\n{END}\n"
    if a.only is not None:  # keep the entries not regenerated, in the order of FIGURES
        old = _index_entries(text)
        new = dict(entries)
        names = [n for n in old if n not in new] + [n for n, _ in entries]
        entries = [(n, new.get(n, old.get(n))) for n in names]
        entries.sort(key=lambda e: (e[0].startswith("thesis_"), 0))
    body = "\n".join(f"### {name}\n\n![{name}]({name})\n\n{caption}\n" for name, caption in entries)
    head, rest = text.split(BEGIN, 1)
    tail = rest.split(END, 1)[1]
    index.write_text(f"{head}{BEGIN}\n{body}\n{END}{tail}")
    total = sum((out / n).stat().st_size for n, _ in entries if (out / n).exists())
    print(f"{len(entries)} figures, {total / 1e6:.2f} MB; index {index}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
