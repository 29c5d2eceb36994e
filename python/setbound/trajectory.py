"""The result of ``estimator.run(...)``, common to every estimator family.

Time indexing (the same for all estimators): measurements ``y[k]`` and inputs ``u[k]`` are
rows ``k = 0 … N-1``; row ``k`` of ``center``, ``lower`` and ``upper`` and ``sets[k]``
describe the state ``x_k``. Filters (the zonotopic family, the improved ellipsoidal
correction) have used ``y_0 … y_k`` for row ``k``; one-step predictors (the ellipsoidal
family of [BenChabane2014]) have used ``y_0 … y_{k-1}``.

``radius[k]`` is the level ``ρ_k`` of an ellipsoidal set ``E(P, c_k, ρ_k)`` (papers.md §0.1:
a level, not a squared radius) and NaN for other set types. ``guaranteed`` is False only for
the Kalman filter baseline, whose box is ``mean ± 3σ``.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .errors import SetboundError


@dataclass
class Trajectory:
    center: np.ndarray  # (N, n_x)
    lower: np.ndarray  # (N, n_x)
    upper: np.ndarray  # (N, n_x)
    sets: list[Any] = field(default_factory=list)
    _volume: np.ndarray | None = field(default=None, repr=False)
    _radius: np.ndarray | None = field(default=None, repr=False)
    guaranteed: bool = True

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

    def contains(self, x: np.ndarray, tol: float = 0.0) -> np.ndarray:
        """Per step: is the true state row x[k] inside the interval hull of row k?"""
        x = np.asarray(x, dtype=float)
        return np.all((self.lower - tol <= x) & (x <= self.upper + tol), axis=1)
