"""Fuzzing of the public Python API (issue 8): hypothesis-generated shapes, scales (1e-6..1e6),
NaN/Inf, non-symmetric / singular / indefinite matrices, empty arrays, wrong dtypes and memory
layouts, fed to every constructor, design, step and run entry point.

Property of every case: either a clean result that passes a validity check (finite numbers,
right shapes, PSD shape matrices, and sets that contain what they must: a simulated true state
for every estimator step on a valid system, every sampled point for set operations), or a
setbound error (SetboundError / ValueError / TypeError) whose message names the argument.
Never a crash, an unnamed generic error or a NaN from finite input.
"""
from __future__ import annotations

import gc
import itertools
import warnings

import numpy as np
import pytest
from hypothesis import given, strategies as st

import setbound as sb
from setbound import Box, Ellipsoid, Interval, IntervalMatrix, LinearSystem, Plant, Strip, Zonotope
from setbound import ellipsoidal, errors, hinf, inclusion, interval_observers as iobs, lmi, zonotopic

from fuzz_support import assert_finite, assert_psd, check_error, count, fuzz

SCALES = (1e-6, 1e-3, 1.0, 1e3, 1e6)
CONTAIN_TOL = 1e-9


def attempt(fn, *args, **kw):
    """(result, None) or (None, error) after checking that the error is a clean setbound one."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ellipsoidal.DegenerateDesignWarning)
            return fn(*args, **kw), None
    except Exception as exc:  # noqa: BLE001 - the property is on the exception itself
        check_error(exc)
        return None, exc


# ---- corruptions of an array argument ------------------------------------------------------------

CORRUPTIONS = ("none", "nan", "inf", "fortran", "strided", "int", "float32", "list", "transpose", "drop_row",
               "empty", "scalar", "3d", "complex", "object", "string")


def corrupt(a: np.ndarray, how: str, rng):
    """``a`` changed by ``how``. Returns (value, still_valid): the layout/dtype changes keep the
    same numbers (the API must accept them and give the same result); the others are invalid."""
    a = np.asarray(a, dtype=float)
    if how == "none":
        return a, True
    if how in ("nan", "inf"):
        if a.size == 0:
            return a, True
        b = a.copy()
        b.flat[rng.integers(0, a.size)] = np.nan if how == "nan" else -np.inf
        return b, False
    if how == "fortran":
        return np.asfortranarray(a), True
    if how == "strided":
        big = np.zeros(a.shape + (2,))
        big[..., 0] = a
        return big[..., 0], True
    if how == "int":
        return np.round(a).astype(np.int64), None  # valid, other numbers
    if how == "float32":
        return a.astype(np.float32), None
    if how == "list":
        return a.tolist(), True
    if how == "transpose":
        return (a.T, True) if a.ndim < 2 or a.shape[0] == a.shape[1] and np.array_equal(a, a.T) else (a.T, False)
    if how == "drop_row":
        return (a[:-1], False) if a.ndim >= 1 and a.shape[0] > 0 else (a, True)
    if how == "empty":
        return np.zeros((0,) * max(a.ndim, 1)), a.size == 0
    if how == "scalar":
        return 1.0, a.size == 1
    if how == "3d":
        return a[None, ...], False
    if how == "complex":
        return a + 1j, False
    if how == "object":
        b = a.astype(object)
        if b.size:
            b.flat[0] = None
        return b, a.size == 0
    if how == "string":
        return "abc", False
    raise AssertionError(how)


def rand_spd(rng, n, scale=1.0, cond=1e3):
    Q, _ = np.linalg.qr(rng.standard_normal((n, n)))
    w = scale * np.exp(rng.uniform(0, np.log(cond), n))
    P = (Q * w) @ Q.T
    return 0.5 * (P + P.T)


def sample_ellipsoid(E: Ellipsoid, rng, k):
    n = E.n
    w, V = np.linalg.eigh(E.P)
    L = V / np.sqrt(w)  # L L^T = P^-1
    d = rng.standard_normal((k, n))
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    d *= rng.uniform(0, 1, (k, 1)) ** (1 / n)
    return E.center + np.sqrt(E.rho) * d @ L.T * (1 - 1e-9)


# ---- sets ------------------------------------------------------------------------------------------

@fuzz(400)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 4), scale=st.sampled_from(SCALES),
       kind=st.sampled_from(("spd", "singular", "indefinite", "nonsym", "ill")),
       how=st.sampled_from(CORRUPTIONS), rho=st.sampled_from((0.0, 1e-12, 1.0, 1e6, -1.0, np.nan, np.inf)))
def test_ellipsoid(seed, n, scale, kind, how, rho):
    count("ellipsoid")
    rng = np.random.default_rng(seed)
    P = rand_spd(rng, n, scale, 1e12 if kind == "ill" else 1e3)
    if kind == "singular" and n > 1:
        v = rng.standard_normal(n)
        P = P - (v @ P @ v) ** -1 * np.outer(P @ v, P @ v)
        P = 0.5 * (P + P.T)
    elif kind == "indefinite":
        P = P - 2 * np.abs(np.linalg.eigvalsh(P)).max() * np.eye(n)[:, [0]] @ np.eye(n)[[0], :]
    elif kind == "nonsym" and n > 1:
        P = P.copy()
        P[0, 1] += 0.1 * scale
    c = rng.standard_normal(n) * scale
    Pc, valid = corrupt(P, how, rng)
    E, err = attempt(Ellipsoid, Pc, c, rho)
    if E is None:
        return
    assert E.P.shape == (n, n) and E.center.shape == (n,)
    assert_psd(E.P)
    assert np.isfinite(E.rho) and E.rho >= 0
    lo, hi = E.bounding_box()
    radius = np.sqrt(E.rho / np.linalg.eigvalsh(E.P).min())
    resolvable = E.rho > 0 and np.linalg.cond(E.P) < 1e10 and radius > 1e-6 * np.abs(E.center).max()
    pts = sample_ellipsoid(E, rng, 20) if resolvable else E.center[None]
    assert np.all(pts >= lo - 1e-9 * np.abs(pts)) and np.all(pts <= hi + 1e-9 * np.abs(pts))
    assert np.all(E.contains(pts, rel_tol=1e-6))
    d = rng.standard_normal((3, n))
    s = E.support(d)
    assert_finite(s)
    assert np.all(s[:, None] >= (d @ pts.T) - 1e-7 * (np.abs(d) @ np.abs(pts).T + 1e-300))
    v, e2 = attempt(lambda: E.volume)
    if v is not None:
        assert v >= 0 and not np.isnan(v)
    M = rng.standard_normal((n, n)) + 3 * np.eye(n)
    F, e3 = attempt(E.affine_map, M, rng.standard_normal(n))
    if F is not None:
        assert_psd(F.P)
    P_new = rand_spd(rng, n)
    r, e4 = attempt(E.level_for_shape, P_new)
    if r is not None:
        assert np.isfinite(r) and r >= 0
        G = Ellipsoid(P_new, E.center, r)
        assert np.all(G.contains(pts, rel_tol=1e-6))


@fuzz(400)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 4), m=st.integers(0, 7), scale=st.sampled_from(SCALES),
       how=st.sampled_from(CORRUPTIONS), limit=st.integers(-1, 8),
       method=st.sampled_from(("combastel", "girard", "pca", "bogus")))
def test_zonotope(seed, n, m, scale, how, limit, method):
    count("zonotope")
    rng = np.random.default_rng(seed)
    H = rng.standard_normal((n, m)) * scale
    if m > 1 and rng.integers(0, 3) == 0:
        H[:, 1] = H[:, 0]  # parallel generators
    p = rng.standard_normal(n) * scale
    Hc, valid = corrupt(H, how, rng)
    Z, err = attempt(Zonotope, p, Hc)
    if Z is None:
        if valid is True:
            # a scalar or an empty array is refused for H (a 2-D array is required): clean errors
            assert how in ("empty", "scalar") or m == 0, f"valid input refused: {err}"
        return
    xi = rng.uniform(-1, 1, (15, Z.m))
    pts = Z.center + xi @ Z.generators.T
    lo, hi = Z.interval_hull()
    tol = 1e-12 * (np.abs(pts) + np.abs(Z.generators).sum(axis=1) + 1)
    assert np.all(pts >= lo - tol) and np.all(pts <= hi + tol)
    d = rng.standard_normal((3, n))
    s = Z.support(d)
    assert np.all(s[:, None] >= d @ pts.T - 1e-9 * (1 + np.abs(d) @ np.abs(pts).T))
    R, e2 = attempt(Z.reduce, limit, method)
    if R is not None:
        assert R.m <= max(limit, 0) or R.m <= Z.m
        inside = R.contains(pts, rel_tol=1e-7) if R.n <= 3 else np.ones(len(pts), bool)
        assert np.all(inside), (limit, method)
        rlo, rhi = R.interval_hull()
        assert np.all(rlo <= lo + 1e-9 * (1 + np.abs(lo))) and np.all(rhi >= hi - 1e-9 * (1 + np.abs(hi)))
    c = rng.standard_normal(n)
    y = float(c @ pts[0])
    strip, e3 = attempt(Strip, c, y, float(np.abs(c @ (pts - pts[0]).T).max()) + 1e-3)
    if strip is not None:
        lam = rng.standard_normal(n) * 0.1
        Zi, e4 = attempt(Z.intersect_strip, strip, lam)
        if Zi is not None:
            ok = strip.contains(pts)
            ilo, ihi = Zi.interval_hull()
            tol = 1e-9 * (1 + np.abs(pts))
            assert np.all((pts[ok] >= ilo - tol[ok]) & (pts[ok] <= ihi + tol[ok]))
    P = rand_spd(rng, n)
    if Z.m <= 10:
        r, e5 = attempt(Z.pradius, P)
        if r is not None:
            gen = xi @ Z.generators.T
            assert np.all(np.einsum("ij,jk,ik->i", gen, P, gen) <= r * (1 + 1e-9) + 1e-300)


@fuzz(600)
@given(a=st.floats(allow_nan=True), b=st.floats(allow_nan=True), c=st.floats(-1e6, 1e6), d=st.floats(-1e6, 1e6),
       op=st.sampled_from(("+", "-", "*", "/", "&", "|", "sqr", "sqrt", "exp", "sin", "cos", "abs", "pow", "recip")),
       p=st.integers(-4, 5), t1=st.floats(0, 1), t2=st.floats(0, 1))
def test_interval(a, b, c, d, op, p, t1, t2):
    """Interval operations on arbitrary ends (NaN, ±Inf, huge): a clean error for NaN/reversed
    ends, otherwise a result that contains the exact result at sampled points."""
    count("interval")
    X, err = attempt(Interval, min(a, b), max(a, b))
    Y = Interval(min(c, d), max(c, d))
    if X is None:
        # NaN ends, or [inf, inf] / [-inf, -inf] (no real number): refused
        assert np.isnan(a) or np.isnan(b) or (np.isinf(a) and a == b)
        return
    with np.errstate(all="ignore"):
        x = X.lo + t1 * (X.hi - X.lo) if np.isfinite(X.lo) and np.isfinite(X.hi) else (X.lo if np.isfinite(X.lo) else X.hi)
        y = Y.lo + t2 * (Y.hi - Y.lo)
        x, y = min(max(x, X.lo), X.hi), min(max(y, Y.lo), Y.hi)  # rounding of lo + t (hi - lo)
        fn = {"+": (lambda: X + Y, lambda: x + y), "-": (lambda: X - Y, lambda: x - y),
              "*": (lambda: X * Y, lambda: x * y), "/": (lambda: X / Y, lambda: x / y if y != 0 else np.nan),
              "&": (lambda: X.intersect(Y), lambda: x if Y.contains(x) else np.nan),
              "|": (lambda: X.hull(Y), lambda: x),
              "sqr": (X.sqr, lambda: x * x), "sqrt": (X.sqrt, lambda: np.sqrt(x) if x >= 0 else np.nan),
              "exp": (X.exp, lambda: np.exp(x)), "sin": (X.sin, lambda: np.sin(x)), "cos": (X.cos, lambda: np.cos(x)),
              "abs": (X.abs, lambda: abs(x)), "pow": (lambda: sb.interval.power(X, p),
                                                      lambda: np.float64(x) ** p if (x != 0 or p >= 0) else np.nan),
              "recip": (X.reciprocal, lambda: 1 / x if x != 0 else np.nan)}[op]
        R, err = attempt(fn[0])
        if R is None:
            return
        assert not (np.isnan(R.lo) or np.isnan(R.hi)), (op, X, Y, R)
        v = fn[1]()
        if np.isfinite(x) and np.isfinite(v):
            assert R.lo <= v <= R.hi, (op, X, Y, x, y, v, R)


@fuzz(300)
@given(seed=st.integers(0, 2**32 - 1), r=st.integers(0, 3), c=st.integers(0, 3), scale=st.sampled_from(SCALES),
       how=st.sampled_from(CORRUPTIONS))
def test_interval_matrix_and_box(seed, r, c, scale, how):
    count("interval-matrix")
    rng = np.random.default_rng(seed)
    mid = rng.standard_normal((r, c)) * scale
    rad = np.abs(rng.standard_normal((r, c))) * scale * 0.1
    radc, valid = corrupt(rad, how, rng)
    M, err = attempt(IntervalMatrix.from_mid_rad, mid, radc)
    if M is None:
        return
    xlo = rng.standard_normal(c) * scale
    X, err = attempt(Box, xlo, xlo + np.abs(rng.standard_normal(c)) * scale)
    if X is None or r == 0 or c == 0:
        return
    Yb, err = attempt(lambda: M @ X)
    if Yb is None:
        return
    for _ in range(5):
        A = M.lo + rng.uniform(0, 1, (r, c)) * (M.hi - M.lo)
        x = X.lo + rng.uniform(0, 1, c) * (X.hi - X.lo)
        y = A @ x
        tol = 1e-12 * (np.abs(A) @ np.abs(x) + 1e-300)
        assert np.all(y >= Yb.lo - tol) and np.all(y <= Yb.hi + tol)
    nrm = M.norm()
    assert nrm >= np.abs(M.mid).sum(axis=1).max() * (1 - 1e-12)


@fuzz(200)
@given(seed=st.integers(0, 2**32 - 1), scale=st.sampled_from(SCALES), kind=st.sampled_from(("natural", "centered")))
def test_inclusion(seed, scale, kind):
    count("inclusion")
    rng = np.random.default_rng(seed)
    lo = rng.standard_normal() * scale
    X = Interval(lo, lo + abs(rng.standard_normal()) * scale)

    def f(x):
        return x * x - sb.interval.sin(x) * 3.0 + sb.interval.exp(x * 1e-6)

    def df(x):
        return x * 2.0 - sb.interval.cos(x) * 3.0 + sb.interval.exp(x * 1e-6) * 1e-6

    R, err = attempt(inclusion.natural_inclusion if kind == "natural" else inclusion.centered_inclusion,
                     *((f, X) if kind == "natural" else (f, df, X)))
    if R is None:
        return
    for t in rng.uniform(0, 1, 10):
        x = X.lo + t * (X.hi - X.lo)
        v = x * x - 3 * np.sin(x) + np.exp(x * 1e-6)
        if np.isfinite(v):
            assert R.lo - 1e-12 * abs(v) <= v <= R.hi + 1e-12 * abs(v)


# ---- systems ---------------------------------------------------------------------------------------

def random_system(rng, nx, ny, nw, nu, scale=1.0, stable=True):
    A = rng.standard_normal((nx, nx))
    rad = max(abs(np.linalg.eigvals(A)))
    A *= (rng.uniform(0.3, 0.95) if stable else rng.uniform(1.0, 1.3)) / max(rad, 1e-9)
    C = rng.standard_normal((ny, nx))
    E = rng.standard_normal((nx, nw)) * 0.1 * scale
    F = rng.standard_normal((ny, nw)) * 0.1 * scale
    B = rng.standard_normal((nx, nu)) if nu else None
    return A, B, C, E, F


@fuzz(400)
@given(seed=st.integers(0, 2**32 - 1), nx=st.integers(0, 4), ny=st.integers(0, 3), nw=st.integers(0, 3),
       nu=st.integers(0, 2), arg=st.sampled_from("ABCDEF"), how=st.sampled_from(CORRUPTIONS),
       interval=st.booleans())
def test_linear_system(seed, nx, ny, nw, nu, arg, how, interval):
    count("linear-system")
    rng = np.random.default_rng(seed)
    A, B, C, E, F = random_system(rng, max(nx, 1), max(ny, 1), max(nw, 1), nu)
    if nx == 0:
        A = np.zeros((0, 0))
    D = rng.standard_normal((C.shape[0], nu)) if nu else None
    args = dict(A=A, B=B, C=C, D=D, E=E, F=F)
    if args[arg] is not None:
        args[arg], _ = corrupt(args[arg], how, rng)
    if (interval and isinstance(args["A"], np.ndarray) and args["A"].ndim == 2 and args["A"].size
            and args["A"].dtype.kind in "fi"):
        args["A"], e = attempt(IntervalMatrix.from_mid_rad, args["A"], 0.01 * np.abs(args["A"]))
        if args["A"] is None:
            return
    S, err = attempt(LinearSystem, args.pop("A"), args.pop("C"), **args)
    if S is None:
        return
    for a in (S.A, S.B, S.C, S.D, S.E, S.F):
        assert_finite(a)
    assert S.A.shape == (S.nx, S.nx) and S.C.shape == (S.ny, S.nx) and S.E.shape == (S.nx, S.nw)
    d, err = attempt(S.is_detectable)
    assert d in (True, False) or err is not None
    count("linear-system-valid")


@fuzz(100)
@given(seed=st.integers(0, 2**32 - 1), how=st.sampled_from(CORRUPTIONS), arg=st.sampled_from(("E", "A", "C", "D", "F")),
       rank_def=st.booleans())
def test_descriptor_system(seed, how, arg, rank_def):
    count("descriptor-system")
    rng = np.random.default_rng(seed)
    n = int(rng.integers(2, 4))
    Ed = np.diag([1.0] * (n - 1) + [0.0])
    A = rng.standard_normal((n, n)) * 0.3
    C = rng.standard_normal((2, n))
    if rank_def:
        C[:, -1] = 0.0
    D = rng.standard_normal((n, 3)) * 0.1
    F = rng.standard_normal((2, 3)) * 0.1
    args = dict(E=Ed, A=A, C=C, D=D, F=F)
    args[arg], _ = corrupt(args[arg], how, rng)
    S, err = attempt(sb.DescriptorSystem, args["E"], args["A"], args["C"], D=args["D"], F=args["F"])
    if S is None:
        return
    T, N = S.T, S.N
    assert_finite(T, N)
    np.testing.assert_allclose(T @ S.E + N @ S.C, np.eye(S.nx), atol=1e-8)
    count("descriptor-system-valid")
    if seed % 4:
        return  # the design below solves LMIs: a quarter of the cases
    d, err = attempt(ellipsoidal.design_offline, S, beta=0.8)
    if d is None:
        return
    assert_psd(d.P)
    est = ellipsoidal.DescriptorEstimator(d, Ellipsoid(np.eye(S.nx), np.zeros(S.nx), 1.0))
    traj = est.run(rng.standard_normal((4, S.ny)) * 0.1)
    assert_finite(traj.center, traj.lower, traj.upper)
    assert np.all(traj.lower <= traj.upper)
    count("descriptor-estimator")


# ---- estimators on fuzzed systems: containment of a simulated state --------------------------------

def simulate(rng, A, B, C, E, F, x0, N, vertex, D=None, nu=0):
    x = x0.copy()
    xs, ys, us = [], [], []
    for _ in range(N):
        w = rng.choice([-1.0, 1.0], E.shape[1]) if vertex else rng.uniform(-1, 1, E.shape[1])
        u = rng.standard_normal(nu) if nu else None
        y = C @ x + F @ w + ((D @ u) if (D is not None and nu) else 0)
        xs.append(x.copy())
        ys.append(y)
        us.append(u)
        x = A @ x + E @ w + ((B @ u) if nu else 0)
    xs.append(x.copy())
    return xs, ys, us


system_params = dict(seed=st.integers(0, 2**32 - 1), nx=st.integers(1, 3), ny=st.integers(1, 2),
                     nw=st.integers(1, 3), nu=st.integers(0, 1), scale=st.sampled_from((1e-3, 1.0, 1e3)),
                     stable=st.booleans(), vertex=st.booleans())


@fuzz(25)
@given(**system_params, method=st.sampled_from(("offline", "online", "scaled", "improved")),
       beta=st.sampled_from((None, 0.5, 0.9, 0.0, 1.0, np.nan)))
def test_ellipsoidal(seed, nx, ny, nw, nu, scale, stable, vertex, method, beta):
    count("ellipsoidal")
    rng = np.random.default_rng(seed)
    A, B, C, E, F = random_system(rng, nx, ny, nw, nu, scale, stable)
    S = LinearSystem(A, C, B=B, E=E, F=F)
    design, err = attempt(ellipsoidal.design_offline, S, beta=beta)
    if design is None:
        return
    assert_psd(design.P)
    assert 0 < design.beta < 1 and np.isfinite(design.sigma)
    assert design.L.shape == (nx, ny)
    x0set = Ellipsoid(np.eye(nx), np.zeros(nx), 1.0)
    cls = {"offline": lambda: ellipsoidal.OfflineEstimator(design, x0set),
           "online": lambda: ellipsoidal.OnlineEstimator(design, x0set),
           "scaled": lambda: ellipsoidal.OnlineEstimator(design, x0set, scaling=True),
           "improved": lambda: ellipsoidal.ImprovedEstimator(design, x0set)}[method]
    est = cls()
    x0 = sample_ellipsoid(x0set, rng, 1)[0]
    xs, ys, us = simulate(rng, A, B, C, E, F, x0, 7, vertex, nu=nu)
    ys[2] = ys[2].copy()
    ys[2][0] = np.nan  # one output missing
    ys[5] = np.full(ny, np.nan)  # nothing measured: a certified pure prediction
    for k in range(7):
        Ek = est.step(ys[k], us[k])
        assert_psd(Ek.P)
        assert np.isfinite(Ek.rho)
        target = xs[k] if est.is_filter else xs[k + 1]
        assert Ek.contains(target, rel_tol=CONTAIN_TOL), (method, k)
        assert not est.last_check.flagged, (method, k)  # fault-free data: no alarm
    count("ellipsoidal-contained")
    # a step with bad data (±inf; NaN is a missing output) raises and leaves the estimator unchanged
    before = est.current
    bad, err = attempt(est.step, np.full(ny, np.inf), us[0])
    assert bad is None
    np.testing.assert_array_equal(est.current.P, before.P)


@fuzz(40)
@given(**system_params, method=st.sampled_from(("segment", "volume", "pradius")), maxgen=st.integers(-1, 8))
def test_zonotopic(seed, nx, ny, nw, nu, scale, stable, vertex, method, maxgen):
    count("zonotopic")
    rng = np.random.default_rng(seed)
    A, B, C, E, F = random_system(rng, nx, ny, nw, nu, scale, stable)
    S = LinearSystem(A, C, B=B, E=E, F=F)
    X0 = Zonotope(np.zeros(nx), np.eye(nx))
    if method == "pradius":
        d, err = attempt(zonotopic.design_pradius, S)
        if d is None:
            return
        assert np.all(np.isfinite(d.lambdas)) and np.all(np.isfinite(d.tau)) and np.isfinite(d.psi)
        est, err = attempt(zonotopic.PRadiusEstimator, d, X0, max_generators=maxgen)
    else:
        cls = zonotopic.SegmentMinEstimator if method == "segment" else zonotopic.VolumeMinEstimator
        est, err = attempt(cls, S, X0, max_generators=maxgen)
    if est is None:
        return
    x0 = rng.uniform(-1, 1, nx)
    xs, ys, us = simulate(rng, A, B, C, E, F, x0, 8, vertex, nu=nu)
    if seed % 2:  # the batch entry point: the same sets as stepping
        traj = est.run(np.array(ys), np.array(us) if nu else None)
        for k in range(8):
            tol = 1e-9 * (1 + np.abs(xs[k]))
            assert np.all(xs[k] >= traj.lower[k] - tol) and np.all(xs[k] <= traj.upper[k] + tol), (method, k)
        count("zonotopic-contained")
        return
    for k in range(8):
        Z = est.step(ys[k], us[k])
        assert_finite(Z.center, Z.generators)
        lo, hi = Z.interval_hull()
        tol = 1e-9 * (1 + np.abs(xs[k]))
        assert np.all(xs[k] >= lo - tol) and np.all(xs[k] <= hi + tol), (method, k)
        if Z.n <= 2 and Z.m <= 12:
            assert Z.contains(xs[k][None], rel_tol=1e-7)[0], (method, k)
    count("zonotopic-contained")


@fuzz(60)
@given(**system_params, how=st.sampled_from(CORRUPTIONS))
def test_kalman(seed, nx, ny, nw, nu, scale, stable, vertex, how):
    count("kalman")
    rng = np.random.default_rng(seed)
    A, B, C, E, F = random_system(rng, nx, ny, nw, nu, scale, stable)
    S = LinearSystem(A, C, B=B, E=E, F=F)
    cov0, _ = corrupt(rand_spd(rng, nx), how, rng)
    kf, err = attempt(ellipsoidal.KalmanFilter, S, np.zeros(nx), cov0)
    if kf is None:
        return
    xs, ys, us = simulate(rng, A, B, C, E, F, rng.standard_normal(nx), 5, vertex, nu=nu)
    for k in range(5):
        m, P = kf.step(ys[k], us[k])
        assert_finite(m)
        assert_psd(P)
    count("kalman-valid")


def random_plant(rng, nx, ny, nd, nv, nu, scale):
    A, B, C, _, _ = random_system(rng, nx, ny, 1, nu, 1.0, True)
    Fm = rng.standard_normal((nx, nd)) * 0.1 * scale if nd else None
    Zm = rng.standard_normal((ny, nv)) * 0.1 * scale if nv else None
    return A, B, C, Fm, Zm


def sim_plant(rng, A, B, C, Fm, Zm, x0, N, vertex, dbar, vbar, nu):
    x = x0.copy()
    xs, ys, us = [x.copy()], [], []
    for _ in range(N):
        d = (rng.choice([-1.0, 1.0], len(dbar)) if vertex else rng.uniform(-1, 1, len(dbar))) * dbar
        v = (rng.choice([-1.0, 1.0], len(vbar)) if vertex else rng.uniform(-1, 1, len(vbar))) * vbar
        u = rng.standard_normal(nu) if nu else None
        y = C @ x + (Zm @ v if Zm is not None else 0)
        x = A @ x + (Fm @ d if Fm is not None else 0) + (B @ u if nu else 0)
        ys.append(y)
        us.append(u)
        xs.append(x.copy())
    return xs, ys, us


plant_params = dict(seed=st.integers(0, 2**32 - 1), nx=st.integers(1, 3), ny=st.integers(1, 2),
                    nd=st.integers(0, 2), nv=st.integers(0, 1), nu=st.integers(0, 1),
                    scale=st.sampled_from((1e-3, 1.0, 1e2)), vertex=st.booleans())


@fuzz(20)
@given(**plant_params)
def test_hinf_observer(seed, nx, ny, nd, nv, nu, scale, vertex):
    count("hinf")
    rng = np.random.default_rng(seed)
    A, B, C, Fm, Zm = random_plant(rng, nx, ny, nd, nv, nu, scale)
    p, err = attempt(Plant, A, C, B=B, F=Fm, Z=Zm)
    if p is None:
        return
    wbar = np.full(nd + nv, 1.0)
    d, err = attempt(hinf.design_ellipsoidal_sm_observer, p, wbar)
    if d is None:
        return
    assert_psd(d.P)
    assert np.isfinite(d.gamma) and d.gamma > 0
    x0 = rng.uniform(-1, 1, nx)
    xh = np.zeros(nx)
    mu0, err = attempt(hinf.mu0_from_box, d, -np.ones(nx), np.ones(nx))
    if mu0 is None:
        return
    obs = hinf.EllipsoidalSMObserver(d, xh, mu0)
    xs, ys, us = sim_plant(rng, A, B, C, Fm, Zm, x0, 6, vertex, wbar[:nd], wbar[nd:], nu)
    for k in range(6):
        bx = obs.step(ys[k], us[k])
        assert_finite(bx.lo, bx.hi)
        tol = 1e-9 * (1 + np.abs(xs[k + 1]))
        assert np.all(xs[k + 1] >= bx.lo - tol) and np.all(xs[k + 1] <= bx.hi + tol), k
    count("hinf-contained")


@fuzz(10)
@given(**plant_params)
def test_eso_d_observer(seed, nx, ny, nd, nv, nu, scale, vertex):
    """CORA's ESO-D (design_eso_d, up to 200 feasibility SDPs) with the thesis observer."""
    count("eso_d")
    rng = np.random.default_rng(seed)
    A, B, C, Fm, Zm = random_plant(rng, nx, ny, nd, nv, nu, scale)
    p, err = attempt(Plant, A, C, B=B, F=Fm, Z=Zm)
    if p is None:
        return
    wbar = np.full(nd + nv, 1.0)
    d, err = attempt(hinf.design_eso_d, p, wbar)
    if d is None:
        return
    assert_psd(d.P)
    assert 0 < d.lambda_ <= 1 and np.isfinite(d.gamma) and d.gamma >= 1
    obs = hinf.EllipsoidalSMObserver(d, np.zeros(nx), hinf.mu0_from_box(d, -np.ones(nx), np.ones(nx)))
    x0 = rng.uniform(-1, 1, nx)
    xs, ys, us = sim_plant(rng, A, B, C, Fm, Zm, x0, 6, vertex, wbar[:nd], wbar[nd:], nu)
    for k in range(6):
        bx = obs.step(ys[k], us[k])
        assert_finite(bx.lo, bx.hi)
        tol = 1e-9 * (1 + np.abs(xs[k + 1]))
        assert np.all(xs[k + 1] >= bx.lo - tol) and np.all(xs[k + 1] <= bx.hi + tol), k
    count("eso_d-contained")


@fuzz(30)
@given(**plant_params, kind=st.sampled_from(("luenberger", "wrapped", "invariant", "nonlinear")))
def test_interval_observers(seed, nx, ny, nd, nv, nu, scale, vertex, kind):
    count("interval-observers")
    rng = np.random.default_rng(seed)
    if kind == "nonlinear":
        nd = nx
    A, B, C, Fm, Zm = random_plant(rng, nx, ny, nd, nv, nu, scale)
    if kind == "nonlinear":
        Fm = np.eye(nx)
    if nd + nv == 0:
        Fm, nd = np.eye(nx) * 0.1, nx
    p = Plant(A, C, B=B, Fd=Fm, Z=Zm)
    x0 = Box(-np.ones(nx), np.ones(nx))
    dbar, vbar = np.full(nd, 0.1 * scale), np.full(nv, 0.1 * scale)
    dbox = Box(-dbar, dbar) if nd else None
    vbox = Box(-vbar, vbar) if nv else None
    if kind in ("luenberger", "wrapped"):
        obs, err = attempt(iobs.IntervalLuenbergerObserver, p, x0, np.zeros(nx), dbox, vbox,
                           variant="tight" if kind == "luenberger" else "wrapped")
    elif kind == "invariant":
        des, err = attempt(iobs.offline_error_sequence, p, x0, np.zeros(nx), dbox, vbox, epsilon=0.05)
        if des is None:
            return
        obs, err = attempt(iobs.IntervalInvariantObserver, des)
    else:
        obs, err = attempt(iobs.NonlinearIntervalObserver, p, x0, np.zeros(nx), vbox, Box(-dbar, dbar))
    if obs is None:
        return
    xs, ys, us = sim_plant(rng, A, B, C, Fm, Zm, rng.uniform(-1, 1, nx), 6, vertex, dbar, vbar, nu)
    for k in range(6):
        bx = obs.step(ys[k], us[k])
        assert_finite(bx.lo, bx.hi)
        tol = 1e-9 * (1 + np.abs(xs[k + 1]))
        assert np.all(xs[k + 1] >= bx.lo - tol) and np.all(xs[k + 1] <= bx.hi + tol), (kind, k)
    count("interval-observers-contained")


# ---- the LMI front end -------------------------------------------------------------------------------

@fuzz(200)
@given(seed=st.integers(0, 2**32 - 1), nv=st.integers(0, 3), n=st.integers(0, 3), how=st.sampled_from(CORRUPTIONS),
       scale=st.sampled_from(SCALES))
def test_lmi_problem(seed, nv, n, how, scale):
    count("lmi")
    rng = np.random.default_rng(seed)
    prob, err = attempt(lmi.Problem, nv)
    if prob is None:
        return
    F0 = rand_spd(rng, max(n, 1))[:n, :n] * scale
    Fs = np.stack([0.5 * (G + G.T) for G in rng.standard_normal((nv, n, n))]) if nv else np.zeros((0, n, n))
    F0c, valid = corrupt(F0, how, rng)
    idx, err = attempt(prob.add_block, F0c, Fs)
    if idx is None:
        return
    _, err = attempt(prob.set_objective, rng.standard_normal(nv))
    prob.set_options(max_iter=30)
    res, err = attempt(prob.solve)
    if res is None:
        return
    if res.status == "optimal":
        x = np.asarray(res.x)
        assert_finite(x)
        m = prob.margin(x)
        assert m >= -1e-6 * max(1.0, np.abs(F0).max() + np.abs(Fs).max() * max(1.0, np.abs(x).max()))


# ---- use of freed objects and double free -----------------------------------------------------------

def test_handles_are_freed_exactly_once_and_objects_keep_their_dependencies():
    """The Python objects own their handles through ffi.gc (freed once, when unreachable); an
    estimator keeps what its handle was built from, so dropping the user's references never
    frees a handle still in use."""
    count("lifetime")
    rng = np.random.default_rng(3)
    A, B, C, E, F = random_system(rng, 2, 1, 2, 0)
    S = LinearSystem(A, C, E=E, F=F)
    d = ellipsoidal.design_offline(S)
    est = ellipsoidal.OnlineEstimator(d, Ellipsoid(np.eye(2), np.zeros(2), 1.0))
    z = zonotopic.SegmentMinEstimator(S, Zonotope(np.zeros(2), np.eye(2)))
    del S, d
    gc.collect()
    y = C @ np.zeros(2)
    est.step(y)
    z.step(y)
    # no public free/close: the handle attribute is an ffi.gc pointer that cannot be freed twice
    from setbound._native import ffi

    for obj in (est, z, est.design, z.system):
        h = getattr(obj, "_handle")
        assert ffi.typeof(h).kind == "pointer"
        closer = getattr(obj, "close", None) or getattr(obj, "free", None)
        if closer is not None:  # if an explicit close is ever added: idempotent, then a clear error
            closer()
            closer()
            with pytest.raises(errors.SetboundError):
                obj.step(y)


# ---- thesis Chapter 1: polytopes and the mRPI shrinking ----------------------------------------------

@fuzz(200)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 3), p=st.integers(0, 9), scale=st.sampled_from(SCALES),
       how=st.sampled_from(CORRUPTIONS), kind=st.sampled_from(("random", "flat", "duplicate")))
def test_polytope(seed, n, p, scale, how, kind):
    count("polytope")
    rng = np.random.default_rng(seed)
    pts = rng.standard_normal((p, n)) * scale
    if kind == "flat" and n > 1:
        pts[:, -1] = 0.0  # not full-dimensional
    elif kind == "duplicate" and p > 1:
        pts[1] = pts[0]
    ptsc, _ = corrupt(pts, how, rng)
    P, err = attempt(sb.Polytope, ptsc)
    if P is None:
        return
    n = P.dimension  # (a transposed point array is a valid polytope of another dimension)
    tol = 1e-9 * scale
    src = np.asarray(ptsc, dtype=float).reshape(-1, n)
    assert np.all(P.contains(src, tol=tol * 10)), "a generating point is outside its hull"
    bb = P.bounding_box()
    assert np.all(src >= bb.lo - tol) and np.all(src <= bb.hi + tol)
    M = rng.standard_normal((n, n)) + 2 * np.eye(n)
    Q, err = attempt(P.linear_map, M)
    if Q is not None:
        assert np.all(Q.contains(src @ M.T, tol=1e-8 * scale * np.abs(M).max() * n))
    S, err = attempt(P.minkowski_sum, P)
    if S is not None:
        assert np.all(S.contains(2 * src, tol=tol * 20))
    R, err = attempt(P.scaled, float(rng.choice([0.5, 2.0, 0.0, -1.0, np.nan])))
    count("polytope-valid")


@fuzz(40)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 3), m=st.integers(1, 2), mu=st.sampled_from((2.0, 10.0, 1.5, 0.5, 1.0)),
       eps=st.sampled_from((0.05, 0.1, 1e-3, 0.0, -1.0)), stop=st.sampled_from(("radius", "shrinking_index", "vertex_norm")))
def test_mrpi(seed, n, m, mu, eps, stop):
    count("mrpi")
    rng = np.random.default_rng(seed)
    A, _, _, E, _ = random_system(rng, n, 1, m, 0)
    r, err = attempt(sb.invariant.mrpi_outer_shrinking, A, E, np.ones(m), eps=eps, mu=mu, stop=stop,
                     boxes_only=True, max_iterations=60)
    if r is None:
        return
    assert r.k_star >= 0 and len(r.boxes) == r.k_star + 1
    for b in r.boxes:
        assert_finite(b.lo, b.hi)
    assert_finite(r.radius_bound)
    # Phi_0 contains the origin's disturbance-driven states: simulate x+ = A x + E w from x in Phi_0
    # and check that the k-th state lies in box k (Phi_k = A Phi_{k-1} + E W)
    x = r.phi0.vertices[rng.integers(0, r.phi0.num_vertices)]
    for k in range(1, r.k_star + 1):
        x = A @ x + E @ rng.choice([-1.0, 1.0], m)
        tol = 1e-9 * (1 + np.abs(x))
        assert np.all(x >= r.boxes[k].lo - tol) and np.all(x <= r.boxes[k].hi + tol), k
    count("mrpi-contained")


# ---- scalar options (issue 26 point 3) ----------------------------------------------------------------
# Every keyword of every public function and method, and every required scalar argument, is listed
# in OPTIONS with its kind; test_every_keyword_is_in_the_options_table fails when a public function
# gains a keyword that is not listed, so that no new option escapes the fuzz below. Kinds:
#   int, int? (None allowed), int* (no upper bound: nothing is sized by it), float, float?,
#   float~ (NaN/±Inf passed to the library, which names them), bool, bool?, choice, choice?, str,
#   str?, pair (two numbers/indices), list (of indices), floats? (a number or one per component),
#   seed (an rng seed), data (an array, a set,
#   a callable: fuzzed by the tests above, not here).

import dataclasses
import functools
import importlib
import inspect
import math
import time

from setbound import interval as sbinterval, invariant, plotting, simulation, system as sbsystem, trajectory
from setbound import fault as sbfault, sets as sbsets
from setbound import constrained_zonotopic as czn, cora as sbcora
from setbound import studies

OPTIONS: dict[str, dict[str, str]] = {
    # ellipsoidal
    "setbound.ellipsoidal.design_offline": {"normalization": "choice", "beta": "float?"},
    "setbound.ellipsoidal.OfflineEstimator.__init__": {"on_inconsistency": "choice", "reset_set": "data"},
    "setbound.ellipsoidal.OnlineEstimator.__init__": {"scaling": "bool", "reuse_tolerance": "float",
                                                      "on_inconsistency": "choice", "reset_set": "data"},
    "setbound.ellipsoidal.ImprovedEstimator.__init__": {"option": "choice", "feedback": "choice",
                                                        "predictor": "choice", "on_inconsistency": "choice",
                                                        "reset_set": "data"},
    "setbound.ellipsoidal.KalmanFilter.__init__": {"omega_cov": "data", "nsigma": "float"},
    "setbound.ellipsoidal.KalmanFilter.step": {"u": "data"},
    "setbound.ellipsoidal.KalmanFilter.run": {"u": "data"},
    "setbound.ellipsoidal._EllipsoidalEstimator.step": {"u": "data"},
    "setbound.ellipsoidal._EllipsoidalEstimator.run": {"u": "data"},
    "setbound.ellipsoidal._BoundingEllipsoidEstimator.__init__": {"QW": "data", "QV": "data", "convention": "choice",
                                                                  "step_cap": "float"},
    "setbound.ellipsoidal._BoundingEllipsoidEstimator.step": {"u": "data"},
    "setbound.ellipsoidal._BoundingEllipsoidEstimator.run": {"u": "data"},
    "setbound.interval_observers.CoraIntervalObserver.step": {"u": "data"},
    "setbound.interval_observers.CoraIntervalObserver.run": {"u": "data"},
    # zonotopic
    "setbound.zonotopic.exact_hull": {"u": "data", "x0": "data", "use_first_measurement": "bool"},
    "setbound.zonotopic.design_pradius": {"approach": "choice", "order": "data", "beta_range": "pair"},
    "setbound.zonotopic._ZonotopicEstimator.__init__": {"max_generators": "int", "use_first_measurement": "bool",
                                                        "strip_order": "data", "reduction": "choice",
                                                        "on_inconsistency": "choice", "reset_set": "data"},
    "setbound.zonotopic.PRadiusEstimator.__init__": {"max_generators": "int", "use_first_measurement": "bool",
                                                     "reduction": "choice", "on_inconsistency": "choice",
                                                     "reset_set": "data"},
    "setbound.zonotopic._ZonotopicEstimator.step": {"u": "data"},
    "setbound.zonotopic._ZonotopicEstimator.run": {"u": "data"},
    # constrained zonotopes
    "setbound.constrained_zonotopic.ConstrainedZonotopicEstimator.__init__": {
        "correction": "choice", "reduction": "choice", "technique": "choice", "order": "float",
        "max_constraints": "int?", "max_generators": "int?", "use_first_measurement": "bool",
        "on_inconsistency": "choice", "reset_set": "data"},
    "setbound.constrained_zonotopic.ConstrainedZonotopicEstimator.step": {"u": "data"},
    "setbound.constrained_zonotopic.ConstrainedZonotopicEstimator.run": {"u": "data", "keep_sets": "bool"},
    "setbound.cora.observe": {"convention": "choice", "gain": "data", "steps": "int?"},
    "setbound.cora.prepare": {"convention": "choice", "gain": "data"},
    "setbound.cora.register_algorithm": {"summary": "str", "accepts_gain": "bool", "gain_required": "data"},
    "setbound.zonotopic.BravoEstimator.__init__": {"max_generators": "int", "reduction": "choice",
                                                   "convention": "choice", "on_inconsistency": "choice"},
    "setbound.zonotopic.WangEstimator.__init__": {"max_generators": "int", "reduction": "choice",
                                                  "convention": "choice", "on_inconsistency": "choice"},
    "setbound.zonotopic.CombastelObserver.__init__": {"max_generators": "int", "reduction": "choice",
                                                      "convention": "choice", "on_inconsistency": "choice"},
    "setbound.zonotopic.StripGainEstimator.__init__": {"all_strips": "bool", "max_generators": "int",
                                                       "reduction": "choice", "convention": "choice", "on_inconsistency": "choice"},
    "setbound.zonotopic.PropagationObserver.__init__": {"max_generators": "int", "reduction": "choice",
                                                        "convention": "choice", "on_inconsistency": "choice"},
    "setbound.zonotopic.ZonotopicObserver.__init__": {"rule": "choice", "gain": "data", "max_generators": "int",
                                                      "reduction": "choice", "convention": "choice",
                                                      "on_inconsistency": "choice"},
    "setbound.zonotopic.design_zonotopic_gain": {"method": "choice", "max_iterations": "int?", "time_limit": "float?"},
    # CORA's ROPO and the Rauch-Tung-Striebel smoother
    "setbound.parallelotope.ParallelotopeEstimator.__init__": {"reduction": "choice", "convention": "choice",
                                                               "on_inconsistency": "choice"},
    "setbound.parallelotope.ParallelotopeEstimator.step": {"u": "data"},
    "setbound.parallelotope.ParallelotopeEstimator.run": {"u": "data"},
    "setbound.point.rts_smooth": {"u": "data", "use_first_measurement": "bool"},
    "setbound.zonotopic._ZonotopicObserver.step": {"u": "data"},
    "setbound.zonotopic._ZonotopicObserver.run": {"u": "data"},
    # hinf
    "setbound.hinf.LpvPlant.__init__": {"B": "data", "Fd": "data", "Z": "data"},
    "setbound.hinf.hinf_observer_gain": {"Q": "data"},
    "setbound.hinf.ellipsoidal_error_rpi": {"g": "float"},
    "setbound.hinf.refine_dissipation_matrix": {"route": "choice", "g": "float"},
    "setbound.hinf.chebyshev_error_ellipsoid": {"t": "float"},
    "setbound.hinf.design_ellipsoidal_sm_observer": {"wbar": "data", "W": "data", "lambda_route": "choice?",
                                                     "passes": "int"},
    "setbound.hinf.design_ellipsoidal_sm_observer_lpv": {"W": "data", "lambda_route": "choice?", "passes": "int"},
    "setbound.hinf.mu0_from_ball": {"radius": "float"},
    "setbound.hinf.design_eso_d": {"wbar": "data", "W": "data", "gammas": "data"},
    "setbound.hinf._Observer.__init__": {"mu0": "float", "on_inconsistency": "choice", "reset_set": "data"},
    "setbound.hinf.EllipsoidalSMObserver.step": {"u": "data"},
    "setbound.hinf.EllipsoidalSMObserver.run": {"u": "data"},
    "setbound.hinf.LPVEllipsoidalSMObserver.step": {"u": "data", "rho": "data"},
    "setbound.hinf.LPVEllipsoidalSMObserver.run": {"u": "data", "rho": "data"},
    # interval
    "setbound.interval.Interval.__init__": {"hi": "data", "name": "str"},
    "setbound.interval.Box.__init__": {"name": "str"},
    "setbound.interval.Box.from_center_radius": {"name": "str"},
    "setbound.interval.Box.empty": {"n": "int"},
    "setbound.interval.IntervalMatrix.__init__": {"name": "str"},
    "setbound.interval.IntervalMatrix.from_mid_rad": {"name": "str"},
    "setbound.interval.power": {"n": "int"},
    # interval observers
    "setbound.interval_observers.interval_error_recursion": {"steps": "int", "variant": "choice"},
    "setbound.interval_observers.interval_error_limit": {"variant": "choice"},
    "setbound.interval_observers.IntervalLuenbergerObserver.__init__": {"xhat0": "data", "d": "data", "v": "data",
                                                                        "L": "data", "variant": "choice",
                                                                        "on_inconsistency": "choice",
                                                                        "reset_set": "data"},
    "setbound.interval_observers.NonlinearIntervalObserver.__init__": {"v": "data", "h": "data", "L": "data",
                                                                       "window": "int", "on_inconsistency": "choice",
                                                                       "reset_set": "data"},
    "setbound.interval_observers.IntervalInvariantObserver.__init__": {"on_inconsistency": "choice",
                                                                       "reset_set": "data"},
    "setbound.interval_observers.NonlinearIntervalObserver.step": {"u": "data", "h": "data"},
    "setbound.interval_observers.IntervalLuenbergerObserver.step": {"u": "data"},
    "setbound.interval_observers.IntervalInvariantObserver.step": {"u": "data"},
    "setbound.interval_observers._OnlineObserver.run": {"u": "data"},
    "setbound.interval_observers.InvariantObserverDesign.box_at": {"k": "int*"},
    "setbound.interval_observers.offline_error_sequence": {
        "d": "data", "v": "data", "L": "data", "P": "data", "gamma": "float?", "mu": "float", "inflation": "float?",
        "epsilon": "float", "variant": "choice"},
    # invariant
    "setbound.invariant.Polytope.contains": {"tol": "float"},
    "setbound.invariant.Polytope.contains_polytope": {"tol": "float"},
    "setbound.invariant.Polytope.scaled": {"a": "float"},
    "setbound.invariant.Polytope.plot_data": {"dims": "pair"},
    "setbound.invariant.ellipsoid_bounding_box": {"rho": "float"},
    "setbound.invariant.expanded_ellipsoid_levels": {"gamma": "float", "wbar_sq": "float", "mu": "float"},
    "setbound.invariant.polyhedral_rpi_between_ellipsoids": {"c_in": "float", "c_out": "float",
                                                            "max_vertices": "int?"},
    "setbound.invariant.mrpi_outer_shrinking": {
        "wbar": "data", "eps": "float", "mu": "float", "stop": "choice", "phi0": "data", "P": "data",
        "c_out": "float?", "delta": "data", "boxes_only": "bool", "max_iterations": "int?"},
    # lmi
    "setbound.lmi.Problem.__init__": {"num_vars": "int"},
    "setbound.lmi.Problem.set_options": {"tol": "float?", "max_iter": "int?", "feas": "float?",
                                         "time_limit": "float?", "threads": "int?"},
    "setbound.lmi.Problem.solve": {"feasibility": "bool", "duals": "bool"},
    "setbound.lmi.Problem.update_block": {"index": "int*"},
    "setbound.lmi.Problem.gevp": {"lambda_lo": "float", "lambda_hi": "float", "tol": "float"},
    "setbound.lmi.solve": {"logdet": "data", "eq": "data", "tol": "float?", "max_iter": "int?", "threads": "int?"},
    # sets
    "setbound.sets.Strip.__init__": {"y": "float~", "phi": "float~"},
    "setbound.sets.Strip.contains": {"rel_tol": "float"},
    "setbound.sets.Ellipsoid.__init__": {"rho": "float~"},
    "setbound.sets.Ellipsoid.contains": {"rel_tol": "float"},
    "setbound.sets.Ellipsoid.affine_map": {"b": "data"},
    "setbound.sets.Zonotope.__init__": {"generators": "data"},
    "setbound.sets.Zonotope.pradius": {"return_vertex": "bool"},
    "setbound.sets.Zonotope.contains": {"rel_tol": "float"},
    "setbound.sets.Zonotope.reduce": {"limit": "int*", "method": "choice"},
    # systems, plants, simulation, trajectories
    "setbound.system.LinearSystem.__init__": {"B": "data", "D": "data", "E": "data", "F": "data", "dt": "float?"},
    "setbound.system.DescriptorSystem.__init__": {"B": "data", "D": "data", "F": "data"},
    "setbound.system.from_statespace": {"E": "data", "F": "data", "disturbance_inputs": "list",
                                        "output_noise": "floats?"},
    "setbound.plant.Plant.__init__": {"B": "data", "Fd": "data", "Z": "data", "dt": "float?"},
    "setbound.sets.ConstrainedZonotope.__init__": {"generators": "data", "A": "data", "b": "data", "rounding": "data"},
    "setbound.sets.ConstrainedZonotope.reduce": {"method": "choice", "technique": "choice", "order": "float~",
                                                 "max_generators": "int?", "max_constraints": "int?"},
    "setbound.sets.ConstrainedZonotope.projection": {"i": "int", "j": "int", "max_vertices": "int"},
    "setbound.sets.ConstrainedZonotope.intersect": {"R": "data"},
    "setbound.sets.ConstrainedZonotope.intersect_halfspace": {"d": "float~"},
    "setbound.sets.as_constrained_zonotope": {"name": "str"},
    "setbound.sets.as_box": {"name": "str"},
    "setbound.sets.as_zonotope": {"name": "str"},
    "setbound.sets.as_ellipsoid": {"name": "str"},
    "setbound.simulation.disturbances": {"kind": "choice", "N": "int", "n": "int"},
    "setbound.simulation.sample_in": {"boundary": "bool"},
    "setbound.simulation.simulate": {"N": "int", "disturbance": "choice", "rng": "seed?", "u": "data",
                                     "A_choice": "choice", "boundary_start": "bool?"},
    "setbound.trajectory.Trajectory.contains": {"tol": "float"},
    "setbound.trajectory.Trajectory.in_bounds": {"tol": "float"},
    "setbound.trajectory.Trajectory.to_dataframe": {"t": "data"},
    "setbound.trajectory.Trajectory.to_pandas": {"names": "data"},
    "setbound.trajectory.Trajectory.plot": {"x_true": "data", "name": "str", "components": "list?", "title": "str?",
                                            "figsize": "pair?"},
    # fault detection
    "setbound.fault.simulate_faulty": {"faults": "data", "disturbance": "choice", "rng": "seed?", "u": "data"},
    "setbound.fault.Detection.plot": {"ax": "data", "fault_start": "int?", "title": "str?"},
    "setbound.fault.detect": {"u": "data"},
    "setbound.fault.nominal": {"name": "str"},
    "setbound.fault.sensor_bias": {"name": "str?"},
    "setbound.fault.stuck_sensor": {"name": "str?"},
    "setbound.fault.actuator_loss": {"name": "str?"},
    "setbound.fault.parameter_change": {"name": "str"},
    "setbound.fault.FaultBank.__init__": {"estimator": "data"},
    "setbound.fault.FaultBank.run": {"u": "data"},
    # plotting
    "setbound.plotting.plot_bounds": {"names": "data", "x_true": "data", "t": "data", "components": "list?",
                                      "title": "str?", "figsize": "pair?"},
    "setbound.plotting.plot_widths": {"names": "data", "reference": "data", "t": "data", "components": "list?",
                                      "log": "bool?", "title": "str?", "figsize": "pair?"},
    "setbound.plotting.plot_volume": {"names": "data", "t": "data", "log": "bool", "title": "str?",
                                      "figsize": "pair?"},
    "setbound.plotting.plot_projections": {"names": "data", "steps": "list", "dims": "pair", "x_true": "data",
                                           "system": "data", "y": "data", "u": "data", "title": "str?",
                                           "figsize": "pair?"},
    "setbound.plotting.ellipse_points": {"rho": "float", "dims": "pair", "n": "int"},
    "setbound.plotting.measurement_strips": {"u": "data"},
    "setbound.plotting.save_png": {"dpi": "int"},
    # studies (issue 23)
    "setbound.studies.engine.Engine.__init__": {"client": "data", "scheduler": "str?", "scheduler_file": "data",
                                               "processes": "int?", "timeout": "float"},
    "setbound.studies.executor.run_cases": {"context": "data", "engine": "data", "total": "int?",
                                            "chunk_seconds": "float", "max_in_flight": "int?", "max_chunk": "int",
                                            "reproduce": "data", "label": "str", "quiet": "bool", "poll": "float"},
    "setbound.studies.store.ResultStore.__init__": {"resume": "bool"},
    "setbound.studies.study.run_study": {"out": "data", "client": "data", "scheduler": "str?",
                                         "scheduler_file": "data", "processes": "int?", "resume": "bool",
                                         "timeout": "float", "chunk_seconds": "float", "plots": "bool",
                                         "quiet": "bool", "sink": "data"},
    "setbound.studies.summary.write_summary": {"extra": "data"},
}

#: The modules whose public functions the table must cover (the API modules; the job-file modules
#: config, campaign, cli, demo and thesis_jobs validate their own values).
API_MODULES = ("ellipsoidal", "zonotopic", "parallelotope", "point", "constrained_zonotopic", "cora", "hinf", "interval", "interval_observers", "invariant", "inclusion", "lmi",
               "sets", "system", "simulation", "plant", "trajectory", "plotting", "benchmarks", "fault",
               "studies", "studies.engine", "studies.executor", "studies.store", "studies.study", "studies.summary",
               "studies.tasks")


def _public_callables():
    """(key, function) of every public function and method defined in the API modules."""
    seen = {}
    for short in API_MODULES:
        mod = importlib.import_module(f"setbound.{short}")
        names = getattr(mod, "__all__", None) or [n for n in vars(mod) if not n.startswith("_")]
        for name in names:
            obj = getattr(mod, name, None)
            if inspect.isfunction(obj) and obj.__module__ == mod.__name__:
                seen[f"{obj.__module__}.{obj.__qualname__}"] = obj
            elif inspect.isclass(obj) and obj.__module__ == mod.__name__:
                for attr, member in inspect.getmembers(obj):
                    if attr.startswith("_") and attr != "__init__":
                        continue
                    fn = member.__func__ if isinstance(member, (classmethod, staticmethod)) else member
                    fn = getattr(fn, "__func__", fn)
                    if not inspect.isfunction(fn) or not fn.__module__.startswith("setbound."):
                        continue
                    if fn.__module__.split(".")[1] not in API_MODULES:
                        continue  # e.g. the state methods of setbound._state
                    if attr == "__init__" and dataclasses.is_dataclass(obj):
                        continue  # a record's generated constructor, not an API entry with options
                    seen[f"{fn.__module__}.{fn.__qualname__}"] = fn
    return seen


def test_every_keyword_is_in_the_options_table():
    """A keyword (a parameter with a default, or keyword-only) of a public function that is
    missing from OPTIONS fails here: classify it there, and the fuzz then draws hostile values
    for it."""
    missing, stale = [], []
    callables = _public_callables()
    for key, fn in callables.items():
        table = OPTIONS.get(key, {})
        for p in inspect.signature(fn).parameters.values():
            if p.name in ("self", "cls") or p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
                continue
            if (p.default is not p.empty or p.kind is p.KEYWORD_ONLY) and p.name not in table:
                missing.append(f"{key}({p.name}=...)")
    for key, opts in OPTIONS.items():
        fn = callables.get(key)
        if fn is None:
            stale.append(key)
            continue
        params = inspect.signature(fn).parameters
        stale += [f"{key}({o})" for o in opts if o not in params]
    assert not missing, "keywords missing from OPTIONS: " + ", ".join(missing)
    assert not stale, "OPTIONS lists what no public function has: " + ", ".join(stale)
    count("options-table")


# -- the small valid problems every option is tried on (built once) --

@functools.cache
def _ctx():
    rng = np.random.default_rng(11)
    S = LinearSystem([[0.5, 0.1], [0.0, 0.6]], [[1.0, 0.0]], E=0.1 * np.eye(2), F=[[0.1, 0.0]])
    d = ellipsoidal.design_offline(S, beta=0.8)
    p = Plant([[0.2, 0.2], [0, 0.5]], [[1, 0]], B=[[1], [1]], Fd=[[0], [0.1]], Z=[[0.1]])
    nlp = Plant([[0.5, 0.1], [0.0, 0.4]], [[1.0, 0.0]], Fd=np.eye(2), Z=[[0.1]])
    lpv = hinf.LpvPlant([[[1, r], [0, 1]] for r in (0.05, 0.1)], [[1, 0]], [[0.05], [0.1]],
                        B=[[[0], [r]] for r in (0.05, 0.1)], Fd=[[[0], [r]] for r in (0.05, 0.1)], Z=[[0.01]])
    hd = hinf.design_ellipsoidal_sm_observer(p, [1.0, 1.0])
    hl = hinf.design_ellipsoidal_sm_observer_lpv(lpv, [1.0, 1.0])
    x0b = Box([-1, -1], [1, 1])
    inv = iobs.offline_error_sequence(p, x0b, np.zeros(2), Box([-0.1], [0.1]), Box([-0.1], [0.1]), epsilon=0.05)
    pr = zonotopic.design_pradius(S)
    poly = sb.Polytope(rng.standard_normal((6, 2)))
    Z = Zonotope(np.zeros(2), np.eye(2) + 0.1)
    E = Ellipsoid(np.eye(2), np.zeros(2), 1.0)
    X0 = Zonotope(np.zeros(2), np.eye(2))
    traj = zonotopic.SegmentMinEstimator(S, X0).run(np.zeros((3, 1)))
    ell_traj = ellipsoidal.OnlineEstimator(d, E).run(np.zeros((3, 1)))
    Su = LinearSystem([[0.5, 0.1], [0.0, 0.6]], [[1.0, 0.0]], B=[[1.0], [0.0]], E=0.1 * np.eye(2), F=[[0.1, 0.0]])
    return dict(S=S, Su=Su, d=d, p=p, nlp=nlp, lpv=lpv, hd=hd, hl=hl, x0b=x0b, inv=inv, pr=pr, poly=poly, Z=Z, E=E,
                X0=X0, traj=traj, ell_traj=ell_traj)


def _cora_model(c):
    from setbound.benchmarks import CoraBenchmark

    return CoraBenchmark("fuzz", c["S"], c["X0"], y=np.zeros((3, 1)), u=np.zeros((3, 0)), truth=None,
                         zonotope_order=20, reduction="girard")


class _FakeSS:  # a discrete-time state-space model (python-control's attributes)
    A, B, C, D, dt = np.array([[0.5]]), np.array([[1.0, 0.5]]), np.array([[1.0]]), np.array([[0.0, 0.0]]), 0.1


def _lmi_problem():
    q = lmi.Problem(1)
    q.add_block(np.eye(2), np.eye(2)[None])
    q.set_objective([1.0])
    return q


def _figure(**kw):
    from matplotlib.figure import Figure

    return plotting.save_png(Figure(figsize=(1, 1)), _TMP / "f.png", **kw)


import tempfile  # noqa: E402
from pathlib import Path  # noqa: E402

_TMP = Path(tempfile.mkdtemp(prefix="setbound-options-"))

#: key -> a call of the function on a small valid problem, with the fuzzed keyword(s) in **kw.
CALLS = {
    "setbound.ellipsoidal.design_offline": lambda c, **kw: ellipsoidal.design_offline(c["S"], **kw),
    "setbound.ellipsoidal.OnlineEstimator.__init__": lambda c, **kw: ellipsoidal.OnlineEstimator(c["d"], c["E"], **kw),
    "setbound.ellipsoidal.OfflineEstimator.__init__": lambda c, **kw: ellipsoidal.OfflineEstimator(c["d"], c["E"], **kw),
    "setbound.ellipsoidal.ImprovedEstimator.__init__":
        lambda c, **kw: ellipsoidal.ImprovedEstimator(c["d"], c["E"], **kw),
    "setbound.ellipsoidal.KalmanFilter.__init__":
        lambda c, **kw: ellipsoidal.KalmanFilter(c["S"], np.zeros(2), np.eye(2), **kw),
    "setbound.ellipsoidal._BoundingEllipsoidEstimator.__init__":
        lambda c, **kw: ellipsoidal.EllipsoidalStateBoundingEstimator(c["S"], c["E"], **kw),
    "setbound.zonotopic.exact_hull": lambda c, **kw: zonotopic.exact_hull(c["S"], np.zeros((2, 1)), x0=c["X0"], **kw),
    "setbound.zonotopic.design_pradius": lambda c, **kw: zonotopic.design_pradius(c["S"], **kw),
    "setbound.zonotopic._ZonotopicEstimator.__init__":
        lambda c, **kw: zonotopic.SegmentMinEstimator(c["S"], c["X0"], **kw),
    "setbound.zonotopic.PRadiusEstimator.__init__": lambda c, **kw: zonotopic.PRadiusEstimator(c["pr"], c["X0"], **kw),
    "setbound.zonotopic.design_zonotopic_gain": lambda c, **kw: zonotopic.design_zonotopic_gain(c["S"], **kw),
    "setbound.zonotopic.BravoEstimator.__init__": lambda c, **kw: zonotopic.BravoEstimator(c["S"], c["X0"], **kw),
    "setbound.parallelotope.ParallelotopeEstimator.__init__":
        lambda c, **kw: sb.parallelotope.ParallelotopeEstimator(c["S"], c["X0"], **kw),
    "setbound.point.rts_smooth": lambda c, **kw: sb.point.rts_smooth(c["S"], np.zeros(2), np.eye(2), 0.01 * np.eye(2),
                                                                     [[0.01]], np.zeros((3, 1)), **kw),
    "setbound.zonotopic.WangEstimator.__init__": lambda c, **kw: zonotopic.WangEstimator(c["S"], c["X0"], **kw),
    "setbound.zonotopic.CombastelObserver.__init__":
        lambda c, **kw: zonotopic.CombastelObserver(c["S"], c["X0"], **kw),
    "setbound.zonotopic.StripGainEstimator.__init__":
        lambda c, **kw: zonotopic.StripGainEstimator(c["S"], c["X0"], [[0.5], [0.1]], **kw),
    "setbound.zonotopic.PropagationObserver.__init__":
        lambda c, **kw: zonotopic.PropagationObserver(c["S"], c["X0"], [[0.5], [0.1]], **kw),
    "setbound.zonotopic.ZonotopicObserver.__init__":
        lambda c, **kw: zonotopic.ZonotopicObserver(c["S"], c["X0"], **{"rule": "volume_min", **kw}),
    "setbound.hinf.ellipsoidal_error_rpi":
        lambda c, **kw: hinf.ellipsoidal_error_rpi(c["hd"].P, c["hd"].Q_refined, wbar=[1.0, 1.0], **kw),
    "setbound.hinf.refine_dissipation_matrix":
        lambda c, **kw: hinf.refine_dissipation_matrix(c["p"], c["hd"].P, c["hd"].L, **{"g": c["hd"].g, **kw}),
    "setbound.hinf.chebyshev_error_ellipsoid": lambda c, **kw: hinf.chebyshev_error_ellipsoid(c["hd"].V, **kw),
    "setbound.hinf.design_ellipsoidal_sm_observer":
        lambda c, **kw: hinf.design_ellipsoidal_sm_observer(c["p"], [1.0, 1.0], **kw),
    "setbound.hinf.design_ellipsoidal_sm_observer_lpv":
        lambda c, **kw: hinf.design_ellipsoidal_sm_observer_lpv(c["lpv"], [1.0, 1.0], **kw),
    "setbound.hinf.mu0_from_ball": lambda c, **kw: hinf.mu0_from_ball(c["hd"], **kw),
    "setbound.hinf._Observer.__init__": lambda c, **kw: hinf.EllipsoidalSMObserver(c["hd"], np.zeros(2), **kw),
    "setbound.interval.Interval.__init__": lambda c, **kw: Interval(0.0, 1.0, **kw),
    "setbound.interval.Box.__init__": lambda c, **kw: Box([0.0], [1.0], **kw),
    "setbound.interval.Box.from_center_radius": lambda c, **kw: Box.from_center_radius([0.0], [1.0], **kw),
    "setbound.interval.Box.empty": lambda c, **kw: Box.empty(**kw),
    "setbound.interval.IntervalMatrix.__init__": lambda c, **kw: IntervalMatrix([[0.0]], [[1.0]], **kw),
    "setbound.interval.IntervalMatrix.from_mid_rad": lambda c, **kw: IntervalMatrix.from_mid_rad([[0.0]], [[1.0]], **kw),
    "setbound.interval.power": lambda c, **kw: sbinterval.power(Interval(0.5, 2.0), **kw),
    "setbound.interval_observers.interval_error_recursion":
        lambda c, **kw: iobs.interval_error_recursion([[0.5]], [[1.0]], Box([-1], [1]), Box([-1], [1]),
                                                      **{"steps": 3, **kw}),
    "setbound.interval_observers.interval_error_limit":
        lambda c, **kw: iobs.interval_error_limit([[0.5]], [[1.0]], Box([-1], [1]), **kw),
    "setbound.interval_observers.IntervalLuenbergerObserver.__init__":
        lambda c, **kw: iobs.IntervalLuenbergerObserver(c["p"], c["x0b"], np.zeros(2), Box([-0.1], [0.1]),
                                                        Box([-0.1], [0.1]), **kw),
    "setbound.interval_observers.NonlinearIntervalObserver.__init__":
        lambda c, **kw: iobs.NonlinearIntervalObserver(c["nlp"], c["x0b"], np.zeros(2), Box([-1], [1]),
                                                       Box([-0.1, -0.1], [0.1, 0.1]), **kw),
    "setbound.interval_observers.InvariantObserverDesign.box_at": lambda c, **kw: c["inv"].box_at(**kw),
    "setbound.interval_observers.IntervalInvariantObserver.__init__":
        lambda c, **kw: iobs.IntervalInvariantObserver(c["inv"], **kw),
    "setbound.plant.Plant.__init__": lambda c, **kw: Plant([[0.5]], [[1.0]], **{"Fd": [[1.0]], **kw}),
    "setbound.interval_observers.offline_error_sequence":
        lambda c, **kw: iobs.offline_error_sequence(c["p"], c["x0b"], np.zeros(2), Box([-0.1], [0.1]),
                                                    Box([-0.1], [0.1]), **kw),
    "setbound.invariant.Polytope.contains": lambda c, **kw: c["poly"].contains(np.zeros(2), **kw),
    "setbound.invariant.Polytope.contains_polytope": lambda c, **kw: c["poly"].contains_polytope(c["poly"], **kw),
    "setbound.invariant.Polytope.scaled": lambda c, **kw: c["poly"].scaled(**kw),
    "setbound.invariant.Polytope.plot_data": lambda c, **kw: c["poly"].plot_data(**kw),
    "setbound.invariant.ellipsoid_bounding_box": lambda c, **kw: invariant.ellipsoid_bounding_box(np.eye(2), [0, 0], **kw),
    "setbound.invariant.expanded_ellipsoid_levels":
        lambda c, **kw: invariant.expanded_ellipsoid_levels(np.eye(2), **{"gamma": 1.0, "wbar_sq": 1.0, "mu": 2.0, **kw}),
    "setbound.invariant.polyhedral_rpi_between_ellipsoids":
        lambda c, **kw: invariant.polyhedral_rpi_between_ellipsoids(np.eye(2), **{"c_in": 1.0, "c_out": 2.0, **kw}),
    "setbound.invariant.mrpi_outer_shrinking":
        lambda c, **kw: invariant.mrpi_outer_shrinking([[0.5]], [[1.0]], [1.0], **{"eps": 0.1, "boxes_only": True,
                                                                                 **kw}),
    "setbound.lmi.Problem.__init__": lambda c, **kw: lmi.Problem(**kw),
    "setbound.lmi.Problem.set_options": lambda c, **kw: _lmi_problem().set_options(**kw),
    "setbound.lmi.Problem.solve": lambda c, **kw: _lmi_problem().solve(**kw),
    "setbound.lmi.Problem.update_block":
        lambda c, **kw: _lmi_problem().update_block(F0=np.eye(2), Fs=np.eye(2)[None], **kw),
    "setbound.lmi.Problem.gevp":
        lambda c, **kw: _lmi_problem().gevp((np.eye(2), np.zeros((1, 2, 2))), (np.eye(2), np.zeros((1, 2, 2))), **kw),
    "setbound.lmi.solve": lambda c, **kw: lmi.solve([1.0], [(np.eye(2), np.eye(2)[None])], **kw),
    "setbound.sets.Strip.__init__": lambda c, **kw: Strip([1.0, 0.0], **{"y": 0.0, "phi": 1.0, **kw}),
    "setbound.sets.Strip.contains": lambda c, **kw: Strip([1.0, 0.0], 0.0, 1.0).contains(np.zeros(2), **kw),
    "setbound.sets.Ellipsoid.__init__": lambda c, **kw: Ellipsoid(np.eye(2), np.zeros(2), **kw),
    "setbound.sets.Ellipsoid.contains": lambda c, **kw: c["E"].contains(np.zeros(2), **kw),
    "setbound.sets.Zonotope.pradius": lambda c, **kw: c["Z"].pradius(np.eye(2), **kw),
    "setbound.sets.Zonotope.contains": lambda c, **kw: c["Z"].contains(np.zeros(2), **kw),
    "setbound.sets.Zonotope.reduce": lambda c, **kw: c["Z"].reduce(**{"limit": 2, **kw}),
    "setbound.system.from_statespace":
        lambda c, **kw: sbsystem.from_statespace(_FakeSS(), **{"disturbance_inputs": [1], **kw}),
    "setbound.simulation.disturbances":
        lambda c, **kw: simulation.disturbances(rng=np.random.default_rng(0), **{"kind": "uniform", "N": 3, "n": 2, **kw}),
    "setbound.simulation.sample_in": lambda c, **kw: simulation.sample_in(c["E"], np.random.default_rng(0), **kw),
    "setbound.simulation.simulate": lambda c, **kw: simulation.simulate(c["S"], c["E"], **{"N": 4, **kw}),
    "setbound.trajectory.Trajectory.contains": lambda c, **kw: c["traj"].contains(np.zeros((3, 2)), **kw),
    "setbound.trajectory.Trajectory.in_bounds": lambda c, **kw: c["traj"].in_bounds(np.zeros((3, 2)), **kw),
    "setbound.trajectory.Trajectory.plot": lambda c, **kw: c["traj"].plot(**kw),
    "setbound.sets.ConstrainedZonotope.reduce":
        lambda c, **kw: sbsets.ConstrainedZonotope([0.0, 0.0], np.eye(2), [[1.0, 0.5]], [0.2]).reduce(**kw),
    "setbound.sets.ConstrainedZonotope.projection":
        lambda c, **kw: sbsets.ConstrainedZonotope([0.0, 0.0], np.eye(2), [[1.0, 0.5]], [0.2]).projection(**kw),
    "setbound.sets.ConstrainedZonotope.intersect_halfspace":
        lambda c, **kw: sbsets.ConstrainedZonotope([0.0, 0.0], np.eye(2)).intersect_halfspace([1.0, 0.0], **kw),
    "setbound.sets.as_constrained_zonotope": lambda c, **kw: sbsets.as_constrained_zonotope(c["Z"], **kw),
    "setbound.constrained_zonotopic.ConstrainedZonotopicEstimator.__init__":
        lambda c, **kw: czn.ConstrainedZonotopicEstimator(c["S"], c["X0"], **kw),
    "setbound.constrained_zonotopic.ConstrainedZonotopicEstimator.run":
        lambda c, **kw: czn.ConstrainedZonotopicEstimator(c["S"], c["X0"]).run(np.zeros((2, 1)), **kw),
    "setbound.cora.observe": lambda c, **kw: sbcora.observe(_cora_model(c), "FRad-A", **kw),
    "setbound.cora.prepare": lambda c, **kw: sbcora.prepare(_cora_model(c), "FRad-A", **kw)(),
    "setbound.cora.register_algorithm":
        lambda c, **kw: sbcora.register_algorithm("FRad-A", lambda m, **o: None, **{"summary": "x", **kw}),
    "setbound.sets.as_box": lambda c, **kw: sbsets.as_box(c["E"], **kw),
    "setbound.sets.as_zonotope": lambda c, **kw: sbsets.as_zonotope(c["E"], **kw),
    "setbound.sets.as_ellipsoid": lambda c, **kw: sbsets.as_ellipsoid(c["Z"], **kw),
    "setbound.system.LinearSystem.__init__": lambda c, **kw: LinearSystem([[0.5]], [[1.0]], **{"E": [[0.1, 0]],
                                                                                              "F": [[0, 0.1]], **kw}),
    "setbound.fault.simulate_faulty": lambda c, **kw: sbfault.simulate_faulty(c["S"], c["X0"], 4, **kw),
    "setbound.fault.Detection.plot": lambda c, **kw: sbfault.detect(zonotopic.SegmentMinEstimator(c["S"], c["X0"]),
                                                                   np.zeros((3, 1))).plot(**kw),
    "setbound.fault.nominal": lambda c, **kw: sbfault.nominal(c["S"], c["X0"], **kw),
    "setbound.fault.sensor_bias": lambda c, **kw: sbfault.sensor_bias(c["S"], c["X0"], 0, 1.0, **kw),
    "setbound.fault.stuck_sensor": lambda c, **kw: sbfault.stuck_sensor(c["S"], c["X0"], 0, **kw),
    "setbound.fault.actuator_loss": lambda c, **kw: sbfault.actuator_loss(c["Su"], c["X0"], 0, 0.5, 1.0, **kw),
    "setbound.fault.parameter_change": lambda c, **kw: sbfault.parameter_change(c["S"], c["X0"], np.eye(2) * 0.5,
                                                                                **kw),
    "setbound.plotting.plot_bounds": lambda c, **kw: plotting.plot_bounds(c["traj"], **kw),
    "setbound.plotting.plot_widths": lambda c, **kw: plotting.plot_widths(c["traj"], **kw),
    "setbound.plotting.plot_volume": lambda c, **kw: plotting.plot_volume(c["traj"], **kw),
    "setbound.plotting.plot_projections":
        lambda c, **kw: plotting.plot_projections(c["ell_traj"], **{"steps": [1], **kw}),
    "setbound.plotting.ellipse_points": lambda c, **kw: plotting.ellipse_points(np.eye(2), np.zeros(2), **{"rho": 1.0,
                                                                                                        **kw}),
    "setbound.plotting.save_png": lambda c, **kw: _figure(**kw),
    # constructing an Engine starts nothing (entering it does)
    "setbound.studies.engine.Engine.__init__": lambda c, **kw: studies.Engine(**kw),
    "setbound.studies.executor.run_cases":
        lambda c, **kw: studies.run_cases("setbound.studies.tasks:busy_case", [{"i": 0, "key": "0"}], list, **kw),
    "setbound.studies.store.ResultStore.__init__":
        lambda c, **kw: studies.ResultStore(_TMP / "store", {"kind": "fuzz", "options": {}}, **kw),
    # every option is checked before any work: the output folder (another study's) then refuses the run
    "setbound.studies.study.run_study": lambda c, **kw: studies.run_study(_study_file(), **{"out": _other_out(), **kw}),
}


def _study_file():
    p = _TMP / "study.toml"
    if not p.exists():
        p.write_text("[system]\nA = [[0.5]]\nC = [[1.0]]\nE = [[0.1, 0.0]]\nF = [[0.0, 0.1]]\n"
                     "[initial]\nlower = [-1.0]\nupper = [1.0]\n[simulation]\nhorizon = 5\n"
                     "[[estimator]]\nmethod = \"segment_min\"\n[study]\nseeds = 2\n")
    return p


def _other_out():
    out = _TMP / "other-study"
    if not out.exists():
        studies.ResultStore(out, {"kind": "another", "options": {}})
    return out

#: Hostile values drawn for every scalar option (the last ones are valid for most kinds).
HOSTILE = (2**31, 2**63, 2**1024, -(2**31) - 1, -1, 0, 3.7, "5", True, False, None, math.nan, math.inf, -math.inf,
           1e300, -0.0, 5e-324, np.int64(3), np.float64(0.5), np.bool_(True), [1], (1.0, 2.0), b"x", object())

_SCALAR_KINDS = ("int", "int?", "int*", "float", "float?", "float~", "bool", "bool?", "choice", "choice?", "str", "str?",
                 "pair", "pair?", "list", "list?", "seed?", "floats?")
FUZZ_OPTIONS = [(k, o, kind) for k, opts in OPTIONS.items() for o, kind in opts.items()
                if kind in _SCALAR_KINDS and k in CALLS]


def _is_int(v):
    return isinstance(v, (int, np.integer)) and not isinstance(v, (bool, np.bool_))


def _must_refuse(kind: str, v) -> bool:
    """Whether ``v`` is invalid for an option of ``kind`` whatever its range (wrong type, NaN, a C
    int overflow); in-range checks depend on the option and are left to the call."""
    if v is None:
        return not kind.endswith("?")
    base = kind.rstrip("?*~")
    if base == "int":
        return not _is_int(v) or (kind != "int*" and not -(2**31) <= int(v) < 2**31)
    if base == "float":
        real = isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, (bool, np.bool_))
        if not real:
            return True
        if kind == "float~":
            return False
        return _is_int(v) and abs(int(v)) > 2**1000 or math.isnan(float(v)) or math.isinf(float(v))
    if base == "bool":
        return not isinstance(v, (bool, np.bool_))
    if base == "str":
        return not isinstance(v, str)
    if base == "choice":  # strings and integers may be among the choices (checked by the call)
        return not (isinstance(v, str) or _is_int(v))
    if base == "pair":
        return not isinstance(v, (list, tuple)) or len(v) != 2
    if base == "list":  # a list of indices (disturbance_inputs also takes one index)
        return not (isinstance(v, (list, tuple)) or _is_int(v))
    if base == "floats":  # a number or one per component
        return not isinstance(v, (list, tuple)) and _must_refuse("float", v)
    return False


def _try_option(key: str, option: str, kind: str, value) -> None:
    call = CALLS[key]
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            call(_ctx(), **{option: value})
        err = None
    except Exception as exc:  # noqa: BLE001 - the property is on the exception itself
        err = exc
    elapsed = time.perf_counter() - t0
    # no hang: a valid-looking huge value is refused before the work starts
    assert elapsed < 10.0, f"{key}({option}={value!r}) took {elapsed:.1f} s"
    if err is None:
        assert not _must_refuse(kind, value), f"{key}({option}={value!r}) accepted a value of the wrong kind"
        return
    assert not isinstance(err, (OverflowError, MemoryError, errors.InternalError)), \
        f"{key}({option}={value!r}): {type(err).__name__}: {err}"
    check_error(err)
    if _must_refuse(kind, value):
        assert isinstance(err, (errors.InvalidArgumentError, errors.DimensionError, errors.NotFiniteError)), \
            f"{key}({option}={value!r}): {type(err).__name__}: {err}"
        assert option in str(err), f"{key}({option}={value!r}): the message does not name the option: {err}"


@pytest.mark.parametrize("key,option,kind", FUZZ_OPTIONS, ids=[f"{k.split('.', 1)[1]}:{o}" for k, o, _ in FUZZ_OPTIONS])
def test_option_hostile_values(key, option, kind):
    """Every hostile value on every scalar option: a result or a named input error."""
    for value in HOSTILE:
        count("options")
        _try_option(key, option, kind, value)


_values = st.one_of(
    st.integers(-(2**70), 2**70), st.integers(-8, 8), st.floats(allow_nan=True, allow_infinity=True),
    st.booleans(), st.none(), st.text(max_size=4), st.sampled_from(HOSTILE),
    st.lists(st.integers(-3, 3), max_size=3), st.tuples(st.floats(-10, 10), st.floats(-10, 10)))


@fuzz(400)
@given(case=st.sampled_from(FUZZ_OPTIONS), value=_values)
def test_option_random_values(case, value):
    count("options-random")
    _try_option(*case, value)


def test_every_fuzzed_function_has_a_call():
    """Every table entry with a scalar option has a CALLS entry (else its options are not fuzzed)."""
    uncovered = [k for k, opts in OPTIONS.items() if any(kd in _SCALAR_KINDS for kd in opts.values()) and k not in CALLS]
    assert not uncovered, "no CALLS entry for: " + ", ".join(uncovered)
    count("options-table")
