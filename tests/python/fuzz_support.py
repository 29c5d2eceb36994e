"""Shared helpers of the fuzz tests (test_fuzz_api.py, test_fuzz_capi.py).

The hypothesis profiles are registered in conftest.py: ``ci`` (the default: derandomized, so a
CI run is reproducible) and ``fuzz`` (``make fuzz``: random seeds, ``FUZZ_SCALE`` times more
examples). The profile is chosen with ``SETBOUND_HYPOTHESIS_PROFILE``.

Every fuzz test calls :func:`count` once per generated case; conftest.py prints the total at
the end of the session and fails the run below the CI budget (10 000 cases).
"""
from __future__ import annotations

import os
import re
from collections import Counter

import numpy as np
from hypothesis import HealthCheck, settings

import setbound
from setbound import errors

PROFILE = os.environ.get("SETBOUND_HYPOTHESIS_PROFILE", "ci")
#: How many times more examples the long ``fuzz`` profile runs than ``ci``.
FUZZ_SCALE = int(os.environ.get("SETBOUND_FUZZ_SCALE", "20"))

#: test name -> generated cases executed in this process.
CASES: Counter = Counter()


def count(name: str) -> None:
    CASES[name] += 1


def fuzz(n: int):
    """hypothesis settings of one fuzz test: ``n`` examples in CI, ``n * FUZZ_SCALE`` in ``make fuzz``."""
    scale = FUZZ_SCALE if PROFILE == "fuzz" else 1
    return settings(
        max_examples=n * scale,
        deadline=None,
        suppress_health_check=list(HealthCheck),
        derandomize=PROFILE != "fuzz",
        database=None,
    )


_NAMED = re.compile(r"^[A-Za-z_][A-Za-z0-9_\[\]\. ,'()-]*:")


def check_error(exc: BaseException) -> None:
    """An error raised by setbound on fuzzed input must be a setbound error (or a
    ValueError/TypeError) with a message that names what is wrong."""
    assert isinstance(exc, (errors.SetboundError, ValueError, TypeError)), (
        f"unexpected exception type {type(exc).__name__}: {exc}")
    msg = str(exc)
    assert msg.strip(), f"{type(exc).__name__} without a message"
    assert not isinstance(exc, errors.InternalError), f"internal error: {msg}"
    assert "internal error" not in msg, msg
    if isinstance(exc, errors.SetboundError):
        # "<argument or function>: <what is wrong>"
        assert _NAMED.match(msg), f"message does not start with a name: {msg!r}"


def assert_finite(*arrays) -> None:
    for a in arrays:
        a = np.asarray(a, dtype=float)
        assert np.all(np.isfinite(a)), f"non-finite output {a}"


def assert_psd(P, name="P") -> None:
    P = np.asarray(P, dtype=float)
    assert_finite(P)
    assert np.allclose(P, P.T, rtol=1e-9, atol=1e-12 * max(1.0, np.abs(P).max())), f"{name} not symmetric"
    w = np.linalg.eigvalsh(0.5 * (P + P.T))
    assert w.min() >= -1e-9 * max(1.0, abs(w).max()), f"{name} not PSD: {w}"


__all__ = ["CASES", "PROFILE", "count", "fuzz", "check_error", "assert_finite", "assert_psd", "setbound"]
