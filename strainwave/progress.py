"""Progress of long commands, on stderr through the CLI's logger: counted work says k/N and the time left (with a
rich bar on a terminal, as validate's cases do), work that cannot be counted says every few seconds that it is
still going and for how long, so no command sits silent for more than ``TICK_S``; work done sooner says nothing."""
from __future__ import annotations

import io
import sys
import threading
import time
from contextlib import contextmanager
from typing import Callable, Iterator

__all__ = ["Counter", "ticking", "TICK_S"]

TICK_S = 5.0   # the "more than 5 s without a word"


def _bar(k: int, n: int) -> str:
    from rich.console import Console
    from rich.progress_bar import ProgressBar
    buf = io.StringIO()
    Console(file=buf, force_terminal=True, width=24).print(ProgressBar(total=n, completed=k, width=20), end="")
    return buf.getvalue() + " "


class Counter:
    """k of n items done: ``step(label)`` prints 'WHAT k/n label, about S s left' (time left from the mean so far)."""

    def __init__(self, what: str, total: int, progress: Callable[[str], None], *, terminal: bool | None = None):
        self.what, self.total, self._progress = what, max(1, int(total)), progress
        self._terminal = sys.stderr.isatty() if terminal is None else terminal
        self._start, self.done = time.perf_counter(), 0

    def seconds_left(self) -> float:
        elapsed = time.perf_counter() - self._start
        return elapsed / self.done * max(0, self.total - self.done) if self.done else float("nan")

    def step(self, label: str) -> str:
        self.done += 1
        left = self.seconds_left()
        line = f"{self.what} {self.done}/{self.total} {label}" + (f", about {left:.0f} s left" if left == left else "")
        self._progress((_bar(min(self.done, self.total), self.total) if self._terminal else "") + line)
        return line


@contextmanager
def ticking(what: str | Callable[[], str], progress: Callable[[str], None], *, every_s: float | None = None,
            first_s: float | None = None, done: str | None = None) -> Iterator[None]:
    """'WHAT: still working, N s' after ``first_s`` (default ``every_s``, default ``TICK_S``) and then every
    ``every_s`` seconds, and 'DONE done in N s' (``done`` defaults to WHAT) at the end of work that ticked: work
    done sooner prints nothing, so an input refused at once (imports and checks take seconds on a loaded machine)
    stays its one error line. ``what`` may be a callable: each line names the stage the work is in then."""
    every_s = TICK_S if every_s is None else every_s
    start, stop, ticked = time.perf_counter(), threading.Event(), []
    name = what if callable(what) else (lambda: what)

    def tick():
        wait = every_s if first_s is None else first_s
        while not stop.wait(wait):
            wait = every_s
            ticked.append(True)
            progress(f"{name()}: still working, {time.perf_counter() - start:.0f} s")

    thread = threading.Thread(target=tick, name="strainwave-progress", daemon=True)
    thread.start()
    try:
        yield
    finally:
        stop.set()
        thread.join()
    if ticked:
        progress(f"{done or name()} done in {time.perf_counter() - start:.1f} s")
