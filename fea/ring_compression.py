"""Study `ring-compression` (seed 003): the EWG flexspline ring squeezed by two diametral forces.

Smooth ring (seed 003's model: rim of thickness delta between the root circle and the outer circle,
mid-layer radius r_m of eq 1) and toothed ring, 2D plane stress on ``Part.section`` (and 3D, coarser,
in ``fea/ring_solid.py``). Loads: the force pair F spread over a small arc (``fea/ring_loads.py``)
and the EWG's prescribed deformation (rigid contact strips pushed in by W0).

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

import time
from pathlib import Path

import numpy as np

from ..errors import StageError
from .assembly import Lame
from .convergence import grid_convergence
from .fields import field_info, write_solid_fields
from .meshing import MeshingFailed
from .result import Quantity, StudyResult
from .refinement import DEFAULT_RATIO, refinement_sizes
from .ring_loads import ArcLoad, point_load_factors, thin_ring_deflections_mm, thin_ring_moment_Nmm
from .ring_plane import RingGeometry, solve_ring_section

STUDY = "ring-compression"
REFINEMENT_RATIO = DEFAULT_RATIO    # every study refines at the one ratio of fea/refinement.py
SOLID_LAYERS = (4, 3, 2)    # 3D: P2 tets through the thickness, fine first (ratios 1.33, 1.5 > 1.3)


def ring_geometry(params) -> RingGeometry:
    """Rim radii from seed 003, eq 1: root circle 0.5 d_R + h_fR, r_m = root + delta/2, outer = root + delta."""
    e = params.ewg_drive
    r_root = 0.5 * e.module_mm * e.flexspline_teeth + e.dedendum_coefficient * e.module_mm
    return RingGeometry(r_root, r_root + e.rim_thickness_mm, r_root + 0.5 * e.rim_thickness_mm, e.face_width_mm)


def prescribed_w0_mm(params) -> float:
    """Seed 003, eq 7: W0 = 0.5 m dZ."""
    return 0.5 * params.ewg_drive.module_mm * params.ewg_drive.tooth_difference


def reference_force_N(params, geo: RingGeometry) -> float:
    """Thin-ring force for delta_CD = 2 W0 (seed 003, eqs 3 and 5 inverted); the FEA applies this F."""
    ei = params.material.youngs_modulus_MPa * geo.width_mm * geo.thickness_mm ** 3 / 12.0
    return 2.0 * prescribed_w0_mm(params) * ei / (point_load_factors()["delta_cd"] * geo.r_m_mm ** 3)


def contact_load(geo: RingGeometry, force_N: float) -> ArcLoad:
    """Each force spread over an arc of half-width delta/2 at the outer surface (a roller's contact is
    narrower still; delta/2 keeps the arc resolvable and moves M_D by only ~pi c/(4 r), see meta)."""
    return ArcLoad(force_N, 0.5 * geo.thickness_mm / geo.r_outer_mm, geo.r_outer_mm, geo.width_mm)


def section_face(params, *, teeth: bool):
    """The ring's 2D cross-section from geometry/ (``Part.section``)."""
    from ..geometry.parts import build_part
    return build_part("ewg-flexspline-ring", params, teeth=teeth).section


def mesh_sizes_mm(geo: RingGeometry, mesh_size_mm: float | None, quick: bool) -> tuple[float, float, float]:
    """Fine, medium, coarse. Default fine size delta/4 (delta/1.5 quick): a fibre stress sampled at h = delta/4
    is within 0.12 % of Winkler-Bach (0.67 % at delta/2), delta_CD within 1e-5 already at delta/2."""
    fine = mesh_size_mm if mesh_size_mm else geo.thickness_mm / (1.5 if quick else 4.0)
    return refinement_sizes(fine, REFINEMENT_RATIO)


def _scaled(sol, w0: float) -> dict[str, float]:
    """Force-case values scaled to delta_CD = 2 W0 (linear elasticity)."""
    k = 2.0 * w0 / sol.mid.delta_cd_mm
    return {"force_for_W0_N": sol.force_N * k,
            "sigma_B_outer_MPa": sol.sigma_B[0] * k, "sigma_B_inner_MPa": sol.sigma_B[1] * k,
            "sigma_D_outer_MPa": sol.sigma_D[0] * k, "sigma_D_inner_MPa": sol.sigma_D[1] * k,
            "outer_B_MPa": sol.outer_B_MPa * k, "outer_D_MPa": sol.outer_D_MPa * k,
            "root_B_MPa": sol.root_B_MPa * k, "root_D_MPa": sol.root_D_MPa * k}


def _series(face, geo, load, lame, sizes, order, w0, pitch, progress, label, keep_fields=False):
    out = []
    for k, h in enumerate(sizes):
        progress(f"{STUDY}: {label} ring, 2D plane stress, h = {h:.3g} mm")
        try:
            out.append(solve_ring_section(face, geo, load, lame, size_mm=h, order=order, ewg_w0_mm=w0,
                                          pitch_rad=pitch, keep_fields=keep_fields and k == 0))
        except MeshingFailed as exc:
            raise StageError("mesh", STUDY, f"{label} ring section, h = {h:g} mm: {exc}") from exc
    return out


def _quantity(name: str, unit: str, sizes, values) -> Quantity:
    conv = grid_convergence(list(sizes), list(values))
    return Quantity(name, float(values[0]), unit, conv)


def run(params, *, mesh_size_mm=None, order=2, crack_depth_mm=None, vtu=None, progress=lambda m: None,
        quick=False) -> StudyResult:
    t_start = time.perf_counter()
    geo = ring_geometry(params)
    w0 = prescribed_w0_mm(params)
    f_ref = reference_force_N(params, geo)
    load = contact_load(geo, f_ref)
    mat = params.material
    lame = Lame.from_young(mat.youngs_modulus_MPa, mat.poisson_ratio, plane_stress=True)
    pitch = 2.0 * np.pi / params.ewg_drive.flexspline_teeth
    sizes = mesh_sizes_mm(geo, mesh_size_mm, quick)
    # The smooth ring is cheap (2.9 to 4.4 s a mesh at delta/4), and its fibre stresses are sampled on the
    # boundary, where one or two P2 elements across the rim are 0.6 % off (sigma_B outer 153.31 MPa at
    # delta/1.5 and 153.29 at delta, non-monotone, against 152.44 at delta/4 and Winkler-Bach 152.4): it is
    # always solved on the full run's meshes, so --quick and the full run check the same numbers.
    smooth_sizes = mesh_sizes_mm(geo, mesh_size_mm, False)
    timings = {}
    t0 = time.perf_counter()
    smooth_face, toothed_face = section_face(params, teeth=False), section_face(params, teeth=True)
    timings["geometry"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    smooth = _series(smooth_face, geo, load, lame, smooth_sizes, order, w0, pitch, progress, "smooth",
                     vtu is not None)
    timings["smooth_2d"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    toothed = _series(toothed_face, geo, load, lame, sizes, order, w0, pitch, progress, "toothed", vtu is not None)
    timings["toothed_2d"] = time.perf_counter() - t0

    q: dict[str, Quantity] = {}
    # smooth-ring quantities converge with the smooth meshes; toothed/smooth ratios with the toothed ones
    add = lambda name, unit, vals: q.__setitem__(name, _quantity(name, unit, smooth_sizes, vals))   # noqa: E731
    add_t = lambda name, unit, vals: q.__setitem__(name, _quantity(name, unit, sizes, vals))   # noqa: E731
    add("delta_cd_mm", "mm", [s["force"].mid.delta_cd_mm for s in smooth])
    add("delta_ab_mm", "mm", [s["force"].mid.delta_ab_mm for s in smooth])
    sc = [_scaled(s["force"], w0) for s in smooth]
    tc = [_scaled(s["force"], w0) for s in toothed]
    for key in ("force_for_W0_N", "sigma_B_outer_MPa", "sigma_B_inner_MPa", "sigma_D_outer_MPa", "sigma_D_inner_MPa"):
        add(key, "N" if key.endswith("_N") else "MPa", [v[key] for v in sc])
    add_t("tooth_influence", "1", [(t["outer_D_MPa"] - t["outer_B_MPa"]) / (s["outer_D_MPa"] - s["outer_B_MPa"])
                                 for t, s in zip(tc, sc)])
    kd = [(t["outer_D_MPa"] - t["outer_B_MPa"]) / (s["outer_D_MPa"] - s["outer_B_MPa"]) for t, s in zip(tc, sc)]
    product = [(t["root_D_MPa"] - t["root_B_MPa"]) / (s["root_D_MPa"] - s["root_B_MPa"]) for t, s in zip(tc, sc)]
    add_t("root_stress_factor", "1", product)
    add_t("stress_concentration", "1", [p / k for p, k in zip(product, kd)])
    ewg = [s["ewg"] for s in smooth]
    add("ewg_force_N", "N", [e.force_N for e in ewg])
    for key, idx, sec in (("ewg_sigma_B_outer_MPa", 0, "B"), ("ewg_sigma_B_inner_MPa", 1, "B"),
                          ("ewg_sigma_D_outer_MPa", 0, "D"), ("ewg_sigma_D_inner_MPa", 1, "D")):
        add(key, "MPa", [(e.sigma_B if sec == "B" else e.sigma_D)[idx] for e in ewg])
    add_t("toothed_force_for_W0_N", "N", [t["force_for_W0_N"] for t in tc])
    add_t("toothed_ewg_force_N", "N", [s["ewg"].force_N for s in toothed])

    meta = _meta(params, geo, load, lame, smooth, toothed, sc, tc, w0, f_ref, sizes)
    meta["smooth_mesh_sizes_mm"] = list(smooth_sizes)
    # 3D solid (fea/ring_solid.py), in --quick too: 1.0 + 1.7 + 2.1 s for 2, 3, 4 layers (measured), and the
    # same meshes in both runs, so ring.delta_cd_3d reads the same number in both
    t0 = time.perf_counter()
    q3, meta["solid_3d"] = _solid_3d(params, geo, load, q, progress)
    q.update(q3)
    timings["solid_3d"] = time.perf_counter() - t0
    fine = smooth[0]["force"]
    fields = ()
    if vtu is not None:
        t0 = time.perf_counter()
        info = field_info(STUDY, f"diametral force F = {f_ref:g} N on the contact arcs (plane stress)",
                          params.material)
        fields = tuple(write_force_field(path, sol[0]["force"], lame, info)
                       for path, sol in zip(vtu_paths(vtu), (smooth, toothed)))
        timings["vtu"] = time.perf_counter() - t0
        meta["fields"] = {"force_case_N": f_ref, "files": [str(p) for p in fields],
                          "note": "force case at the reference force (delta_CD ~ 2 W0), finest mesh; plane stress"}
    timings["total"] = time.perf_counter() - t_start
    return StudyResult(STUDY, q, fine.mesh.quality, timings, fields, meta,
                       tuple(s["force"].mesh.quality for s in smooth))


def _solid_3d(params, geo, load, q2d, progress) -> tuple[dict[str, Quantity], dict]:
    """delta_CD, delta_AB of the smooth ring as a 3D solid (P2 tets, 2, 3, 4 elements through the
    thickness) at the same F, and their ratio to the 2D plane-stress values (expected in [1 - nu^2, 1])."""
    from .ring_solid import solve_ring_solid
    mat = params.material
    lame3 = Lame.from_young(mat.youngs_modulus_MPa, mat.poisson_ratio)
    sols = []
    for n in SOLID_LAYERS:
        progress(f"{STUDY}: smooth ring, 3D solid, {n} P2 tets through the thickness")
        sols.append(solve_ring_solid(geo, load, lame3, n_radial=n))
    h = [s.h_mm for s in sols]
    q = {"delta_cd_3d_mm": _quantity("delta_cd_3d_mm", "mm", h, [s.delta_cd_mm for s in sols]),
         "delta_ab_3d_mm": _quantity("delta_ab_3d_mm", "mm", h, [s.delta_ab_mm for s in sols])}
    fine = sols[0]
    nu = mat.poisson_ratio
    meta = {"model": "one-eighth ring (symmetry x = 0, y = 0, mid-plane), structured curved P2 tets, same arc "
                     "load uniform over the width; delta at r_m averaged over the width (Simpson on P2 nodes)",
            "layers": list(SOLID_LAYERS), "h_mm": h, "dofs": [s.mesh.dofs for s in sols],
            "elements": [s.mesh.elements for s in sols], "timings_s": [s.timings_s for s in sols],
            "ratio_cd_3d_over_2d": fine.delta_cd_mm / q2d["delta_cd_mm"].value,
            "ratio_ab_3d_over_2d": fine.delta_ab_mm / q2d["delta_ab_mm"].value,
            "ratio_cd_extrapolated": q["delta_cd_3d_mm"].convergence.extrapolated
            / q2d["delta_cd_mm"].convergence.extrapolated,
            "ratio_cd_midplane_over_2d": fine.delta_cd_midplane_mm / q2d["delta_cd_mm"].value,
            "ratio_cd_edge_over_2d": fine.delta_cd_edge_mm / q2d["delta_cd_mm"].value,
            "plane_strain_bound": 1.0 - nu ** 2,
            "B2_over_r_delta": geo.width_mm ** 2 / (geo.r_m_mm * geo.thickness_mm),
            "solver": fine.solver}
    return q, meta


def vtu_paths(vtu) -> tuple[Path, Path]:
    """(smooth, toothed) field files next to ``vtu``: <stem>_smooth.vtu first (the report's mid-layer plot)."""
    v = Path(vtu)
    return v.with_name(f"{v.stem}_smooth.vtu"), v.with_name(f"{v.stem}_toothed.vtu")


def write_force_field(path, sol, lame: Lame, info=None) -> Path:
    """Displacement, von Mises and stress (plane stress, zz = 0) of one 2D force-case solve, as VTU."""
    sk, u = sol.fields
    return write_solid_fields(path, sol.mesh, sk, u, lame, info=info)


def _meta(params, geo, load, lame, smooth, toothed, sc, tc, w0, f_ref, sizes) -> dict:
    """Everything a reader needs to reproduce or interpret the numbers: load, BCs, thin-ring references."""
    mat = params.material
    ei = mat.youngs_modulus_MPa * geo.width_mm * geo.thickness_mm ** 3 / 12.0
    cd_arc, ab_arc = thin_ring_deflections_mm(load, geo.r_m_mm, ei)
    m_arc = thin_ring_moment_Nmm(np.array([0.0, 0.5 * np.pi]), load, geo.r_m_mm)
    pf = point_load_factors()
    fs, ft = smooth[0], toothed[0]
    return {
        "model": "2D plane stress, whole ring, curved P2 triangles, thickness = face width B",
        "geometry": {"r_root_mm": geo.r_root_mm, "r_outer_mm": geo.r_outer_mm, "r_m_mm": geo.r_m_mm,
                     "rim_thickness_mm": geo.thickness_mm, "width_mm": geo.width_mm,
                     "r_m_over_delta": geo.r_m_mm / geo.thickness_mm,
                     "smooth_equivalent": "rim between root circle and outer circle (seed 003 eq 1); teeth ignored"},
        "material": {"E_MPa": mat.youngs_modulus_MPa, "nu": mat.poisson_ratio,
                     "G_implied_MPa": mat.implied_shear_modulus_MPa, "G_seed_MPa": mat.shear_modulus_MPa},
        "W0_mm": w0, "reference_force_N": f_ref,
        "load": {"profile": "elliptical pressure, normal to the outer surface", "half_angle_rad": load.half_angle_rad,
                 "half_width_mm": load.half_angle_rad * load.radius_mm, "peak_pressure_MPa": load.peak_pressure_MPa},
        "supports": "u_y(A) = u_y(B) = 0, u_x(D) = 0 at outer-surface nodes on the symmetry axes (no reaction "
                    "in the symmetric solution); C free",
        "ewg_case": "rigid flat contact strips (the load arcs) pushed radially by W0 at the outer surface, "
                    "tangential motion free",
        "thin_ring_arc_load": {"delta_cd_mm": cd_arc, "delta_ab_mm": ab_arc, "moment_B_Nmm": float(m_arc[0]),
                               "moment_D_Nmm": float(m_arc[1]),
                               "moment_D_over_point_load": float(m_arc[1] / (pf["moment_D"] * f_ref * geo.r_m_mm)),
                               "delta_cd_over_point_load": cd_arc / (pf["delta_cd"] * f_ref * geo.r_m_mm ** 3 / ei)},
        "symmetry_uy_C_plus_D_mm": float(fs["force"].mid.u_C_mm[1] + fs["force"].mid.u_D_mm[1]),
        "ewg_mid_layer_W0_mm": float(fs["ewg"].mid.delta_cd_mm / 2),
        "tooth_stiffness_ratio": tc[0]["force_for_W0_N"] / sc[0]["force_for_W0_N"],
        "toothed_delta_cd_mm": ft["force"].mid.delta_cd_mm, "toothed_delta_ab_mm": ft["force"].mid.delta_ab_mm,
        "per_section_factors": {
            "K_delta_B": tc[0]["outer_B_MPa"] / sc[0]["outer_B_MPa"],
            "K_delta_D": tc[0]["outer_D_MPa"] / sc[0]["outer_D_MPa"],
            "K_sigma_B": tc[0]["root_B_MPa"] / sc[0]["root_B_MPa"],
            "K_sigma_D": tc[0]["root_D_MPa"] / sc[0]["root_D_MPa"]},
        "toothed_scaled_to_W0_MPa": {k: v for k, v in tc[0].items() if k != "force_for_W0_N"},
        "mesh_sizes_mm": list(sizes),
        "toothed_mesh": ft["force"].mesh.quality.to_dict(),
        "solver": fs["force"].solver,
    }
