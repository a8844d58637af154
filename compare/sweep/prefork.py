"""The workers of the sweep's own LocalCluster are forked from one process that imported their libraries once.

Spawned, every worker is a new interpreter that imports distributed and the FEA libraries by itself, all
workers at the same time, and only after the driver has imported pandas and distributed and started the
scheduler. Here the driver starts multiprocessing's fork server as soon as it knows the points' modules
(``start``, right after the grid is checked): the server imports them once, while the driver goes on with
its own imports and the scheduler, and each worker is a cheap copy-on-write ``fork`` of it that starts with
everything loaded (docs/decisions/013-sweep-worker-start-up.md).

This module is imported twice: by the driver (``start``), and by the fork server as its preload, where
the names in ``PRELOAD_ENV`` are imported (a library that fails to import is left to the points that need
it, each failing with its own message, as in ``worker.SweepWorker``).
"""
from __future__ import annotations

import gc
import importlib
import multiprocessing
import os
from typing import Sequence

PRELOAD_ENV = "STRAINWAVE_SWEEP_PRELOAD"
# The workers' own machinery, unpickled by every forked worker before it runs anything of the sweep.
BASE_MODULES = ("distributed", "distributed.nanny", "distributed.worker", "strainwave.compare.sweep.worker")


def available() -> bool:
    """Fork servers exist on POSIX only (not on Windows, where workers are spawned as before)."""
    return "forkserver" in multiprocessing.get_all_start_methods()


def start(modules: Sequence[str], env: dict[str, str]) -> bool:
    """Start the fork server (if this process has none yet) preloading ``BASE_MODULES`` and ``modules``
    with ``env`` in its environment (one BLAS thread: it is set before numpy loads there, as Dask's
    ``pre-spawn-environ`` is for a spawned worker). Returns at once; the imports run in the server while
    the caller goes on. Returns False where there is no fork server (workers are spawned then).

    A fork server is one per process and keeps its first preload: a later sweep in the same process forks
    from it, and its workers import what they lack as they start (``worker.SweepWorker``). The caller starts
    it with the terminal's SIGINT ignored (``interrupt.children_ignore_sigint``): it and the workers forked
    from it restore that disposition, and leave Ctrl-C to the driver, as spawned workers do."""
    if not available():
        return False
    from multiprocessing import forkserver

    names = list(dict.fromkeys([*BASE_MODULES, *modules]))
    # ``PRELOAD_ENV`` and ``env`` are set only while the server process is created, then restored.
    extra = {**env, PRELOAD_ENV: ",".join(names)}
    saved = {key: os.environ.get(key) for key in extra}
    forkserver.set_forkserver_preload([__name__])
    os.environ.update(extra)
    try:
        forkserver.ensure_running()
    finally:
        for key, value in saved.items():
            if value is None:
                os.environ.pop(key, None)
            else:
                os.environ[key] = value
    return True


def _preload(names: Sequence[str]) -> None:
    # No cyclic collection while importing: it only walks the growing heap (docs/decisions/013-sweep-worker-start-up.md).
    gc.disable()
    try:
        for name in names:
            try:
                importlib.import_module(name)
            except Exception:  # noqa: BLE001 - a broken library fails the points that need it, each with its message
                pass
        # Every object loaded so far goes to the permanent generation: the forked workers' collections skip
        # it (and do not write to those copy-on-write pages), and so does their collection at exit.
        gc.freeze()
    finally:
        gc.enable()


if PRELOAD_ENV in os.environ:   # in the fork server, as it starts: import the workers' libraries once
    _preload(os.environ.pop(PRELOAD_ENV).split(","))


def stop_now() -> None:
    """Kill this process's fork server at once and reap it: an interrupted sweep (Ctrl-C, SIGTERM) must not
    leave it importing libraries for seconds after the sweep has gone (it notices its parent only then)."""
    import signal
    from multiprocessing import forkserver

    server = getattr(forkserver, "_forkserver", None)
    pid = getattr(server, "_forkserver_pid", None)
    if not pid:
        return
    from strainwave.compare.validate.isolated import stop_descendants
    stop_descendants(pid)   # the workers forked from it first: once it is gone they belong to init
    try:
        os.kill(pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    try:
        server._stop()   # closes its pipe, reaps it, removes its socket (multiprocessing's own teardown)
    except (AttributeError, OSError):
        pass
