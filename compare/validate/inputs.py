"""The report's inputs-and-model section: per component what was built, loaded, held and meshed.

Dimensions and material come from the parameters (typed), the load magnitude from the rated-load record
(``strainwave.rated_stress``), the element and the three meshes from the study result (``StudyResult.meshes``:
the ``MeshQuality`` of each refinement; their sizes from the quantities' convergence records). How each study
loaded and held its part is read from the result's typed ``Load`` and ``Support`` records; the part from the
registry; the dimensions and the element family in words from the study's variant (``StudyFacts``).
"""
from __future__ import annotations

from dataclasses import dataclass

from strainwave.registry import study as registered

__all__ = ["ComponentInputs", "component_inputs"]

@dataclass(frozen=True)
class MeshRow:
    h_mm: float
    dofs: int | None
    min_quality: float | None


@dataclass(frozen=True)
class ComponentInputs:
    component: str
    case: str
    study: str
    part: str
    dimensions: tuple[tuple[str, str], ...]      # (name, value with unit)
    material: str
    load: str
    supports: str
    element: str
    meshes: tuple[MeshRow, ...]                  # fine to coarse
    mesh_note: str

    def to_dict(self) -> dict:
        return {"component": self.component, "case": self.case, "study": self.study,
                "part": self.part, "dimensions": [list(d) for d in self.dimensions],
                "material": self.material, "load": self.load, "supports": self.supports, "element": self.element,
                "meshes": [{"h_mm": m.h_mm, "dofs": m.dofs, "min_quality": m.min_quality} for m in self.meshes],
                "mesh_note": self.mesh_note}


def component_inputs(component: str, case, result, params, rated) -> ComponentInputs:
    """The inputs of ``component`` solved as ``case`` (its ``StudyResult``; ``rated``: its ``RatedLoad``)."""
    m = params.material
    material = (f"E = {m.youngs_modulus_MPa:g} MPa, nu = {m.poisson_ratio:g} (the FEA's G = E/2(1+nu) = "
                f"{m.youngs_modulus_MPa / (2 * (1 + m.poisson_ratio)):.5g} MPa; seed 000's mu = "
                f"{m.shear_modulus_MPa:g} MPa), fatigue limit sigma_-1 = {m.fatigue_limit_MPa:g} MPa")
    applied = result.load
    load = (f"{applied.distribution} on {', '.join(repr(g) for g in applied.on)} ({applied.name}); solved at "
            f"{rated.solved:.4g} {rated.unit}, drawn at {rated.describe()}")
    supports = "; ".join(s.describe() for s in result.supports)
    crack = "" if case.crack_depth_mm is None else f"; crack depth a = {case.crack_depth_mm:g} mm"
    # the three sizes of the quantity the headline mesh serves first (its own series: smooth ring, 3D shaft)
    sizes = next((q.convergence.h_mm for q in result.quantities.values() if q.convergence is not None), ())
    finest = result.mesh
    recorded = result.meshes if len(result.meshes) == len(sizes) else (finest,)
    meshes = tuple(MeshRow(h, recorded[k].dofs if k < len(recorded) else None,
                           recorded[k].min_quality if k < len(recorded) else None) for k, h in enumerate(sizes))
    note = (f"finest mesh: {finest.elements} elements, {finest.nodes} nodes, {finest.dofs} dofs, element quality "
            f"(gmsh SICN) min {finest.min_quality:.3g}, mean {finest.mean_quality:.3g}"
            + ("" if len(recorded) == len(sizes) else "; the coarser meshes were not recorded by the study"))
    spec = registered(case.study)
    facts = spec.facts()       # the study's own words: its dimensions and element family
    return ComponentInputs(component, case.label, case.study, spec.part,
                           facts.dimensions(params) + ((("crack depth a", f"{case.crack_depth_mm:g} mm"),)
                                                       if crack else ()),
                           material, load, supports, facts.element_text.format(order=finest.order), meshes, note)
