"""Study `wg-bearing` (issue 34, item 3): the wave generator bearing's inner ring on the elliptical cam.

Model: the ring's cross-section in its mid-plane (normal to the axis), plane stress with thickness = the ring
width B (the ring's faces are free), P2 on a structured polar mesh (``fea.ring2d``); radii and width follow
the CAD (``geometry.bearing_ring``). Loads, all inputs (fea/ holds no closed form):
- the cam: the bore's radial displacement is w0 cos 2phi (frictionless: tangential free);
- the balls: Hertz line patches p = 2Q/(pi b B) sqrt(1 - (s/b)^2) on the race at the ball angles, the ball
  loads Q_i and half-widths b_i given (Stribeck's law, ``analytic.study_loads.wg_bearing_load``);
- the race crack at the major axis (phi = 0, under the load-line ball), an edge crack of depth a through the
  width, faces in frictionless contact: it opens or shuts with the net hoop stress.
Quantities, each on three meshes (GCI): the race hoop stress at both axes under the cam alone; the ball-load
distribution when the balls are Hertz springs (Q = K_n delta^(3/2)) between this ring and a rigid outer race
(the ring's flexibility at the balls from the FEA, the spring law given); the radial compliance
C = f.(u(cam + F) - u(cam))/F^2 (f: the Stribeck patches) and its crack increment per depth.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from strainwave.errors import InputError
from strainwave.fea import ring2d
from strainwave.fea.refinement import CRACK_FORMAL_ORDER, DEFAULT_RATIO, converged_quantity
from strainwave.fea.result import CrackRecord, Load, MeshQuality, StudyResult, Support
from strainwave.fea.study_facts import StudyFacts

STUDY = "wg-bearing"
GROWTH = 0.4            # element growth per unit distance away from the crack tip and the race
TIP_OVER_A = 0.125       # crack-tip element size on the finest mesh, times a


@dataclass(frozen=True)
class RingSetup:
    r_bore_mm: float
    r_race_mm: float
    width_mm: float
    E_MPa: float
    nu: float
    w0_mm: float
    force_N: float
    ball_angles_rad: tuple[float, ...]
    ball_loads_N: tuple[float, ...]
    patch_half_widths_mm: tuple[float, ...]
    hertz_constant: float                    # K_n of Q = K_n delta^(3/2), one ball between two races
    ball_count: int                          # Z (the loaded balls are those with |psi| < 90 deg)
    race_over_b: float = 0.5                 # race element size over the load-line ball's patch half-width b

    @property
    def thickness_mm(self) -> float:
        return self.r_race_mm - self.r_bore_mm


def setup_from(params, *, force_N, w0_mm, ball_angles_rad, ball_loads_N, patch_half_widths_mm,
               hertz_constant, ball_count) -> RingSetup:
    from strainwave.geometry.bearing_ring import check_ring_fits

    wg, mat = params.wave_generator, params.material
    r_race, r_bore = check_ring_fits(params)
    return RingSetup(r_bore, r_race, wg.bearing_width_mm, mat.youngs_modulus_MPa,
                     mat.poisson_ratio, float(w0_mm), float(force_N), tuple(ball_angles_rad), tuple(ball_loads_N),
                     tuple(patch_half_widths_mm), float(hertz_constant), int(ball_count))


def _sizer(near_mm: float, focus: float, far_mm: float, flat_mm: float = 0.0):
    """Size ``near_mm`` within ``flat_mm`` of ``focus``, growing by GROWTH per mm beyond, at most ``far_mm``."""
    return lambda x: min(far_mm, near_mm + GROWTH * max(0.0, abs(x - focus) - flat_mm))


def _radial_nodes(s: RingSetup, far_mm: float, race_mm: float, tip_mm: float, crack_mm: float | None):
    r_o, r_i = s.r_race_mm, s.r_bore_mm
    if not crack_mm:
        return r_o - ring2d.graded_nodes(0.0, r_o - r_i, _sizer(race_mm, 0.0, far_mm))[::-1], None
    r_tip = r_o - crack_mm
    below = r_tip - ring2d.graded_nodes(0.0, r_tip - r_i, _sizer(tip_mm, 0.0, far_mm, 0.5 * crack_mm))[::-1]
    near_tip, near_race = _sizer(tip_mm, r_tip, far_mm, crack_mm), _sizer(race_mm, r_o, far_mm)
    above = ring2d.graded_nodes(r_tip, r_o, lambda x: min(near_tip(x), near_race(x)))
    return np.concatenate([below[:-1], above]), len(below) - 1


def grid(s: RingSetup, h_mm: float, scale: float, crack_mm: float | None):
    """(radial nodes, angular columns 0..2pi, tip index or None): global size h scale, race size
    min(h, b/2) scale (b: the load-line ball's patch; 0.7 b with --quick), tip size a/8 scale over the crack's depth and
    within a of it, graded beyond;
    the loaded half (|phi| < 90 deg + 0.2 rad) keeps the race size, the rest grows to 2 h."""
    far = h_mm * scale
    race = min(h_mm, s.race_over_b * max(s.patch_half_widths_mm)) * scale
    tip = min(race, TIP_OVER_A * crack_mm * scale) if crack_mm else race
    r, tip_index = _radial_nodes(s, far, race, tip, crack_mm)
    r_o, edge = s.r_race_mm, s.r_race_mm * (0.5 * math.pi + 0.2)
    loaded = lambda arc: min(2.0 * far, race + GROWTH * max(0.0, arc - edge))     # noqa: E731
    near = _sizer(tip, 0.0, far, crack_mm or 0.0)
    quarter = ring2d.graded_nodes(0.0, 0.5 * math.pi * r_o, lambda arc: min(loaded(arc), near(arc)))
    second = math.pi * r_o - ring2d.graded_nodes(0.0, 0.5 * math.pi * r_o, lambda arc: loaded(math.pi * r_o - arc))
    half = np.concatenate([quarter, second[::-1][1:]]) / r_o
    phi = np.concatenate([half, 2.0 * math.pi - half[::-1][1:]])
    return r, phi, tip_index


def _system(s: RingSetup, r, phi, tip):
    mesh, pairs = ring2d.ring_mesh(r, phi, tip)
    return ring2d.assemble(mesh, pairs, E_MPa=s.E_MPa, nu=s.nu, width_mm=s.width_mm, r_bore_mm=s.r_bore_mm)


def cam_displacement_mm(system, w0_mm: float) -> np.ndarray:
    """w0 cos 2phi at every bore dof (radial, outward +)."""
    xy = system.scalar.doflocs[:, system.bore_dofs]
    return w0_mm * np.cos(2.0 * np.arctan2(xy[1], xy[0]))


def _race_points(s: RingSetup, angles, system) -> np.ndarray:
    """Race vertices nearest the angles (the race is a polygon through them), a hair inside."""
    p = system.scalar.mesh.p
    on = np.flatnonzero(np.abs(np.hypot(*p) - s.r_race_mm) < 1e-7 * s.r_race_mm)
    ang = np.arctan2(p[1, on], p[0, on])
    pick = on[[int(np.argmin(np.abs(np.angle(np.exp(1j * (ang - a)))))) for a in angles]]
    return p[:, pick] * (1.0 - 1e-9)


def coupled_ball_loads(G: np.ndarray, psi: np.ndarray, force_N: float, K_n: float, start_N: np.ndarray):
    """Balls as Hertz springs Q_i = K_n (delta_0 cos psi_i - (G Q)_i)_+^(3/2) between the ring (flexibility G
    at the balls, mm/N) and a rigid outer race moved by delta_0 along psi = 0; sum Q_i cos psi_i = F.
    Returns (Q, delta_0)."""
    from scipy.optimize import fsolve

    c = np.cos(psi)
    d0 = (start_N.max() / K_n) ** (2.0 / 3.0)

    def residual(x):
        q, d = x[:-1] * start_N.max(), x[-1] * d0
        approach = np.clip(d * c - G @ q, 0.0, None)
        return np.append(q / start_N.max() - K_n * approach ** 1.5 / start_N.max(), (q @ c - force_N) / force_N)

    x, info, ok, msg = fsolve(residual, np.append(start_N / start_N.max(), 1.0), full_output=True, xtol=1e-12)
    if ok != 1:
        raise RuntimeError(f"{STUDY}: coupled ball loads did not converge ({msg})")
    return x[:-1] * start_N.max(), x[-1] * d0


def solve_plain(s: RingSetup, h_mm: float, scale: float, profile_depth_mm: float) -> dict:
    """The uncracked ring on one refinement: cam stresses, ball flexibility, coupled ball loads, compliance,
    and the hoop stress per newton along the crack line (phi = 0) from the race down to ``profile_depth_mm``."""
    system = _system(s, *grid(s, h_mm, scale, None))
    F = ring2d.patch_load_vectors(system, s.r_race_mm, s.ball_angles_rad, s.patch_half_widths_mm)
    # the cam alone first, then each ball's patch: one factorisation
    U = ring2d.solve_many(system, F, bore_radial_mm=cam_displacement_mm(system, s.w0_mm))
    u_cam, U = U[:, 0], U[:, 1:]
    q = np.asarray(s.ball_loads_N)
    u_f = U @ q
    G = F.T @ U
    q_fea, d0 = coupled_ball_loads(G, np.asarray(s.ball_angles_rad), s.force_N, s.hertz_constant, q)
    st_cam, st_f = ring2d.nodal_stress(system, np.column_stack([u_cam, u_f]), s.E_MPa, s.nu)
    race = _race_points(s, (0.0, 0.5 * math.pi), system)
    cam = ring2d.hoop_stress_at(system, st_cam, race)
    bore = ring2d.hoop_stress_at(system, st_cam, np.array([[s.r_bore_mm * (1 + 1e-9)], [0.0]]))
    ring_phi = np.linspace(0.0, 2.0 * math.pi, 73)[:-1]
    all_round = ring2d.hoop_stress_at(system, st_cam + st_f, _race_points(s, ring_phi, system))
    x = profile_depth_mm * np.linspace(0.0, 1.0, 121) ** 2      # dense at the race, where the patch acts
    line = np.array([s.r_race_mm * (1 - 1e-9) - x, 0 * x])
    profile = ring2d.hoop_stress_at(system, st_f, line) / s.force_N
    f = F @ q
    return {"race_major_MPa": float(cam[0]), "race_minor_MPa": float(cam[1]), "bore_major_MPa": float(bore[0]),
            "net_race_major_MPa": float(all_round[0]), "compliance": float(f @ u_f) / s.force_N ** 2,
            "ball_ratio": float(q_fea.max()) * s.ball_count / s.force_N, "radial_stiffness": s.force_N / d0,
            "_ball_loads": q_fea, "_net_round": (ring_phi, all_round), "_profile": (x, profile),
            "_dofs": system.K.shape[0], "_elements": system.scalar.mesh.t.shape[1],
            "_nodes": system.scalar.N, "_quality": ring2d.triangle_quality(system.scalar.mesh),
            "_system": system, "_u": u_cam + u_f, "_stress": st_cam + st_f}


def write_fields(vtu, s: RingSetup, plain: dict, material) -> Path:
    """The uncracked ring of ``plain`` (a ``solve_plain`` result) on the cam under the Stribeck ball loads:
    displacement, stress tensor (plane stress: zz = 0), von Mises, principal and hoop stress at the P2 nodes,
    with the boundary groups bore and race (NAME.boundary.vtu)."""
    from strainwave.fea.fields import field_info, stress_fields, write_vtu

    md = ring2d.mesh_data(plain["_system"], s.r_bore_mm, s.r_race_mm)
    u, st, zero = plain["_u"], plain["_stress"], np.zeros(md.nodes_mm.shape[0])
    tensor = np.column_stack([st[0], st[1], zero, st[2], zero, zero])
    point_data = {"displacement_mm": np.column_stack([u[0::2], u[1::2], zero]), **stress_fields(tensor),
                  "hoop_stress_MPa": ring2d.hoop_stress(md.nodes_mm[:, :2].T, st)}
    info = field_info(STUDY, f"{_load(s).describe()}; uncracked ring, finest mesh", material)
    return write_vtu(Path(vtu), md, point_data, info=info)


def _ball_count(s: RingSetup) -> int:
    return s.ball_count


def solve_crack(s: RingSetup, h_mm: float, scale: float, depth_mm: float, *, profile: bool = True,
                compressed: bool = False) -> dict:
    """One crack depth on one refinement, every state from one factorisation with the Schur complement S on the
    crack pairs' openings (``ring2d.seam_system``): the compliance under the ball loads on the cracked mesh (faces
    in contact, cam then cam + balls, each contact set a dense solve of S) minus the same mesh merged (every pair
    held). The cam and the balls are one back-substitution; ``profile``: the uncracked hoop stress per newton on
    the crack line too; ``compressed``: the same crack with the cam reversed (w0 -> -w0), under "compressed"."""
    cracked = _system(s, *grid(s, h_mm, scale, depth_mm))
    q = np.asarray(s.ball_loads_N)
    f = ring2d.patch_load_vectors(cracked, s.r_race_mm, s.ball_angles_rad, s.patch_half_widths_mm) @ q
    seam = ring2d.seam_system(cracked)
    try:
        cam = ring2d.bore_load(cracked, cam_displacement_mm(cracked, s.w0_mm))
        ft = seam.T.T @ np.column_stack([cracked.R.T @ f, cam])
        v = seam.faces.free_solution(ft)          # the balls, then the cam: the faces free
        r_f, r_cam = seam.faces.condensed(v).T
        u0 = cracked.R @ seam.solution(ft[:, 0], r_f, np.ones(r_f.size, bool)) if profile else None
    finally:
        seam.close()
    free, face = seam.faces.free, seam.faces.face_z
    # f.u with every pair held: f.u with the openings free less their share
    c0 = float(ft[free, 0] @ v[free, 0] - v[face, 0] @ r_f) / s.force_N ** 2
    mouth = int(np.argmax(np.hypot(*cracked.scalar.doflocs[:, cracked.pairs.minus])))

    def states(sign: float) -> dict:
        # each state's threshold from its own faces-free solution, as ``SeamSystem.contact`` takes it
        tol = [1e-9 * float(np.abs(seam.T @ (sign * v[:, 1] + balls * v[:, 0])).max()) for balls in (0.0, 1.0)]
        _, _, force_base, _, _ = seam.settle(sign * r_cam, tol[0])
        active, gap, force, _, _ = seam.settle(sign * r_cam + r_f, tol[1])
        return {"delta": ring2d.crack_work(seam, r_f, force_base, force) / s.force_N ** 2, "uncracked": c0,
                "closed_pairs": int(active.sum()), "pairs": int(active.size), "mouth_opening_mm": float(gap[mouth]),
                "dofs": cracked.R.shape[0]}

    out = states(1.0)
    if profile:     # the uncracked hoop stress per newton on the crack line, on this mesh: the closed form's input
        x = depth_mm * np.linspace(0.0, 1.0, 65)
        stress = ring2d.nodal_stress(cracked, u0, s.E_MPa, s.nu)
        line = np.array([s.r_race_mm * (1 - 1e-9) - x, 0 * x + 1e-9])
        out["profile"] = (x, ring2d.hoop_stress_at(cracked, stress, line) / s.force_N)
    if compressed:
        out["compressed"] = states(-1.0)
    return out


# Crack depths of the sweep: up to a_max = 0.1 t (the back face, held by the cam, stays a small allowance,
# analytic.wg_bearing.back_face_allowance), three geometric depths a_max/8 .. a_max, plus the seed's a.
SWEEP_OVER_T = 0.1


def sweep_depths_mm(params, quick: bool) -> tuple[float, ...]:
    """Quick: a_max. Full: the seed's a (when below a_max) and a_max/8, a_max/2.83, a_max."""
    t = params.wave_generator.bearing_inner_ring_thickness_mm
    deepest = SWEEP_OVER_T * t
    depths = (deepest,) if quick else np.geomspace(deepest / 8.0, deepest, 3)
    out = {float(f"{d:.3g}") for d in depths}
    seed = params.wave_generator.bearing_crack_depth_mm
    if not quick and seed < deepest:
        out.add(float(seed))
    return tuple(sorted(out))


def delta_name(depth_mm: float) -> str:
    return f"delta_radial_compliance_a{depth_mm:g}_mm_per_N"


def default_size_mm(params, quick: bool) -> float:
    """Finest global size: t/8 (t/6 with --quick)."""
    return params.wave_generator.bearing_inner_ring_thickness_mm / (6.0 if quick else 8.0)


class WgBearing(StudyFacts):
    """The ring on the cam's facts (its solve is ``run``, not the skeleton: it sweeps its own crack depths)."""

    study = STUDY
    # graded to the race patches and the crack tip: the cracked quick mesh at a = 1 mm, h = 1.67 mm (12)
    elements_per_cell = 12.0
    cpu_s_per_element = (1.9e-4, 8.0e-5)   # full, --quick: validate's schedule (decisions 049, 059)
    default_size_mm = staticmethod(default_size_mm)
    plane = True
    # solved at the rated F_r already (scale 1: the cam's share is not linear in F_r)
    rated_load = "strainwave.analytic.rated_load:rated_radial_force"
    report_component = "bearing"
    title = "bearing inner ring on the cam"
    image_marks = (("bore",), None, "F_r")     # the ball patches are too small to mark at the ring's scale
    signed_stress = ("hoop_stress_MPa", "hoop stress")     # the cam's bending: tension or compression
    outside_design = ("the ring on the cam has its own design factor (compare/validate/design_fea.py): Goodman on the "
                      "cam's steady hoop stress at the race and the swing the passing balls add; its contact is rated "
                      "by ISO 281/76; a peak von Mises taken as fully reversed would count the cam's mean as an amplitude")
    element_text = ("P2 triangles on a graded polar grid, 2D plane stress, thickness = ring width B; race crack as "
                    "two coincident faces with frictionless contact")

    @classmethod
    def volume_and_wall(cls, params) -> tuple[float, float]:
        from strainwave.fea.bearing_ring import race_section_mm2
        return race_section_mm2(params)     # the plane section, per mm of width


def _converge(name, unit, sizes, values, order=None):
    return converged_quantity(name, unit, sizes, values, order=order)


def _plain_quantities(s: RingSetup, h: float, sizes, progress, deepest_mm: float):
    runs = []
    for k in (2, 1, 0):
        progress(f"{STUDY}: uncracked ring on the cam, refinement {3 - k}/3 (h = {h * DEFAULT_RATIO ** k:.3g} mm)")
        runs.append(solve_plain(s, h, DEFAULT_RATIO ** k, deepest_mm))
    runs = runs[::-1]
    names = {"race_major_MPa": ("race_stress_major_MPa", "MPa"), "race_minor_MPa": ("race_stress_minor_MPa", "MPa"),
             "bore_major_MPa": ("bore_stress_major_MPa", "MPa"), "net_race_major_MPa": ("net_race_stress_major_MPa", "MPa"),
             "ball_ratio": ("ball_load_ratio", "1"), "radial_stiffness": ("radial_stiffness_N_per_mm", "N/mm"),
             "compliance": ("radial_compliance_mm_per_N", "mm/N")}
    q = {name: _converge(name, unit, sizes, [r[key] for r in runs]) for key, (name, unit) in names.items()}
    return q, runs[0]


def _crack_quantities(s: RingSetup, h: float, sizes, depths, progress):
    """Each depth's increment on three meshes, its finest mesh's facts, and (first principles: under the cam's
    compression, w0 -> -w0, the crack shuts; the coarsest mesh suffices) the deepest crack with the cam reversed."""
    q, facts, compressed = {}, {}, None
    for depth in depths:
        runs = []
        for k in (2, 1, 0):
            progress(f"{STUDY}: crack a = {depth:g} mm, refinement {3 - k}/3")
            runs.append(solve_crack(s, h, DEFAULT_RATIO ** k, depth, profile=k == 0,
                                    compressed=k == 2 and depth == max(depths)))
        compressed = runs[0].pop("compressed", compressed)
        runs = runs[::-1]
        name = delta_name(depth)
        q[name] = _converge(name, "mm/N", sizes, [r["delta"] for r in runs], CRACK_FORMAL_ORDER)
        x, profile = runs[0]["profile"]
        facts[f"{depth:g}"] = {"depth_mm": depth, "closed_pairs": runs[0]["closed_pairs"], "pairs": runs[0]["pairs"],
                               "mouth_opening_mm": runs[0]["mouth_opening_mm"], "dofs": runs[0]["dofs"],
                               "profile_x_mm": x.tolist(), "hoop_stress_per_N_MPa": profile.tolist()}
    return q, facts, compressed


def run(params, *, force_N: float, w0_mm: float, ball_angles_rad, ball_loads_N, patch_half_widths_mm,
        hertz_constant: float, ball_count: int, mesh_size_mm=None, order=2, crack_depth_mm=None, vtu=None,
        progress=lambda m: None, quick=False) -> StudyResult:
    """The ring on the cam under the Stribeck ball loads, uncracked and with the sweep's race cracks, each on
    three meshes. ``crack_depth_mm`` must be None: the study sweeps its own depths (``sweep_depths_mm``)."""
    if order != 2:
        raise InputError("--order", order, f"study {STUDY} is P2 only")
    if crack_depth_mm is not None:
        raise InputError("--crack-depth-mm", crack_depth_mm, f"study {STUDY} sweeps its own crack depths; leave it out")
    s = setup_from(params, force_N=force_N, w0_mm=w0_mm, ball_angles_rad=ball_angles_rad, ball_loads_N=ball_loads_N,
                   patch_half_widths_mm=patch_half_widths_mm, hertz_constant=hertz_constant, ball_count=ball_count)
    h = mesh_size_mm or default_size_mm(params, quick)
    if quick:     # three race elements per patch: the quick case stays within its time limit on a loaded machine
        s = replace(s, race_over_b=0.7)
    sizes = [h * DEFAULT_RATIO ** k for k in range(3)]
    depths = sweep_depths_mm(params, quick)
    t0 = time.perf_counter()
    q, finest = _plain_quantities(s, h, sizes, progress, max(depths))
    t1 = time.perf_counter()
    qc, facts, compressed = _crack_quantities(s, h, sizes, depths, progress)
    t2 = time.perf_counter()
    phi, net = finest["_net_round"]
    meta = {"model": "2D plane stress (thickness = ring width B), the ring's mid-plane cross-section, P2",
            "r_bore_mm": s.r_bore_mm, "r_race_mm": s.r_race_mm, "width_mm": s.width_mm, "w0_mm": s.w0_mm,
            "ball_count": s.ball_count, "ball_angles_deg": np.degrees(s.ball_angles_rad).tolist(),
            "ball_loads_stribeck_N": list(s.ball_loads_N), "ball_loads_fea_N": finest["_ball_loads"].tolist(),
            "patch_half_widths_mm": list(s.patch_half_widths_mm), "hertz_constant_N_per_mm1_5": s.hertz_constant,
            "crack_depths_mm": list(depths), "cracks": facts, "compressed_crack": {"w0_mm": -s.w0_mm,
            "depth_mm": max(depths), **compressed},
            "net_race_hoop_stress": {"phi_deg": np.degrees(phi).tolist(), "MPa": net.tolist()}}
    mesh = MeshQuality(finest["_elements"], finest["_nodes"], finest["_dofs"], 2, *finest["_quality"])
    # the crack sweep's fields are not kept: the one field is the uncracked ring, named so (rated_stress)
    fields = () if vtu is None else (write_fields(Path(vtu).with_name(f"{Path(vtu).stem}_uncracked.vtu"), s, finest,
                                                  params.material),)
    return StudyResult(STUDY, {**q, **qc}, mesh, _load(s), _supports(),
                       CrackRecord(max(depths), "2D edge crack at the major axis, frictionless face contact, "
                                   "sweep of depths (each on three meshes)"),
                       {"uncracked": t1 - t0, "cracks": t2 - t1}, fields, {}, meta, (mesh,) * 3)


def _load(s: RingSetup) -> Load:
    return Load("wave generator radial force F_r (ball loads) on the cam-forced ring", s.force_N, "N", ("race",),
                f"Stribeck (zero clearance): Q_i = Q_max cos^1.5 psi_i on {len(s.ball_loads_N)} loaded balls, Hertz "
                "line patches 2Q/(pi b B) sqrt(1 - (s/b)^2); plus the cam: bore radial displacement w0 cos 2phi",
                (("w0_mm", s.w0_mm), ("ball_count", float(s.ball_count)), ("q_max_N", float(max(s.ball_loads_N)))))


def _supports() -> tuple[Support, ...]:
    return (Support(("bore",), "radial displacement w0 cos 2phi (the elliptical cam), tangential free "
                               "(frictionless), the bore's tangential displacement at phi = 0 held (symmetry line)"),)
