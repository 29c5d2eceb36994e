"""Missing and impossible readings (issue 24; C++ ``estimators/measurement_check.hpp``).

A guaranteed estimator holds a set ``X`` containing every state consistent with the model, the
bounds and the data so far, so output ``i`` lies in the *predicted output set*
``c_iᵀX + D_i u ± φ_i``. A reading outside it cannot come from any state of the model: the
estimator never uses it (intersecting with it would "correct" with an empty set and lose the
true state) and reports it, with its *margin*: the distance from the predicted output set in
units of the output's noise bound ``φ_i`` (absolute when ``φ_i = 0``); ``> 0`` outside, ``<= 0``
inside, NaN when the output was missing or not tested. Since ``X`` is an outer bound, a reported
inconsistency is a certificate that the model, the bounds or the data are wrong: no false alarm
while they hold. Rounding is accounted for.

A missing output is a NaN entry of ``y`` (``step(None)`` means "nothing measured").

Policies (``on_inconsistency=``): ``"flag"`` (default: skip the impossible outputs, use the
others, mark the step), ``"raise"`` (:class:`~setbound.errors.InconsistentMeasurementError`
naming the step and the output; the estimator is unchanged) and ``"reset"`` (restart from
``reset_set``, by default the initial set, corrected with the outputs consistent with it).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._native import check, dptr, ffi, lib

__all__ = ["MeasurementCheck", "POLICIES", "USED", "MISSING", "INCONSISTENT", "UNUSED", "measurement_or_missing",
           "ReadingChecks"]

#: Status codes of an output at one step (``MeasurementCheck.status``, ``Trajectory.status``).
USED, MISSING, INCONSISTENT, UNUSED = (lib.SB_OUTPUT_USED, lib.SB_OUTPUT_MISSING, lib.SB_OUTPUT_INCONSISTENT,
                                       lib.SB_OUTPUT_UNUSED)

#: ``on_inconsistency`` values and their C codes.
POLICIES = {"flag": lib.SB_ON_INCONSISTENCY_FLAG, "raise": lib.SB_ON_INCONSISTENCY_RAISE,
            "reset": lib.SB_ON_INCONSISTENCY_RESET}


@dataclass(frozen=True)
class MeasurementCheck:
    """What one step did with each output.

    Parameters
    ----------
    status : ndarray of int, shape (n_y,)
        :data:`USED`, :data:`MISSING`, :data:`INCONSISTENT` or :data:`UNUSED` per output.
    margin : ndarray, shape (n_y,)
        The margin of each reading (see the module docstring).
    reset : bool, optional
        The step restarted from the reset set; statuses and margins are then those of the test
        that triggered it.
    """

    status: np.ndarray
    margin: np.ndarray
    reset: bool = False

    @property
    def used(self) -> np.ndarray:
        """Per output: used in the correction."""
        return self.status == USED

    @property
    def missing(self) -> np.ndarray:
        """Per output: not measured (NaN)."""
        return self.status == MISSING

    @property
    def inconsistent(self) -> np.ndarray:
        """Per output: outside the predicted output set, not used."""
        return self.status == INCONSISTENT

    @property
    def flagged(self) -> bool:
        """Some output was impossible at this step."""
        return bool(np.any(self.status == INCONSISTENT))


def measurement_or_missing(y, ny: int):
    """``y`` itself, or ``n_y`` NaN (every output missing) when ``y`` is None.

    Parameters
    ----------
    y : array_like or None
        A measurement.
    ny : int
        Number of outputs.

    Returns
    -------
    array_like
    """
    return np.full(ny, np.nan) if y is None else y


class ReadingChecks:
    """Mixin of the estimators that screen their readings through the C ABI: ``_last_check_fn`` is
    their ``sb_*_last_check`` function, the attribute named ``_check_handle_attr`` (default
    ``_handle``) the C object, :meth:`_reading_ny` the number of outputs (default
    ``system.ny``); call :meth:`_init_checks` once the handle exists."""

    _last_check_fn = None
    _check_handle_attr = "_handle"

    def _reading_ny(self) -> int:
        return self.system.ny

    def _init_checks(self) -> None:
        self._status = ffi.new("int[]", max(self._reading_ny(), 1))
        self._reset_flag = ffi.new("int*")

    def _check_into(self, status, margin) -> bool:
        """Writes the last step's statuses and margins into the given rows; returns the reset flag."""
        check(type(self)._last_check_fn(getattr(self, self._check_handle_attr), self._status, dptr(margin),
                                        self._reset_flag))
        ny = self._reading_ny()
        status[:] = np.frombuffer(ffi.buffer(self._status, 4 * max(ny, 1)), dtype=np.intc)[:ny]
        return bool(self._reset_flag[0])

    @property
    def last_check(self) -> MeasurementCheck:
        """What the last step did with each output of ``y_k`` (:class:`MeasurementCheck`)."""
        ny = self._reading_ny()
        status, margin = np.empty(ny, dtype=np.int8), np.empty(ny)
        reset = self._check_into(status, margin)
        return MeasurementCheck(status, margin, reset)


def _set_box_policy(set_fn, handle, on_inconsistency: str, reset_set, nx: int) -> str:
    """Sets the policy of a thesis observer through ``set_fn`` (its
    ``sb_*_set_inconsistency_policy``): ``reset_set`` is any set (its interval hull is used) or
    None (the observer's initial box). Returns the validated policy name."""
    from ._validate import as_choice
    from .errors import DimensionError, InvalidArgumentError
    from .sets import as_box

    on_inconsistency = as_choice(on_inconsistency, "on_inconsistency", POLICIES)
    lo = hi = ffi.NULL
    if reset_set is not None:
        if on_inconsistency != "reset":
            raise InvalidArgumentError('reset_set: only used with on_inconsistency="reset"')
        box = as_box(reset_set, "reset_set")
        lo_a = np.ascontiguousarray(box.lo, dtype=np.float64)
        hi_a = np.ascontiguousarray(box.hi, dtype=np.float64)
        if lo_a.shape != (nx,):
            raise DimensionError(f"reset_set: expected a set of dimension {nx}, got {lo_a.shape[0]}")
        lo, hi = dptr(lo_a), dptr(hi_a)
    check(set_fn(handle, POLICIES[on_inconsistency], lo, hi))
    return on_inconsistency
