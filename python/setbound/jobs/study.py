"""The ``[study]`` section of a job file: one job expanded into a grid of cases (issue 23).

::

    [study]
    seeds = 20                       # or [3, 7, 11], or {start = 100, count = 20}
    estimators = ["offline", "segment_min"]   # optional: a subset of the job's estimator names
    exact_hull = false               # true: each case also computes the exact hull (linear systems)

    [study.parameters]               # every combination of these values, for every seed
    noise_scale = [0.5, 1.0, 2.0]    # multiplies the disturbance matrices (E and F; D and F of a descriptor)
    horizon = [50, 200]              # the simulation's horizon
    max_generators = [10, 20]        # an estimator option: varies for the estimators that have it
    "offline.beta" = [0.5, 0.8]      # NAME.OPTION: an option of one estimator
    "simulation.disturbance" = ["uniform", "vertex"]   # any other [simulation] key

A case is ``(estimator, seed, parameter values)``; a parameter that does not apply to an estimator
(an option it does not have) is left out of that estimator's cases instead of repeating them. With
an integer ``seeds = n`` the seeds are ``simulation.seed + 0 … n − 1``.

:func:`load_study` validates the section completely before anything runs: the keys, the seeds,
and every value of every parameter, by loading the job with that value (so a value is checked by
the same code that checks the job file, and the error names ``study.parameters.<name>[i]``).
:class:`Study` enumerates the cases lazily (a grid of millions of cases is never held in memory).
"""
from __future__ import annotations

import copy
import hashlib
import itertools
import json
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from .loader import from_dict, load
from .registry import ESTIMATORS
from .schema import ConfigError, as_bool, as_int, check_keys, closest, describe

__all__ = ["Study", "load_study", "study_from_dict", "apply_case", "MAX_CASES", "BUILTIN_PARAMETERS"]

#: Largest grid (cases) a study may describe.
MAX_CASES = 10_000_000
#: Largest number of values of one parameter, and of seeds given as a list.
MAX_VALUES = 100_000
#: Parameters every study knows (besides estimator options and ``simulation.<key>``).
BUILTIN_PARAMETERS = ("noise_scale", "horizon")


@dataclass
class Study:
    """A validated study: the job document without ``[study]`` (``doc``, plain data), the directory
    its relative data files are looked up in (``base``), the ``seeds``, the swept ``parameters``
    (name → list of values, in file order), the ``estimators`` (names), ``exact_hull``, and for
    each parameter the estimator names it applies to (``applies``)."""

    doc: dict
    base: str
    source: str
    seeds: list
    parameters: dict
    estimators: list
    exact_hull: bool = False
    applies: dict = field(default_factory=dict)

    def parameters_of(self, estimator: str) -> list:
        """The parameter names that vary ``estimator``'s cases (file order)."""
        return [p for p in self.parameters if estimator in self.applies[p]]

    @property
    def size(self) -> int:
        """The number of cases (computed, not enumerated)."""
        total = 0
        for e in self.estimators:
            total += len(self.seeds) * math.prod(len(self.parameters[p]) for p in self.parameters_of(e))
        return total

    def cases(self):
        """Yields the cases in a fixed order: ``{"i", "key", "estimator", "seed", "params"}``
        (``i`` the case's index, ``key`` a string naming it uniquely)."""
        i = 0
        for e in self.estimators:
            names = self.parameters_of(e)
            for values in itertools.product(*(self.parameters[p] for p in names)):
                params = dict(zip(names, values))
                for s in self.seeds:
                    yield {"i": i, "key": case_key(e, s, params), "estimator": e, "seed": s, "params": params}
                    i += 1

    def fingerprint(self) -> str:
        """SHA-256 of everything that decides the cases' results (the job and the grid): a resumed
        study must have the same."""
        blob = json.dumps({"doc": self.doc, "seeds": self.seeds, "parameters": self.parameters,
                           "estimators": self.estimators, "exact_hull": self.exact_hull},
                          sort_keys=True, default=str)
        return hashlib.sha256(blob.encode()).hexdigest()

    def context(self) -> dict:
        """What every task of the study needs besides its cases (plain data)."""
        return {"doc": self.doc, "base": self.base, "exact_hull": self.exact_hull}


def case_key(estimator: str, seed: int, params: dict) -> str:
    """``estimator=NAME;seed=S;p=v;…``: the case's unique name (values as JSON)."""
    parts = [f"estimator={estimator}", f"seed={seed}"] + [f"{k}={json.dumps(v)}" for k, v in params.items()]
    return ";".join(parts)


def _scale(doc: dict, scale: float) -> None:
    sysd = doc["system"]
    kind = sysd.get("kind", "linear")
    names = {"linear": ("E", "F"), "descriptor": ("D", "F")}.get(kind)
    for nm in names:
        if nm in sysd:
            sysd[nm] = [[scale * v for v in row] for row in sysd[nm]]


def apply_case(doc: dict, estimator: str, seed: int, params: dict) -> dict:
    """The job document of one case: ``doc`` with the seed, the parameter values and only the
    estimator ``estimator`` (no ``[plots]``, no ``[[hypothesis]]`` bank). ``doc`` is not changed."""
    d = copy.deepcopy(doc)
    d.pop("plots", None)
    d.pop("hypothesis", None)
    d["estimator"] = [t for t in d["estimator"] if t.get("name", t.get("method")) == estimator]
    d["simulation"]["seed"] = seed
    for name, v in params.items():
        if name == "noise_scale":
            _scale(d, v)
        elif name == "horizon":
            d["simulation"]["horizon"] = v
        elif name.startswith("simulation."):
            d["simulation"][name.split(".", 1)[1]] = v
        else:
            option = name.split(".", 1)[1] if "." in name else name
            for t in d["estimator"]:
                t[option] = v
    return d


def _seeds(v, base_seed: int) -> list:
    key = "study.seeds"
    if isinstance(v, dict):
        check_keys(v, {"start", "count"}, key)
        start = as_int(v.get("start", base_seed), f"{key}.start", lo=0, hi=2**63 - 1)
        count = as_int(v.get("count"), f"{key}.count", lo=1, hi=MAX_CASES)
        if start + count - 1 > 2**63 - 1:
            raise ConfigError(f"{key}.count: the seeds would pass 2**63 - 1")
        return list(range(start, start + count))
    if isinstance(v, list):
        if not v or len(v) > MAX_VALUES:
            raise ConfigError(f"{key}: expected a non-empty list of at most {MAX_VALUES} seeds, got {describe(v)}")
        seeds = [as_int(s, f"{key}[{i}]", lo=0, hi=2**63 - 1) for i, s in enumerate(v)]
        if len(set(seeds)) != len(seeds):
            dup = next(s for s in seeds if seeds.count(s) > 1)
            raise ConfigError(f"{key}: seed {dup} is listed twice")
        return seeds
    count = as_int(v, key, lo=1, hi=MAX_CASES)
    return list(range(base_seed, base_seed + count))


def _applies(name: str, specs: dict, sim_keys: set, system_kind: str) -> list:
    """The estimator names parameter ``name`` applies to, or a ConfigError naming it."""
    key = f"study.parameters.{name}"
    if name == "noise_scale":
        if system_kind not in ("linear", "descriptor"):
            raise ConfigError(f"{key}: applies to linear and descriptor systems (it scales E and F, or D and F), "
                              f"not to a {system_kind!r} system")
        return list(specs)
    if name == "horizon":
        return list(specs)
    if name.startswith("simulation."):
        sub = name.split(".", 1)[1]
        if sub == "seed":
            raise ConfigError(f"{key}: the seeds are study.seeds, not a parameter")
        if sub not in sim_keys:
            raise ConfigError(f"{key}: unknown [simulation] key {sub!r}{closest(sub, sim_keys)}")
        return list(specs)
    if "." in name:
        est, option = name.split(".", 1)
        if est not in specs:
            raise ConfigError(f"{key}: {est!r} is not an estimator of this study ({', '.join(specs)})"
                              f"{closest(est, specs)}")
        if option not in ESTIMATORS[specs[est]].options:
            opts = sorted(ESTIMATORS[specs[est]].options)
            raise ConfigError(f"{key}: {specs[est]!r} has no option {option!r} (options: {', '.join(opts)})"
                              f"{closest(option, opts)}")
        return [est]
    having = [e for e, m in specs.items() if name in ESTIMATORS[m].options]
    if not having:
        options = sorted({o for m in specs.values() for o in ESTIMATORS[m].options})
        raise ConfigError(f"{key}: unknown parameter (not {', '.join(BUILTIN_PARAMETERS)}, simulation.<key>, "
                          f"NAME.OPTION or an option of the study's estimators: {', '.join(options)})"
                          f"{closest(name, [*BUILTIN_PARAMETERS, *options])}")
    return having


def _check_value(doc: dict, base: Path, estimators: list, name: str, value, key: str) -> None:
    """Loads the job with ``name = value`` (validation only): the loader's own checks, reported
    under ``key``."""
    if name == "noise_scale":
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not (
                math.isfinite(value) and value > 0):
            raise ConfigError(f"{key}: expected a finite number > 0, got {describe(value)}")
    for e in estimators:
        d = apply_case(doc, e, doc["simulation"].get("seed", 0), {name: value})
        try:
            from_dict(d, base=base, simulate=False)
        except ConfigError as exc:
            raise ConfigError(f"{key}: {exc}") from None


def study_from_dict(doc: dict, *, base=Path("."), source: str = "") -> Study:
    """Validates a parsed job file with a ``[study]`` section; raises ConfigError naming the key."""
    if "study" not in doc:
        raise ConfigError("study: missing (a study file is a job file with a [study] section)")
    tab = doc["study"]
    if not isinstance(tab, dict):
        raise ConfigError(f"study: expected a table, got {describe(tab)}")
    check_keys(tab, {"seeds", "parameters", "estimators", "exact_hull"}, "study")
    job_doc = {k: v for k, v in doc.items() if k != "study"}
    if "simulation" not in job_doc:
        raise ConfigError("study: needs a [simulation] section (the study varies the seed of the simulated "
                          "disturbances; a [data] file has none)")
    job = from_dict(job_doc, base=base, source=source, simulate=False)  # the base job, complete
    specs = {s.name: s.method for s in job.estimators}
    names = list(specs)
    if "estimators" in tab:
        want = tab["estimators"]
        if not isinstance(want, list) or not want:
            raise ConfigError(f"study.estimators: expected a non-empty list of estimator names, got {describe(want)}")
        for i, w in enumerate(want):
            if not isinstance(w, str) or w not in specs:
                raise ConfigError(f"study.estimators[{i}]: {describe(w)} is not an estimator name of this job "
                                  f"({', '.join(names)}){closest(w, names) if isinstance(w, str) else ''}")
        if len(set(want)) != len(want):
            raise ConfigError("study.estimators: a name is listed twice")
        names = list(want)
        specs = {n: specs[n] for n in names}
    exact = as_bool(tab.get("exact_hull", False), "study.exact_hull")
    if exact and job.system_kind != "linear":
        raise ConfigError(f"study.exact_hull: the exact hull is computed for linear systems, not for a "
                          f"{job.system_kind!r} system")
    seeds = _seeds(tab.get("seeds", 1), job_doc["simulation"].get("seed", 0))
    params = tab.get("parameters", {})
    if not isinstance(params, dict):
        raise ConfigError(f"study.parameters: expected a table of name = [values], got {describe(params)}")
    sim_keys = {"horizon", "disturbance", "inputs", "time", "x0", "A_choice",
                *getattr(job.system, "simulation_keys", ())}
    parameters, applies = {}, {}
    base = Path(base)
    for name, values in params.items():
        key = f"study.parameters.{name}"
        applies[name] = _applies(name, specs, sim_keys, job.system_kind)
        if not isinstance(values, list):
            raise ConfigError(f"{key}: expected a list of values, got {describe(values)}")
        if not values:
            raise ConfigError(f"{key}: empty list (the grid would have no case)")
        if len(values) > MAX_VALUES:
            raise ConfigError(f"{key}: {len(values)} values, at most {MAX_VALUES}")
        seen = []
        for i, v in enumerate(values):
            if v in seen and type(v) is type(seen[seen.index(v)]):
                raise ConfigError(f"{key}[{i}]: {describe(v)} is listed twice")
            seen.append(v)
            _check_value(job_doc, base, applies[name], name, v, f"{key}[{i}]")
        parameters[name] = list(values)
    study = Study({k: v for k, v in job_doc.items()}, str(base), source, seeds, parameters, names, exact, applies)
    n = study.size
    if n > MAX_CASES:
        raise ConfigError(f"study: the grid has {n} cases, at most {MAX_CASES}")
    return study


def load_study(path) -> Study:
    """Reads and validates a study file (a job file with ``[study]``); ConfigError names the key."""
    path = Path(path)
    load(path, simulate=False)  # the file's own checks (size, encoding, TOML) and the base job
    with open(path, "rb") as fh:
        doc = tomllib.load(fh)
    return study_from_dict(doc, base=path.parent, source=str(path))
