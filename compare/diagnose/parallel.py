"""Independent model fits shared between this process and one forked copy of it.

A diagnosis fits each catalogue effect in every model form, then pairs of them: dozens of small
trust-region fits that do not depend on one another. Threads gain nothing (the fits are Python loops
around tiny BLAS calls, serialised by the GIL; docs/decisions/019-diagnose-speed.md), so the second core is used by a
forked copy of the process. It inherits the recording and the noise model without pickling, takes the next
unclaimed fit from a shared counter (costliest first), and sends its fits back through a pipe with their effects
left out (the parent already holds them). Fits of a form with a history basis (relay states, play operators)
stay in the parent, which builds each basis once while the copy is already fitting the other forms. Each fit is the same computation whichever
process runs it, so the answer does not depend on the number of workers.

Forking is only safe, and only worth it, in a single-threaded process on a machine with a second core:
anywhere else (another thread running, a daemonic worker, no fork) the fits run here, one after another.
A copy that dies or fails leaves its unsent fits to this process; where no copy can be started (no shared
semaphore, a process limit) the fits run here.
"""
from __future__ import annotations

import dataclasses
import math
import multiprocessing
import os
import threading
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from strainwave.compare.diagnose.effects.base import Context, Effect
from strainwave.compare.diagnose.fit import Fit, fit_effects

__all__ = ["FitTask", "fit_all", "usable_workers"]


@dataclass(frozen=True)
class FitTask:
    """One call of ``fit_effects``: the effects, optional starting points, optional fixed noise model."""

    effects: tuple[Effect, ...]
    starts: tuple[np.ndarray, ...] | None = None
    noise: object | None = None


def usable_workers() -> int:
    """Processes the fits may use: 2 where forking is safe and a second core is ours, else 1."""
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:                      # no affinity call on this platform
        cores = os.cpu_count() or 1
    if cores < 2 or "fork" not in multiprocessing.get_all_start_methods():
        return 1
    # a fork copies only the calling thread: a lock another thread holds stays held in the copy forever
    if threading.active_count() > 1 or multiprocessing.current_process().daemon:
        return 1
    return 2


def _run(ctx: Context, task: FitTask, sigma: float, uncertainty: float, then=None) -> Fit:
    fit = fit_effects(ctx, task.effects, sigma, uncertainty,
                      starts=None if task.starts is None else list(task.starts), noise=task.noise)
    return fit if then is None else then(ctx, fit)


def _warm(ctx: Context, tasks: Sequence[FitTask]) -> None:
    """Fill this process's memo of history bases (and the other per-context pieces the effects keep), once."""
    for e in {e.label: e for t in tasks for e in t.effects}.values():
        if e.basis is not None:
            e.basis(ctx)
        theta = np.array([p.starts[0] for p in e.params])
        e.contribution(ctx, np.clip(theta, [p.lo for p in e.params], [p.hi for p in e.params]))


def _cost(task: FitTask) -> int:
    """A fit's rough cost: its trust-region starts times the parameters the trust region searches."""
    searched = [p for e in task.effects if e.basis is None for p in e.params]
    starts = len(task.starts) if task.starts is not None else math.prod(len(p.starts) for p in searched)
    return starts * (len(searched) + 1)


def _has_basis(task: FitTask) -> bool:
    return any(e.basis is not None for e in task.effects)


def fit_all(ctx: Context, tasks: Sequence[FitTask], sigma: float, uncertainty: float,
            workers: int = 1, then: Callable[[Context, Fit], Fit] | None = None) -> list[Fit]:
    """``fit_effects`` for every task, in the order given; on ``workers`` = 2 processes when more than one
    task waits. ``then(ctx, fit)``: applied to each fit by the process that made it."""
    # the costliest fits are claimed first, so neither process is left with a long one at the end; fits of a
    # form with a history basis stay here, where the basis is built once while the copy starts on the others
    order = sorted(range(len(tasks)), key=lambda i: -_cost(tasks[i]))
    own = [i for i in order if _has_basis(tasks[i])]
    shared = [i for i in order if not _has_basis(tasks[i])]
    if workers < 2 or len(shared) < 1 or len(tasks) < 2:
        return [_run(ctx, t, sigma, uncertainty, then) for t in tasks]
    mp = multiprocessing.get_context("fork")
    try:
        # a shared counter needs a POSIX semaphore (/dev/shm): some containers have none
        claimed = mp.Value("l", 0)
    except OSError:
        return [_run(ctx, t, sigma, uncertainty, then) for t in tasks]

    def claim() -> int:
        with claimed.get_lock():
            k = claimed.value
            claimed.value += 1
        return shared[k] if k < len(shared) else len(tasks)

    def copy_side(conn) -> None:
        done: list[tuple[int, Fit]] = []
        try:
            while (i := claim()) < len(tasks):
                done.append((i, dataclasses.replace(_run(ctx, tasks[i], sigma, uncertainty, then), effects=())))
            conn.send(done)
        except BaseException:                  # noqa: BLE001 - whatever happens here, the parent finishes the work
            pass
        finally:
            conn.close()
            os._exit(0)                        # no atexit handlers, no flushing of the parent's buffers

    receive, send = mp.Pipe(duplex=False)
    copy = mp.Process(target=copy_side, args=(send,), daemon=True)
    try:
        copy.start()
    except OSError:                            # no process to spare (a process limit, no memory to fork)
        receive.close()
        send.close()
        return [_run(ctx, t, sigma, uncertainty, then) for t in tasks]
    send.close()
    fits: dict[int, Fit] = {}
    try:
        _warm(ctx, tasks)
        for i in own:
            fits[i] = _run(ctx, tasks[i], sigma, uncertainty, then)
        while (i := claim()) < len(tasks):
            fits[i] = _run(ctx, tasks[i], sigma, uncertainty, then)
        try:
            for i, f in receive.recv():
                fits[i] = dataclasses.replace(f, effects=tasks[i].effects)
        except (EOFError, OSError):
            pass                               # the copy died: its claimed fits are redone below
    finally:
        receive.close()
        copy.join(timeout=1.0)
        if copy.is_alive():
            copy.terminate()
            copy.join()
    return [fits[i] if i in fits else _run(ctx, tasks[i], sigma, uncertainty, then) for i in range(len(tasks))]
