"""What leaves a study: plain values with units, their discretization error and the mesh facts."""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from .convergence import Convergence


@dataclass(frozen=True)
class MeshQuality:
    elements: int
    nodes: int
    dofs: int
    order: int
    min_quality: float      # gmsh minSICN of the worst element
    mean_quality: float

    def to_dict(self) -> dict:
        return dict(self.__dict__)


@dataclass(frozen=True)
class Quantity:
    """One headline number. ``value`` is from the finest mesh; ``convergence`` holds all three."""

    name: str              # units in the name, e.g. flexibility_rad_per_Nmm
    value: float
    unit: str
    convergence: Convergence | None = None

    @property
    def uncertainty(self) -> float | None:
        return None if self.convergence is None else self.convergence.uncertainty

    def to_dict(self) -> dict:
        return {"name": self.name, "value": self.value, "unit": self.unit, "uncertainty": self.uncertainty,
                "convergence": None if self.convergence is None else self.convergence.to_dict()}


@dataclass(frozen=True)
class StudyResult:
    study: str                                   # kebab-case study name
    quantities: dict[str, Quantity]
    mesh: MeshQuality                            # of the finest mesh
    timings_s: dict[str, float] = field(default_factory=dict)
    fields: tuple[Path, ...] = ()                # VTU files written
    meta: dict = field(default_factory=dict)     # loads, BCs, solver settings, material constants used
    meshes: tuple[MeshQuality, ...] = ()         # the three refinements of ``mesh``'s series, finest first

    def __getitem__(self, name: str) -> Quantity:
        return self.quantities[name]

    def to_dict(self) -> dict:
        return {"study": self.study, "quantities": {k: q.to_dict() for k, q in self.quantities.items()},
                "mesh": self.mesh.to_dict(), "timings_s": dict(self.timings_s),
                "fields": [str(p) for p in self.fields], "meta": self.meta,
                "meshes": [m.to_dict() for m in self.meshes]}

    def summary(self) -> str:
        lines = [f"{self.study}: {self.mesh.elements} elements, {self.mesh.dofs} dofs, P{self.mesh.order}, "
                 f"quality min {self.mesh.min_quality:.3f} mean {self.mesh.mean_quality:.3f}"]
        for q in self.quantities.values():
            err = "" if q.convergence is None else (
                f"  +/- {q.convergence.gci_fine * 100:.3g} % (GCI, p = {q.convergence.observed_order:.2f}, "
                f"extrapolated {q.convergence.extrapolated:.6g})")
            lines.append(f"  {q.name:<40s} {q.value:.6g} {q.unit}{err}")
        if self.timings_s:
            lines.append("  time: " + ", ".join(f"{k} {v:.2f} s" for k, v in self.timings_s.items()))
        return "\n".join(lines)
