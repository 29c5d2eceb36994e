"""Zonotopic estimators (papers.md §3, §5).

The estimator structure of papers.md §3.1: exact prediction ``A X ⊕ E B`` (or the
[Le2013] inclusion for an interval ``A``), correction strip by strip with a gain ``λ``,
reduction to at most ``max_generators`` generators. The true state is in the set for any
``λ``; the gain rule only decides the size.

Available now: :class:`SegmentMinEstimator` ([Alamo2005] segment minimisation, §5.1).
"""
from __future__ import annotations

import numpy as np

from ._native import as_f64, check, dptr, ffi, lib
from .errors import DimensionError, InvalidArgumentError
from .sets import Zonotope
from .system import LinearSystem
from .trajectory import Trajectory


class _ZonotopicEstimator:
    _gain: int

    def __init__(self, system: LinearSystem, x0: Zonotope, *, max_generators: int = 20,
                 use_first_measurement: bool = True, strip_order=None):
        if not isinstance(system, LinearSystem):
            raise InvalidArgumentError(f"system: expected a setbound.LinearSystem, got {type(system).__name__}")
        if not isinstance(x0, Zonotope):
            raise InvalidArgumentError(f"x0: expected a setbound.sets.Zonotope, got {type(x0).__name__}")
        if x0.n != system.nx:
            raise DimensionError(f"x0: expected a zonotope of dimension {system.nx}, got {x0.n}")
        self.system = system
        order_ptr = ffi.NULL
        if strip_order is not None:
            order = np.asarray(strip_order)
            if order.shape != (system.ny,) or not np.issubdtype(order.dtype, np.integer):
                raise InvalidArgumentError(f"strip_order: expected {system.ny} integers (a permutation of the outputs)")
            self._order = ffi.new("int[]", [int(i) for i in order])
            order_ptr = self._order
        handle = ffi.new("sb_zonotopic**")
        check(lib.sb_zonotopic_create(system._handle, self._gain, int(max_generators),
                                      1 if use_first_measurement else 0, order_ptr, x0.m,
                                      dptr(x0.center), dptr(x0.generators), handle))
        self._handle = ffi.gc(handle[0], lib.sb_zonotopic_free)
        self._m = ffi.new("int*")

    def _step(self, y, u):
        s = self.system
        y = as_f64(y, "y", shape=(s.ny,))
        if s.nu > 0:
            if u is None:
                raise InvalidArgumentError(f"u: the system has {s.nu} inputs; an input is required")
            u = as_f64(u, "u", shape=(s.nu,))
        elif u is not None and np.size(u) != 0:
            raise DimensionError("u: the system has no input")
        c, lo, hi = np.empty(s.nx), np.empty(s.nx), np.empty(s.nx)
        check(lib.sb_zonotopic_step(self._handle, dptr(y), dptr(u) if s.nu > 0 else ffi.NULL,
                                    dptr(c), dptr(lo), dptr(hi), self._m))
        return c, lo, hi

    def _last_set(self) -> Zonotope:
        m = self._m[0]
        p, H = np.empty(self.system.nx), np.empty((self.system.nx, m))
        cap = ffi.new("int*", m)
        check(lib.sb_zonotopic_last_set(self._handle, cap, dptr(p), dptr(H)))
        return Zonotope(p, H)

    def step(self, y, u=None) -> Zonotope:
        """Uses ``y_k`` (and ``u_k``), returns the set for ``x_k``, predicts ``x_{k+1}``."""
        self._step(y, u)
        return self._last_set()

    def run(self, y, u=None) -> Trajectory:
        """Processes the rows of ``y`` (N × n_y) and ``u`` (N × n_u); row k is about x_k."""
        s = self.system
        y = as_f64(y, "y", shape=(None, s.ny))
        N = y.shape[0]
        if s.nu > 0:
            u = as_f64(u, "u", shape=(N, s.nu))
        centers, lows, highs, sets = np.empty((N, s.nx)), np.empty((N, s.nx)), np.empty((N, s.nx)), []
        for k in range(N):
            centers[k], lows[k], highs[k] = self._step(y[k], u[k] if s.nu > 0 else None)
            sets.append(self._last_set())
        return Trajectory(centers, lows, highs, sets)


class SegmentMinEstimator(_ZonotopicEstimator):
    """[Alamo2005] segment minimisation (papers.md §5.1): per strip,
    ``λ* = H Hᵀ c / (cᵀ H Hᵀ c + φ²)``, the minimiser of the squared generator lengths."""

    _gain = lib.SB_ZONO_GAIN_SEGMENT_MIN
