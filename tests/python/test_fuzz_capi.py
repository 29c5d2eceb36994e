"""Fuzzing of the raw C ABI through cffi (issue 8): every exported ``sb_*`` function.

The signatures are read from ``setbound.h`` itself (const-ness and parameter names), so a new
function is fuzzed without touching this file. Each generated case calls one function with

* ``int`` arguments from {-1, 0, 1, 2, 3} (negative, zero and small dimensions, codes) and, in
  the "huge" cases, 2^20 / 2^31-1 with every data pointer NULL (a huge dimension must be
  refused or fail cleanly; with real buffers it would only be a caller's overrun);
* ``double`` arguments among 0, ±1, 0.5, 2, 1e±300, NaN and ±Inf;
* pointers either NULL or a large buffer (the ABI cannot check buffer sizes, so every buffer is
  big enough for the small dimensions used) filled with random normals, zeros, ones, identity
  blocks, huge or tiny numbers or NaNs (identity blocks make symmetric positive definite
  matrices, so the calls also get past validation);
* handles either NULL or a live handle of the right type built once per module.

Property: the process survives, the status is SB_OK or one of the SB_ERR_* codes, never
SB_ERR_INTERNAL; a failure leaves a message "sb_function: argument: what" in sb_last_error();
a success on finite inputs writes no NaN into an output buffer (except the documented NaN
outputs). A segfault would kill pytest, so ``test_capi_fuzz_in_subprocess`` runs a short fuzz
in a child process and reports a crash with its seed.
"""
from __future__ import annotations

import math
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, strategies as st

import setbound
from setbound._native import _header_path, ffi, lib

from fuzz_support import CASES, PROFILE, count, fuzz

STATUSES = set(range(-11, 1))
BUF_DOUBLES = 4096
BUF_INTS = 256
HUGE_INTS = (1 << 20, 2**31 - 1)
DOUBLES = (0.0, 1.0, -1.0, 0.5, 2.0, 1e-300, 1e300, math.nan, math.inf, -math.inf)
FINITE_DOUBLES = (0.0, 1.0, -1.0, 0.5, 2.0, 1e-300, 1e300)
FILLS = ("normal", "zeros", "ones", "eye1", "eye2", "eye3", "nan", "huge", "tiny", "inf")
FINITE_FILLS = ("normal", "zeros", "ones", "eye1", "eye2", "eye3", "huge", "tiny")

# Outputs documented as NaN in some successful cases (setbound.h): the LMI solution of an
# infeasible problem, lambda_direct of an H-infinity pass, gamma of a user gain, mu0 and
# design scalars that are NaN when not computed, margins of outputs that were not tested.
NAN_OUTPUT_OK = re.compile(
    r"^sb_(lmi_solve|lmi_solve_class|lmi_solve_gevp|lmi_dual|lmi_dual_eq|hinf_design_pass|hinf_design_get"
    r"|zonotopic_last_check|czonotopic_last_check|ellipsoidal_last_check|hinf_observer_last_check|interval_luenberger_last_check"
    r"|interval_nonlinear_last_check|interval_invariant_last_check|ropo_last_check|zono_observer_last_check"
    r"|interval_luenberger_info|interval_nonlinear_info|interval_luenberger_gain|interval_nonlinear_gain)$")


# ---- the signatures, from the header --------------------------------------------------------

def _parse_header():
    text = _header_path().read_text()
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    funcs = {}
    for m in re.finditer(r"\bint\s+(sb_\w+)\s*\(([^)]*)\)\s*;", text):
        name, params = m.group(1), m.group(2).strip()
        if params in ("", "void"):
            funcs[name] = []
            continue
        out = []
        for p in params.split(","):
            p = " ".join(p.split())
            pm = re.match(r"^(const\s+)?([A-Za-z_]\w*)\s*(\**)\s*(\w+)$", p.replace("* ", "*").replace(" *", "*"))
            assert pm, f"cannot parse parameter {p!r} of {name}"
            out.append((bool(pm.group(1)), pm.group(2), len(pm.group(3)), pm.group(4)))
        funcs[name] = out
    return funcs


SIGNATURES = _parse_header()
# The two int functions without arguments return a value, not a status (checked in test_lmi.py
# and test_lmi_capi.cpp).
FUNCTIONS = sorted(n for n in SIGNATURES if n not in ("sb_abi_version", "sb_lmi_threads_available"))


def test_header_parsed_completely():
    exported = {n for n in dir(lib) if n.startswith("sb_") and callable(getattr(lib, n))}
    non_int = {"sb_version", "sb_last_error", "sb_status_name"}
    assert exported - non_int == set(SIGNATURES), sorted((exported - non_int) ^ set(SIGNATURES))
    assert len(FUNCTIONS) > 100


# ---- live handles (small, valid objects of every handle type) ----------------------------------

def _arr(x):
    return np.ascontiguousarray(np.asarray(x, dtype=np.float64))


def _p(a):
    return ffi.cast("double*", ffi.from_buffer(a)) if a is not None else ffi.NULL


class Handles:
    """One live handle per type, created through the C ABI; freed with the module."""

    def __init__(self):
        self.h = {}
        self._keep = []
        A = _arr([[0.5, 0.1], [0.0, 0.4]])
        B = _arr([[1.0], [0.0]])
        C = _arr([[1.0, 0.0]])
        E = _arr([[0.1, 0.0], [0.0, 0.1]])
        F = _arr([[0.0, 0.1]])
        self._keep += [A, B, C, E, F]
        self._make("sb_linear_system", lib.sb_linear_system_create, 2, 1, 1, 2, _p(A), _p(B), _p(C), ffi.NULL,
                   _p(E), _p(F), ffi.NULL)
        sysh = self.h["sb_linear_system"]
        p0, H0 = _arr([0.0, 0.0]), _arr([[1.0, 0.0], [0.0, 1.0]])
        self._keep += [p0, H0]
        self._make("sb_zonotopic", lib.sb_zonotopic_create, sysh, lib.SB_ZONO_GAIN_SEGMENT_MIN, ffi.NULL, 6, 1,
                   ffi.NULL, 2, _p(p0), _p(H0))
        self._make("sb_czonotopic", lib.sb_czonotopic_create, sysh, lib.SB_CZN_EXACT_OUTPUT, lib.SB_CZN_REDUCE_LIMITS,
                   lib.SB_REDUCE_GIRARD, 20.0, -1, -1, 1, 2, 0, _p(p0), _p(H0), ffi.NULL, ffi.NULL, ffi.NULL)
        self._make("sb_zono_observer", lib.sb_zono_observer_create, sysh, lib.SB_ZOBS_WANG, ffi.NULL, 6,
                   lib.SB_ZONO_REDUCE_GIRARD, lib.SB_CONVENTION_SETBOUND, 2, _p(p0), _p(H0))
        self._make("sb_ell_design", lib.sb_ell_design_offline, sysh, lib.SB_ELL_NORM_LOGDET, 0.7)
        I2 = _arr(np.eye(2))
        self._keep.append(I2)
        self._make("sb_ellipsoidal", lib.sb_ellipsoidal_create, self.h["sb_ell_design"], lib.SB_ELL_ONLINE_SCALED,
                   0, 0, 0, ffi.NULL, _p(I2), _p(p0), 1.0)
        self._make("sb_kalman", lib.sb_kalman_create, sysh, _p(p0), _p(I2), ffi.NULL)
        self._make("sb_ropo", lib.sb_ropo_create, sysh, ffi.NULL, 2, _p(p0), _p(H0))
        self._make("sb_bounding_ellipsoid", lib.sb_bounding_ellipsoid_create, sysh, ffi.NULL, ffi.NULL, _p(p0),
                   _p(I2), 1.0, lib.SB_BE_X0_SHAPE, lib.SB_BE_LIU, lib.SB_CONVENTION_SETBOUND, 1e-4)
        Lc = _arr([[0.3], [0.1]])
        self._keep.append(Lc)
        self._make("sb_cora_interval", lib.sb_cora_interval_create, sysh, _p(p0), 2, _p(I2), _p(Lc))
        # descriptor system (papers.md §4.2 EX-ME19)
        Ed = _arr(np.diag([1.0, 1.0, 0.0]))
        Ad = _arr([[0.5, 0, 0], [0.8, 0.95, 0], [-1, 0.5, 1]])
        Bd = _arr([[1, 0], [0, 1], [0, 0]])
        Cd = _arr([[1, 0, 1], [1, -1, 0]])
        Dd = _arr([[0.1, 0, 0, 0, 0], [0, 1.5, 0, 0, 0], [0, 0, 0.6, 0, 0]])
        Fd = _arr([[0, 0, 0, 0.5, 0], [0, 0, 0, 0, 1.5]])
        self._keep += [Ed, Ad, Bd, Cd, Dd, Fd]
        self._make("sb_descriptor_system", lib.sb_descriptor_system_create, 3, 2, 2, 5, _p(Ed), _p(Ad), _p(Bd),
                   _p(Cd), _p(Dd), _p(Fd))
        # LMI problem: 2 variables, x1 I + x2 J >= I - ..., a 2x2 block
        self._make("sb_lmi_problem", lib.sb_lmi_problem_create, 2)
        F0 = _arr(-np.eye(2))
        Fs = _arr(np.stack([np.eye(2), np.array([[0.0, 1.0], [1.0, 0.0]])]))
        c = _arr([1.0, 0.0])
        self._keep += [F0, Fs, c]
        assert lib.sb_lmi_add_block(self.h["sb_lmi_problem"], 2, _p(F0), _p(Fs), ffi.NULL) == 0
        assert lib.sb_lmi_set_objective(self.h["sb_lmi_problem"], _p(c)) == 0
        # H-infinity design and observer (LTI, nvert = 1): x+ = A x + F d, y = C x + Z v
        Fh, Zh, wbar = _arr([[0.1], [0.1]]), _arr([[0.1]]), _arr([1.0, 1.0])
        self._keep += [Fh, Zh, wbar]
        self._make("sb_hinf_design", lib.sb_hinf_design_create, 1, 2, 1, 1, 1, 1, 0, _p(A), _p(B), _p(C), _p(Fh),
                   _p(Zh), ffi.NULL, _p(wbar), ffi.NULL, lib.SB_LAMBDA_DEFAULT, 2)
        self._make("sb_hinf_observer", lib.sb_hinf_observer_create, self.h["sb_hinf_design"], _p(p0), 2.0)
        # polytope and mRPI
        sq = _arr([[-1, -1], [1, -1], [1, 1], [-1, 1]])
        self._keep.append(sq)
        self._make("sb_polytope", lib.sb_polytope_from_vertices, 2, 4, _p(sq))
        self._make("sb_mrpi", lib.sb_mrpi_algorithm1, 2, 1, _p(A), _p(Fh), _p(_arr([1.0])), 2.0, 0.1,
                   lib.SB_MRPI_STOP_RADIUS, 0, 0)
        # interval observers on the same plant
        lo, hi = _arr([-1.0, -1.0]), _arr([1.0, 1.0])
        dlo, dhi = _arr([-0.1]), _arr([0.1])
        self._keep += [lo, hi, dlo, dhi]
        self._make("sb_interval_luenberger", lib.sb_interval_luenberger_create, 2, 1, 1, 1, 1, _p(A), _p(B), _p(C),
                   _p(Fh), _p(Zh), ffi.NULL, _p(lo), _p(hi), _p(p0), _p(dlo), _p(dhi), _p(dlo), _p(dhi),
                   lib.SB_IOBS_TIGHT)
        self._make("sb_interval_nonlinear", lib.sb_interval_nonlinear_create, 2, 1, 1, 1, _p(A), _p(B), _p(C),
                   _p(Zh), ffi.NULL, _p(lo), _p(hi), _p(p0), _p(dlo), _p(dhi), 0)
        self._make("sb_interval_invariant_design", lib.sb_interval_invariant_design_create, 2, 1, 1, 1, 1, _p(A),
                   _p(B), _p(C), _p(Fh), _p(Zh), ffi.NULL, ffi.NULL, math.nan, _p(lo), _p(hi), _p(p0), _p(dlo),
                   _p(dhi), _p(dlo), _p(dhi), 2.0, 0.0, 0.05, lib.SB_IOBS_TIGHT)
        self._make("sb_interval_invariant", lib.sb_interval_invariant_create, self.h["sb_interval_invariant_design"])

    def _make(self, type_name, fn, *args):
        out = ffi.new(f"{type_name}**")
        status = fn(*args, out)
        assert status == 0, f"{type_name}: {ffi.string(lib.sb_last_error()).decode()}"
        self.h[type_name] = ffi.gc(out[0], getattr(lib, type_name + "_free"))


@pytest.fixture(scope="module")
def handles():
    return Handles()


def test_every_handle_type_has_a_live_handle(handles):
    types = {t for sig in SIGNATURES.values() for (_, t, stars, _) in sig if t.startswith("sb_") and stars >= 1}
    types.discard("sb_lmi_result")
    types.discard("sb_ropo_options")  # a plain struct (filled per call), not a handle
    assert types <= set(handles.h), sorted(types - set(handles.h))


# ---- one generated call ---------------------------------------------------------------------------

def _make_fill(kind, rng, n):
    if kind == "normal":
        return rng.standard_normal(n)
    if kind == "zeros":
        return np.zeros(n)
    if kind == "ones":
        return np.ones(n)
    if kind.startswith("eye"):
        k = int(kind[3:])
        return np.resize(np.eye(k).ravel(), n)
    if kind in ("nan", "inf"):
        a = rng.standard_normal(n)
        a[rng.integers(0, n, size=n // 16)] = np.nan if kind == "nan" else np.inf
        return a
    if kind == "huge":
        return 1e300 * rng.standard_normal(n)
    if kind == "tiny":
        return 1e-300 * rng.standard_normal(n)
    raise AssertionError(kind)


# Pools of fill values; a case copies a window at a random offset (cheaper than generating).
_POOL = {k: _make_fill(k, np.random.default_rng(7), 4 * BUF_DOUBLES) for k in FILLS}


def _fill(kind, rng, n):
    if kind in ("zeros", "ones") or kind.startswith("eye"):
        return _POOL[kind][:n].copy()
    off = int(rng.integers(0, 3 * BUF_DOUBLES))
    return _POOL[kind][off:off + n].copy()


def call_case(handles, name, data, allow_huge=False):
    """Calls ``name`` with arguments drawn from ``data``; returns what check_case needs.

    ``allow_huge``: some cases use huge dimensions (only in the memory-limited child process: a
    function that allocated before checking its pointers could exhaust the machine's memory)."""
    sig = SIGNATURES[name]
    huge = (allow_huge and data.draw(st.integers(0, 3)) == 0
            and any(t == "int" and s == 0 for (_, t, s, _) in sig))
    seed = data.draw(st.integers(0, 2**32 - 1))
    rng = np.random.default_rng(seed)
    args, outputs, created, finite = [], [], [], not huge
    for const, typ, stars, pname in sig:
        if typ == "int" and stars == 0:
            v = data.draw(st.sampled_from(HUGE_INTS + (-1, 1)) if huge else st.sampled_from((-1, 0, 1, 2, 3)))
            args.append(v)
        elif typ == "double" and stars == 0:
            v = data.draw(st.sampled_from(DOUBLES))
            finite &= math.isfinite(v)
            args.append(v)
        elif typ == "double" and stars == 1:
            if huge or data.draw(st.integers(0, 7)) == 0:
                args.append(ffi.NULL)
            elif const:
                kind = data.draw(st.sampled_from(FILLS))
                finite &= kind in FINITE_FILLS
                buf = np.ascontiguousarray(_fill(kind, rng, BUF_DOUBLES))
                outputs.append((None, buf))
                args.append(ffi.cast("double*", ffi.from_buffer(buf)))
            else:
                buf = np.zeros(BUF_DOUBLES)
                outputs.append((pname, buf))
                args.append(ffi.cast("double*", ffi.from_buffer(buf)))
        elif typ == "int" and stars == 1:
            if huge or data.draw(st.integers(0, 7)) == 0:
                args.append(ffi.NULL)
            else:
                v = data.draw(st.sampled_from((-1, 0, 1, 2, 3, 64)))
                args.append(ffi.new("int[]", [v] + [int(i) % 3 for i in range(BUF_INTS - 1)]))
        elif typ == "sb_lmi_result" and stars == 1:
            args.append(ffi.NULL if data.draw(st.integers(0, 7)) == 0 else ffi.new("sb_lmi_result*"))
        elif typ == "sb_ropo_options" and stars == 1:
            if data.draw(st.integers(0, 5)) == 0:
                args.append(ffi.NULL)
            else:
                o = ffi.new("sb_ropo_options*")
                o.reduction, o.convention, o.on_inconsistency = (data.draw(st.sampled_from((-1, 0, 1, 2, 3, 4)))
                                                                 for _ in range(3))
                args.append(o)
        elif typ.startswith("sb_") and stars == 1:
            if name.endswith("_free"):
                args.append(ffi.NULL)  # live handles are shared; freeing them is the caller's bug
            else:
                args.append(ffi.NULL if data.draw(st.integers(0, 5)) == 0 else handles.h[typ])
        elif typ.startswith("sb_") and stars == 2:
            if data.draw(st.integers(0, 7)) == 0:
                args.append(ffi.NULL)
            else:
                out = ffi.new(f"{typ}**")
                created.append((typ, out))
                args.append(out)
        else:
            raise AssertionError(f"{name}: unhandled parameter {typ}{'*' * stars} {pname}")
    status = getattr(lib, name)(*args)
    message = ffi.string(lib.sb_last_error()).decode("utf-8", "replace")
    for typ, out in created:
        if out[0] != ffi.NULL:
            assert status == 0, f"{name} failed ({status}) but returned a handle"
            assert getattr(lib, typ + "_free")(out[0]) == 0
    nan_out = [p for p, buf in outputs if p is not None and np.isnan(buf).any()]
    return status, message, finite, nan_out, huge


def check_case(name, status, message, finite, nan_out, huge=False):
    assert status in STATUSES, f"{name}: status {status}"
    if status != 0:
        if not (huge and message.endswith(": out of memory")):  # a clean refusal of a huge size
            assert status != lib.SB_ERR_INTERNAL, f"{name}: internal error: {message}"
        assert message.startswith(name + ": "), f"{name}: message {message!r}"
        rest = message[len(name) + 2:]
        assert rest.strip(), f"{name}: empty message"
        assert "internal error" not in rest, message
    elif finite and not NAN_OUTPUT_OK.match(name):
        assert not nan_out, f"{name}: NaN written to {nan_out} from finite inputs"


# Functions that solve LMIs (designs with a scalar search take ~1 s a call): fewer examples.
SLOW = {"sb_zono_gain_design", "sb_zono_gain_design_limits", "sb_ell_design_descriptor", "sb_ell_design_offline", "sb_pradius_design", "sb_hinf_design_create",
        "sb_eso_d_design_create",
        "sb_interval_invariant_design_create", "sb_interval_luenberger_create", "sb_interval_nonlinear_create",
        "sb_mrpi_algorithm1", "sb_lmi_solve_gevp"}


@pytest.mark.parametrize("name", [n for n in FUNCTIONS if n not in SLOW])
@fuzz(60)
@given(data=st.data())
def test_capi_function(handles, name, data):
    status, message, finite, nan_out, huge = call_case(handles, name, data)
    count("capi")
    check_case(name, status, message, finite, nan_out, huge)


@pytest.mark.parametrize("name", sorted(SLOW))
@fuzz(10)
@given(data=st.data())
def test_capi_solver_function(handles, name, data):
    status, message, finite, nan_out, huge = call_case(handles, name, data)
    count("capi")
    check_case(name, status, message, finite, nan_out, huge)


def test_null_handles_are_refused_everywhere():
    """Every function taking a handle refuses NULL with SB_ERR_INVALID_ARGUMENT (free accepts it)."""
    for name, sig in SIGNATURES.items():
        if not any(t.startswith("sb_") and s == 1 and t != "sb_lmi_result" for (_, t, s, _) in sig):
            continue
        args = []
        for const, typ, stars, pname in sig:
            if stars == 0:
                args.append(1 if typ == "int" else 1.0)
            elif typ.startswith("sb_") and stars == 2:
                args.append(ffi.new(f"{typ}**"))
            elif typ == "sb_lmi_result":
                args.append(ffi.new("sb_lmi_result*"))
            elif typ == "int":
                args.append(ffi.new("int[]", BUF_INTS))
            elif typ == "double":
                args.append(ffi.new("double[]", 64))
            else:
                args.append(ffi.NULL)
        status = getattr(lib, name)(*args)
        count("capi-null-handle")
        if name.endswith("_free"):
            assert status == 0, name
        else:
            assert status == lib.SB_ERR_INVALID_ARGUMENT, (name, status)
            msg = ffi.string(lib.sb_last_error()).decode()
            assert msg.startswith(name + ": ") and "null" in msg, msg


# ---- the same fuzz in a child process: a crash is a reported failure -----------------------------

CHILD = textwrap.dedent(r"""
    import resource, sys
    # a huge allocation must fail (bad_alloc) instead of driving the machine out of memory
    resource.setrlimit(resource.RLIMIT_AS, (4 << 30, 4 << 30))
    sys.path.insert(0, {tests!r})
    import numpy as np
    from hypothesis import given, settings, strategies as st, HealthCheck
    import test_fuzz_capi as T
    H = T.Handles()
    for name in T.FUNCTIONS:
        @settings(max_examples={n}, deadline=None, database=None, derandomize={derandomize},
                  suppress_health_check=list(HealthCheck))
        @given(data=st.data())
        def one(data):
            status, message, finite, nan_out, huge = T.call_case(H, name, data, allow_huge=True)
            T.check_case(name, status, message, finite, nan_out, huge)
        print("FUNC", name, flush=True)
        one()
    print("DONE", flush=True)
""")


def test_capi_fuzz_in_subprocess(tmp_path):
    """A segfault or abort in the library kills only the child; the failure names the function."""
    n = 8 if PROFILE != "fuzz" else 200
    script = tmp_path / "child.py"
    script.write_text(CHILD.format(tests=str(Path(__file__).parent), n=n, derandomize=PROFILE != "fuzz"))
    r = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=600,
                       env=dict(os.environ))
    last = [ln for ln in r.stdout.splitlines() if ln.startswith("FUNC")]
    assert r.returncode == 0 and "DONE" in r.stdout, (
        f"child exited with {r.returncode} while fuzzing {last[-1] if last else '?'}\n{r.stderr[-3000:]}")
    CASES["capi-subprocess"] += n * len(FUNCTIONS)


REGRESSION_CHILD = textwrap.dedent(r"""
    import resource, sys
    resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))
    from setbound._native import ffi, lib
    N = ffi.NULL
    out = []
    # fuzz findings: a huge vertex count / state dimension with NULL data was allocated before the
    # pointers were checked (16 GB for theta, nx^2 doubles for the identity): out of memory, or
    # the kernel's OOM killer without a memory limit. Now the NULL pointer is reported first.
    rc = lib.sb_hinf_observer_gain(2**31 - 1, 1, 1, 0, 0, N, N, N, N, N, N, N, N, N, N)
    out.append((rc, ffi.string(lib.sb_last_error()).decode()))
    rc = lib.sb_refine_dissipation_matrix(2**31 - 1, 1, 1, 0, 0, N, N, N, N, N, N, 1.0, 0, N, N)
    out.append((rc, ffi.string(lib.sb_last_error()).decode()))
    rc = lib.sb_interval_nonlinear_create(1 << 16, 0, 1, 0, N, N, N, N, N, N, N, N, N, N, 0,
                                          ffi.new("sb_interval_nonlinear**"))
    out.append((rc, ffi.string(lib.sb_last_error()).decode()))
    print(repr(out))
""")


def test_huge_dimensions_with_null_data_are_refused_before_allocating(tmp_path):
    script = tmp_path / "regression.py"
    script.write_text(REGRESSION_CHILD)
    r = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120, env=dict(os.environ))
    assert r.returncode == 0, r.stderr[-2000:]
    results = eval(r.stdout.strip().splitlines()[-1])
    count("capi-regression")
    for rc, msg in results:
        assert rc == lib.SB_ERR_INVALID_ARGUMENT, msg
        assert msg.endswith("A: null pointer"), msg


@fuzz(100)
@given(cap=st.integers(-3, 12), q=st.integers(0, 3), m=st.integers(1, 6), limit=st.integers(1, 6))
def test_capacities_are_checked(handles, cap, q, m, limit):
    """The in/out capacity arguments (the only buffer sizes the ABI can check): a capacity below
    the size needed gives SB_ERR_BUFFER_TOO_SMALL with the size needed, never an overrun (the
    buffers here hold exactly `cap` items plus a guard zone that must stay untouched)."""
    count("capi-capacity")
    guard = 64
    # vert[M] of a 2x2 interval matrix with q uncertain entries: 2^q matrices
    lo = np.zeros(4)
    hi = np.array([1.0 if i < q else 0.0 for i in range(4)])
    out = np.full(max(cap, 0) * 4 + guard, 7.0)
    cnt = ffi.new("int*", cap)
    rc = lib.sb_imatrix_vertices(2, 2, _p(lo), _p(hi), cnt, _p(out))
    need = 2 ** q
    if cap < need:
        assert rc in (lib.SB_ERR_BUFFER_TOO_SMALL, lib.SB_ERR_INVALID_ARGUMENT), rc
        if rc == lib.SB_ERR_BUFFER_TOO_SMALL:
            assert cnt[0] == need
    else:
        assert rc == 0 and cnt[0] == need
    assert np.all(out[max(cap, 0) * 4:] == 7.0), "write past the capacity"
    # zonotope reduction: at most min(m, limit) generators
    n = 2
    rng = np.random.default_rng(cap + 16 * m)
    H = np.ascontiguousarray(rng.standard_normal((n, m)))
    p = np.zeros(n)
    Hout = np.full(n * max(cap, 0) + guard, 7.0)
    mo = ffi.new("int*", cap)
    rc = lib.sb_zonotope_reduce(n, m, _p(p), _p(H), lib.SB_REDUCE_GIRARD, max(limit, n), mo, _p(Hout))
    if rc == 0:
        assert 0 <= mo[0] <= max(cap, 0)
    else:
        assert rc in (lib.SB_ERR_BUFFER_TOO_SMALL, lib.SB_ERR_INVALID_ARGUMENT, lib.SB_ERR_DIMENSION), rc
        if rc == lib.SB_ERR_BUFFER_TOO_SMALL:
            assert mo[0] > cap
    assert np.all(Hout[n * max(cap, 0):] == 7.0), "write past the capacity"
    # the last set of a zonotopic estimator
    ps, Hs = np.zeros(2), np.full(2 * max(cap, 0) + guard, 7.0)
    mz = ffi.new("int*", cap)
    rc = lib.sb_zonotopic_last_set(handles.h["sb_zonotopic"], mz, _p(ps), _p(Hs))
    assert rc in (0, lib.SB_ERR_BUFFER_TOO_SMALL, lib.SB_ERR_INVALID_ARGUMENT), rc
    if rc == 0:
        assert mz[0] <= max(cap, 0)
    assert np.all(Hs[2 * max(cap, 0):] == 7.0), "write past the capacity"


def test_zonotope_support_overflow_is_an_error_not_nan():
    """Fuzz finding (make fuzz): finite data whose products overflow made d.p = inf + (-inf) and
    sb_zonotope_support wrote NaN with SB_OK. Now SB_ERR_NUMERICAL naming d."""
    count("capi-regression")
    p = _arr([1e300, -1e300])
    H = _arr([[1.0], [1.0]])
    d = _arr([1e10, 1e10])
    v = np.zeros(1)
    rc = lib.sb_zonotope_support(2, 1, _p(p), _p(H), 1, _p(d), _p(v))
    assert rc == lib.SB_ERR_NUMERICAL, (rc, v)
    assert ffi.string(lib.sb_last_error()).decode().startswith("sb_zonotope_support: d: ")
    with pytest.raises(setbound.NumericalError, match="d: "):
        setbound.Zonotope(p, H).support([1e10, 1e10])
    # an ordinary overflow to +inf (no cancellation) stays a valid (infinite) upper bound
    rc = lib.sb_zonotope_support(2, 1, _p(_arr([1e300, 1e300])), _p(H), 1, _p(d), _p(v))
    assert rc == 0 and v[0] == np.inf
