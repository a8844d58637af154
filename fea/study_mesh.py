"""Mesh one part for a study: one gmsh session, and a mesher failure named by its study and stage."""
from __future__ import annotations

import time
from typing import Callable, Sequence

from strainwave.errors import StageError
from strainwave.fea.mesh_data import MeshData
from strainwave.fea.meshing import OPTIMIZE_THRESHOLD, MeshingFailed, Refine, mesh_part
from strainwave.fea.session import mesh_in_child


def mesh_for_study(part, *, study: str, h_mm: float, order: int, refine: Sequence[Refine] = (),
                   progress: Callable[[str], None] = lambda m: None,
                   optimize_threshold: float = OPTIMIZE_THRESHOLD) -> tuple[MeshData, float]:
    """(mesh, seconds spent meshing); a gmsh failure becomes ``StageError("mesh", study, ...)`` (exit 1)."""
    t0 = time.perf_counter()
    progress(f"{study}: meshing h = {h_mm:.3g} mm")
    try:
        md = mesh_in_child(lambda model: mesh_part(model, part, size_mm=h_mm, order=order, refine=list(refine),
                                                   optimize_threshold=optimize_threshold, preload_kernels=False))
    except MeshingFailed as exc:
        raise StageError("mesh", study, str(exc)) from exc
    return md, time.perf_counter() - t0
