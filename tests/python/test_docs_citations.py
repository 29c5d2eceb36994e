"""Citations a user sees resolve to something the user can open.

The method specification (papers.md, thesis.md) is the project's, not the user's: docstrings,
messages, job-registry descriptions (printed by the command line) and the documentation pages
cite the documentation site instead — "Methods › <page> › <section>" (a page of docs/theory/ and
one of its sections) and bibliography keys such as [Le2013] (docs/bibliography.md).
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
THEORY = ROOT / "docs" / "theory"
SOURCES = sorted((ROOT / "python" / "setbound").rglob("*.py")) + sorted((ROOT / "python" / "setbound").rglob("*.toml"))
PAGES = sorted((ROOT / "docs").glob("*.md")) + sorted(THEORY.glob("*.md")) + [ROOT / "README.md"] + sorted(
    (ROOT / "examples" / "gallery").glob("*.py"))


def method_pages() -> dict[str, set[str]]:
    """``{page title: {section titles}}`` of docs/theory/*.md."""
    out = {}
    for page in THEORY.glob("*.md"):
        text = page.read_text()
        title = re.search(r"^# (.+)$", text, flags=re.M).group(1).strip()
        out[title] = {h.strip() for h in re.findall(r"^## (.+)$", text, flags=re.M)}
    return out


def unresolved(text: str, pages: dict[str, set[str]]) -> list[str]:
    """The citations ``Methods › <page>[ › <section>]`` of ``text`` that name no page of
    docs/theory (by its title) or no section of it. Line breaks inside a citation are allowed;
    ``Methods › <page>`` / ``*page*`` placeholders are not citations."""
    flat = re.sub(r"\s*\n\s*(?:#\s*)?", " ", text)
    bad = []
    for m in re.finditer(r"Methods › ", flat):
        rest = flat[m.end():]
        if rest[:1] in "<*":
            continue
        page = next((t for t in sorted(pages, key=len, reverse=True) if rest.startswith(t)), None)
        if page is None:
            bad.append("Methods › " + re.split(r"[)\];:\"'`]| ›|\. ", rest)[0][:40])
            continue
        rest = rest[len(page):]
        if rest.startswith(" › "):
            rest = rest[3:]
            if not any(rest.startswith(sec) for sec in pages[page]):
                bad.append(f"Methods › {page} › " + re.split(r"[)\];:\"'`]|\. ", rest)[0][:40])
    return bad


@pytest.mark.parametrize("path", SOURCES + PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_no_citation_of_the_specification(path):
    text = path.read_text()
    assert not re.search(r"\b(papers|thesis)\.md\b", text), (
        f"{path.relative_to(ROOT)} cites papers.md/thesis.md, which users do not have: cite the site instead "
        "(Methods › <page> › <section>, see docs/theory/)")


@pytest.mark.parametrize("path", SOURCES + PAGES, ids=lambda p: str(p.relative_to(ROOT)))
def test_method_citations_resolve(path):
    bad = unresolved(path.read_text(), method_pages())
    assert not bad, f"{path.relative_to(ROOT)}: no such method page/section: {sorted(set(bad))}"


def test_bibliography_keys_resolve():
    bib = (ROOT / "docs" / "bibliography.md").read_text()
    keys = set(re.findall(r"^\*\*\[(\w+)\]\*\*", bib, flags=re.M))
    assert {"BenChabane2014", "Merhy2017", "Le2013", "Merhy2019", "Alamo2005", "Loukkas2018"} <= keys
    used = set()
    for path in SOURCES + PAGES:
        used |= set(re.findall(r"\[((?:BenChabane|Merhy|Le|Alamo|Loukkas)\d{4}b?)\]", path.read_text()))
    assert used - keys == set(), f"bibliography keys cited but not in docs/bibliography.md: {used - keys}"


def test_citation_checker_finds_a_bad_section():
    pages = {"Ellipsoidal estimation": {"Offline design"}}
    assert unresolved("see Methods › Ellipsoidal estimation › Offline design.", pages) == []
    assert unresolved("(Methods › Ellipsoidal estimation › Offline desing)", pages) == [
        "Methods › Ellipsoidal estimation › Offline desing"]
    assert unresolved("Methods › Nowhere", pages) == ["Methods › Nowhere"]
