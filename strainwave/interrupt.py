"""Ctrl-C taken at a safe point.

VTK and matplotlib call back into Python from native code (weakref finalizers, observers). A
KeyboardInterrupt that Python's default SIGINT handler raises inside such a callback is printed as
"Exception ignored in: ..." and lost, and the run goes on as if nothing happened. Around that kind of
work the signal only records itself, and the caller raises it between steps, where it unwinds normally.
"""
from __future__ import annotations

import signal
import threading
from contextlib import contextmanager
from typing import Callable, Iterator

__all__ = ["children_ignore_sigint", "deferred_interrupt"]


@contextmanager
def deferred_interrupt() -> Iterator[Callable[[], None]]:
    """Yield ``checkpoint()``, which raises KeyboardInterrupt once SIGINT has arrived; leaving the block
    normally is a checkpoint too. Outside the main thread, or where SIGINT is not Python's own handler
    (ignored in a child, or a caller's handler), it changes nothing."""
    if (threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGINT) is not signal.default_int_handler):
        yield lambda: None
        return
    received: list[int] = []

    def checkpoint() -> None:
        if received:
            raise KeyboardInterrupt

    previous = signal.signal(signal.SIGINT, lambda signum, frame: received.append(signum))
    try:
        yield checkpoint
    finally:
        signal.signal(signal.SIGINT, previous)
    checkpoint()


@contextmanager
def children_ignore_sigint() -> Iterator[None]:
    """Processes started inside the block ignore SIGINT (an ignored signal survives fork and exec, and
    Python keeps it ignored at start-up). A terminal's Ctrl-C reaches the whole process group; helpers
    such as Dask's workers would each print a KeyboardInterrupt traceback and die on their own, while the
    parent that owns them is the one that should stop them, once."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
