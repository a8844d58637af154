"""Run one FEA case in a child process: a native crash or a hang fails that case, not the validation.

gmsh and VTK are C++ libraries; an abort inside them (e.g. gmsh's "Failed to reach critical value ...
ScaledJac") kills the whole Python process, which would leave no report at all. Each case therefore
runs in a process forked from a clean fork server that has the FEA stack preloaded (so a case starts in
milliseconds, not seconds of imports). Progress messages and the result come back through a pipe; a
case that exceeds its time limit is terminated and reported as such.

Children never outlive the run: they stay in the run's process group (``kill -9 -PGID`` reaches them),
ask the kernel for SIGKILL when their parent dies (a ``kill -9`` of the run alone: the fork server
exits with the run, and its children follow), ignore the terminal's Ctrl-C (the run decides, and stops
them together with their own children: ``stop_descendants``), and exit silently when the run that
reads their pipe is gone instead of printing BrokenPipeError tracebacks.
"""
from __future__ import annotations

import ctypes
import multiprocessing
import os
import signal
import time
import traceback
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from strainwave.errors import MaterialWarning

# build123d too: importing it in every case's child was slow (docs/decisions/014-validate-case-isolation.md).
PRELOAD = ["numpy", "scipy.sparse", "skfem", "gmsh", "pyamg", "build123d", "strainwave.fea.studies",
           "strainwave.params"]


@dataclass(frozen=True)
class ChildOutcome:
    result: dict | None       # StudyResult.to_dict() of the finished case
    error: str                # "" on success
    seconds: float
    cpu_s: float | None = None   # CPU time of the case process (see _cpu_seconds); None when it failed


_PR_SET_PDEATHSIG = 1   # linux/prctl.h


def bind_to_parent() -> None:
    """Make this (child) process die with its parent and leave Ctrl-C to the parent.

    prctl comes from the symbols already loaded in this process (``CDLL(None)``): looking libc up with
    ``ctypes.util.find_library`` would run ldconfig/gcc, i.e. write outside the outputs."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    ctypes.CDLL(None, use_errno=True).prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    # The run may have died while this child was still starting (before prctl): then it was re-parented
    # (to init or a sub-reaper, so getppid() proves nothing) and the run's sentinel pipe is closed.
    initiator = multiprocessing.parent_process()
    if initiator is not None and not initiator.is_alive():
        os._exit(1)


def send_or_exit(conn, message) -> None:
    """Send to the parent; if it is gone (its end of the pipe closed), leave at once and quietly."""
    try:
        conn.send(message)
    except (BrokenPipeError, ConnectionResetError, EOFError, OSError):
        os._exit(1)


def _child(conn, study: str, params, kwargs: dict) -> None:
    """Child side: solve, stream progress, send ("result", dict) or ("error", text)."""
    bind_to_parent()
    # The run printed the material's E/G/nu warning once; each case re-validates the same material and
    # would print it again in Python's raw format (with a source line) on every case.
    warnings.simplefilter("ignore", MaterialWarning)
    one_thread_per_case()
    try:
        from strainwave.fea.studies import run_study

        def progress(msg: str) -> None:
            send_or_exit(conn, ("progress", msg))

        result = run_study(study, params, progress=progress, **kwargs)
        send_or_exit(conn, ("result", (result.to_dict(), _cpu_seconds())))
    except BaseException as exc:  # noqa: BLE001 - everything goes back to the parent as text
        last = traceback.extract_tb(exc.__traceback__)[-1:] if exc.__traceback__ else []
        where = f" at {last[0].filename.rsplit('/', 1)[-1]}:{last[0].lineno}" if last else ""
        send_or_exit(conn, ("error", f"{type(exc).__name__}: {exc}{where}"))
    finally:
        conn.close()


def one_thread_per_case() -> None:
    """Every BLAS and OpenMP pool (OpenBLAS, MKL/PARDISO) in one thread in this case process, unless the user
    set MKL_NUM_THREADS or OMP_NUM_THREADS.

    Cases run two at a time on the two cores (and the STEP export beside them), so a second thread finds no
    free core: it spins in its wait loop and takes CPU from the other case (docs/decisions/014-validate-case-
    isolation.md; OpenBLAS's second thread made the wave generator's case 8x slower, decision 035).
    MKL is loaded only when a case first solves directly (pypardiso), after the environment variable is set;
    numpy's OpenBLAS is preloaded by the fork server, so its pool is limited at run time."""
    os.environ.setdefault("MKL_NUM_THREADS", "1")
    if "OMP_NUM_THREADS" not in os.environ and "OPENBLAS_NUM_THREADS" not in os.environ:
        from threadpoolctl import threadpool_limits
        threadpool_limits(limits=1)


def _cpu_seconds() -> float:
    """CPU time (user + system) of this case process and of the processes it started and waited for
    (the bearing's mesh attempts). A forked child starts from zero. Unlike the wall time it hardly
    depends on what else runs on the machine, so it states what a case costs."""
    import resource
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def fork_server_context():
    """The fork server's context: each process it forks starts with ``PRELOAD`` imported."""
    ctx = multiprocessing.get_context("forkserver")
    ctx.set_forkserver_preload(PRELOAD)
    return ctx


def run_isolated(study: str, params, kwargs: dict, *, timeout_s: float,
                 progress: Callable[[str], None]) -> ChildOutcome:
    """``run_study(study, params, **kwargs)`` in a child process, at most ``timeout_s`` seconds."""
    ctx = fork_server_context()
    parent_conn, child_conn = ctx.Pipe(duplex=False)
    # Not a daemon: a study may start worker processes of its own (daemons may not have children);
    # the ``finally`` below terminates the child on every way out instead.
    process = ctx.Process(target=_child, args=(child_conn, study, params, kwargs), daemon=False)
    start = time.perf_counter()
    process.start()
    child_conn.close()
    result, error, cpu_s = None, "", None
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
                (result, cpu_s), error = (payload, "") if kind == "result" else ((None, None), payload)
                break
            if not process.is_alive() and not parent_conn.poll(0):
                error = _death(process)
                break
    finally:
        if process.is_alive():
            stop_descendants(process.pid)   # the workers the study started (mesh attempts), then the child
            process.kill()
        process.join(5)
        parent_conn.close()
    return ChildOutcome(result, error, time.perf_counter() - start, cpu_s)


def _children_of() -> dict[int, list[int]]:
    """ppid -> pids of every process visible in /proc (one pass; a process may vanish meanwhile)."""
    tree: dict[int, list[int]] = {}
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        # "pid (comm) state ppid ...": comm may hold spaces and parentheses, so split after the last ')'
        ppid = int(stat.rsplit(")", 1)[1].split()[1])
        tree.setdefault(ppid, []).append(int(entry.name))
    return tree


def descendants(pid: int) -> list[int]:
    """Every process below ``pid`` (children first)."""
    tree, out, todo = _children_of(), [], [pid]
    while todo:
        kids = tree.get(todo.pop(), [])
        out.extend(kids)
        todo.extend(kids)
    return out


def stop_descendants(pid: int) -> int:
    """SIGKILL every process below ``pid`` (not ``pid`` itself); returns how many were signalled.
    SIGKILL, not SIGTERM: a study in a native gmsh/BLAS call would not act on SIGTERM before its time."""
    victims = descendants(pid)
    for victim in victims:
        try:
            os.kill(victim, signal.SIGKILL)
        except (ProcessLookupError, PermissionError):
            pass  # already gone
    return len(victims)


def _death(process) -> str:
    process.join(5)
    code = process.exitcode
    by_signal = f" (signal {-code})" if code is not None and code < 0 else ""
    return (f"the worker process died with exit code {code}{by_signal}: a native crash in gmsh, VTK or the solver; "
            "its message, if any, is on stderr above")
