"""Job files: jobs described by TOML files (read with ``tomllib``): a system, an initial set, a data
source (a simulation of the true system, or measured data) and one or more estimators.

::

    title = "EX-BC14"                       # optional
    [system]                                # kind = "linear" (default) or "descriptor"
    A = [[1, 0, 0.2], [0, 0.8, 1], [0, 0, 1]]
    C = [[1, 0, 2], [0, -1, 1]]
    E = [[0.1, 0, 0, 0, 0], [0, 0.05, 0, 0, 0], [0, 0, 0.05, 0, 0]]
    F = [[0, 0, 0, 0.15, 0], [0, 0, 0, 0, 0.15]]
    # B, D: inputs; A_radius: entrywise radius of an interval A (A is then its midpoint).
    # omega = {lower = [...], upper = [...]} or {center = [...], generators = [[...]]}: explicit
    # bounds of ω instead of the unit box (converted: ω = c + G ξ, ξ in the unit box; an offset
    # c becomes an input column that is always 1, appended after the user's inputs).
    # kind = "descriptor": E x⁺ = A x + B u + D w, y = C x + F w (the letters of Methods › Ellipsoidal estimation › Descriptor systems).

    [initial]                               # the initial set: an ellipsoid E(P, center, rho) …
    center = [0, 0, 0]
    P = "identity"                          # or a matrix
    rho = 1.4142135623730951
    # … or a zonotope (center, generators) or a box (lower, upper)

    [simulation]                            # or [data] file = "y.csv" / "run.npz"
    horizon = 50
    seed = 1
    disturbance = "uniform"                 # uniform | vertex | gaussian | zero
    inputs = ["0.5*sin(t) + 1", "-2*cos(t)"]  # expressions of t (or an N × n_u array)
    time = {start = 0.0, stop = 15.707963267948966}   # t_k = linspace(start, stop, horizon)

    [[estimator]]
    method = "offline"                      # a registered estimator kind (ESTIMATORS)
    normalization = "logdet"                # per-method options
    name = "offline-logdet"                 # optional, unique; default: the method

    [plots]                                 # optional: what `setbound run` draws
    reference = "offline"                   # widths relative to this estimator (default: the first guaranteed one)
    steps = [0, 10, 49]                     # steps of the 2-D projections (default: first, middle, last)
    dims = [0, 1]                           # state components of the projections
    enabled = true                          # false: no PNG files

Registry
--------
The estimator kinds and system kinds a job file may name live in two registries, so a new
method or model is added in one place:

* ``register_system(kind, keys, build, cls)`` — ``[system] kind = "..."``: ``keys`` are the
  allowed keys (besides ``kind``), ``build(table)`` validates the table and returns the system
  object (raise :class:`ConfigError` naming ``system.<key>``), ``cls`` its Python type (used to
  decide which estimators apply). Registered: ``linear`` (:class:`~setbound.LinearSystem`) and
  ``descriptor`` (:class:`~setbound.DescriptorSystem`).
* ``register_estimator(method, family, options, build, systems=("linear",), ...)`` — ``method``
  is the name used in ``[[estimator]] method = "..."``, ``options`` the allowed options with
  their defaults, ``systems`` the system kinds it applies to, and ``build(job, options)`` returns
  ``(estimator, design)``: an object with ``run(y, u) -> Trajectory`` and the offline design
  (or ``None``). ``steady_volume(design, trajectory)`` optionally gives the steady-state volume
  of the method (the ellipsoidal designs' ``volume_inf``); otherwise the summary reports the
  final volume. Registered: ``offline``, ``online``, ``scaled``, ``improved``, ``descriptor``
  (ellipsoidal), ``segment_min``, ``volume_min``, ``pradius`` (zonotopic), ``kalman``.

The thesis kinds (system kinds ``thesis``, ``lpv``, ``nonlinear``; estimators
``interval_luenberger``, ``interval_invariant``, ``nonlinear_interval``, ``ellipsoidal_sm``,
``lpv_sm``, ``invariant_tube``) live in :mod:`setbound.jobs.thesis`; CORA's observer names
(``method = "FRad-B"``, ``convention``, ``gain``: every name of :func:`setbound.cora.algorithms`) in
:mod:`setbound.jobs.cora`. A system object may bring its own simulation (``simulate_job``, plus extra
``[simulation]`` keys in ``simulation_keys``) and per-step data for its estimators
(``job.extra``, e.g. the LPV scheduling signal); :func:`compile_expression` evaluates the
whitelisted expressions with extra variables (``k``, the state ``x1 … xn``, a parameter ``p``).

Every error is a :class:`ConfigError` (a ``ValueError``) whose message starts with the key
(``system.A``, ``estimator[2].option``…) and says what is wrong. Values are not coerced
(``horizon = "200"``, ``"0.1"`` or ``true`` inside a matrix are refused), unknown keys are
refused with the closest valid name, expressions are bounded (:mod:`setbound.jobs.expressions`),
data files are read strictly (:mod:`setbound.jobs.data`), and a horizon whose run would not fit
in memory is refused with the estimate.

Modules
-------
The package is layered so that every import points one way (``tests/python/test_config.py``
checks the import graph)::

    schema       ConfigError, key/matrix/scalar checks (scalars via setbound._validate)
    expressions  the bounded expression evaluator            -> schema
    registry     SYSTEMS, ESTIMATORS, register_*             -> schema
    model        Job, EstimatorSpec, PlotSpec, Result        (no package imports)
    data         CSV / NPZ data files                        -> schema
    loader       load, from_dict                             -> schema, expressions, registry, model, data
    runner       run, run_estimator, run_trajectory          -> registry, model
    linear       the papers' kinds (registered on import)    -> schema, registry
    thesis       the thesis kinds (registered on import)     -> schema, expressions, registry
    cora         CORA's names of setbound.cora (on import)   -> schema, registry, linear
    study        the [study] grid: Study, load_study         -> schema, registry, loader

:mod:`setbound.config` and :mod:`setbound.thesis_jobs` are façades re-exporting these names.
"""
from __future__ import annotations

from .expressions import compile_expression, eval_expression
from .loader import estimator_spec, from_dict, load
from .model import EstimatorSpec, Job, PlotSpec, Result
from .registry import (ESTIMATORS, METHODS, SYSTEMS, BuiltSystem, EstimatorKind, SystemKind, register_estimator,
                       register_system, system_kind_of)
from .runner import run, run_estimator, run_trajectory
from .schema import ConfigError

# the registered kinds: importing them registers them (the papers' first, then the thesis')
from . import linear  # noqa: E402,F401  isort: skip
from . import thesis  # noqa: E402,F401  isort: skip
from . import cora  # noqa: E402,F401  isort: skip  (CORA's names: setbound.cora's registry)

cora.register_cora_names()

__all__ = ["ConfigError", "BuiltSystem", "SystemKind", "EstimatorKind", "SYSTEMS", "ESTIMATORS", "METHODS",
           "register_system", "register_estimator", "system_kind_of", "EstimatorSpec", "PlotSpec", "Job", "Result",
           "load", "from_dict", "estimator_spec", "run", "run_estimator", "run_trajectory", "compile_expression", "eval_expression"]
