"""setbound — guaranteed (set-membership) state estimation.

A thin numpy layer over the setbound C library (loaded with cffi): sets (intervals, boxes,
interval matrices, ellipsoids, zonotopes, strips), the bundled LMI solver and the
estimators. Every error raised is a :class:`setbound.SetboundError` subclass carrying the
library's message.
"""
from __future__ import annotations

from . import errors, lmi, measurement
from ._native import ABI_VERSION, version
from .errors import *  # noqa: F401,F403  (the exception classes are part of the API)
from .interval import Box, Interval, IntervalMatrix
from .sets import Ellipsoid, Strip, Zonotope
from .system import DescriptorSystem, LinearSystem, is_detectable
from .plant import Plant
from .trajectory import Trajectory
from . import zonotopic  # noqa: E402  (needs the classes above)
from .zonotopic import exact_hull  # noqa: E402
from . import ellipsoidal  # noqa: E402
from . import hinf  # noqa: E402  (thesis Ch. 1-3 H-infinity observers)
from .hinf import LpvPlant  # noqa: E402
from . import inclusion, invariant  # noqa: E402  (thesis Chapter 1)
from .invariant import Polytope  # noqa: E402
from . import interval_observers  # noqa: E402
from . import parallelotope, point  # noqa: E402  (CORA's ROPO; the Rauch-Tung-Striebel smoother)
from .interval_observers import (  # noqa: E402
    IntervalInvariantObserver,
    IntervalLuenbergerObserver,
    NonlinearIntervalObserver,
    interval_error_limit,
    interval_error_recursion,
    offline_error_sequence,
)

__version__ = version()

__all__ = [
    "ABI_VERSION",
    "Box",
    "DescriptorSystem",
    "Ellipsoid",
    "Interval",
    "IntervalMatrix",
    "LinearSystem",
    "LpvPlant",
    "Polytope",
    "Plant",
    "Strip",
    "Trajectory",
    "Zonotope",
    "is_detectable",
    "__version__",
    "ellipsoidal",
    "interval_observers",
    "IntervalInvariantObserver",
    "IntervalLuenbergerObserver",
    "NonlinearIntervalObserver",
    "interval_error_limit",
    "interval_error_recursion",
    "offline_error_sequence",
    "errors",
    "exact_hull",
    "hinf",
    "inclusion",
    "invariant",
    "lmi",
    "measurement",
    "parallelotope",
    "point",
    "zonotopic",
    "version",
] + list(errors.__all__)
