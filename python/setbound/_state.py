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

Sharing between threads (:class:`ThreadSafe`, the base of :class:`StateMixin` and of
``lmi.Problem``): cffi releases the GIL during every C call, so two Python threads stepping one
estimator ran its C++ step concurrently on the same object and crashed (issue 26). Every public
method and property of such a class holds the object's own re-entrant lock for the whole call:
one object is stepped by one thread at a time, in the order the lock admits them; different
objects never wait for each other (no global lock) and the GIL stays released inside C.
"""

from __future__ import annotations

import functools
import inspect
import threading

import numpy as np

from ._native import check, dptr, ffi, lib
from .errors import DimensionError, InvalidArgumentError

__all__ = ["reconstructible", "remember_call", "run_from_initial_set", "StateMixin", "ThreadSafe"]


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


def _picklable(value):
    """A construction argument as pickle can store it: a python-control ``StateSpace`` (whose
    instances hold local lambdas) becomes the :class:`~setbound.LinearSystem` the estimator made
    of it (the same model, so the rebuilt estimator is the same)."""
    from .system import _is_statespace, as_system

    return as_system(value) if _is_statespace(value) else value


def _reduce(self):
    args, kwargs = _ctor_of(self)
    args = tuple(_picklable(a) for a in args)
    kwargs = {k: _picklable(v) for k, v in kwargs.items()}
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
        outermost = "_ctor" not in self.__dict__
        if outermost:
            self.__dict__["_ctor"] = (args, dict(kwargs))
        init(self, *args, **kwargs)
        if outermost and isinstance(self, StateMixin) and "_initial_state" not in self.__dict__:
            # the state of construction, for reset() (and run()): a twin built again would
            # repeat a design made inside the library (e.g. the H∞ gain of an interval
            # observer built without L: seconds on tank30, once per run)
            self.__dict__["_initial_state"] = self.save_state()

    cls.__init__ = __init__
    if "__reduce__" not in cls.__dict__:
        cls.__reduce__ = _reduce
    cls.__copy__ = _copy
    cls.__deepcopy__ = _deepcopy
    return cls


def _is_time_response(obj) -> bool:
    return all(hasattr(obj, a) for a in ("time", "outputs", "inputs")) and not isinstance(obj, np.ndarray)


def _from_time_response(self, resp, u):
    """``(y, u, t)`` of a python-control ``TimeResponseData`` (signals on the last axis): the
    outputs, the known inputs (the inputs whose label does not start with ``w``: those are the
    disturbances, the convention of :func:`setbound.system.as_system`) unless ``u`` is given,
    and the time."""
    t = np.asarray(resp.time, dtype=float).ravel()
    y = np.asarray(resp.outputs, dtype=float)
    y = y.reshape(1, -1) if y.ndim == 1 else y.reshape(y.shape[0], -1)
    y = y.T
    system = getattr(self, "system", None)
    nu = getattr(system, "nu", 0) or 0
    if u is None and nu:
        ins = np.asarray(resp.inputs, dtype=float)
        ins = (ins.reshape(1, -1) if ins.ndim == 1 else ins.reshape(ins.shape[0], -1)).T
        labels = list(getattr(resp, "input_labels", None) or [])
        known = [i for i, name in enumerate(labels) if not str(name).startswith("w")] if labels else \
            list(range(ins.shape[1]))
        if len(known) != nu:
            raise InvalidArgumentError(f"y: the TimeResponseData has {len(known)} known inputs (inputs not labelled "
                                       f"'w…'), the system {nu}; pass u= explicitly")
        u = ins[:, known]
    return y, u, t


def run_from_initial_set(run):
    """Decorator of an estimator's ``run``: adds the keyword ``reset`` (default True: start from
    the initial set, so the same record always gives the same result; False: continue from the
    current state, to process a record in pieces) and makes the call atomic: when it fails, the
    estimator is left as it was before the call. ``y`` may be a python-control
    ``TimeResponseData`` (outputs, known inputs and time taken from it); ``t=`` gives the time of
    the rows. The trajectory's ``t`` is that time, else ``k·dt`` with the system's sampling
    time, else the step index."""
    @functools.wraps(run)
    def wrapper(self, y=None, u=None, *args, reset: bool = True, t=None, **kwargs):
        if _is_time_response(y):
            y, u, t_resp = _from_time_response(self, y, u)
            t = t_resp if t is None else t
        before = self.save_state()
        if reset:
            self.reset()
        try:
            traj = run(self, y, u, *args, **kwargs)
        except BaseException:
            self.restore_state(before)
            raise
        if hasattr(traj, "center") and hasattr(traj, "t"):
            if getattr(traj, "filter", None) is None and hasattr(self, "is_filter"):
                traj.filter = bool(self.is_filter)  # whether row k used y_k
            N = len(traj.center)
            if t is not None:
                t = np.asarray(t, dtype=float).ravel()
                if t.shape != (N,):
                    self.restore_state(before)
                    raise DimensionError(f"t: expected {N} time values (one per row), got {t.shape[0]}")
                traj.t = t
            elif traj.t is None:
                system = getattr(self, "system", None) or getattr(self, "plant", None)
                dt = getattr(system, "dt", None)
                traj.t = np.arange(N, dtype=float) * (dt if dt else 1.0)
        return traj
    return wrapper


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


# Dunder methods that read or change the object's state are locked like public methods; the
# pickling/copy hooks need no lock of their own (they read the state with one save_state call,
# which is locked, and the construction arguments, which never change).
_LOCKED_DUNDERS = frozenset({"__call__", "__repr__", "__str__", "__len__", "__iter__", "__next__",
                             "__contains__", "__getitem__", "__setitem__"})
_LOCKED_MARK = "_sb_locked"


def _locked_function(fn):
    """``fn`` (a method) run under its object's lock. A generator method holds the lock while it
    computes each item, not while the caller holds the generator: a generator kept open across a
    whole loop would otherwise block every other thread on the object until it is exhausted."""
    if getattr(fn, _LOCKED_MARK, False):
        return fn
    if inspect.isgeneratorfunction(fn):
        @functools.wraps(fn)
        def locked(self, *args, **kwargs):
            gen = fn(self, *args, **kwargs)  # runs no code of fn yet
            while True:
                with self._sb_lock:
                    try:
                        item = next(gen)
                    except StopIteration as stop:
                        return stop.value
                yield item
    elif inspect.isasyncgenfunction(fn) or inspect.iscoroutinefunction(fn):
        raise TypeError(f"{fn.__qualname__}: async methods cannot hold the per-object thread lock")
    else:
        @functools.wraps(fn)
        def locked(self, *args, **kwargs):
            with self._sb_lock:
                return fn(self, *args, **kwargs)
    setattr(locked, _LOCKED_MARK, True)
    return locked


def _locked_member(value):
    """The locked version of a class attribute, or the attribute itself when it needs no lock
    (data, static and class methods: they do not touch an instance)."""
    if inspect.isfunction(value):
        return _locked_function(value)
    if isinstance(value, property):
        return property(*(None if f is None else _locked_function(f) for f in (value.fget, value.fset, value.fdel)),
                        value.__doc__)
    if isinstance(value, functools.cached_property):
        # its first computation would run unlocked (and a lock would not make it thread-safe):
        # refuse it at class creation rather than leave one unguarded path into the handle
        raise TypeError(f"{value.attrname}: cached_property is not supported on a ThreadSafe class; use a property")
    return value


class ThreadSafe:
    """Base of every Python object that holds a mutable C handle (estimators, observers, filters,
    ``lmi.Problem``): one object may be shared by several threads.

    Why a lock: cffi releases the GIL during each C call, and the C ABI leaves the serialisation
    of calls on one handle to its user (docs/c_api.md, "Threads"). Every public method and
    property (and the dunders in ``_LOCKED_DUNDERS``) of a subclass runs under the object's own
    ``threading.RLock``, made in ``__new__`` so that every instance has one however it was made
    (constructor, unpickling, copy). Re-entrant because locked methods call each other (``run``
    calls ``step``, ``restore_state`` of a subclass calls the base one, a nonlinearity callable
    may read the observer it is called from). Private helpers (``_step``) are not locked: they
    are only called from locked public methods. Cost: one RLock acquire/release and one wrapper
    call per public call, about 2.5 times an empty Python method call (bench/bench_lock.py:
    0.44 µs on the loaded 2-core CI machine, where an empty method call took 0.18 µs).
    A public method of a subclass must therefore never wait for *another* thread that uses the
    same object (that would deadlock)."""

    def __new__(cls, *args, **kwargs):
        obj = super().__new__(cls)
        obj._sb_lock = threading.RLock()
        return obj

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        _lock_members(cls)


def _lock_members(cls) -> None:
    """Replaces the public methods and properties defined in ``cls`` itself (inherited ones are
    already locked in their own class) by locked versions."""
    for name, value in list(vars(cls).items()):
        if name.startswith("_") and name not in _LOCKED_DUNDERS:
            continue
        locked = _locked_member(value)
        if locked is not value:
            setattr(cls, name, locked)


class StateMixin(ThreadSafe):
    """``save_state()`` / ``restore_state()`` through the C functions ``<prefix>_state_size``,
    ``<prefix>_save_state`` and ``<prefix>_restore_state`` on the handle in ``_state_handle``."""

    _state_prefix = ""
    _state_handle_attr = "_handle"

    def _state_handle(self):
        return getattr(self, self._state_handle_attr)

    @property
    def current_k(self) -> int | None:
        """Which time the current set — the set the last ``step()`` returned — bounds: the index k
        of ``x_k``, as row k of a trajectory. A predictor (``is_filter`` False) after k steps bounds
        ``x_k`` (it has used ``y_0 … y_{k−1}``); a filter's step with ``y_k`` bounds ``x_k`` (None
        before its first step)."""
        steps = self.steps
        if getattr(self, "is_filter", False):
            return None if steps == 0 else steps - 1
        return steps

    @property
    def current_t(self) -> float | None:
        """The time of :attr:`current_k`: ``k·dt`` with the system's sampling time ``dt``, else k
        (None when ``current_k`` is None)."""
        k = self.current_k
        if k is None:
            return None
        system = getattr(self, "system", None) or getattr(self, "plant", None)
        dt = getattr(system, "dt", None)
        return float(k) * (dt if dt else 1.0)

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
        """Restore a state returned by ``save_state`` of an estimator of the same kind and design.

        A corrupted state, one of another estimator kind or design raises ``InvalidArgumentError``
        (message starting with ``state``) and leaves this one unchanged.

        Parameters
        ----------
        state : bytes
            The saved state.
        """
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

    def reset(self) -> None:
        """Back to the state of construction: the initial set, no step taken (``run()`` starts
        with it, so the same record always gives the same result)."""
        state = self.__dict__.get("_initial_state")  # recorded by @reconstructible
        if state is None:
            # a twin made with the same construction arguments (designs are immutable objects,
            # so this does not design again) gives the state of construction; kept for later
            args, kwargs = _ctor_of(self)
            state = type(self)(*args, **kwargs).save_state()
            self.__dict__["_initial_state"] = state
        self.restore_state(state)

    def _after_restore(self) -> None:
        """Refreshes values cached on the Python side (overridden where there are some)."""


_lock_members(StateMixin)  # save_state / restore_state (__init_subclass__ runs for subclasses only)
