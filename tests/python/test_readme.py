"""The README's Python quickstart runs as printed."""
import re
from pathlib import Path

import pytest

README = Path(__file__).resolve().parents[2] / "README.md"


def test_python_quickstart_runs(capsys):
    text = README.read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert blocks, "README has no python example"
    for code in blocks:
        exec(compile(code, "README.md", "exec"), {})
    out = capsys.readouterr().out
    assert "array(" in out  # the examples print bounds


def test_cpp_quickstart_is_the_program_the_consumer_test_builds():
    # The ctest cpp_consumer_find_package compiles and runs examples/cpp_consumer/quickstart.cpp
    # against an installed setbound; this keeps the README's copy identical to it.
    text = README.read_text()
    blocks = re.findall(r"```cpp\n(.*?)```", text, flags=re.S)
    assert len(blocks) == 1, "README should have exactly one C++ example"
    program = README.parent / "examples" / "cpp_consumer" / "quickstart.cpp"
    assert blocks[0] == program.read_text()
