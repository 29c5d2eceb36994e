"""The C++ headers' two compilation modes (include/setbound/core/config.hpp) stay consistent.

Every header with out-of-line definitions includes its impl/<name>.ipp when used header-only,
every .ipp is compiled exactly once into libsetbound (one cpp/definitions_*.cpp includes it), and
every function definition of an .ipp is marked SETBOUND_INLINE, without which two translation
units of a header-only program would define it twice. The compiled mode itself is what the C++
tests build; the header-only mode is built by the ctest cpp_consumer_find_package.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
INCLUDE = ROOT / "include"
IPPS = sorted((INCLUDE / "setbound").glob("**/impl/*.ipp"))  # families may have sub-folders (issue 22)

if not (ROOT / "cpp").is_dir():  # pragma: no cover - an installed package without the sources
    pytest.skip("needs the source tree", allow_module_level=True)


def test_there_are_definition_files():
    assert len(IPPS) >= 30


@pytest.mark.parametrize("ipp", IPPS, ids=lambda p: str(p.relative_to(INCLUDE)))
def test_header_includes_its_definitions_when_header_only(ipp):
    header = ipp.parent.parent / (ipp.stem + ".hpp")
    assert header.is_file(), f"{ipp} has no header {header}"
    text = header.read_text()
    rel = ipp.relative_to(INCLUDE).as_posix()
    tail = re.search(r'#if !defined\(SETBOUND_SEPARATE_COMPILATION\)\s*#include "([^"]+)"\s*#endif\s*$', text)
    assert tail, f"{header.name} must end by including its .ipp unless SETBOUND_SEPARATE_COMPILATION"
    assert tail.group(1) == rel
    own = ipp.read_text()
    assert f'#include "{header.relative_to(INCLUDE).as_posix()}"' in own
    assert '#include "setbound/core/config.hpp"' in own


def test_every_definition_file_is_compiled_exactly_once():
    included: dict[str, list[str]] = {}
    for src in sorted((ROOT / "cpp").glob("definitions_*.cpp")):
        for inc in re.findall(r'^#include "(setbound/[^"]+\.ipp)"', src.read_text(), re.M):
            included.setdefault(inc, []).append(src.name)
    expected = {p.relative_to(INCLUDE).as_posix() for p in IPPS}
    assert set(included) == expected, (sorted(expected - set(included)), sorted(set(included) - expected))
    twice = {k: v for k, v in included.items() if len(v) > 1}
    assert not twice


# A definition starts at column 0 (bodies, continuation lines and ctor initializers are indented).
# A class definition (`struct Name {`) may be repeated in every translation unit (ODR), so it needs
# no marker; a function returning a struct still does.
_NOT_A_DEFINITION = re.compile(r"^(#|//|/\*|\}|namespace\b|$|\s|(struct|class) \w+( final)? \{$)")


@pytest.mark.parametrize("ipp", IPPS, ids=lambda p: str(p.relative_to(INCLUDE)))
def test_every_definition_is_marked_setbound_inline(ipp):
    bad = []
    for number, line in enumerate(ipp.read_text().splitlines(), 1):
        if _NOT_A_DEFINITION.match(line):
            continue
        if not line.startswith("SETBOUND_INLINE "):
            bad.append(f"{ipp.name}:{number}: {line}")
    assert not bad, "definitions without SETBOUND_INLINE (or a body line at column 0):\n" + "\n".join(bad)


def test_the_lint_above_would_catch_a_missing_marker(tmp_path):
    line = "double Ellipsoid::volume() const {"
    assert not _NOT_A_DEFINITION.match(line) and not line.startswith("SETBOUND_INLINE ")
    assert not _NOT_A_DEFINITION.match("struct Plan plan_of(const Eigen::MatrixXd& G) {")
    assert _NOT_A_DEFINITION.match("struct Plan {")
