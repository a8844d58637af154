"""Study `bearing-ring` (seed 000): radial compliance of the wave-generator bearing inner ring, with and
without the semi-elliptical surface crack at the ball contact.

Load: F_r = 1.15 k_r T / d1 (seed 000) as a Hertzian pressure p = p0 sqrt(1 - (s/b')^2 - (z'/a')^2),
p0 = 3 F_r/(2 pi a' b') (seed 000), on the race around the contact centre (+x); a' along the ring axis
(across the race), b' along the circumference (rolling direction). The resultant is made exactly F_r.
Support: the whole bore fixed. The inner ring sits on the wave generator's cam, which is far stiffer
than the ring locally and carries it all round; a bonded bore is that rigid-cam limit (it also removes
every rigid-body mode without a point constraint that would add its own compliance).
Compliance: the work-conjugate displacement of the load, C = f.u / F_r^2 (what the crack-compliance
integral of seed 000 is conjugate to). Crack effect: C(cracked) - C(uncracked) on ONE mesh per refinement:
the ring is meshed with the crack as an embedded zero-width surface (geometry's CrackModel.SEAM), solved
as is, then with the surface opened (fea.crack_seam.open_crack), so the far-field discretization error
cancels in the difference.
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import StageError
from .assembly import Lame, elasticity_stiffness, scalar_basis
from .convergence import grid_convergence
from .refinement import CRACK_ORDER_BOUNDS, DEFAULT_RATIO
from .fields import field_info, write_solid_fields
from .facet_traction import facet_traction_load
from .crack_contact import crack_pairs, solve_with_contact
from .crack_seam import open_crack_for
from .mesh_data import group_dofs, to_skfem
from .mesh_isolated import mesh_part_isolated
from .meshing import MeshingFailed, Refine
from .result import Quantity, StudyResult
from .solver import solve_elasticity

STUDY = "bearing-ring"
PART = "wg-bearing-ring"
REFINEMENT_RATIO = DEFAULT_RATIO    # every study refines at the one ratio of fea/refinement.py
# Iterative solve (p-multigrid / AMG-CG, fea/solver.py): 3D P2 fill-in makes a sparse direct solve lose
# early; the crossover is measured by benchmarks/bench_fea.py --compare, not asserted here.
SOLVER = "amg"


def radial_force_N(params) -> float:
    """Seed 000: F_r = 1.15 k_r T / d1."""
    return 1.15 * params.gear.force_coefficient * params.gear.output_torque_Nmm / params.flexspline_cup.pitch_diameter_mm


def hertz_pressure(force_N: float, semi_axes_mm: tuple[float, float], centre_mm, race_radius_mm: float):
    """Callable x (3, ...) -> pressure (MPa); a' along z, b' along the arc s = R (psi - psi_c)."""
    a_ax, b_circ = semi_axes_mm
    p0 = 3.0 * force_N / (2.0 * np.pi * a_ax * b_circ)
    psi_c = np.arctan2(centre_mm[1], centre_mm[0])

    def p(x):
        s = race_radius_mm * np.angle(np.exp(1j * (np.arctan2(x[1], x[0]) - psi_c)))
        rho2 = (s / b_circ) ** 2 + ((x[2] - centre_mm[2]) / a_ax) ** 2
        return p0 * np.sqrt(np.clip(1.0 - rho2, 0.0, None))
    return p


def contact_centre_mm(part, contact_name: str) -> np.ndarray:
    """Centre of the contact on the race: the named patch's centre projected radially onto the race
    (its centre of mass lies inside the curved surface), or +x at mid-width when only ``race`` is named."""
    bb = part.solid.bounding_box()
    r_out = float(bb.max.X)
    if contact_name == "contact":
        c = np.asarray(part.named_faces["contact"][0].center_mm, float)
        psi = np.arctan2(c[1], c[0])
        return np.array([r_out * np.cos(psi), r_out * np.sin(psi), c[2]])
    return np.array([r_out, 0.0, 0.5 * (bb.min.Z + bb.max.Z)])


@dataclass(frozen=True)
class ComplianceSolve:
    """One bearing-ring solve: compliance, mesh facts and (optionally) the field for VTU output."""

    compliance_mm_per_N: float
    quality: object
    timings_s: dict
    solver: dict
    field: tuple = ()          # (MeshData, SkfemMesh, u) when asked for
    size_factor: float = 1.0   # sizes scaled by this after a failed gmsh attempt (mesh_isolated)


def ring_refine(part, params, *, size_mm, refine_points, local_mm, contact_mm=None) -> list[Refine]:
    """Size fields: the contact ellipse (``contact_mm``, default min(size, b'/3)) and the crack front."""
    a_ax, b_circ = params.wave_generator.contact_semi_axes_mm
    centre = contact_centre_mm(part, "contact" if "contact" in part.named_faces else "race")
    c_mm = min(size_mm, contact_mm if contact_mm else b_circ / 3)
    refine = [Refine(size_mm=c_mm, dist_min_mm=max(a_ax, b_circ), dist_max_mm=3 * max(a_ax, b_circ),
                     points_mm=(tuple(centre),))]
    if refine_points:
        refine.append(Refine(size_mm=local_mm, dist_min_mm=2 * local_mm, dist_max_mm=max(a_ax, b_circ),
                             points_mm=tuple(refine_points)))
    return refine


def compliance_on_mesh(md, part, params, lame, *, force_N, method=SOLVER, keep_field=False,
                       contact: bool = False) -> tuple:
    """Load (Hertzian patch, resultant F_r), fix the bore, solve once on ``md``:
    (compliance, solver info dict, field or ()). ``contact``: an opened crack's faces may not pass through
    each other (``crack_contact``, frictionless, solved by active set with the direct solver)."""
    a_ax, b_circ = params.wave_generator.contact_semi_axes_mm
    contact_name = "contact" if "contact" in part.named_faces else "race"
    centre = contact_centre_mm(part, contact_name)
    sk = to_skfem(md)
    sb = scalar_basis(sk.mesh, sk.element)
    K = elasticity_stiffness(sb, lame)
    race_nodes = group_dofs(sk, md, contact_name)
    r_race = float(np.median(np.hypot(*sb.doflocs[:2, race_nodes])))
    p = hertz_pressure(force_N, (a_ax, b_circ), centre, r_race)
    # integrated on the facet triangles: FacetBasis's inverse mapping fails on curved sliver tets
    f = facet_traction_load(md, sk, contact_name,
                            lambda x: -p(x) * np.stack([x[0], x[1], 0 * x[2]]) / np.hypot(x[0], x[1]))
    fx = f[0::3].sum() * np.cos(np.arctan2(centre[1], centre[0])) + f[1::3].sum() * np.sin(np.arctan2(centre[1], centre[0]))
    f *= force_N / -fx                  # the resultant is F_r exactly (quadrature of the sqrt profile)
    fixed = (3 * group_dofs(sk, md, "bore")[:, None] + np.arange(3)).ravel()
    if contact and "crack_plus" in md.groups:
        infos = []

        def linear(Kc, fc, fixed_c):
            uc, inf = solve_elasticity(Kc, fc, fixed_dofs=fixed_c, coords=sb.doflocs, dim=3, study=STUDY,
                                       method="direct")
            infos.append(inf)
            return uc
        res = solve_with_contact(K, f, fixed, crack_pairs(md).in_dofs(sk.node_to_dof), linear)
        u = res.u
        info = dict(infos[-1].to_dict(), contact_iterations=res.iterations, contact_pairs=int(res.active.size),
                    contact_closed_pairs=int(res.active.sum()),
                    contact_min_opening_mm=float(res.opening_mm.min()), contact_max_opening_mm=float(res.opening_mm.max()),
                    compliance_without_contact_mm_per_N=float(f @ res.u_unconstrained) / force_N ** 2)
        return float(f @ u) / force_N ** 2, info, ((md, sk, u) if keep_field else ())
    u, info = solve_elasticity(K, f, fixed_dofs=fixed, coords=sb.doflocs, dim=3, study=STUDY, method=method,
                               p2_element_dofs=sb.element_dofs if md.order == 2 else None)
    return float(f @ u) / force_N ** 2, info.to_dict(), ((md, sk, u) if keep_field else ())


def mesh_ring(part, params, *, size_mm, order, refine_points, local_mm, contact_mm=None) -> tuple:
    """(mesh, size factor of the successful gmsh attempt)."""
    refine = ring_refine(part, params, size_mm=size_mm, refine_points=refine_points, local_mm=local_mm,
                         contact_mm=contact_mm)
    try:   # in a forked child: gmsh's high-order optimiser can abort natively (seen on the old slot)
        return mesh_part_isolated(part, size_mm=size_mm, order=order, refine=refine)
    except MeshingFailed as exc:
        raise StageError("mesh", STUDY, f"h = {size_mm:g} mm: {exc}") from exc


def solve_compliance(part, params, lame, *, size_mm, order, refine_points, local_mm, force_N,
                     contact_mm=None, method=SOLVER, keep_field=False) -> ComplianceSolve:
    """Mesh, load (Hertzian patch, resultant F_r), fix the bore, solve once.

    ``contact_mm`` is the element size over the contact ellipse (default min(size, b'/3)); the study
    scales it with the global size so that all three refinements refine the contact zone too."""
    t0 = time.perf_counter()
    md, size_factor = mesh_ring(part, params, size_mm=size_mm, order=order, refine_points=refine_points,
                                local_mm=local_mm, contact_mm=contact_mm)
    t1 = time.perf_counter()
    c, info, field = compliance_on_mesh(md, part, params, lame, force_N=force_N, method=method, keep_field=keep_field)
    t2 = time.perf_counter()
    return ComplianceSolve(c, md.quality, {"mesh": t1 - t0, "assemble+solve": t2 - t1}, info, field, size_factor)


def seam_compliances(part, params, lame, *, size_mm, order, refine_points, local_mm, force_N, contact_mm=None,
                     keep_field=False) -> tuple[ComplianceSolve, ComplianceSolve]:
    """Mesh the seam part ONCE; (uncracked, cracked) solves on that mesh as is and with the crack opened."""
    t0 = time.perf_counter()
    md, size_factor = mesh_ring(part, params, size_mm=size_mm, order=order, refine_points=refine_points,
                                local_mm=local_mm, contact_mm=contact_mm)
    t_mesh = time.perf_counter() - t0
    out = []
    for m, contact in ((md, False), (open_crack_for(md, STUDY), True)):
        t1 = time.perf_counter()
        # the opened crack's faces may separate but not interpenetrate (crack_contact)
        c, info, field = compliance_on_mesh(m, part, params, lame, force_N=force_N, keep_field=keep_field,
                                            contact=contact)
        out.append(ComplianceSolve(c, m.quality, {"mesh": t_mesh, "assemble+solve": time.perf_counter() - t1},
                                   info, field, size_factor))
        t_mesh = 0.0
    return out[0], out[1]


# Crack-front size floor as a fraction of the finest global size (see crack_front_size_mm). None: the
# semi-elliptical front is short (~ pi (a + c) / 2), so a/3 is affordable at any depth. Measured (seam,
# h = 3.33 mm, 3 refinements x 2 solves, 2 shared cores): a = 1.04 mm: 79k dofs, 39 s, delta C
# 1.49e-8 +- 2.7e-9 mm/N (p = 0.6); a = 0.1 mm: 78k dofs, 22 s, 2.24e-11 +- 1.9e-14 mm/N.
FRONT_FLOOR_OVER_H = 0.0


def crack_front_size_mm(a_mm: float, fine_mm: float, floor_over_h: float = FRONT_FLOOR_OVER_H) -> float:
    """Element size at the crack front on the finest mesh: a/3, not below ``floor_over_h`` h."""
    return max(a_mm / 3.0, floor_over_h * fine_mm)


def build_seam_part(params, crack_depth_mm: float):
    """The wave-generator bearing inner ring with its crack as an embedded seam (tests substitute a stand-in)."""
    from ..geometry.part import CrackModel
    from ..geometry.parts import build_part
    return build_part(PART, params, crack_depth_mm=crack_depth_mm, crack_model=CrackModel.SEAM)


def build_plain_part(params):
    """The uncracked wave-generator bearing inner ring (tests substitute a stand-in)."""
    from ..geometry.parts import build_part
    return build_part(PART, params)


def vtu_paths(vtu) -> tuple[Path, Path]:
    """(cracked, uncracked) field files next to ``vtu``: <stem>_cracked.vtu first (the report's close-up)."""
    v = Path(vtu)
    return v.with_name(f"{v.stem}_cracked.vtu"), v.with_name(f"{v.stem}_uncracked.vtu")


def write_fields(path, field, lame, info=None) -> Path:
    """Displacement, von Mises and the stress tensor at the mesh nodes, as VTU (``info``: FieldData)."""
    return write_solid_fields(path, *field, lame, info=info)


def _info(params, force_N: float) -> dict:
    return field_info(STUDY, f"radial force F = {force_N:g} N as Hertz pressure on 'contact'", params.material)


def run(params, *, mesh_size_mm=None, order=2, crack_depth_mm=None, vtu=None, progress=lambda m: None,
        quick=False) -> StudyResult:
    """Radial compliance on three meshes (GCI), cracked and uncracked, and their difference per mesh.

    Every length of the size field scales with the refinement: global size h, contact size
    min(h, b'/3) r^k and crack-front size a/3 r^k, so the GCI covers the contact zone too."""
    if crack_depth_mm is None:      # None means uncracked, as in every study
        return _run_uncracked(params, mesh_size_mm=mesh_size_mm, order=order, vtu=vtu, progress=progress,
                              quick=quick)
    t_start = time.perf_counter()
    a = crack_depth_mm
    force, mat, lame, b_circ, fine, sizes = _setup(params, mesh_size_mm, quick)
    t0 = time.perf_counter()
    seam = build_seam_part(params, a)
    timings = {"geometry": time.perf_counter() - t0}
    front = list(seam.crack_front_mm)
    c_unc, c_cr, qual, info, fields_fine, factors, meshes = [], [], None, None, {}, {}, []
    h_used = []     # sizes as meshed (a gmsh retry scales them a little)
    for k, h in enumerate(sizes):
        scale = REFINEMENT_RATIO ** k
        local = crack_front_size_mm(a, fine) * scale      # the crack-tip size refines with the mesh
        contact = min(fine, b_circ / 3.0) * scale
        progress(f"{STUDY}: a = {a:g} mm, h = {h:.3g} mm: one mesh, solved uncracked and with the crack opened")
        unc, cr = seam_compliances(seam, params, lame, size_mm=h, order=order, refine_points=front, local_mm=local,
                                   force_N=force, contact_mm=contact, keep_field=(k == 0 and vtu is not None))
        c_unc.append(unc.compliance_mm_per_N)
        c_cr.append(cr.compliance_mm_per_N)
        meshes.append(unc.quality)
        factors[f"h{k}"] = unc.size_factor
        h_used.append(h * unc.size_factor)
        for label, sol in (("uncracked", unc), ("cracked", cr)):
            for key, v in sol.timings_s.items():
                timings[f"{key}_{label}"] = timings.get(f"{key}_{label}", 0.0) + v
            if k == 0:
                fields_fine[label] = sol.field
        if k == 0:   # the uncracked mesh's facts; the opened one adds the duplicated crack nodes
            qual, info = unc.quality, dict(unc.solver, dofs_total=unc.quality.dofs, dofs_cracked=cr.quality.dofs,
                                           **{k: v for k, v in cr.solver.items() if k.startswith(('contact', 'compliance'))})
    fields = ()
    if vtu is not None:
        t0 = time.perf_counter()
        p_cr, p_unc = vtu_paths(vtu)
        fields = (write_fields(p_cr, fields_fine["cracked"], lame, _info(params, force)),
                  write_fields(p_unc, fields_fine["uncracked"], lame, _info(params, force)))
        timings["vtu"] = time.perf_counter() - t0
    delta = [cc - cu for cc, cu in zip(c_cr, c_unc)]
    q = {"radial_compliance_mm_per_N": Quantity("radial_compliance_mm_per_N", c_unc[0], "mm/N",
                                                grid_convergence(h_used, c_unc)),
         "cracked_radial_compliance_mm_per_N": Quantity("cracked_radial_compliance_mm_per_N", c_cr[0], "mm/N",
                                                        grid_convergence(h_used, c_cr)),
         "delta_radial_compliance_mm_per_N": Quantity("delta_radial_compliance_mm_per_N", delta[0], "mm/N",
                                                      grid_convergence(h_used, delta, min_order=CRACK_ORDER_BOUNDS[0],
                                                                       max_order=CRACK_ORDER_BOUNDS[1]))}
    dq = q["delta_radial_compliance_mm_per_N"]
    timings["total"] = time.perf_counter() - t_start
    meta = {"radial_force_N": force, "crack_depth_mm": a,
            "load": "Hertzian ellipsoidal pressure on the race, a' axial x b' circumferential, p0 = 3F/(2 pi a'b')",
            "support": "bore fixed (rigid cam, bonded)", "compliance": "work-conjugate f.u/F^2",
            "seed_uncracked_stiffness_N_per_mm": params.wave_generator.uncracked_radial_stiffness_N_per_mm,
            "fea_uncracked_stiffness_N_per_mm": 1.0 / c_unc[0],
            # |delta| below its GCI band means the crack is below the resolution of these meshes
            "delta_resolved": bool(abs(dq.value) > dq.uncertainty),
            "mesh_sizes_mm": sizes, "contact_sizes_mm": [min(fine, b_circ / 3.0) * REFINEMENT_RATIO ** k for k in range(3)],
            "crack_front_sizes_mm": [crack_front_size_mm(a, fine) * REFINEMENT_RATIO ** k for k in range(3)],
            "crack_model": "seam (one mesh per refinement, solved closed and opened)",
            "mesh_size_factors": factors, "solver": info, "part": {k: v for k, v in (seam.meta or {}).items() if isinstance(v, (int, float, str))},
            "E_MPa": mat.youngs_modulus_MPa, "nu": mat.poisson_ratio, "G_implied_MPa": mat.implied_shear_modulus_MPa}
    return StudyResult(STUDY, q, qual, timings, fields, meta, tuple(meshes))


def _setup(params, mesh_size_mm, quick):
    """(F_r, material, Lame, b', finest size, three sizes finest first) shared by the cracked and uncracked runs."""
    mat = params.material
    t_i = params.wave_generator.bearing_inner_ring_thickness_mm
    fine = mesh_size_mm if mesh_size_mm else t_i / (2.0 if quick else 3.0)
    return (radial_force_N(params), mat, Lame.from_young(mat.youngs_modulus_MPa, mat.poisson_ratio),
            params.wave_generator.contact_semi_axes_mm[1], fine, [fine * REFINEMENT_RATIO ** k for k in range(3)])


def _run_uncracked(params, *, mesh_size_mm, order, vtu, progress, quick) -> StudyResult:
    """The uncracked ring alone: radial compliance on three meshes (same sizes as the cracked run)."""
    t_start = time.perf_counter()
    force, mat, lame, b_circ, fine, sizes = _setup(params, mesh_size_mm, quick)
    part = build_plain_part(params)
    timings = {"geometry": time.perf_counter() - t_start}
    sols = []
    for k, h in enumerate(sizes):
        progress(f"{STUDY}: uncracked, h = {h:.3g} mm")
        sols.append(solve_compliance(part, params, lame, size_mm=h, order=order, refine_points=(), local_mm=h,
                                     force_N=force, contact_mm=min(fine, b_circ / 3.0) * REFINEMENT_RATIO ** k,
                                     keep_field=(k == 0 and vtu is not None)))
        for key, v in sols[-1].timings_s.items():
            timings[key] = timings.get(key, 0.0) + v
    c = [s.compliance_mm_per_N for s in sols]
    h_used = [h * s.size_factor for h, s in zip(sizes, sols)]
    fields = (write_fields(vtu, sols[0].field, lame, _info(params, force)),) if vtu is not None else ()
    q = {"radial_compliance_mm_per_N": Quantity("radial_compliance_mm_per_N", c[0], "mm/N",
                                                grid_convergence(h_used, c))}
    timings["total"] = time.perf_counter() - t_start
    meta = {"radial_force_N": force, "crack_depth_mm": None,
            "load": "Hertzian ellipsoidal pressure on the race, a' axial x b' circumferential, p0 = 3F/(2 pi a'b')",
            "support": "bore fixed (rigid cam, bonded)", "compliance": "work-conjugate f.u/F^2",
            "seed_uncracked_stiffness_N_per_mm": params.wave_generator.uncracked_radial_stiffness_N_per_mm,
            "fea_uncracked_stiffness_N_per_mm": 1.0 / c[0], "mesh_sizes_mm": sizes, "solver": sols[0].solver,
            "E_MPa": mat.youngs_modulus_MPa, "nu": mat.poisson_ratio, "G_implied_MPa": mat.implied_shear_modulus_MPa}
    return StudyResult(STUDY, q, sols[0].quality, timings, fields, meta, tuple(s.quality for s in sols))
