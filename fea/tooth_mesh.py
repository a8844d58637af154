"""Study ``tooth-mesh``: the teeth in mesh, from the FE flank compliance to the drive's torque-twist loop.

Per mesh (three, one ratio): the flexspline's toothed rim on a rigid wave generator and a sector of the
circular spline's teeth (fea/tooth_mesh_fe.py) give the flank influence of tooth 0 on every tooth at a grid
of contact radii; the teeth are alike, so tooth j on tooth k is the influence of k - j. At each
wave-generator angle the kinematic engagement (analytic/mesh_engagement.py, passed in as numbers by the
registry's ``load_inputs``) names the flank pairs, their contact radii, unloaded clearances, levers and
slides; the 2 x 2 band flexibility of those pairs (normal and tangential; FS rim + CS teeth, in series) and the
frictional contact solve along 0 -> +T -> -T -> +T with Coulomb on the true slip (fea/mesh_friction.py,
decision 073-slipstudy48; not a closed form) give the loop. Every reported number is that chain on one mesh,
so each carries its GCI.

Read from the loop with compare/diagnose/catalogue_values.py's rules (the same as a recording):
K1, K2, K3, T1, T2, lost motion at +/-4 % rated, flank friction's work per cycle. Also: the transmission error (the twist
at the rated torque over one tooth-passing period of the WG, which repeats Z_c times per WG revolution),
the teeth in contact and the largest tooth's share at rated torque, and the single pair's compliance at
the major axis (the checks' number).
"""
from __future__ import annotations

import math
import time
from typing import ClassVar, Mapping

import numpy as np

from strainwave.fea.assembly import Lame
from strainwave.fea.convergence import Convergence
# the exact loop on the reader's fixed torque grid: one implementation, shared with the catalogue's curve
from strainwave.fea.mesh_loop import READ_STEPS_PER_LEG, resampled_loop
from strainwave.fea.mesh_loop import branch_twist as _branch_twist
from strainwave.fea.result import Load, MeshQuality, Quantity, StudyResult, Support
from strainwave.fea.skeleton import MeshSolve, Series, SeriesPlan, StudyVariant, check_variant, run_variant
from strainwave.fea.study_facts import TORQUE_RATED
from strainwave.fea import tooth_mesh_fe as fe

STUDY = "tooth-mesh"
# finest element size over the module, then x1.4 twice (the project's ratio)
H_OVER_M = {False: 0.30, True: 0.42}
RATIO = 1.4
N_RADII = 5                       # contact radii of the influence grid
BAND_OVER_M = 0.2                 # half-width of a unit flank load's parabolic band, over m
CS_NEIGHBOURS = 2                 # CS teeth either side whose coupling is kept (thick rim: it decays fast)
QUANTITIES = (
    ("pair_compliance_major_mm_per_N", "mm/N"), ("fs_tooth_compliance_major_mm_per_N", "mm/N"),
    ("cs_tooth_compliance_major_mm_per_N", "mm/N"), ("fs_coupling_next_ratio", "1"),
    ("K1_Nmm_per_rad", "N*mm/rad"), ("K2_Nmm_per_rad", "N*mm/rad"), ("K3_Nmm_per_rad", "N*mm/rad"),
    ("T1_Nmm", "N*mm"), ("T2_Nmm", "N*mm"), ("secant_stiffness_rated_Nmm_per_rad", "N*mm/rad"),
    ("lost_motion_arcmin", "arcmin"), ("friction_loss_per_cycle_Nmm", "N*mm"),
    ("transmission_error_pp_rad", "rad"), ("teeth_in_contact_rated", "1"), ("peak_tooth_share", "1"),
    ("peak_tooth_load_N", "N"), ("pair_stiffness_solid_N_per_mm_um", "N/(mm*um)"),
    ("pair_stiffness_internal_N_per_mm_um", "N/(mm*um)"),
    ("crack_tooth_compliance_ratio", "1"), ("crack_te_peak_rad", "rad"),
    ("rigid_rim_peak_tooth_share", "1"), ("rigid_rim_teeth_in_contact", "1"), ("rigid_rim_twist_rated_rad", "rad"),
    ("engagement_edge_rated_rad", "rad"), ("engagement_edge_first_step_rad", "rad"),
    ("ratcheting_torque_Nmm", "N*mm"), ("ratcheting_lift_rated_mm", "mm"), ("ratcheting_overlap_mm", "mm"),
    ("root_stress_peak_tooth_MPa", "MPa"), ("root_stress_per_N_MPa", "MPa/N"), ("root_contact_radius_mm", "mm"),
)
# the knees are read on the exact loop with the dead band taken out (decision 073): they no longer follow the torque
# step; T1 alone still moves with the reader's own torque grid (400 -> 800 a leg: +0.69 % / +0.35 % on the two
# gears, 200 -> 400 -0.41 % / -0.68 %: over the rule's 0.5 %), so it keeps the refusal: value kept, no GCI claimed
STEP_LIMITED = ("T1_Nmm",)
STEP_LIMITED_WHY = ("the reader's T1 moves 0.4-0.7 % with its own torque grid (200 / 400 / 800 a leg on the exact "
                    "loop), over the 0.5 % fixed before (decision 073)")
# friction on the true slip (fea/mesh_friction.torque_path): torque increments per history step. The path is
# split at every state change (decision 078-slipknots48), so it does not depend on them: 1 reads the knees and
# friction's work as 4 does to 1.5e-9 at 40 % of the cost (4 was needed when the knots were the increments' ends)
INCREMENTS = 1
SECTOR_H_RATIO = 0.5              # the sectors' element size over the rim's
SOLID_DEPTH_OVER_M = 6.0          # the FS tooth's solid-body sector is held this deep below its root (ISO's body)


def refinements(module_mm: float, quick: bool) -> tuple[float, float, float]:
    h = H_OVER_M[bool(quick)] * module_mm
    return (h, h * RATIO, h * RATIO ** 2)


def radii_grids(mesh: Mapping) -> tuple[np.ndarray, np.ndarray]:
    """FS (own frame) and CS contact radii of the influence grids: the span the engagement's contact points use,
    kept a band inside each tooth's tip."""
    lo, hi = mesh["fs_radius_range_mm"]
    band = BAND_OVER_M * mesh["module_mm"]
    fs = np.linspace(lo, min(hi, mesh["fs_tip_mm"] - band), N_RADII)
    clo, chi = mesh["cs_radius_range_mm"]
    cs = np.linspace(max(clo, mesh["cs_tip_mm"] + band), chi, N_RADII)
    return fs, cs


def _interp_weights(grid: np.ndarray, r: np.ndarray) -> np.ndarray:
    """(n, len(grid)) linear interpolation weights (clamped at the ends)."""
    r = np.clip(r, grid[0], grid[-1])
    i = np.clip(np.searchsorted(grid, r) - 1, 0, len(grid) - 2)
    t = (r - grid[i]) / (grid[i + 1] - grid[i])
    W = np.zeros((r.size, grid.size))
    W[np.arange(r.size), i] = 1.0 - t
    W[np.arange(r.size), i + 1] = t
    return W


def pair_compliance(infl: Mapping, pairs: Mapping, z_f: int, z_c: int) -> np.ndarray:
    """(n, n) compliance of the flank pairs (FS rim + CS teeth): side +1 pairs first, then -1.

    ``infl``: fs_same[d, a, b], fs_other[d, a, b] (load on a +1 flank, measured on +1 / -1 flanks), cs[d, a, b]
    (CS tooth d from the loaded one, same flank side); the mirror image gives the -1 loads."""
    side, tooth, space = pairs["side"], pairs["tooth"], pairs["cs_space"]
    Wf = _interp_weights(infl["fs_radii"], pairs["fs_radius_mm"])
    Wc = _interp_weights(infl["cs_radii"], pairs["cs_radius_mm"])
    d = (tooth[None, :] - tooth[:, None])
    same = side[:, None] == side[None, :]
    # mirror about the loaded tooth: a -1 load sees tooth -d as a +1 load sees tooth d
    dd = np.where(side[:, None] > 0, d, -d) % z_f
    block = np.where(same[..., None, None], infl["fs_same"][dd], infl["fs_other"][dd])
    C = np.einsum("ja,kb,jkab->jk", Wf, Wf, block)
    dc = np.where(side[:, None] > 0, space[None, :] - space[:, None], space[:, None] - space[None, :])
    dc = (dc + z_c // 2) % z_c - z_c // 2
    near = same & (np.abs(dc) <= CS_NEIGHBOURS)
    cs = infl["cs"][np.clip(dc + CS_NEIGHBOURS, 0, 2 * CS_NEIGHBOURS)]
    C = C + np.where(near, np.einsum("ja,kb,jkab->jk", Wc, Wc, cs), 0.0)
    return 0.5 * (C + C.T)


def _contract(W: np.ndarray, table: np.ndarray, idx: np.ndarray) -> np.ndarray:
    """C[j, k] = W[j] . table[idx[j, k]] . W[k] (table (D, na, na), W (n, na)), without the (n, n, na, na) gather."""
    A = np.einsum("ja,dab->djb", W, table)
    return np.einsum("jkb,kb->jk", A[idx, np.arange(W.shape[0])[:, None], :], W)


MIRROR_SIGN = np.array([1.0, -1.0])   # a -1 flank's (normal, tangential) band is the mirrored +1 one's times these


def pair_flexibility(infl: Mapping, pairs: Mapping, z_f: int, z_c: int) -> np.ndarray:
    """(2n, 2n) band flexibility [[Cff, Cfg], [Cgf, Cgg]] of the flank pairs (FS rim + CS teeth, in series), in
    pair_compliance's order: the normal band N (pressure) and the tangential Q (along t = rot90(n) of the FS flank;
    the CS flank gets -Q t_FS = Q t_CS, so both bodies add). Tooth 0's blocks by translation symmetry; a -1 pair's
    by the mirror, where t changes sign (MIRROR_SIGN); the CS coupling keeps CS_NEIGHBOURS teeth, as the normal
    one (decision 073-slipstudy48). Cff is pair_compliance's."""
    side, tooth, space = pairs["side"], pairs["tooth"], pairs["cs_space"]
    n = side.size
    Wf = _interp_weights(infl["fs_radii"], pairs["fs_radius_mm"])
    Wc = _interp_weights(infl["cs_radii"], pairs["cs_radius_mm"])
    same = side[:, None] == side[None, :]
    mirror = side[:, None] < 0                      # row j loaded: a -1 load is the mirrored +1 load
    dd = np.where(mirror, tooth[:, None] - tooth[None, :], tooth[None, :] - tooth[:, None]) % z_f
    dc = np.where(mirror, space[:, None] - space[None, :], space[None, :] - space[:, None])
    dc = (dc + z_c // 2) % z_c - z_c // 2
    near = same & (np.abs(dc) <= CS_NEIGHBOURS)
    kc = np.clip(dc + CS_NEIGHBOURS, 0, 2 * CS_NEIGHBOURS)
    flex = np.zeros((2 * n, 2 * n))
    for x in (0, 1):
        for y in (0, 1):
            sign = np.where(mirror, MIRROR_SIGN[x] * MIRROR_SIGN[y], 1.0)
            C = np.where(same, _contract(Wf, infl["fs_t_same"][x, y], dd),
                         _contract(Wf, infl["fs_t_other"][x, y], dd))
            C = C + np.where(near, _contract(Wc, infl["cs_t"][x, y], kc), 0.0)
            # C[j, k]: reading y at k per load x at j; flexibility rows are readings
            flex[y * n:(y + 1) * n, x * n:(x + 1) * n] += (sign * C).T
    return 0.5 * (flex + flex.T)


def influences(params, mesh: Mapping, h_mm: float, *, plane_stress: bool = False,
               bed_N_per_mm2: float | None = None) -> tuple[dict, dict]:
    """The FS rim's and the CS sector's flank influences on one mesh size, and the mesh facts (``bed_N_per_mm2``:
    the rim's bore on a radial Winkler bed instead of held, fea/tooth_mesh_fe.rim_model)."""
    from strainwave.geometry.mesh_geometry import mesh_geometry
    geo = mesh_geometry(params)
    m = params.material
    # plane strain: the face width (30 mm) is 15-40x the tooth and the rim thickness (docs/decisions/064)
    lame = Lame.from_young(m.youngs_modulus_MPa, m.poisson_ratio, plane_stress=plane_stress)
    band = BAND_OVER_M * geo.fs.module_mm
    fs_r, cs_r = radii_grids(mesh)
    rim = fe.rim_model(geo.fs, geo.r_bore_mm, h_mm, lame, geo.face_width_mm, bed_N_per_mm2)
    offs = np.arange(geo.z_f)
    # tooth 0's +1 flank loaded by the pressure band and its turned twin, read on both flanks of every tooth
    rim_t = fe.influence_blocks(rim, geo.fs.root_radius_mm, fs_r, band, +1, (1, -1), offs, geo.r_bore_mm)
    same, other = rim_t[1][0, 0], rim_t[-1][0, 0]
    hs = SECTOR_H_RATIO * h_mm        # a sector holds a few teeth: finer costs little and keeps its GCI small
    # as wide as twice its depth: a narrow sector with free sides is a column, far softer than the CS ring
    # (4 teeth a side were 26 % softer than 20 on the default gear)
    depth = geo.cs_outer_radius_mm - geo.cs_tooth.root_radius_mm
    wide = max(CS_NEIGHBOURS + 2, int(math.ceil(2 * depth / (math.pi * geo.cs_tooth.module_mm))) + 2)
    sector = fe.sector_model(geo.cs_tooth, geo.cs_outer_radius_mm, wide, hs, lame, geo.face_width_mm)
    # the FS's +1 flank presses the CS tooth's -1 flank
    cs_t = fe.influence_blocks(sector, geo.cs_tooth.root_radius_mm, cs_r, band, -1, (-1,),
                               np.arange(-CS_NEIGHBOURS, CS_NEIGHBOURS + 1), None)[-1]
    cs = cs_t[0, 0]
    solid = fe.sector_model(geo.fs, geo.fs.root_radius_mm - SOLID_DEPTH_OVER_M * geo.fs.module_mm, 2, hs, lame,
                            geo.face_width_mm)
    fs_solid = fe.influence(solid, geo.fs.root_radius_mm, fs_r, band, +1, np.array([0]), None)
    cracked = fe.sector_model(geo.fs, geo.fs.root_radius_mm - SOLID_DEPTH_OVER_M * geo.fs.module_mm, 2, hs, lame,
                              geo.face_width_mm, crack=(mesh["crack_depth_mm"], mesh["slot_width_mm"]))
    fs_cracked = fe.influence(cracked, geo.fs.root_radius_mm, fs_r, band, +1, np.array([0]), None)
    facts = {"elements": int(rim.mesh.t.shape[1] + sector.mesh.t.shape[1]),
             "nodes": int(rim.basis.N + sector.basis.N), "dofs": int(2 * (rim.basis.N + sector.basis.N))}
    timings = {k: rim.timings_s[k] + sector.timings_s[k] for k in rim.timings_s}
    return {"fs_same": same, "fs_other": other, "cs": cs, "fs_t_same": rim_t[1], "fs_t_other": rim_t[-1],
            "cs_t": cs_t,
            "fs_solid": fs_solid, "fs_radii": fs_r, "cs_radii": cs_r,
            "face_width_mm": geo.face_width_mm, "rim": rim, "r_bore_mm": geo.r_bore_mm,
            "crack_delta": fs_cracked[0] - fs_solid[0]}, facts | timings


def systems(infl: Mapping, mesh: Mapping) -> list:
    """One MeshSystem per wave-generator angle."""
    from strainwave.fea.mesh_contact import MeshSystem
    out = []
    for pairs in mesh["angles"]:
        C = pair_compliance(infl, pairs, mesh["z_f"], mesh["z_c"])
        out.append(MeshSystem(pairs["clearance_mm"], C, pairs["lever_mm"], pairs["slide_mm_per_rad"],
                              mesh["friction_coefficient"], mesh["rim_radius_mm"]))
    return out


def band_systems(infl: Mapping, mesh: Mapping) -> list:
    """One fea/mesh_friction.BandSystem per wave-generator angle: the pairs' 2 x 2 band flexibility (normal and
    tangential, pair_flexibility) for Coulomb's law on the true slip; the counter-tooth's slide along the FS flank's
    t = rot90(n) is the engagement's ``slide_mm_per_rad`` with its sign (decision 072-slip48)."""
    from strainwave.fea.mesh_friction import BandSystem
    return [BandSystem(np.asarray(p["clearance_mm"], float), pair_flexibility(infl, p, mesh["z_f"], mesh["z_c"]),
                       np.asarray(p["lever_mm"], float), np.asarray(p["slide_mm_per_rad"], float),
                       float(mesh["friction_coefficient"])) for p in mesh["angles"]]


ARCMIN = 60.0 * 180.0 / math.pi
LOST_MOTION_FRACTION = 0.04       # Harmonic Drive's lost-motion torque, of the rated (catalogue_values.py)


def knee_values(path, rated_Nmm: float, steps_per_leg: int = READ_STEPS_PER_LEG) -> dict:
    """K1, K2, K3, T1, T2 by the catalogue's reader on the exact loop with the dead band taken out (decision 073)."""
    from threadpoolctl import threadpool_limits
    with threadpool_limits(limits=1):       # the reader's small dense solves: BLAS threads only spin (decision 071)
        return read_knees(*resampled_loop(path, steps_per_leg), rated_Nmm)


def read_knees(T: np.ndarray, th: np.ndarray, rated_Nmm: float) -> dict:
    """The catalogue reader's K1, K2, K3, T1, T2 of a loop sampled at torques ``T`` (0 -> +T -> -T -> +T)."""
    from strainwave.compare.diagnose.catalogue_values import catalogue_values
    from strainwave.compare.diagnose.context import find_segments, reversal_threshold
    from strainwave.compare.diagnose.effects.base import Context
    X = float(np.max(np.abs(T)))
    c0 = float(np.max(np.abs(th))) / X
    u = T / X
    segs = find_segments(u, reversal_threshold(u))
    direction = np.empty(u.size)
    for a, b, d in segs:
        direction[a:b] = d
    ctx = Context(u=u, y=th / (c0 * X), t=np.linspace(0, 1, u.size), X=X, Y=c0 * X, c0=c0, load_unit="N*mm",
                  response_unit="rad", direction=direction, segments=tuple(segs))
    cv = catalogue_values(ctx, rated_Nmm)
    if cv is None:
        raise RuntimeError("tooth-mesh: the loop has no reversal to read")
    return {k: cv.values[k][0] for k in ("K1", "K2", "K3", "T1", "T2")}


def loop_values(paths: list, rated_Nmm: float) -> dict:
    """Catalogue readings of the headline angle's loop and the spread over the angles (TE)."""
    p = paths[0]
    T, th = p.torque_Nmm, p.twist_rad
    v = knee_values(p, rated_Nmm)
    # the lost motion read on the exact loop's branches (the catalogue's definition; no fitted curve between). The
    # hysteresis loss at zero torque is not reported: zero torque lies inside the backlash's dead band, where the
    # twist is undetermined (it read 0 and -0.99 arcmin on the two gears); friction's loss is its work per cycle
    lm = LOST_MOTION_FRACTION * rated_Nmm
    v["lost_motion_arcmin"] = ARCMIN * (_branch_twist(p, lm, -1) - _branch_twist(p, -lm, +1))
    from strainwave.fea.mesh_contact import loop_area_Nmm_rad
    v["friction_loss"] = loop_area_Nmm_rad(p)       # the work flank friction takes per +/-rated cycle
    k_peak = int(np.argmax(T))
    at_rated = np.array([q.twist_rad[int(np.argmax(q.torque_Nmm))] for q in paths])
    F = p.forces_N[k_peak]
    return {"K1_Nmm_per_rad": v["K1"], "K2_Nmm_per_rad": v["K2"], "K3_Nmm_per_rad": v["K3"],
            "T1_Nmm": v["T1"], "T2_Nmm": v["T2"], "lost_motion_arcmin": v["lost_motion_arcmin"],
            "friction_loss_per_cycle_Nmm": v["friction_loss"],
            "secant_stiffness_rated_Nmm_per_rad": float(T[k_peak] / th[k_peak]),
            "transmission_error_pp_rad": float(at_rated.max() - at_rated.min()),
            "teeth_in_contact_rated": float(np.count_nonzero(F > 0)),
            "peak_tooth_share": float(F.max() / F.sum()), "peak_tooth_load_N": float(F.max())}


def rigid_rim(infl: Mapping, mesh: Mapping) -> tuple[dict, dict]:
    """The headline angle's contact solve with the rim's coupling removed (teeth on a rigid rim: each pair's own
    FE compliance, the diagonal of the flexibility), first loading 0 -> rated with friction: the readings the check
    ``mesh.rigid_rim_sharing`` holds against the closed form, and the inputs of that solve (the check's closed
    form takes the same ones)."""
    from strainwave.fea.mesh_contact import MeshSystem, solve_torque_path
    pairs = mesh["angles"][0]
    c = np.diag(pair_compliance(infl, pairs, mesh["z_f"], mesh["z_c"])).copy()
    system = MeshSystem(pairs["clearance_mm"], np.diag(c), pairs["lever_mm"], pairs["slide_mm_per_rad"],
                        mesh["friction_coefficient"], mesh["rim_radius_mm"])
    history = np.asarray(mesh["torque_history_Nmm"], float)
    first = history[:int(np.argmax(history)) + 1]           # the virgin loading up to rated
    path = solve_torque_path(system, first)
    F = path.forces_N[-1]
    values = {"rigid_rim_peak_tooth_share": float(F.max() / F.sum()),
              "rigid_rim_teeth_in_contact": float(np.count_nonzero(F > 0.0)),
              "rigid_rim_twist_rated_rad": float(path.twist_rad[-1])}
    inputs = {"clearance_mm": np.asarray(pairs["clearance_mm"]).tolist(), "compliance_mm_per_N": c.tolist(),
              "lever_mm": np.asarray(pairs["lever_mm"]).tolist(),
              "slide_mm_per_rad": np.asarray(pairs["slide_mm_per_rad"]).tolist(),
              "friction_coefficient": float(mesh["friction_coefficient"]), "torque_Nmm": float(first[-1]),
              "forces_N": F.tolist(), "twist_rad": float(path.twist_rad[-1])}
    return values, inputs


def engagement_edge(path, pairs: Mapping) -> dict:
    """The outermost loaded flank pair's angle from the major axis, folded into its lobe (dual wave), on the headline
    angle's first loading: at rated (the check ``mesh.engagement_zone``'s reading) and at the path's first load
    step (a small torque, shown beside it)."""
    folded = 0.5 * np.angle(np.exp(2j * np.asarray(pairs["phi_rad"])))
    k_peak = int(np.argmax(path.torque_Nmm))
    k_first = int(np.flatnonzero(path.torque_Nmm > 0.0)[0])
    edge = {}
    for name, k in (("engagement_edge_rated_rad", k_peak), ("engagement_edge_first_step_rad", k_first)):
        on = path.forces_N[k] > 0.0
        edge[name] = float(folded[on].max()) if on.any() else math.nan
    return edge


def ratcheting_torque_Nmm(forces_N, pressure_angle_rad, phi_rad, depth_mm, K_G_N_per_mm: float,
                          torque_Nmm: float) -> dict:
    """The torque at which the loaded teeth climb out: each flank load's radial part F sin(alpha) pushes its WG
    lobe in (the lobe's resultant along its axis over K_G, one lobe's radial stiffness); the lobe's approach delta
    shrinks the wave w0 cos 2 phi, so pair k loses delta cos 2 phi_k of its radial overlap depth_k. With the contact
    set of ``torque_Nmm`` held (loads linear in the torque), the teeth climb out where the overlap at the load's
    centroid (load-weighted over the loaded pairs) is used up: T_r = T sum(F depth) / sum(F lift)."""
    F = np.asarray(forces_N, float)
    phi = np.asarray(phi_rad, float)
    folded = 0.5 * np.angle(np.exp(2j * phi))              # angle from the own lobe's axis
    lobe = np.round((phi - folded) / math.pi).astype(int) % 2
    push = np.asarray([np.sum((F * np.sin(pressure_angle_rad) * np.cos(folded))[lobe == j]) for j in (0, 1)])
    lift = push[lobe] / K_G_N_per_mm * np.cos(2.0 * folded)  # each pair's overlap lost at torque_Nmm
    w = F / F.sum()
    overlap, lost = float(w @ np.maximum(np.asarray(depth_mm, float), 0.0)), float(w @ lift)
    return {"ratcheting_torque_Nmm": torque_Nmm * overlap / lost if lost > 0 else math.inf,
            "ratcheting_lift_rated_mm": lost, "ratcheting_overlap_mm": overlap}


def ratcheting(path, pairs: Mapping, mesh: Mapping) -> dict:
    """The ratcheting torque from the headline angle's first loading at rated: the FE contact solve's flank loads,
    their pressure angle at the CS contact radius (the involute's, cos alpha = r_b / r) and the kinematic overlap."""
    k = int(np.argmax(path.torque_Nmm))
    alpha = np.arccos(np.clip(np.abs(pairs["lever_mm"]) / pairs["cs_radius_mm"], -1.0, 1.0))
    return ratcheting_torque_Nmm(path.forces_N[k], alpha, pairs["phi_rad"], pairs["depth_mm"],
                                 mesh["wg_radial_stiffness_N_per_mm"], float(path.torque_Nmm[k]))


def root_stress(params, mesh: Mapping, path, h_mm: float) -> dict:
    """The most loaded tooth's root stress at rated (headline angle, first loading): the filleted sector of
    fea/tooth_root_fe.py under that tooth's flank load, at its contact radius, on this mesh's size (so it has a GCI)."""
    from strainwave.fea.tooth_root_fe import root_stress_per_N
    from strainwave.geometry.mesh_geometry import mesh_geometry
    geo = mesh_geometry(params)
    m = params.material
    k_peak = int(np.argmax(path.torque_Nmm))
    F = path.forces_N[k_peak]
    j = int(np.argmax(F))
    pairs = mesh["angles"][0]
    lame = Lame.from_young(m.youngs_modulus_MPa, m.poisson_ratio)
    r = root_stress_per_N(geo.fs, geo.r_bore_mm, h_mm, lame, geo.face_width_mm, float(pairs["fs_radius_mm"][j]),
                          int(pairs["side"][j]), BAND_OVER_M * geo.fs.module_mm)
    return {"root_stress_peak_tooth_MPa": r["stress_MPa_per_N"] * float(F[j]),
            "root_stress_per_N_MPa": r["stress_MPa_per_N"], "root_contact_radius_mm": float(pairs["fs_radius_mm"][j])}


def crack_signature(infl: Mapping, mesh: Mapping) -> tuple[dict, np.ndarray]:
    """The root crack of tooth 0 (its +theta flank's root) as tooth 0 passes the loaded zone: the crack's added
    compliance (solid-body sector, cracked minus uncracked, same mesh size) on tooth 0's +flank pair; the
    -flank load closes the crack, so it is left uncracked (the FE's slot would stay open). Returns the readings
    and the twist change at rated torque against tooth 0's angle from the major axis."""
    from strainwave.fea.mesh_contact import solve_torque_path
    ramp = np.linspace(0.0, mesh["rated_torque_Nmm"], 21)
    change = []
    for pairs in mesh["crack_angles"]:
        C = pair_compliance(infl, pairs, mesh["z_f"], mesh["z_c"])
        hit = np.flatnonzero((pairs["tooth"] == 0) & (pairs["side"] == 1))
        twists = []
        for cracked in (False, True):
            Ck = C.copy()
            if cracked and hit.size:
                w = _interp_weights(infl["fs_radii"], pairs["fs_radius_mm"][hit])[0]
                Ck[hit[0], hit[0]] += float(w @ infl["crack_delta"] @ w)
            from strainwave.fea.mesh_contact import MeshSystem
            sys_ = MeshSystem(pairs["clearance_mm"], Ck, pairs["lever_mm"], pairs["slide_mm_per_rad"], 0.0,
                              mesh["rim_radius_mm"])
            twists.append(solve_torque_path(sys_, ramp).twist_rad[-1])
        change.append(twists[1] - twists[0])
    change = np.asarray(change)
    r_f = mesh["major_fs_radius_mm"]
    wf = _interp_weights(infl["fs_radii"], np.array([r_f]))[0]
    base = float(wf @ infl["fs_solid"][0] @ wf)
    return {"crack_tooth_compliance_ratio": (base + float(wf @ infl["crack_delta"] @ wf)) / base,
            "crack_te_peak_rad": float(change.max())}, change


def rated_compliance(infl: Mapping, mesh: Mapping, path) -> dict:
    """The pair compliance of the headline angle's pairs loaded at rated (first loading), with their indices: the
    drive-assembled check's teeth member (fea/drive_assembled.py), small enough for the record."""
    C = pair_compliance(infl, mesh["angles"][0], mesh["z_f"], mesh["z_c"])
    on = np.flatnonzero(path.forces_N[int(np.argmax(path.torque_Nmm))] > 0.0)
    return {"index": on.tolist(), "compliance_mm_per_N": C[np.ix_(on, on)].tolist()}


def crack_orders(mesh: Mapping) -> dict:
    """How often the cracked tooth passes an engagement zone: the WG's lobes sweep the FS at (1 + dZ/Z_f) of
    the WG's speed relative to it, twice per relative turn (dual wave)."""
    zf, zc = mesh["z_f"], mesh["z_c"]
    per_input = 2.0 * (1.0 + (zc - zf) / zf)
    return {"per_input_revolution": per_input, "per_output_revolution": per_input * zf / (zc - zf)}


def major_pair(infl: Mapping, mesh: Mapping) -> dict:
    """The single pair on the major axis at its contact radius: FS tooth, CS tooth and the two in series."""
    r_f, r_c = mesh["major_fs_radius_mm"], mesh["major_cs_radius_mm"]
    wf = _interp_weights(infl["fs_radii"], np.array([r_f]))[0]
    wc = _interp_weights(infl["cs_radii"], np.array([r_c]))[0]
    c_fs = float(wf @ infl["fs_same"][0] @ wf)
    c_cs = float(wc @ infl["cs"][CS_NEIGHBOURS] @ wc)
    nxt = float(wf @ infl["fs_same"][1] @ wf)
    c_solid = float(wf @ infl["fs_solid"][0] @ wf)
    b = infl["face_width_mm"]
    return {"pair_stiffness_solid_N_per_mm_um": 1e-3 / (2 * c_solid * b),
            "pair_stiffness_internal_N_per_mm_um": 1e-3 / ((c_solid + c_cs) * b),
            "fs_tooth_compliance_major_mm_per_N": c_fs, "cs_tooth_compliance_major_mm_per_N": c_cs,
            "pair_compliance_major_mm_per_N": c_fs + c_cs, "fs_coupling_next_ratio": nxt / c_fs}


def rated_field(infl: Mapping, mesh: Mapping, path, tangential_N: np.ndarray | None = None) -> tuple:
    """(mesh, vertex displacement (Nv, 2)) of the FS rim under the headline angle's flank loads at rated torque (the
    normal bands and, given the path's tangential forces (m, n), their turned twins)."""
    rim, pairs = infl["rim"], mesh["angles"][0]
    k = int(np.argmax(path.torque_Nmm))
    F = path.forces_N[k]
    Q = np.zeros_like(F) if tangential_N is None else np.asarray(tangential_N)[k]
    band = BAND_OVER_M * mesh["module_mm"]
    total = np.zeros(rim.T.shape[0])
    shear = fe.bore_shear(rim, infl["r_bore_mm"])
    for side in (1, -1):
        on = (pairs["side"] == side) & (F > 0)
        if on.any():
            L, M = fe.flank_loads(rim, pairs["tooth"][on], pairs["fs_radius_mm"][on], band, side)
            G = fe.turned(rim, L)
            total += (L - shear[:, None] * M[None, :]) @ F[on]
            total += (G - shear[:, None] * fe.load_moments(rim, G)[None, :]) @ Q[on]
    u = rim.T @ fe.displacements(rim, total[:, None])[:, 0]
    nv = rim.mesh.p.shape[1]
    return rim.mesh, np.column_stack([u[0:2 * nv:2], u[1:2 * nv:2]]), vertex_von_mises(rim, u)


def vertex_von_mises(model, u: np.ndarray) -> np.ndarray:
    """Plane-strain von Mises stress (MPa), cell means averaged onto the vertices (a picture, not a design value:
    the outline's roots are sharp)."""
    b, lame = model.basis, model.lame
    grad = np.stack([b.interpolate(u[c::2]).grad for c in (0, 1)])          # (2, 2, nel, nq)
    eps = 0.5 * (grad + grad.transpose(1, 0, 2, 3))
    tr = eps[0, 0] + eps[1, 1]
    sxx = lame.lam_MPa * tr + 2 * lame.mu_MPa * eps[0, 0]
    syy = lame.lam_MPa * tr + 2 * lame.mu_MPa * eps[1, 1]
    sxy = 2 * lame.mu_MPa * eps[0, 1]
    szz = lame.lam_MPa * tr
    vm = np.sqrt(0.5 * ((sxx - syy) ** 2 + (syy - szz) ** 2 + (szz - sxx) ** 2) + 3 * sxy ** 2).mean(axis=1)
    t = model.mesh.t
    acc = np.bincount(t.ravel(), np.repeat(vm[None, :], 3, axis=0).ravel(), model.mesh.p.shape[1])
    return acc / np.bincount(t.ravel(), minlength=model.mesh.p.shape[1])


def write_pictures(folder, meta: Mapping, mesh: Mapping, catalogue: tuple | None) -> list:
    """The loop (beside the catalogue's curve when given) and the load per tooth around the circumference."""
    import matplotlib
    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt
    from strainwave.io_atomic import atomic_path
    out = []
    fig, ax = plt.subplots(figsize=(6, 4))
    T = np.asarray(meta["loop"]["torque_Nmm"]) * 1e-3
    th = np.asarray(meta["loop"]["twist_rad"]) * 60 * 180 / np.pi
    ax.plot(th, T, "-", lw=1.2, label="tooth mesh alone (FE + contact), +/-rated")
    if catalogue is not None:
        K1, K2, K3, T1, T2 = catalogue                     # N m/rad, N m
        t = np.linspace(0, T.max(), 50)
        phi = np.where(t <= T1, t / K1, np.where(t <= T2, T1 / K1 + (t - T1) / K2, T1 / K1 + (T2 - T1) / K2 + (t - T2) / K3))
        ax.plot(phi * 60 * 180 / np.pi, t, "k--", lw=1, label="catalogue unit (CHA, power law at this size)")
    ax.set_xlabel("output twist (arcmin)")
    ax.set_ylabel("output torque (N m)")
    ax.legend(fontsize=7)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    for name, figure in (("tooth_mesh_loop.png", fig),):
        with atomic_path(folder / name) as tmp:
            figure.savefig(tmp, dpi=120, format="png")
        out.append(folder / name)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(6, 3))
    pairs = meta["pairs"]
    F = np.asarray(meta["forces_at_rated_N"])
    phi = np.degrees(np.asarray(pairs["phi_rad"]))
    side = np.asarray(pairs["side"])
    for s, c in ((1, "C0"), (-1, "C3")):
        on = side == s
        ax.bar(phi[on], F[on], width=1.2, color=c, label=f"flank {'+' if s > 0 else '-'}")
    ax.set_xlabel("FS tooth angle from the WG major axis (deg)")
    ax.set_ylabel("flank normal load at rated (N)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    with atomic_path(folder / "tooth_mesh_load_per_tooth.png") as tmp:
        fig.savefig(tmp, dpi=120, format="png")
    plt.close(fig)
    return out + [folder / "tooth_mesh_load_per_tooth.png"]


class ToothMesh(StudyVariant):
    study = STUDY
    plane = True
    teeth_key = "flexspline_cup.teeth"
    # measured: 82k elements (rim + three sectors) at h = 0.24 mm on the default gear's 1315 mm2 section
    elements_per_cell = 3.6
    cpu_s_per_element = (2.7e-4, 2.7e-4)    # 22.5 CPU-s over those 82k (make bench, load ~22)
    title = "Teeth in mesh (plane FE compliance + frictional contact)"
    element_text = "P2 triangles, plane strain, thickness = engaged face width"
    rated_load = TORQUE_RATED
    outside_design = "the mesh study reports the drive's stiffness and tooth loads, not a design stress factor"

    def __init__(self, params, *, mesh_size_mm=None, order=2, quick=False, mesh=None, progress=None):
        self.params, self.quick, self.mesh_inputs = params, quick, mesh
        self.sizes = refinements(params.flexspline_cup.module_mm, quick) if mesh_size_mm is None else \
            (mesh_size_mm, mesh_size_mm * RATIO, mesh_size_mm * RATIO ** 2)
        check_variant(STUDY, order=order, sizes_mm=self.sizes)
        if order != 2:
            raise ValueError(f"{STUDY}: P2 only")

    @classmethod
    def default_size_mm(cls, params, quick: bool) -> float:
        return refinements(params.flexspline_cup.module_mm, quick)[0]

    @classmethod
    def volume_and_wall(cls, params) -> tuple[float, float]:
        fc = params.flexspline_cup
        r = 0.5 * fc.pitch_diameter_mm
        area = math.pi * (r ** 2 - (r - fc.wall_thickness_mm) ** 2) + fc.teeth * 1.6 * fc.module_mm ** 2
        return area, fc.module_mm

    def build(self):
        return None

    def series(self) -> tuple[SeriesPlan, ...]:
        return (SeriesPlan("rim", tuple(self.sizes)),)

    def solve(self, parts, series: str, refinement: float, k: int, keep_fields: bool, progress) -> MeshSolve:
        t0 = time.perf_counter()
        infl, facts = influences(self.params, self.mesh_inputs, refinement)
        t1 = time.perf_counter()
        from strainwave.fea.mesh_friction import torque_path
        history = np.asarray(self.mesh_inputs["torque_history_Nmm"])
        # Coulomb on the true slip with the flanks' tangential loads (decision 073-slipstudy48)
        solved = [torque_path(s, history, INCREMENTS) for s in band_systems(infl, self.mesh_inputs)]
        paths = [p for p, _ in solved]
        crack, change = crack_signature(infl, self.mesh_inputs)
        rigid, rigid_inputs = rigid_rim(infl, self.mesh_inputs)
        values = (loop_values(paths, self.mesh_inputs["rated_torque_Nmm"]) | major_pair(infl, self.mesh_inputs) | crack
                  | rigid | engagement_edge(paths[0], self.mesh_inputs["angles"][0])
                  | ratcheting(paths[0], self.mesh_inputs["angles"][0], self.mesh_inputs)
                  | root_stress(self.params, self.mesh_inputs, paths[0], refinement))
        t2 = time.perf_counter()
        quality = MeshQuality(facts["elements"], facts["nodes"], facts["dofs"], 2, float("nan"), float("nan"))
        # the rigid-rim solve's inputs are kept on every mesh (small): the check mesh.rigid_rim_sharing reads them
        fields = {"rigid_rim": rigid_inputs}
        if k == 0:
            fields["paths"] = paths          # small: the finest loop reaches meta (diagnose --baseline fea reads it)
            fields["rated_compliance"] = rated_compliance(infl, self.mesh_inputs, paths[0])
        if keep_fields:
            fields |= {"rated_u": rated_field(infl, self.mesh_inputs, paths[0], solved[0][1]),
                       "r_bore_mm": infl["r_bore_mm"], "crack_change": change}
        infl.pop("rim")
        return MeshSolve(refinement, values, quality,
                         {"mesh": facts["mesh"], "assemble": facts["assemble"], "solve": facts["solve"],
                          "contact": t2 - t1, "influence": t1 - t0 - facts["mesh"] - facts["assemble"] - facts["solve"]},
                         fields=fields)

    def quantities(self, series: Mapping[str, Series]) -> dict:
        s = series["rim"]
        out = {name: s.converged(name, unit) for name, unit in QUANTITIES}
        for name in STEP_LIMITED:     # the mesh's GCI would claim a band the reader's grid does not honour
            q = out[name]
            out[name] = Quantity(name, q.value, q.unit, Convergence.refusal(s.h_mm, s.values(name), STEP_LIMITED_WHY,
                                                                            q.convergence.formal_order))
        return out

    def load(self, parts) -> Load:
        return Load("output torque T", float(self.mesh_inputs["rated_torque_Nmm"]), "N*mm", ("tooth_flanks",),
                    "0 -> +T -> -T -> +T on the flank pairs in contact (wave generator and CS held)")

    def supports(self) -> tuple[Support, ...]:
        return (Support(("bore",), "u_r = 0 (rigid wave generator); torque reacted by a uniform tangential shear "
                                   "(the cup wall); one tangential pin against the rigid rotation"),
                Support(("cs_outer",), "circular spline sector held at its outer diameter"))

    def write_fields(self, series: Mapping[str, Series], vtu, load: Load) -> tuple:
        from pathlib import Path
        from strainwave.fea.fields import field_info, write_vtu
        from strainwave.fea.mesh_data import MeshData
        f = series["rim"].finest.fields
        mesh, u, vm = f["rated_u"]
        bf = mesh.boundary_facets()
        r_mid = np.hypot(*mesh.p[:, mesh.facets[:, bf]].mean(axis=1))
        bore = r_mid < f["r_bore_mm"] + 1e-3
        md = MeshData(np.column_stack([mesh.p.T, np.zeros(mesh.p.shape[1])]), mesh.t.T.copy(), 2, 1,
                      groups={"bore": mesh.facets[:, bf[bore]].T.copy(), "teeth": mesh.facets[:, bf[~bore]].T.copy()})
        info = field_info(STUDY, "flank loads of the headline WG angle at rated torque; " + load.describe(),
                          self.params.material)
        vtu = Path(vtu)
        files = [write_vtu(vtu, md, {"displacement_mm": np.column_stack([u, np.zeros(len(u))]), "von_mises_MPa": vm},
                           info=info)]
        return tuple(files) + tuple(write_pictures(vtu.parent, self.meta(None, series), self.mesh_inputs,
                                                   self.mesh_inputs.get("catalogue_curve")))

    def meta(self, parts, series: Mapping[str, Series]) -> dict:
        f = series["rim"].finest.fields
        if "paths" not in f:
            return {"rigid_rim": f["rigid_rim"]}
        p = f["paths"][0]
        out = {"loop": {"torque_Nmm": p.torque_Nmm.tolist(), "twist_rad": p.twist_rad.tolist()},
               "forces_at_rated_N": p.forces_N[int(np.argmax(p.torque_Nmm))].tolist(),
               "pairs": {k: np.asarray(v).tolist() for k, v in self.mesh_inputs["angles"][0].items()},
               "te_twist_at_rated_rad": [float(q.twist_rad[int(np.argmax(q.torque_Nmm))]) for q in f["paths"]],
               "rigid_rim": f["rigid_rim"], "rated_compliance": f.get("rated_compliance"),
               # the exact loop (decision 073) for diagnose's drive curve (decision 076)
               "loop_knots": np.asarray(p.knots).tolist() if p.knots is not None else None,
               "dead_band_rad": [float(b) for b in p.dead_band_rad]}
        if "crack_change" not in f:
            return out
        return out | {"crack": {"tooth_phi_rad": list(self.mesh_inputs["crack_phi_rad"]),
                                "twist_change_at_rated_rad": np.asarray(f["crack_change"]).tolist(),
                                "orders": crack_orders(self.mesh_inputs)}}


def run(params, *, mesh_size_mm=None, order=2, crack_depth_mm=None, vtu=None, progress=None, quick=False,
        mesh=None, **_) -> StudyResult:
    if crack_depth_mm is not None:
        raise ValueError(f"{STUDY}: no crack")
    variant = ToothMesh(params, mesh_size_mm=mesh_size_mm, order=order, quick=quick, mesh=mesh)
    return run_variant(variant, vtu=vtu, progress=progress or (lambda m: None))
