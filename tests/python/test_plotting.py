"""setbound.plotting: figures render without a display (Agg), have the requested pixel size and
are not blank; the 2-D geometry (exact zonotope polygons, projected ellipses, strips) is right."""
import itertools

import numpy as np
import pytest

matplotlib = pytest.importorskip("matplotlib")

from matplotlib.image import imread  # noqa: E402

from setbound import Ellipsoid, LinearSystem, Trajectory, Zonotope, ellipsoidal, plotting, zonotopic  # noqa: E402
from setbound.simulation import simulate  # noqa: E402


@pytest.fixture(scope="module")
def runs():
    system = LinearSystem([[1, 0, 0.2], [0, 0.8, 1], [0, 0, 1]], C=[[1, 0, 2], [0, -1, 1]],
                          E=[[0.1, 0, 0, 0, 0], [0, 0.05, 0, 0, 0], [0, 0, 0.05, 0, 0]],
                          F=[[0, 0, 0, 0.15, 0], [0, 0, 0, 0, 0.15]])
    x0 = Ellipsoid(np.eye(3), np.zeros(3), np.sqrt(2))
    sim = simulate(system, x0, 12, disturbance="vertex", rng=5)
    design = ellipsoidal.design_offline(system, beta=0.5)
    trajs = {
        "offline": ellipsoidal.OfflineEstimator(design, x0).run(sim.y),
        "segment_min": zonotopic.SegmentMinEstimator(system, Zonotope(np.zeros(3), 1.2 * np.eye(3))).run(sim.y),
        "kalman": ellipsoidal.KalmanFilter(system, np.zeros(3), np.eye(3)).run(sim.y),
    }
    return system, sim, trajs


def _panels(fig):
    """The visible data panels (a spare panel holding the legend has its axis switched off)."""
    return [a for a in fig.axes if a.get_visible() and a.axison]


def _legend_texts(fig):
    return [t.get_text() for a in fig.axes if a.get_legend() is not None for t in a.get_legend().get_texts()]


def _check_png(path, figsize, dpi=plotting.DEFAULT_DPI):
    img = imread(path)
    assert img.shape[:2] == (round(figsize[1] * dpi), round(figsize[0] * dpi))
    gray = img[..., :3].mean(axis=2)
    assert gray.std() > 0.02  # something is drawn
    assert (gray < 0.5).mean() > 0.001  # dark pixels: lines, text
    return img


def test_renders_without_a_display_and_without_pyplot(tmp_path):
    """In a fresh interpreter with no display: importing setbound.plotting and saving a figure
    neither needs a GUI backend nor imports pyplot (no global figure state)."""
    import os
    import subprocess
    import sys

    code = (
        "import sys, numpy as np\n"
        "from setbound import Trajectory, plotting\n"
        "t = Trajectory(np.zeros((3, 2)), -np.ones((3, 2)), np.ones((3, 2)), [])\n"
        f"plotting.save_png(plotting.plot_bounds(t), {str(tmp_path / 'x.png')!r})\n"
        "assert 'matplotlib.pyplot' not in sys.modules, 'pyplot was imported'\n"
    )
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY", "MPLBACKEND")}
    r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "x.png").stat().st_size > 1000


@pytest.mark.parametrize("kind", ["bounds", "widths", "relative", "volume", "projections"])
def test_figures_render_with_the_requested_size(runs, tmp_path, kind):
    system, sim, trajs = runs
    if kind == "bounds":
        fig = plotting.plot_bounds(trajs, x_true=sim.x, title="t")
        assert len(_panels(fig)) == 3
        assert _legend_texts(fig)[-1] == "true state"
    elif kind == "widths":
        fig = plotting.plot_widths(trajs)
    elif kind == "relative":
        fig = plotting.plot_widths(trajs, reference="offline", components=[0, 2])
        ax = fig.axes[0]
        ref_line = [ln for ln in ax.get_lines() if ln.get_label() == "offline"][0]
        np.testing.assert_allclose(ref_line.get_ydata(), 1.0)  # the reference divided by itself
    elif kind == "volume":
        fig = plotting.plot_volume(trajs)
        labels = [ln.get_label() for ln in fig.axes[0].get_lines()]
        assert labels == ["offline", "segment_min"]  # the Kalman filter has no sets
    else:
        fig = plotting.plot_projections(trajs, steps=[0, 6, 11], dims=(0, 2), x_true=sim.x, system=system, y=sim.y)
        assert len(_panels(fig)) == 3
    size = tuple(fig.get_size_inches())
    path = plotting.save_png(fig, tmp_path / "sub" / f"{kind}.png")
    _check_png(path, size)
    path2 = plotting.save_png(fig, tmp_path / f"{kind}_hi.png", dpi=50)
    _check_png(path2, size, dpi=50)


def test_inputs_are_checked(runs):
    _, _, trajs = runs
    with pytest.raises(ValueError, match="reference: 'nope'"):
        plotting.plot_widths(trajs, reference="nope")
    with pytest.raises(ValueError, match="steps: step 99"):
        plotting.plot_projections(trajs, steps=[99])
    with pytest.raises(ValueError, match="dims"):
        plotting.plot_projections(trajs, steps=[0], dims=(1, 1))
    with pytest.raises(TypeError, match="trajectories"):
        plotting.plot_bounds(3)
    with pytest.raises(ValueError, match="names: expected 3"):
        plotting.plot_bounds(list(trajs.values()), names=["a"])
    fig = plotting.plot_bounds(list(trajs.values()))  # default names
    assert "estimator 0" in _legend_texts(fig)


def _support_polygon(V, d):
    return np.max(V @ d)


def test_zonotope_polygon_is_exact(rng):
    for m in (1, 2, 3, 7, 15):
        c = rng.normal(size=2)
        G = rng.normal(size=(2, m))
        if m >= 3:
            G[:, 1] = -2.0 * G[:, 0]  # parallel generators, opposite directions
        V = plotting.zonotope_polygon(c, G)
        # support function of a zonotope: h(d) = d·c + Σ |d·g_j|
        for th in np.linspace(0, 2 * np.pi, 97):
            d = np.array([np.cos(th), np.sin(th)])
            assert _support_polygon(V, d) == pytest.approx(d @ c + np.abs(d @ G).sum(), rel=1e-12, abs=1e-12)
        # counter-clockwise convex polygon: every turn is to the left
        E = np.roll(V, -1, axis=0) - V
        cross = E[:, 0] * np.roll(E, -1, axis=0)[:, 1] - E[:, 1] * np.roll(E, -1, axis=0)[:, 0]
        assert np.all(cross >= -1e-12)
        # vertices are points of the zonotope (corners: some sign vector) for small m
        if m <= 7:
            corners = np.array([c + G @ np.array(s) for s in itertools.product([-1, 1], repeat=m)])
            for v in V:
                assert np.min(np.linalg.norm(corners - v, axis=1)) < 1e-9
    # degenerate: no or zero generators
    np.testing.assert_array_equal(plotting.zonotope_polygon([1.0, 2.0], np.zeros((2, 2))), [[1.0, 2.0]])


def test_ellipse_points_are_the_projection(rng):
    M = rng.normal(size=(3, 3))
    P = M @ M.T + 0.5 * np.eye(3)
    c, rho = rng.normal(size=3), 2.5
    pts = plotting.ellipse_points(P, c, rho, dims=(0, 2), n=400)
    Q = rho * np.linalg.inv(P)
    Q2 = Q[np.ix_([0, 2], [0, 2])]
    r = pts - c[[0, 2]]
    # every point is on the boundary of the projected ellipse {p : (p - c)' Q2^-1 (p - c) <= 1}
    np.testing.assert_allclose(np.einsum("ij,jk,ik->i", r, np.linalg.inv(Q2), r), 1.0, rtol=1e-10)
    for th in np.linspace(0, np.pi, 13):
        d3 = np.array([np.cos(th), 0.0, np.sin(th)])
        exact = d3 @ c + np.sqrt(d3 @ Q @ d3)  # support of E(P, c, rho) in direction d3
        got = np.max(pts @ d3[[0, 2]])
        assert exact - 1e-3 * np.sqrt(np.trace(Q2)) <= got <= exact + 1e-12  # polygon inside, close


def test_ellipse_points_rejects_bad_input_by_name():
    # found by the option fuzzer (CI, 2026-11-27): dims=[0, 2] on a 2-state P raised a bare IndexError
    from setbound.errors import InvalidArgumentError

    cases = [((np.eye(2), [0, 0], 1.0, (0, 2)), "dims"),
             ((np.eye(3), [0, 0, 0], 1.0, (1, 1)), "dims"),
             ((np.eye(2), [0, 0, 0], 1.0), "center"),
             ((np.ones(3), [0, 0, 0], 1.0), "P"),
             ((np.zeros((2, 2)), [0, 0], 1.0), "P"),
             (([[np.nan, 0], [0, 1]], [0, 0], 1.0), "finite")]
    for args, word in cases:
        with pytest.raises(InvalidArgumentError, match=word):
            plotting.ellipse_points(*args)


def test_measurement_strips_contain_the_true_state(runs):
    system, sim, _ = runs
    for k in range(len(sim.y)):
        C, lo, hi = plotting.measurement_strips(system, sim.y[k])
        v = C @ sim.x[k]
        assert np.all(lo - 1e-12 <= v) and np.all(v <= hi + 1e-12)
        np.testing.assert_allclose(hi - lo, 2 * np.abs(system.F).sum(axis=1))


def test_clip_strip_polygon():
    square = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]])
    half = plotting._clip(square, 1.0, 0.0, 1.0)  # x <= 1
    assert half[:, 0].max() == pytest.approx(1.0)
    area = 0.5 * abs(np.dot(half[:, 0], np.roll(half[:, 1], -1)) - np.dot(half[:, 1], np.roll(half[:, 0], -1)))
    assert area == pytest.approx(2.0)
    assert len(plotting._clip(square, 1.0, 0.0, -1.0)) == 0


def test_box_only_results_are_drawn_as_boxes():
    t = Trajectory(np.zeros((2, 2)), -np.ones((2, 2)), np.ones((2, 2)), [], guaranteed=False)
    fig = plotting.plot_projections({"box": t}, steps=[1])
    patches = [p for p in fig.axes[0].patches if p.get_label() == "box"]
    xy = patches[0].get_xy()
    assert xy[:, 0].min() == -1 and xy[:, 0].max() == 1 and xy[:, 1].min() == -1 and xy[:, 1].max() == 1
