"""A small progress bar for long work (long horizons, design searches, campaigns).

It writes to ``stderr`` and only when ``stderr`` is a terminal; it is silent otherwise, or
when ``quiet=True`` or :func:`set_quiet` has been called (the command line's ``--quiet``).
No dependency::

    with Progress(total=N, label="online") as bar:
        for k in range(N):
            ...
            bar.update()

The bar redraws at most every 0.1 s, so wrapping a fast loop costs a clock read per step.
"""
from __future__ import annotations

import sys
import time

_QUIET = False


def set_quiet(quiet: bool = True) -> None:
    """Silences (or re-enables) every progress bar of the process.

    Parameters
    ----------
    quiet : bool, optional
        Silence (True) or re-enable.
    """
    global _QUIET
    _QUIET = bool(quiet)


def is_quiet() -> bool:
    """True when progress bars are globally silenced with :func:`set_quiet`."""
    return _QUIET


class Progress:
    """A text progress bar ``label [#####.....] k/N  elapsed  eta`` on ``stream`` (stderr).

    ``enabled`` is decided once at construction: False when ``quiet``, when progress bars are
    globally silenced, or when ``stream`` is not a terminal (``isatty()``). A disabled bar
    still counts (``count``), it just draws nothing.

    Parameters
    ----------
    total : int, optional
        Number of items (None: unknown, no eta).
    label : str, optional
        Label.
    stream : file, optional
        Where to draw (default: stderr).
    quiet : bool, optional
        Draw nothing.
    width : int, optional
        Bar width in characters.
    min_interval : float, optional
        Seconds between redraws.
    """

    def __init__(self, total: int | None = None, label: str = "", *, stream=None, quiet: bool = False,
                 width: int = 30, min_interval: float = 0.1):
        self.total = None if total is None else max(0, int(total))
        self.label = label
        self.stream = sys.stderr if stream is None else stream
        isatty = getattr(self.stream, "isatty", None)
        self.enabled = not (quiet or _QUIET) and bool(isatty and isatty())
        self.width = int(width)
        self.min_interval = float(min_interval)
        self.count = 0
        self._start = time.perf_counter()
        self._last_draw = -1e300
        self._drawn = False

    def __enter__(self) -> "Progress":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def render(self) -> str:
        """The current line (without carriage return)."""
        elapsed = time.perf_counter() - self._start
        head = f"{self.label} " if self.label else ""
        if self.total:
            frac = min(1.0, self.count / self.total)
            filled = int(round(frac * self.width))
            eta = elapsed / frac - elapsed if frac > 0 else float("nan")
            eta_s = f" eta {eta:5.1f}s" if frac > 0 and frac < 1 else ""
            return (f"{head}[{'#' * filled}{'.' * (self.width - filled)}] {self.count}/{self.total}"
                    f" {elapsed:5.1f}s{eta_s}")
        return f"{head}{self.count} {elapsed:5.1f}s"

    def update(self, n: int = 1) -> None:
        """Advances by ``n`` and redraws if enough time has passed.

        Parameters
        ----------
        n : int, optional
            Items done.
        """
        self.count += n
        if not self.enabled:
            return
        now = time.perf_counter()
        if now - self._last_draw >= self.min_interval or (self.total and self.count >= self.total):
            self._last_draw = now
            self.stream.write("\r" + self.render() + "\x1b[K")
            self.stream.flush()
            self._drawn = True

    def close(self) -> None:
        """Ends the line if something was drawn."""
        if self.enabled and self._drawn:
            self.stream.write("\r" + self.render() + "\x1b[K\n")
            self.stream.flush()
            self._drawn = False


def track(iterable, total: int | None = None, label: str = "", **kw):
    """Yields the items of ``iterable`` while advancing a :class:`Progress` bar.

    Parameters
    ----------
    iterable : iterable
        The items.
    total : int, optional
        Their number (default: ``len(iterable)`` when it has one).
    label : str, optional
        Label.
    **kw
        Passed to :class:`Progress`.

    Yields
    ------
    object
        The items.
    """
    if total is None:
        try:
            total = len(iterable)
        except TypeError:
            total = None
    with Progress(total, label, **kw) as bar:
        for item in iterable:
            yield item
            bar.update()
