"""The generated parts of docs/benchmarks.md: each benchmark script owns the region between its
markers `<!-- NAME:begin -->` and `<!-- NAME:end -->` and leaves the rest of the file alone
(bench_zonotopic_cpp.cpp writes its own region the same way)."""
from __future__ import annotations


def marked(name: str, body: str) -> str:
    """`body` between the markers of `name`."""
    return f"<!-- {name}:begin -->\n{body}\n<!-- {name}:end -->"


def replace_region(text: str, name: str, body: str) -> str | None:
    """`text` with the region of `name` replaced by `body`; None when `text` has no such region."""
    begin, end = f"<!-- {name}:begin -->", f"<!-- {name}:end -->"
    if begin not in text or end not in text:
        return None
    return text[:text.index(begin)] + marked(name, body) + text[text.index(end) + len(end):]
