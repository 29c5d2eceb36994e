"""CORA's observer names in job files: ``method = "FRad-B"`` runs the observer CORA calls so.

Every name of :func:`setbound.cora.algorithms` is registered as an estimator kind when
:mod:`setbound.jobs` is imported (:func:`register_cora_names`), so a name a family adds to the
CORA registry is usable in job files and in ``setbound compare --estimators`` without a change
here. The run goes through :func:`setbound.cora.prepare`, the same runner as
:func:`setbound.cora.observe`: the job's system, initial set and data become the CORA-format model
the runner expects (:func:`cora_model`), so a job and ``observe`` on the same model give the same
sets. ::

    [[estimator]]
    method = "PRad-E"            # any CORA name
    convention = "cora"          # "setbound" (default): the papers' guaranteed algorithm; "cora": CORA's code
    gain = [[0.05], [0.08]]      # n_x x n_y; only for the names that take a gain (else their design)
    zonotope_order = 100         # zonotopic and CZN names: CORA's zonotopeOrder (zonotopic: order x n_x
                                 # generators; CZN under convention = "cora": the order of CORA's reduction)
    reduction = "pca"            # zonotopic names: CORA's reductionTechnique (default "girard", as CORA)

Keys of every CORA name: ``convention`` and ``gain`` (refused, with the reason, for a name that takes
no gain). The method's own keys come from :data:`CORA_METHODS` (one row per name: the options the
Python class takes, the family, which conventions are guaranteed); a name without a row runs with
the common keys and its results are reported as not guaranteed until a row says otherwise.
Options not given are not passed: the method's default, or CORA's settings of the model in the
``"cora"`` convention.

The job's model becomes CORA's convention: inputs ``[u, 1]`` with a last column of ``B`` (and ``D``)
holding the constant term — zero, or the centre of ``[system.omega]`` when the job has one (then it
is ``W``'s and ``V``'s centre, and CORA's constant ``c`` is zero).
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .linear import MAX_GENERATORS, _CZN_CHECKS
from .registry import ESTIMATORS, number, one_of, optional_matrix, positive_int, register_estimator
from .schema import ConfigError

__all__ = ["CoraMethod", "CORA_METHODS", "CoraObserver", "cora_model", "register_cora_names"]

CONVENTIONS = ("setbound", "cora")
#: CORA's default zonotope order (``options.zonotopeOrder``), as :func:`setbound.benchmarks.load_cora`.
DEFAULT_ZONOTOPE_ORDER = 20.0


@dataclass(frozen=True)
class CoraMethod:
    """What a job file may say about one CORA name besides ``convention`` and ``gain``.

    Parameters
    ----------
    family : str
        The set family (``zonotopic``, ``ellipsoidal``, ``interval``, ``constrained_zonotopic``,
        ``parallelotope``; ``point`` for the point estimates of the RTS smoother).
    options : dict
        The method's own job-file keys, each with its check ``f(value, key)``; every default is
        "not given" (the method's own default).
    guaranteed : tuple of str
        The conventions whose sets are guaranteed (the truth is checked against them).
    filter : dict, optional
        Per convention: whether row ``k`` used ``y_k`` (``Trajectory.filter``); absent: unknown.
    conventions : tuple of str, optional
        The conventions it runs with.
    why_not_cora : str, optional
        The reason given when ``convention = "cora"`` is not among ``conventions``.
    setbound_only : tuple of str, optional
        Options of the ``"setbound"`` convention's estimator that CORA's recursion does not take.
    validate : callable, optional
        ``validate(options, where)``: further rules between options.
    interval_a : bool, optional
        Whether it takes a job's interval ``A`` (``A_radius``); the others refuse such a job (their
        runners read the midpoint only, or refuse it themselves).
    """

    family: str
    options: dict
    guaranteed: tuple = ("setbound", "cora")
    filter: dict = field(default_factory=dict)
    conventions: tuple = CONVENTIONS
    why_not_cora: str = ""
    setbound_only: tuple = ()
    validate: Callable[[dict, str], None] | None = None
    interval_a: bool = False


_POLICY = one_of("flag", "raise", "reset")
_ZONO = {"max_generators": positive_int(MAX_GENERATORS), "zonotope_order": number(lo=1, hi=MAX_GENERATORS),
         "reduction": one_of("combastel", "girard", "pca")}
_FILTER, _PREDICTOR = {"setbound": True, "cora": True}, {"setbound": False, "cora": False}


def _one_size(o: dict, where: str) -> None:
    if o.get("zonotope_order") is not None and o.get("max_generators") is not None:
        raise ConfigError(f"{where}.max_generators: give the size as zonotope_order (CORA's) or as max_generators, "
                          "not both")


def _one_order(o: dict, where: str) -> None:
    if o.get("zonotope_order") is not None and o.get("order") is not None:
        raise ConfigError(f"{where}.order: give the order as zonotope_order (CORA's, the model's) or as order, "
                          "not both")


def _ellipsoids(o: dict, where: str) -> None:
    if o.get("ellipsoids") == "inner" and o["convention"] != "cora":
        raise ConfigError(f'{where}.ellipsoids: "inner" ellipsoids are not outer bounds of W, V and R0, so the '
                          'sets would not be guaranteed; only with convention = "cora" (CORA\'s conversion)')


def _zonotopic(filter_: dict, interval_a: bool = False) -> CoraMethod:
    # setbound.zonotopic.ZonotopicObserver and its named rules: the screening's policy is
    # setbound's (CORA tests nothing)
    return CoraMethod("zonotopic", {**_ZONO, "on_inconsistency": _POLICY}, filter=filter_, validate=_one_size,
                      interval_a=interval_a, setbound_only=("on_inconsistency",))

# CZN-A/B: the options of setbound.constrained_zonotopic (as the czn_a/czn_b kinds) and CORA's
# zonotope order of the model (the order of CORA's reduction under convention = "cora")
_CZN = {**_CZN_CHECKS, "zonotope_order": _ZONO["zonotope_order"]}

#: The job-file keys of the CORA names setbound knows (see :class:`CoraMethod`). The checks are the
#: options of the Python classes the runners build: :mod:`setbound.zonotopic` (``max_generators``,
#: ``reduction``; ``zonotope_order`` sets the model's order instead), :mod:`setbound.ellipsoidal`
#: (ESO-A/B: ``ellipsoids``, ``step_cap``), :mod:`setbound.hinf` (ESO-C: the design's ``lambda_route``,
#: ``passes``), :mod:`setbound.interval_observers` (Hinf-G) and :mod:`setbound.constrained_zonotopic`.
CORA_METHODS: dict[str, CoraMethod] = {
    # the skeleton's segment_min / volume_min rules take an interval A ([Le2013]'s example)
    "FRad-A": _zonotopic(_FILTER, interval_a=True),
    "VolMin-A": _zonotopic(_FILTER, interval_a=True),
    "VolMin-B": _zonotopic(_FILTER),
    "FRad-B": _zonotopic(_FILTER),
    "FRad-C": _zonotopic(_PREDICTOR),
    "PRad-A": _zonotopic(_FILTER),
    "PRad-B": _zonotopic(_FILTER),
    "PRad-C": _zonotopic(_FILTER),
    "PRad-D": _zonotopic(_FILTER),
    "PRad-E": _zonotopic(_PREDICTOR),
    "Nom-G": _zonotopic(_PREDICTOR),
    "ESO-A": CoraMethod("ellipsoidal", {"ellipsoids": one_of("auto", "inner", "outer"),
                                        "step_cap": number(lo=0, hi=1, lo_open=True, hi_open=True)},
                        guaranteed=("setbound",), filter=_FILTER, validate=_ellipsoids),
    "ESO-B": CoraMethod("ellipsoidal", {"ellipsoids": one_of("auto", "inner", "outer"),
                                        "step_cap": number(lo=0, hi=1, lo_open=True, hi_open=True)},
                        guaranteed=("setbound",), filter=_FILTER, validate=_ellipsoids),
    "ESO-C": CoraMethod("ellipsoidal", {"lambda_route": one_of("logdet", "direct", "input_or_logdet", "largest"),
                                        "passes": positive_int(100)},
                        guaranteed=("setbound",), filter={"setbound": False}, conventions=("setbound",),
                        why_not_cora="CORA's ESO-C cannot run (its gain design reads an undefined variable), so "
                                     "there is nothing to reproduce; setbound's is Loukkas' guaranteed observer"),
    # ESO-D: design_eso_d (Martinez, Loukkas, Meslem 2020) + the thesis observer; the γ grid is the
    # design's own (CORA's linspace(1, 50, 100)), not a job key
    "ESO-D": CoraMethod("ellipsoidal", {}, guaranteed=("setbound",), filter={"setbound": False},
                        conventions=("setbound",),
                        why_not_cora="CORA's ESO-D cannot be reproduced: its design solves feasibility problems with "
                                     "no objective (one with YALMIP's default solver), so its result is whatever "
                                     "that solver stops at; setbound's is the same algorithm with defined choices, "
                                     "guaranteed"),
    "Hinf-G": CoraMethod("interval", {"variant": one_of("tight", "wrapped"), "on_inconsistency": _POLICY},
                         guaranteed=("setbound",), filter={"setbound": False},
                         setbound_only=("variant", "on_inconsistency")),
    "CZN-A": CoraMethod("constrained_zonotopic", _CZN, filter=_FILTER, validate=_one_order),
    "CZN-B": CoraMethod("constrained_zonotopic", _CZN, filter=_FILTER, validate=_one_order),
    # ---- ROPO and the Rauch-Tung-Striebel smoother (setbound.parallelotope, setbound.point) ----
    # ROPO: CORA's reduction technique (always order 1: no zonotope_order / max_generators); the
    # cora convention has no emptiness check, so only the setbound one is guaranteed
    "ROPO": CoraMethod("parallelotope", {"reduction": one_of("girard", "pca"), "on_inconsistency": _POLICY},
                       guaranteed=("setbound",), filter=_FILTER, setbound_only=("on_inconsistency",)),
    # point estimates (lower = upper = the smoothed state): never guaranteed
    "Rauch-Tung-Striebel": CoraMethod("point", {}, guaranteed=(), filter=_FILTER),
    "RTS": CoraMethod("point", {}, guaranteed=(), filter=_FILTER),
}

#: Keys that shape the model (not passed to the runner).
_MODEL_KEYS = ("zonotope_order",)


def cora_model(system, initial, y, u=None, *, name: str = "job", zonotope_order: float = DEFAULT_ZONOTOPE_ORDER,
               reduction: str = "girard", constant_input: bool = False, truth=None, dt: float = 1.0):
    """A job's system, initial set and data as the CORA-format model of :func:`setbound.cora.observe`.

    Parameters
    ----------
    system : LinearSystem
        The job's system (its ``A`` may be an interval matrix).
    initial : Box, Zonotope or Ellipsoid
        The initial set (an ellipsoid becomes its bounding box, :func:`setbound.sets.as_zonotope`).
    y : array_like, shape (N, n_y)
        Measurements.
    u : array_like, shape (N, n_u), optional
        Inputs (with the constant column already appended when ``constant_input``).
    name : str, optional
        The model's name.
    zonotope_order : float, optional
        CORA's zonotope order.
    reduction : str, optional
        CORA's reduction technique (``"girard"`` or ``"pca"``).
    constant_input : bool, optional
        The system's last input column is the constant 1 (a job's ``[system.omega]`` centre).
    truth : array_like, shape (N, n_x), optional
        The true states.
    dt : float, optional
        Sampling time.

    Returns
    -------
    setbound.benchmarks.CoraBenchmark
        ``B`` and ``D`` end with the constant column and ``u`` with ones, as
        :func:`setbound.benchmarks.load_cora` builds them.

    Examples
    --------
    >>> import numpy as np
    >>> sys = setbound.LinearSystem([[0.5]], [[1.0]], E=[[0.1, 0.0]], F=[[0.0, 0.1]])
    >>> m = setbound.jobs.cora.cora_model(sys, setbound.Box([-1.0], [1.0]), np.zeros((3, 1)))
    >>> m.system.B.shape, m.u[:, -1].tolist()
    ((1, 1), [1.0, 1.0, 1.0])
    """
    from ..benchmarks import CoraBenchmark
    from ..interval import IntervalMatrix
    from ..sets import as_zonotope
    from ..system import LinearSystem

    s = system
    y = np.asarray(y, dtype=float)
    N = y.shape[0]
    u = np.zeros((N, 0)) if u is None else np.asarray(u, dtype=float).reshape(N, -1)
    if constant_input:
        sc, uc = s, u
    else:
        A = IntervalMatrix.from_mid_rad(s.A, s.A_rad) if np.any(s.A_rad != 0) else s.A
        sc = LinearSystem(A, s.C, B=np.hstack([s.B, np.zeros((s.nx, 1))]), D=np.hstack([s.D, np.zeros((s.ny, 1))]),
                          E=s.E, F=s.F, dt=s.dt)
        uc = np.hstack([u, np.ones((N, 1))])
    return CoraBenchmark(name=name, system=sc, x0=as_zonotope(initial, "initial"), y=y, u=uc,
                         truth=None if truth is None else np.asarray(truth, dtype=float),
                         zonotope_order=float(zonotope_order), reduction=reduction, dt=float(dt),
                         c=np.zeros(s.nx), v_center=np.array(sc.D[:, -1], dtype=float))


class CoraObserver:
    """One CORA-named run of a job: :func:`setbound.cora.prepare` on the job's model, as an estimator
    of the job runner (``run(y, u) -> Trajectory``).

    The design happens here (timed by the job runner as the design); :meth:`run` processes a whole
    record from the initial set (CORA's runners cannot continue a run: ``resumable`` is False).

    Parameters
    ----------
    alg : str
        CORA's name.
    model : setbound.benchmarks.CoraBenchmark
        From :func:`cora_model`.
    convention : {"setbound", "cora"}, optional
        The convention.
    gain : array_like, shape (n_x, n_y), optional
        A given gain.
    options : dict, optional
        The method's own options.
    guaranteed : bool, optional
        Whether the sets are guaranteed (``Trajectory.guaranteed``).
    filter : bool, optional
        ``Trajectory.filter`` (None: unknown).
    """

    resumable = False

    def __init__(self, alg: str, model, *, convention: str = "setbound", gain=None, options: dict | None = None,
                 guaranteed: bool = False, filter: bool | None = None):
        from ..cora import prepare

        self.alg, self.model, self.convention = alg, model, convention
        self.gain = None if gain is None else np.asarray(gain, dtype=float)
        self.options = dict(options or {})
        self.guaranteed, self.filter = bool(guaranteed), filter
        self._prepare = prepare
        self._run = prepare(model, alg, convention=convention, gain=self.gain, **self.options)

    def run(self, y, u=None, *, reset: bool = True, t=None):
        """Runs the record from the initial set.

        Parameters
        ----------
        y : array_like, shape (N, n_y)
            Measurements.
        u : array_like, shape (N, n_u), optional
            Inputs, without the constant column of the model.
        reset : bool, optional
            Must be True (a CORA-named run cannot continue another).
        t : array_like, shape (N,), optional
            Time of the rows.

        Returns
        -------
        Trajectory
        """
        from ..errors import InvalidArgumentError
        from ..trajectory import Trajectory

        if not reset:
            raise InvalidArgumentError(f"reset: {self.alg} by CORA's name runs a whole record; it cannot continue one")
        m = self.model
        y = np.asarray(y, dtype=float)
        N = y.shape[0]
        uc = np.hstack([np.zeros((N, 0)) if u is None else np.asarray(u, dtype=float).reshape(N, -1),
                        np.ones((N, 1))])[:, :m.u.shape[1]]
        if y.shape == m.y.shape and uc.shape == m.u.shape and np.array_equal(y, m.y, equal_nan=True) \
                and np.array_equal(uc, m.u):
            run = self._run  # the record the design was made with
        else:
            run = self._prepare(dataclasses.replace(m, y=y, u=uc, truth=None), self.alg, convention=self.convention,
                                gain=self.gain, **self.options)
        lower, upper, sets = run()
        lower, upper = np.asarray(lower, dtype=float), np.asarray(upper, dtype=float)
        traj = Trajectory(0.5 * (lower + upper), lower, upper, list(sets or []), guaranteed=self.guaranteed)
        traj.filter = self.filter
        if t is not None:
            traj.t = np.asarray(t, dtype=float)
        return traj


def _no_gain(alg: str, with_gain: list[str]):
    def check(v, key):
        raise ConfigError(f"{key}: {alg} takes no observer gain; the CORA names with one: {', '.join(with_gain)}")
    return check


def _validate(alg: str, row: CoraMethod):
    def validate(o: dict, where: str) -> None:
        conv = o["convention"]
        if conv not in row.conventions:
            raise ConfigError(f"{where}.convention: {alg} runs only with convention = "
                              f"{' or '.join(repr(c) for c in row.conventions)}" +
                              (f" ({row.why_not_cora})" if row.why_not_cora else ""))
        from ..cora import gain_requirement  # the rule setbound.cora.prepare applies, from one table

        why = gain_requirement(alg, conv)
        if why is not None and o.get("gain") is None:
            raise ConfigError(f"{where}.gain: {alg} needs a given gain (n_x x n_y) with convention = {conv!r}: {why}")
        if conv == "cora":
            for k in row.setbound_only:
                if o.get(k) is not None:
                    raise ConfigError(f"{where}.{k}: an option of setbound's {alg}; CORA's recursion (convention = "
                                      "'cora') takes none")
        if row.validate is not None:
            row.validate(o, where)
    return validate


def _build(alg: str, row: CoraMethod):
    def build(job, o: dict):
        opts = {k: v for k, v in o.items() if v is not None and k not in ("convention", "gain", *_MODEL_KEYS)}
        t = job.t
        dt = float(t[1] - t[0]) if t is not None and len(t) > 1 and t[1] > t[0] else 1.0
        model = cora_model(job.system, job.initial, job.y, job.u, name=job.title,
                           zonotope_order=o.get("zonotope_order") or DEFAULT_ZONOTOPE_ORDER,
                           constant_input=job.constant_input, truth=job.x_true, dt=dt)
        from ..errors import InvalidArgumentError

        if not row.interval_a and np.any(job.system.A_rad != 0):
            raise InvalidArgumentError(f"system: {alg} by CORA's name needs a known A (system.A_radius is not "
                                       "supported; FRad-A and VolMin-A take an interval A)")
        order = o.get("zonotope_order")
        if order is not None and row.family == "zonotopic" and int(order * job.system.nx) > MAX_GENERATORS:
            raise InvalidArgumentError(f"zonotope_order: {order:g} x n_x = {int(order * job.system.nx)} generators, "
                                       f"more than {MAX_GENERATORS}")
        conv = o["convention"]
        return CoraObserver(alg, model, convention=conv, gain=o.get("gain"), options=opts,
                            guaranteed=conv in row.guaranteed, filter=row.filter.get(conv)), None
    return build


def register_cora_names() -> list[str]:
    """Registers every name of :func:`setbound.cora.algorithms` as a job-file estimator kind (a name
    registered as a kind already is left as it is); called when :mod:`setbound.jobs` is imported.

    Returns
    -------
    list of str
        The names registered by this call.

    Examples
    --------
    >>> "FRad-B" in setbound.jobs.ESTIMATORS
    True
    """
    from .. import cora

    names = cora.algorithms()
    with_gain = [n for n in names if cora.accepts_gain(n)]
    added = []
    for alg, summary in names.items():
        if alg in ESTIMATORS:
            continue
        row = CORA_METHODS.get(alg) or CoraMethod("cora", {}, guaranteed=())
        options = {"convention": "setbound", "gain": None, **{k: None for k in row.options}}
        checks = {"convention": one_of(*CONVENTIONS),
                  "gain": optional_matrix if cora.accepts_gain(alg) else _no_gain(alg, with_gain), **row.options}
        note = "" if row.guaranteed else "; not declared guaranteed in setbound.jobs.cora"
        register_estimator(alg, row.family, options, _build(alg, row), guaranteed="setbound" in row.guaranteed,
                           checks=checks, validate=_validate(alg, row),
                           description=f"CORA's {alg}: {summary} (setbound.cora{note})")
        added.append(alg)
    return added
