"""The one way gmsh is used: a session that initializes, configures and always finalizes it.

gmsh keeps global state (options, models); confining it to a ``with`` block guarantees that nothing
leaks between studies and that a failed mesher leaves no half-initialized library behind.
"""
from __future__ import annotations

from contextlib import contextmanager


@contextmanager
def gmsh_session(*, verbosity: int = 0, threads: int = 1):
    """Initialize gmsh, yield ``gmsh.model``, finalize in ``finally``.

    Parameters
    ----------
    verbosity : gmsh ``General.Verbosity`` (0 silent .. 5 debug).
    threads : ``General.NumThreads``; 1 by default because the machine is shared.
    """
    import gmsh  # lazy: no gmsh work at import time

    if gmsh.isInitialized():
        # a nested session would finalize the outer one's state on exit
        raise RuntimeError("gmsh_session: a gmsh session is already open")
    gmsh.initialize(readConfigFiles=False, interruptible=False)  # no SIGINT handler: Ctrl-C stays Python's
    try:
        gmsh.option.setNumber("General.Terminal", 1 if verbosity > 0 else 0)
        gmsh.option.setNumber("General.Verbosity", verbosity)
        gmsh.option.setNumber("General.NumThreads", threads)
        gmsh.model.add("strainwave")
        yield gmsh.model
    finally:
        gmsh.finalize()
