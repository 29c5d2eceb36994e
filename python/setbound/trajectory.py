"""The result of ``estimator.run(...)``, common to every estimator family.

Time indexing (the same for all estimators): measurements ``y[k]`` and inputs ``u[k]`` are
rows ``k = 0 … N-1``; row ``k`` of ``center``, ``lower`` and ``upper`` and ``sets[k]``
describe the state ``x_k``. Filters (the zonotopic family, the improved ellipsoidal
correction) have used ``y_0 … y_k`` for row ``k``; one-step predictors (the ellipsoidal
family of [BenChabane2014]) have used ``y_0 … y_{k-1}``.

``t[k]`` is the time of row ``k``: ``k`` steps, or ``t0 + k·dt`` with the system's sampling time
``dt``, the ``t=`` given to ``run`` or the time of the measurement source (a python-control
``TimeResponseData``, or a job's ``[simulation.time]``). The state names are 0-based everywhere
(``x0 … x{n−1}``: Python, the command line, the plots and ``to_pandas``).

``radius[k]`` is the level ``ρ_k`` of an ellipsoidal set ``E(P, c_k, ρ_k)`` (papers.md §0.1:
a level, not a squared radius) and NaN for other set types. ``guaranteed`` is False only for
the Kalman filter baseline, whose box is ``mean ± 3σ``.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ._validate import as_float
from .measurement import INCONSISTENT
from .errors import SetboundError


@dataclass
class Trajectory:
    """Row ``k`` of ``center``, ``lower``, ``upper`` (N × n_x) and ``sets[k]`` describe ``x_k``;
    see the module docstring. ``guaranteed`` is False for the Kalman baseline only."""

    center: np.ndarray  # (N, n_x)
    lower: np.ndarray  # (N, n_x)
    upper: np.ndarray  # (N, n_x)
    sets: list[Any] = field(default_factory=list)
    _volume: np.ndarray | None = field(default=None, repr=False)
    _radius: np.ndarray | None = field(default=None, repr=False)
    guaranteed: bool = True
    #: Per step and output (N × n_y): what the step did with the reading (setbound.measurement:
    #: USED, MISSING, INCONSISTENT, UNUSED) and its margin; None for families that do not
    #: screen their measurements yet.
    status: np.ndarray | None = None
    margin: np.ndarray | None = None
    #: Per step: the estimator restarted from its reset set (on_inconsistency="reset").
    resets: np.ndarray | None = None
    #: Time of each row, (N,) (see the module docstring); None: not set (then ``k``).
    t: np.ndarray | None = None
    #: Whether row k used y_k (a filter: zonotopic, improved, descriptor, Kalman) or only
    #: y_0 … y_{k−1} (a predictor: offline / online / scaled ellipsoidal, the thesis observers);
    #: None when unknown.
    filter: bool | None = None

    @property
    def k(self) -> np.ndarray:
        """Step index of each row, (N,)."""
        return np.arange(len(self))

    @property
    def times(self) -> np.ndarray:
        """``t`` when set, else the step index (as floats), (N,)."""
        return np.asarray(self.t, dtype=float) if self.t is not None else self.k.astype(float)

    @property
    def flagged(self) -> np.ndarray:
        """Per step: some reading was impossible (outside the predicted output set), (N,)."""
        if self.status is None:
            return np.zeros(len(self), dtype=bool)
        return np.any(self.status == INCONSISTENT, axis=1)

    def __len__(self) -> int:
        return self.center.shape[0]

    @property
    def width(self) -> np.ndarray:
        """Interval-hull widths, (N, n_x)."""
        return self.upper - self.lower

    @property
    def radius(self) -> np.ndarray:
        """Level ρ_k of each ellipsoidal set (NaN for other set types), (N,)."""
        if self._radius is None:
            self._radius = np.array([float(getattr(s, "rho", np.nan)) for s in self.sets]) if self.sets \
                else np.full(len(self), np.nan)
        return self._radius

    @property
    def volume(self) -> np.ndarray:
        """Volume of each set (NaN where the exact volume is too expensive to compute)."""
        if self._volume is None:
            vols = []
            for s in self.sets:
                try:
                    vols.append(float(s.volume))
                except SetboundError:
                    vols.append(float("nan"))
            self._volume = np.array(vols)
        return self._volume

    def in_bounds(self, x: np.ndarray, tol: float = 0.0) -> np.ndarray:
        """Per step: is the true state row x[k] inside the interval bounds ``lower[k] … upper[k]``
        (widened by ``tol``, a finite number >= 0)? Cheap; see :meth:`contains` for the set."""
        tol = as_float(tol, "tol", lo=0.0)
        x = np.asarray(x, dtype=float)
        return np.all((self.lower - tol <= x) & (x <= self.upper + tol), axis=1)

    def contains(self, x: np.ndarray, tol: float = 0.0) -> np.ndarray:
        """Per step: is the true state row x[k] inside the set of row k (``sets[k]``: an ellipsoid,
        a zonotope or a box; their own membership test with its rounding tolerance) and inside
        the bounds (widened by ``tol``)? Without sets (the Kalman baseline): the bounds only."""
        inside = self.in_bounds(x, tol)
        if not self.sets:
            return inside
        x = np.asarray(x, dtype=float)
        for k, S in enumerate(self.sets):
            if inside[k] and tol == 0.0:
                inside[k] = bool(S.contains(x[k]))
        return inside

    def to_pandas(self, names=None):
        """A ``pandas.DataFrame`` indexed by time ``t`` (:attr:`times`) with, per state, the columns
        ``<name>_lower``, ``<name>_center``, ``<name>_upper`` (names ``x0 … x{n−1}`` unless given),
        the step ``k``, and ``flagged`` when the estimator tested its readings. ``attrs``:
        ``guaranteed``. Needs pandas (``pip install setbound[interop]``)."""
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("Trajectory.to_pandas needs pandas, which is not installed: "
                              "pip install pandas (or setbound[interop])") from None
        N, n = self.center.shape
        names = [f"x{i}" for i in range(n)] if names is None else [str(v) for v in names]
        if len(names) != n:
            raise ValueError(f"names: expected {n} state names, got {len(names)}")
        cols = {"k": self.k}
        for i, nm in enumerate(names):
            cols[f"{nm}_lower"], cols[f"{nm}_center"], cols[f"{nm}_upper"] = (self.lower[:, i], self.center[:, i],
                                                                            self.upper[:, i])
        if self.status is not None:
            cols["flagged"] = self.flagged
        df = pd.DataFrame(cols, index=pd.Index(self.times, name="t"))
        df.attrs["guaranteed"] = bool(self.guaranteed)
        return df

    def plot(self, *, x_true=None, name: str = "estimate", components=None, title=None, figsize=None):
        """The bounds of each state over time (:func:`setbound.plotting.plot_bounds`; the legend says
        whether the method is guaranteed), against ``t``; returns the matplotlib Figure."""
        from ._validate import as_str
        from .plotting import plot_bounds

        name = as_str(name, "name")
        label = f"{name} ({'guaranteed' if self.guaranteed else 'not guaranteed'})"
        return plot_bounds({label: self}, x_true=x_true, t=self.t, components=components, title=title,
                           figsize=figsize)

    def to_dataframe(self, t=None):
        """A ``pandas.DataFrame`` with one row per step (index ``k``; a column ``t`` when ``t`` is
        given) and the columns ``center{i}``, ``lower{i}``, ``upper{i}`` (i = 0 … n_x−1), then
        ``volume`` and ``radius`` when the trajectory has sets. Needs pandas (``pip install
        setbound[interop]``)."""
        try:
            import pandas as pd
        except ImportError:
            raise ImportError("Trajectory.to_dataframe needs pandas, which is not installed: "
                              "pip install pandas (or setbound[interop])") from None
        N, n = self.center.shape
        cols = {}
        if t is not None:
            t = np.asarray(t, dtype=float).ravel()
            if t.shape != (N,):
                raise ValueError(f"t: expected {N} time values, got {t.shape[0]}")
            cols["t"] = t
        for name, arr in (("center", self.center), ("lower", self.lower), ("upper", self.upper)):
            for i in range(n):
                cols[f"{name}{i}"] = arr[:, i]
        if self.sets:
            cols["volume"] = self.volume
            cols["radius"] = self.radius
        df = pd.DataFrame(cols, index=pd.RangeIndex(N, name="k"))
        df.attrs["guaranteed"] = bool(self.guaranteed)
        return df
