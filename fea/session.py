"""The one way gmsh is used: a session that initializes, configures and always finalizes it, run by the one
meshing guard, ``mesh_in_child``.

gmsh keeps global state (options, models); confining it to a ``with`` block guarantees that nothing
leaks between studies and that a failed mesher leaves no half-initialized library behind.

gmsh's C++ meshers neither return to Python on Ctrl-C nor bound their time or memory: in-range teeth
meshed for 270 s, a long contact patch took 5.9 GB. So every mesh is made in a forked child that

- is interruptible (gmsh's SIGINT is the default action: the child dies at Ctrl-C, the parent unwinds);
- dies with its parent (``PR_SET_PDEATHSIG``), so ``kill -9`` of strainwave leaves no mesher running;
- has a wall time and an address-space limit derived from the element budget (``budget.mesh_limits``);
- sends back its mesh, or a reason that is never empty.
"""
from __future__ import annotations

import os
import pickle
import select
import signal
import threading
import time
from contextlib import contextmanager
from typing import Callable, TypeVar

T = TypeVar("T")


@contextmanager
def gmsh_session(*, verbosity: int = 0, threads: int = 1, interruptible: bool = True):
    """Initialize gmsh, yield ``gmsh.model``, finalize in ``finally``.

    Parameters
    ----------
    verbosity : gmsh ``General.Verbosity`` (0 silent .. 5 debug).
    threads : ``General.NumThreads``; 1 by default because the machine is shared.
    interruptible : gmsh sets SIGINT to its default action while the session is open (restored at the
        end), so Ctrl-C stops the native mesher; ``mesh_in_child`` confines that to a child process.
    """
    import gmsh  # lazy: no gmsh work at import time

    if gmsh.isInitialized():
        # a nested session would finalize the outer one's state on exit
        raise RuntimeError("gmsh_session: a gmsh session is already open")
    main_thread = threading.current_thread() is threading.main_thread()
    previous = signal.getsignal(signal.SIGINT) if main_thread else None
    gmsh.initialize(readConfigFiles=False, interruptible=interruptible and main_thread)
    if main_thread:
        keep_sigpipe_ignored()
    try:
        gmsh.option.setNumber("General.Terminal", 1 if verbosity > 0 else 0)
        gmsh.option.setNumber("General.Verbosity", verbosity)
        gmsh.option.setNumber("General.NumThreads", threads)
        gmsh.model.add("strainwave")
        yield gmsh.model
    finally:
        gmsh.finalize()
        if main_thread and previous is not None:   # gmsh.finalize leaves SIGINT at its default action
            signal.signal(signal.SIGINT, previous)


def keep_sigpipe_ignored() -> None:
    """Put SIGPIPE back to ignored in the kernel, as Python starts it: gmsh.initialize sets it to its default
    action behind Python's back, and a write to a closed socket (a Dask client gone, say) then kills the
    process instead of raising BrokenPipeError. Main thread only."""
    signal.signal(signal.SIGPIPE, signal.SIG_IGN)


_PR_SET_PDEATHSIG = 1


def _die_with_parent(parent_pid: int) -> None:
    """SIGKILL this process when its parent dies (Linux prctl); elsewhere, the parent's pipe closing is
    noticed at the next write and the child's wall-time limit ends it."""
    try:
        import ctypes
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    except (OSError, AttributeError):
        pass
    if os.getppid() != parent_pid:   # the parent died before prctl took effect
        os._exit(1)


def _limit_memory(extra_bytes: int) -> None:
    import resource
    try:
        with open("/proc/self/statm") as stream:   # pages of address space inherited from the parent
            inherited = int(stream.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError):
        return
    limit = inherited + extra_bytes
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    if hard != resource.RLIM_INFINITY:
        limit = min(limit, hard)
    resource.setrlimit(resource.RLIMIT_AS, (limit, hard))


def _child(write_fd: int, parent_pid: int, extra_bytes: int, scratch: str, build: Callable[[object], T]) -> None:
    """In the forked child: limits, one gmsh session, the pickled outcome down the pipe, then _exit."""
    outcome: tuple
    try:
        _die_with_parent(parent_pid)
        import tempfile
        tempfile.tempdir = scratch   # the BREP hand-over goes where the parent removes it, killed or not
        signal.signal(signal.SIGTERM, signal.SIG_DFL)   # not the CLI's unwinding handler: just die
        _limit_memory(extra_bytes)
        with gmsh_session() as model:
            outcome = ("ok", build(model))
    except MemoryError:
        outcome = ("error", f"out of memory: the meshing limit is {extra_bytes / 2**30:.2g} GB beyond the process")
    except BaseException as exc:   # noqa: BLE001 - every failure goes back to the parent as text
        outcome = ("error", f"{type(exc).__name__}: {exc}".rstrip(": ") or type(exc).__name__)
    try:
        data = pickle.dumps(outcome, protocol=pickle.HIGHEST_PROTOCOL)
    except Exception as exc:   # noqa: BLE001
        data = pickle.dumps(("error", f"the mesh could not be sent back ({type(exc).__name__}: {exc})"))
    try:
        view = memoryview(data)
        while view:
            view = view[os.write(write_fd, view):]
    finally:
        os._exit(0)


def _read_until_eof(fd: int, pid: int, wall_s: float) -> bytes | None:
    """The child's bytes, or None when ``wall_s`` passed first."""
    deadline = time.monotonic() + wall_s
    chunks = []
    while True:
        left = deadline - time.monotonic()
        if left <= 0:
            return None
        ready, _, _ = select.select([fd], [], [], min(left, 0.5))
        if ready:
            chunk = os.read(fd, 1 << 20)
            if not chunk:
                return b"".join(chunks)
            chunks.append(chunk)


def _kill(pid: int) -> int:
    try:
        os.kill(pid, signal.SIGKILL)
        return os.waitpid(pid, 0)[1]
    except (ProcessLookupError, ChildProcessError):   # already reaped
        return 0


def _death(status: int, extra_bytes: int) -> str:
    if os.WIFSIGNALED(status):
        sig = os.WTERMSIG(status)
        name = signal.Signals(sig).name if sig in signal.Signals._value2member_map_ else str(sig)
        return (f"the gmsh child exited with code {-sig} (killed by {name}: a native abort, or its memory "
                f"limit of {extra_bytes / 2**30:.2g} GB beyond the process)")
    return f"the gmsh child exited with code {os.WEXITSTATUS(status)} before sending a mesh"


def mesh_in_child(build: Callable[[object], T], *, what: str = "gmsh") -> T:
    """``build(model)`` inside a gmsh session in a guarded child (module docstring); returns its result.

    Raises MeshLimitExceeded when the wall time passes, MeshingFailed when gmsh fails (its message) or the
    child dies (how). Ctrl-C or SIGTERM in the parent kill the child before they propagate."""
    import shutil
    import tempfile

    from strainwave.fea.budget import mesh_limits
    from strainwave.fea.meshing import MeshingFailed, MeshLimitExceeded

    limits = mesh_limits()
    parent = os.getpid()
    from strainwave.output_guard import make_owned_dir
    scratch = str(make_owned_dir(f"strainwave-mesh-{parent}-"))   # its owner recorded: removable once we are gone
    read_fd, write_fd = os.pipe()
    pid = os.fork()
    if pid == 0:   # pragma: no cover - the child
        os.close(read_fd)
        _child(write_fd, parent, limits.extra_bytes, scratch, build)
    os.close(write_fd)
    try:
        data = _read_until_eof(read_fd, pid, limits.wall_s)
        status = _kill(pid) if data is None else os.waitpid(pid, 0)[1]
    except BaseException:
        _kill(pid)
        raise
    finally:
        os.close(read_fd)
        shutil.rmtree(scratch, ignore_errors=True)
    if data is None:
        raise MeshLimitExceeded(f"{what} took longer than {limits.wall_s:.0f} s, the limit for "
                                f"{limits.elements:,} estimated elements; choose a larger mesh size")
    if not data:   # a native abort may pass on retry with other sizes (mesh_isolated): not a limit
        raise MeshingFailed(_death(status, limits.extra_bytes))
    try:
        kind, payload = pickle.loads(data)   # our own child's bytes
    except Exception:   # noqa: BLE001 - cut short: the child died while sending
        raise MeshingFailed(_death(status, limits.extra_bytes)) from None
    if kind != "ok":
        raise MeshingFailed(payload)
    return payload
