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

from strainwave.errors import InputError
from strainwave.registry import study as registered
from strainwave.fea.result import StudyResult


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
              progress: Callable[[str], None] | None = None, quick: bool = False,
              crack_field_only: bool = False, cache_dir: Path | None = None) -> StudyResult:
    """``crack_field_only``: ``vtu`` receives the crack's own field alone (a study whose facts say
    ``crack_field_alone``; validate's close-up case), so the whole part need not be solved for its field.
    ``cache_dir``: a folder where a study whose facts say ``shares_cache`` keeps what its cases share (others
    ignore it)."""
    spec = registered(study)
    if crack_field_only and not spec.facts().crack_field_alone:
        raise ValueError(f"{study}: cannot write its crack's field alone (crack_field_only)")
    only = {"crack_field_only": True} if crack_field_only else {}
    if cache_dir is not None and spec.facts().shares_cache:
        only["cache_dir"] = Path(cache_dir)
    if order not in (1, 2):
        raise InputError("--order", order, "must be 1 or 2")
    params = with_crack(study, params, crack_depth_mm)
    # every path that meshes a study (solve, validate, diagnose --baseline fea, a sweep's worker) is budgeted
    from strainwave.fea.budget import check_budget
    check_budget(study, params, mesh_size_mm, quick, flag="--mesh-size-mm" if mesh_size_mm else "--params")
    module = importlib.import_module(spec.module)
    say = progress or (lambda msg: None)
    size = mesh_size_mm
    for _ in range(DEFAULT_RETRIES + 1):
        result = module.run(params, mesh_size_mm=size, order=order, crack_depth_mm=crack_depth_mm,
                            vtu=vtu, progress=say, quick=quick, **only, **spec.load_for(params))
        finest = identical_meshes(result)
        if finest is None:
            return result
        if mesh_size_mm is not None:   # the user's own size: refused, never a 0 % GCI
            raise InputError("--mesh-size-mm", mesh_size_mm,
                             f"{study}: the three meshes came out identical ({result.mesh.dofs} dofs each, every "
                             "quantity the same three times), so no GCI can be computed; the part's own features "
                             "cap the element size here: give a smaller size (the finest of the three meshes)")
        size = finest / COARSEST_OVER_FINEST   # the default was too coarse for this part: the coarsest mesh at it
        say(f"{study}: the three meshes at the default size came out identical (the part's features cap it); "
            f"solving again with the finest at {size:.3g} mm")
    raise InputError("--mesh-size-mm", "the study default",
                     f"{study}: the three meshes stay identical down to {size:.3g} mm; give a size")


# A default size whose three meshes come out identical is refined this often (by the whole ladder each time).
DEFAULT_RETRIES = 2
COARSEST_OVER_FINEST = 1.96      # 1.4^2: the refinement ladder of every study


def identical_meshes(result: StudyResult) -> float | None:
    """The finest size when every quantity has the same value on all three meshes (they came out the same:
    the part's own features set gmsh's size, not h), else None. Such a GCI, 0 % at p = inf, means nothing."""
    series = [q.convergence for q in result.quantities.values() if q.convergence is not None]
    if series and all(c.values[0] == c.values[1] == c.values[2] for c in series):
        return min(min(c.h_mm) for c in series)
    return None
