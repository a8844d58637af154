"""What leaves a study: typed records with units (quantities with their discretization error, the load it
applied, the supports it held the part by, its crack, the mesh facts), never dict keys a consumer probes.

``StudyResult.to_dict`` / ``StudyResult.from_dict`` are the one JSON form (result cache, results.json).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from strainwave.fea.convergence import Convergence, GciUndefined, formal_order, grid_convergence

LOAD_UNITS = ("N*mm", "N")      # a torque or a force: every study applies one resultant


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
        # a refused GCI (three identical values) is no uncertainty at all, not a NaN one
        return None if self.convergence is None or self.convergence.refused else self.convergence.uncertainty

    def to_dict(self) -> dict:
        return {"name": self.name, "value": self.value, "unit": self.unit, "uncertainty": self.uncertainty,
                "convergence": None if self.convergence is None else self.convergence.to_dict()}

    @classmethod
    def from_dict(cls, data: dict) -> "Quantity":
        conv = data.get("convergence")
        return cls(data["name"], data["value"], data["unit"], _convergence_of(data["name"], data["unit"], conv))


def _convergence_of(name: str, unit: str, conv: dict | None) -> Convergence | None:
    """The stored record; one written before the GCI rule of issue 37 (no ``safety_factor``) is recomputed by
    that rule from its own three values, and one of three identical values has none."""
    if conv is None:
        return None
    if "safety_factor" in conv:
        return Convergence.from_dict(conv)
    try:
        return grid_convergence(conv["h_mm"], conv["values"], formal_order=formal_order(name, unit)[0])
    except GciUndefined as exc:
        return Convergence.refusal(conv["h_mm"], conv["values"], str(exc), formal_order(name, unit)[0])


@dataclass(frozen=True)
class Load:
    """The one resultant a study applied: what it is, its magnitude, the named faces it acts on and how it
    is spread there (``shape``: the distribution's parameters, units in their names)."""

    name: str                                  # e.g. "output torque T"
    magnitude: float
    unit: str                                  # one of LOAD_UNITS
    on: tuple[str, ...]                        # named boundary groups of the mesh
    distribution: str                          # how it is spread, in words (the report quotes it)
    shape: tuple[tuple[str, float], ...] = ()

    def __post_init__(self):
        if not (isinstance(self.magnitude, (int, float)) and math.isfinite(self.magnitude) and self.magnitude > 0):
            raise ValueError(f"load {self.name!r}: magnitude must be finite and > 0, got {self.magnitude!r}")
        if self.unit not in LOAD_UNITS:
            raise ValueError(f"load {self.name!r}: unit must be one of {', '.join(LOAD_UNITS)}, got {self.unit!r}")
        if not self.on:
            raise ValueError(f"load {self.name!r}: name the faces it acts on")

    @property
    def force_N(self) -> float | None:
        """The magnitude when the load is a force (the closed forms of a force-loaded study scale with it)."""
        return float(self.magnitude) if self.unit == "N" else None

    def parameter(self, name: str) -> float:
        for key, value in self.shape:
            if key == name:
                return value
        raise KeyError(f"load {self.name!r} has no shape parameter {name!r}")

    def describe(self) -> str:
        from strainwave.catalogue_units import beside   # a torque also in the catalogue's N m
        return (f"{self.name} = {self.magnitude:g} {self.unit}{beside(self.magnitude, self.unit)} on "
                f"{', '.join(repr(g) for g in self.on)}: {self.distribution}")

    def to_dict(self) -> dict:
        return {"name": self.name, "magnitude": self.magnitude, "unit": self.unit, "on": list(self.on),
                "distribution": self.distribution, "shape": dict(self.shape)}

    @classmethod
    def from_dict(cls, data: dict) -> "Load":
        return cls(data["name"], data["magnitude"], data["unit"], tuple(data["on"]), data["distribution"],
                   tuple((k, float(v)) for k, v in data.get("shape", {}).items()))


@dataclass(frozen=True)
class Support:
    """How the part is held: the named boundary groups and the condition imposed on them."""

    on: tuple[str, ...]
    condition: str

    def __post_init__(self):
        if not self.on or not self.condition:
            raise ValueError("a support names its faces and its condition")

    def describe(self) -> str:
        return f"{', '.join(repr(g) for g in self.on)}: {self.condition}"

    def to_dict(self) -> dict:
        return {"on": list(self.on), "condition": self.condition}

    @classmethod
    def from_dict(cls, data: dict) -> "Support":
        return cls(tuple(data["on"]), data["condition"])


@dataclass(frozen=True)
class CrackRecord:
    """The crack a study solved: its depth, how it was modelled and where it sits (for close-ups)."""

    depth_mm: float
    model: str                                 # e.g. "seam (one mesh, closed and opened)"
    z_mm: float | None = None                  # axial position of the crack plane, when the part has an axis

    def __post_init__(self):
        if not (math.isfinite(self.depth_mm) and self.depth_mm > 0):
            raise ValueError(f"crack depth must be finite and > 0, got {self.depth_mm!r}")

    def to_dict(self) -> dict:
        return {"depth_mm": self.depth_mm, "model": self.model, "z_mm": self.z_mm}

    @classmethod
    def from_dict(cls, data: dict | None) -> "CrackRecord | None":
        return None if data is None else cls(data["depth_mm"], data["model"], data.get("z_mm"))


@dataclass(frozen=True)
class StudyResult:
    study: str                                   # kebab-case study name
    quantities: dict[str, Quantity]
    mesh: MeshQuality                            # of the finest mesh
    load: Load
    supports: tuple[Support, ...]
    crack: CrackRecord | None = None             # None: the part was solved uncracked
    timings_s: dict[str, float] = field(default_factory=dict)
    fields: tuple[Path, ...] = ()                # VTU files written
    solver: dict = field(default_factory=dict)   # solver facts of the finest solve (method, iterations, ...)
    meta: dict = field(default_factory=dict)     # further facts for the reader of results.json; no stage reads it
    meshes: tuple[MeshQuality, ...] = ()         # the three refinements of ``mesh``'s series, finest first

    def __post_init__(self):
        if not self.supports:
            raise ValueError(f"{self.study}: a study states how its part is held")

    def __getitem__(self, name: str) -> Quantity:
        return self.quantities[name]

    @property
    def crack_depth_mm(self) -> float | None:
        return None if self.crack is None else self.crack.depth_mm

    def to_dict(self) -> dict:
        return {"study": self.study, "quantities": {k: q.to_dict() for k, q in self.quantities.items()},
                "mesh": self.mesh.to_dict(), "load": self.load.to_dict(),
                "supports": [s.to_dict() for s in self.supports],
                "crack": None if self.crack is None else self.crack.to_dict(),
                "timings_s": dict(self.timings_s), "fields": [str(p) for p in self.fields],
                "solver": dict(self.solver), "meta": self.meta, "meshes": [m.to_dict() for m in self.meshes]}

    @classmethod
    def from_dict(cls, data: dict) -> "StudyResult":
        """Inverse of ``to_dict`` (cached cases); KeyError/TypeError/ValueError on another layout."""
        return cls(data["study"], {name: Quantity.from_dict(q) for name, q in data["quantities"].items()},
                   MeshQuality(**data["mesh"]), Load.from_dict(data["load"]),
                   tuple(Support.from_dict(s) for s in data["supports"]), CrackRecord.from_dict(data.get("crack")),
                   dict(data.get("timings_s", {})), tuple(Path(p) for p in data.get("fields", [])),
                   dict(data.get("solver", {})), dict(data.get("meta", {})),
                   tuple(MeshQuality(**m) for m in data["meshes"]))

    def summary(self) -> str:
        lines = [f"{self.study}: {self.mesh.elements} elements, {self.mesh.dofs} dofs, P{self.mesh.order}, "
                 f"quality min {self.mesh.min_quality:.3f} mean {self.mesh.mean_quality:.3f}",
                 f"  load: {self.load.describe()}"]
        lines += [f"  support: {s.describe()}" for s in self.supports]
        if self.crack is not None:
            lines.append(f"  crack: a = {self.crack.depth_mm:g} mm, {self.crack.model}")
        for q in self.quantities.values():
            c = q.convergence
            # the basis names the observed p when it rests on it: said once
            observed = "" if c is None or "observed p" in c.basis else f"observed p = {c.observed_order:.2f}, "
            err = "" if c is None else (
                f"  +/- {c.gci_fine * 100:.3g} % (GCI, {c.basis}, {observed}extrapolated {c.extrapolated:.6g})")
            lines.append(f"  {q.name:<40s} {q.value:.6g} {q.unit}{err}")
        if self.timings_s:
            lines.append("  time: " + ", ".join(f"{k} {v:.2f} s" for k, v in self.timings_s.items()))
        return "\n".join(lines)
