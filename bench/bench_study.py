"""Throughput of the study machinery (issue 23, docs/benchmarks.md "Studies on Dask").

Cases of known cost (``setbound.studies.tasks:busy_case``: a CPU spin of 10 ms or 1 s, so the
figures measure the machinery, not an estimator) run through :func:`setbound.studies.run_cases`
with a :class:`~setbound.studies.ResultStore` (JSON lines, fsync per batch), on

* the serial path (``processes=1``, in this process),
* the embedded LocalCluster with 2 worker processes,
* an external cluster: ``dask scheduler`` + ``dask worker --nworkers 2 --nthreads 1`` started as
  separate programs on 127.0.0.1.

The clusters are started (and warmed up with one task per worker) before the clock starts: the
figures are steady-state throughput. Each figure is the median of ``--repeat`` runs. Then the
driver's memory: the Python allocations of the driver (tracemalloc peak) for 1 000, 10 000 and
100 000 cases of 0 s through the embedded cluster and the store.

Besides the throughput, each run reports the CPU the machinery spent per case (driver, scheduler,
workers, beyond the cases' own CPU): a loaded machine slows the throughput but not that.

Targets: >= 1.7x the serial throughput with 2 workers for 1 s cases; <= 5 % overhead per case
(chunked) for 10 ms cases; a 100 000-case run does not grow the driver's memory beyond a constant.

Usage: python bench/bench_study.py [--repeat 3] [--json out/bench/study.json]
"""
from __future__ import annotations

import argparse
import json
import os
import signal
import statistics
import subprocess
import sys
import tempfile
import time
import tracemalloc
from pathlib import Path

from setbound.studies import Engine, ResultStore, run_cases

TASK = "setbound.studies.tasks:busy_case"


def _cases(n, seconds):
    for i in range(n):
        yield {"i": i, "key": str(i), "seconds": seconds}


def _cpu(engine, external: bool) -> float:
    """CPU seconds used so far by the driver, the workers and (external cluster) the scheduler."""
    t = time.process_time()  # the driver (and the embedded scheduler, which runs in it)
    if engine.client is not None:
        t += sum(engine.client.run(time.process_time).values())
        if external:
            t += engine.client.run_on_scheduler(time.process_time)
    return t


def idle_rate(engine, external: bool, seconds: float = 5.0) -> float:
    """CPU seconds per second the engine spends while idle (heartbeats, system monitors, event
    loops of the scheduler, workers and client)."""
    c0, t0 = _cpu(engine, external), time.perf_counter()
    time.sleep(seconds)
    return (_cpu(engine, external) - c0) / (time.perf_counter() - t0)


def throughput(engine, n, seconds, tmp, external=False) -> tuple:
    """(cases per second, CPU overhead per case as a fraction of the case's CPU time) of one run of
    ``n`` cases of ``seconds`` each, results saved to a store. The overhead counts every CPU second
    of the driver, workers and scheduler beyond the cases' own: unlike the throughput it does not
    depend on what else the machine runs."""
    out = Path(tempfile.mkdtemp(dir=tmp))
    store = ResultStore(out / "o", {"kind": "bench", "options": {}})
    c0 = _cpu(engine, external)
    t0 = time.perf_counter()
    stats = run_cases(TASK, _cases(n, seconds), store.append, engine=engine, total=n, quiet=True)
    dt = time.perf_counter() - t0
    c1 = _cpu(engine, external)
    store.close()
    assert stats.records == n
    return n / dt, (c1 - c0 - n * seconds) / (n * seconds), dt


def _warm(engine):
    if engine.client is not None:
        engine.client.run(lambda: __import__("setbound.studies.tasks"))


class External:
    """``dask scheduler`` and ``dask worker --nworkers 2`` as separate programs."""

    def __init__(self, tmp):
        self.dir = Path(tmp)
        self.file = self.dir / "scheduler.json"
        self.log = open(self.dir / "cluster.log", "wb")
        self.procs = [subprocess.Popen([sys.executable, "-m", "dask", "scheduler", "--host", "127.0.0.1", "--port",
                                        "0", "--no-dashboard", "--scheduler-file", str(self.file)],
                                       stdout=self.log, stderr=subprocess.STDOUT, start_new_session=True)]
        t0 = time.monotonic()
        while not self.file.exists():
            if time.monotonic() - t0 > 120:
                raise RuntimeError("the scheduler did not start")
            time.sleep(0.1)
        self.procs.append(subprocess.Popen([sys.executable, "-m", "dask", "worker", "--scheduler-file",
                                            str(self.file), "--nworkers", "2", "--nthreads", "1", "--no-dashboard",
                                            "--host", "127.0.0.1", "--local-directory", str(self.dir)],
                                           stdout=self.log, stderr=subprocess.STDOUT, start_new_session=True))

    def close(self):
        for p in reversed(self.procs):
            if p.poll() is None:
                os.killpg(p.pid, signal.SIGTERM)
                try:
                    p.wait(timeout=20)
                except subprocess.TimeoutExpired:
                    os.killpg(p.pid, signal.SIGKILL)
                    p.wait(timeout=20)
        self.log.close()


def driver_memory(engine, n, tmp) -> float:
    """Peak Python allocations (MiB) of the driver while ``n`` cases of 0 s run and are saved."""
    out = Path(tempfile.mkdtemp(dir=tmp))
    store = ResultStore(out / "o", {"kind": "bench", "options": {}})
    tracemalloc.start()
    tracemalloc.reset_peak()
    base = tracemalloc.get_traced_memory()[0]
    run_cases(TASK, _cases(n, 0.0), store.append, engine=engine, total=n, quiet=True, max_chunk=2000)
    peak = tracemalloc.get_traced_memory()[1] - base
    tracemalloc.stop()
    # resuming needs one bit per case: the done bitmap is read back from the files
    bits = store.done(n)
    store.close()
    assert sum(bin(b).count("1") for b in bits) == n
    return peak / 2**20


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--json", default="out/bench/study.json")
    ap.add_argument("--long-cases", type=int, default=8, help="1 s cases per run (default 8)")
    ap.add_argument("--short-cases", type=int, default=600, help="10 ms cases per run (default 600)")
    a = ap.parse_args(argv)
    tmp = tempfile.mkdtemp(prefix="bench-study-")
    res = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "cores": os.cpu_count(),
           "load_before": os.getloadavg(), "repeat": a.repeat, "rows": []}
    ext = External(tmp)
    try:
        engines = [("serial", Engine(processes=1)), ("LocalCluster, 2 workers", Engine(processes=2, timeout=120)),
                   ("external dask scheduler + 2 workers", Engine(scheduler_file=ext.file, timeout=120))]
        for label, eng in engines:
            with eng:
                if eng.client is not None:
                    eng.client.wait_for_workers(2, timeout=120)
                _warm(eng)
                idle = idle_rate(eng, label.startswith("external"))
                print(f"{label:38} idle: {idle:.3f} CPU-s per s", flush=True)
                for seconds, n in ((1.0, a.long_cases), (0.01, a.short_cases)):
                    both = [throughput(eng, n, seconds, tmp, label.startswith("external")) for _ in range(a.repeat)]
                    runs = [b[0] for b in both]
                    row = {"engine": label, "case_s": seconds, "cases": n, "runs": runs,
                           "cases_per_s": statistics.median(runs), "load": os.getloadavg()[0],
                           "cpu_overhead": statistics.median(b[1] for b in both), "idle_cpu_per_s": idle,
                           # the per-case part: the idle background of the run's duration taken off
                           "cpu_overhead_net": statistics.median(b[1] - idle * b[2] / (n * seconds) for b in both)}
                    ideal = (1 if eng.client is None else eng.threads) / seconds
                    row["efficiency"] = row["cases_per_s"] / ideal
                    res["rows"].append(row)
                    print(f"{label:38} {seconds * 1000:6.0f} ms cases: {row['cases_per_s']:8.2f} cases/s "
                          f"(runs {', '.join(f'{r:.2f}' for r in runs)}; {100 * row['efficiency']:.1f} % of "
                          f"{ideal:.0f}/s; CPU overhead per case {100 * row['cpu_overhead']:+.2f} %, "
                          f"{100 * row['cpu_overhead_net']:+.2f} % without the idle background; "
                          f"load {row['load']:.2f})", flush=True)
                if label.startswith("LocalCluster"):
                    res["memory"] = {}
                    for n in (1_000, 10_000, 100_000):
                        mib = driver_memory(eng, n, tmp)
                        res["memory"][n] = mib
                        print(f"driver memory, {n:7d} cases of 0 s: peak {mib:6.2f} MiB of Python allocations",
                              flush=True)
    finally:
        ext.close()
    by = {(r["engine"], r["case_s"]): r["cases_per_s"] for r in res["rows"]}
    for label in ("LocalCluster, 2 workers", "external dask scheduler + 2 workers"):
        sp = by[(label, 1.0)] / by[("serial", 1.0)]
        short = [r for r in res["rows"] if r["engine"] == label and r["case_s"] == 0.01][0]
        ov = 1 / short["efficiency"] - 1
        res.setdefault("speedup_1s", {})[label] = sp
        res.setdefault("overhead_10ms", {})[label] = ov
        print(f"{label}: speed-up for 1 s cases {sp:.2f}x (target >= 1.7); 10 ms cases: wall-clock overhead "
              f"{100 * ov:+.1f} % against 2 idle cores, CPU overhead {100 * short['cpu_overhead']:+.2f} % "
              f"({100 * short['cpu_overhead_net']:+.2f} % per case without the idle background; target <= 5 %)")
    res["load_after"] = os.getloadavg()
    print(f"load average before {res['load_before'][0]:.2f}, after {res['load_after'][0]:.2f}")
    Path(a.json).parent.mkdir(parents=True, exist_ok=True)
    Path(a.json).write_text(json.dumps(res, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
