"""The plant of the thesis methods (Methods › H∞ set-membership observers › Model), in the thesis's own letters.

``x⁺ = A x + B u + F d``, ``y = C x + Z v``, ``w = (d, v)`` with ``m = n_d + n_v``. The
thesis's ``F`` (state disturbance) is passed as ``Fd=`` so it cannot be confused with
:class:`~setbound.LinearSystem`'s ``F`` (output noise); ``plant.F`` reads it back.
The disturbances are bounded by boxes ``d ∈ [d]``, ``v ∈ [v]`` (Ch. 4) or by the 2-norm
bound ``wᵀw ≤ w̄ᵀw̄`` (Ch. 1–3, ``w̄`` the vector of box half-widths). The error of a
Luenberger observer with gain ``L`` obeys ``e⁺ = (A − LC) e + E w`` with ``E = [F, −LZ]``.

This is the advanced form: every thesis function and observer also takes the library's
:class:`~setbound.LinearSystem` (or a python-control ``StateSpace``) and converts it with
:func:`as_plant` (``d`` = the ω components that drive the state, ``v`` = those that drive the
outputs, each in the unit box), with an error naming the reason when it cannot be converted (a
component that drives both, a ``D`` term, an interval ``A``).
"""
from __future__ import annotations

import numpy as np

from ._native import as_f64
from ._validate import as_float
from .errors import DimensionError, InvalidArgumentError, NotFiniteError


def _finite(a: np.ndarray, name: str) -> np.ndarray:
    bad = np.argwhere(~np.isfinite(a))
    if bad.size:
        idx = tuple(int(i) for i in bad[0])
        raise NotFiniteError(f"{name}: entry {idx} is {a[idx]}; all entries must be finite")
    return a


class Plant:
    """The thesis's plant ``x⁺ = A x + B u + F d``, ``y = C x + Z v``, ``d`` and ``v`` bounded.

    The thesis's ``F`` is given as ``Fd=`` (Methods › H∞ set-membership observers › Model).

    Parameters
    ----------
    A : array_like, shape (n_x, n_x)
        State matrix.
    C : array_like, shape (n_y, n_x)
        Output matrix.
    B : array_like, shape (n_x, n_u), optional
        Input matrix (default: no input).
    Fd : array_like, shape (n_x, n_d), optional
        State-disturbance matrix (default: none).
    Z : array_like, shape (n_y, n_v), optional
        Measurement-noise matrix (default: none).
    dt : float, optional
        Sampling time (None: unknown; results are then indexed by the step), kept from a converted
        ``LinearSystem``.
    **wrong
        Refused: ``F=`` gets a message pointing to ``Fd=``; any other keyword is a TypeError.

    Examples
    --------
    >>> plant = setbound.Plant([[0.2, 0.2], [0.0, 0.5]], [[1.0, 0.0]], B=[[1.0], [1.0]], Fd=[[0.0], [0.1]], Z=[[0.1]])
    >>> plant.nx, plant.ny, plant.nd, plant.nv
    (2, 1, 1, 1)
    """

    def __init__(self, A, C, *, B=None, Fd=None, Z=None, dt=None, **wrong):
        if "F" in wrong:
            raise InvalidArgumentError(
                "F: a Plant's state-disturbance matrix is passed as Fd= (x+ = A x + B u + Fd d); F is the "
                "output-noise matrix of setbound.LinearSystem. To use a LinearSystem, pass it directly or "
                "convert it with Plant.from_linear_system")
        if wrong:
            raise TypeError(f"Plant() got unexpected keyword arguments {sorted(wrong)}")
        F = Fd
        A = _finite(as_f64(A, "A", ndim=2), "A")
        n = A.shape[0]
        if n == 0 or A.shape != (n, n):
            raise DimensionError(f"A: must be square with n_x >= 1, got shape {A.shape}")
        C = _finite(as_f64(C, "C", shape=(None, n)), "C")
        if C.shape[0] == 0:
            raise DimensionError("C: the plant needs at least one output")
        ny = C.shape[0]
        B = np.zeros((n, 0)) if B is None else _finite(as_f64(B, "B", shape=(n, None)), "B")
        F = np.zeros((n, 0)) if F is None else _finite(as_f64(F, "F", shape=(n, None)), "F")
        Z = np.zeros((ny, 0)) if Z is None else _finite(as_f64(Z, "Z", shape=(ny, None)), "Z")
        if F.shape[1] + Z.shape[1] == 0:
            raise DimensionError("F, Z: the plant has no disturbance (n_d + n_v = 0)")
        self.A, self.B, self.C, self.Fd, self.Z = A, B, C, F, Z
        if dt is not None:
            dt = as_float(dt, "dt")
            if not dt > 0:
                raise InvalidArgumentError(f"dt: the sampling time must be > 0, got {dt}")
        self.dt = dt

    F = property(lambda self: self.Fd, doc="The thesis's F: the state-disturbance matrix (given as Fd=).")

    nx = property(lambda self: self.A.shape[0], doc="State dimension.")
    nu = property(lambda self: self.B.shape[1], doc="Number of known inputs.")
    ny = property(lambda self: self.C.shape[0], doc="Number of outputs.")
    nd = property(lambda self: self.F.shape[1], doc="Number of state disturbances (columns of F).")
    nv = property(lambda self: self.Z.shape[1], doc="Number of measurement noises (columns of Z).")
    m = property(lambda self: self.F.shape[1] + self.Z.shape[1], doc="nd + nv, the length of the stacked uncertainty.")

    def error_input(self, L) -> np.ndarray:
        """The error-input matrix ``E = [F, −L Z]`` of the observer error ``e⁺ = (A − LC) e + E [d; v]``.

        Parameters
        ----------
        L : array_like, shape (n_x, n_y)
            Observer gain.

        Returns
        -------
        ndarray, shape (n_x, n_d + n_v)
        """
        L = as_f64(L, "L", shape=(self.nx, self.ny))
        return np.hstack([self.F, -L @ self.Z])

    @classmethod
    def from_linear_system(cls, system) -> "Plant":
        """The plant of a :class:`~setbound.system.LinearSystem`.

        Each ω component must drive either the state (a column of ``E``) or the output (a column of
        ``F``), not both: ``d`` = the state columns, ``v`` = the output columns, each bounded by the
        unit box.

        Parameters
        ----------
        system : LinearSystem
            The system to convert.

        Returns
        -------
        Plant
        """
        E, Fo = np.asarray(system.E), np.asarray(system.F)
        if system.uncertain_A:
            raise DimensionError("system: the thesis plant has a known A (no interval A)")
        if np.any(system.D != 0):
            raise DimensionError("system: D must be zero (the thesis output is y = C x + Z v)")
        state = np.any(E != 0, axis=0)
        output = np.any(Fo != 0, axis=0)
        both = np.flatnonzero(state & output)
        if both.size:
            raise DimensionError(f"system: disturbance components {both.tolist()} drive both the state and "
                                 "the output; the thesis plant needs independent d and v")
        return cls(system.A, system.C, B=system.B if system.nu else None, Fd=E[:, state], Z=Fo[:, output & ~state],
                   dt=getattr(system, "dt", None))

    def unit_boxes(self):
        """The boxes ``[d] = [−1, 1]^{n_d}`` and ``[v] = [−1, 1]^{n_v}`` of a plant made from a
        :class:`~setbound.LinearSystem` (its ω is the unit box)."""
        from .interval import Box

        return Box(-np.ones(self.nd), np.ones(self.nd)), Box(-np.ones(self.nv), np.ones(self.nv))

    def __repr__(self) -> str:
        return f"Plant(n_x={self.nx}, n_u={self.nu}, n_y={self.ny}, n_d={self.nd}, n_v={self.nv})"


def as_plant(system) -> Plant:
    """The thesis plant of ``system``.

    A :class:`Plant` is returned unchanged; a :class:`~setbound.system.LinearSystem` or a
    python-control ``StateSpace`` (see :func:`setbound.system.as_system`) is converted by
    :meth:`Plant.from_linear_system` (unit-box ``d`` and ``v``); anything else, or a system that
    cannot be converted, is an error naming the argument (``plant``) and the reason.

    Parameters
    ----------
    system : Plant, LinearSystem or control.StateSpace
        The system.

    Returns
    -------
    Plant

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.5]], C=[[1.0]], E=[[0.1, 0.0]], F=[[0.0, 0.2]])
    >>> p = setbound.plant.as_plant(sys)
    >>> p.nd, p.nv
    (1, 1)
    """
    name = "plant"
    if isinstance(system, Plant):
        return system
    from .system import LinearSystem, _is_statespace, as_system

    if _is_statespace(system):
        system = as_system(system)
    if isinstance(system, LinearSystem):
        try:
            return Plant.from_linear_system(system)
        except DimensionError as exc:
            msg = str(exc)
            raise DimensionError(f"{name}: cannot use this LinearSystem with the thesis methods: "
                                 f"{msg.split(': ', 1)[1] if msg.startswith('system: ') else msg}") from None
    raise InvalidArgumentError(f"{name}: expected a setbound.Plant, a setbound.LinearSystem or a discrete-time "
                               f"control.StateSpace, got {type(system).__name__}")
