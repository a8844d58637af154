"""Study registry: a kebab-case name -> the module whose ``run`` solves it.

Each study module exposes ``run(params, *, mesh_size_mm, order, crack_depth_mm, vtu, progress, quick)``
and returns a ``StudyResult``; the import is lazy so choosing one study loads only its code.
"""
from __future__ import annotations

import importlib
from pathlib import Path
from typing import Callable

from ..errors import InputError
from .result import StudyResult

STUDY_MODULES = {
    "shaft-torsion": "strainwave.fea.shaft_torsion",
    "cup-torsion": "strainwave.fea.cup_torsion",
    "bearing-ring": "strainwave.fea.bearing_ring",
    "ring-compression": "strainwave.fea.ring_compression",
}


def run_study(study: str, params, *, mesh_size_mm: float | None = None, order: int = 2,
              crack_depth_mm: float | None = None, vtu: Path | None = None,
              progress: Callable[[str], None] | None = None, quick: bool = False) -> StudyResult:
    if study not in STUDY_MODULES:
        raise InputError("study", study, f"must be one of {', '.join(STUDY_MODULES)}")
    if order not in (1, 2):
        raise InputError("--order", order, "must be 1 or 2")
    module = importlib.import_module(STUDY_MODULES[study])
    return module.run(params, mesh_size_mm=mesh_size_mm, order=order, crack_depth_mm=crack_depth_mm,
                      vtu=vtu, progress=progress or (lambda msg: None), quick=quick)
