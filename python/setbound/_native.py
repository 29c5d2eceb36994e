"""Loading of the setbound shared library through cffi (ABI mode) and array helpers.

The C header ``setbound.h`` is plain declarations and is handed to ``ffi.cdef`` as is.
Where the library and header are looked up, in order:

1. ``$SETBOUND_LIBRARY`` (path of ``libsetbound.so``) and ``$SETBOUND_HEADER``;
2. every directory of the package ``__path__`` (a wheel installs both next to this file;
   an editable install adds the build's install directory to ``__path__``);
3. the source tree (``include/setbound/setbound.h``) for the header; it comes first when
   ``$SETBOUND_LIBRARY`` is set, since a hand-picked library is usually a build of the tree.

Conventions for the bindings (every module of the package uses them):

* ``as_f64(x, name, shape=...)`` turns input into a C-contiguous float64 array without
  copying when it already is one, and raises :class:`DimensionError` naming ``name`` on a
  wrong shape. Finiteness, symmetry and definiteness are checked by the C library, so the
  same messages reach C, C++ and Python users.
* ``dptr(a)`` gives the ``double*`` into such an array (zero copy).
* ``check(status)`` raises the :mod:`setbound.errors` class of a non-zero status with the
  library's last-error message.
"""
from __future__ import annotations

import os
import sys
from pathlib import Path
from typing import Iterable, Sequence

import numpy as np
from cffi import FFI

from .errors import ERROR_BY_STATUS, DimensionError, InvalidArgumentError, SetboundError

#: ABI version this Python package was written for (must equal sb_abi_version()).
ABI_VERSION = 2

_LIBRARY_NAMES = {
    "linux": ("libsetbound.so",),
    "darwin": ("libsetbound.dylib",),
    "win32": ("setbound.dll", "libsetbound.dll"),
}.get(sys.platform, ("libsetbound.so",))


def _package_dirs() -> list[Path]:
    from . import __path__ as package_path  # type: ignore[attr-defined]

    return [Path(p) for p in package_path]


def _find(candidates: Iterable[Path], what: str) -> Path:
    tried = []
    for c in candidates:
        tried.append(str(c))
        if c.is_file():
            return c
    raise ImportError(
        f"setbound: cannot find the {what}; looked in:\n  " + "\n  ".join(tried)
        + "\nBuild and install the package (pip install .) or set $SETBOUND_LIBRARY."
    )


def _library_path() -> Path:
    env = os.environ.get("SETBOUND_LIBRARY")
    if env:
        return _find([Path(env)], "shared library named by $SETBOUND_LIBRARY")
    return _find((d / n for d in _package_dirs() for n in _LIBRARY_NAMES), "shared library")


def _header_path() -> Path:
    env = os.environ.get("SETBOUND_HEADER")
    if env:
        return _find([Path(env)], "C header named by $SETBOUND_HEADER")
    here = Path(__file__).resolve().parent
    source_header = here.parent.parent / "include" / "setbound" / "setbound.h"
    candidates = [d / "setbound.h" for d in _package_dirs()]
    if os.environ.get("SETBOUND_LIBRARY"):
        # A library picked by hand is usually a fresh build of this source tree: pair it with
        # the tree's header rather than one installed earlier next to the package.
        candidates.insert(0, source_header)
    else:
        candidates.append(source_header)
    return _find(candidates, "C header setbound.h")


def _load():
    ffi = FFI()
    ffi.cdef(_header_path().read_text())
    path = _library_path()
    try:
        lib = ffi.dlopen(str(path))
    except OSError as exc:  # pragma: no cover - depends on the machine
        raise ImportError(f"setbound: cannot load {path}: {exc}") from exc
    abi = lib.sb_abi_version()
    if abi != ABI_VERSION:
        raise ImportError(
            f"setbound: the shared library {path} has ABI version {abi}, but this Python "
            f"package needs ABI version {ABI_VERSION}; reinstall setbound so that both match"
        )
    return ffi, lib, path


ffi, lib, library_path = _load()


def last_error() -> str:
    return ffi.string(lib.sb_last_error()).decode("utf-8", "replace")


def check(status: int) -> None:
    """Raise the matching SetboundError when a C call did not return SB_OK."""
    if status == 0:
        return
    cls = ERROR_BY_STATUS.get(int(status), SetboundError)
    raise cls(last_error() or ffi.string(lib.sb_status_name(status)).decode(), int(status))


def as_f64(
    x,
    name: str,
    shape: Sequence[int | None] | None = None,
    ndim: int | None = None,
) -> np.ndarray:
    """Convert ``x`` to a C-contiguous float64 array (no copy when possible).

    ``shape`` may contain ``None`` for a free dimension. Raises DimensionError or
    InvalidArgumentError naming ``name``.
    """
    if x is None:
        raise InvalidArgumentError(f"{name}: a value is required, got None")
    if np.iscomplexobj(x):
        # numpy would drop the imaginary part with only a warning: a silent wrong result
        raise InvalidArgumentError(f"{name}: expected real numbers, got a complex array")
    try:
        a = np.ascontiguousarray(x, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InvalidArgumentError(f"{name}: expected a numeric array ({exc})") from None
    if shape is not None:
        ndim = len(shape)
    if ndim is not None and a.ndim != ndim:
        if ndim == 2 and a.ndim == 0 and shape is not None and all(s in (1, None) for s in shape):
            a = a.reshape(1, 1)
        else:
            raise DimensionError(
                f"{name}: expected a {ndim}-dimensional array"
                + (f" of shape {_fmt_shape(shape)}" if shape is not None else "")
                + f", got shape {a.shape}"
            )
    if shape is not None:
        for want, got in zip(shape, a.shape):
            if want is not None and want != got:
                raise DimensionError(
                    f"{name}: expected shape {_fmt_shape(shape)}, got {a.shape}"
                )
    return a


def _fmt_shape(shape: Sequence[int | None]) -> str:
    return "(" + ", ".join("n" if s is None else str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"


def dptr(a: np.ndarray):
    """``double*`` into a C-contiguous float64 array (zero copy)."""
    if a.dtype != np.float64 or not a.flags.c_contiguous:
        raise InvalidArgumentError("internal: dptr needs a C-contiguous float64 array")
    if a.size == 0:
        return ffi.NULL
    return ffi.cast("double*", ffi.from_buffer(a, require_writable=False))


def version() -> str:
    """The version of the loaded C library (``setbound.__version__``).

    Returns
    -------
    str

    Examples
    --------
    >>> setbound.version() == setbound.__version__
    True
    """
    return ffi.string(lib.sb_version()).decode()
