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

``radius[k]`` is the level ``ρ_k`` of an ellipsoidal set ``E(P, c_k, ρ_k)`` (Methods › Sets, intervals and LMI tools › Ellipsoids:
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
    """The sets of a run: row ``k`` of ``center``, ``lower``, ``upper`` and ``sets[k]`` describe ``x_k``.

    See the module docstring for the time indexing of filters and predictors.

    Parameters
    ----------
    center, lower, upper : ndarray, shape (N, n_x)
        Centre and interval-hull bounds of each step's set.
    sets : list, optional
        The set of each step (Ellipsoid, Zonotope or Box), when kept.
    guaranteed : bool, optional
        False for the Kalman baseline only.
    status, margin : ndarray, shape (N, n_y), optional
        What each step did with each reading (:mod:`setbound.measurement`) and its margin; None for
        families that do not screen their measurements.
    resets : ndarray of bool, shape (N,), optional
        Steps where the estimator restarted from its reset set.
    t : ndarray, shape (N,), optional
        Time of each row (None: the step index).
    filter : bool, optional
        Whether row ``k`` used ``y_k`` (a filter) or only ``y_0 … y_{k−1}`` (a predictor); None when
        unknown.

    Examples
    --------
    Every estimator's ``run`` returns one:

    >>> sys = setbound.LinearSystem(A=[[0.9]], C=[[1.0]], E=[[0.1, 0.0]], F=[[0.0, 0.1]])
    >>> traj = setbound.zonotopic.SegmentMinEstimator(sys, setbound.Box([-1], [1])).run(np.zeros((4, 1)))
    >>> len(traj), traj.width.shape, bool(traj.contains(np.zeros((4, 1))).all())
    (4, (4, 1), True)
    """

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
        """Per step: is the true state inside the interval bounds (widened by ``tol``)?

        Cheap; see :meth:`contains` for the sets themselves.

        Parameters
        ----------
        x : ndarray, shape (N, n_x)
            True states.
        tol : float, optional
            Widening of the bounds (finite, >= 0).

        Returns
        -------
        ndarray of bool, shape (N,)
        """
        tol = as_float(tol, "tol", lo=0.0)
        x = np.asarray(x, dtype=float)
        return np.all((self.lower - tol <= x) & (x <= self.upper + tol), axis=1)

    def contains(self, x: np.ndarray, tol: float = 0.0) -> np.ndarray:
        """Per step: is the true state inside the set of its row and inside the bounds (widened by ``tol``)?

        ``sets[k]`` is an ellipsoid, a zonotope or a box, tested with its own membership test and
        rounding tolerance. Without sets (the Kalman baseline): the bounds only.

        Parameters
        ----------
        x : ndarray, shape (N, n_x)
            True states.
        tol : float, optional
            Widening of the bounds (finite, >= 0).

        Returns
        -------
        ndarray of bool, shape (N,)
        """
        inside = self.in_bounds(x, tol)
        if not self.sets:
            return inside
        x = np.asarray(x, dtype=float)
        for k, S in enumerate(self.sets):
            if inside[k] and tol == 0.0:
                inside[k] = bool(S.contains(x[k]))
        return inside

    def to_pandas(self, names=None):
        """A ``pandas.DataFrame`` indexed by time ``t`` (:attr:`times`).

        Per state, the columns ``<name>_lower``, ``<name>_center``, ``<name>_upper``; the step ``k``,
        and ``flagged`` when the estimator tested its readings. ``attrs``: ``guaranteed``. Needs pandas
        (``pip install setbound[interop]``).

        Parameters
        ----------
        names : sequence of str, optional
            State names (default ``x0 … x{n−1}``).

        Returns
        -------
        pandas.DataFrame
        """
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
        """The bounds of each state over time (:func:`setbound.plotting.plot_bounds`), against ``t``.

        Parameters
        ----------
        x_true : ndarray, shape (N, n_x), optional
            True states, drawn when given.
        name : str, optional
            Legend label of the estimator (the legend also says whether it is guaranteed).
        components : sequence of int, optional
            State components drawn (default: all).
        title : str, optional
            Figure title.
        figsize : (float, float), optional
            Figure size in inches.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ._validate import as_str
        from .plotting import plot_bounds

        name = as_str(name, "name")
        label = f"{name} ({'guaranteed' if self.guaranteed else 'not guaranteed'})"
        return plot_bounds({label: self}, x_true=x_true, t=self.t, components=components, title=title,
                           figsize=figsize)

    def to_dataframe(self, t=None):
        """A ``pandas.DataFrame`` with one row per step (index ``k``).

        Columns ``center{i}``, ``lower{i}``, ``upper{i}`` (i = 0 … n_x−1), then ``volume`` and
        ``radius`` when the trajectory has sets. Needs pandas (``pip install setbound[interop]``).

        Parameters
        ----------
        t : array_like, shape (N,), optional
            Adds a column ``t``.

        Returns
        -------
        pandas.DataFrame
        """
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
