"""The report's inputs-and-model section: per component what was built, loaded, held and meshed.

Dimensions and material come from the parameters (typed), the load magnitude from the rated-load record
(``strainwave.rated_stress``), the element and the three meshes from the study result (``StudyResult.meshes``:
the ``MeshQuality`` of each refinement; their sizes from the quantities' convergence records). How each study
loaded and held its part is read from the result's typed ``Load`` and ``Support`` records; the part from the
registry. Only the element family is worded here (the mesh records state the degree).
"""
from __future__ import annotations

from dataclasses import dataclass

from strainwave.registry import study as registered

__all__ = ["ComponentInputs", "ELEMENT", "component_inputs"]

# The element family of each study, in words ({order} is filled with the degree of the finest mesh).
ELEMENT = {
    "shaft-torsion": "P{order} tetrahedra (curved, isoparametric); the crack on an axisymmetric (r, z) section of "
                     "P2 triangles",
    "cup-torsion": "P{order} tetrahedra (curved, isoparametric); crack as a seam, closed and opened",
    "bearing-ring": "P{order} tetrahedra (curved, isoparametric); crack as a seam with frictionless crack-face contact",
    "ring-compression": "P{order} triangles (curved), 2D plane stress, thickness = face width B; 3D check on curved "
                        "P2 tetrahedra",
    "wg-bearing": "P2 triangles on a graded polar grid, 2D plane stress, thickness = ring width B; race crack as two "
                  "coincident faces with frictionless contact",
    "cup-surface-crack": "P2 tetrahedra graded to the crack front, quarter block of the band wall; the crack face in "
                         "frictionless contact with its mirror (symmetry plane)",
}


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


def _dimensions(study: str, params) -> tuple[tuple[str, str], ...]:
    if study == "shaft-torsion":
        s = params.output_shaft
        return (("outer diameter d_s", f"{s.outer_diameter_mm:g} mm"), ("inner diameter d_s2", f"{s.inner_diameter_mm:g} mm"),
                ("length L_s", f"{s.length_mm:g} mm"), ("wall", f"{s.wall_mm:g} mm"))
    if study == "cup-torsion":
        c = params.flexspline_cup
        return (("pitch diameter d1", f"{c.pitch_diameter_mm:g} mm"), ("wall delta", f"{c.wall_thickness_mm:g} mm"),
                ("length L", f"{c.length_mm:g} mm"), ("shape", f"{c.shape}{', cup' if c.cup else ''}"),
                ("teeth x module", f"{c.teeth} x {c.module_mm:g} mm"))
    if study == "bearing-ring":
        w = params.wave_generator
        a, b = w.contact_semi_axes_mm
        return (("inner ring thickness t_i", f"{w.bearing_inner_ring_thickness_mm:g} mm"),
                ("contact ellipse a' x b'", f"{a:g} x {b:g} mm"), ("wave generator", w.kind.value),
                ("flexspline pitch diameter d1", f"{params.flexspline_cup.pitch_diameter_mm:g} mm"))
    e = params.ewg_drive
    return (("teeth Z_R, tooth difference dZ", f"{e.flexspline_teeth}, {e.tooth_difference}"),
            ("module m", f"{e.module_mm:g} mm"), ("reference diameter d_R", f"{e.reference_diameter_mm:g} mm"),
            ("rim thickness delta", f"{e.rim_thickness_mm:.4g} mm"), ("face width B", f"{e.face_width_mm:g} mm"),
            ("root fillet rho_f", f"{e.root_fillet_coefficient:g} m"))


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
    return ComponentInputs(component, case.label, case.study, registered(case.study).part,
                           _dimensions(case.study, params) + ((("crack depth a", f"{case.crack_depth_mm:g} mm"),)
                                                              if crack else ()),
                           material, load, supports, ELEMENT[case.study].format(order=finest.order), meshes, note)
