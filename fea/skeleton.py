"""The one study skeleton: build the part -> mesh three refinements at one ratio -> solve -> converge (GCI)
-> write fields, and a typed ``StudyResult`` out.

As in scikit-fem's tests/test_convergence.py, the skeleton is written once and each study is a variant
that overrides hooks for what differs: the part it builds (``build``), the series of three refinements
it needs (``series``: a 3D study has one; the ring has a smooth, a toothed and a 3D series), how one
refinement is meshed and solved (``solve``), which quantities it reports from the solved series
(``quantities``), the load and supports it applied (``load``, ``supports``), its crack (``crack``) and
the fields it writes (``write_fields``). The three-mesh loop itself is ``refinement.on_three_meshes``;
the GCI is ``refinement.converged_quantity``.
"""
from __future__ import annotations

import math
import time
from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Mapping, Sequence

from strainwave.fea.refinement import converged_quantity, on_three_meshes
from strainwave.fea.result import CrackRecord, Load, MeshQuality, Quantity, StudyResult, Support
from strainwave.fea.study_facts import StudyFacts

Progress = Callable[[str], None]


@dataclass(frozen=True)
class MeshSolve:
    """What one refinement of a series gives back: its values by quantity name, its mesh and its cost."""

    h_mm: float                                  # size as meshed (a gmsh retry may scale the request)
    values: Mapping[str, float]                  # by name: the quantities' values and per-mesh facts (sizes)
    mesh: MeshQuality
    timings_s: Mapping[str, float] = field(default_factory=dict)
    solver: Mapping = field(default_factory=dict)
    fields: Mapping[str, object] = field(default_factory=dict)   # kept on the finest mesh only, for write_fields

    def __post_init__(self):
        if not self.h_mm > 0:
            raise ValueError(f"mesh size must be > 0, got {self.h_mm!r}")


@dataclass(frozen=True)
class SeriesPlan:
    """One series of three refinements: its name and the refinement parameter of each mesh, finest first
    (a global size in mm for a mesher series; a count of layers for a structured one)."""

    name: str
    refinements: tuple[float, float, float]

    def __post_init__(self):
        if len(self.refinements) != 3:
            raise ValueError(f"series {self.name}: three refinements, finest first")


@dataclass(frozen=True)
class Series:
    """The three solves of one series, finest first."""

    name: str
    solves: tuple[MeshSolve, MeshSolve, MeshSolve]

    @property
    def finest(self) -> MeshSolve:
        return self.solves[0]

    @property
    def h_mm(self) -> tuple[float, float, float]:
        return tuple(s.h_mm for s in self.solves)

    def values(self, name: str) -> list[float]:
        return [s.values[name] for s in self.solves]

    def converged(self, name: str, unit: str, values: Sequence[float] | None = None, *,
                  order: float | None = None) -> Quantity:
        """``name`` (or the per-mesh ``values`` derived from this series) with its GCI on this series' sizes."""
        return converged_quantity(name, unit, self.h_mm, self.values(name) if values is None else list(values),
                                  order=order)


class StudyVariant(StudyFacts, ABC):
    """The hooks a study overrides; ``run_variant`` is the skeleton that calls them. Its class-level facts
    (element estimate, default size, CAD, rated load, report) are ``StudyFacts``'."""

    @abstractmethod
    def build(self):
        """The part(s) the series mesh (geometry stage)."""

    @abstractmethod
    def series(self) -> tuple[SeriesPlan, ...]:
        """The series to solve; the first is the headline: its finest mesh is ``StudyResult.mesh``."""

    @abstractmethod
    def solve(self, parts, series: str, refinement: float, k: int, keep_fields: bool,
              progress: Progress) -> MeshSolve:
        """Mesh and solve refinement ``k`` (0 = finest) of ``series``; keep the fields when asked."""

    @abstractmethod
    def quantities(self, series: Mapping[str, Series]) -> dict[str, Quantity]:
        """The study's quantities, each with its GCI, from the solved series."""

    @abstractmethod
    def load(self, parts) -> Load:
        """The resultant the study applied."""

    @abstractmethod
    def supports(self) -> tuple[Support, ...]:
        """How the part is held."""

    def crack(self, parts) -> CrackRecord | None:
        return None

    def write_fields(self, series: Mapping[str, Series], vtu: Path, load: Load) -> tuple[Path, ...]:
        """The finest solves' fields as VTU next to ``vtu`` (FieldData states ``load``)."""
        return ()

    def meta(self, parts, series: Mapping[str, Series]) -> dict:
        """Further facts for the reader of results.json (no stage reads them)."""
        return {}


def check_variant(study: str, *, order: int, sizes_mm: Sequence[float], crack_depth_mm: float | None = None,
                  **positive: float) -> None:
    """What every variant's ``__post_init__`` asserts: a P1/P2 element, positive finite sizes and loads, a crack
    depth > 0 when there is one (the CLI refuses bad input before this with exit 2; this guards direct use)."""
    if order not in (1, 2):
        raise ValueError(f"{study}: element order must be 1 or 2, got {order!r}")
    named = {f"size {k}": h for k, h in enumerate(sizes_mm)} | dict(positive)
    if crack_depth_mm is not None:
        named["crack_depth_mm"] = crack_depth_mm
    for name, value in named.items():
        if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise ValueError(f"{study}: {name} must be finite and > 0, got {value!r}")


def _add(timings: dict, more: Mapping[str, float]) -> None:
    for key, seconds in more.items():
        timings[key] = timings.get(key, 0.0) + seconds


def run_variant(variant: StudyVariant, *, vtu: Path | None = None,
                progress: Progress = lambda m: None) -> StudyResult:
    """part -> three refinements per series (coarse to fine) -> quantities with GCI -> fields -> StudyResult."""
    t_start = time.perf_counter()
    parts = variant.build()
    timings = {"geometry": time.perf_counter() - t_start}
    solved: dict[str, Series] = {}
    plans = variant.series()
    for plan in plans:
        solves = on_three_meshes(
            lambda r, k, name=plan.name: variant.solve(parts, name, r, k, vtu is not None and k == 0, progress),
            plan.refinements, progress=progress, label=f"{variant.study} ({plan.name}): ")
        solved[plan.name] = Series(plan.name, solves)
        for s in solves:
            _add(timings, s.timings_s)
    quantities = variant.quantities(solved)
    load = variant.load(parts)
    fields = ()
    if vtu is not None:
        t0 = time.perf_counter()
        fields = tuple(variant.write_fields(solved, Path(vtu), load))
        timings["vtu"] = time.perf_counter() - t0
    head = solved[plans[0].name]
    timings["total"] = time.perf_counter() - t_start
    return StudyResult(variant.study, quantities, head.finest.mesh, load, variant.supports(),
                       variant.crack(parts), timings, fields, dict(head.finest.solver), variant.meta(parts, solved),
                       tuple(s.mesh for s in head.solves))
