"""Run one study of the registry (``strainwave/registry.py``) by name.

Each study module exposes ``run(params, *, mesh_size_mm, order, crack_depth_mm, vtu, progress, quick, **load)``
and returns a ``StudyResult``; the import is lazy so choosing one study loads only its code. A load that
follows from a seed formula (the bearing's F_r, the ring's F and W0) is computed by the ``analytic``
function the registry names (``Study.load_for``) and passed in as numbers: fea/ holds no closed form.

``crack_depth_mm``: None means the study's component is uncracked, for every study. A depth is the
crack of the study's own component: it is written into ``params`` under the registry's crack key, so it
is checked against that component's wall by the parameter schema before any part or mesh is built;
a study whose part carries no crack refuses it.
"""
from __future__ import annotations

import importlib
from pathlib import Path
from typing import Callable

from ..errors import InputError
from ..registry import study as registered
from .result import StudyResult


def with_crack(study: str, params, crack_depth_mm: float | None):
    """``params`` with the study's own crack set to ``crack_depth_mm`` (validated); unchanged for None."""
    spec = registered(study)
    if crack_depth_mm is None:
        return params
    if spec.crack_key is None:
        raise InputError("--crack-depth-mm", crack_depth_mm,
                         f"study {study} meshes the {spec.part}, which carries no crack; leave it out")
    return params.with_value(spec.crack_key, float(crack_depth_mm))


def run_study(study: str, params, *, mesh_size_mm: float | None = None, order: int = 2,
              crack_depth_mm: float | None = None, vtu: Path | None = None,
              progress: Callable[[str], None] | None = None, quick: bool = False) -> StudyResult:
    spec = registered(study)
    if order not in (1, 2):
        raise InputError("--order", order, "must be 1 or 2")
    params = with_crack(study, params, crack_depth_mm)
    # every path that meshes a study (solve, validate, diagnose --baseline fea, a sweep's worker) is budgeted
    from .budget import check_budget
    check_budget(study, params, mesh_size_mm, quick, flag="--mesh-size-mm" if mesh_size_mm else "--params")
    module = importlib.import_module(spec.module)
    result = module.run(params, mesh_size_mm=mesh_size_mm, order=order, crack_depth_mm=crack_depth_mm,
                        vtu=vtu, progress=progress or (lambda msg: None), quick=quick, **spec.load_for(params))
    refuse_identical_meshes(study, result, mesh_size_mm)
    return result


def refuse_identical_meshes(study: str, result: StudyResult, mesh_size_mm: float | None) -> None:
    """Three meshes that came out the same (the part's own features set gmsh's size, not h) give every
    quantity the same value three times: a GCI of 0 % at p = inf that means nothing. Refused, never reported."""
    series = [q.convergence.values for q in result.quantities.values() if q.convergence is not None]
    if series and all(v[0] == v[1] == v[2] for v in series):
        dofs = result.mesh.dofs
        raise InputError("--mesh-size-mm", "the study default" if mesh_size_mm is None else mesh_size_mm,
                         f"{study}: the three meshes came out identical ({dofs} dofs each, every quantity the same "
                         "three times), so no GCI can be computed; the part's own features cap the element size "
                         "here: give a smaller size (the finest of the three meshes)")
