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


# --- fuzz case count (issue 8: >= 10 000 generated cases per CI run) ----------------------
# Every fuzz test calls fuzz_support.count() once per generated case. The total is checked at the
# end of the session, over both fuzz modules, also when pytest-xdist spreads them over workers
# (`make test` runs -n 2): each worker sends its counts to the controller (workeroutput), which
# adds them up. The check applies only when both fuzz modules ran completely (no -k / -m, no
# selection of single tests); a total below the budget fails the run.
FUZZ_MODULES = ("test_fuzz_api.py", "test_fuzz_capi.py")
FUZZ_BUDGET = int(os.environ.get("SETBOUND_FUZZ_BUDGET", "10000"))  # override only to test this check
_fuzz = {"cases": {}, "complete": None}


def _fuzz_selection_complete(session) -> bool:
    opt = session.config.option
    if getattr(opt, "keyword", "") or getattr(opt, "markexpr", ""):
        return False
    files = {it.path.name for it in session.items}
    if not all(m in files for m in FUZZ_MODULES):
        return False
    # single tests picked by node id (path::name) are a partial selection
    return not any("::" in str(a) and any(m in str(a) for m in FUZZ_MODULES) for a in session.config.args)


def _local_cases() -> dict:
    import sys

    support = sys.modules.get("fuzz_support")
    return dict(support.CASES) if support is not None else {}


def pytest_collection_finish(session):
    _fuzz["complete"] = _fuzz_selection_complete(session)


def pytest_sessionfinish(session, exitstatus):
    workeroutput = getattr(session.config, "workeroutput", None)
    if workeroutput is not None:  # an xdist worker: report to the controller
        workeroutput["fuzz_cases"] = _local_cases()
        workeroutput["fuzz_complete"] = bool(_fuzz["complete"])
        return
    for k, v in _local_cases().items():
        _fuzz["cases"][k] = _fuzz["cases"].get(k, 0) + v
    total = sum(_fuzz["cases"].values())
    if _fuzz["complete"] and session.exitstatus == 0 and total < FUZZ_BUDGET:
        session.config._fuzz_short = total
        session.exitstatus = pytest.ExitCode.TESTS_FAILED


@pytest.hookimpl(optionalhook=True)  # an xdist hook: unknown (and unused) without pytest-xdist
def pytest_testnodedown(node, error):  # xdist controller: a worker finished
    out = getattr(node, "workeroutput", {}) or {}
    for k, v in out.get("fuzz_cases", {}).items():
        _fuzz["cases"][k] = _fuzz["cases"].get(k, 0) + v
    if out.get("fuzz_complete"):
        _fuzz["complete"] = True


def pytest_terminal_summary(terminalreporter):
    cases = dict(_fuzz["cases"]) or _local_cases()
    if not cases:
        return
    total = sum(cases.values())
    import sys

    support = sys.modules.get("fuzz_support")
    profile = support.PROFILE if support is not None else os.environ.get("SETBOUND_HYPOTHESIS_PROFILE", "ci")
    terminalreporter.write_sep("-", f"fuzz cases executed: {total} (profile {profile})")
    for name, n in sorted(cases.items()):
        terminalreporter.write_line(f"  {name}: {n}")
    short = getattr(terminalreporter.config, "_fuzz_short", None)
    if short is not None:
        terminalreporter.write_sep("!", f"FAILED: only {short} fuzz cases executed, the CI budget is {FUZZ_BUDGET}")
