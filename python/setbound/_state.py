"""Saved states, pickling and deep copies of the estimators (docs/user_guide.md, "Saving and
restoring estimators").

Objects of this package hold C handles, which cannot be pickled. Two mechanisms:

* :func:`reconstructible` (class decorator): the construction arguments are recorded; pickling
  calls the class again with them (after pickling them) and, for an estimator, restores the
  saved state (``save_state()`` bytes) into the new object.
* :func:`remember_call`: for objects made by a function (designs), the function and its
  arguments are recorded; unpickling calls the function again. Designs are deterministic, and a
  state restored into an estimator whose design differs is refused by the library (the state
  carries a fingerprint of the design).

``copy.deepcopy`` of an estimator builds a new estimator from the same (immutable) design
objects and restores the state: the copy continues exactly as the original, independently.
"""

from __future__ import annotations

import functools

import numpy as np

from ._native import check, dptr, ffi, lib
from .errors import InvalidArgumentError

__all__ = ["reconstructible", "remember_call", "StateMixin"]


def _rebuild(factory, args, kwargs, state):
    obj = factory(*args, **kwargs)
    if state is not None:
        obj.restore_state(state)
    return obj


def _call(function, args, kwargs):
    obj = function(*args, **kwargs)
    return obj


def _ctor_of(obj):
    ctor = obj.__dict__.get("_ctor")
    if ctor is None:
        raise InvalidArgumentError(f"{type(obj).__name__}: this object was not made by its constructor and cannot "
                                   "be pickled")
    return ctor


def _reduce(self):
    args, kwargs = _ctor_of(self)
    state = self.save_state() if isinstance(self, StateMixin) else None
    return (_rebuild, (type(self), args, kwargs, state))


def _copy(self):
    args, kwargs = _ctor_of(self)
    state = self.save_state() if isinstance(self, StateMixin) else None
    return _rebuild(type(self), args, kwargs, state)


def _deepcopy(self, memo):
    out = _copy(self)
    memo[id(self)] = out
    return out


def reconstructible(cls):
    """Class decorator: records ``(args, kwargs)`` of the outermost ``__init__`` call and gives
    the class ``__reduce__`` (pickle), ``__copy__`` and ``__deepcopy__`` that call the class
    again with them (estimators then restore their saved state)."""
    init = cls.__init__

    @functools.wraps(init)
    def __init__(self, *args, **kwargs):
        if "_ctor" not in self.__dict__:
            self.__dict__["_ctor"] = (args, dict(kwargs))
        init(self, *args, **kwargs)

    cls.__init__ = __init__
    if "__reduce__" not in cls.__dict__:
        cls.__reduce__ = _reduce
    cls.__copy__ = _copy
    cls.__deepcopy__ = _deepcopy
    return cls


def remember_call(obj, function, *args, **kwargs):
    """Records that ``obj = function(*args, **kwargs)`` (for pickling ``obj``); returns ``obj``."""
    object.__setattr__(obj, "_made_by", (function, args, kwargs))
    return obj


class MadeByCall:
    """Mixin of immutable objects made by a function (designs): pickling calls the function
    again; ``copy`` and ``deepcopy`` return the object itself (it is immutable)."""

    def __reduce__(self):
        made = self.__dict__.get("_made_by")
        if made is None:
            raise InvalidArgumentError(f"{type(self).__name__}: this object was not made by a setbound function and "
                                       "cannot be pickled")
        function, args, kwargs = made
        return (_call, (function, args, kwargs))

    def __copy__(self):
        return self

    def __deepcopy__(self, memo):
        return self


class StateMixin:
    """``save_state()`` / ``restore_state()`` through the C functions ``<prefix>_state_size``,
    ``<prefix>_save_state`` and ``<prefix>_restore_state`` on the handle in ``_state_handle``."""

    _state_prefix = ""
    _state_handle_attr = "_handle"

    def _state_handle(self):
        return getattr(self, self._state_handle_attr)

    def save_state(self) -> bytes:
        """The estimator's full mutable state (current set, step counter, last gain, working
        sets, windows) as bytes: restored into an estimator made from the same design and
        arguments (``restore_state``) it continues bit-for-bit as this one."""
        h = self._state_handle()
        n = ffi.new("int*")
        check(getattr(lib, self._state_prefix + "_state_size")(h, n))
        buf = np.empty(int(n[0]), dtype=np.float64)
        check(getattr(lib, self._state_prefix + "_save_state")(h, dptr(buf), buf.size))
        return buf.astype("<f8", copy=False).tobytes()

    def restore_state(self, state) -> None:
        """Restores a state returned by ``save_state`` of an estimator of the same kind and
        design. A corrupted state, one of another estimator kind or design raises
        ``InvalidArgumentError`` (message starting with ``state``) and leaves this one unchanged."""
        if isinstance(state, np.ndarray):
            state = state.tobytes()
        if not isinstance(state, (bytes, bytearray, memoryview)):
            raise InvalidArgumentError(f"state: expected bytes (from save_state), got {type(state).__name__}")
        raw = bytes(state)
        if len(raw) % 8 != 0:
            raise InvalidArgumentError(f"state: {len(raw)} bytes is not a whole number of float64 values (truncated)")
        buf = np.frombuffer(raw, dtype="<f8").astype(np.float64)
        check(getattr(lib, self._state_prefix + "_restore_state")(self._state_handle(), dptr(buf), buf.size))
        self._after_restore()

    def _after_restore(self) -> None:
        """Refreshes values cached on the Python side (overridden where there are some)."""
