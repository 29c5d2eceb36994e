"""The registries of job-file kinds: the system kinds a ``[system] kind`` may name and the
estimator kinds an ``[[estimator]] method`` may name, so a new method or model is added in one
place (see :mod:`setbound.jobs` for the contract of ``build``).

Option checks: ``register_estimator(..., checks={option: check})`` where ``check`` is either a
*conversion* ``f(value, key) -> value`` that raises :class:`ConfigError` (the form the
built-in kinds use, built on :mod:`setbound._validate` through the helpers below), or the older
pair ``(predicate, "what it must be")``.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable

from .._validate import INT_MAX
from .schema import ConfigError, as_bool, as_choice, as_float, as_int, closest, describe, matrix

__all__ = ["BuiltSystem", "SystemKind", "EstimatorKind", "SYSTEMS", "ESTIMATORS", "METHODS", "register_system",
           "register_estimator", "system_kind_of", "check_option", "one_of", "positive_int", "boolean", "number",
           "optional_vector", "optional_matrix"]


@dataclass(frozen=True)
class BuiltSystem:
    """What a system kind's ``build`` may return instead of the bare system: the system and
    ``constant_input`` — True when the conversion appended an input column that is always 1 (the
    offset of non-centred disturbance bounds); jobs then append that column to the inputs.

    Parameters
    ----------
    system : object
        The system.
    constant_input : bool, optional
        See above.
    """

    system: Any
    constant_input: bool = False


@dataclass(frozen=True)
class SystemKind:
    """A registered ``[system] kind``: allowed ``keys``, ``build(table) -> system``, the Python ``cls``.

    Parameters
    ----------
    kind : str
        Name used as ``[system] kind``.
    keys : frozenset of str
        Allowed keys of the table.
    build : callable
        ``build(table) -> system``.
    cls : type
        The Python class of the systems.
    description : str, optional
        One line for the command line's listings.
    """

    kind: str
    keys: frozenset
    build: Callable[[dict], Any]
    cls: type
    description: str = ""


@dataclass(frozen=True)
class EstimatorKind:
    """A registered ``[[estimator]] method``: see :mod:`setbound.jobs` (Registry).

    Parameters
    ----------
    method : str
        Name used as ``[[estimator]] method``.
    family : str
        Family (ellipsoidal, zonotopic, …).
    options : dict
        Options and their defaults.
    build : callable
        ``build(job, options) -> (estimator, design)``.
    systems : tuple of str, optional
        System kinds it accepts.
    guaranteed : bool, optional
        Whether its sets are guaranteed.
    steady_volume : callable, optional
        ``steady_volume(design, estimator) -> float``.
    description : str, optional
        One line for the command line's listings.
    checks : dict, optional
        Validation of option values (see :func:`register_estimator`).
    validate : callable, optional
        ``validate(options, where)``: rules between options (see :func:`register_estimator`).
    """

    method: str
    family: str
    options: dict[str, Any]
    build: Callable[[Any, dict], tuple[Any, Any]]
    systems: tuple[str, ...] = ("linear",)
    guaranteed: bool = True
    steady_volume: Callable[[Any, Any], float] | None = None
    description: str = ""
    checks: dict[str, Any] = field(default_factory=dict)
    validate: Callable[[dict, str], None] | None = None


#: Registered system kinds, ``kind -> SystemKind``.
SYSTEMS: dict[str, SystemKind] = {}
#: Registered estimator kinds, ``method -> EstimatorKind``.
ESTIMATORS: dict[str, EstimatorKind] = {}
#: ``method -> (family, allowed options with defaults)``: a view of :data:`ESTIMATORS` kept in step
#: by :func:`register_estimator` (the older name of the table).
METHODS: dict[str, tuple[str, dict[str, Any]]] = {}


def register_system(kind: str, keys, build: Callable[[dict], Any], cls: type, *, description: str = "",
                    replace: bool = False) -> SystemKind:
    """Adds a system kind usable as ``[system] kind = "<kind>"`` (see :mod:`setbound.jobs`).

    Parameters
    ----------
    kind : str
        The name.
    keys : iterable of str
        Allowed keys.
    build : callable
        ``build(table) -> system``.
    cls : type
        The Python class of the systems.
    description : str, optional
        One line for listings.
    replace : bool, optional
        Replace an existing registration of ``kind``.

    Returns
    -------
    SystemKind
    """
    if kind in SYSTEMS and not replace:
        raise ValueError(f"kind: the system kind {kind!r} is already registered (replace=True to override)")
    entry = SystemKind(kind, frozenset(keys) | {"kind"}, build, cls, description)
    SYSTEMS[kind] = entry
    return entry


def register_estimator(method: str, family: str, options: dict[str, Any], build, *, systems=("linear",),
                       guaranteed: bool = True, steady_volume=None, description: str = "", checks=None,
                       validate=None, replace: bool = False) -> EstimatorKind:
    """Adds an estimator kind usable as ``[[estimator]] method = "<method>"`` (see
    :mod:`setbound.jobs`). ``options`` must not contain ``method`` or ``name``. ``checks`` maps an
    option to a conversion ``f(value, key)`` or to ``(predicate, what it must be)``: values given
    in a job file are validated when it is loaded. ``validate(options, where)`` then sees all the
    options (defaults filled in) and raises :class:`ConfigError` naming ``<where>.<option>`` when
    two of them do not go together.

    Parameters
    ----------
    method : str
        The name.
    family : str
        Family.
    options : dict
        Options and their defaults.
    build : callable
        ``build(job, options) -> (estimator, design)``.
    systems : tuple of str, optional
        System kinds it accepts.
    guaranteed : bool, optional
        Whether its sets are guaranteed.
    steady_volume : callable, optional
        Steady-state volume of a design.
    description : str, optional
        One line for listings.
    checks : dict, optional
        Option validation.
    validate : callable, optional
        ``validate(options, where)``: rules between options.
    replace : bool, optional
        Replace an existing registration of ``method``.

    Returns
    -------
    EstimatorKind
    """
    if method in ESTIMATORS and not replace:
        raise ValueError(f"method: the estimator {method!r} is already registered (replace=True to override)")
    bad = {"method", "name"} & set(options)
    if bad:
        raise ValueError(f"options: {', '.join(sorted(bad))} is reserved")
    entry = EstimatorKind(method, family, dict(options), build, tuple(systems), guaranteed, steady_volume,
                          description, dict(checks or {}), validate)
    ESTIMATORS[method] = entry
    METHODS[method] = (family, entry.options)
    return entry


def system_kind_of(system) -> str:
    """The registered kind of a system object (the most specific registered class).

    Parameters
    ----------
    system : object
        A system.

    Returns
    -------
    str
    """
    for kind, entry in SYSTEMS.items():
        if type(system) is entry.cls:
            return kind
    for kind, entry in SYSTEMS.items():
        if isinstance(system, entry.cls):
            return kind
    raise ConfigError(f"system: {type(system).__name__} is not a registered system kind "
                      f"({', '.join(SYSTEMS)})")


def unknown_method(method, where: str) -> ConfigError:
    """The error of an unregistered ``method`` (with the closest registered name)."""
    return ConfigError(f"{where}.method: unknown method {describe(method)}{closest(method, ESTIMATORS)} "
                       f"(one of {', '.join(ESTIMATORS)})")


def check_option(check, value, key: str):
    """Applies one entry of ``EstimatorKind.checks``; returns the (converted) value."""
    if isinstance(check, tuple):
        pred, what = check
        try:
            ok = bool(pred(value))
        except Exception:  # a predicate meeting a type it did not expect: the value is wrong  # noqa: BLE001
            ok = False
        if not ok:
            raise ConfigError(f"{key}: must be {what}, got {describe(value)}")
        return value
    return check(value, key)


# ---------------------------------------------------------------- conversions for checks
def one_of(*values):
    """A check: ``value`` is one of ``values``."""
    return lambda v, key: as_choice(v, key, values)


def positive_int(hi: int = INT_MAX):
    """A check: an integer in [1, hi]."""
    return lambda v, key: as_int(v, key, lo=1, hi=hi)


def boolean(v, key):
    """A check: true or false."""
    return as_bool(v, key)


def number(**kw):
    """A check: a finite number in the range of :func:`setbound._validate.as_float` ``kw``."""
    return lambda v, key: as_float(v, key, **kw)


def optional_vector(v, key):
    """A check: a numeric vector (converted later, when the size is known)."""
    if v is not None:
        matrix(v, key, ndim=1)
    return v


def optional_matrix(v, key):
    """A check: a numeric matrix (converted later, when the shape is known)."""
    if v is not None:
        matrix(v, key)
    return v
