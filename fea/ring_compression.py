"""Study `ring-compression` (seed 003): the EWG flexspline ring squeezed by two diametral forces.

Smooth ring (seed 003's model: rim of thickness delta between the root circle and the outer circle,
mid-layer radius r_m of eq 1) and toothed ring, 2D plane stress on ``Part.section`` (and 3D, coarser,
in ``fea/ring_solid.py``). Loads: the force pair F spread over a small arc (``fea/ring_loads.py``)
and the EWG's prescribed deformation (rigid contact strips pushed in by W0). F and W0 are inputs: the
registry computes them from seed 003 (``analytic/study_loads.py``: W0 = 0.5 m dZ, eq 7, and the thin-ring
force for delta_CD = 2 W0, eqs 3 and 5), so fea/ holds no closed form.

Definitions (every ratio at the SAME prescribed mid-layer deformation W0 = 0.5 m dZ, seed 003 eq 7;
linear problem, so each force solution is scaled to delta_CD = 2 W0):
- ``force_for_W0_N``: the F that gives delta_CD = 2 W0 (seed 003, eqs 3, 5).
- ``sigma_B/D_outer/inner_MPa``: hoop stress at sections B (phi = 0) and D (under the load), smooth ring;
  thin-ring values: eq 9 (B, outer, tensile) and eq 8 (D, outer, compressive); inner fibres opposite.
- ``tooth_influence`` K_delta: seed 003 eqs 10-11 multiply the smooth-shell stresses at given W0 by
  K_delta, so K_delta = (sigma_D - sigma_B)_toothed / (sigma_D - sigma_B)_smooth at the outer fibre
  (the smooth surface of an internally toothed ring: the rim's nominal stress, free of notch effects;
  peak within half a pitch of each section). The stiffness ratio F_toothed/F_smooth at equal W0 (the
  "delta" reading of K_delta) is reported in meta as ``tooth_stiffness_ratio``.
- ``root_stress_factor`` K_delta K_sigma: (root_D - root_B)_toothed / (inner_D - inner_B)_smooth, the peak
  signed principal stress on the tooth-root fillets within half a pitch of each section over the
  smooth ring's inner-fibre stress at the same W0 (the amplitude form).
- ``stress_concentration`` K_sigma = root_stress_factor / tooth_influence, per mesh: eq 13 applies K_sigma to
  sigma_a, which already holds K_delta (eq 11), so the root peak is K_sigma K_delta times the smooth stress.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar, Mapping

import numpy as np

from strainwave.errors import InputError, StageError
from strainwave.fea.assembly import Lame
from strainwave.fea.fields import field_info, write_solid_fields
from strainwave.fea.meshing import MeshingFailed
from strainwave.fea.refinement import DEFAULT_RATIO, refinement_sizes
from strainwave.fea.result import Load, StudyResult, Support
from strainwave.fea.ring_loads import ArcLoad
from strainwave.fea.ring_plane import RingGeometry, solve_ring_section
from strainwave.fea.skeleton import MeshSolve, Series, SeriesPlan, StudyVariant, check_variant, run_variant

STUDY = "ring-compression"
SOLID_LAYERS = (4, 3, 2)    # 3D: P2 tets through the thickness, fine first (ratios 1.33, 1.5 > 1.3)
# Force-case values scaled to delta_CD = 2 W0 (``_scaled``), per refinement.
SCALED = ("force_for_W0_N", "sigma_B_outer_MPa", "sigma_B_inner_MPa", "sigma_D_outer_MPa", "sigma_D_inner_MPa",
          "outer_B_MPa", "outer_D_MPa", "root_B_MPa", "root_D_MPa")
EWG_STRESSES = (("ewg_sigma_B_outer_MPa", 0, "B"), ("ewg_sigma_B_inner_MPa", 1, "B"),
                ("ewg_sigma_D_outer_MPa", 0, "D"), ("ewg_sigma_D_inner_MPa", 1, "D"))


def ring_geometry(params) -> RingGeometry:
    """Rim radii from seed 003, eq 1: root circle 0.5 d_R + h_fR, r_m = root + delta/2, outer = root + delta."""
    e = params.ewg_drive
    r_root = 0.5 * e.module_mm * e.flexspline_teeth + e.dedendum_coefficient * e.module_mm
    return RingGeometry(r_root, r_root + e.rim_thickness_mm, r_root + 0.5 * e.rim_thickness_mm, e.face_width_mm)


def contact_load(geo: RingGeometry, force_N: float) -> ArcLoad:
    """Each force spread over an arc of half-width delta/2 at the outer surface (a roller's contact is
    narrower still; delta/2 keeps the arc resolvable and moves M_D by only ~pi c/(4 r), see meta)."""
    return ArcLoad(force_N, 0.5 * geo.thickness_mm / geo.r_outer_mm, geo.r_outer_mm, geo.width_mm)


def section_face(params, *, teeth: bool):
    """The ring's 2D cross-section from geometry/ (``Part.section``)."""
    from strainwave.geometry.parts import build_part
    return build_part("ewg-flexspline-ring", params, teeth=teeth).section


def mesh_sizes_mm(geo: RingGeometry, mesh_size_mm: float | None, quick: bool) -> tuple[float, float, float]:
    """Fine, medium, coarse. Default fine size delta/4 (delta/1.5 quick): a fibre stress sampled at h = delta/4
    is within 0.12 % of Winkler-Bach (0.67 % at delta/2), delta_CD within 1e-5 already at delta/2."""
    fine = mesh_size_mm if mesh_size_mm else geo.thickness_mm / (1.5 if quick else 4.0)
    return refinement_sizes(fine, DEFAULT_RATIO)


def _scaled(sol, w0: float) -> dict[str, float]:
    """Force-case values scaled to delta_CD = 2 W0 (linear elasticity)."""
    k = 2.0 * w0 / sol.mid.delta_cd_mm
    return {"force_for_W0_N": sol.force_N * k,
            "sigma_B_outer_MPa": sol.sigma_B[0] * k, "sigma_B_inner_MPa": sol.sigma_B[1] * k,
            "sigma_D_outer_MPa": sol.sigma_D[0] * k, "sigma_D_inner_MPa": sol.sigma_D[1] * k,
            "outer_B_MPa": sol.outer_B_MPa * k, "outer_D_MPa": sol.outer_D_MPa * k,
            "root_B_MPa": sol.root_B_MPa * k, "root_D_MPa": sol.root_D_MPa * k}


@dataclass(frozen=True)
class RingCompression(StudyVariant):
    """The skeleton's hooks for the ring: three series, the smooth and the toothed 2D section (force and EWG
    cases on each mesh) and the smooth 3D solid (layers through the thickness)."""

    study: ClassVar[str] = STUDY
    elements_per_cell: ClassVar[float] = 0.54
    cpu_s_per_element: ClassVar[tuple[float, float]] = (7.2e-4, 4.1e-3)   # full, --quick: validate's schedule (decision 049)
    plane: ClassVar[bool] = True
    teeth_key: ClassVar[str] = "ewg_drive.flexspline_teeth"
    rated_load: ClassVar[str] = "strainwave.analytic.rated_load:rated_ewg_force"
    stress_field_suffix: ClassVar[str] = "_toothed"     # the root stress a designer wants
    report_component: ClassVar[str] = "ring"
    title: ClassVar[str] = "EWG flexspline ring"
    element_text: ClassVar[str] = ("P{order} triangles (curved), 2D plane stress, thickness = face width B; 3D check "
                                   "on curved P2 tetrahedra")
    # u_y = 0 at A and B, u_x = 0 at D; the EWG's two strips
    image_marks: ClassVar[tuple] = (("A", "B", "D"), "contact", "W0")
    validate_label: ClassVar[str] = "ring"
    params: object
    order: int
    force_N: float           # the diametral force F of the force case
    w0_mm: float             # the prescribed mid-layer deformation W0 of the EWG case and of every ratio
    sizes_mm: tuple[float, float, float]          # toothed series
    smooth_sizes_mm: tuple[float, float, float]   # smooth series

    def __post_init__(self):
        check_variant(STUDY, order=self.order, sizes_mm=self.sizes_mm + self.smooth_sizes_mm, force_N=self.force_N,
                      w0_mm=self.w0_mm)

    @classmethod
    def default_size_mm(cls, params, quick: bool) -> float:
        return mesh_sizes_mm(ring_geometry(params), None, quick)[0]

    @classmethod
    def volume_and_wall(cls, params) -> tuple[float, float]:
        e = params.ewg_drive   # the plane section (toothed rim), per mm of depth
        r_in = 0.5 * e.module_mm * e.flexspline_teeth
        r_out = r_in + e.dedendum_coefficient * e.module_mm + e.rim_thickness_mm + 2.25 * e.module_mm
        return math.pi * (r_out ** 2 - r_in ** 2), e.rim_thickness_mm

    @classmethod
    def dimensions(cls, params) -> tuple[tuple[str, str], ...]:
        e = params.ewg_drive
        return (("teeth Z_R, tooth difference dZ", f"{e.flexspline_teeth}, {e.tooth_difference}"),
                ("module m", f"{e.module_mm:g} mm"), ("reference diameter d_R", f"{e.reference_diameter_mm:g} mm"),
                ("rim thickness delta", f"{e.rim_thickness_mm:.4g} mm"), ("face width B", f"{e.face_width_mm:g} mm"),
                ("root fillet rho_f", f"{e.root_fillet_coefficient:g} m"))

    @classmethod
    def image_zoom_mm(cls, params) -> float:
        return 2.0 * params.ewg_drive.module_mm     # the whole ring hides its thin rim: 4 modules wide

    @property
    def geometry(self) -> RingGeometry:
        return ring_geometry(self.params)

    @property
    def arc_load(self) -> ArcLoad:
        return contact_load(self.geometry, self.force_N)

    def build(self):
        return {"smooth": section_face(self.params, teeth=False), "toothed": section_face(self.params, teeth=True)}

    def series(self) -> tuple[SeriesPlan, ...]:
        return (SeriesPlan("smooth", self.smooth_sizes_mm), SeriesPlan("toothed", self.sizes_mm),
                SeriesPlan("solid_3d", SOLID_LAYERS))

    def solve(self, faces, series, refinement, k, keep_fields, progress) -> MeshSolve:
        mat = self.params.material
        t0 = time.perf_counter()
        if series == "solid_3d":
            from strainwave.fea.ring_solid import solve_ring_solid
            progress(f"{STUDY}: smooth ring, 3D solid, {refinement:g} P2 tets through the thickness")
            s = solve_ring_solid(self.geometry, self.arc_load, Lame.from_young(mat.youngs_modulus_MPa, mat.poisson_ratio),
                                 n_radial=int(refinement))
            return MeshSolve(s.h_mm, {"delta_cd_3d_mm": s.delta_cd_mm, "delta_ab_3d_mm": s.delta_ab_mm,
                                      "delta_cd_midplane_mm": s.delta_cd_midplane_mm,
                                      "delta_cd_edge_mm": s.delta_cd_edge_mm},
                             s.mesh, {"solid_3d": time.perf_counter() - t0}, s.solver,
                             {"timings_s": s.timings_s})
        progress(f"{STUDY}: {series} ring, 2D plane stress, h = {refinement:.3g} mm")
        lame = Lame.from_young(mat.youngs_modulus_MPa, mat.poisson_ratio, plane_stress=True)
        try:
            sol = solve_ring_section(faces[series], self.geometry, self.arc_load, lame, size_mm=refinement,
                                     order=self.order, ewg_w0_mm=self.w0_mm,
                                     pitch_rad=2.0 * np.pi / self.params.ewg_drive.flexspline_teeth,
                                     keep_fields=keep_fields)
        except MeshingFailed as exc:
            raise StageError("mesh", STUDY, f"{series} ring section, h = {refinement:g} mm: {exc}") from exc
        force, ewg = sol["force"], sol["ewg"]
        values = dict(_scaled(force, self.w0_mm), delta_cd_mm=force.mid.delta_cd_mm,
                      delta_ab_mm=force.mid.delta_ab_mm, ewg_force_N=ewg.force_N,
                      symmetry_uy_C_plus_D_mm=float(force.mid.u_C_mm[1] + force.mid.u_D_mm[1]),
                      ewg_mid_layer_W0_mm=float(ewg.mid.delta_cd_mm / 2))
        for key, idx, sec in EWG_STRESSES:
            values[key] = (ewg.sigma_B if sec == "B" else ewg.sigma_D)[idx]
        return MeshSolve(refinement, values, force.mesh.quality, {f"{series}_2d": time.perf_counter() - t0},
                         force.solver, {"force": force} if keep_fields else {})

    def quantities(self, series: Mapping[str, Series]) -> dict:
        smooth, toothed, solid = series["smooth"], series["toothed"], series["solid_3d"]
        # smooth-ring quantities converge with the smooth meshes; toothed/smooth ratios with the toothed ones,
        # refinement k with refinement k
        q = {name: smooth.converged(name, "mm") for name in ("delta_cd_mm", "delta_ab_mm")}
        q["force_for_W0_N"] = smooth.converged("force_for_W0_N", "N")
        for name in ("sigma_B_outer_MPa", "sigma_B_inner_MPa", "sigma_D_outer_MPa", "sigma_D_inner_MPa"):
            q[name] = smooth.converged(name, "MPa")
        sc, tc = smooth.solves, toothed.solves
        kd = [(t.values["outer_D_MPa"] - t.values["outer_B_MPa"]) / (s.values["outer_D_MPa"] - s.values["outer_B_MPa"])
              for t, s in zip(tc, sc)]
        product = [(t.values["root_D_MPa"] - t.values["root_B_MPa"]) / (s.values["root_D_MPa"] - s.values["root_B_MPa"])
                   for t, s in zip(tc, sc)]
        q["tooth_influence"] = toothed.converged("tooth_influence", "1", kd)
        q["root_stress_factor"] = toothed.converged("root_stress_factor", "1", product)
        q["stress_concentration"] = toothed.converged("stress_concentration", "1", [p / k for p, k in zip(product, kd)])
        q["ewg_force_N"] = smooth.converged("ewg_force_N", "N")
        for key, _, _ in EWG_STRESSES:
            q[key] = smooth.converged(key, "MPa")
        q["toothed_force_for_W0_N"] = toothed.converged("toothed_force_for_W0_N", "N", toothed.values("force_for_W0_N"))
        q["toothed_ewg_force_N"] = toothed.converged("toothed_ewg_force_N", "N", toothed.values("ewg_force_N"))
        # 3D solid in --quick too: cheap, and the same number in both runs (docs/decisions/011-ring-meshes.md)
        q["delta_cd_3d_mm"] = solid.converged("delta_cd_3d_mm", "mm")
        q["delta_ab_3d_mm"] = solid.converged("delta_ab_3d_mm", "mm")
        return q

    def load(self, parts) -> Load:
        arc = self.arc_load
        return Load("diametral force F", self.force_N, "N", ("contact",),
                    "elliptical pressure normal to the outer surface, over two opposite arcs (the EWG's contact "
                    "strips)",
                    (("half_angle_rad", float(arc.half_angle_rad)), ("radius_mm", float(arc.radius_mm)),
                     ("w0_mm", float(self.w0_mm))))

    def supports(self) -> tuple[Support, ...]:
        return (Support(("A", "B"), "u_y = 0 (outer-surface points on the x axis; no reaction in the symmetric "
                                    "solution)"),
                Support(("D",), "u_x = 0 (outer-surface point on the y axis); C free"))

    def write_fields(self, series: Mapping[str, Series], vtu: Path, load: Load) -> tuple[Path, ...]:
        mat = self.params.material
        lame = Lame.from_young(mat.youngs_modulus_MPa, mat.poisson_ratio, plane_stress=True)
        info = field_info(STUDY, load.describe(), mat)
        return tuple(write_force_field(path, series[name].finest.fields["force"], lame, info)
                     for path, name in zip(vtu_paths(vtu), ("smooth", "toothed")))

    def meta(self, faces, series: Mapping[str, Series]) -> dict:
        """Everything a reader needs to reproduce or interpret the numbers (no stage reads it)."""
        geo, mat, load = self.geometry, self.params.material, self.arc_load
        smooth, toothed, solid = series["smooth"], series["toothed"], series["solid_3d"]
        fs, ft = smooth.finest.values, toothed.finest.values
        nu = mat.poisson_ratio
        return {
            "model": "2D plane stress, whole ring, curved P2 triangles, thickness = face width B",
            "geometry": {"r_root_mm": geo.r_root_mm, "r_outer_mm": geo.r_outer_mm, "r_m_mm": geo.r_m_mm,
                         "rim_thickness_mm": geo.thickness_mm, "width_mm": geo.width_mm,
                         "r_m_over_delta": geo.r_m_mm / geo.thickness_mm,
                         "smooth_equivalent": "rim between root circle and outer circle (seed 003 eq 1); teeth ignored"},
            "material": {"E_MPa": mat.youngs_modulus_MPa, "nu": nu,
                         "G_implied_MPa": mat.implied_shear_modulus_MPa, "G_seed_MPa": mat.shear_modulus_MPa},
            "load": {"half_width_mm": load.half_angle_rad * load.radius_mm, "peak_pressure_MPa": load.peak_pressure_MPa},
            "ewg_case": "rigid flat contact strips (the load arcs) pushed radially by W0 at the outer surface, "
                        "tangential motion free",
            "symmetry_uy_C_plus_D_mm": fs["symmetry_uy_C_plus_D_mm"],
            "ewg_mid_layer_W0_mm": fs["ewg_mid_layer_W0_mm"],
            "tooth_stiffness_ratio": ft["force_for_W0_N"] / fs["force_for_W0_N"],
            "toothed_delta_cd_mm": ft["delta_cd_mm"], "toothed_delta_ab_mm": ft["delta_ab_mm"],
            "per_section_factors": {
                "K_delta_B": ft["outer_B_MPa"] / fs["outer_B_MPa"], "K_delta_D": ft["outer_D_MPa"] / fs["outer_D_MPa"],
                "K_sigma_B": ft["root_B_MPa"] / fs["root_B_MPa"], "K_sigma_D": ft["root_D_MPa"] / fs["root_D_MPa"]},
            "toothed_scaled_to_W0_MPa": {k: ft[k] for k in SCALED if k != "force_for_W0_N"},
            "mesh_sizes_mm": list(self.sizes_mm), "smooth_mesh_sizes_mm": list(self.smooth_sizes_mm),
            "toothed_mesh": toothed.finest.mesh.to_dict(),
            "solid_3d": {
                "model": "one-eighth ring (symmetry x = 0, y = 0, mid-plane), structured curved P2 tets, same arc "
                         "load uniform over the width; delta at r_m averaged over the width (Simpson on P2 nodes)",
                "layers": list(SOLID_LAYERS), "h_mm": list(solid.h_mm), "dofs": [m.mesh.dofs for m in solid.solves],
                "elements": [m.mesh.elements for m in solid.solves],
                "timings_s": [m.fields["timings_s"] for m in solid.solves],
                "ratio_cd_midplane_over_2d": solid.finest.values["delta_cd_midplane_mm"] / fs["delta_cd_mm"],
                "ratio_cd_edge_over_2d": solid.finest.values["delta_cd_edge_mm"] / fs["delta_cd_mm"],
                "plane_strain_bound": 1.0 - nu ** 2,
                "B2_over_r_delta": geo.width_mm ** 2 / (geo.r_m_mm * geo.thickness_mm),
                "solver": solid.finest.solver},
        }


def vtu_paths(vtu) -> tuple[Path, Path]:
    """(smooth, toothed) field files next to ``vtu``: <stem>_smooth.vtu first (the report's mid-layer plot)."""
    v = Path(vtu)
    return v.with_name(f"{v.stem}_smooth.vtu"), v.with_name(f"{v.stem}_toothed.vtu")


def write_force_field(path, sol, lame: Lame, info=None) -> Path:
    """Displacement, von Mises and stress (plane stress, zz = 0) of one 2D force-case solve, as VTU."""
    sk, u = sol.fields
    return write_solid_fields(path, sol.mesh, sk, u, lame, info=info)


def run(params, *, force_N: float, w0_mm: float, mesh_size_mm=None, order=2, crack_depth_mm=None, vtu=None,
        progress=lambda m: None, quick=False) -> StudyResult:
    """The ring at the diametral force ``force_N`` and the prescribed deformation ``w0_mm`` (both from
    ``analytic/study_loads.py`` through the registry). The ring carries no crack."""
    if crack_depth_mm is not None:
        raise InputError("--crack-depth-mm", crack_depth_mm, f"study {STUDY} meshes a ring without a crack; leave it out")
    geo = ring_geometry(params)
    if mesh_size_mm is not None and mesh_size_mm > geo.thickness_mm / 1.5:   # coarser: no node on the contact arcs
        raise InputError("--mesh-size-mm", mesh_size_mm, f"must be <= delta/1.5 = {geo.thickness_mm / 1.5:.3g} mm for "
                                                         f"the ring (the coarsest size the study is checked at)")
    # Always the full run's meshes: cheap, and coarser ones miss the boundary stresses (docs/decisions/011-ring-meshes.md)
    variant = RingCompression(params, order, float(force_N), float(w0_mm), mesh_sizes_mm(geo, mesh_size_mm, quick),
                              mesh_sizes_mm(geo, mesh_size_mm, False))
    return run_variant(variant, vtu=vtu, progress=progress)
