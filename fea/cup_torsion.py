"""Study ``cup-torsion``: torsional flexibility of the flexspline cup, lambda_f, vs seed 000's lambda_f0.

The cup (``geometry``'s "flexspline-cup"; smooth band by default, teeth optional) is clamped at the hub
face ``fixed``; the torque acts on the toothed band ``loaded`` as a uniform tangential shear whose moment
about z is T (solved for a unit shear and rescaled: the problem is linear). Twist = area-weighted mean
rotation of the band, lambda_f = twist / T. Seed 000: lambda_f0 = k_f k_G c_L / (0.1 mu [1 - (1 - 2 c_d)^4]
d1^3), published with 0.1 and the seed's mu; corrected with pi/32; k_G = 0.83 for a cup, k_f = 1 or 0.83.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import ClassVar, Mapping

from strainwave.errors import InputError
from strainwave.fea.assembly import Lame
from strainwave.fea.cup_axisym import section_displacement, section_fine_mm, solve_cup_section
from strainwave.fea.crack_extruded import PlaneGrading, crack_tips_xy, cylinder_map, extruded_patch, plane_patch_mesh
from strainwave.fea.crack_local import RELEASE_RTOL, compliance_from_release, interpolate_p2, local_release, patch_solver
from strainwave.fea.crack_seam import open_crack_for, seam_crack
from strainwave.fea.fields import field_info, write_solid_fields
from strainwave.fea.mesh_data import MeshData
from strainwave.fea.meshing import OPTIMIZE_THRESHOLD
from strainwave.fea.refinement import DEFAULT_RATIO, CrackFrontGrading, crack_flexibility_quantities, refinement_sizes
from strainwave.fea.result import CrackRecord, Load, StudyResult
from strainwave.fea.session import mesh_in_child
from strainwave.fea.skeleton import MeshSolve, Series, SeriesPlan, check_variant, run_variant
from strainwave.fea.static import StaticSolution, solve_static
from strainwave.fea.study_mesh import mesh_for_study
from strainwave.fea.torsion_load import (TorsionVariant, mean_rotation_rad, moment_arm_mm3, torsion_meta,
                           uniform_tangential_traction)

STUDY = "cup-torsion"
UNIT = "rad/(N*mm)"


def default_size_mm(params, quick: bool) -> float:
    """Finest global size: 3 walls (4 with --quick): one P2 element through the wall carries the membrane
    shear of torsion (docs/decisions/012-cup-global-mesh-size.md)."""
    return params.flexspline_cup.wall_thickness_mm * (4.0 if quick else 3.0)


# Tip a/4, no floor, uniform within a: shallow cracks need it (docs/decisions/001-cup-crack-front-grading.md).
CRACK_FRONT = CrackFrontGrading(tip_over_a=0.25, floor_over_h=0.0, near_over_a=1.0, zone_over_a=2.0, grow_over_h=3.0)


# Elements of 7+ walls stay flat: optimising them is wasted time (docs/decisions/012-cup-global-mesh-size.md).
COARSE_OVER_WALL = 7.0
COARSE_OPTIMIZE_THRESHOLD = 0.1


def optimize_threshold(h_mm: float, wall_mm: float) -> float:
    """gmsh's optimisation threshold for a cup mesh of global size ``h_mm`` (see COARSE_OVER_WALL)."""
    return COARSE_OPTIMIZE_THRESHOLD if h_mm >= COARSE_OVER_WALL * wall_mm else OPTIMIZE_THRESHOLD


def solve_mesh(md, params, *, progress=lambda m: None) -> tuple[float, StaticSolution, float]:
    """(lambda_f, solution for unit shear, applied torque of the unit shear) on a given mesh."""
    mat = params.material
    sol = solve_static(md, Lame.from_young(mat.youngs_modulus_MPa, mat.poisson_ratio), fixed={"fixed": 0.0},
                       tractions={"loaded": uniform_tangential_traction(1.0, 1.0)}, study=STUDY, progress=progress,
                       # thin walls: nearly 2D graph, cheap to factor (docs/decisions/003-direct-vs-multigrid-solver.md)
                       method="direct")
    torque = moment_arm_mm3(sol, "loaded")     # moment of the unit tangential shear
    return mean_rotation_rad(sol, "loaded") / torque, sol, torque


def _build(params, depth_mm, teeth):
    from strainwave.geometry.part import CrackModel
    from strainwave.geometry.parts import build_part
    # a crack is the zero-width seam (FEA on one mesh, cracked and uncracked); the CAD slot is for STEP
    model = CrackModel.SEAM if depth_mm is not None else CrackModel.SLOT
    return build_part("flexspline-cup", params, crack_depth_mm=depth_mm, teeth=teeth, crack_model=model)


FLEX = "flexibility_rad_per_Nmm"
CRACKED = "cracked_flexibility_rad_per_Nmm"
DELTA = "delta_flexibility_rad_per_Nmm"
# How the crack compliance is solved: "seam" cracks the whole cup's mesh (refined at the front, solved
# closed and opened); "global-local" solves the cup uncracked and the crack in a patch (crack_local)
SEAM, GLOBAL_LOCAL = "seam", "global-local"
CRACK_METHODS = (SEAM, GLOBAL_LOCAL)
# global-local meets the crack-compliance rule on both gears at a quarter of the CPU; lambda_f of the smooth
# cup comes from its exact (r, z) section, not the 3D global mesh (docs/decisions/031)
DEFAULT_CRACK_METHOD = GLOBAL_LOCAL
FLEX_3D = "flexibility_3d_rad_per_Nmm"     # the 3D mesh's own uncracked lambda_f, reported beside the section's
# The local patch: half size L = PATCH_HALF_OVER_A a (fixed grip on its cut faces costs O((a/L)^2) of the
# released energy: 1.3 (a/L)^2, docs/decisions/025), meshed as a tip-graded plane extruded through the wall
# (crack_extruded): quarter-point tips of a/4 on the finest mesh, rings growing by 0.4 of the distance, up to
# 10 layers through the wall, the fewest whose face layer is no thicker than the tip (docs/decisions/044)
PATCH_HALF_OVER_A = 32.0
# the section is solved for a unit torque (shaft_axisym.solve_torsion_section's default)
SECTION_TORQUE_NMM = 1.0
# the patch's stress read this fraction inside each element: a quarter-point tip's map is singular at its node
QUARTER_POINT_INSET = 1e-3
# Nodes within half a wall of the hub's sharp corner are its singular zone: outside it the section's three meshes
# agree to 0.2 % at the rated torque, inside the stress grows as h^(-1/3) (docs/decisions/052).
CORNER_ZONE_OVER_WALL = 0.5
LOCAL_GRADING = PlaneGrading(tip_over_a=0.25, growth=0.4, far_over_a=8.0, layers=10, quarter_point=True,
                             face_layer_to_tip=True)


def local_patch_mesh(part, a_mm: float, f: float, grading: PlaneGrading = LOCAL_GRADING) -> tuple[MeshData, float]:
    """(mesh, seconds) of the crack's local patch (+-PATCH_HALF_OVER_A a of the wall around the seam crack of
    the SEAM cup ``part``) at refinement factor ``f`` (1: finest)."""
    from strainwave.geometry.flexspline_cup import check_crack_patch
    half = PATCH_HALF_OVER_A * a_mm
    check_crack_patch(part, half)
    m, t0 = part.meta, time.perf_counter()
    tip, far, growth, layers = grading.sizes(a_mm, f, m["wall_mm"])
    tips = crack_tips_xy(a_mm, m["crack_angle_deg"])
    plane = mesh_in_child(lambda model: plane_patch_mesh(model, half, tips, tip_mm=tip, far_mm=far, growth=growth),
                          what=f"{STUDY} crack patch")
    centre = m["crack_centre_mm"]
    to_xyz = cylinder_map(m["mid_radius_mm"], math.atan2(centre[1], centre[0]), m["crack_z_mm"])
    md = extruded_patch(plane, m["wall_mm"], layers, to_xyz, quarter_point=grading.quarter_point, h_mm=far)
    return md, time.perf_counter() - t0


@dataclass(frozen=True)
class CupTorsion(TorsionVariant):
    """The skeleton's hooks for the cup: one 3D series; with a crack each mesh carries the seam and is
    solved closed and opened. The load is a unit shear, rescaled (linear problem)."""

    study: ClassVar[str] = STUDY
    load_distribution: ClassVar[str] = "uniform tangential shear on the toothed band, moment T"
    clamped_face: ClassVar[str] = "hub face"
    sweep_at_quick_size: ClassVar[bool] = True   # the crack delta, closed and opened on one mesh
    crack_field_alone: ClassVar[bool] = True     # the patch's own field, without solving the 3D cup
    shares_cache: ClassVar[bool] = True          # the section, the same in every cup case of a gear
    elements_per_cell: ClassVar[float] = 13.3
    cpu_s_per_element: ClassVar[tuple[float, float]] = (3.2e-4, 6.2e-4)   # full, --quick: validate's schedule (decision 049)
    default_size_mm = staticmethod(default_size_mm)
    report_component: ClassVar[str] = "cup"
    title: ClassVar[str] = "flexspline cup"
    element_text: ClassVar[str] = ("P{order} tetrahedra (curved, isoparametric); lambda_f of the toothless cup on its "
                                   "axisymmetric (r, z) section of P2 triangles; the crack as a seam or in a global-local patch")
    teeth: bool
    crack_method: str = DEFAULT_CRACK_METHOD
    solid_field: bool = True        # the 3D cup's own field for the stress picture; see ``run``
    section_cache: Path | None = None   # where the section's solutions are kept for the other cup cases

    @classmethod
    def volume_and_wall(cls, params) -> tuple[float, float]:
        c = params.flexspline_cup
        tube = math.pi * c.pitch_diameter_mm * c.wall_thickness_mm * c.length_mm
        diaphragm = math.pi / 4 * c.pitch_diameter_mm ** 2 * c.wall_thickness_mm
        return tube + diaphragm, c.wall_thickness_mm

    @classmethod
    def deepest_crack_mm(cls, params) -> float:
        return 0.5 * params.flexspline_cup.wall_thickness_mm

    @classmethod
    def singular_edges_mm(cls, params) -> tuple[tuple[float, float, float], ...]:
        from strainwave.geometry.flexspline_cup import reentrant_corners_mm
        zone = CORNER_ZONE_OVER_WALL * params.flexspline_cup.wall_thickness_mm
        return tuple((r, z, zone) for r, z in reentrant_corners_mm(params))

    @classmethod
    def dimensions(cls, params) -> tuple[tuple[str, str], ...]:
        c = params.flexspline_cup
        return (("pitch diameter d1", f"{c.pitch_diameter_mm:g} mm"), ("wall delta", f"{c.wall_thickness_mm:g} mm"),
                ("length L", f"{c.length_mm:g} mm"), ("shape", f"{c.shape}{', cup' if c.cup else ''}"),
                ("teeth x module", f"{c.teeth} x {c.module_mm:g} mm"))

    def __post_init__(self):
        if self.crack_method not in CRACK_METHODS:
            raise ValueError(f"{STUDY}: crack_method must be one of {CRACK_METHODS}, got {self.crack_method!r}")
        check_variant(STUDY, order=self.order, sizes_mm=(self.h_fine_mm,), crack_depth_mm=self.crack_depth_mm,
                      ratio=self.ratio)

    def build(self):
        # the seam part IS the uncracked cup when solved closed
        return _build(self.params, self.crack_depth_mm, self.teeth)

    @property
    def patch_on_section(self) -> bool:
        """The crack's patch driven by the exact axisymmetric field of the section (a smooth cup, global-local)."""
        return self.crack_depth_mm is not None and self.crack_method == GLOBAL_LOCAL and not self.teeth

    def series(self) -> tuple[SeriesPlan, ...]:
        plans = ()
        if not self.patch_on_section:   # with a patch on the section, no quantity needs the 3D cup
            plans += (SeriesPlan("solid", refinement_sizes(self.h_fine_mm, self.ratio)),)
        if not self.teeth:      # the toothless cup is axisymmetric: lambda_f on its (r, z) section
            plans += (SeriesPlan("section", refinement_sizes(section_fine_mm(self.params, False), self.ratio)),)
        return plans

    def solve(self, part, series, h_mm, k, keep_fields, progress) -> MeshSolve:
        if series == "section":
            return self._solve_section(part, h_mm, k, keep_fields, progress)
        if self.crack_depth_mm is not None and self.crack_method == GLOBAL_LOCAL:
            return self._solve_global_local(part, h_mm, keep_fields, progress)
        cracked = self.crack_depth_mm is not None
        refine = (CRACK_FRONT.refine(part.crack_front_mm, h_mm, self.h_fine_mm, self.crack_depth_mm),) if cracked else ()
        md, t_mesh = mesh_for_study(part, study=STUDY, h_mm=h_mm, order=self.order, refine=refine, progress=progress,
                                    optimize_threshold=optimize_threshold(
                                        h_mm, self.params.flexspline_cup.wall_thickness_mm))
        # with a crack: the same mesh solved as is (embedded surface closed) and opened
        meshes = [(FLEX, md)] + ([(CRACKED, open_crack_for(md, STUDY))] if cracked else [])
        values, sols = {}, []
        for name, mdk in meshes:
            values[name], sol, torque = solve_mesh(mdk, self.params, progress=progress)
            sols.append(sol)
        timings = {"mesh": t_mesh, "assembly": sum(s.timings_s["assembly"] for s in sols),
                   "solve": sum(s.timings_s["solve"] for s in sols)}
        last = sols[-1]
        return MeshSolve(h_mm, values, last.md.quality, timings, last.solver.to_dict(),
                         {"solution": last, "unit_shear_torque_Nmm": torque} if keep_fields else {})

    def _solve_section(self, part, h_mm, k, keep_fields, progress) -> MeshSolve:
        """lambda_f on the section; with a crack (``patch_on_section``) its patch on refinement k, held at the
        section's exact 3D field for a unit torque; with the fields kept, the 3D cup's own too (``solid_field``)."""
        solved = solve_cup_section(self.params, h_mm, keep_fields=self.patch_on_section, progress=progress,
                                   cache_dir=self.section_cache)
        if not self.patch_on_section:
            return solved
        a, mat = self.crack_depth_mm, self.params.material
        md_loc, t_loc = local_patch_mesh(part, a, self.ratio ** k)
        solver = patch_solver(2 * PATCH_HALF_OVER_A * a, self.params.flexspline_cup.wall_thickness_mm)
        # the kept field's stress moves by 1e-3 of its peak at RELEASE_RTOL: a picture, read by no check
        local = local_release(md_loc, Lame.from_young(mat.youngs_modulus_MPa, mat.poisson_ratio),
                              section_displacement(solved.fields["section"]), study=STUDY, method=solver,
                              keep_field=keep_fields, rtol=RELEASE_RTOL)
        delta = compliance_from_release(local.released_Nmm, SECTION_TORQUE_NMM)
        progress(f"{STUDY}: local patch {local.dofs} dofs, released {local.released_Nmm:.4g} N mm")
        flex = solved.values[FLEX]
        values = dict(solved.values, **{CRACKED: flex + delta, DELTA: delta, "local_dofs": float(local.dofs)})
        timings = dict(solved.timings_s, mesh_patch=t_loc, solve_patch=local.solve_s)
        fields = {"patch": local.field, "patch_torque_Nmm": SECTION_TORQUE_NMM} if keep_fields else {}
        if keep_fields and self.solid_field:
            solid = self._solve_solid(part, self.h_fine_mm, True, progress)
            fields.update(solid.fields)
            for key, seconds in solid.timings_s.items():
                timings[key] = timings.get(key, 0.0) + seconds
        return MeshSolve(h_mm, values, solved.mesh, timings, solved.solver, fields)

    def _uncracked_solid(self, part, h_mm, progress) -> tuple[MeshData, float, float, StaticSolution, float]:
        """(mesh, meshing s, lambda_f, solution, unit-shear torque) of the uncracked 3D cup at size h."""
        md, t_mesh = mesh_for_study(part, study=STUDY, h_mm=h_mm, order=self.order, progress=progress,
                                    optimize_threshold=optimize_threshold(
                                        h_mm, self.params.flexspline_cup.wall_thickness_mm))
        return (md, t_mesh, *solve_mesh(md, self.params, progress=progress))

    def _solve_solid(self, part, h_mm, keep_fields, progress) -> MeshSolve:
        """The uncracked 3D cup on the mesh of size h, for its field: one mesh, as no check reads its lambda_f
        (docs/decisions/051)."""
        md, t_mesh, flex, sol, torque = self._uncracked_solid(part, h_mm, progress)
        timings = {"mesh": t_mesh, "assembly": sol.timings_s["assembly"], "solve": sol.timings_s["solve"]}
        return MeshSolve(h_mm, {FLEX: flex}, md.quality, timings, sol.solver.to_dict(),
                         {"solution": sol, "unit_shear_torque_Nmm": torque} if keep_fields else {})

    def _solve_global_local(self, part, h_mm, keep_fields, progress) -> MeshSolve:
        """The uncracked cup on the mesh of size h (no crack-front refinement), then the crack in its local
        patch (``local_patch_mesh``: sizes times h / h_fine, layers over it) driven by that solution."""
        md, t_mesh, flex, sol, torque = self._uncracked_solid(part, h_mm, progress)
        a = self.crack_depth_mm
        md_loc, t_loc = local_patch_mesh(part, a, h_mm / self.h_fine_mm)
        global_u = partial(interpolate_p2, sol.sk.doflocs, sol.sk.element_dofs, sol.u)
        solver = patch_solver(2 * PATCH_HALF_OVER_A * a, self.params.flexspline_cup.wall_thickness_mm)
        local = local_release(md_loc, sol.lame, global_u, study=STUDY, method=solver, keep_field=keep_fields,
                              rtol=RELEASE_RTOL)
        delta = compliance_from_release(local.released_Nmm, torque)
        progress(f"{STUDY}: local patch {local.dofs} dofs, released {local.released_Nmm:.4g} N mm")
        values = {FLEX: flex, CRACKED: flex + delta, DELTA: delta, "local_dofs": float(local.dofs)}
        timings = {"mesh": t_mesh + t_loc, "assembly": sol.timings_s["assembly"],
                   "solve": sol.timings_s["solve"] + local.solve_s}
        return MeshSolve(h_mm, values, md.quality, timings, sol.solver.to_dict(),
                         {"solution": sol, "unit_shear_torque_Nmm": torque, "patch": local.field,
                          "patch_torque_Nmm": torque} if keep_fields else {})

    def quantities(self, series: Mapping[str, Series]) -> dict:
        if self.patch_on_section:
            sec = series["section"]
            return crack_flexibility_quantities(sec.h_mm, sec.values(FLEX), sec.values(CRACKED), UNIT,
                                                delta=sec.values(DELTA))
        s = series["solid"]
        cracked = self.crack_depth_mm is not None
        delta = s.values(DELTA) if cracked and self.crack_method == GLOBAL_LOCAL else None
        out = crack_flexibility_quantities(s.h_mm, s.values(FLEX), s.values(CRACKED) if cracked else None, UNIT,
                                           delta=delta)
        if "section" not in series:
            return out
        section = series["section"]
        lam = section.values(FLEX)
        out[FLEX_3D] = s.converged(FLEX_3D, UNIT, s.values(FLEX))
        out[FLEX] = section.converged(FLEX, UNIT)
        if cracked:
            # the section's lambda_f plus the crack's delta, refinement k with refinement k
            d = delta if delta is not None else [c - u for c, u in zip(s.values(CRACKED), s.values(FLEX))]
            out[CRACKED] = s.converged(CRACKED, UNIT, [l0 + dk for l0, dk in zip(lam, d)])
        return out

    def crack(self, part) -> CrackRecord | None:
        if self.crack_depth_mm is None:
            return None
        what = "the seed's through-wall 45 deg crack in the tube"
        if self.crack_method == GLOBAL_LOCAL:
            return CrackRecord(self.crack_depth_mm, f"global-local ({what}): the cup uncracked, the crack in a wall "
                               f"patch of +-{PATCH_HALF_OVER_A:g} a (tip-graded, extruded through the wall) held at "
                               "the cup's displacement, opened and loaded on its faces by the uncracked field's forces (Bueckner)",
                               part.meta.get("crack_z_mm"))
        return seam_crack(self.crack_depth_mm, part, what)

    def write_fields(self, series: Mapping[str, Series], vtu: Path, load: Load) -> tuple[Path, ...]:
        """The 3D cup's field, and with a patch the crack's own: the patch opened (global field plus
        Bueckner's correction), both at the design torque."""
        info = field_info(STUDY, load.describe(), self.params.material)
        T = self.params.gear.output_torque_Nmm
        written = ()
        solid = [s.finest.fields for s in series.values() if "solution" in s.finest.fields]
        if solid:
            sol = solid[0]["solution"]
            written += (write_solid_fields(vtu, sol.md, sol.sk, sol.u * (T / solid[0]["unit_shear_torque_Nmm"]),
                                           sol.lame, info=info),)
        with_patch = [s.finest.fields for s in series.values() if s.finest.fields.get("patch")]
        if not with_patch:
            return written
        md_loc, sk_loc, u_loc = with_patch[0]["patch"]
        mat = self.params.material
        cracked = Path(vtu).with_name(Path(vtu).stem + "_cracked.vtu")
        return written + (write_solid_fields(cracked, md_loc, sk_loc, u_loc * (T / with_patch[0]["patch_torque_Nmm"]),
                                             Lame.from_young(mat.youngs_modulus_MPa, mat.poisson_ratio), info=info,
                                             inset=QUARTER_POINT_INSET),)

    def meta(self, part, series: Mapping[str, Series]) -> dict:
        sizes = (series["solid"] if "solid" in series else series["section"]).h_mm
        out = dict(torsion_meta(self.params, self.order, self.ratio, sizes), teeth=self.teeth)
        if self.crack_depth_mm is not None:
            out["crack_part"] = {k: v for k, v in part.meta.items() if isinstance(v, (int, float, str))}
        if "section" in series:
            s = series["section"]
            out["axisymmetric"] = {"section_sizes_mm": list(s.h_mm), "section_nodes": [m.values["nodes"] for m in s.solves]}
        return out


def run(params, *, mesh_size_mm=None, order=2, crack_depth_mm=None, vtu=None, progress=lambda m: None,
        quick=False, teeth: bool = False, ratio: float = DEFAULT_RATIO,
        crack_method: str | None = None, crack_field_only: bool = False, cache_dir: Path | None = None) -> StudyResult:
    """lambda_f on three meshes (GCI); with a crack delta lambda_f from the crack's local patch ("global-local",
    the default: crack_local, crack_extruded; a smooth cup's patch held at its section's exact field, the 3D
    cup solved on the finest mesh only, for its field) or cracked - uncracked on each whole-cup mesh
    (``crack_method`` "seam").
    ``crack_field_only``: with a patch, ``vtu`` gets the opened patch's field alone (the 3D cup is not solved).
    ``cache_dir``: the section's solutions are kept there and read back (``cup_axisym.solve_cup_section``)."""
    fc = params.flexspline_cup
    h = mesh_size_mm or default_size_mm(params, quick)
    if h >= fc.length_mm / 4:
        raise InputError("--mesh-size-mm", h, f"must be < L/4 = {fc.length_mm / 4:g} mm for the cup")
    variant = CupTorsion(params, order, h, ratio, crack_depth_mm, teeth, crack_method or DEFAULT_CRACK_METHOD,
                         solid_field=vtu is not None and not crack_field_only, section_cache=cache_dir)
    return run_variant(variant, vtu=vtu, progress=progress)
