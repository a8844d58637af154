"""The tooth-root crack seen through the mesh: the drive's twist ripple against the crack's depth (issue 48 item 7).

A crack at the root of flexspline tooth 0 (its +theta flank: the tension side under a positive torque) softens
that tooth (the solid-body sector of fea/tooth_mesh_fe.py with a radial root slot, cracked minus uncracked on
the same mesh size: tooth_mesh.influences' own ``crack_delta``). As tooth 0 passes the loaded zone its flank pair
is that much more compliant and the drive twists more at the same torque (tooth_mesh.crack_signature's chain: the
frictionless contact solve with tooth 0 at each position). Kept here: that twist change at every step of the
0 -> rated ramp (the contact is non-linear: more pairs close as the torque rises) and at PHI_DEG positions of
tooth 0, for DEPTH_FRACTIONS of the tooth's root thickness, on each of the study's three meshes. The quantities
and their GCIs are formed by the reader (compare/diagnose/tooth_crack.py), which caches this record.

The -theta flank's root is left uncracked: a positive torque loads the +flank, whose root fibre is in tension;
the -flank's root is in compression under its own load, so a crack there closes (the FE's open slot would not).

The rim's influences do not depend on the crack, so each mesh size solves them once and the cracked sector
once per depth.
"""
from __future__ import annotations

import math
from typing import Callable, Mapping

import numpy as np

from strainwave.fea import tooth_mesh as tm
from strainwave.fea import tooth_mesh_fe as fe

__all__ = ["DEPTH_FRACTIONS", "PHI_DEG", "root_thickness_mm", "curve_depths_mm", "signature",
           "curve_points"]

# of the FS tooth's root thickness: shallow (0.05) to half through; the slot's width stays <= depth/5
DEPTH_FRACTIONS = (0.05, 0.1, 0.2, 0.35, 0.5)
RAMP_STEPS = 21             # steps of the 0 -> rated ramp (the study's); the ripple is kept at every step
# positions of tooth 0 (from the WG major axis): the +flank carries load from 0 to +6 deg at rated torque on the
# default gear (the study's 7.5 deg grid sees it at one position), so 1.5 deg steps, well clear each side
PHI_DEG = np.arange(-12.0, 27.0 + 1e-9, 1.5)


def root_thickness_mm(params) -> float:
    """The flexspline tooth's chordal thickness at its root circle (s_F)."""
    from strainwave.geometry.involute import half_angle_rad
    from strainwave.geometry.mesh_geometry import mesh_geometry
    fs = mesh_geometry(params).fs
    return 2.0 * fs.root_radius_mm * math.sin(float(half_angle_rad(fs, fs.root_radius_mm)))


def curve_depths_mm(params) -> tuple[float, ...]:
    """The curve's crack depths (mm), rounded to 1 um; refused where the slot is wider than depth/5."""
    s = root_thickness_mm(params)
    depths = tuple(round(f * s, 3) for f in DEPTH_FRACTIONS)
    w = params.crack_geometry.slot_width_mm
    if w > depths[0] / 5.0:
        from strainwave.errors import InputError
        raise InputError("crack_geometry.slot_width_mm", w, f"<= {depths[0] / 5:g} mm for the tooth-crack curve's "
                         f"shallowest crack ({depths[0]:g} mm = {DEPTH_FRACTIONS[0]:g} of the root thickness)")
    return depths


def signature(infl: Mapping, mesh: Mapping, angles: list[dict]) -> np.ndarray:
    """(RAMP_STEPS, len(angles)): the twist change (rad) the crack of ``infl["crack_delta"]`` adds at each step of
    the 0 -> rated ramp with tooth 0 at each position: tooth_mesh.crack_signature's chain (same pairs, the same
    added compliance on tooth 0's +flank pair, frictionless), kept along the ramp."""
    from strainwave.fea.mesh_contact import MeshSystem, solve_torque_path
    ramp = np.linspace(0.0, mesh["rated_torque_Nmm"], RAMP_STEPS)
    out = np.zeros((RAMP_STEPS, len(angles)))
    for k, pairs in enumerate(angles):
        C = tm.pair_compliance(infl, pairs, mesh["z_f"], mesh["z_c"])
        hit = np.flatnonzero((pairs["tooth"] == 0) & (pairs["side"] == 1))
        twists = []
        for cracked in (False, True):
            Ck = C.copy()
            if cracked and hit.size:
                w = tm._interp_weights(infl["fs_radii"], pairs["fs_radius_mm"][hit])[0]
                Ck[hit[0], hit[0]] += float(w @ infl["crack_delta"] @ w)
            system = MeshSystem(pairs["clearance_mm"], Ck, pairs["lever_mm"], pairs["slide_mm_per_rad"], 0.0,
                                mesh["rim_radius_mm"])
            twists.append(solve_torque_path(system, ramp).twist_rad)
        out[:, k] = twists[1] - twists[0]
    return out


def _crack_delta(params, mesh: Mapping, h_mm: float, depth_mm: float, infl: Mapping) -> np.ndarray:
    """Tooth 0's added flank compliance (mm/N, on the FS radii grid) of a root crack ``depth_mm`` deep."""
    from strainwave.fea.assembly import Lame
    from strainwave.geometry.mesh_geometry import mesh_geometry
    geo = mesh_geometry(params)
    m = params.material
    lame = Lame.from_young(m.youngs_modulus_MPa, m.poisson_ratio, plane_stress=False)
    hs = tm.SECTOR_H_RATIO * h_mm
    body = geo.fs.root_radius_mm - tm.SOLID_DEPTH_OVER_M * geo.fs.module_mm
    cracked = fe.sector_model(geo.fs, body, 2, hs, lame, geo.face_width_mm,
                              crack=(depth_mm, mesh["slot_width_mm"]))
    band = tm.BAND_OVER_M * geo.fs.module_mm
    c = fe.influence(cracked, geo.fs.root_radius_mm, np.asarray(infl["fs_radii"]), band, +1, np.array([0]), None)
    return c[0] - infl["fs_solid"][0]


def _tooth_ratio(infl: Mapping, mesh: Mapping, delta: np.ndarray) -> float:
    """The cracked tooth's own compliance over the sound one's at the major axis's contact radius."""
    w = tm._interp_weights(infl["fs_radii"], np.array([mesh["major_fs_radius_mm"]]))[0]
    base = float(w @ infl["fs_solid"][0] @ w)
    return (base + float(w @ delta @ w)) / base


def mesh_values(params, mesh: Mapping, h_mm: float, depths: tuple[float, ...], angles: list[dict]) -> list[dict]:
    """Per depth on one mesh size: the cracked tooth's compliance ratio and the twist change along the ramp."""
    infl, _ = tm.influences(params, dict(mesh) | {"crack_depth_mm": depths[0]}, h_mm)
    infl.pop("rim")
    out = []
    for k, a in enumerate(depths):
        delta = infl["crack_delta"] if k == 0 else _crack_delta(params, mesh, h_mm, a, infl)
        change = signature(dict(infl) | {"crack_delta": delta}, mesh, angles)
        out.append({"depth_mm": a, "tooth_ratio": _tooth_ratio(infl, mesh, delta), "change_rad": change.tolist()})
    return out


def curve_points(params, mesh: Mapping, angles: list[dict], *, quick: bool = False,
                 progress: Callable[[str], None] = lambda m: None) -> dict:
    """The raw curve on the study's three meshes (finest first): per mesh and depth the cracked tooth's compliance
    ratio and the twist change (rad) at every ramp step and position of tooth 0; a JSON-ready record, from which
    compare/diagnose/tooth_crack.py forms each quantity and its GCI. ``angles``: the kinematic flank pairs with
    tooth 0 at each of PHI_DEG, handed in as numbers (closed forms stay out of fea/)."""
    depths = curve_depths_mm(params)
    sizes = tm.refinements(params.flexspline_cup.module_mm, quick)
    per_mesh = []
    for h in sizes[::-1]:                                 # coarse first: a failure shows early and cheap
        progress(f"tooth-crack curve: mesh h = {h:.3g} mm, {len(depths)} depths x {len(angles)} positions")
        per_mesh.append(mesh_values(params, mesh, h, depths, angles))
    from strainwave.geometry.mesh_geometry import mesh_geometry
    geo = mesh_geometry(params)
    return {"sizes_mm": list(sizes), "depths_mm": list(depths), "root_thickness_mm": root_thickness_mm(params),
            "wall_mm": float(geo.fs.root_radius_mm - geo.r_bore_mm),          # the rim below the root
            "phi_rad": np.radians(PHI_DEG).tolist(), "rated_torque_Nmm": float(mesh["rated_torque_Nmm"]),
            "torque_fractions": np.linspace(0.0, 1.0, RAMP_STEPS).tolist(), "per_mesh": per_mesh[::-1]}
