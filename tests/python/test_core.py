"""The loader, the ABI-version check and the mapping of C status codes to exceptions."""
import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import setbound
from setbound import _native
from setbound.errors import ERROR_BY_STATUS


def run_python(code: str, **env):
    full_env = dict(os.environ, **env)
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code)], capture_output=True,
                          text=True, env=full_env, timeout=120)


def test_version_comes_from_the_library():
    assert setbound.__version__ == _native.version()
    assert _native.lib.sb_abi_version() == setbound.ABI_VERSION


def test_abi_mismatch_is_a_clear_import_error():
    r = run_python("""
        import setbound._native as n
        n.ABI_VERSION = n.ABI_VERSION + 1
        try:
            n._load()
        except ImportError as e:
            print("IMPORT-ERROR:", e)
    """)
    assert r.returncode == 0, r.stderr
    assert "IMPORT-ERROR:" in r.stdout
    assert "ABI version" in r.stdout and "reinstall" in r.stdout


def test_missing_library_is_a_clear_import_error(tmp_path):
    r = run_python("import setbound", SETBOUND_LIBRARY=str(tmp_path / "nope.so"))
    assert r.returncode != 0
    assert "ImportError" in r.stderr and "nope.so" in r.stderr


def test_every_status_code_maps_to_its_own_class():
    codes = [getattr(_native.lib, n) for n in dir(_native.lib) if n.startswith("SB_ERR_")]
    assert len(codes) == 11
    classes = {ERROR_BY_STATUS[c] for c in codes}
    assert len(classes) == len(codes)
    for c in codes:
        cls = ERROR_BY_STATUS[c]
        assert issubclass(cls, setbound.SetboundError)
        with pytest.raises(cls) as info:
            _native.check(c)
        assert info.value.status == c
    _native.check(0)  # no exception


def test_input_errors_are_also_value_errors():
    assert issubclass(setbound.DimensionError, ValueError)
    assert issubclass(setbound.NotPositiveDefiniteError, ValueError)
    assert not issubclass(setbound.InfeasibleError, ValueError)


def test_as_f64_is_zero_copy_and_names_the_argument():
    a = np.arange(6.0).reshape(2, 3)
    assert _native.as_f64(a, "A", shape=(2, 3)) is a
    b = _native.as_f64(np.asfortranarray(a), "A", shape=(2, None))
    assert b.flags.c_contiguous and np.array_equal(a, b)
    with pytest.raises(setbound.DimensionError, match=r"^A: expected shape \(3, n\)"):
        _native.as_f64(a, "A", shape=(3, None))
    with pytest.raises(setbound.InvalidArgumentError, match="^M: expected a numeric array"):
        _native.as_f64([["a", "b"]], "M", ndim=2)
    with pytest.raises(setbound.InvalidArgumentError, match="^x: a value is required"):
        _native.as_f64(None, "x")
