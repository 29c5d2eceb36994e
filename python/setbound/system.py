"""System models: ``LinearSystem`` (Methods › Ellipsoidal estimation › Model).

``x⁺ = A x + B u + E ω``, ``y = C x + D u + F ω``, ``ω`` in the unit box ``[-1, 1]^{n_ω}``.
``A`` may be an :class:`~setbound.IntervalMatrix` (``A ∈ [A]``); the estimators then use
``mid[A]`` for the centre and account for every ``A ∈ [A]``.

The zonotopic papers' form ``x⁺ = A x + F_w ω``, ``y = C x + Φ v`` is
``LinearSystem(A, C, E=[F_w, 0], F=[0, Φ])``: stack the disturbances, ``ω = [w; v]``.

:func:`from_statespace` converts a discrete-time ``control.StateSpace`` (python-control).
"""
from __future__ import annotations

import numpy as np

from ._native import as_f64, check, dptr, ffi, lib
from ._validate import as_float, as_int
from .errors import DimensionError, InvalidArgumentError, NotFiniteError
from ._state import reconstructible
from .interval import IntervalMatrix


def refuse_missing(y, who: str) -> None:
    """Raise NotFiniteError naming the first NaN (missing) reading, for an estimator that needs every output.

    Parameters
    ----------
    y : ndarray, shape (n_y,) or (N, n_y)
        One step's or all measurements.
    who : str
        The estimator's class name (for the message).

    Raises
    ------
    NotFiniteError
    """
    bad = np.argwhere(np.isnan(y))
    if bad.size == 0:
        return
    where = f"row {bad[0][0]}, output {bad[0][1]}" if y.ndim == 2 else f"output {bad[0][0]}"
    raise NotFiniteError(f"y: {where} is NaN (a missing reading): {who} needs every output at every step; the "
                         "other estimators accept missing readings (docs/user_guide.md, \"Real measurement data\")")


def refuse_infinite(y) -> None:
    """Raise NotFiniteError naming the row and output of the first ±inf reading (NaN is a missing reading and passes).

    Parameters
    ----------
    y : ndarray, shape (N, n_y)
        Measurements.

    Raises
    ------
    NotFiniteError
    """
    bad = np.argwhere(np.isinf(y))
    if bad.size:
        r, i = (int(v) for v in bad[0])
        raise NotFiniteError(f"y: row {r}, output {i} is {y[r, i]}; a reading must be finite (NaN marks a "
                             "missing one)")


def step_inputs(system, y, u):
    """One measurement and input, checked against ``system``.

    Parameters
    ----------
    system : LinearSystem or DescriptorSystem
        The system the data are checked against.
    y : array_like, shape (n_y,)
        Measurement.
    u : array_like, shape (n_u,), optional
        Input (None without inputs).

    Returns
    -------
    y : ndarray
    u_ptr : cffi pointer
        A C pointer to ``u``, or NULL.
    """
    y = as_f64(y, "y", shape=(system.ny,))
    if system.nu > 0:
        if u is None:
            raise InvalidArgumentError(f"u: the system has {system.nu} inputs; an input is required")
        u = as_f64(u, "u", shape=(system.nu,))
        return y, dptr(u)
    if u is not None and np.size(u) != 0:
        raise DimensionError("u: the system has no input")
    return y, ffi.NULL


def run_inputs(system, y, u):
    """Measurements and inputs of a run, checked against ``system``.

    Parameters
    ----------
    system : LinearSystem or DescriptorSystem
        The system the data are checked against.
    y : array_like, shape (N, n_y)
        Measurements.
    u : array_like, shape (N, n_u), optional
        Inputs (None without inputs).

    Returns
    -------
    y, u : ndarray
        ``u`` is None when the system has no input.
    """
    y = as_f64(y, "y", shape=(None, system.ny))
    refuse_infinite(y)
    if system.nu > 0:
        return y, as_f64(u, "u", shape=(y.shape[0], system.nu))
    if u is not None and np.size(u) != 0:
        raise DimensionError("u: the system has no input")
    return y, None


@reconstructible
class LinearSystem:
    """A discrete-time linear model with unit-box disturbances (validated by the C library).

    ``x⁺ = A x + B u + E ω``, ``y = C x + D u + F ω``, every component of ``ω`` in ``[-1, 1]``
    (Methods › Ellipsoidal estimation › Model). ``A`` may be an
    :class:`~setbound.interval.IntervalMatrix` (a system whose matrix is any element of it).

    Parameters
    ----------
    A : array_like or IntervalMatrix, shape (n_x, n_x)
        State matrix.
    C : array_like, shape (n_y, n_x)
        Output matrix.
    B : array_like, shape (n_x, n_u), optional
        Input matrix (default: no input).
    D : array_like, shape (n_y, n_u), optional
        Feedthrough of the input (default: zero).
    E : array_like, shape (n_x, n_ω)
        Disturbance matrix of the state equation.
    F : array_like, shape (n_y, n_ω)
        Disturbance matrix of the output equation.
    dt : float, optional
        Sampling time (> 0), used for the time of each trajectory row; None: results are indexed by
        the step.

    Examples
    --------
    >>> sys = setbound.LinearSystem(A=[[0.9, 0.2], [0.0, 0.7]], C=[[1.0, 0.0]],
    ...                             E=[[0.1, 0.0], [0.0, 0.0]], F=[[0.0, 0.05]])
    >>> sys.nx, sys.ny, sys.nw
    (2, 1, 2)
    >>> sys.is_detectable()
    True
    """

    def __init__(self, A, C, *, B=None, D=None, E, F, dt=None):
        if dt is not None:
            dt = as_float(dt, "dt", lo=0.0, lo_open=True)
        if isinstance(A, IntervalMatrix):
            A_mid = as_f64(A.mid, "A", ndim=2)
            A_rad = as_f64(A.rad, "A", shape=A_mid.shape)
        else:
            A_mid = as_f64(A, "A", ndim=2)
            A_rad = None
        nx = A_mid.shape[0]
        if A_mid.shape != (nx, nx):
            raise DimensionError(f"A: must be square, got shape {A_mid.shape}")
        C = as_f64(C, "C", shape=(None, nx))
        ny = C.shape[0]
        E = as_f64(E, "E", shape=(nx, None))
        F = as_f64(F, "F", shape=(ny, E.shape[1]))
        nw = E.shape[1]
        if B is None:
            if D is not None:
                raise InvalidArgumentError("D: given without B (there is no input)")
            nu = 0
        else:
            B = as_f64(B, "B", shape=(nx, None))
            nu = B.shape[1]
            if D is not None:
                D = as_f64(D, "D", shape=(ny, nu))
        handle = ffi.new("sb_linear_system**")
        check(lib.sb_linear_system_create(
            nx, ny, nu, nw, dptr(A_mid), dptr(B) if B is not None else ffi.NULL, dptr(C),
            dptr(D) if D is not None else ffi.NULL, dptr(E), dptr(F),
            dptr(A_rad) if A_rad is not None else ffi.NULL, handle))
        self._handle = ffi.gc(handle[0], lib.sb_linear_system_free)
        self.A = A_mid
        self.A_rad = A_rad if A_rad is not None else np.zeros_like(A_mid)
        self.B = B if B is not None else np.zeros((nx, 0))
        self.C, self.E, self.F = C, E, F
        self.D = D if D is not None else np.zeros((ny, nu))
        for a in (self.A, self.A_rad, self.B, self.C, self.D, self.E, self.F):
            a.flags.writeable = False  # the C library holds its own copy; keep both in step
        self.dt = dt

    @property
    def nx(self) -> int:
        """State dimension."""
        return self.A.shape[0]

    @property
    def ny(self) -> int:
        """Number of outputs."""
        return self.C.shape[0]

    @property
    def nu(self) -> int:
        """Number of known inputs (0 without B)."""
        return self.B.shape[1]

    @property
    def nw(self) -> int:
        """Number of unit-box disturbances ω."""
        return self.E.shape[1]

    @property
    def uncertain_A(self) -> bool:
        """True when A is an interval matrix with a nonzero radius."""
        return bool(np.any(self.A_rad > 0))

    @property
    def A_interval(self) -> IntervalMatrix:
        """The interval matrix [A] = [A − A_rad, A + A_rad]."""
        return IntervalMatrix.from_mid_rad(self.A, self.A_rad)

    def is_detectable(self) -> bool:
        """PBH test of ``(C, mid[A])``: every eigenvalue of ``mid[A]`` with modulus >= 1 is seen by ``C``.

        Returns
        -------
        bool
        """
        return is_detectable(self.A, self.C)

    def __repr__(self) -> str:
        unc = ", interval A" if self.uncertain_A else ""
        return f"LinearSystem(nx={self.nx}, ny={self.ny}, nu={self.nu}, nw={self.nw}{unc})"


def is_detectable(A, C) -> bool:
    """PBH test: every eigenvalue of ``A`` with modulus >= 1 is seen by ``C``.

    Parameters
    ----------
    A : array_like, shape (n, n)
        State matrix.
    C : array_like, shape (p, n)
        Output matrix.

    Returns
    -------
    bool

    Examples
    --------
    >>> setbound.is_detectable([[1.0, 1.0], [0.0, 1.0]], [[1.0, 0.0]])
    True
    """
    A = as_f64(A, "A", ndim=2)
    C = as_f64(C, "C", shape=(None, A.shape[0]))
    out = ffi.new("int*")
    check(lib.sb_check_detectability(A.shape[0], C.shape[0], dptr(A), dptr(C), out, ffi.NULL, ffi.NULL))
    return bool(out[0])


@reconstructible
class DescriptorSystem:
    """A descriptor model ``E x⁺ = A x + B u + D w``, ``y = C x + F w``, ``w`` in the unit box.

    ``E`` may be singular; the rank conditions (infinite and finite observability) are checked at
    construction and a failure names the condition. ``T`` and ``N`` (``T E + N C = I``,
    ``[T N] = pinv([E; C])``) are exposed (Methods › Ellipsoidal estimation › Descriptor systems).

    Note the letters: here ``E`` is the descriptor matrix and ``D`` the disturbance matrix,
    as in [Merhy2019], unlike :class:`LinearSystem`.

    Parameters
    ----------
    E : array_like, shape (n_x, n_x)
        Descriptor matrix (may be singular).
    A : array_like, shape (n_x, n_x)
        State matrix.
    C : array_like, shape (n_y, n_x)
        Output matrix.
    B : array_like, shape (n_x, n_u), optional
        Input matrix (default: no input).
    D : array_like, shape (n_x, n_w)
        Disturbance matrix of the state equation.
    F : array_like, shape (n_y, n_w)
        Disturbance matrix of the output equation.

    Raises
    ------
    NotDetectableError
        When a rank condition fails (the message names it).

    Examples
    --------
    The example of [Merhy2019] (singular ``E``):

    >>> E = [[1, 0, 0], [0, 1, 0], [0, 0, 0]]
    >>> A = [[0.5, 0, 0], [0.8, 0.95, 0], [-1, 0.5, 1]]
    >>> C = [[1, 0, 1], [1, -1, 0]]
    >>> D = np.hstack([np.diag([0.1, 1.5, 0.6]), np.zeros((3, 2))])
    >>> F = np.hstack([np.zeros((2, 3)), np.diag([0.5, 1.5])])
    >>> ds = setbound.DescriptorSystem(E, A, C, B=[[1, 0], [0, 1], [0, 0]], D=D, F=F)
    >>> bool(np.allclose(ds.T @ np.asarray(E) + ds.N @ np.asarray(C), np.eye(3)))
    True
    """

    def __init__(self, E, A, C, *, B=None, D, F):
        A = as_f64(A, "A", ndim=2)
        nx = A.shape[0]
        if A.shape != (nx, nx):
            raise DimensionError(f"A: must be square, got shape {A.shape}")
        E = as_f64(E, "E", shape=(nx, nx))
        C = as_f64(C, "C", shape=(None, nx))
        ny = C.shape[0]
        D = as_f64(D, "D", shape=(nx, None))
        nw = D.shape[1]
        F = as_f64(F, "F", shape=(ny, nw))
        if B is None:
            B = np.zeros((nx, 0))
        else:
            B = as_f64(B, "B", shape=(nx, None))
        nu = B.shape[1]
        handle = ffi.new("sb_descriptor_system**")
        check(lib.sb_descriptor_system_create(nx, ny, nu, nw, dptr(E), dptr(A),
                                              dptr(B) if nu > 0 else ffi.NULL, dptr(C), dptr(D), dptr(F), handle))
        self._handle = ffi.gc(handle[0], lib.sb_descriptor_system_free)
        self.E, self.A, self.B, self.C, self.D, self.F = E, A, B, C, D, F
        T, N = np.empty((nx, nx)), np.empty((nx, ny))
        check(lib.sb_descriptor_system_tn(self._handle, dptr(T), dptr(N)))
        self.T, self.N = T, N
        for a in (self.E, self.A, self.B, self.C, self.D, self.F, self.T, self.N):
            a.flags.writeable = False

    nx = property(lambda self: self.A.shape[0], doc="State dimension.")
    ny = property(lambda self: self.C.shape[0], doc="Number of outputs.")
    nu = property(lambda self: self.B.shape[1], doc="Number of known inputs.")
    nw = property(lambda self: self.D.shape[1], doc="Number of unit-box disturbances w.")

    def __repr__(self) -> str:
        return f"DescriptorSystem(nx={self.nx}, ny={self.ny}, nu={self.nu}, nw={self.nw})"


def from_statespace(ss, *, E=None, F=None, disturbance_inputs=None, output_noise=None) -> LinearSystem:
    """A :class:`LinearSystem` from a discrete-time ``control.StateSpace``.

    Any object with ``A``, ``B``, ``C``, ``D`` and a sampling time ``dt`` that is not None or 0 is
    accepted. A state-space model carries no disturbance description, so say which unit-box
    disturbances ``ω`` act (at least one is required).

    Parameters
    ----------
    ss : control.StateSpace
        The discrete-time model.
    E, F : array_like, optional
        Extra disturbance columns (``E`` n_x × m, ``F`` n_y × m; a missing one is zero).
    disturbance_inputs : sequence of int, optional
        Indices of inputs of ``ss`` that are bounded disturbances (``|ω_i| ≤ 1``): their columns of
        ``B`` and ``D`` become columns of ``E`` and ``F``; the other inputs stay known inputs ``u``.
    output_noise : float or array_like, optional
        A bound ``φ`` (scalar, or one per output) of the measurement noise ``|v_i| ≤ φ_i``,
        appended as columns ``[0; diag(φ)]``.

    Returns
    -------
    LinearSystem

    Examples
    --------
    ``from_statespace(control.ss(A, B, C, 0, dt=0.1), disturbance_inputs=[0], output_noise=0.2)``
    is ``x⁺ = A x + B ω₀``, ``y = C x + 0.2 v``.
    """
    for attr in ("A", "B", "C", "D"):
        if not hasattr(ss, attr):
            raise InvalidArgumentError(f"ss: expected a control.StateSpace (with A, B, C, D), "
                                       f"got {type(ss).__name__}")
    dt = getattr(ss, "dt", None)
    if dt is None or dt is False or (not isinstance(dt, bool) and dt == 0):
        raise InvalidArgumentError(f"ss: must be a discrete-time system (dt not None or 0), got dt = {dt!r}; "
                                   "discretise it first, e.g. control.sample_system(sys, Ts)")
    A = np.array(ss.A, dtype=float, ndmin=2)
    nx = A.shape[0]
    B = np.array(ss.B, dtype=float).reshape(nx, -1)
    C = np.array(ss.C, dtype=float).reshape(-1, nx)
    ny = C.shape[0]
    D = np.array(ss.D, dtype=float).reshape(ny, B.shape[1])
    nu_all = B.shape[1]
    idx = [] if disturbance_inputs is None else [
        as_int(i, f"disturbance_inputs[{k}]", lo=None, hi=None)
        for k, i in enumerate(np.atleast_1d(np.asarray(disturbance_inputs, dtype=object)))]
    for i in idx:
        if not 0 <= i < nu_all:
            raise InvalidArgumentError(f"disturbance_inputs: input index {i} out of range 0..{nu_all - 1}")
    if len(set(idx)) != len(idx):
        raise InvalidArgumentError("disturbance_inputs: repeated input index")
    known = [i for i in range(nu_all) if i not in idx]
    Ecols, Fcols = [B[:, idx]], [D[:, idx]]
    if E is not None or F is not None:
        Ex = as_f64(E, "E", shape=(nx, None)) if E is not None else None
        Fx = as_f64(F, "F", shape=(ny, None)) if F is not None else None
        m = (Ex if Ex is not None else Fx).shape[1]
        if Ex is not None and Fx is not None and Fx.shape[1] != m:
            raise DimensionError(f"F: expected {m} columns (as E), got {Fx.shape[1]}")
        Ecols.append(Ex if Ex is not None else np.zeros((nx, m)))
        Fcols.append(Fx if Fx is not None else np.zeros((ny, m)))
    if output_noise is not None:
        phi = np.full(ny, as_float(output_noise, "output_noise", lo=0.0)) if np.ndim(output_noise) == 0 \
            else as_f64(output_noise, "output_noise", shape=(ny,))
        if not np.all(np.isfinite(phi)) or np.any(phi < 0):
            raise InvalidArgumentError("output_noise: must be finite and >= 0")
        Ecols.append(np.zeros((nx, ny)))
        Fcols.append(np.diag(phi))
    Ew, Fw = np.hstack(Ecols), np.hstack(Fcols)
    if Ew.shape[1] == 0:
        raise InvalidArgumentError("ss: no disturbance given; pass disturbance_inputs, E/F or output_noise "
                                   "(a state-space model does not say which signals are bounded)")
    T = None if isinstance(dt, bool) else float(dt)  # dt = True: discrete, sampling time unspecified
    if known:
        return LinearSystem(A, C, B=B[:, known], D=D[:, known], E=Ew, F=Fw, dt=T)
    return LinearSystem(A, C, E=Ew, F=Fw, dt=T)


def _is_statespace(obj) -> bool:
    return type(obj).__name__ == "StateSpace" and all(hasattr(obj, a) for a in ("A", "B", "C", "D", "dt"))


def as_system(system):
    """The system argument of the estimators, designs and simulations.

    A :class:`LinearSystem` or :class:`DescriptorSystem` is returned unchanged; a discrete-time
    ``control.StateSpace`` is accepted directly when its inputs say which signals are the unit-box
    disturbances: every input whose label starts with ``w`` (``"w"``, ``"w[0]"``, ``"w1"``…; name
    them with ``control.ss(A, B, C, D, dt, inputs=["u", "w[0]", "w[1]"])``) is a disturbance
    ``|ω_i| ≤ 1``, the others are known inputs. Anything else (or a StateSpace without such inputs)
    gets an error that says what to do; :func:`from_statespace` gives full control.

    Parameters
    ----------
    system : LinearSystem, DescriptorSystem or control.StateSpace
        The system.

    Returns
    -------
    LinearSystem or DescriptorSystem

    Raises
    ------
    InvalidArgumentError
        For anything else (the message says what to pass).
    """
    if isinstance(system, (LinearSystem, DescriptorSystem)):
        return system
    if _is_statespace(system):
        labels = list(getattr(system, "input_labels", []) or [])
        idx = [i for i, name in enumerate(labels) if str(name).startswith("w")]
        if not idx:
            raise InvalidArgumentError(
                f"system: a control.StateSpace is accepted when its disturbance inputs are labelled 'w…' "
                f"(its inputs are {labels}); label them, e.g. control.ss(A, B, C, D, dt, inputs=['u', 'w']), "
                "or convert with setbound.system.from_statespace(ss, disturbance_inputs=[...], output_noise=...)")
        return from_statespace(system, disturbance_inputs=idx)
    raise InvalidArgumentError(f"system: expected a LinearSystem, DescriptorSystem or discrete-time "
                               f"control.StateSpace, got {type(system).__name__}")
