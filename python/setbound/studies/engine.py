"""Where the tasks of a study or campaign run: :class:`Engine`.

* ``processes=1`` (and no scheduler or client): in this process, one case after the other (for
  debugging one case; nothing is pickled, a crash of a case is a crash of the caller).
* no scheduler given: an embedded ``distributed.LocalCluster`` of worker *processes*, one per core
  (or ``processes``), one thread each, no dashboard; started on entry, closed on exit.
* ``scheduler="tcp://HOST:PORT"`` or ``scheduler_file=PATH``: an existing Dask cluster (``dask
  scheduler`` / ``dask worker``, dask-jobqueue, …); the client made for it is closed on exit, the
  cluster is left running.
* ``client=``: the caller's ``distributed.Client``, used as it is and never closed.

A scheduler that cannot be reached raises :class:`SchedulerUnreachable` (a ``ConnectionError``)
naming the address within ``timeout`` seconds.
"""
from __future__ import annotations

import logging
import os

from .._validate import as_float, as_int, as_str

__all__ = ["Engine", "SchedulerUnreachable", "default_processes"]


#: Messages a batched stream of the driver process keeps for debugging (distributed's default: 1000).
_LOG_LENGTH = 8


class SchedulerUnreachable(ConnectionError):
    """The scheduler given (address or file) did not answer within the timeout."""


def default_processes() -> int:
    """Worker processes of the embedded cluster: the cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


class Engine:
    """The task engine (see the module docstring), a context manager.

    ::

        with Engine(processes=2) as eng:
            eng.client    # a distributed.Client, or None on the serial path
            eng.threads   # tasks that run at once (worker threads, 1 when serial)

    Parameters
    ----------
    client : distributed.Client, optional
        Yours, left open.
    scheduler : str, optional
        Address ``tcp://HOST:PORT`` of a running scheduler.
    scheduler_file : str or Path, optional
        A Dask scheduler file.
    processes : int, optional
        Workers of an embedded LocalCluster (default: one per core; 1 runs serially).
    timeout : float, optional
        Seconds to reach a scheduler.
    """

    def __init__(self, *, client=None, scheduler=None, scheduler_file=None, processes=None,
                 timeout: float = 30.0):
        given = [n for n, v in (("client", client), ("scheduler", scheduler), ("scheduler_file", scheduler_file))
                 if v is not None]
        if len(given) > 1:
            raise ValueError(f"{given[1]}: give one of client, scheduler and scheduler_file, not {' and '.join(given)}")
        self.scheduler = None if scheduler is None else as_str(scheduler, "scheduler")
        self.scheduler_file = None if scheduler_file is None else os.fspath(scheduler_file)
        self.processes = None if processes is None else as_int(processes, "processes", lo=1, hi=4096)
        self.timeout = as_float(timeout, "timeout", lo=0, lo_open=True, hi=86400)
        if client is not None and not hasattr(client, "submit"):
            raise ValueError(f"client: expected a distributed.Client, got {type(client).__name__}")
        self._caller_client = client
        self.client = None
        self._cluster = None
        self._own_client = False
        self._config = None

    @property
    def serial(self) -> bool:
        """True when tasks run in this process (``processes=1``, no scheduler, no client)."""
        return (self.processes == 1 and self._caller_client is None and self.scheduler is None
                and self.scheduler_file is None)

    @property
    def where(self) -> str:
        """Where the tasks run, for messages and the manifest."""
        if self.serial:
            return "serial (in this process)"
        if self._caller_client is not None:
            return f"the caller's client ({getattr(self._caller_client, 'scheduler', None) and self._caller_client.scheduler.address})"
        if self.scheduler:
            return self.scheduler
        if self.scheduler_file:
            return f"scheduler file {self.scheduler_file}"
        return f"LocalCluster ({self.processes or default_processes()} worker processes)"

    def __enter__(self) -> "Engine":
        if self.serial:
            return self
        if self._caller_client is not None:
            self.client = self._caller_client
            return self
        import dask
        from distributed import Client

        # Every batched stream of this process (the client's to the scheduler, and the embedded
        # scheduler's to its workers) keeps its last `low-level-log-length` messages (1000 by
        # default) for debugging, each with a task and its chunk of cases: with long chunks that
        # is hundreds of MiB held by the driver. Keep a few. The event-loop "tick" (a check for a
        # blocked loop, every 20 ms by default, in the client, the embedded scheduler and, through
        # the nannies, the embedded workers) is a third of an idle 2-worker cluster's CPU: 1 s.
        self._config = dask.config.set({"distributed.admin.low-level-log-length": _LOG_LENGTH,
                                        "distributed.admin.tick.interval": "1s"})
        try:
            return self._start(Client)
        except BaseException:
            self.close()
            raise

    def _start(self, Client) -> "Engine":

        if self.scheduler is not None or self.scheduler_file is not None:
            what = self.scheduler if self.scheduler is not None else f"scheduler file {self.scheduler_file}"
            if self.scheduler_file is not None and not os.path.exists(self.scheduler_file):
                # Client would wait for the file to appear until the timeout; say it now
                raise SchedulerUnreachable(f"scheduler_file: {self.scheduler_file}: no such file")
            try:
                self.client = Client(self.scheduler, scheduler_file=self.scheduler_file, timeout=self.timeout,
                                     set_as_default=False)
            except (OSError, TimeoutError, ValueError) as exc:
                raise SchedulerUnreachable(f"scheduler: cannot reach {what} within {self.timeout:g} s "
                                           f"({type(exc).__name__}: {exc})") from None
            self._own_client = True
            return self
        from distributed import LocalCluster

        n = self.processes or default_processes()
        self._cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None,
                                     silence_logs=logging.ERROR)
        self.client = Client(self._cluster, timeout=self.timeout, set_as_default=False)
        self._own_client = True
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def close(self) -> None:
        """Closes what this engine started (the client it made, the embedded cluster); never the
        caller's client."""
        if self._own_client and self.client is not None:
            self.client.close()
        self.client = None
        self._own_client = False
        if self._cluster is not None:
            self._cluster.close()
            self._cluster = None
        if self._config is not None:
            self._config.__exit__(None, None, None)
            self._config = None

    @property
    def threads(self) -> int:
        """Tasks that run at once: the cluster's worker threads (1 when serial; at least 1)."""
        if self.client is None:
            return 1
        try:
            return max(1, sum(self.client.nthreads().values()))
        except Exception:  # noqa: BLE001  a cluster being resized: count what answers
            return 1
