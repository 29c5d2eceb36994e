"""One validating conversion for the scalar options of the Python API and the job files.

Every int, float and bool option that a user passes (a keyword of a constructor or function, a
value of a job file) goes through one of the functions below before it reaches the C library.
They never coerce silently: ``3.7``, ``"5"`` and ``True`` are not integers, ``"0.1"`` is not a
float, ``1`` is not a bool. Errors are :class:`setbound.errors.InvalidArgumentError` (also a
``ValueError``) whose message starts with the option's name, so C, C++ and Python users read
the same kind of message:

    max_generators: expected an integer in [1, 1000000], got 3.7

Ranges are closed unless stated. Where the work or the memory grows with a value, the caller
passes a documented upper bound (``hi``); a size the machine cannot hold is refused here, before
anything is allocated, instead of surfacing as ``OverflowError`` (a C ``int`` argument),
``MemoryError`` or the library's "out of memory".
"""
from __future__ import annotations

import math
import numbers
from typing import Any, Iterable

import numpy as np

from .errors import InvalidArgumentError

__all__ = ["describe", "as_int", "as_float", "as_bool", "as_choice", "as_str", "INT_MAX", "fmt_range", "memory_budget",
           "check_memory"]

#: The largest value of a C ``int`` (every count crosses the C ABI as an ``int``).
INT_MAX = 2**31 - 1


def describe(value: Any, limit: int = 40) -> str:
    """A short, safe ``repr`` for messages: a hostile value (a 400-digit integer, a list nested
    thousands deep) must not turn the error message itself into the failure (``str`` of an
    integer of more than 4300 digits raises ``ValueError``)."""
    if isinstance(value, (list, tuple)):
        return f"a list of {len(value)} item{'s' if len(value) != 1 else ''}"
    if isinstance(value, dict):
        return f"a table ({len(value)} key{'s' if len(value) != 1 else ''})"
    if isinstance(value, int) and not isinstance(value, bool) and value.bit_length() > 100:
        if value.bit_length() < 14000:  # below Python's 4300-digit limit of int -> str
            return f"an integer of {len(str(abs(value)))} digits"
        return f"an integer of about {int(value.bit_length() * 0.30103) + 1} digits"  # str() would raise
    try:
        r = repr(value)
    except (RecursionError, ValueError):
        return f"a {type(value).__name__}"
    return r if len(r) <= limit else r[:limit - 3] + "..."


def fmt_range(lo, hi, *, lo_open: bool = False, hi_open: bool = False) -> str:
    """``[lo, hi]`` / ``(lo, hi]`` / ``[lo, ∞)`` as text."""
    left = "(" if lo_open or lo is None else "["
    right = ")" if hi_open or hi is None else "]"
    a = "-inf" if lo is None else f"{lo:g}" if isinstance(lo, float) else str(lo)
    b = "inf" if hi is None else f"{hi:g}" if isinstance(hi, float) else str(hi)
    return f"{left}{a}, {b}{right}"


def _is_int(value: Any) -> bool:
    return isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_))


def as_int(value: Any, name: str, *, lo: int | None = None, hi: int | None = INT_MAX) -> int:
    """``value`` as a Python ``int`` in ``[lo, hi]``.

    Accepted: ``int`` and numpy integers (not ``bool``). Refused with an error naming ``name``:
    floats (also integral ones such as ``5.0``: a float where a count is expected is a sign of
    a mistake), strings, bools, ``None``, and values outside the range. ``hi`` defaults to the
    largest C ``int``; pass ``hi=None`` for no upper bound (only where nothing is sized by it).
    """
    if not _is_int(value):
        raise InvalidArgumentError(f"{name}: expected an integer in {fmt_range(lo, hi)}, got {describe(value)}"
                                   f" ({type(value).__name__})")
    v = int(value)
    if (lo is not None and v < lo) or (hi is not None and v > hi):
        raise InvalidArgumentError(f"{name}: expected an integer in {fmt_range(lo, hi)}, got {describe(v)}")
    return v


def as_float(value: Any, name: str, *, lo: float | None = None, hi: float | None = None,
             lo_open: bool = False, hi_open: bool = False, finite: bool = True, nan: bool = False) -> float:
    """``value`` as a Python ``float`` in the range given (``lo_open``/``hi_open`` exclude an end).

    Accepted: real numbers (``int``, ``float``, numpy scalars), not ``bool``, strings or
    ``None``. NaN is refused unless ``nan=True`` (and ±Inf unless ``finite=False``):
    ``nan=True, finite=False`` only checks the type, for a value whose content the C library
    checks itself (its ``NotFiniteError`` names the value as it does for C users).
    """
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise InvalidArgumentError(f"{name}: expected a number in {fmt_range(lo, hi, lo_open=lo_open, hi_open=hi_open)}"
                                   f", got {describe(value)} ({type(value).__name__})")
    try:
        v = float(value)
    except OverflowError:  # an int beyond the float range
        raise InvalidArgumentError(f"{name}: {describe(value)} is too large for a floating-point number") from None
    if math.isnan(v) and nan:
        return v
    if math.isnan(v) or (finite and math.isinf(v)):
        raise InvalidArgumentError(f"{name}: expected a finite number, got {v}")
    bad = ((lo is not None and (v < lo or (lo_open and v == lo)))
           or (hi is not None and (v > hi or (hi_open and v == hi))))
    if bad:
        raise InvalidArgumentError(f"{name}: expected a number in {fmt_range(lo, hi, lo_open=lo_open, hi_open=hi_open)}"
                                   f", got {v:g}")
    return v


def as_bool(value: Any, name: str) -> bool:
    """``value`` as a ``bool``: only ``True``/``False`` (and numpy bools), never ``1``, ``"yes"``
    or ``None``."""
    if not isinstance(value, (bool, np.bool_)):
        raise InvalidArgumentError(f"{name}: expected True or False, got {describe(value)} ({type(value).__name__})")
    return bool(value)


def as_choice(value: Any, name: str, choices: Iterable[Any]):
    """``value`` if it is one of ``choices`` (compared by type and value, so ``True`` is not ``1``)."""
    choices = list(choices)
    for c in choices:
        if (type(value) is type(c) or (_is_int(value) and _is_int(c))) and value == c:
            return c
    raise InvalidArgumentError(f"{name}: expected one of {', '.join(repr(c) for c in choices)}, got {describe(value)}")


def as_str(value: Any, name: str) -> str:
    """``value`` if it is a ``str`` (a label or a name; ``None``, numbers and bytes are refused)."""
    if not isinstance(value, str):
        raise InvalidArgumentError(f"{name}: expected a string, got {describe(value)} ({type(value).__name__})")
    return value


def memory_budget() -> int:
    """Bytes one call may allocate for a size the user chose: half the machine's physical memory
    (``os.sysconf``; 4 GiB where the platform does not tell). Half, so that the request fails
    here with a message instead of pushing the machine into swap or the OOM killer."""
    import os

    try:
        total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (ValueError, OSError, AttributeError):
        total = 8 * 2**30
    return max(int(total) // 2, 2**20)


def check_memory(name: str, value: int, nbytes: float) -> None:
    """Refuses ``name`` = ``value`` when the ``nbytes`` it needs exceed :func:`memory_budget`,
    with the estimate in the message (before anything is allocated)."""
    budget = memory_budget()
    if nbytes > budget:
        raise InvalidArgumentError(f"{name}: {value} needs about {nbytes / 2**30:.3g} GiB, more than half of this "
                                   f"machine's memory ({budget / 2**30:.3g} GiB); use a smaller value")
