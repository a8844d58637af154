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
import time
from typing import Callable, Sequence


from ..errors import InputError
from .assembly import Lame
from .fields import field_info, write_solid_fields
from .crack_seam import open_crack_for
from .meshing import Refine
from .refinement import DEFAULT_RATIO, crack_flexibility_quantities, crack_front_size_mm, refinement_sizes
from .result import StudyResult
from .static import StaticSolution, solve_static
from .study_mesh import mesh_for_study
from .torsion_load import mean_rotation_rad, saint_venant_traction

STUDY = "shaft-torsion"
UNIT = "rad/(N*mm)"


def default_size_mm(params, quick: bool) -> float:
    """Finest global size: wall / 1.5 (wall / 1 with --quick); curved P2 is exact to ~1e-5 there."""
    return params.output_shaft.wall_mm / (1.0 if quick else 1.5)


# Crack-front size (refinement.crack_front_size_mm): a/6 at the finest mesh, floor h/32; graded zone
# 3a + h. Measured on the shaft (seam, h = 8.33 mm, 3 refinements x 2 solves, 2 shared cores, +-1.5x):
#  a = 3.13 mm: tip a/2 fixed (not refined with h), zone a + 3h: 87k dofs, 18 s, 1.218e-11 +- 0.5 %, but
#    the GCI missed the tip error: refined tips give 1.34e-11; tip a/2 scaled: 62k dofs, p = 0.3, GCI 69 %;
#    a/4: 175k dofs, p = 0.05 (equal steps, GCI useless); a/6: 381k dofs, 86 s, 1.344e-11 +- 5.5 %, p = 1.1
#    (the O(tip) singularity error of P2 without quarter-point elements);
#  a = 0.78 mm (floor a/3): 267k dofs, 64 s, 7.58e-13 +- 7.6 %, p = 1.6;
#  a = 0.1 mm (floor, 0.26 mm): zone a + 3h: 606k dofs, 227 s, 8.08e-15 +- 3.5e-15; zone a + h: 190k dofs,
#    58 s, 7.97e-15 +- 2.7e-15 (extrapolated 1.01e-14). Floor h/16: 324k dofs, 5.98e-15 +- 1.35e-14.
# The seam leaves no far-field noise to grade away, so a narrow zone costs nothing in accuracy.
FRONT_FLOOR_OVER_H = 1.0 / 32.0
TIP_OVER_A = 1.0 / 6.0
GROW_OVER_H = 1.0
ZONE_OVER_A = 3.0


def crack_refine(part, h_mm: float, depth_mm: float, *, h_fine_mm: float | None = None,
                 floor_over_h: float | None = None, grow_over_h: float | None = None) -> Refine:
    """Crack-front refinement: a/6 at the front on the finest mesh, never below ``floor_over_h`` h (shallow
    cracks stay affordable; their GCI then says how well they are resolved), scaled with h/h_fine on the
    coarser meshes (so the GCI sees the front converge too), growing to h within 3a + ``grow_over_h`` h."""
    floor = FRONT_FLOOR_OVER_H if floor_over_h is None else floor_over_h
    grow = GROW_OVER_H if grow_over_h is None else grow_over_h
    tip = crack_front_size_mm(h_mm, h_mm if h_fine_mm is None else h_fine_mm, depth_mm,
                              tip_over_a=TIP_OVER_A, floor_over_h=floor)
    return Refine(size_mm=tip, dist_min_mm=max(depth_mm / 2.0, tip), dist_max_mm=ZONE_OVER_A * depth_mm + grow * h_mm,
                  points_mm=part.crack_front_mm)


def solve_mesh(md, params, *, progress: Callable[[str], None] = lambda m: None) -> tuple[float, StaticSolution]:
    """Solve the torsion case on a mesh; return (lambda, solution)."""
    sh, mat = params.output_shaft, params.material
    T = params.gear.output_torque_Nmm
    J = math.pi / 32.0 * (sh.outer_diameter_mm ** 4 - sh.inner_diameter_mm ** 4)
    sol = solve_static(md, Lame.from_young(mat.youngs_modulus_MPa, mat.poisson_ratio), fixed={"fixed": 0.0},
                       tractions={"loaded": saint_venant_traction(T, J)}, study=STUDY, progress=progress)
    return mean_rotation_rad(sol, "loaded") / T, sol


def solve_once(part, params, *, h_mm: float, order: int, refine: Sequence[Refine] = (),
               progress: Callable[[str], None] = lambda m: None) -> tuple[float, StaticSolution, float]:
    """Mesh ``part`` at h, solve the torsion case, return (lambda, solution, mesh time)."""
    md, t_mesh = mesh_for_study(part, study=STUDY, h_mm=h_mm, order=order, refine=refine, progress=progress)
    lam, sol = solve_mesh(md, params, progress=progress)
    return lam, sol, t_mesh


def solve_seam(part, params, *, h_mm: float, order: int, refine: Sequence[Refine] = (),
               progress: Callable[[str], None] = lambda m: None
               ) -> tuple[float, float, StaticSolution, StaticSolution, float]:
    """Mesh the seam part ONCE, solve it uncracked and with the crack opened (same mesh):
    (lambda uncracked, lambda cracked, uncracked solution, cracked solution, mesh time)."""
    md, t_mesh = mesh_for_study(part, study=STUDY, h_mm=h_mm, order=order, refine=refine, progress=progress)
    lam0, sol0 = solve_mesh(md, params, progress=progress)
    lam1, sol1 = solve_mesh(open_crack_for(md, STUDY), params, progress=progress)
    return lam0, lam1, sol0, sol1, t_mesh


def _write_fields(vtu, sol: StaticSolution, params) -> tuple:
    if vtu is None:
        return ()
    info = field_info(STUDY, f"torque T = {params.gear.output_torque_Nmm:g} N*mm on 'loaded', 'fixed' clamped",
                      params.material)
    path = write_solid_fields(vtu, sol.md, sol.sk, sol.u, sol.lame, info=info)
    return (path,)


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


def run(params, *, mesh_size_mm=None, order=2, crack_depth_mm=None, vtu=None, progress=lambda m: None,
        quick=False, ratio: float = DEFAULT_RATIO, crack_model: str = "auto") -> StudyResult:
    """Flexibility on three meshes (GCI); with a crack also delta lambda = cracked - uncracked, both on
    the same mesh: the (r, z) section for a full circumferential crack (``crack_model`` "auto" or
    "axisymmetric", exact and cheap), the 3D seam otherwise ("seam")."""
    model = crack_model_for(params, crack_model)
    if crack_depth_mm is not None and model == "axisymmetric":
        from .shaft_axisym_study import run_axisymmetric
        uncracked = run(params, mesh_size_mm=mesh_size_mm, order=order, crack_depth_mm=None, vtu=vtu,
                        progress=progress, quick=quick, ratio=ratio)
        return run_axisymmetric(params, uncracked, crack_depth_mm, quick=quick, ratio=ratio, vtu=vtu,
                                progress=progress)
    h = mesh_size_mm or default_size_mm(params, quick)
    if h >= params.output_shaft.length_mm / 2:
        raise InputError("--mesh-size-mm", h, f"must be < L_s/2 = {params.output_shaft.length_mm / 2:g} mm")
    sizes = refinement_sizes(h, ratio)
    timings = {"geometry": 0.0, "mesh": 0.0, "assembly": 0.0, "solve": 0.0}
    t0 = time.perf_counter()
    cracked = _build_seam(params, crack_depth_mm) if crack_depth_mm is not None else None
    plain = _build(params, None) if cracked is None else None
    timings["geometry"] = time.perf_counter() - t0
    lam0, lam1, finest, meshes = [], [], None, []

    def add(sol, tm):
        timings["mesh"] += tm
        timings["assembly"] += sol.timings_s["assembly"]
        timings["solve"] += sol.timings_s["solve"]

    for k, hk in enumerate(reversed(sizes)):        # coarse to fine
        progress(f"{STUDY}: refinement {k + 1}/3, h = {hk:.3g} mm")
        if cracked is not None:
            # one mesh with the embedded crack surface, solved as is (uncracked) and opened (cracked):
            # the difference then carries almost none of the far field's discretization error
            l0, l1, sol0, sol1, tm = solve_seam(cracked, params, h_mm=hk, order=order,
                                                refine=[crack_refine(cracked, hk, crack_depth_mm, h_fine_mm=sizes[0])],
                                                progress=progress)
            lam0.append(l0)
            lam1.append(l1)
            add(sol0, tm)
            add(sol1, 0.0)
            finest = sol1
            meshes.append(sol1.md.quality)
            continue
        lam, sol, tm = solve_once(plain, params, h_mm=hk, order=order, progress=progress)
        add(sol, tm)
        finest = sol
        meshes.append(sol.md.quality)
        lam0.append(lam)
    lam0, lam1 = lam0[::-1], lam1[::-1]             # finest first, like ``sizes``
    quantities = crack_flexibility_quantities(sizes, lam0, lam1 if cracked is not None else None, UNIT)
    fields = _write_fields(vtu, finest, params)
    mesh_q = finest.md.quality
    mat = params.material
    meta = {"torque_Nmm": params.gear.output_torque_Nmm, "load": "Saint-Venant shear traction tau = T r / J on 'loaded'",
            "bc": "'fixed' clamped (all components)", "twist": "area-weighted mean rotation of 'loaded'",
            "G_fea_MPa": mat.implied_shear_modulus_MPa, "mu_seed_MPa": mat.shear_modulus_MPa,
            "order": order, "refinement_ratio": ratio, "mesh_sizes_mm": list(sizes),
            "solver": finest.solver.to_dict(), "crack_depth_mm": crack_depth_mm}
    if cracked is not None:
        meta["crack"] = {k: v for k, v in cracked.meta.items() if isinstance(v, (int, float, str))}
    timings["total"] = time.perf_counter() - t0
    return StudyResult(STUDY, quantities, mesh_q, timings, fields, meta, tuple(meshes[::-1]))
