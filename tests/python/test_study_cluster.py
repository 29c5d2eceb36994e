"""Studies on a real multi-process Dask cluster started as separate programs (issue 23):
``dask scheduler`` and ``dask worker --nworkers 2`` on 127.0.0.1 with a scheduler file in a temp
folder. A worker killed with SIGKILL, the driver killed and resumed, a case that kills its worker,
the caller's client, an unreachable scheduler. Every wait is bounded (subprocess and client
timeouts); the cluster is stopped by the process ids this file started.

The scheduler runs with ``allowed-failures = 1`` (environment), so a case that kills its worker is
given up after two deaths instead of the default four (each death costs a worker restart)."""
from __future__ import annotations

import json
import operator
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from setbound.jobs.study import load_study
from setbound.studies import Engine, ResultStore, SchedulerUnreachable, run_cases, run_study, summarize

from study_support import records, without_timing, write_study

REPO = Path(__file__).resolve().parents[2]
TESTS = Path(__file__).resolve().parent
START_TIMEOUT = 120  # s: a loaded 2-core CI machine starts Python processes slowly


def _env():
    paths = [str(REPO / "python"), str(TESTS)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
    return {**os.environ, "PYTHONPATH": os.pathsep.join(paths),
            "DASK_DISTRIBUTED__SCHEDULER__ALLOWED_FAILURES": "1",
            # fetching a result from a worker that just died fails after this, not after 30 s
            "DASK_DISTRIBUTED__COMM__TIMEOUTS__CONNECT": "5s"}


def _stop(proc) -> None:
    if proc.poll() is None:
        os.killpg(proc.pid, signal.SIGTERM)  # the group this test created (start_new_session)
        try:
            proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait(timeout=20)


@pytest.fixture(scope="module")
def cluster(tmp_path_factory):
    from distributed import Client

    d = tmp_path_factory.mktemp("dask")
    sf = d / "scheduler.json"
    log = open(d / "cluster.log", "wb")
    procs = []
    client = None
    try:
        procs.append(subprocess.Popen([sys.executable, "-m", "dask", "scheduler", "--host", "127.0.0.1", "--port", "0",
                                       "--no-dashboard", "--scheduler-file", str(sf)], env=_env(), stdout=log,
                                      stderr=subprocess.STDOUT, start_new_session=True))
        t0 = time.monotonic()
        while not sf.exists():
            assert procs[0].poll() is None, (d / "cluster.log").read_text()
            assert time.monotonic() - t0 < START_TIMEOUT, "the scheduler did not write its file"
            time.sleep(0.1)
        procs.append(subprocess.Popen([sys.executable, "-m", "dask", "worker", "--scheduler-file", str(sf),
                                       "--nworkers", "2", "--nthreads", "1", "--no-dashboard", "--host", "127.0.0.1",
                                       "--local-directory", str(d)], env=_env(), stdout=log,
                                      stderr=subprocess.STDOUT, start_new_session=True))
        client = Client(scheduler_file=str(sf), timeout=START_TIMEOUT, set_as_default=False)
        client.wait_for_workers(2, timeout=START_TIMEOUT)
        yield {"file": sf, "client": client, "dir": d}
    finally:
        if client is not None:
            client.close()
        for p in reversed(procs):
            _stop(p)
        log.close()


def _two_workers(client) -> dict:
    client.wait_for_workers(2, timeout=START_TIMEOUT)
    deadline = time.monotonic() + START_TIMEOUT
    while True:  # a restarted worker may be registered before it answers
        pids = client.run(os.getpid)
        if len(pids) >= 2 or time.monotonic() > deadline:
            return pids
        time.sleep(0.2)


def test_worker_killed_mid_study(cluster, tmp_path):
    """A worker SIGKILLed after >= 20 results: every case recorded exactly once, and the records
    equal those of a serial run (timing fields aside)."""
    client = cluster["client"]
    path = write_study(tmp_path / "s.toml", seeds=10)  # 60 cases
    pids = _two_workers(client)
    victim = sorted(pids.values())[0]
    killed = []

    def sink(recs):
        n = sum(len(r) for r in sink.batches) + len(recs)
        sink.batches.append(recs)
        if n >= 20 and not killed:
            os.kill(victim, signal.SIGKILL)
            killed.append(n)
    sink.batches = []

    res = run_study(path, out=tmp_path / "dask", client=client, chunk_seconds=0.05, plots=False, quiet=True,
                    sink=sink)
    assert killed and 20 <= killed[0] < 60, killed
    got = records(tmp_path / "dask")
    assert len(got) == 60 and len({r["key"] for r in got}) == 60 and res.summary.duplicates == 0
    serial = run_study(path, out=tmp_path / "serial", processes=1, plots=False, quiet=True)
    assert serial.stats.records == 60
    a = sorted((without_timing(r) for r in got), key=lambda r: r["i"])
    b = sorted((without_timing(r) for r in records(tmp_path / "serial")), key=lambda r: r["i"])
    assert a == b
    assert client.status == "running"  # the caller's client: still open and usable
    assert client.submit(operator.add, 1, 2, pure=False).result(timeout=60) == 3


def test_driver_killed_then_resumed(cluster, tmp_path):
    """`setbound study` killed after >= 30 % of the cases; `--resume` runs exactly the missing
    cases and the union holds every case once."""
    path = write_study(tmp_path / "s.toml", seeds=10, horizon=800)  # 60 cases of ~50 ms
    out = tmp_path / "out"
    n = 60
    _two_workers(cluster["client"])
    cmd = [sys.executable, "-m", "setbound", "--quiet", "study", path, "--scheduler-file", str(cluster["file"]),
           "--out", str(out), "--no-plots", "--chunk-seconds", "0.05", "--timeout", "60"]
    drv = subprocess.Popen(cmd, env=_env(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, start_new_session=True)
    part = out / "results" / "part-00000.jsonl"
    deadline = time.monotonic() + 180
    try:
        while True:
            lines = part.read_bytes().count(b"\n") if part.exists() else 0
            if lines >= 0.3 * n:
                break
            assert drv.poll() is None, drv.stderr.read().decode()
            assert time.monotonic() < deadline, "the driver recorded too few cases in time"
            time.sleep(0.02)
        os.killpg(drv.pid, signal.SIGKILL)
    finally:
        _stop(drv)
        drv.stderr.close()
    before = records(out)
    done = {r["key"] for r in before}
    assert len(done) == len(before) and 0.3 * n <= len(done) < n, len(done)
    again = subprocess.run(cmd[:-4] + ["--resume", "--timeout", "60"], env=_env(), capture_output=True, text=True,
                           timeout=300)
    assert again.returncode == 0, again.stderr
    assert f"{n} cases ({len(done)} already recorded, {n - len(done)} run now" in again.stdout
    new = [json.loads(x) for x in (out / "results" / "part-00001.jsonl").read_bytes().split(b"\n")[:-1]]
    assert {r["key"] for r in new}.isdisjoint(done)  # exactly the missing cases ran
    union = before + new
    assert len(union) == n and len({r["key"] for r in union}) == n
    assert sorted(r["i"] for r in union) == list(range(n))


def test_a_case_that_kills_its_worker_is_recorded_as_crashed(cluster, tmp_path):
    client = cluster["client"]
    path = write_study(tmp_path / "s.toml", seeds=2)  # 12 cases
    st = load_study(path)
    cases = list(st.cases())
    bad = cases[5]["key"]
    _two_workers(client)
    store = ResultStore(tmp_path / "out", {"kind": "test", "options": {}})
    with Engine(client=client) as eng:
        stats = run_cases("study_support:crash_on", st.cases(), store.append,
                          context={**st.context(), "crash_keys": [bad]}, engine=eng, chunk_seconds=0.0,
                          reproduce=lambda c: f"setbound study {path} --case '{c['key']}'")
    store.close()
    assert stats.crashed == 1 and stats.worker_deaths >= 1
    s = summarize(ResultStore(tmp_path / "out", {"kind": "test", "options": {}}))
    assert s.cases == 12
    assert [c["key"] for c in s.crashed] == [bad]
    assert s.crashed[0]["reproduce"] == f"setbound study {path} --case '{bad}'"
    assert sum(r["ok"] for r in s.rows if not r["parameter"]) == 11  # the others completed
    assert client.status == "running"


def test_unreachable_scheduler_fails_within_the_timeout(tmp_path):
    with socket.socket() as s:  # a port nobody listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    addr = f"tcp://127.0.0.1:{port}"
    path = write_study(tmp_path / "s.toml", seeds=1)
    t0 = time.monotonic()
    with pytest.raises(SchedulerUnreachable) as ei:
        run_study(path, out=tmp_path / "o", scheduler=addr, timeout=3, plots=False, quiet=True)
    assert time.monotonic() - t0 < 30
    assert addr in str(ei.value) and "within 3 s" in str(ei.value)
    # the command line: exit 2, the address named
    p = subprocess.run([sys.executable, "-m", "setbound", "study", path, "--scheduler", addr, "--timeout", "3",
                        "--out", str(tmp_path / "o2")], env=_env(), capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and addr in p.stderr, p.stderr
    with pytest.raises(SchedulerUnreachable, match="no such file"):
        run_study(path, out=tmp_path / "o3", scheduler_file=tmp_path / "missing.json", timeout=3, quiet=True)
