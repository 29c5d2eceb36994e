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
    """What one step did with each output: ``status`` (n_y ints: :data:`USED`, :data:`MISSING`,
    :data:`INCONSISTENT`, :data:`UNUSED`), ``margin`` (n_y floats, see the module docstring) and
    ``reset`` (the step restarted from the reset set; statuses and margins are then those of
    the test that triggered it)."""

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
    """``y`` itself, or ``n_y`` NaN (every output missing) when ``y`` is None."""
    return np.full(ny, np.nan) if y is None else y


class ReadingChecks:
    """Mixin of the estimators that screen their readings through the C ABI: ``_last_check_fn`` is
    their ``sb_*_last_check`` function, ``_handle`` the C object, ``system`` the model; call
    :meth:`_init_checks` once the handle exists."""

    _last_check_fn = None

    def _init_checks(self) -> None:
        self._status = ffi.new("int[]", max(self.system.ny, 1))
        self._reset_flag = ffi.new("int*")

    def _check_into(self, status, margin) -> bool:
        """Writes the last step's statuses and margins into the given rows; returns the reset flag."""
        check(type(self)._last_check_fn(self._handle, self._status, dptr(margin), self._reset_flag))
        ny = self.system.ny
        status[:] = np.frombuffer(ffi.buffer(self._status, 4 * max(ny, 1)), dtype=np.intc)[:ny]
        return bool(self._reset_flag[0])

    @property
    def last_check(self) -> MeasurementCheck:
        """What the last step did with each output of ``y_k`` (:class:`MeasurementCheck`)."""
        ny = self.system.ny
        status, margin = np.empty(ny, dtype=np.int8), np.empty(ny)
        reset = self._check_into(status, margin)
        return MeasurementCheck(status, margin, reset)
