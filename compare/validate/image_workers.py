"""The report's pictures on two cores: this process and one forked worker take the next picture in turn.

Each picture is a task that returns typed records (``artifacts.Attempted``: the image, the stress at the rated load,
the 3D view, what could not be made); the worker sends its records back when it has drawn its share, and they are
merged in the order the pictures were asked for, so the report reads the same as when one process draws them all.
The worker is forked before any plotter exists (each process makes its own off-screen window) and ignores Ctrl-C:
the caller stops between pictures (``checkpoint``) and the worker is killed with it.
"""
from __future__ import annotations

import multiprocessing
import os
import signal
from typing import Callable, TypeVar

__all__ = ["WORKERS", "run_tasks"]

T = TypeVar("T")
WORKERS = 2        # this process and one forked worker: the machine this targets has two cores


def _claim(counter) -> int:
    """The next task index (shared by both processes)."""
    with counter.get_lock():
        k = counter.value
        counter.value += 1
    return k


def _worker(n: int, one: Callable[[int], T], counter, conn) -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)    # the caller stops between pictures and kills this process
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    done = []
    try:
        while (k := _claim(counter)) < n:
            done.append((k, one(k)))
    finally:
        conn.send(done)       # all at the end: a full pipe would otherwise stall the worker mid-share
        conn.close()


def run_tasks(n: int, one: Callable[[int], T], checkpoint: Callable[[], None], died: Callable[[int, str], T]) -> list[T]:
    """[one(0), ..., one(n - 1)], shared between this process and a forked worker; ``checkpoint()`` runs before each
    task here; a task the worker took but never answered (it died) gets ``died(k, why)``."""
    if n < 2 or WORKERS < 2 or (os.cpu_count() or 1) < 2:
        out = []
        for k in range(n):
            checkpoint()
            out.append(one(k))
        return out
    import pyvista.plotting  # noqa: F401 - loaded once, before the fork, for both processes

    ctx = multiprocessing.get_context("fork")
    counter = ctx.Value("i", 0)
    receive, send = ctx.Pipe(duplex=False)
    worker = ctx.Process(target=_worker, args=(n, one, counter, send), daemon=True)
    worker.start()
    send.close()
    results: dict[int, T] = {}
    try:
        while True:
            checkpoint()
            k = _claim(counter)
            if k >= n:
                break
            results[k] = one(k)
        try:
            results.update(receive.recv())
        except EOFError:
            pass
    finally:
        if worker.is_alive() and len(results) < n:
            worker.kill()
        worker.join()
        receive.close()
    why = f"the image worker process died (exit code {worker.exitcode})"
    return [results[k] if k in results else died(k, why) for k in range(n)]
