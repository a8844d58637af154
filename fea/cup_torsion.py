"""Study ``cup-torsion``: torsional flexibility of the flexspline cup, lambda_f, vs seed 000's lambda_f0.

The cup (``geometry``'s "flexspline-cup"; smooth band by default, teeth optional) is clamped at the hub
face ``fixed``; the torque acts on the toothed band ``loaded`` as a uniform tangential shear whose moment
about z is T (solved for a unit shear and rescaled: the problem is linear). Twist = area-weighted mean
rotation of the band, lambda_f = twist / T. Seed 000: lambda_f0 = k_f k_G c_L / (0.1 mu [1 - (1 - 2 c_d)^4]
d1^3), published with 0.1 and the seed's mu; corrected with pi/32; k_G = 0.83 for a cup, k_f = 1 or 0.83.
"""
from __future__ import annotations

import time

from ..errors import InputError
from .assembly import Lame
from .fields import field_info, write_solid_fields
from .crack_seam import open_crack_for
from .meshing import Refine
from .refinement import DEFAULT_RATIO, crack_flexibility_quantities, crack_front_size_mm, refinement_sizes
from .result import StudyResult
from .static import StaticSolution, solve_static
from .study_mesh import mesh_for_study
from .torsion_load import mean_rotation_rad, moment_arm_mm3, uniform_tangential_traction

STUDY = "cup-torsion"
UNIT = "rad/(N*mm)"


def default_size_mm(params, quick: bool) -> float:
    """Finest global size: 3 walls (4 with --quick). One P2 element through the wall carries the membrane
    shear of torsion; measured GCI 0.24 % at 2 walls (211k dofs, 64 s), ~1 % at 4 walls."""
    return params.flexspline_cup.wall_thickness_mm * (4.0 if quick else 3.0)


# Crack-front size (refinement.crack_front_size_mm): a/4 at the finest mesh, no floor: the root crack's
# front is short (a/sin beta + 2c), so a fine tip is cheap, while a floor of h/16 (0.42 mm) left the
# 0.1 mm crack as two triangles with every node on the front (delta lambda = 0). Measured (seam, h = 6.72
# mm, 3 refinements x 2 solves, 2 shared cores, +-1.5x):
#   a = 1.12 mm: tip a/2: 109k dofs, 43 s, 2.438e-15 +- 1.1e-16 (p = 3.8 from irregular steps; the a/4
#     value lies outside that band); a/4: 145k dofs, 50 s, 2.585e-15, equal steps (p = 0.05, GCI 195 %);
#   a = 0.1 mm: tip a/2: 116k dofs, 70 s, 1.65e-18 +- 1.1e-18; a/4: 154k dofs, 51 s, 1.766e-18 +- 2.4 %.
# delta lambda ~ a^3.0 between the two depths, as for a 3D crack of fixed aspect ratio (c = 2a).
FRONT_FLOOR_OVER_H = 0.0
GROW_OVER_H = 3.0
TIP_OVER_A = 0.25


def crack_refine(part, h_mm: float, depth_mm: float, *, h_fine_mm: float | None = None,
                 floor_over_h: float | None = None, grow_over_h: float | None = None) -> Refine:
    """a/4 at the root-crack front on the finest mesh, scaled with h/h_fine on the coarser meshes so the
    GCI sees the front converge, growing to h within 2a + 3h."""
    floor = FRONT_FLOOR_OVER_H if floor_over_h is None else floor_over_h
    grow = GROW_OVER_H if grow_over_h is None else grow_over_h
    tip = crack_front_size_mm(h_mm, h_mm if h_fine_mm is None else h_fine_mm, depth_mm,
                              tip_over_a=TIP_OVER_A, floor_over_h=floor)
    return Refine(size_mm=tip, dist_min_mm=max(depth_mm, tip), dist_max_mm=2 * depth_mm + grow * h_mm,
                  points_mm=part.crack_front_mm)


def solve_mesh(md, params, *, progress=lambda m: None) -> tuple[float, StaticSolution, float]:
    """(lambda_f, solution for unit shear, applied torque of the unit shear) on a given mesh."""
    mat = params.material
    sol = solve_static(md, Lame.from_young(mat.youngs_modulus_MPa, mat.poisson_ratio), fixed={"fixed": 0.0},
                       tractions={"loaded": uniform_tangential_traction(1.0, 1.0)}, study=STUDY, progress=progress,
                       # thin walls: the matrix graph is nearly 2D, so Cholesky fill stays small, while
                       # AMG-CG needed 470-800 iterations (measured at 37k-54k dofs)
                       method="direct")
    torque = moment_arm_mm3(sol, "loaded")     # moment of the unit tangential shear
    return mean_rotation_rad(sol, "loaded") / torque, sol, torque


def solve_once(part, params, *, h_mm: float, order: int, refine=(), progress=lambda m: None
               ) -> tuple[float, StaticSolution, float, float]:
    """(lambda_f, solution for unit shear, applied torque of the unit shear, mesh time)."""
    md, t_mesh = mesh_for_study(part, study=STUDY, h_mm=h_mm, order=order, refine=refine, progress=progress)
    return (*solve_mesh(md, params, progress=progress), t_mesh)


def _build(params, depth_mm, teeth):
    from strainwave.geometry.part import CrackModel
    from strainwave.geometry.parts import build_part
    # a crack is the zero-width seam (FEA on one mesh, cracked and uncracked); the CAD slot is for STEP
    model = CrackModel.SEAM if depth_mm is not None else CrackModel.SLOT
    return build_part("flexspline-cup", params, crack_depth_mm=depth_mm, teeth=teeth, crack_model=model)


def run(params, *, mesh_size_mm=None, order=2, crack_depth_mm=None, vtu=None, progress=lambda m: None,
        quick=False, teeth: bool = False, ratio: float = DEFAULT_RATIO) -> StudyResult:
    """lambda_f on three meshes (GCI); with a crack delta lambda_f = cracked - uncracked on each mesh."""
    fc = params.flexspline_cup
    h = mesh_size_mm or default_size_mm(params, quick)
    if h >= fc.length_mm / 4:
        raise InputError("--mesh-size-mm", h, f"must be < L/4 = {fc.length_mm / 4:g} mm for the cup")
    sizes = refinement_sizes(h, ratio)
    timings = {"geometry": 0.0, "mesh": 0.0, "assembly": 0.0, "solve": 0.0}
    t0 = time.perf_counter()
    cracked = _build(params, crack_depth_mm, teeth) if crack_depth_mm is not None else None
    plain = _build(params, None, teeth) if cracked is None else cracked   # the seam part IS the uncracked cup
    timings["geometry"] = time.perf_counter() - t0
    lam0, lam1, finest, meshes = [], [], None, []
    for k, hk in enumerate(reversed(sizes)):
        progress(f"{STUDY}: refinement {k + 1}/3, h = {hk:.3g} mm")
        refine = (crack_refine(cracked, hk, crack_depth_mm, h_fine_mm=sizes[0]),) if cracked is not None else ()
        md, tm = mesh_for_study(plain, study=STUDY, h_mm=hk, order=order, refine=refine, progress=progress)
        timings["mesh"] += tm
        # with a crack: the same mesh solved as is (embedded surface closed) and opened
        cases = [(md, lam0)] + ([(open_crack_for(md, STUDY), lam1)] if cracked is not None else [])
        for mdk, out in cases:
            lam, sol, torque = solve_mesh(mdk, params, progress=progress)
            out.append(lam)
            timings["assembly"] += sol.timings_s["assembly"]
            timings["solve"] += sol.timings_s["solve"]
            finest = (sol, torque)
        meshes.append(finest[0].md.quality)     # the mesh the result's ``mesh`` states, per refinement
    lam0, lam1 = lam0[::-1], lam1[::-1]
    quantities = crack_flexibility_quantities(sizes, lam0, lam1 if cracked is not None else None, UNIT)
    sol, torque = finest
    fields = ()
    if vtu is not None:
        scale = params.gear.output_torque_Nmm / torque       # report fields at the design torque T
        fields = (write_solid_fields(vtu, sol.md, sol.sk, sol.u * scale, sol.lame,
                                     info=field_info(STUDY, f"torque T = {params.gear.output_torque_Nmm:g} N*mm as "
                                                     "tangential shear on 'loaded' (band), 'fixed' clamped",
                                                     params.material)),)
    mat = params.material
    meta = {"torque_Nmm": params.gear.output_torque_Nmm, "teeth": teeth,
            "load": "uniform tangential shear on 'loaded' (band), moment T", "bc": "'fixed' (hub face) clamped",
            "twist": "area-weighted mean rotation of 'loaded'",
            "G_fea_MPa": mat.implied_shear_modulus_MPa, "mu_seed_MPa": mat.shear_modulus_MPa,
            "order": order, "refinement_ratio": ratio, "mesh_sizes_mm": list(sizes),
            "solver": sol.solver.to_dict(), "crack_depth_mm": crack_depth_mm}
    if cracked is not None:
        meta["crack"] = {k: v for k, v in cracked.meta.items() if isinstance(v, (int, float, str))}
    timings["total"] = time.perf_counter() - t0
    return StudyResult(STUDY, quantities, sol.md.quality, timings, fields, meta, tuple(meshes[::-1]))
