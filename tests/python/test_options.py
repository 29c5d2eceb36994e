"""Scalar options of the Python API (issue 26 point 3): every reproduction of the issue as a
regression test. Each hostile value must raise a setbound input error (InvalidArgumentError or
DimensionError, both ValueErrors) whose message starts with the option's name, never an
OverflowError, MemoryError, InternalError or a silent coercion, and never a long run.

The fuzz of every option of every public function is in test_fuzz_api.py (``OPTIONS``)."""
from __future__ import annotations

import math
import time

import numpy as np
import pytest

import setbound as sb
from setbound import Box, Ellipsoid, LinearSystem, Plant, Zonotope, errors, hinf, lmi, zonotopic
from setbound import ellipsoidal, interval_observers as iobs, invariant, simulation
from setbound._validate import as_bool, as_choice, as_float, as_int, check_memory, memory_budget

INPUT_ERRORS = (errors.InvalidArgumentError, errors.DimensionError)


def refused(name: str, fn, *args, **kw) -> errors.SetboundError:
    """Calls ``fn``; it must raise an input error whose message starts with ``name:``."""
    with pytest.raises(INPUT_ERRORS) as info:
        fn(*args, **kw)
    exc = info.value
    assert not isinstance(exc, (OverflowError, MemoryError, errors.InternalError)), repr(exc)
    assert str(exc).startswith(name), f"message does not start with {name!r}: {exc}"
    return exc


# ---- small problems ---------------------------------------------------------------------------

@pytest.fixture(scope="module")
def system():
    return LinearSystem([[0.5, 0.1], [0.0, 0.6]], [[1.0, 0.0]], E=0.1 * np.eye(2), F=[[0.1, 0.0]])


@pytest.fixture(scope="module")
def design(system):
    return ellipsoidal.design_offline(system, beta=0.8)


@pytest.fixture(scope="module")
def x0e():
    return Ellipsoid(np.eye(2), np.zeros(2), 1.0)


@pytest.fixture(scope="module")
def x0z():
    return Zonotope(np.zeros(2), np.eye(2))


@pytest.fixture(scope="module")
def plant():
    return Plant([[0.2, 0.2], [0, 0.5]], [[1, 0]], B=[[1], [1]], Fd=[[0], [0.1]], Z=[[0.1]])


@pytest.fixture(scope="module")
def nl_plant():
    return Plant([[0.5, 0.1], [0.0, 0.4]], [[1.0, 0.0]], Fd=np.eye(2), Z=[[0.1]])


def nonlinear(nl_plant, **kw):
    return iobs.NonlinearIntervalObserver(nl_plant, Box([-1, -1], [1, 1]), [0.0, 0.0], Box([-1], [1]),
                                          Box([-0.1, -0.1], [0.1, 0.1]), **kw)


def lmi_problem():
    p = lmi.Problem(1)
    p.add_block(np.eye(2), np.eye(2)[None])
    p.set_objective([1.0])
    return p


# ---- the reproductions ------------------------------------------------------------------

@pytest.mark.parametrize("value", [2**40, math.inf, 2**31, True, 0, -1, 3.7, "5"])
def test_max_iter(value):
    refused("max_iter", lmi_problem().set_options, max_iter=value)
    refused("max_iter", lmi.solve, [1.0], [(np.eye(2), np.eye(2)[None])], max_iter=value)


@pytest.mark.parametrize("value", [2**31, 2**30, 2**63, 3.7, "5", True, 0, -1])
def test_max_generators(system, x0z, value):
    refused("max_generators", zonotopic.SegmentMinEstimator, system, x0z, max_generators=value)
    refused("max_generators", zonotopic.VolumeMinEstimator, system, x0z, max_generators=value)


@pytest.mark.parametrize("value", [2**31, 257, 0, -1, 2.0, "2", True])
def test_threads(value):
    refused("threads", lmi_problem().set_options, threads=value)


@pytest.mark.parametrize("value", [2**31, 2**30, lmi.MAX_VARS + 1, 0, -1, 3.7, "5", True, None])
def test_problem_num_vars(value):
    refused("num_vars", lmi.Problem, value)


@pytest.mark.parametrize("value", [2**31, 2**30, 3.7, "5", -1, 0, True, None])
def test_window(nl_plant, value):
    refused("window", nonlinear, nl_plant, window=value)


def test_window_in_range_is_kept_or_reported(nl_plant):
    """A valid window is used as given, up to the stored powers of A_o (reported, not hidden)."""
    assert nonlinear(nl_plant, window=3).window == 3
    obs = nonlinear(nl_plant, window=iobs.MAX_WINDOW)
    assert 1 <= obs.window <= iobs.MAX_WINDOW


@pytest.mark.parametrize("value", [2**31, 2**30, 0, -1, 2.0, "2", True])
def test_passes_fail_fast(plant, value):
    t0 = time.perf_counter()
    refused("passes", hinf.design_ellipsoidal_sm_observer, plant, [1.0, 1.0], passes=value)
    assert time.perf_counter() - t0 < 1.0  # checked before any LMI is solved


@pytest.mark.parametrize("value", [2**31, 0, -1, 3.7, True])
def test_mrpi_max_iterations(value):
    refused("max_iterations", invariant.mrpi_outer_shrinking, [[0.5]], [[1.0]], [1.0], eps=0.1, boxes_only=True,
            max_iterations=value)


@pytest.mark.parametrize("value", [2**31, 0, -1, 3.7, True])
def test_max_vertices(value):
    refused("max_vertices", invariant.polyhedral_rpi_between_ellipsoids, np.eye(2), 1.0, 2.0, max_vertices=value)


@pytest.mark.parametrize("value", [2**31, 2**40, -1, 3.7, "5", True])
def test_interval_error_recursion_steps(value):
    refused("steps", iobs.interval_error_recursion, [[0.5]], [[1.0]], Box([-1], [1]), Box([-1], [1]), steps=value)


def test_interval_error_recursion_memory_estimate():
    """A step count a C int can hold but the memory cannot: refused with the estimate."""
    exc = refused("steps", iobs.interval_error_recursion, [[0.5]], [[1.0]], Box([-1], [1]), Box([-1], [1]),
                  steps=2**31 - 2)
    assert "GiB" in str(exc) and "memory" in str(exc)


@pytest.mark.parametrize("value", [2**31, 2**63, 0, -1, 3.7, "5", True])
def test_simulate_horizon(system, value):
    refused("N", simulation.simulate, system, np.zeros(2), value)


def test_simulate_horizon_memory(system, monkeypatch):
    """A horizon within the documented bound whose arrays do not fit: refused with the estimate."""
    monkeypatch.setattr("setbound._validate.memory_budget", lambda: 2**20)
    exc = refused("N", simulation.simulate, system, np.zeros(2), 10**6)
    assert "GiB" in str(exc)


@pytest.mark.parametrize("value", ["5", math.nan, 1, 0, None])
def test_scaling(design, x0e, value):
    refused("scaling", ellipsoidal.OnlineEstimator, design, x0e, scaling=value)


def test_nsigma_approach_max_iter_not_bools(system):
    refused("nsigma", ellipsoidal.KalmanFilter, system, np.zeros(2), np.eye(2), nsigma=True)
    refused("approach", zonotopic.design_pradius, system, approach=True)
    refused("max_iter", lmi_problem().set_options, max_iter=True)


@pytest.mark.parametrize("name", ["max_iter", "tol", "time_limit", "feas"])
@pytest.mark.parametrize("value", [0, -1, 0.0, -0.0, -1e-9])
def test_non_positive_is_not_default(name, value):
    refused(name, lmi_problem().set_options, **{name: value})


@pytest.mark.parametrize("value", [1e300, 1.0, math.inf, math.nan])
def test_feas_bounded(value):
    refused("feas", lmi_problem().set_options, feas=value)


def test_feas_at_its_bound_does_not_certify_unboundedness():
    """feas=1e300 reported 'unbounded' for a bounded problem: the certificates are accepted at
    residual <= feas × objective. At the largest accepted feas the bounded problem min x s.t.
    [[1, x], [x, 1]] ⪰ 0 (x ∈ [-1, 1]) is solved, not certified unbounded."""
    p = lmi.Problem(1)
    p.add_block(np.eye(2), np.array([[[0.0, 1.0], [1.0, 0.0]]]))
    p.set_objective([1.0])
    p.set_options(feas=lmi.MAX_FEAS)
    r = p.solve()
    assert r.status in ("optimal", "inaccurate"), r.status
    assert r.x[0] == pytest.approx(-1.0, abs=1e-3)


@pytest.mark.parametrize("value", [1e-300, 0.0, 1.0, math.nan])
def test_gevp_tol(value):
    """A bisection tolerance below the rounding of λ never terminated: refused."""
    p = lmi.Problem(1)
    p.add_block(np.eye(2), np.eye(2)[None])
    refused("tol", p.gevp, (np.eye(2), np.zeros((1, 2, 2))), (np.eye(2), np.zeros((1, 2, 2))), tol=value)


def test_valid_options_still_work(system, x0z, design, x0e, plant):
    """The checks refuse the hostile values only: numpy integers and floats are accepted."""
    zonotopic.SegmentMinEstimator(system, x0z, max_generators=np.int64(6))
    ellipsoidal.OnlineEstimator(design, x0e, scaling=np.bool_(True), reuse_tolerance=np.float32(0.0))
    p = lmi_problem()
    p.set_options(max_iter=np.int32(50), tol=1e-6, time_limit=5, threads=1)
    assert p.solve().status == "optimal"
    assert len(iobs.interval_error_recursion([[0.5]], [[1.0]], Box([-1], [1]), Box([-1], [1]), steps=3)) == 4
    assert simulation.simulate(system, np.zeros(2), np.int16(4), rng=1).x.shape == (4, 2)


# ---- the C ABI enforces the size bounds too (C users get the same errors) --------------------------

def test_c_abi_bounds():
    from setbound._native import ffi, lib

    h = ffi.new("sb_lmi_problem**")
    assert lib.sb_lmi_problem_create(2**30, h) == lib.SB_ERR_DIMENSION
    assert ffi.string(lib.sb_last_error()).decode().startswith("sb_lmi_problem_create: num_vars")
    assert lib.sb_lmi_problem_create(lib.SB_LMI_MAX_VARS + 1, h) == lib.SB_ERR_DIMENSION


def test_c_abi_max_generators(system, x0z):
    from setbound._native import dptr, ffi, lib

    h = ffi.new("sb_zonotopic**")
    rc = lib.sb_zonotopic_create(system._handle, lib.SB_ZONO_GAIN_SEGMENT_MIN, ffi.NULL, 2**30, 1, ffi.NULL,
                                 x0z.m, dptr(x0z.center), dptr(x0z.generators), h)
    assert rc == lib.SB_ERR_INVALID_ARGUMENT
    assert "max_generators" in ffi.string(lib.sb_last_error()).decode()


# ---- the conversions themselves ------------------------------------------------------------------

def test_validate_conversions():
    assert as_int(np.int64(5), "k") == 5 and type(as_int(np.int64(5), "k")) is int
    for bad in (3.7, 5.0, "5", True, np.bool_(True), None, [1], 2**31):
        with pytest.raises(errors.InvalidArgumentError, match="^k:"):
            as_int(bad, "k")
    assert as_float(np.float32(0.5), "x") == 0.5
    for bad in ("0.1", True, None, math.nan, math.inf, 2**1024, [1.0]):
        with pytest.raises(errors.InvalidArgumentError, match="^x:"):
            as_float(bad, "x")
    assert as_float(math.inf, "x", finite=False) == math.inf
    assert math.isnan(as_float(math.nan, "x", finite=False, nan=True))
    with pytest.raises(errors.InvalidArgumentError, match=r"^x: expected a number in \(0, 1\]"):
        as_float(0.0, "x", lo=0.0, hi=1.0, lo_open=True)
    assert as_bool(np.bool_(False), "b") is False
    for bad in (1, 0, "yes", None, math.nan):
        with pytest.raises(errors.InvalidArgumentError, match="^b:"):
            as_bool(bad, "b")
    assert as_choice(2, "c", (1, 2)) == 2
    for bad in (True, 2.0, "2", [2]):
        with pytest.raises(errors.InvalidArgumentError, match="^c:"):
            as_choice(bad, "c", (1, 2))
    assert memory_budget() > 2**20
    check_memory("n", 1, 8.0)
    with pytest.raises(errors.InvalidArgumentError, match="^n: .* GiB"):
        check_memory("n", 2**62, 8.0 * 2**62)


def test_c_abi_passes_and_window(plant, nl_plant):
    """C callers get the same bounds (the C ABI keeps "<= 0 = default" as documented for C)."""
    from setbound._native import dptr, ffi, lib

    f = lambda a: np.ascontiguousarray(a, dtype=float)  # noqa: E731
    A, B, C, F, Z = (f(m) for m in (plant.A, plant.B, plant.C, plant.F, plant.Z))
    wbar = f([1.0, 1.0])
    h = ffi.new("sb_hinf_design**")
    t0 = time.perf_counter()
    rc = lib.sb_hinf_design_create(1, 2, 1, 1, 1, 1, 0, dptr(A), dptr(B), dptr(C), dptr(F), dptr(Z), ffi.NULL,
                                   dptr(wbar), ffi.NULL, -1, lib.SB_HINF_MAX_PASSES + 1, h)
    assert rc == lib.SB_ERR_INVALID_ARGUMENT and time.perf_counter() - t0 < 1.0
    assert "passes" in ffi.string(lib.sb_last_error()).decode()
    A, B, C, Z = (f(m) for m in (nl_plant.A, nl_plant.B, nl_plant.C, nl_plant.Z))
    lo, hi, xh, vlo, vhi = f([-1, -1]), f([1, 1]), f([0, 0]), f([-1]), f([1])
    g = ffi.new("sb_interval_nonlinear**")
    rc = lib.sb_interval_nonlinear_create(2, 0, 1, 1, dptr(A), dptr(B), dptr(C), dptr(Z), ffi.NULL, dptr(lo), dptr(hi),
                                          dptr(xh), dptr(vlo), dptr(vhi), lib.SB_INTERVAL_MAX_WINDOW + 1, g)
    assert rc == lib.SB_ERR_INVALID_ARGUMENT
    assert "window" in ffi.string(lib.sb_last_error()).decode()


def test_integers_beyond_the_str_limit_are_named_not_a_bare_value_error():
    # str() of an integer of more than 4300 digits raises ValueError: the message itself must not
    # fail (it did for the API's as_int/as_float before they shared describe with the job files)
    huge = 10**5000
    for convert in (lambda v: as_int(v, "k", lo=1, hi=5), lambda v: as_float(v, "k")):
        with pytest.raises(errors.InvalidArgumentError, match=r"^k: .*an integer of about 5001 digits"):
            convert(huge)
    with pytest.raises(errors.InvalidArgumentError, match="^max_generators:"):
        zonotopic.SegmentMinEstimator(LinearSystem([[0.5]], C=[[1.0]], E=[[0.1]], F=[[0.1]]),
                                      Zonotope([0.0], [[1.0]]), max_generators=huge)
