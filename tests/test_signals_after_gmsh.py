"""gmsh.initialize sets SIGPIPE to its default action behind Python's back; after a gmsh session the process
ignores it again, so a write to a closed pipe raises BrokenPipeError instead of killing strainwave (a Dask
scheduler in the process would die when a client left)."""
from __future__ import annotations

import subprocess
import sys
import textwrap

_CHILD = textwrap.dedent("""
    import os, sys
    from strainwave.fea.session import gmsh_session
    with gmsh_session() as model:
        model.occ.addBox(0, 0, 0, 1, 1, 1)
    r, w = os.pipe()
    os.close(r)
    try:
        os.write(w, b"x")
    except BrokenPipeError:
        sys.exit(0)
    sys.exit(3)
""")


def test_a_write_to_a_closed_pipe_after_gmsh_raises_instead_of_killing():
    proc = subprocess.run([sys.executable, "-c", _CHILD], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, (proc.returncode, proc.stderr[-500:])   # -13 = killed by SIGPIPE
