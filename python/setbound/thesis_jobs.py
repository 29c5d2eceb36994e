"""The thesis kinds of job files (``thesis``, ``lpv``, ``nonlinear`` systems and the thesis
estimators): the public names of :mod:`setbound.jobs.thesis`, kept here for the code and tests
that import ``setbound.thesis_jobs``. Re-exports only (no import circle)."""
from __future__ import annotations

from .jobs.thesis import LpvSystem, NonlinearSystem, ThesisSystem, polytopic_weights_lp

__all__ = ["ThesisSystem", "LpvSystem", "NonlinearSystem", "polytopic_weights_lp"]
