"""One sweep point as one Dask task: parameters -> mesh -> solve -> a record with the closed forms beside it.

A task is pure in its inputs and idempotent: the record is cached on disk under a hash of the full
parameter table, the study, the mesh level, the task function and the code version
(``compare/cache.py``), so a rerun or a resumed sweep reads it back instead of solving again.
Errors are caught per point: the record says ``failed`` with the one-line message and the sweep goes on.
Deterministic refusals (``StrainwaveError``: geometry refused, mesher or solver failed) are cached like
results; anything unexpected (a crashed library, memory) is recorded but *not* cached, so a rerun retries it.
"""
from __future__ import annotations

import math
import os
import socket
import time
import warnings
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path
from typing import Callable, Sequence

from strainwave.cache import ResultCache, case_key
from strainwave.errors import StrainwaveError
from strainwave.fea.result import Load
from strainwave.fea.study_facts import DEFAULT_CAD_MODULES
from strainwave.registry import STUDIES

# A task computes the quantities of one point: (study, params, quick) -> a ``StudyResult.to_dict()``-shaped
# dict (``{"quantities": {name: {"value", "unit", "uncertainty"}}, "mesh": {"dofs": ...} | None}``).
# The default is the FEA study; run_sweep accepts another one (the seam tests and benchmarks use to
# exercise the Dask machinery without meshing). It must be a module-level function, so workers can import it.
TaskFn = Callable[[str, object, bool], dict]

# Which closed form stands beside each FEA quantity is validate's check list (``check_list.CHECKS``), evaluated
# under the registry study's load conditions; a quantity without a check beside it gets no analytic column.

@dataclass(frozen=True)
class PointSpec:
    """Everything a worker needs for one point; small and picklable."""

    study: str
    values: tuple[tuple[str, object], ...]    # the varied dotted keys and their values at this point
    base: dict = field(hash=False)              # Params.to_dict() of the sweep's base parameters
    quick: bool = False
    seed_crack: bool = False                    # mesh the study's crack, of the depth under its crack key

    @property
    def inputs(self) -> dict:
        return dict(self.values)

    def merged(self) -> dict:
        """The full parameter table of this point (not yet validated)."""
        table = {section: dict(keys) for section, keys in self.base.items()}
        for dotted, value in self.values:
            section, _, key = dotted.partition(".")
            table[section][key] = value
        return table


def task_name(task: TaskFn | None) -> str:
    """Stable identity of a task function, part of the cache key (an FEA record never answers a probe)."""
    if task is None:
        return "fea.run_study"
    inner = getattr(task, "func", task)   # functools.partial keeps its arguments in the name
    args = getattr(task, "keywords", None)
    return f"{inner.__module__}.{inner.__qualname__}" + (f"{sorted(args.items())}" if args else "")


def point_key(spec: PointSpec, task: TaskFn | None) -> str:
    return case_key(f"sweep:{spec.study}", {"params": spec.merged(), "quick": spec.quick,
                                            "crack": spec.seed_crack, "task": task_name(task)})


def fea_task(study: str, params, quick: bool, *, crack_depth_mm: float | None = None) -> dict:
    """The default task: the FEA study of ``fea/studies.py`` on this point's parameters."""
    from strainwave.fea.studies import run_study
    return run_study(study, params, quick=quick, crack_depth_mm=crack_depth_mm).to_dict()


# The default task's libraries, which the pipeline imports inside the functions that use them (so that a
# closed form or a refused point never pays for them): meshing, assembly and solver, the closed forms.
FEA_MODULES = ("gmsh", "skfem", "pyamg", "strainwave.analytic.summary")


def warm_modules(study: str, task: TaskFn | None, specs: Sequence[PointSpec] = ()) -> tuple[str, ...]:
    """What a worker of the sweep's own cluster imports before it registers (``worker.SweepWorker``): the FEA
    pipeline of ``study`` and the CAD its points ``specs`` build with (the variant's ``cad_modules``,
    docs/decisions/013-sweep-worker-start-up.md); nothing for another task (its module comes with the first
    task it unpickles, and it may need none of the FEA's libraries)."""
    if task is not None:
        return ()
    from strainwave.params import params_from_dict

    # the driver has imported the study module already, to estimate each point's elements (fea/budget.py)
    facts = STUDIES[study].facts()
    cad: dict[str, None] = {} if specs else dict.fromkeys(DEFAULT_CAD_MODULES)   # no point known: the general CAD
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")   # a point's RangeWarnings are its worker's to record
        for spec in specs:
            cad.update(dict.fromkeys(facts.cad_modules(params_from_dict(spec.merged()), spec.seed_crack)))
    return (__name__, STUDIES[study].module, *FEA_MODULES, *cad)


def closed_form_probe(study: str, params, quick: bool, *, delay_s: float = 0.0) -> dict:
    """A cheap, real task for testing the sweep machinery: the hollow-shaft torsional compliance.

    lambda = 32 L / (pi mu (D^4 - d^4)) (Seed 000, lambda_so0, with the bore; see the formula audit).
    It is *not* an FEA result and is labelled ``probe_`` so it never stands in for one; ``delay_s``
    stands for the cost of a solve when timing the scheduler. Impossible points (a bore wider than the
    shaft, a crack through the wall) are refused before it runs, by the parameter schema, as for FEA.
    """
    shaft, mu = params.output_shaft, params.material.shear_modulus_MPa
    if delay_s:
        time.sleep(delay_s)
    compliance = 32.0 * shaft.length_mm / (math.pi * mu * (shaft.outer_diameter_mm ** 4 - shaft.inner_diameter_mm ** 4))
    return {"quantities": {"probe_shaft_compliance_rad_per_Nmm": {
        "value": compliance, "unit": "rad/(N mm)", "uncertainty": 0.0}}, "mesh": None}


def analytic_beside(study: str, params, names, force_N: float | None = None,
                    crack_depth_mm: float | None = None) -> dict:
    """{quantity: {key, published, corrected}} for the FEA quantities ``names``: the closed form of the validate
    check that stands beside each (``check_list.CHECKS``: the same function validate asserts), at this point's
    parameters under the study's load conditions, its crack depth and the force the FEA applied."""
    from strainwave.compare.validate.check_list import At, beside
    specs = {name: spec for name, spec in beside(study).items() if name in names and spec.reference is not None}
    if not specs:
        return {}
    for dotted, value in STUDIES[study].analytic_overrides:
        params = params.with_value(dotted, value)
    at = At(crack_depth_mm, force_N)
    out = {}
    for name, spec in specs.items():
        ref = spec.reference(params, at)      # None: no closed form at this point (uncracked, no force)
        out[name] = {"key": f"checks.{spec.id}", "unit": None if ref is None else ref.unit,
                     "published": None if ref is None else ref.published,
                     "corrected": None if ref is None else ref.corrected}
    return out


def _compute(spec: PointSpec, task: TaskFn | None) -> dict:
    from strainwave.params import params_from_dict
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        params = params_from_dict(spec.merged())      # InputError here: the point is impossible
        crack = params.crack_depth_mm(STUDIES[spec.study].crack_key) if spec.seed_crack else None
        if task is None:
            result = fea_task(spec.study, params, spec.quick, crack_depth_mm=crack)
        else:
            result = task(spec.study, params, spec.quick)
        fea = {name: {"value": q["value"], "unit": q["unit"], "uncertainty": q.get("uncertainty")}
               for name, q in result["quantities"].items()}
        load = result.get("load")
        analytic = analytic_beside(spec.study, params, fea, None if load is None else Load.from_dict(load).force_N,
                                   crack)
    notes = {str(w.message) for w in caught}
    for name, entry in analytic.items():
        if entry.get("unit") and _unit(entry["unit"]) != _unit(fea[name]["unit"]):
            # never compare numbers in different units: the closed form is dropped and the point says why
            notes.add(f"{name}: FEA in {fea[name]['unit']}, {entry['key']} in {entry['unit']}; not compared")
            entry["published"] = entry["corrected"] = None
    mesh = result.get("mesh") or {}
    return {"status": "ok", "error": None, "fea": fea, "analytic": analytic, "dofs": mesh.get("dofs"),
            "warnings": sorted(notes), "design_n": design_n(params)}


def design_n(params) -> dict[str, float | None]:
    """Each design factor's n at this point, closed form (analytic/design_factors.py): the sweep's n columns."""
    from strainwave.analytic import design_factors as df
    out = {}
    for name, build in DESIGN_BUILDERS.items():
        try:
            n = getattr(df, build)(params, None, False).n
        except ValueError:      # a point the factor's closed form cannot take (the bearing does not fit)
            n = None
        out[name] = n if n is None or math.isfinite(n) else None
    return out


DESIGN_BUILDERS = {"ring": "ring_factor", "cup_tooth_root": "cup_tooth_root_factor", "wg_inner_ring": "wg_inner_ring_factor",
                   "wg_outer_ring": "wg_outer_ring_factor", "cup_diaphragm": "diaphragm_factor"}


def _unit(text: str) -> str:
    """A unit string without spelling differences: 'rad/(N mm)' == 'rad/(N*mm)'."""
    return "".join(c for c in text if c not in " *·")


def point_record_ok(record: dict, key: str) -> bool:
    """A cached point is one this code wrote under ``key``: a status, and an ok point's every quantity a number
    with its unit (a hand-made ``{"status": "ok"}`` is no finished point)."""
    if record.get("key") != key or record.get("status") not in ("ok", "failed") \
            or not isinstance(record.get("fea"), dict) or not isinstance(record.get("analytic"), dict):
        return False
    if record["status"] == "failed":
        return isinstance(record.get("error"), str)
    return bool(record["fea"]) and all(isinstance(q, dict) and isinstance(q.get("value"), (int, float))
                                       and isinstance(q.get("unit"), str) for q in record["fea"].values())


def run_point(spec: PointSpec, key: str, cache_root: str, task: TaskFn | None = None) -> dict:
    """Solve one point (or read it back from the cache under ``key``); never raises for a bad point.

    ``key`` is ``point_key(spec, task)`` computed once by the driver: the code version is hashed there,
    so a worker that started on other sources still writes where the driver will look.
    """
    # One BLAS/OpenMP thread per worker process; a remote cluster should also start its workers so.
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    cache = ResultCache(Path(cache_root))
    cached = cache.get(key, lambda r: point_record_ok(r, key))
    if cached is not None:
        return {**cached, "cached": True}
    started = time.perf_counter()
    keep = True
    try:
        record = _compute(spec, task)
    except StrainwaveError as exc:
        record = {"status": "failed", "error": f"{type(exc).__name__}: {exc}"}
    except Exception as exc:  # noqa: BLE001 - one bad point must not stop the sweep; recorded, not cached
        record = {"status": "failed", "error": f"{type(exc).__name__}: {exc}"}
        keep = False
    record.update({"key": key, "study": spec.study, "inputs": spec.inputs, "task": task_name(task),
                   "elapsed_s": time.perf_counter() - started, "host": socket.gethostname(), "pid": os.getpid(),
                   "computed_at": datetime.now(timezone.utc).isoformat()})
    record.setdefault("fea", {})
    record.setdefault("analytic", {})
    if keep:
        cache.put(key, record)
    return {**record, "cached": False}
