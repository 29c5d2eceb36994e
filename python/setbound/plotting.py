"""Plots of estimation results (matplotlib), as in the papers' figures; used by the command line.

Every function takes trajectories — a mapping ``{name: Trajectory}``, a list of
:class:`~setbound.Trajectory` with ``names=[...]``, or a single Trajectory — and returns a
:class:`matplotlib.figure.Figure`. Figures are made with the object API (no ``pyplot``, no
global state, no display needed: safe under the Agg backend, in scripts, tests and
notebooks). :func:`save_png` writes one to a PNG of exactly ``figsize × dpi`` pixels.

* :func:`plot_bounds` — the bounds tube of each state component, with the true state;
* :func:`plot_widths` — bound widths over time, or relative to a reference method
  (``reference="offline"``: width / width of the reference, as [BenChabane2014] Figs 4–6
  and [Le2013] plot them);
* :func:`plot_volume` — the volume of the sets over time (log scale);
* :func:`plot_projections` — 2-D projections of the sets at chosen steps (ellipses of
  :class:`~setbound.Ellipsoid`, the exact polygons of projected :class:`~setbound.Zonotope` and
  :class:`~setbound.sets.ConstrainedZonotope`, boxes for box-only results such as the Kalman filter's ``mean ± 3σ``), with the true state
  and the measurement strips of that step.

Time axis: ``t`` (one value per row; by default the first trajectory's own ``t``) or the step
index ``k``. Row ``k`` of a trajectory is about ``x_k`` for every estimator (see
:mod:`setbound.trajectory`). States are named 0-based, ``x_0 … x_{n−1}``, as in Python and the
command line's files.
"""
from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

try:  # the object API only: no pyplot, so importing never needs a display
    from matplotlib.figure import Figure
    from matplotlib.patches import Polygon as _MplPolygon
except ImportError as _exc:  # pragma: no cover - matplotlib is a dependency of the package
    raise ImportError("setbound.plotting needs matplotlib (pip install matplotlib)") from _exc

from ._validate import as_bool, as_float, as_int, as_str, check_memory
from .errors import InvalidArgumentError
from .interval import Box
from .measurement import USED
from .sets import ConstrainedZonotope, Ellipsoid, Zonotope

#: Largest figure side in inches and largest ``dpi`` (a figure is drawn as a w·dpi × h·dpi raster).
MAX_FIGSIZE = 200.0
MAX_DPI = 2400
#: Largest number of points of :func:`ellipse_points`.
MAX_POINTS = 1_000_000


def _figsize(figsize):
    """``None`` or a pair (w, h) of finite numbers in (0, MAX_FIGSIZE] inches."""
    if figsize is None:
        return None
    try:
        w, h = figsize
    except (TypeError, ValueError):
        raise InvalidArgumentError(f"figsize: expected a pair (width, height) in inches, got {figsize!r}") from None
    return (as_float(w, "figsize[0]", lo=0.0, hi=MAX_FIGSIZE, lo_open=True),
            as_float(h, "figsize[1]", lo=0.0, hi=MAX_FIGSIZE, lo_open=True))


def _title(title):
    return None if title is None else as_str(title, "title")


def _index_pair(dims, name: str = "dims") -> tuple[int, int]:
    try:
        a, b = dims
    except (TypeError, ValueError):
        raise InvalidArgumentError(f"{name}: expected a pair of state indices, got {dims!r}") from None
    return as_int(a, f"{name}[0]", lo=0), as_int(b, f"{name}[1]", lo=0)

__all__ = ["plot_bounds", "plot_widths", "plot_volume", "plot_projections", "save_png", "zonotope_polygon",
           "ellipse_points", "measurement_strips", "DEFAULT_DPI"]

#: Resolution used by :func:`save_png` (pixels per inch).
DEFAULT_DPI = 100

_STYLES = ["-", "--", "-.", ":"]


def _items(trajectories, names=None) -> list[tuple[str, object]]:
    """Normalises the accepted inputs to a list of (name, Trajectory)."""
    from .trajectory import Trajectory

    if isinstance(trajectories, Trajectory):
        trajectories = [trajectories]
    if isinstance(trajectories, Mapping):
        items = list(trajectories.items())
    elif isinstance(trajectories, Sequence):
        trajectories = list(trajectories)
        if names is None:
            names = [f"estimator {i}" for i in range(len(trajectories))]
        if len(names) != len(trajectories):
            raise ValueError(f"names: expected {len(trajectories)} names, got {len(names)}")
        items = list(zip(names, trajectories))
    else:
        raise TypeError(f"trajectories: expected a Trajectory, a list of them or a mapping name -> Trajectory, "
                        f"got {type(trajectories).__name__}")
    if not items:
        raise ValueError("trajectories: nothing to plot")
    for name, t in items:
        if not isinstance(t, Trajectory):
            raise TypeError(f"trajectories[{name!r}]: expected a setbound.Trajectory, got {type(t).__name__}")
    return [(str(n), t) for n, t in items]


def _time(t, N: int) -> tuple[np.ndarray, str]:
    if t is None:
        return np.arange(N, dtype=float), "k"
    t = np.asarray(t, dtype=float).ravel()
    if t.shape[0] < N:
        raise ValueError(f"t: expected at least {N} time values, got {t.shape[0]}")
    return t[:N], "t"


def _colors(n: int):
    import matplotlib

    cycle = matplotlib.rcParams["axes.prop_cycle"].by_key().get("color", ["C0"])
    return [cycle[i % len(cycle)] for i in range(n)]


def _grid(n: int) -> tuple[int, int]:
    cols = 1 if n == 1 else (2 if n <= 4 else 3)
    return math.ceil(n / cols), cols


def _new_figure(rows: int, cols: int, cell=(5.0, 3.0), figsize=None):
    # A fixed layout (margins in inches): much cheaper than constrained/tight layout at draw time.
    w, h = figsize or (cell[0] * cols, cell[1] * rows)
    fig = Figure(figsize=(w, h))
    axes = fig.subplots(rows, cols, squeeze=False)
    fig.subplots_adjust(left=0.85 / w, right=1 - 0.2 / w, bottom=0.55 / h, top=1 - 0.55 / h,
                        wspace=1.0 * cols / max(w - 1.05, 1e-3), hspace=0.95 * rows / max(h - 1.1, 1e-3))
    return fig, axes


def _finish_grid(fig, axes, used: int, rows: int, cols: int, fontsize=8) -> None:
    """Hides the unused panels; the legend goes into the first unused panel when there is one
    (it then covers no data), else into the first panel."""
    spare = [axes[j // cols][j % cols] for j in range(used, rows * cols)]
    handles, labels = axes[0][0].get_legend_handles_labels()
    for ax in spare:
        ax.set_visible(False)
    if spare:
        spare[0].set_visible(True)
        spare[0].axis("off")
        spare[0].legend(handles, labels, loc="center", fontsize=fontsize + 1, frameon=False)
    else:
        axes[0][0].legend(fontsize=fontsize, loc="best")


def _quiet_minor_labels(ax) -> None:
    """No labels on the minor ticks of a log axis (they clutter short ranges)."""
    from matplotlib.ticker import NullFormatter

    ax.yaxis.set_minor_formatter(NullFormatter())


def _components(components, n: int) -> list[int]:
    if components is None:
        return list(range(n))
    if isinstance(components, (str, bytes)) or not hasattr(components, "__iter__"):
        raise InvalidArgumentError(f"components: expected a list of state indices, got {components!r}")
    comps = [as_int(i, f"components[{k}]", lo=None) for k, i in enumerate(components)]
    for i in comps:
        if not 0 <= i < n:
            raise ValueError(f"components: index {i} out of range for n_x = {n}")
    return comps


# ---------------------------------------------------------------- time series
def plot_bounds(trajectories, names=None, *, x_true=None, t=None, components=None, title=None, figsize=None):
    """One panel per state component: the bounds ``[lower, upper]`` of every trajectory (a filled
    tube for the first, lines for the others) and the true state when given (``x_true``,
    N × n_x). Non-guaranteed results (Kalman) are drawn dotted and marked ``(not guaranteed)``.

    Parameters
    ----------
    trajectories : Trajectory, sequence or dict of Trajectory
        The results (a dict maps names to trajectories).
    names : sequence of str, optional
        Legend names (default: the dict keys, or ``estimate 0 …``).
    x_true : ndarray, shape (N, n_x), optional
        True states.
    t : array_like, shape (N,), optional
        Time axis (default: the trajectories' ``times``).
    components : sequence of int, optional
        Components drawn (default: all).
    title : str, optional
        Figure title.
    figsize : (float, float), optional
        Size in inches.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> traj = setbound.Trajectory(np.zeros((3, 1)), -np.ones((3, 1)), np.ones((3, 1)))
    >>> fig = setbound.plotting.plot_bounds({"box": traj})
    >>> len(fig.axes)
    1
    """
    title, figsize = _title(title), _figsize(figsize)
    items = _items(trajectories, names)
    N, n = items[0][1].center.shape
    comps = _components(components, n)
    tt, tlabel = _time(t if t is not None else getattr(items[0][1], "t", None), N)
    rows, cols = _grid(len(comps))
    fig, axes = _new_figure(rows, cols, figsize=figsize)
    colors = _colors(len(items))
    for j, i in enumerate(comps):
        ax = axes[j // cols][j % cols]
        for m, (name, tr) in enumerate(items):
            label = name + ("" if tr.guaranteed else " (not guaranteed)")
            k = min(len(tr), N)
            style = ":" if not tr.guaranteed else _STYLES[m % len(_STYLES)]
            if m == 0 and tr.guaranteed:
                ax.fill_between(tt[:k], tr.lower[:k, i], tr.upper[:k, i], color=colors[m], alpha=0.25, lw=0,
                                label=label)
                ax.plot(tt[:k], tr.lower[:k, i], color=colors[m], lw=0.8)
                ax.plot(tt[:k], tr.upper[:k, i], color=colors[m], lw=0.8)
            else:
                ax.plot(tt[:k], tr.lower[:k, i], color=colors[m], ls=style, lw=1.1, label=label)
                ax.plot(tt[:k], tr.upper[:k, i], color=colors[m], ls=style, lw=1.1)
        if x_true is not None:
            x = np.asarray(x_true, dtype=float)
            ax.plot(tt[:x.shape[0]], x[:N, i], "k.-", ms=2.5, lw=0.7, label="true state")
        ax.set_xlabel(tlabel)
        ax.set_ylabel(f"$x_{{{i}}}$")
        ax.set_title(f"bounds of $x_{{{i}}}$", fontsize=10)
        ax.grid(alpha=0.3)
    _finish_grid(fig, axes, len(comps), rows, cols)
    if title:
        fig.suptitle(title)
    return fig


def plot_widths(trajectories, names=None, *, reference=None, t=None, components=None, log=None, title=None,
                figsize=None):
    """Bound widths ``upper − lower`` over time, one panel per component. With ``reference`` (the
    name of one of the trajectories) each width is divided by the reference's width at the same
    step (a value below 1 is tighter than the reference); the reference itself is then a line at 1.
    ``log`` defaults to a log scale for absolute widths.

    Parameters
    ----------
    trajectories : Trajectory, sequence or dict of Trajectory
        The results (a dict maps names to trajectories).
    names : sequence of str, optional
        Legend names (default: the dict keys, or ``estimate 0 …``).
    reference : str, optional
        Name of the reference trajectory.
    t : array_like, shape (N,), optional
        Time axis.
    components : sequence of int, optional
        Components drawn.
    log : bool, optional
        Log scale (default: for absolute widths).
    title : str, optional
        Figure title.
    figsize : (float, float), optional
        Size in inches.

    Returns
    -------
    matplotlib.figure.Figure

    Examples
    --------
    >>> traj = setbound.Trajectory(np.zeros((3, 1)), -np.ones((3, 1)), np.ones((3, 1)))
    >>> len(setbound.plotting.plot_widths({'box': traj}).axes)
    1
    """
    title, figsize = _title(title), _figsize(figsize)
    log = None if log is None else as_bool(log, "log")
    items = _items(trajectories, names)
    N, n = items[0][1].center.shape
    comps = _components(components, n)
    tt, tlabel = _time(t if t is not None else getattr(items[0][1], "t", None), N)
    ref = None
    if reference is not None:
        d = dict(items)
        if reference not in d:
            raise ValueError(f"reference: {reference!r} is not one of {', '.join(d)}")
        ref = d[reference].width
    rows, cols = _grid(len(comps))
    fig, axes = _new_figure(rows, cols, figsize=figsize)
    colors = _colors(len(items))
    for j, i in enumerate(comps):
        ax = axes[j // cols][j % cols]
        for m, (name, tr) in enumerate(items):
            k = min(len(tr), N, N if ref is None else ref.shape[0])
            w = tr.width[:k, i]
            if ref is not None:
                with np.errstate(divide="ignore", invalid="ignore"):
                    w = w / ref[:k, i]
            ax.plot(tt[:k], w, color=colors[m], ls=":" if not tr.guaranteed else _STYLES[m % len(_STYLES)],
                    lw=1.2, label=name + ("" if tr.guaranteed else " (not guaranteed)"))
        if ref is not None:
            ax.axhline(1.0, color="0.4", lw=0.6)
            ax.set_ylabel(f"width of $x_{{{i}}}$ / {reference}")
        else:
            ax.set_ylabel(f"width of $x_{{{i}}}$")
            if log is None or log:
                ax.set_yscale("log")
                _quiet_minor_labels(ax)
        if log and ref is not None:
            ax.set_yscale("log")
            _quiet_minor_labels(ax)
        ax.set_xlabel(tlabel)
        ax.grid(alpha=0.3, which="both")
    _finish_grid(fig, axes, len(comps), rows, cols)
    fig.suptitle(title or ("bound widths relative to " + reference if reference else "bound widths"),
                 fontsize=11)
    return fig


def plot_volume(trajectories, names=None, *, t=None, log=True, title=None, figsize=(6.0, 3.6)):
    """The volume of each trajectory's sets over time (trajectories without sets, such as the
    Kalman filter's, are skipped; NaN volumes leave gaps).

    Parameters
    ----------
    trajectories : Trajectory, sequence or dict of Trajectory
        The results (a dict maps names to trajectories).
    names : sequence of str, optional
        Legend names (default: the dict keys, or ``estimate 0 …``).
    t : array_like, shape (N,), optional
        Time axis.
    log : bool, optional
        Log scale.
    title : str, optional
        Figure title.
    figsize : (float, float), optional
        Size in inches.

    Returns
    -------
    matplotlib.figure.Figure
    """
    title, figsize = _title(title), _figsize(figsize)
    log = as_bool(log, "log")
    items = _items(trajectories, names)
    N = items[0][1].center.shape[0]
    tt, tlabel = _time(t if t is not None else getattr(items[0][1], "t", None), N)
    fig, axes = _new_figure(1, 1, figsize=figsize)
    ax = axes[0][0]
    colors = _colors(len(items))
    drawn = 0
    for m, (name, tr) in enumerate(items):
        if not tr.sets:
            continue
        v = tr.volume
        k = min(len(v), N)
        ax.plot(tt[:k], v[:k], color=colors[m], ls=_STYLES[m % len(_STYLES)], lw=1.2, label=name)
        drawn += 1
    finite = [v for _, tr in items if tr.sets for v in tr.volume if np.isfinite(v) and v > 0]
    if log and finite and max(finite) > 20 * min(finite):  # a log axis only when it helps
        ax.set_yscale("log")
        _quiet_minor_labels(ax)
    ax.set_xlabel(tlabel)
    ax.set_ylabel("volume")
    ax.grid(alpha=0.3, which="both")
    if drawn:
        ax.legend(fontsize=8)
    else:
        ax.text(0.5, 0.5, "no set-valued result", ha="center", va="center", transform=ax.transAxes)
    ax.set_title(title or "volume of the sets", fontsize=11)
    return fig


def plot_margins(trajectories, names=None, *, fault_start=None, title=None, figsize=None):
    """Fault detection (:mod:`setbound.fault`): per estimator that tests its readings, the largest
    margin of each step in noise bounds (> 0: a reading no state of the model can produce), the
    flagged steps, the alarm (the first flagged step) and the fault's start when given."""
    from .fault import Detection

    title = _title(title)
    items = [(n, tr) for n, tr in _items(trajectories, names) if tr.status is not None]
    if not items:
        raise InvalidArgumentError("trajectories: none of them tested its readings (no status)")
    fig, axes = _new_figure(len(items), 1, cell=(7.0, 2.4), figsize=_figsize(figsize))
    for row, (name, tr) in enumerate(items):
        Detection.from_trajectory(tr).plot(axes[row][0], fault_start=fault_start, title=name)
    if title:
        fig.suptitle(title, fontsize=11)
    return fig


# ---------------------------------------------------------------- 2-D projections
def zonotope_polygon(center, generators) -> np.ndarray:
    """The exact vertices (counter-clockwise, K × 2) of the 2-D zonotope ``center ⊕ G B^m``
    (``G`` 2 × m): generators turned into the upper half-plane and sorted by angle, the
    boundary is the walk ``c − Σg, +2g₁, +2g₂, …, −2g₁, −2g₂, …``.

    Parameters
    ----------
    center : array_like, shape (2,)
        Centre.
    generators : array_like, shape (2, m)
        Generators.

    Returns
    -------
    ndarray, shape (K, 2)

    Examples
    --------
    >>> setbound.plotting.zonotope_polygon([0, 0], [[1, 0], [0, 1]]).tolist()
    [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]]
    """
    c = np.asarray(center, dtype=float).ravel()
    G = np.asarray(generators, dtype=float).reshape(2, -1)
    if c.shape != (2,):
        raise ValueError(f"center: expected 2 components, got {c.shape[0]}")
    keep = np.linalg.norm(G, axis=0) > 0
    G = G[:, keep]
    if G.shape[1] == 0:
        return c[None, :].copy()
    flip = (G[1] < 0) | ((G[1] == 0) & (G[0] < 0))
    G = np.where(flip, -G, G)
    G = G[:, np.argsort(np.arctan2(G[1], G[0]), kind="stable")]
    start = c - G.sum(axis=1)
    steps = np.concatenate([2 * G, -2 * G], axis=1).T
    return start + np.vstack([np.zeros(2), np.cumsum(steps, axis=0)[:-1]])


def ellipse_points(P, center, rho, dims=(0, 1), n: int = 200) -> np.ndarray:
    """Boundary points (n × 2) of the projection onto ``dims`` of ``E(P, c, ρ) = {x : (x−c)ᵀP(x−c) ≤ ρ}``:
    the ellipse with shape matrix ``ρ (P⁻¹)[dims, dims]``. ``rho`` a finite number >= 0, ``n`` an
    integer in [2, ``MAX_POINTS``], ``dims`` a pair of indices.

    Parameters
    ----------
    P : array_like, shape (n, n)
        Shape.
    center : array_like, shape (n,)
        Centre.
    rho : float
        Level.
    dims : (int, int), optional
        Projected coordinates.
    n : int, optional
        Number of points.

    Returns
    -------
    ndarray, shape (n, 2)

    Examples
    --------
    >>> pts = setbound.plotting.ellipse_points(np.eye(2), [0.0, 0.0], 4.0, n=8)
    >>> bool(np.allclose(np.hypot(pts[:, 0], pts[:, 1]), 2.0))
    True
    """
    rho = as_float(rho, "rho", lo=0.0)
    n = as_int(n, "n", lo=2, hi=MAX_POINTS)
    dims = list(_index_pair(dims))
    try:
        P = np.asarray(P, dtype=float)
        center = np.asarray(center, dtype=float).ravel()
    except (TypeError, ValueError):
        raise InvalidArgumentError("P and center: expected arrays of numbers") from None
    if P.ndim != 2 or P.shape[0] != P.shape[1] or P.shape[0] < 2:
        raise InvalidArgumentError(f"P: expected a square matrix of size >= 2, got shape {P.shape}")
    dim = P.shape[0]
    if center.shape != (dim,):
        raise InvalidArgumentError(f"center: expected {dim} components (the size of P), got {center.shape[0]}")
    if not (np.all(np.isfinite(P)) and np.all(np.isfinite(center))):
        raise InvalidArgumentError("P and center: expected finite numbers (NaN or infinity found)")
    if dims[0] == dims[1] or max(dims) >= dim:
        raise InvalidArgumentError(f"dims: expected two distinct state indices below {dim}, got {tuple(dims)}")
    try:
        Pinv = np.linalg.inv(0.5 * (P + P.T))
    except np.linalg.LinAlgError:
        raise InvalidArgumentError("P: singular (an ellipsoid's shape must be positive definite)") from None
    Q = rho * Pinv[np.ix_(dims, dims)]
    Q = 0.5 * (Q + Q.T)
    w, V = np.linalg.eigh(Q)
    L = V @ np.diag(np.sqrt(np.maximum(w, 0.0)))
    th = np.linspace(0.0, 2.0 * np.pi, n)
    return center[dims] + (L @ np.vstack([np.cos(th), np.sin(th)])).T


def _set_outline(s, dims, lo=None, hi=None) -> np.ndarray | None:
    dims = list(dims)
    if isinstance(s, Ellipsoid):
        return ellipse_points(s.P, s.center, s.rho, dims)
    if isinstance(s, Zonotope):
        return zonotope_polygon(np.asarray(s.center)[dims], np.asarray(s.generators)[dims, :])
    if isinstance(s, ConstrainedZonotope):  # the exact polygon of the projection (LP support points)
        V = s.projection(*dims)
        return V if len(V) >= 3 else None
    if isinstance(s, Box):
        lo, hi = np.asarray(s.lo, float), np.asarray(s.hi, float)
    if lo is None:
        return None
    a, b = dims
    return np.array([[lo[a], lo[b]], [hi[a], lo[b]], [hi[a], hi[b]], [lo[a], hi[b]]])


def measurement_strips(system, y, u=None):
    """The strips ``{x : |c_iᵀx + d_iᵀu − y_i| ≤ φ_i}`` of one measurement ``y`` (``φ_i = Σ_j |F_ij|``,
    the output noise bound of ω in the unit box), as ``(C, lower, upper)``: ``lower ≤ C x ≤ upper``.

    Parameters
    ----------
    system : LinearSystem
        The model.
    y : array_like, shape (n_y,)
        One measurement.
    u : array_like, shape (n_u,), optional
        Input.

    Returns
    -------
    C, lower, upper : ndarray

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[1.0, 0.0], [0.0, 1.0]], C=[[1.0, 0.0]], E=[[0.0], [0.0]], F=[[0.5]])
    >>> C, lo, hi = setbound.plotting.measurement_strips(sys, [2.0])
    >>> lo.tolist(), hi.tolist()
    ([1.5], [2.5])
    """
    C = np.asarray(system.C, dtype=float)
    F = np.asarray(system.F, dtype=float)
    y = np.asarray(y, dtype=float).ravel()
    off = np.zeros(C.shape[0])
    D = getattr(system, "D", None)
    if u is not None and D is not None and getattr(system, "nu", 0) > 0 and np.shape(D) == (C.shape[0], system.nu):
        off = np.asarray(D, float) @ np.asarray(u, float).ravel()
    phi = np.abs(F).sum(axis=1)
    return C, y - off - phi, y - off + phi


def plot_projections(trajectories, names=None, *, steps, dims=(0, 1), x_true=None, system=None, y=None, u=None,
                     title=None, figsize=None):
    """2-D projections onto state components ``dims`` of the sets at the chosen ``steps`` (one
    panel per step): ellipses, exact zonotope polygons, boxes (from ``lower``/``upper`` when a
    trajectory has no sets). With ``system`` and ``y`` the measurement strips of ``y_k`` are
    drawn (for n_x > 2, their section by the plane through the true state ``x_k`` when
    ``x_true`` is given, else through the first set's centre) when a set of the panel used them:
    only filters' sets of ``x_k`` did (``Trajectory.filter``; a predictor's set of ``x_k`` used
    ``y_0 … y_{k−1}``), and only the outputs they used (not a missing or impossible reading); the
    legend names the sets that used them. With ``x_true`` the true state ``x_k`` is marked.

    Parameters
    ----------
    trajectories : Trajectory, sequence or dict of Trajectory
        The results (a dict maps names to trajectories).
    names : sequence of str, optional
        Legend names (default: the dict keys, or ``estimate 0 …``).
    steps : sequence of int
        The steps drawn (one panel each).
    dims : (int, int), optional
        Projected state components.
    x_true : ndarray, shape (N, n_x), optional
        True states.
    system : LinearSystem, optional
        For the measurement strips.
    y : ndarray, shape (N, n_y), optional
        Measurements (with ``system``).
    u : ndarray, shape (N, n_u), optional
        Inputs.
    title : str, optional
        Figure title.
    figsize : (float, float), optional
        Size in inches.

    Returns
    -------
    matplotlib.figure.Figure
    """
    title, figsize = _title(title), _figsize(figsize)
    dims = _index_pair(dims)
    if isinstance(steps, (str, bytes)) or not hasattr(steps, "__iter__"):
        raise InvalidArgumentError(f"steps: expected a list of step indices, got {steps!r}")
    steps = [as_int(k, f"steps[{j}]", lo=None) for j, k in enumerate(steps)]
    items = _items(trajectories, names)
    N, n = items[0][1].center.shape
    if len(set(dims)) != 2 or not all(0 <= d < n for d in dims):
        raise ValueError(f"dims: expected two distinct state indices below {n}, got {dims}")
    for k in steps:
        if not 0 <= k < N:
            raise ValueError(f"steps: step {k} out of range 0..{N - 1}")
    rows, cols = _grid(len(steps))
    fig, axes = _new_figure(rows, cols, cell=(4.2, 3.8), figsize=figsize)
    colors = _colors(len(items))
    for j, k in enumerate(steps):
        ax = axes[j // cols][j % cols]
        pts_all = []
        for m, (name, tr) in enumerate(items):
            s = tr.sets[k] if tr.sets and k < len(tr.sets) else None
            outline = _set_outline(s, dims, tr.lower[k], tr.upper[k]) if s is not None else \
                _set_outline(None, dims, tr.lower[k], tr.upper[k])
            if outline is None:
                continue
            pts_all.append(outline)
            ls = ":" if not tr.guaranteed else _STYLES[m % len(_STYLES)]
            if m == 0 and tr.guaranteed:
                ax.add_patch(_MplPolygon(outline, closed=True, fill=True, alpha=0.2, facecolor=colors[m],
                                         edgecolor="none"))
            ax.add_patch(_MplPolygon(outline, closed=True, fill=False, edgecolor=colors[m], ls=ls, lw=1.3,
                                     label=name))
        if x_true is not None:
            xk = np.asarray(x_true, float)[k]
            ax.plot(xk[dims[0]], xk[dims[1]], "k*", ms=9, label="true state", zorder=5)
            pts_all.append(xk[list(dims)][None, :])
        pts = np.vstack(pts_all) if pts_all else np.zeros((1, 2))
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        pad = 0.15 * np.maximum(hi - lo, 1e-9)
        xl, yl = (lo[0] - pad[0], hi[0] + pad[0]), (lo[1] - pad[1], hi[1] + pad[1])
        users = [(name, tr) for name, tr in items if getattr(tr, "filter", None)]
        if system is not None and y is not None and users:
            yk = np.asarray(y, float)[k]
            used = np.isfinite(yk)
            for _, tr in users:  # an output some filter used at step k (not missing, not impossible)
                if tr.status is not None:
                    used &= np.any([t.status[k] == USED for _, t in users if t.status is not None], axis=0)
                    break
            uk = None if u is None else np.asarray(u, float)[k]
            C, slo, shi = measurement_strips(system, np.where(np.isfinite(yk), yk, 0.0), uk)
            ref = np.asarray(x_true, float)[k] if x_true is not None else items[0][1].center[k]
            others = [i for i in range(n) if i not in dims]
            label = "strips of y_k (used by " + ", ".join(nm for nm, _ in users) + ")"
            for i in np.flatnonzero(used):
                a, b = C[i, dims[0]], C[i, dims[1]]
                rest = float(C[i, others] @ ref[others]) if others else 0.0
                _draw_strip(ax, a, b, slo[i] - rest, shi[i] - rest, xl, yl, label=label)
                label = None
        ax.set_xlim(*xl)
        ax.set_ylim(*yl)
        ax.set_xlabel(f"$x_{{{dims[0]}}}$")
        ax.set_ylabel(f"$x_{{{dims[1]}}}$")
        ax.set_title(f"k = {k}", fontsize=10)
        ax.grid(alpha=0.3)
    _finish_grid(fig, axes, len(steps), rows, cols, fontsize=7)
    if title:
        fig.suptitle(title, fontsize=11)
    return fig


def _draw_strip(ax, a, b, lo, hi, xl, yl, label=None):
    """Shades {(p, q) : lo ≤ a p + b q ≤ hi} inside the window xl × yl."""
    if a == 0 and b == 0:
        return
    corners = np.array([[xl[0], yl[0]], [xl[1], yl[0]], [xl[1], yl[1]], [xl[0], yl[1]]])
    poly = corners
    for sign, bound in ((1.0, hi), (-1.0, -lo)):  # clip by sign*(a p + b q) <= bound
        poly = _clip(poly, sign * a, sign * b, bound)
        if len(poly) == 0:
            return
    ax.add_patch(_MplPolygon(poly, closed=True, facecolor="0.5", alpha=0.15, edgecolor="0.45", lw=0.6, ls="--",
                             label=label))


def _clip(poly: np.ndarray, a: float, b: float, c: float) -> np.ndarray:
    """Sutherland–Hodgman: the part of the convex polygon where a p + b q ≤ c."""
    out = []
    n = len(poly)
    for i in range(n):
        P, Q = poly[i], poly[(i + 1) % n]
        fp, fq = a * P[0] + b * P[1] - c, a * Q[0] + b * Q[1] - c
        if fp <= 0:
            out.append(P)
        if (fp < 0 < fq) or (fq < 0 < fp):
            out.append(P + (Q - P) * (fp / (fp - fq)))
    return np.array(out)


# ---------------------------------------------------------------- output
def save_png(fig, path, dpi: int = DEFAULT_DPI) -> Path:
    """Writes ``fig`` as a PNG of ``figsize × dpi`` pixels (parent directories are created);
    returns the path. ``dpi``: an integer in [1, ``MAX_DPI``]; the raster (4 bytes a pixel) must
    fit in half the machine's memory.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    path : str or Path
        Output file.
    dpi : int, optional
        Resolution.

    Returns
    -------
    Path

    Examples
    --------
    >>> traj = setbound.Trajectory(np.zeros((3, 1)), -np.ones((3, 1)), np.ones((3, 1)))
    >>> setbound.plotting.save_png(traj.plot(), "out/bounds.png", dpi=50).name
    'bounds.png'
    """
    dpi = as_int(dpi, "dpi", lo=1, hi=MAX_DPI)
    w, h = fig.get_size_inches()
    check_memory("dpi", dpi, 4.0 * w * h * dpi * dpi)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=dpi, format="png")
    return path
