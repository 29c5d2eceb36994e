"""Exceptions raised by setbound.

Every failure reported by the C library becomes a :class:`SetboundError` subclass chosen
by the status code, carrying the library's message (which names the offending
argument). Input problems also derive from :class:`ValueError` so generic handlers work.
"""
from __future__ import annotations


class SetboundError(Exception):
    """Base class of all setbound errors; ``status`` is the C status code.

    Parameters
    ----------
    message : str
        The library's message (it names the offending argument).
    status : int, optional
        The C status code (default: the class's).

    Examples
    --------
    >>> try:
    ...     setbound.Ellipsoid([[1.0, 2.0], [0.0, 1.0]], [0.0, 0.0], 1.0)
    ... except setbound.SetboundError as e:
    ...     print(type(e).__name__, isinstance(e, ValueError))
    NotSymmetricError True
    """

    status: int = -10

    def __init__(self, message: str, status: int | None = None):
        super().__init__(message)
        self.message = message
        if status is not None:
            self.status = status


class InvalidArgumentError(SetboundError, ValueError):
    """A null handle, unknown option or out-of-range scalar."""

    status = -1


class DimensionError(SetboundError, ValueError):
    """Array shapes that do not fit together."""

    status = -2


class NotFiniteError(SetboundError, ValueError):
    """NaN or Inf where finite numbers are required."""

    status = -3


class NotSymmetricError(SetboundError, ValueError):
    """A matrix that must be symmetric is not."""

    status = -4


class NotPositiveDefiniteError(SetboundError, ValueError):
    """A matrix that must be positive definite is not."""

    status = -5


class InfeasibleError(SetboundError):
    """A design or an intersection has no solution."""

    status = -6


class NotDetectableError(SetboundError, ValueError):
    """Unobservable or undetectable pair, or a failed rank condition."""

    status = -7


class NumericalError(SetboundError, ArithmeticError):
    """Numerical breakdown (solver failure, ill-conditioning)."""

    status = -8


class BufferTooSmallError(SetboundError):
    """An output buffer was too small (internal to the bindings)."""

    status = -9


class InternalError(SetboundError):
    """A bug in setbound: please report it with the message."""

    status = -10


class InconsistentMeasurementError(SetboundError):
    """A measurement that no state of the model can produce (a fault, a glitch or a wrong
    model), raised under ``on_inconsistency="raise"``; the message names the step and the
    output."""

    status = -11


ERROR_BY_STATUS: dict[int, type[SetboundError]] = {
    cls.status: cls
    for cls in (
        InvalidArgumentError,
        DimensionError,
        NotFiniteError,
        NotSymmetricError,
        NotPositiveDefiniteError,
        InfeasibleError,
        NotDetectableError,
        NumericalError,
        BufferTooSmallError,
        InternalError,
        InconsistentMeasurementError,
    )
}

__all__ = ["SetboundError", "ERROR_BY_STATUS"] + [c.__name__ for c in ERROR_BY_STATUS.values()]
