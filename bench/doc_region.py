"""The generated parts of docs/benchmarks.md: each benchmark script owns the region between its
markers `<!-- NAME:begin -->` and `<!-- NAME:end -->` and leaves the rest of the file alone
(bench_zonotopic_cpp.cpp writes its own region the same way)."""
from __future__ import annotations

from pathlib import Path


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
