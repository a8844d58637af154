"""Mesh a part in a forked child so that a native gmsh abort costs one attempt, not the process.

gmsh's high-order optimiser (called by ``meshing._generate`` when curved P2 nodes invert an element)
can end in ``std::terminate`` ("Failed to reach critical value ... ScaledJac"), which no Python handler
catches. On the bearing ring with a 0.1 mm crack in a 0.02 mm slot it happens for some size
combinations (e.g. h = 7.5 mm, contact 1.5 mm) and not for neighbouring ones: the inverted elements
are slivers where the slot's elliptical face meets the race. So each attempt runs in a fork of this
process (the part is inherited, nothing is pickled but the resulting MeshData), and a failed attempt
is retried with all sizes scaled by a few per cent; the scaling is reported so it can be seen.
"""
from __future__ import annotations

import dataclasses
import multiprocessing as mp
from typing import Sequence

from .mesh_data import MeshData
from .meshing import MeshingFailed, Refine, mesh_part
from .session import gmsh_session

# +3 %, -2 %, +5 %: small enough that two neighbouring refinements retried in opposite directions keep the
# GCI's ratio above Roache's 1.3 minimum at the one ratio 1.4 (worst 1.4 x 0.98/1.05 = 1.307; the former
# -3 %/+6 % gave 1.4 x 0.97/1.06 = 1.28), large enough to give gmsh a different front. The GCI uses the
# sizes as meshed (the factor is returned), so a retry never misstates h.
SIZE_FACTORS = (1.0, 1.03, 0.98, 1.05)


def _child(conn, part, size_mm, order, refine):
    try:
        with gmsh_session() as model:
            md = mesh_part(model, part, size_mm=size_mm, order=order, refine=refine, preload_kernels=False)
        conn.send(("ok", md))
    except Exception as exc:          # noqa: BLE001 - every failure goes back to the parent as text
        conn.send(("error", f"{type(exc).__name__}: {exc}"))
    finally:
        conn.close()


def _scaled(refine: Sequence[Refine], f: float) -> list[Refine]:
    return [dataclasses.replace(r, size_mm=r.size_mm * f) for r in refine]


def mesh_part_isolated(part, *, size_mm: float, order: int, refine: Sequence[Refine],
                       factors: Sequence[float] = SIZE_FACTORS, timeout_s: float = 600.0) -> tuple[MeshData, float]:
    """``meshing.mesh_part`` in a forked child, retried with scaled sizes; returns (mesh, factor used).

    Raises MeshingFailed with every attempt's outcome when all fail."""
    ctx = mp.get_context("fork")
    errors = []
    for f in factors:
        recv, send = ctx.Pipe(duplex=False)
        proc = ctx.Process(target=_child, args=(send, part, size_mm * f, order, _scaled(refine, f)))
        proc.start()
        send.close()
        msg = None
        if recv.poll(timeout_s):
            try:
                msg = recv.recv()
            except EOFError:          # the child died (native abort) before sending
                msg = None
        proc.join(5.0)
        if proc.is_alive():
            proc.kill()
            proc.join()
        recv.close()
        if msg is not None and msg[0] == "ok":
            return msg[1], f
        errors.append(f"sizes x{f:g}: " + (msg[1] if msg else f"gmsh child exited with code {proc.exitcode}"))
    raise MeshingFailed("; ".join(errors))
