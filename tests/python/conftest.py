import os

import numpy as np
import pytest
from hypothesis import HealthCheck, settings

# hypothesis profiles (tests/python/fuzz_support.py scales the fuzz tests by the profile):
#   ci   (default) derandomized, so every CI run generates the same cases;
#   fuzz (make fuzz) random seeds and many more examples.
settings.register_profile("ci", derandomize=True, deadline=None, database=None,
                          suppress_health_check=[HealthCheck.too_slow])
settings.register_profile("fuzz", derandomize=False, deadline=None,
                          suppress_health_check=[HealthCheck.too_slow])
settings.load_profile(os.environ.get("SETBOUND_HYPOTHESIS_PROFILE", "ci"))


@pytest.fixture
def rng():
    """A seeded generator: every random test is reproducible from its seed."""
    return np.random.default_rng(20261121)


def pytest_terminal_summary(terminalreporter):
    import sys

    support = sys.modules.get("fuzz_support")
    if support is None or not support.CASES:
        return
    total = sum(support.CASES.values())
    terminalreporter.write_sep("-", f"fuzz cases executed: {total} (profile {support.PROFILE})")
    for name, n in sorted(support.CASES.items()):
        terminalreporter.write_line(f"  {name}: {n}")
