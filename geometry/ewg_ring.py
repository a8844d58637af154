"""Flexspline ring of the external-wave-generator drive (seed 003), internal teeth, as a prism.

Seed 003, eq 1: r_m = 0.5 d_R + h_fR + 0.5 delta with d_R = m Z_R, h_fR = h*_fR m and delta =
rim_thickness_ratio d_R. So the rim (``outer`` at r_m + delta/2) lies outside the internal teeth's root
circle r_m - delta/2; the smooth variant replaces the teeth by the bore r_m - delta/2 (same mid-layer).

The outer cylinder is split into the two ``contact`` strips at the minor axis (+y and -y, +/- 2 deg),
where the EWG rollers press, by building the section's outer circle from four arcs; the same
arcs are separate edges of ``Part.section`` (the 2D plane-stress domain, xy plane, z = 0).
"""
from __future__ import annotations

import math

from strainwave.geometry import faces as F
from strainwave.geometry.involute import ToothSpec, ewg_tooth_spec, gear_face
from strainwave.geometry.part import Part, PartName

CONTACT_HALF_ANGLE_DEG = 2.0


def tooth_spec(params) -> ToothSpec:
    return ewg_tooth_spec(params)


def radii_mm(params) -> dict:
    """Reference, root, mid-layer (eq 1) and outer radii of the ring."""
    e = params.ewg_drive
    d_r, h_f, delta = e.reference_diameter_mm, e.dedendum_coefficient * e.module_mm, e.rim_thickness_mm
    r_root = 0.5 * d_r + h_f
    return {"reference_radius_mm": 0.5 * d_r, "root_radius_mm": r_root, "r_m_mm": r_root + 0.5 * delta,
            "outer_radius_mm": r_root + delta, "rim_thickness_mm": delta}


def outer_wire(r_mm: float, half_angle_deg: float = CONTACT_HALF_ANGLE_DEG):
    """Circle of radius r as four arcs: contact arcs centred on +y and -y, and the two arcs between."""
    from build123d import Edge, Wire

    h = math.radians(half_angle_deg)
    cuts = [math.pi / 2 - h, math.pi / 2 + h, 3 * math.pi / 2 - h, 3 * math.pi / 2 + h]
    edges = []
    for a0, a1 in zip(cuts, cuts[1:] + [cuts[0] + 2 * math.pi]):
        am = 0.5 * (a0 + a1)
        edges.append(Edge.make_three_point_arc(*[(r_mm * math.cos(a), r_mm * math.sin(a), 0.0) for a in (a0, am, a1)]))
    return Wire(edges)


def section(params, teeth: bool = True):
    """2D cross-section Face in the xy plane (toothed or smooth) with split contact arcs."""
    from build123d import Edge, Face, Wire

    r = radii_mm(params)
    outer = outer_wire(r["outer_radius_mm"])
    if teeth:
        hole = gear_face(tooth_spec(params), outer_radius_mm=r["outer_radius_mm"]).inner_wires()[0]
    else:
        hole = Wire([Edge.make_circle(r["root_radius_mm"])])
    return Face(outer, [hole])


def build(params, *, crack_depth_mm: float | None = None, teeth: bool = True) -> Part:
    from build123d import extrude

    e = params.ewg_drive
    r = radii_mm(params)
    face = section(params, teeth)
    solid = extrude(face, amount=e.face_width_mm, clean=False).solids()[0]
    r_o, r_f, width = r["outer_radius_mm"], r["root_radius_mm"], e.face_width_mm
    spec = tooth_spec(params)
    infos = F.face_infos(solid)
    outer_all = F.select(infos, F.is_cylinder(r_o))
    h = math.radians(CONTACT_HALF_ANGLE_DEG)
    contact = F.select(outer_all, lambda fi: abs(fi.center_mm[0]) < r_o * math.sin(h) + 1e-9)
    named = {
        "outer": F.refs(F.select(outer_all, F.without(lambda fi: True, contact))),
        "contact": F.refs(contact),
        "side_bottom": F.refs(F.select(infos, F.is_zplane(0.0))),
        "side_top": F.refs(F.select(infos, F.is_zplane(width))),
    }
    inner = F.select(infos, F.without(lambda fi: fi.kind != "plane", outer_all))
    named["bore"] = F.refs(inner)
    if teeth:
        named["tooth_flank"] = F.refs(F.select(inner, lambda fi: fi.kind == "other"))
    meta = dict(r, face_width_mm=width, teeth=e.flexspline_teeth if teeth else 0, module_mm=e.module_mm,
                tip_radius_mm=spec.tip_radius_mm, root_fillet_mm=spec.root_fillet_mm,
                contact_half_angle_deg=CONTACT_HALF_ANGLE_DEG, contact_angles_deg=(90.0, 270.0),
                section_area_mm2=float(face.area), W0_mm=0.5 * e.module_mm * e.tooth_difference,
                volume_closed_form_mm3=(math.pi * (r_o ** 2 - r_f ** 2) * width) if not teeth else float(face.area) * width)
    return Part(PartName.EWG_FLEXSPLINE_RING, solid, named, (), face, meta)
