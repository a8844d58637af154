"""Run one FEA case in a child process: a native crash or a hang fails that case, not the validation.

gmsh and VTK are C++ libraries; an abort inside them (e.g. gmsh's "Failed to reach critical value ...
ScaledJac") kills the whole Python process, which would leave no report at all. Each case therefore
runs in a process forked from a clean fork server that has the FEA stack preloaded (so a case starts in
milliseconds, not seconds of imports). Progress messages and the result come back through a pipe; a
case that exceeds its time limit is terminated and reported as such.
"""
from __future__ import annotations

import multiprocessing
import os
import signal
import time
import traceback
from dataclasses import dataclass
from typing import Callable

PRELOAD = ["numpy", "scipy.sparse", "skfem", "gmsh", "pyamg", "strainwave.fea.studies", "strainwave.params"]


@dataclass(frozen=True)
class ChildOutcome:
    result: dict | None       # StudyResult.to_dict() of the finished case
    error: str                # "" on success
    seconds: float


def _child(conn, study: str, params, kwargs: dict) -> None:
    """Child side: solve, stream progress, send ("result", dict) or ("error", text)."""
    os.setpgid(0, 0)  # own process group: a time-out also stops any worker the study started
    try:
        from ...fea.studies import run_study

        def progress(msg: str) -> None:
            conn.send(("progress", msg))

        result = run_study(study, params, progress=progress, **kwargs)
        conn.send(("result", result.to_dict()))
    except BaseException as exc:  # noqa: BLE001 - everything goes back to the parent as text
        last = traceback.extract_tb(exc.__traceback__)[-1:] if exc.__traceback__ else []
        where = f" at {last[0].filename.rsplit('/', 1)[-1]}:{last[0].lineno}" if last else ""
        conn.send(("error", f"{type(exc).__name__}: {exc}{where}"))
    finally:
        conn.close()


def _context():
    ctx = multiprocessing.get_context("forkserver")
    ctx.set_forkserver_preload(PRELOAD)
    return ctx


def run_isolated(study: str, params, kwargs: dict, *, timeout_s: float,
                 progress: Callable[[str], None]) -> ChildOutcome:
    """``run_study(study, params, **kwargs)`` in a child process, at most ``timeout_s`` seconds."""
    ctx = _context()
    parent_conn, child_conn = ctx.Pipe(duplex=False)
    # Not a daemon: a study may start worker processes of its own (daemons may not have children);
    # the ``finally`` below terminates the child on every way out instead.
    process = ctx.Process(target=_child, args=(child_conn, study, params, kwargs), daemon=False)
    start = time.perf_counter()
    process.start()
    child_conn.close()
    result, error = None, ""
    try:
        while True:
            remaining = timeout_s - (time.perf_counter() - start)
            if remaining <= 0:
                error = f"timed out after {timeout_s:g} s (case limit); the worker was terminated"
                break
            if parent_conn.poll(min(remaining, 1.0)):
                try:
                    kind, payload = parent_conn.recv()
                except EOFError:
                    error = _death(process)
                    break
                if kind == "progress":
                    progress(payload)
                    continue
                result, error = (payload, "") if kind == "result" else (None, payload)
                break
            if not process.is_alive() and not parent_conn.poll(0):
                error = _death(process)
                break
    finally:
        if process.is_alive():
            _stop_group(process.pid)
            process.terminate()
        process.join(5)
        parent_conn.close()
    return ChildOutcome(result, error, time.perf_counter() - start)


def _stop_group(pid: int) -> None:
    """SIGTERM the child's process group (the child and the workers it started, nothing else)."""
    try:
        os.killpg(pid, signal.SIGTERM)
    except (ProcessLookupError, PermissionError):
        pass  # already gone


def _death(process) -> str:
    process.join(5)
    code = process.exitcode
    by_signal = f" (signal {-code})" if code is not None and code < 0 else ""
    return (f"the worker process died with exit code {code}{by_signal}: a native crash in gmsh, VTK or the solver; "
            "its message, if any, is on stderr above")
