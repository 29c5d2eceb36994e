"""Checkpointed results of a study: :class:`ResultStore`, written only by the driver.

Layout of the output folder::

    manifest.json            schema version, setbound version, kind, options (what decides the
                             results: a resume with other options is refused), number of cases
    results/part-00000.jsonl one append-only file per run of the driver (a resume starts the next
                             one); one JSON object per line, one line per case
    results/part-00001.jsonl …

Each finished task's records are appended as one write, then flushed and ``fsync``-ed, so a
killed driver loses at most the chunks in flight. A last line without its newline (the driver
killed in the middle of a write) is ignored and its case runs again; any other unreadable line is
an error naming the file and line (the folder was damaged by something else).

JSON lines rather than Parquet: appending one line per case is atomic enough for a torn-write
check (the newline), needs no dependency (pyarrow is a 100 MB wheel), can be inspected with
``head``/``grep``/``jq``, and ``pandas.read_json(lines=True)`` reads it. Parquet files cannot be
appended to, so a checkpoint would be one small file per chunk, the many-small-files problem.
"""
from __future__ import annotations

import json
import os
import re
from pathlib import Path

from .._validate import as_bool

__all__ = ["ResultStore", "StoreError", "SCHEMA_VERSION", "setbound_version", "is_done"]

#: Version of the manifest and record layout.
SCHEMA_VERSION = 1

_PART = re.compile(r"^part-(\d{5,})\.jsonl$")


class StoreError(ValueError):
    """The output folder cannot be used (other options, damaged, not a study folder)."""


def setbound_version() -> str:
    """The installed package version (``unknown`` when running from a source tree)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("setbound")
    except PackageNotFoundError:
        return "unknown"


def _json_default(v):
    import numpy as np

    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, np.ndarray):
        return v.tolist()
    raise TypeError(f"record field of type {type(v).__name__} is not JSON data")


class ResultStore:
    """The output folder ``out`` of a study or campaign (see the module docstring).

    ``manifest``: ``{"kind": ..., "options": {...}, "cases": n}`` (schema and setbound versions
    are added). A folder that holds a manifest is resumed when ``resume`` is true (refused if its
    kind, options, schema or setbound version differ); with ``resume=False`` a folder that holds
    results is refused.

    Parameters
    ----------
    out : str or Path
        The output folder.
    manifest : dict
        See above.
    resume : bool, optional
        Continue an existing folder of the same study.
    """

    def __init__(self, out, manifest: dict, *, resume: bool = True):
        resume = as_bool(resume, "resume")
        self.out = Path(out)
        self.results_dir = self.out / "results"
        want = {"schema": SCHEMA_VERSION, "setbound": setbound_version(), **manifest}
        path = self.out / "manifest.json"
        if path.exists():
            try:
                have = json.loads(path.read_text())
            except (OSError, ValueError) as exc:
                raise StoreError(f"out: {path}: not a readable manifest ({exc})") from None
            if not resume and any(self.results_dir.glob("part-*.jsonl")):
                raise StoreError(f"out: {self.out} already holds results (resume, or choose another folder)")
            for k in ("schema", "setbound", "kind", "options"):
                if have.get(k) != want.get(k):
                    raise StoreError(f"out: {self.out} holds a {have.get('kind', '?')} run with other {k} "
                                     f"({_diff(have.get(k), want.get(k))}); use another folder to start a new one")
            self.resumed = True
        else:
            if self.out.exists() and not self.out.is_dir():
                raise StoreError(f"out: {self.out} is a file, not a folder")
            if self.out.exists() and any(self.out.iterdir()):
                raise StoreError(f"out: {self.out} is not empty and holds no manifest.json (not a study folder)")
            self.out.mkdir(parents=True, exist_ok=True)
            tmp = path.with_suffix(".tmp")
            tmp.write_text(json.dumps(want, indent=1, sort_keys=True, default=_json_default))
            os.replace(tmp, path)
            self.resumed = False
        self.manifest = want
        self.results_dir.mkdir(exist_ok=True)
        self._fh = None
        self.torn = 0

    # ------------------------------------------------------------------ writing
    def _open(self):
        nums = [int(m.group(1)) for p in self.results_dir.iterdir() if (m := _PART.match(p.name))]
        n = max(nums, default=-1) + 1
        self.part = self.results_dir / f"part-{n:05d}.jsonl"
        self._fh = open(self.part, "xb")
        return self._fh

    def append(self, records) -> None:
        """Appends the records (dicts) as JSON lines in one write, then flushes and fsyncs.

        Parameters
        ----------
        records : iterable of dict
            The records.
        """
        if not records:
            return
        fh = self._fh or self._open()
        data = b"".join(json.dumps(r, sort_keys=True, default=_json_default, allow_nan=True).encode() + b"\n"
                        for r in records)
        fh.write(data)
        fh.flush()
        os.fsync(fh.fileno())

    def close(self) -> None:
        """Closes the current result file."""
        if self._fh is not None:
            self._fh.close()
            self._fh = None

    def __enter__(self) -> "ResultStore":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # ------------------------------------------------------------------ reading
    def files(self) -> list:
        """The result files, in order."""
        return sorted(p for p in self.results_dir.iterdir() if _PART.match(p.name))

    def records(self):
        """Yields every record of every result file (streamed; a torn last line is skipped and
        counted in :attr:`torn`)."""
        self.torn = 0
        for p in self.files():
            with open(p, "rb") as fh:
                no = 0
                for line in fh:
                    no += 1
                    if not line.endswith(b"\n"):
                        self.torn += 1  # the driver was killed while writing it
                        break
                    try:
                        rec = json.loads(line)
                    except ValueError as exc:
                        raise StoreError(f"{p}: line {no}: not a JSON record ({exc}); the folder was changed "
                                         f"by something other than setbound") from None
                    if not isinstance(rec, dict) or "i" not in rec or "key" not in rec:
                        raise StoreError(f"{p}: line {no}: not a case record (no 'i'/'key')")
                    yield rec

    def done(self, n: int) -> bytearray:
        """A bitmap (one bit per case index, ``n`` cases) of the cases recorded so far: O(n/8)
        bytes, whatever the size of the records.

        Parameters
        ----------
        n : int
            Number of cases.

        Returns
        -------
        bytearray
        """
        bits = bytearray((n + 7) // 8)
        for rec in self.records():
            i = rec["i"]
            if not isinstance(i, int) or not 0 <= i < n:
                raise StoreError(f"{self.out}: a record has case index {i!r}, outside 0..{n - 1}")
            bits[i >> 3] |= 1 << (i & 7)
        return bits


def is_done(bits: bytearray, i: int) -> bool:
    """Whether case ``i`` is set in a :meth:`ResultStore.done` bitmap."""
    return bool(bits[i >> 3] & (1 << (i & 7)))


def _diff(a, b) -> str:
    if isinstance(a, dict) and isinstance(b, dict):
        keys = sorted(k for k in set(a) | set(b) if a.get(k) != b.get(k))
        return ", ".join(f"{k}: {_short(a.get(k))} then, {_short(b.get(k))} now" for k in keys[:4])
    return f"{_short(a)} then, {_short(b)} now"


def _short(v) -> str:
    s = json.dumps(v, default=str)
    return s if len(s) <= 60 else s[:57] + "..."
