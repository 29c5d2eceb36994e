"""The validation vocabulary of job files: :class:`ConfigError` and the checks every section uses
(keys of a table, required keys, numeric matrices, scalars, the shape of the parsed document).

Every error is a :class:`ConfigError` whose message starts with the offending key
(``system.A``, ``estimator[2].beta``, ``simulation.time.start``) and says what is wrong; the
command line prints it as ``setbound: error: <key>: <what>``. Scalars go through the one
validating conversion of :mod:`setbound._validate` (no silent coercion: ``"200"`` is not a
horizon, ``true`` is not a number), whose errors are re-raised here as ``ConfigError``.
"""
from __future__ import annotations

import difflib
import numbers

import numpy as np

from .. import _validate
from .._validate import describe  # one safe repr for the API's and the job files' messages
from ..errors import InvalidArgumentError

__all__ = ["ConfigError", "describe", "matrix", "check_keys", "require", "as_int", "as_float", "as_bool",
           "as_choice", "check_document", "MAX_DEPTH"]


class ConfigError(InvalidArgumentError):
    """A job file is invalid; the message starts with the offending key."""


def _wrap(fn, value, key, *args, **kwargs):
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 100:
        raise ConfigError(f"{key}: {describe(value)} is far outside the allowed range")
    try:
        return fn(value, key, *args, **kwargs)
    except InvalidArgumentError as exc:
        raise ConfigError(str(exc)) from None


def as_int(value, key: str, **kw) -> int:
    """:func:`setbound._validate.as_int` raising :class:`ConfigError` (named ``key``)."""
    return _wrap(_validate.as_int, value, key, **kw)


def as_float(value, key: str, **kw) -> float:
    """:func:`setbound._validate.as_float` raising :class:`ConfigError` (named ``key``)."""
    return _wrap(_validate.as_float, value, key, **kw)


def as_bool(value, key: str) -> bool:
    """:func:`setbound._validate.as_bool` raising :class:`ConfigError`; the job-file spelling of
    the booleans is ``true``/``false``."""
    try:
        return _validate.as_bool(value, key)
    except InvalidArgumentError:
        raise ConfigError(f"{key}: expected true or false, got {describe(value)}") from None


def as_choice(value, key: str, choices):
    """:func:`setbound._validate.as_choice` raising :class:`ConfigError`."""
    return _wrap(_validate.as_choice, value, key, choices)


def closest(name, valid) -> str:
    """`` (did you mean 'x'?)`` when ``name`` is close to one of ``valid``, else ``""``."""
    if not isinstance(name, str):
        return ""
    hit = difflib.get_close_matches(name, sorted(valid), n=1, cutoff=0.6)
    return f" (did you mean {hit[0]!r}?)" if hit else ""


def check_keys(table, allowed, where: str) -> None:
    """Refuses a non-table and every key not in ``allowed``, naming the closest valid key."""
    if not isinstance(table, dict):
        raise ConfigError(f"{where}: expected a table, got {describe(table)}")
    for k in table:
        if k not in allowed:
            hint = closest(k, allowed)
            raise ConfigError(f"{where}.{k}: unknown key{hint or ''}"
                              + ("" if hint else f" (allowed: {', '.join(sorted(allowed))})"))


def require(table, key: str, where: str):
    """``table[key]``, or a ConfigError saying it is missing."""
    if key not in table:
        raise ConfigError(f"{where}.{key}: missing (required)")
    return table[key]


def _first_bad_leaf(v, key: str, ndim: int):
    """The index path and description of the first entry of a nested list that is not a real
    number (a string, a boolean, a table); numpy would turn ``"0.1"`` and ``true`` into numbers
    without a word, so the leaves are checked before the conversion."""
    stack = [((), v, 0)]
    while stack:
        path, x, depth = stack.pop()
        if isinstance(x, list):
            if depth >= ndim:
                return path, "a nested list (too many levels)"
            for i in range(len(x) - 1, -1, -1):
                stack.append((path + (i,), x[i], depth + 1))
        elif isinstance(x, bool) or not isinstance(x, numbers.Real):
            what = f"the string {describe(x)}" if isinstance(x, str) else describe(x)
            return path, what
    return None


def matrix(v, key: str, *, ndim: int = 2, shape=None) -> np.ndarray:
    """A finite numeric matrix (``ndim = 2``, a list of rows) or vector (``ndim = 1``) of the given
    ``shape`` (``None`` entries: any size); errors name ``key`` and the offending entry."""
    what = "matrix" if ndim == 2 else "vector"
    if isinstance(v, str):
        raise ConfigError(f"{key}: expected a numeric {what}, got the string {describe(v)}")
    if isinstance(v, (list, int, float)) and not isinstance(v, bool):
        bad = _first_bad_leaf(v, key, ndim)
        if bad is not None:
            path, desc = bad
            raise ConfigError(f"{key}{''.join(f'[{i}]' for i in path)}: expected a number, got {desc}")
    elif not isinstance(v, np.ndarray):
        raise ConfigError(f"{key}: expected a numeric {what}, got {describe(v)}")
    try:
        a = np.array(v, dtype=float)
    except OverflowError:  # an integer beyond the float range
        raise ConfigError(f"{key}: a value is too large for a floating-point number") from None
    except (TypeError, ValueError):
        raise ConfigError(f"{key}: expected a numeric {what} (rows of equal length, numbers only)") from None
    if ndim == 2 and a.ndim == 1 and a.size > 0 and shape is not None and shape[0] == 1:
        a = a.reshape(1, -1)
    if ndim == 2 and a.ndim == 0:
        a = a.reshape(1, 1)
    if a.ndim != ndim:
        raise ConfigError(f"{key}: expected a {'matrix (list of rows)' if ndim == 2 else 'vector (list of numbers)'}, "
                          f"got an array of shape {a.shape}")
    if shape is not None:
        for want, got in zip(shape, a.shape):
            if want is not None and want != got:
                raise ConfigError(f"{key}: expected shape {tuple('n' if s is None else s for s in shape)}, got {a.shape}")
    if not np.all(np.isfinite(a)):
        idx = tuple(int(i) for i in np.argwhere(~np.isfinite(a))[0])
        raise ConfigError(f"{key}{''.join(f'[{i}]' for i in idx)}: not a finite number (NaN or inf)")
    return a


#: Deepest nesting of tables and arrays a job file may have. The deepest legitimate value is an
#: LPV vertex list (document → system → A → matrix → row → entry: 5 levels); the bound stops a
#: hostile file (arrays nested thousands deep) before any recursive code (numpy's conversion,
#: ``repr`` in a message) meets it.
MAX_DEPTH = 12


def _path(parts) -> str:
    out = ""
    for p in parts:
        out += f"[{p}]" if isinstance(p, int) else (f".{p}" if out else str(p))
    return out


def check_document(doc) -> None:
    """Refuses a parsed document nested deeper than :data:`MAX_DEPTH` (iteratively, so the check
    itself cannot exhaust the stack), naming the key where it happens."""
    stack = [((), doc)]
    while stack:
        path, x = stack.pop()
        if len(path) > MAX_DEPTH:
            raise ConfigError(f"{_path(path[:MAX_DEPTH]) or 'job'}: nested too deeply (more than {MAX_DEPTH} levels of "
                              f"tables and arrays)")
        if isinstance(x, dict):
            stack.extend((path + (k,), v) for k, v in x.items())
        elif isinstance(x, list):
            stack.extend((path + (i,), v) for i, v in enumerate(x))
