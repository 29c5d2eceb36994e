"""The generated parts of docs/benchmarks.md: each benchmark script owns the region between its
markers `<!-- NAME:begin -->` and `<!-- NAME:end -->` and leaves the rest of the file alone
(bench_zonotopic_cpp.cpp writes its own region the same way), and states where its figures come
from in the same words (`environment`, `load_text`)."""
from __future__ import annotations

import os
import platform
from pathlib import Path

import setbound


def environment() -> str:
    """What a generated table was measured with: "x86_64, 2 cores, Python 3.11.7, setbound 0.1.0"."""
    return (f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
            f"setbound {setbound.__version__}")


def load_text(load=None) -> str:
    """The 1-, 5- and 15-minute load averages (now, or the given triple) as "0.86 0.71 0.90"."""
    return " ".join(f"{v:.2f}" for v in (os.getloadavg() if load is None else load))


def marked(name: str, body: str) -> str:
    """`body` between the markers of `name`."""
    return f"<!-- {name}:begin -->\n{body}\n<!-- {name}:end -->"


def replace_region(text: str, name: str, body: str) -> str | None:
    """`text` with the region of `name` replaced by `body`; None when `text` has no such region."""
    begin, end = f"<!-- {name}:begin -->", f"<!-- {name}:end -->"
    if begin not in text or end not in text:
        return None
    return text[:text.index(begin)] + marked(name, body) + text[text.index(end) + len(end):]


def write_region(path: str | Path, name: str, body: str, heading: str, empty: str = "") -> None:
    """Writes `body` into the region of `name` in the file at `path`; a file without that region
    (or no file: then `empty` is its text) gets a new section `## heading` with the region at its end."""
    path = Path(path)
    text = path.read_text() if path.exists() else empty
    new = replace_region(text, name, body)
    if new is None:
        new = text.rstrip() + f"\n\n## {heading}\n\n{marked(name, body)}\n"
    path.write_text(new)
