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


FIGURES = [fig_bc14, fig_me17, fig_le13, fig_me19, fig_wrapping]
BEGIN, END = "<!-- gallery:begin -->", "<!-- gallery:end -->"


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--out", default=str(Path(__file__).resolve().parent))
    a = p.parse_args(argv)
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    entries = []
    for make in track(FIGURES, label="gallery"):
        for name, fig, caption in make(out):
            plotting.save_png(fig, out / name, dpi=DPI)
            entries.append((name, caption))
            print(f"{out / name}  ({(out / name).stat().st_size // 1024} kB)")
    index = out / "README.md"
    text = index.read_text() if index.exists() else f"# Gallery\n\n{BEGIN}\n{END}\n"
    body = "\n".join(f"### {name}\n\n![{name}]({name})\n\n{caption}\n" for name, caption in entries)
    head, rest = text.split(BEGIN, 1)
    tail = rest.split(END, 1)[1]
    index.write_text(f"{head}{BEGIN}\n{body}\n{END}{tail}")
    total = sum((out / n).stat().st_size for n, _ in entries)
    print(f"{len(entries)} figures, {total / 1e6:.2f} MB; index {index}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
