"""Measured data of a job (``[data] file = "run.csv"`` or ``"run.npz"``).

A CSV file has one header row naming its columns — ``y0, y1, …`` (measurements), ``u0, …``
(inputs), ``x0, …`` (the true state, when known) — and one row per step, comma-separated. An
NPZ file holds the arrays ``y`` (N × n_y), ``u`` (N × n_u) and ``x`` (N × n_x). A measurement
that was not taken is an empty cell or ``nan`` (NaN in an NPZ ``y``): the estimators that accept
missing readings skip it (docs/user_guide.md, "Real measurement data"); inputs and states must
be complete. Anything else
(another column or array name, a row of another length, a value that is not a number, a missing
or doubled column index) is refused with the file, the key and the row, rather than read
around: a silently dropped column is a silently wrong estimate.
"""
from __future__ import annotations

import csv
import math
import re
import zipfile
from pathlib import Path

import numpy as np

from .schema import ConfigError, describe

__all__ = ["read_data_file", "MAX_DATA_BYTES"]

_PREFIXES = ("y", "u", "x")
_COLUMN = re.compile(r"^([yux])(\d+)$")
#: CSV cells of a y column that mean "not measured".
_MISSING = ("", "nan", "na")
#: Largest data file read (bytes); bigger files are refused before reading.
MAX_DATA_BYTES = 2 * 1024 ** 3


def _csv(f: Path, shown: str) -> dict:
    try:
        fh = open(f, newline="", encoding="utf-8")
    except OSError as exc:
        raise ConfigError(f"data.file: cannot read {shown} ({exc.strerror})") from None
    with fh:
        try:
            rows = csv.reader(fh, delimiter=",", strict=True)
            header = next(rows, None)
            if header is None:
                raise ConfigError(f"data.file: {shown} is empty (expected a header row y0, y1, …)")
            header = [h.strip() for h in header]
            if len(header) == 1 and any(sep in header[0] for sep in ";\t"):
                sep = ";" if ";" in header[0] else "tab"
                raise ConfigError(f"data.file: {shown}, row 1: the header {describe(header[0])} is one column; the "
                                  f"file seems to be separated by {sep!r} — columns must be separated by commas")
            cols = {}
            for j, h in enumerate(header):
                m = _COLUMN.match(h)
                if not m:
                    raise ConfigError(f"data.file: {shown}, row 1: unknown column {describe(h)} (allowed: y0, y1, … "
                                      f"measurements; u0, … inputs; x0, … true state)")
                if h in cols:
                    raise ConfigError(f"data.file: {shown}, row 1: the column {h!r} appears twice")
                cols[h] = j
            values = []
            for r, row in enumerate(rows, start=2):
                if not row or all(not c.strip() for c in row):
                    continue  # a blank line (e.g. at the end)
                if len(row) != len(header):
                    raise ConfigError(f"data.file: {shown}, row {r}: {len(row)} columns, the header has "
                                      f"{len(header)}")
                line = []
                for j, c in enumerate(row):
                    if header[j][0] == "y" and c.strip().lower() in _MISSING:
                        line.append(math.nan)  # a reading that was not taken
                        continue
                    try:
                        v = float(c)
                    except ValueError:
                        hint = " (separate columns by commas, decimals by a point)" if (";" in c or "," in c) else ""
                        raise ConfigError(f"data.file: {shown}, row {r}, column {header[j]}: "
                                          f"{describe(c.strip())} is not a number{hint}") from None
                    if not math.isfinite(v):
                        what = ("not a finite number (a missing reading is an empty cell or nan)" if header[j][0] == "y"
                                else "not a finite number (inputs and states cannot be missing)")
                        raise ConfigError(f"data.file: {shown}, row {r}, column {header[j]}: {what}")
                    line.append(v)
                values.append(line)
        except csv.Error as exc:
            raise ConfigError(f"data.file: {shown}, row {rows.line_num}: not valid CSV ({exc})") from None
        except UnicodeDecodeError:
            raise ConfigError(f"data.file: {shown} is not a UTF-8 text file") from None
    if not values:
        raise ConfigError(f"data.file: {shown} has a header but no data rows")
    table = np.array(values, dtype=float)
    arrays = {}
    for prefix in _PREFIXES:
        idx = sorted(int(_COLUMN.match(h).group(2)) for h in cols if h[0] == prefix)
        if not idx:
            continue
        if idx != list(range(len(idx))):
            missing = next(i for i in range(len(idx) + 1) if i not in idx)
            raise ConfigError(f"data.file: {shown}, row 1: the column {prefix}{missing} is missing (the {prefix} "
                              f"columns must be numbered {prefix}0, {prefix}1, … without gaps)")
        arrays[prefix] = table[:, [cols[f"{prefix}{i}"] for i in idx]]
    return arrays


def _npz(f: Path, shown: str) -> dict:
    try:
        with np.load(f, allow_pickle=False) as z:
            names = list(z.files)
            unknown = [k for k in names if k not in _PREFIXES]
            if unknown:
                raise ConfigError(f"data.file: {shown}: unknown array {describe(unknown[0])} (allowed: y, u, x)")
            arrays = {k: z[k] for k in names}
    except ConfigError:
        raise
    except (OSError, ValueError, zipfile.BadZipFile, EOFError) as exc:
        raise ConfigError(f"data.file: {shown} is not a readable NPZ file ({describe(str(exc), 80)})") from None
    for k, a in arrays.items():
        if a.dtype.kind not in "iuf":
            raise ConfigError(f"data.{k}: the array {k!r} of {shown} holds {a.dtype} values, not numbers")
        if a.ndim == 1:
            arrays[k] = a.reshape(-1, 1)  # one column
        elif a.ndim != 2:
            raise ConfigError(f"data.{k}: the array {k!r} of {shown} has {a.ndim} dimensions (expected N rows × columns)")
        a = arrays[k].astype(float)
        bad = np.argwhere(np.isinf(a) if k == "y" else ~np.isfinite(a))  # NaN in y: a missing reading
        if bad.size:
            raise ConfigError(f"data.{k}: {shown}, row {int(bad[0][0])}: not a finite number"
                              + (" (a missing reading is NaN)" if k == "y" else " (inputs and states cannot be missing)"))
    return arrays


def read_data_file(f: Path, shown: str) -> dict:
    """The arrays ``y``, ``u``, ``x`` (those present) of a CSV or NPZ data file; ``shown`` is the
    file's name as the user wrote it, for messages."""
    if f.suffix not in (".csv", ".npz"):
        raise ConfigError(f"data.file: expected a .csv or .npz file, got {describe(f.suffix or f.name)}")
    if not f.is_file():
        raise ConfigError(f"data.file: no such file {str(shown)!r}")
    size = f.stat().st_size
    if size > MAX_DATA_BYTES:
        raise ConfigError(f"data.file: {shown} is {size / 1024 ** 3:.1f} GiB (at most {MAX_DATA_BYTES / 1024 ** 3:.0f} GiB)")
    return _csv(f, shown) if f.suffix == ".csv" else _npz(f, shown)


def check_shapes(arrays: dict, shown: str, ny: int, nu: int, nx: int):
    """``(y, u, x)`` with the shapes the system needs; the messages name the file and the key."""
    if "y" not in arrays:
        raise ConfigError(f"data.file: {shown} has no measurements (an array 'y', or CSV columns y0, y1, …)")
    want = {"y": ny, "u": nu, "x": nx}
    what = {"y": "outputs", "u": "inputs", "x": "states"}
    N = arrays["y"].shape[0]
    for k, a in arrays.items():
        if a.shape[1] != want[k]:
            raise ConfigError(f"data.{k}: {shown} has {a.shape[1]} {k} column{'s' if a.shape[1] != 1 else ''}, the "
                              f"system has {want[k]} {what[k]}")
        if a.shape[0] != N:
            raise ConfigError(f"data.{k}: {shown} has {a.shape[0]} rows of {k}, but {N} of y")
    if nu and "u" not in arrays:
        raise ConfigError(f"data.u: {shown} has no inputs (the system has {nu}: CSV columns u0, … or an array 'u')")
    return arrays["y"], arrays.get("u"), arrays.get("x")
