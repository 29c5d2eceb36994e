"""Job files (the TOML jobs of ``setbound check/run/compare``): the public names of
:mod:`setbound.jobs`, kept here for the code, tests and documents that import
``setbound.config`` (see :mod:`setbound.jobs` for the format, the registry and the layout of
the package). This module only re-exports; it imports nothing else, so it closes no circle.
"""
from __future__ import annotations

from .jobs import (ESTIMATORS, METHODS, SYSTEMS, BuiltSystem, ConfigError, EstimatorKind, EstimatorSpec, Job, PlotSpec,
                   Result, SystemKind, compile_expression, eval_expression, from_dict, load, register_estimator,
                   register_system, run, run_estimator, run_trajectory, system_kind_of)

__all__ = ["ConfigError", "BuiltSystem", "SystemKind", "EstimatorKind", "SYSTEMS", "ESTIMATORS", "METHODS",
           "register_system", "register_estimator", "system_kind_of", "EstimatorSpec", "PlotSpec", "Job", "Result",
           "load", "from_dict", "run", "run_estimator", "run_trajectory", "compile_expression", "eval_expression"]
