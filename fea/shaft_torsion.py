"""Study ``shaft-torsion``: flexibility of the hollow output shaft, uncracked and with its crack.

Load (seed 000's output shaft): end z = 0 (``fixed``) clamped, torque T on z = L (``loaded``) as the
Saint-Venant shear traction tau = T r / J (tangential). For a circular section that is the exact
solution, and the clamped end is compatible with it (u = theta(z) e_z x r vanishes at z = 0), so the
uncracked FEA must reproduce lambda = 32 L / (pi G (d^4 - d_i^4)) with G = E / (2 (1 + nu)).
Twist = area-weighted mean rotation (x u_y - y u_x) / r^2 of the loaded face; lambda = twist / T.
A crack is a seam (geometry's CrackModel.SEAM): each refinement meshes the shaft once with the crack
surface embedded and solves it closed (uncracked) and opened (``crack_seam.open_crack``), so delta lambda
is a difference on one mesh, free of the far field's mesh-to-mesh noise.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, ClassVar, Mapping, Sequence

from strainwave.errors import InputError
from strainwave.fea.assembly import Lame
from strainwave.fea.crack_seam import open_crack_for, seam_crack
from strainwave.fea.fields import field_info, write_solid_fields
from strainwave.fea.meshing import Refine
from strainwave.fea.refinement import (CRACK_FORMAL_ORDER, DEFAULT_RATIO, CrackFrontGrading, crack_flexibility_quantities,
                         refinement_sizes)
from strainwave.fea.result import CrackRecord, Load, StudyResult
from strainwave.fea.skeleton import MeshSolve, Series, SeriesPlan, check_variant, run_variant
from strainwave.fea.static import StaticSolution, solve_static
from strainwave.fea.study_mesh import mesh_for_study
from strainwave.fea.torsion_load import TorsionVariant, mean_rotation_rad, saint_venant_traction, torsion_meta

STUDY = "shaft-torsion"
UNIT = "rad/(N*mm)"


def default_size_mm(params, quick: bool) -> float:
    """Finest global size: wall / 1.5 (wall / 1 with --quick); curved P2 is exact to ~1e-5 there."""
    return params.output_shaft.wall_mm / (1.0 if quick else 1.5)


# Tip a/6, floor h/32, narrow zone: coarser tips hide the tip error (docs/decisions/002-shaft-crack-front-grading.md).
CRACK_FRONT = CrackFrontGrading(tip_over_a=1.0 / 6.0, floor_over_h=1.0 / 32.0, near_over_a=0.5, zone_over_a=3.0,
                                grow_over_h=1.0)


def solve_mesh(md, params, *, progress: Callable[[str], None] = lambda m: None) -> tuple[float, StaticSolution]:
    """Solve the torsion case on a mesh; return (lambda, solution)."""
    sh, mat = params.output_shaft, params.material
    T = params.gear.output_torque_Nmm
    J = math.pi / 32.0 * (sh.outer_diameter_mm ** 4 - sh.inner_diameter_mm ** 4)
    sol = solve_static(md, Lame.from_young(mat.youngs_modulus_MPa, mat.poisson_ratio), fixed={"fixed": 0.0},
                       tractions={"loaded": saint_venant_traction(T, J)}, study=STUDY, progress=progress)
    return mean_rotation_rad(sol, "loaded") / T, sol


def solve_seam(part, params, *, h_mm: float, order: int, refine: Sequence[Refine] = (),
               progress: Callable[[str], None] = lambda m: None
               ) -> tuple[float, float, StaticSolution, StaticSolution, float]:
    """Mesh the seam part ONCE, solve it uncracked and with the crack opened (same mesh):
    (lambda uncracked, lambda cracked, uncracked solution, cracked solution, mesh time)."""
    md, t_mesh = mesh_for_study(part, study=STUDY, h_mm=h_mm, order=order, refine=refine, progress=progress)
    lam0, sol0 = solve_mesh(md, params, progress=progress)
    lam1, sol1 = solve_mesh(open_crack_for(md, STUDY), params, progress=progress)
    return lam0, lam1, sol0, sol1, t_mesh


def _build(params, depth_mm, crack_model=None):
    from strainwave.geometry.part import CrackModel
    from strainwave.geometry.parts import build_part
    return build_part("output-shaft", params, crack_depth_mm=depth_mm, crack_model=crack_model or CrackModel.SLOT)


def _build_seam(params, depth_mm):
    from strainwave.geometry.part import CrackModel
    return _build(params, depth_mm, CrackModel.SEAM)


def crack_model_for(params, crack_model: str) -> str:
    """"auto": the exact axisymmetric section for a full circumferential crack, the 3D seam otherwise."""
    if crack_model not in ("auto", "axisymmetric", "seam"):
        raise InputError("crack_model", crack_model, "must be auto, axisymmetric or seam")
    full = params.crack_geometry.shaft_arc_deg >= 360.0
    if crack_model == "axisymmetric" and not full:
        raise InputError("crack_geometry.shaft_arc_deg", params.crack_geometry.shaft_arc_deg,
                         "must be 360 for the axisymmetric crack model (use the 3D seam)")
    return crack_model if crack_model != "auto" else ("axisymmetric" if full else "seam")


FLEX = "flexibility_rad_per_Nmm"
CRACKED = "cracked_flexibility_rad_per_Nmm"
DELTA = "delta_flexibility_rad_per_Nmm"


def _timings(sols, t_mesh: float) -> dict[str, float]:
    return {"mesh": t_mesh, "assembly": sum(s.timings_s["assembly"] for s in sols),
            "solve": sum(s.timings_s["solve"] for s in sols)}


@dataclass(frozen=True)
class ShaftTorsion(TorsionVariant):
    """The skeleton's hooks for the shaft: the 3D series (uncracked, or the seam closed and opened on each
    mesh) and, for a full circumferential crack, the (r, z) section series of the crack's added flexibility."""

    study: ClassVar[str] = STUDY
    load_distribution: ClassVar[str] = "Saint-Venant shear traction tau = T r / J (tangential)"
    clamped_face: ClassVar[str] = "end face z = 0"
    sweep_at_quick_size: ClassVar[bool] = True   # the crack delta, closed and opened on one mesh
    elements_per_cell: ClassVar[float] = 4.7
    cpu_s_per_element: ClassVar[tuple[float, float]] = (1.6e-3, 1.5e-3)   # full, --quick: validate's schedule (decision 049)
    default_size_mm = staticmethod(default_size_mm)
    report_component: ClassVar[str] = "shaft"
    title: ClassVar[str] = "output shaft"
    element_text: ClassVar[str] = ("P{order} tetrahedra (curved, isoparametric); the crack on an axisymmetric (r, z) "
                                   "section of P2 triangles")
    crack_model: str | None          # None (uncracked), "seam" or "axisymmetric"
    quick: bool

    @classmethod
    def volume_and_wall(cls, params) -> tuple[float, float]:
        s = params.output_shaft
        return math.pi / 4 * (s.outer_diameter_mm ** 2 - s.inner_diameter_mm ** 2) * s.length_mm, s.wall_mm

    @classmethod
    def deepest_crack_mm(cls, params) -> float:
        return 0.5 * params.output_shaft.wall_mm

    @classmethod
    def cad_modules(cls, params, cracked: bool) -> tuple[str, ...]:
        """build123d for the seam of a part-through crack, OCP alone for the bare uncracked solid (``build``),
        which is also the 3D part beside the axisymmetric section of a full circumferential crack."""
        if cracked and crack_model_for(params, "auto") == "seam":
            return ("build123d", "strainwave.geometry.parts")
        return ("OCP.BRepAlgoAPI", "OCP.BRepPrimAPI", "strainwave.geometry.output_shaft")

    @classmethod
    def dimensions(cls, params) -> tuple[tuple[str, str], ...]:
        s = params.output_shaft
        return (("outer diameter d_s", f"{s.outer_diameter_mm:g} mm"), ("inner diameter d_s2", f"{s.inner_diameter_mm:g} mm"),
                ("length L_s", f"{s.length_mm:g} mm"), ("wall", f"{s.wall_mm:g} mm"))

    def __post_init__(self):
        check_variant(STUDY, order=self.order, sizes_mm=(self.h_fine_mm,), crack_depth_mm=self.crack_depth_mm,
                      ratio=self.ratio)
        if (self.crack_model is None) != (self.crack_depth_mm is None) or \
                self.crack_model not in (None, "seam", "axisymmetric"):
            raise ValueError(f"{STUDY}: crack model {self.crack_model!r} with depth {self.crack_depth_mm!r}")

    @property
    def seam(self) -> bool:
        return self.crack_model == "seam"

    def build(self):
        if self.seam:
            return _build_seam(self.params, self.crack_depth_mm)
        # a bare OCC solid: an uncracked point imports no build123d (docs/decisions/013-sweep-worker-start-up.md)
        from strainwave.geometry.output_shaft import build_bare
        return build_bare(self.params)

    def series(self) -> tuple[SeriesPlan, ...]:
        plans = (SeriesPlan("solid", refinement_sizes(self.h_fine_mm, self.ratio)),)
        if self.crack_model == "axisymmetric":
            from strainwave.fea.shaft_axisym_study import section_fine_mm
            plans += (SeriesPlan("section", refinement_sizes(section_fine_mm(self.params, self.quick), self.ratio)),)
        return plans

    def solve(self, part, series, h_mm, k, keep_fields, progress) -> MeshSolve:
        if series == "section":
            from strainwave.fea.shaft_axisym_study import section_fine_mm, solve_section_refinement
            return solve_section_refinement(self.params, self.crack_depth_mm, h_mm,
                                            section_fine_mm(self.params, self.quick), quick=self.quick,
                                            keep_fields=keep_fields, progress=progress)
        refine = [CRACK_FRONT.refine(part.crack_front_mm, h_mm, self.h_fine_mm, self.crack_depth_mm)] if self.seam else []
        md, t_mesh = mesh_for_study(part, study=STUDY, h_mm=h_mm, order=self.order, refine=refine, progress=progress)
        lam0, sol0 = solve_mesh(md, self.params, progress=progress)
        values, sols = {FLEX: lam0}, [sol0]
        if self.seam:
            # one mesh with the embedded crack surface, solved as is (uncracked) and opened (cracked):
            # the difference then carries almost none of the far field's discretization error
            lam1, sol1 = solve_mesh(open_crack_for(md, STUDY), self.params, progress=progress)
            values[CRACKED] = lam1
            sols.append(sol1)
        last = sols[-1]
        return MeshSolve(h_mm, values, last.md.quality, _timings(sols, t_mesh), last.solver.to_dict(),
                         {"solution": last} if keep_fields else {})

    def quantities(self, series: Mapping[str, Series]) -> dict:
        solid = series["solid"]
        lam0 = solid.values(FLEX)
        if self.crack_model == "axisymmetric":
            section = series["section"]
            deltas = section.values(DELTA)
            # the 3D uncracked flexibility plus the section's delta, refinement k with refinement k
            q = crack_flexibility_quantities(solid.h_mm, lam0, [l0 + d for l0, d in zip(lam0, deltas)], UNIT)
            q[DELTA] = section.converged(DELTA, UNIT, order=CRACK_FORMAL_ORDER)
            return q
        return crack_flexibility_quantities(solid.h_mm, lam0, solid.values(CRACKED) if self.seam else None, UNIT)

    def crack(self, part) -> CrackRecord | None:
        if self.crack_model is None:
            return None
        if self.seam:
            return seam_crack(self.crack_depth_mm, part, "part-through circumferential crack")
        # the cracked field is the (r, z) section (x = r, y = z): it has no z axis for a close-up to centre on
        return CrackRecord(self.crack_depth_mm, "axisymmetric (r, z) section: exact for a full circumferential "
                                                "crack; closed and opened on one mesh")

    def write_fields(self, series: Mapping[str, Series], vtu: Path, load: Load) -> tuple[Path, ...]:
        sol = series["solid"].finest.fields["solution"]
        info = field_info(STUDY, load.describe(), self.params.material)
        paths = (write_solid_fields(vtu, sol.md, sol.sk, sol.u, sol.lame, info=info),)
        if "section" in series:
            from strainwave.fea.shaft_axisym_study import write_section_fields
            paths += (write_section_fields(self.params, series["section"].finest,
                                           vtu.with_name(vtu.stem + "_cracked.vtu")),)
        return paths

    def meta(self, part, series: Mapping[str, Series]) -> dict:
        out = torsion_meta(self.params, self.order, self.ratio, series["solid"].h_mm)
        if self.seam:
            out["crack_part"] = {k: v for k, v in part.meta.items() if isinstance(v, (int, float, str))}
        if "section" in series:
            s = series["section"]
            out["axisymmetric"] = {"section_sizes_mm": list(s.h_mm),
                                   "tip_sizes_mm": [m.values["tip_size_mm"] for m in s.solves],
                                   "section_nodes": [m.mesh.nodes for m in s.solves]}
        return out


def run(params, *, mesh_size_mm=None, order=2, crack_depth_mm=None, vtu=None, progress=lambda m: None,
        quick=False, ratio: float = DEFAULT_RATIO, crack_model: str = "auto") -> StudyResult:
    """Flexibility on three meshes (GCI); with a crack also delta lambda = cracked - uncracked, both on
    the same mesh: the (r, z) section for a full circumferential crack (``crack_model`` "auto" or
    "axisymmetric", exact and cheap), the 3D seam otherwise ("seam")."""
    model = crack_model_for(params, crack_model)       # a wrong choice is refused with or without a crack
    model = model if crack_depth_mm is not None else None
    h = mesh_size_mm or default_size_mm(params, quick)
    if h >= params.output_shaft.length_mm / 2:
        raise InputError("--mesh-size-mm", h, f"must be < L_s/2 = {params.output_shaft.length_mm / 2:g} mm")
    variant = ShaftTorsion(params, order, h, ratio, crack_depth_mm, model, quick)
    return run_variant(variant, vtu=vtu, progress=progress)
