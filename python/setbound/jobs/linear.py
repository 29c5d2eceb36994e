"""The job-file kinds of the papers: system kinds ``linear`` and ``descriptor``; estimators
``offline``, ``online``, ``scaled``, ``improved``, ``descriptor`` (ellipsoidal), ``segment_min``,
``volume_min``, ``pradius`` (zonotopic), ``czn_a``, ``czn_b`` (constrained zonotopes; CORA's names
``CZN-A``, ``CZN-B`` are in :mod:`setbound.jobs.cora`) and ``kalman`` (registered on import)."""
from __future__ import annotations

import numpy as np

from .._validate import as_int
from ..errors import InvalidArgumentError, SetboundError
from ..system import DescriptorSystem, LinearSystem
from ..zonotopic import MAX_GENERATORS as _API_MAX_GENERATORS
from .registry import (BuiltSystem, boolean, number, one_of, optional_matrix, positive_int, register_estimator,
                       register_system)
from .schema import ConfigError, check_keys, matrix, require

__all__ = ["MAX_GENERATORS"]

#: Largest ``max_generators`` of a zonotopic estimator in a job file: the API's own bound
#: (``setbound.zonotopic.MAX_GENERATORS``, which the C library enforces too), so a value the
#: estimator would refuse is a job-file error (exit 2) at load time, not a failed run.
MAX_GENERATORS = _API_MAX_GENERATORS


# ---------------------------------------------------------------- systems
def _linear_system(tab):
    from ..interval import IntervalMatrix

    A = matrix(require(tab, "A", "system"), "system.A")
    n = A.shape[0]
    if A.shape != (n, n):
        raise ConfigError(f"system.A: must be square, got shape {A.shape}")
    C = matrix(require(tab, "C", "system"), "system.C", shape=(None, n))
    E = matrix(require(tab, "E", "system"), "system.E", shape=(n, None))
    F = matrix(require(tab, "F", "system"), "system.F", shape=(C.shape[0], E.shape[1]))
    B = matrix(tab["B"], "system.B", shape=(n, None)) if "B" in tab else None
    D = matrix(tab["D"], "system.D", shape=(C.shape[0], B.shape[1] if B is not None else None)) \
        if "D" in tab else None
    if D is not None and B is None:
        raise ConfigError("system.D: given without system.B (there is no input)")
    if "A_radius" in tab:
        rad = matrix(tab["A_radius"], "system.A_radius", shape=(n, n))
        if np.any(rad < 0):
            raise ConfigError("system.A_radius: entries must be >= 0")
        A = IntervalMatrix.from_mid_rad(A, rad)
    constant_input = False
    if "omega" in tab:
        E, F, offset = _omega_bounds(tab["omega"], E.shape[1], E, F)
        if np.any(offset[0] != 0) or np.any(offset[1] != 0):
            # ω = c + G ξ with c ≠ 0: E c and F c enter as an input column that is always 1
            constant_input = True
            B = np.hstack([B if B is not None else np.zeros((n, 0)), offset[0][:, None]])
            D = np.hstack([D if D is not None else np.zeros((C.shape[0], B.shape[1] - 1)), offset[1][:, None]])
    try:
        system = LinearSystem(A, C, B=B, D=D, E=E, F=F)
    except SetboundError as exc:
        raise ConfigError(f"system: {exc}") from None
    return BuiltSystem(system, constant_input) if constant_input else system


def _omega_bounds(tab, nw: int, E, F):
    """``[system.omega]``: explicit bounds of ω instead of the unit box — a box (``lower``,
    ``upper``) or a zonotope (``center``, ``generators``, nω × m). With ω = c + G ξ, ξ in the unit
    box, the model becomes ``E G``, ``F G`` and the offsets ``E c``, ``F c``."""
    where = "system.omega"
    check_keys(tab, {"lower", "upper", "center", "generators"}, where)
    if "lower" in tab or "upper" in tab:
        if "center" in tab or "generators" in tab:
            raise ConfigError(f"{where}: give a box (lower, upper) or a zonotope (center, generators), not both")
        lo = matrix(require(tab, "lower", where), f"{where}.lower", ndim=1, shape=(nw,))
        hi = matrix(require(tab, "upper", where), f"{where}.upper", ndim=1, shape=(nw,))
        if np.any(lo > hi):
            k = int(np.flatnonzero(lo > hi)[0])
            raise ConfigError(f"{where}.lower: entry {k} is above {where}.upper")
        c, G = (lo + hi) / 2, np.diag((hi - lo) / 2)
    else:
        c = matrix(require(tab, "center", where), f"{where}.center", ndim=1, shape=(nw,))
        G = matrix(require(tab, "generators", where), f"{where}.generators", shape=(nw, None))
    keep = np.any(G != 0, axis=0)  # drop zero generators (a fixed component of ω)
    G = G[:, keep] if np.any(keep) else np.zeros((nw, 1))
    return E @ G, F @ G, (E @ c, F @ c)


def _descriptor_system(tab):
    A = matrix(require(tab, "A", "system"), "system.A")
    n = A.shape[0]
    E = matrix(require(tab, "E", "system"), "system.E", shape=(n, n))
    C = matrix(require(tab, "C", "system"), "system.C", shape=(None, n))
    D = matrix(require(tab, "D", "system"), "system.D", shape=(n, None))
    F = matrix(require(tab, "F", "system"), "system.F", shape=(C.shape[0], D.shape[1]))
    B = matrix(tab["B"], "system.B", shape=(n, None)) if "B" in tab else None
    try:
        return DescriptorSystem(E, A, C, B=B, D=D, F=F)
    except SetboundError as exc:
        raise ConfigError(f"system: {exc}") from None


# ---------------------------------------------------------------- initial sets per family
def ellipsoidal_initial(initial, n: int):
    """The initial set as an ellipsoid (setbound.sets.as_ellipsoid: a box or a zonotope by the
    ellipsoid through the corners of its hull)."""
    from ..sets import as_ellipsoid

    return as_ellipsoid(initial, "initial")


def zonotopic_initial(initial):
    """The initial set as a zonotope (setbound.sets.as_zonotope: an ellipsoid by its bounding box)."""
    from ..sets import as_zonotope

    return as_zonotope(initial, "initial")


# ---------------------------------------------------------------- estimators
def _build_ellipsoidal(method):
    def build(job, o: dict):
        from .. import ellipsoidal as ell

        design, _ = job.cached_design(("ellipsoidal", o["normalization"], o["beta"]),
                                      lambda: ell.design_offline(job.system, normalization=o["normalization"],
                                                                 beta=o["beta"]))
        x0 = ellipsoidal_initial(job.initial, job.system.nx)
        kw = {"on_inconsistency": str(o.get("on_inconsistency", "flag"))}
        if method == "offline":
            est = ell.OfflineEstimator(design, x0, **kw)
        elif method == "online":
            est = ell.OnlineEstimator(design, x0, **kw)
        elif method == "scaled":
            est = ell.OnlineEstimator(design, x0, scaling=True, **kw)
        elif method == "improved":
            est = ell.ImprovedEstimator(design, x0, o["option"], feedback=o["feedback"], predictor=o["predictor"],
                                        **kw)
        else:
            est = ell.DescriptorEstimator(design, x0)
        return est, design
    return build


def _build_kalman(job, o: dict):
    from .. import ellipsoidal as ell

    x0 = ellipsoidal_initial(job.initial, job.system.nx)
    n, nw = job.system.nx, getattr(job.system, "nw", None)
    try:
        cov0 = np.linalg.inv(x0.P) * x0.rho / 9.0 if o["cov0"] is None else matrix(o["cov0"], "cov0", shape=(n, n))
        W = None if o["omega_cov"] is None else matrix(o["omega_cov"], "omega_cov", shape=(nw, nw))
    except ConfigError as exc:  # the shapes are known only here: a library error, named like the option
        raise InvalidArgumentError(str(exc)) from None
    return ell.KalmanFilter(job.system, x0.center, cov0, W, nsigma=float(o["nsigma"])), None


def _build_zonotopic(method):
    def build(job, o: dict):
        from .. import zonotopic as zono

        x0 = zonotopic_initial(job.initial)
        kw = dict(max_generators=int(o["max_generators"]), use_first_measurement=bool(o["use_first_measurement"]),
                  reduction=str(o["reduction"]), on_inconsistency=str(o["on_inconsistency"]))
        if method == "segment_min":
            return zono.SegmentMinEstimator(job.system, x0, **kw), None
        if method == "volume_min":
            return zono.VolumeMinEstimator(job.system, x0, **kw), None
        design, _ = job.cached_design(("pradius", int(o["approach"])),
                                      lambda: zono.design_pradius(job.system, approach=int(o["approach"])))
        return zono.PRadiusEstimator(design, x0, **kw), design
    return build


def _build_czn(correction):
    def build(job, o: dict):
        from ..constrained_zonotopic import ConstrainedZonotopicEstimator

        return ConstrainedZonotopicEstimator(
            job.system, job.initial, correction=correction, reduction=str(o["reduction"]),
            technique=str(o["technique"]), order=float(o["order"]), max_constraints=o["max_constraints"],
            max_generators=o["max_generators"], use_first_measurement=bool(o["use_first_measurement"]),
            on_inconsistency=str(o["on_inconsistency"])), None
    return build


def _optional_limit(v, key):
    return None if v is None else as_int(v, key, lo=0, hi=_CZN_MAX_SIZE)


def _rho_inf_volume(design, trajectory) -> float:
    return float(design.volume_inf)


def _beta(v, key):
    return None if v is None else number(lo=0, hi=1, lo_open=True, hi_open=True)(v, key)


_ELL = {"normalization": "logdet", "beta": None}
# on_inconsistency: what an impossible reading does (setbound.measurement); "reset" restarts from
# the job's initial set. Not for the descriptor estimator (it needs every output).
_POLICY = {"on_inconsistency": "flag"}
_POLICY_CHECKS = {"on_inconsistency": one_of("flag", "raise", "reset")}
_ZONO = {"max_generators": 20, "use_first_measurement": True, "reduction": "combastel", "on_inconsistency": "flag"}
_ELL_CHECKS = {"normalization": one_of("logdet", "ball", "paper_trace"), "beta": _beta}
_ZONO_CHECKS = {"max_generators": positive_int(MAX_GENERATORS), "use_first_measurement": boolean,
                "reduction": one_of("combastel", "girard", "pca"), "on_inconsistency": one_of("flag", "raise", "reset")}

_CZN_MAX_SIZE = 100000  # SB_CZN_MAX_SIZE of setbound.h
_CZN = {"reduction": "limits", "technique": "girard", "order": 20.0, "max_constraints": None, "max_generators": None,
        "use_first_measurement": True, "on_inconsistency": "flag"}
_CZN_CHECKS = {"reduction": one_of("limits", "cora", "none"), "technique": one_of("girard", "pca"),
               "order": number(lo=1), "max_constraints": _optional_limit, "max_generators": _optional_limit,
               "use_first_measurement": boolean, "on_inconsistency": one_of("flag", "raise", "reset")}

register_system("linear", {"A", "A_radius", "B", "C", "D", "E", "F", "omega"}, _linear_system, LinearSystem,
                description="x+ = A x + B u + E w, y = C x + D u + F w (A may be an interval matrix; "
                            "w in the unit box or in the [system.omega] box/zonotope)")
register_system("descriptor", {"E", "A", "B", "C", "D", "F"}, _descriptor_system, DescriptorSystem,
                description="E x+ = A x + B u + D w, y = C x + F w (Methods › Ellipsoidal estimation › Descriptor systems)")
register_estimator("offline", "ellipsoidal", {**_ELL, **_POLICY}, _build_ellipsoidal("offline"),
                   steady_volume=_rho_inf_volume, checks={**_ELL_CHECKS, **_POLICY_CHECKS},
                   description="[BenChabane2014] offline gain (Methods › Ellipsoidal estimation › Offline design)")
register_estimator("online", "ellipsoidal", {**_ELL, **_POLICY}, _build_ellipsoidal("online"),
                   checks={**_ELL_CHECKS, **_POLICY_CHECKS},
                   description="[BenChabane2014] online LMI per step (Methods › Ellipsoidal estimation › Online vertex LMI)")
register_estimator("scaled", "ellipsoidal", {**_ELL, **_POLICY}, _build_ellipsoidal("scaled"),
                   checks={**_ELL_CHECKS, **_POLICY_CHECKS},
                   description="[BenChabane2014] online with scaling (Methods › Ellipsoidal estimation › Online with scaling)")
register_estimator("improved", "ellipsoidal",
                   {**_ELL, **_POLICY, "option": "det_normalized", "feedback": "fixed_shape", "predictor": "online"},
                   _build_ellipsoidal("improved"),
                   checks={**_ELL_CHECKS, **_POLICY_CHECKS, "option": one_of("det_normalized", "fixed_shape", "ball_normalized"),
                           "feedback": one_of("fixed_shape", "outer_bound", "none"),
                           "predictor": one_of("online", "scaled", "offline")},
                   description="[Merhy2017] improved measurement correction (Methods › Ellipsoidal estimation › Improved correction)")
register_estimator("descriptor", "ellipsoidal", _ELL, _build_ellipsoidal("descriptor"), systems=("descriptor",),
                   steady_volume=_rho_inf_volume, checks=_ELL_CHECKS,
                   description="[Merhy2019] descriptor systems (Methods › Ellipsoidal estimation › Descriptor systems)")
register_estimator("kalman", "kalman", {"omega_cov": None, "cov0": None, "nsigma": 3.0}, _build_kalman,
                   guaranteed=False,
                   checks={"nsigma": number(lo=0, lo_open=True), "omega_cov": optional_matrix,
                           "cov0": optional_matrix},
                   description="Kalman filter contrast, mean ± nsigma·σ (Methods › Ellipsoidal estimation › Kalman filter)")
register_estimator("segment_min", "zonotopic", _ZONO, _build_zonotopic("segment_min"), checks=_ZONO_CHECKS,
                   description="[Alamo2005] segment minimisation (Methods › Zonotopic estimation › Segment minimisation)")
register_estimator("volume_min", "zonotopic", _ZONO, _build_zonotopic("volume_min"), checks=_ZONO_CHECKS,
                   description="[Alamo2005] volume minimisation (Methods › Zonotopic estimation › Volume minimisation)")
register_estimator("pradius", "zonotopic", {**_ZONO, "approach": 1}, _build_zonotopic("pradius"),
                   checks={**_ZONO_CHECKS, "approach": one_of(1, 2)},
                   description="[Le2013] offline P-radius gains (Methods › Zonotopic estimation › P-radius designs)")
# CORA's names CZN-A / CZN-B (with `convention`) are registered with the other CORA names by
# setbound.jobs.cora; their options are these.
for _name, _corr, _what in (("czn_a", "exact_output", "exact intersection with the output set"),
                            ("czn_b", "wang_strips", "output strips in Wang et al.'s gain representation")):
    register_estimator(_name, "constrained_zonotopic", _CZN, _build_czn(_corr), checks=_CZN_CHECKS,
                       description=f"[Scott2016] constrained zonotopes, {_what} (CORA's "
                                   f"{_name.upper().replace('_', '-')}; Methods › Constrained zonotopes)")
