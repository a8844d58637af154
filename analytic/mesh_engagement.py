"""Kinematic engagement of a strain-wave tooth mesh: which flexspline (FS) teeth reach into the circular
spline's (CS) spaces at one wave-generator (WG) angle, where they touch and the unloaded flank clearance.

The kinematic theory used (Ivanov; the "neutral line" of J. Mech. Des. 112(1):131, 1990): the FS rim's
neutral line is inextensible and takes the WG's shape w = w0 cos 2 phi (dual wave), so its tangential
displacement is v = -(w0/2) sin 2 phi and its section turns by chi = (v - dw/dphi)/r_n; a tooth is a rigid
body standing on its section, so a point at height y above the neutral line moves by (w, v + y chi). The CS
is fixed; the WG at angle psi; the FS (output, locked with the WG in the stiffness test) has turned by
-2 psi / Z_f (dZ = 2), so the FS tooth on the major axis sits centred in its CS space. The CS's internal
involute has the same profile shift as the cup's teeth (so its tip clears the FS tip at the minor axis by
the same w0 its root clears it at the major axis: geometry/involute.cup_tooth_spec), and the per-flank
circumferential backlash at the pitch circle is ``circular_spline.backlash_mm``.

A pair is engaged where the FS tip, moved by w, passes the CS tip circle; the contact point is taken at the
middle of that radial overlap; the flank clearance is the CS space width minus the FS tooth width there,
minus (loaded flank) or plus (other flank) the tooth's circumferential misalignment, along the flank normal.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from strainwave.geometry.involute import half_angle_rad
from strainwave.geometry.mesh_geometry import MeshGeometry, mesh_geometry

__all__ = ["MeshGeometry", "Engagement", "mesh_geometry", "engagement", "engagement_zone_rad", "study_loads"]


@dataclass(frozen=True)
class Engagement:
    """The pairs that overlap radially at one WG angle, by FS tooth index."""

    tooth: np.ndarray              # (n,) FS tooth indices
    phi_rad: np.ndarray            # (n,) angle of the FS tooth from the WG major axis
    contact_radius_mm: np.ndarray  # (n,) radius of the contact point on the undeformed FS tooth
    depth_mm: np.ndarray           # (n,) radial overlap of FS and CS teeth
    clearance_pos_mm: np.ndarray   # (n,) flank-normal gap of the flank a positive output torque closes (<0: tip interference)
    clearance_neg_mm: np.ndarray   # (n,) of the other flank
    pressure_angle_rad: np.ndarray   # (n,) of the CS flank at the contact radius (the load's line of action)
    lever_mm: float                # CS base radius: a flank normal's arm about the axis
    cs_space: np.ndarray           # (n,) the CS space the tooth stands in
    cs_radius_mm: np.ndarray       # (n,) the contact radius in the CS (deformed FS position)


def _fs_point(geo: MeshGeometry, phi: np.ndarray, rho: np.ndarray):
    """Deformed (R, angle shift) of an FS point at radius rho on the tooth at phi from the major axis."""
    w0, rn = geo.w0_mm, geo.r_neutral_mm
    w = w0 * np.cos(2 * phi)
    v = -0.5 * w0 * np.sin(2 * phi)
    chi = (v + 2 * w0 * np.sin(2 * phi)) / rn
    return rho + w, (v + (rho - rn) * chi) / rho


def engagement(geo: MeshGeometry, psi_rad: float, *, min_depth_mm: float = 0.0) -> Engagement:
    """The engaged pairs with the WG's major axis at ``psi_rad`` (CS frame)."""
    z_f, z_c = geo.z_f, geo.z_c
    j = np.arange(z_f)
    theta = (2 * np.pi * j - (z_c - z_f) * psi_rad) / z_f            # FS tooth angles, output turned
    phi = np.angle(np.exp(1j * (theta - psi_rad)))
    tip_def, _ = _fs_point(geo, phi, np.full(z_f, geo.fs.tip_radius_mm))
    depth = tip_def - geo.cs_tip_mm
    on = depth > max(min_depth_mm, 1e-9)
    j, phi, theta, depth = j[on], phi[on], theta[on], depth[on]
    rho = geo.fs.tip_radius_mm - 0.5 * depth                       # middle of the overlap, FS frame
    R, dtheta = _fs_point(geo, phi, rho)
    ang = theta + dtheta
    k = np.round(ang * z_c / (2 * np.pi))
    mis = R * np.angle(np.exp(1j * (ang - 2 * np.pi * k / z_c)))   # + : ahead of the space centre
    space = R * half_angle_rad(geo.cs_space, R) + geo.backlash_mm * R / geo.cs_space.pitch_radius_mm
    tooth = rho * half_angle_rad(geo.fs, rho)                       # a rigid tooth keeps its width in mm
    alpha = np.arccos(np.clip(geo.cs_space.base_radius_mm / R, -1.0, 1.0))
    gap = space - tooth
    # a negative gap is tip interference of rigid involute teeth (kappa = 1, entry/exit zone): the rigid-tooth
    # kinematics cannot place that contact on the flanks, so those pairs stay negative and callers leave them out
    pos = (gap - mis) * np.cos(alpha)
    neg = (gap + mis) * np.cos(alpha)
    return Engagement(j, phi, rho, depth, pos, neg, alpha, geo.cs_space.base_radius_mm, k.astype(int) % z_c, R)


def engagement_zone_rad(geo: MeshGeometry) -> float:
    """Half-width of one engagement zone (kinematic theory): the FS tip passes the CS tip while
    w0 cos 2 phi > r_tip,CS - r_tip,FS."""
    c = (geo.cs_tip_mm - geo.fs.tip_radius_mm) / geo.w0_mm
    return 0.5 * math.acos(max(-1.0, min(1.0, c)))


# WG angles per tooth-passing period (the pattern repeats every 2 pi / Z_c of WG rotation)
ANGLES = {False: 4, True: 3}
# a flank pair whose gap exceeds this many modules cannot close within the rated twist: left out of the solve
REACH_OVER_M = 0.5
# positions of the cracked tooth 0 through the loaded zone of a positive torque (its +theta flank), rad
CRACK_PHI = np.radians(np.arange(-12.0, 27.0 + 1e-9, 1.5))   # the crack curve's grid (fea/tooth_crack_curve.PHI_DEG): 7.5 deg missed the pulse
MIN_DEPTH_OVER_M = 0.25           # a radial overlap shallower than this is tip-on-tip, not flank contact


def pairs_at(geo: MeshGeometry, psi_rad: float) -> dict:
    """The flank pairs of one WG angle as the tooth-mesh study takes them (side +1 first, then -1)."""
    e = engagement(geo, psi_rad, min_depth_mm=MIN_DEPTH_OVER_M * geo.fs.module_mm)
    reach = REACH_OVER_M * geo.fs.module_mm
    out = {k: [] for k in ("side", "tooth", "cs_space", "fs_radius_mm", "cs_radius_mm", "clearance_mm",
                           "lever_mm", "slide_mm_per_rad", "phi_rad", "depth_mm")}
    slide = np.sqrt(np.maximum(e.cs_radius_mm ** 2 - e.lever_mm ** 2, 0.0))
    for side, gap in ((1, e.clearance_pos_mm), (-1, e.clearance_neg_mm)):
        on = (gap >= 0.0) & (gap < reach)
        for key, val in (("side", np.full(on.sum(), side)), ("tooth", e.tooth[on]), ("cs_space", e.cs_space[on]),
                         ("fs_radius_mm", e.contact_radius_mm[on]), ("cs_radius_mm", e.cs_radius_mm[on]),
                         ("clearance_mm", gap[on]), ("lever_mm", np.full(on.sum(), side * e.lever_mm)),
                         ("slide_mm_per_rad", slide[on]), ("phi_rad", e.phi_rad[on]), ("depth_mm", e.depth_mm[on])):
            out[key].append(val)
    return {k: np.concatenate(v) for k, v in out.items()}


def study_loads(params, quick: bool = False) -> dict:
    """The tooth-mesh study's inputs as numbers: the pairs at each WG angle, the torque history and facts."""
    from strainwave.analytic.catalogue_power_law import catalogue_curve_Nm
    from strainwave.fea.mesh_contact import torque_history
    geo = mesh_geometry(params)
    n = ANGLES[bool(quick)]
    angles = [pairs_at(geo, 2 * np.pi / geo.z_c * k / n) for k in range(n)]
    fs_r = np.concatenate([a["fs_radius_mm"] for a in angles])
    cs_r = np.concatenate([a["cs_radius_mm"] for a in angles])
    major = engagement(geo, 0.0)
    i0 = int(np.argmin(np.abs(major.phi_rad)))
    rated = params.gear.rated_output_torque_Nmm
    return {"mesh": {
        "module_mm": geo.fs.module_mm, "fs_tip_mm": geo.fs.tip_radius_mm, "cs_tip_mm": geo.cs_tip_mm,
        "z_f": geo.z_f, "z_c": geo.z_c, "friction_coefficient": params.circular_spline.flank_friction_coefficient,
        "rim_radius_mm": geo.r_neutral_mm, "rated_torque_Nmm": rated,
        "torque_history_Nmm": torque_history(rated),
        "fs_radius_range_mm": (float(fs_r.min()), float(fs_r.max())),
        "cs_radius_range_mm": (float(cs_r.min()), float(cs_r.max())),
        "major_fs_radius_mm": float(major.contact_radius_mm[i0]), "major_cs_radius_mm": float(major.cs_radius_mm[i0]),
        "angles": angles, "catalogue_curve": catalogue_curve_Nm(params),
        # one WG lobe's radial stiffness (the parameter the closed forms and the wg-bearing check use): ratcheting
        "wg_radial_stiffness_N_per_mm": params.wave_generator.uncracked_radial_stiffness_N_per_mm,
        "crack_depth_mm": params.flexspline_cup.root_crack_depth_mm,
        "slot_width_mm": params.crack_geometry.slot_width_mm,
        "crack_phi_rad": CRACK_PHI.tolist(),
        # tooth 0 at phi from the major axis: psi = -phi / (1 + dZ/Z_f) (the output turned with the WG)
        "crack_angles": [pairs_at(geo, -p / (1 + (geo.z_c - geo.z_f) / geo.z_f)) for p in CRACK_PHI]}}
