"""Run the FEA cases of a validation, reusing finished ones from the result cache.

Each case is one ``run_study`` call. A finished case is stored as ``StudyResult.to_dict()`` under a
key of (study, crack depth, quick, order, parameters, code version); a rerun rebuilds the result
from it as long as the VTU files it names still exist. A case that fails is recorded with the stage
and message, never dropped: the checks that needed it say why they were not evaluated.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from strainwave.fea.result import StudyResult
from strainwave.cache import NUMBER, ResultCache, case_key
from strainwave.output_guard import reuse_output
from strainwave.rated_stress import rated_load_of, write_at_rated


@dataclass(frozen=True)
class Case:
    """One FEA study run: ``label`` names it in the report and in ``fields/<label>.vtu``."""

    label: str
    study: str
    crack_depth_mm: float | None = None
    mesh_size_mm: float | None = None        # finest global size; None = the study's default
    fields: bool = True                      # write fields/<label>.vtu (a report picture draws it)
    crack_field_only: bool = False           # of the fields, only the crack's own (the close-up draws no other)

    def payload(self, params, quick: bool, order: int) -> dict:
        only = {"crack_field_only": True} if self.crack_field_only else {}
        return {"study": self.study, "crack_depth_mm": self.crack_depth_mm, "quick": quick, "order": order,
                "mesh_size_mm": self.mesh_size_mm, "params": params.to_dict(), **only}


@dataclass(frozen=True)
class CaseOutcome:
    case: Case
    result: StudyResult | None
    seconds: float          # wall time of the computation (of the original run when cached)
    cached: bool
    error: str = ""
    cpu_s: float | None = None   # CPU time of the case process (of the original run when cached)

    @property
    def ok(self) -> bool:
        return self.result is not None


def _describe(case: Case) -> str:
    depth = "" if case.crack_depth_mm is None else f", crack {case.crack_depth_mm:g} mm"
    return f"{case.study}{depth}"


# Wall-time limit of one case, far above any case's cost on a loaded machine: past it the study ignored ``quick``
# or hangs.
CASE_TIMEOUT_S = {True: 150.0, False: 900.0}


def run_case(case: Case, params, *, fields_dir: Path, cache: ResultCache, quick: bool, order: int = 2,
             progress: Callable[[str], None], timeout_s: float | None = None) -> CaseOutcome:
    """Solve one case in an isolated child process, or reuse it from the cache (and say so)."""
    from strainwave.compare.validate.isolated import run_isolated

    key = case_key("validate-case", case.payload(params, quick, order))
    hit = cache.get(key, {"result": dict, "seconds": NUMBER})
    if hit is not None:
        try:
            result = StudyResult.from_dict(hit["result"])
            fields = [reuse_output(p) for p in result.fields]   # the previous run's files, into this run's set
            if all(f is not None for f in fields):
                result = dataclasses.replace(result, fields=tuple(fields))
                progress(f"  {case.label}: reusing cached {_describe(case)} (computed in {hit['seconds']:.1f} s)")
                cpu = hit.get("cpu_s")
                return CaseOutcome(case, result, float(hit["seconds"]), True, cpu_s=None if cpu is None else float(cpu))
        except (KeyError, TypeError, ValueError):
            pass  # an entry from an older layout is recomputed
    progress(f"  {case.label}: solving {_describe(case)} ...")
    kwargs = {"mesh_size_mm": case.mesh_size_mm, "order": order, "crack_depth_mm": case.crack_depth_mm,
              "vtu": Path(fields_dir) / f"{case.label}.vtu" if case.fields else None, "quick": quick}
    if case.fields and case.crack_field_only:
        kwargs["crack_field_only"] = True
    kwargs["cache_dir"] = cache.root      # what the study's cases share (the cup's section), beside the results
    child = run_isolated(case.study, params, kwargs, timeout_s=timeout_s or CASE_TIMEOUT_S[quick],
                         progress=lambda msg: progress(f"    {msg}"))
    if child.result is None:
        # One failed study (mesher, solver, crash, time limit, or a module not yet there) must not hide the
        # others: it is recorded with its message and every check that needed it is reported as failed.
        progress(f"  {case.label}: FAILED after {child.seconds:.1f} s ({child.error})")
        return CaseOutcome(case, None, child.seconds, False, child.error)
    result = StudyResult.from_dict(child.result)
    # the fields a reader opens are at the load the report states, and say so in their FieldData; a
    # study with no rated load of its own (wg-bearing: solved at its rated loads) keeps them as solved
    try:
        rated = rated_load_of(case.study, params, result)
    except ValueError:
        rated = None
    if rated is not None:
        write_at_rated(result.fields, rated)
    cache.put(key, {"case": case.label, "seconds": child.seconds, "cpu_s": child.cpu_s, "result": child.result})
    cpu = "" if child.cpu_s is None else f", {child.cpu_s:.1f} s CPU"
    progress(f"  {case.label}: done in {child.seconds:.1f} s ({result.mesh.dofs} dofs{cpu})")
    return CaseOutcome(case, result, child.seconds, False, cpu_s=child.cpu_s)
