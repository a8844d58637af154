"""Wave-generator bearing inner ring (seed 000): thickness t_i, raceway, contact patch, surface crack.

Geometry choices (the seed gives t_i and the contact ellipse a' x b' only):
- the ring sits inside the flexspline bore as built: race (outer) radius R = d1/2 - delta - t_o - D_w (the
  outer ring's thickness and the ball between), bore R - t_i (t_i the RADIAL thickness), width B =
  ``wave_generator.bearing_width_mm`` (seed 000's t_i: the race crack's front runs across it);
- the raceway is the outer cylinder (a roller-type race; a ball groove would only change the contact
  geometry, which the FEA prescribes as a pressure patch anyway);
- ``contact``: a patch imprinted on the race at +x, the rectangle of the contact ellipse's area
  (half sides sqrt(pi)/2 a' axially and sqrt(pi)/2 b' circumferentially), centred at z = width/2;
- crack: semi-elliptical surface crack at +x in the plane y = 0 (normal to the circumferential stress),
  depth a, half length c from Q = 1 + 1.464 (a/c)^1.65 (seed 000), centred at z = width/2. As a slot
  (CAD) or, with ``CrackModel.SEAM``, as the half-ellipse surface ``Part.crack_surface`` on the whole ring.
"""
from __future__ import annotations

import math

from strainwave.errors import InputError

from strainwave.geometry import faces as F
from strainwave.geometry.crack_seams import semi_elliptical_seam
from strainwave.geometry.cracks import check_crack, half_length_from_q, semi_elliptical_slot
from strainwave.geometry.occ import cut, imprint
from strainwave.geometry.part import CrackModel, Part, PartName



def race_radius_mm(params) -> float:
    """The inner race's radius as built: the flexspline's bore less the outer ring and one ball."""
    wg, fc = params.wave_generator, params.flexspline_cup
    return fc.pitch_diameter_mm / 2 - fc.wall_thickness_mm - wg.outer_ring_thickness_mm - wg.ball_diameter_mm


def check_ring_fits(params) -> tuple[float, float]:
    """(race, bore) radii of the inner ring, refused (exit 2) when the ring would close its bore."""
    wg = params.wave_generator
    r_race = race_radius_mm(params)
    if r_race - wg.bearing_inner_ring_thickness_mm <= 0:
        raise InputError("wave_generator.bearing_inner_ring_thickness_mm", wg.bearing_inner_ring_thickness_mm,
                         f"the ring would close its bore: must be < d1/2 - delta - t_o - D_w = {r_race:g} mm")
    return r_race, r_race - wg.bearing_inner_ring_thickness_mm


def _patch_face(r_mm: float, half_theta_rad: float, z0_mm: float, z1_mm: float):
    """A face on the cylinder r = r_mm over |theta| <= half_theta and z0 <= z <= z1 (for imprinting)."""
    from build123d import Face
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace
    from OCP.Geom import Geom_CylindricalSurface
    from OCP.gp import gp_Ax3, gp_Dir, gp_Pnt

    surf = Geom_CylindricalSurface(gp_Ax3(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1), gp_Dir(1, 0, 0)), r_mm)
    return Face(BRepBuilderAPI_MakeFace(surf, -half_theta_rad, half_theta_rad, z0_mm, z1_mm, 1e-7).Face())


def build(params, *, crack_depth_mm: float | None = None, teeth: bool = True,
          crack_model: CrackModel = CrackModel.SLOT) -> Part:
    wg, fc, cg = params.wave_generator, params.flexspline_cup, params.crack_geometry
    t_i = wg.bearing_inner_ring_thickness_mm
    a_c, b_c = wg.contact_semi_axes_mm
    r_race, r_bore = check_ring_fits(params)
    width = wg.bearing_width_mm
    hz, hs = 0.5 * math.sqrt(math.pi) * a_c, 0.5 * math.sqrt(math.pi) * b_c
    if hs >= 0.5 * math.pi * r_race:
        raise InputError("wave_generator.contact_semi_axes_mm", list(wg.contact_semi_axes_mm),
                         "b' is too large for the race circumference")
    z_mid = width / 2
    if crack_depth_mm is not None:  # refuse bad cracks before any CAD work
        check_crack(crack_depth_mm, t_i, "wave_generator.bearing_inner_ring_thickness_mm",
                    0.0 if crack_model == CrackModel.SEAM else cg.slot_width_mm)
        c = half_length_from_q(crack_depth_mm, params.cracks.surface_crack_shape_factor)
        if c >= hz:
            raise InputError("cracks.surface_crack_shape_factor", params.cracks.surface_crack_shape_factor,
                             f"gives a crack half length c = {c:g} mm longer than the contact patch ({hz:g} mm)")
    from build123d import Axis, Solid

    # cylinder seams at -x, away from the contact patch and the crack at +x (no face split there)
    solid = cut(Solid.make_cylinder(r_race, width), Solid.make_cylinder(r_bore, width)).rotate(Axis.Z, 180)
    solid = imprint(solid, _patch_face(r_race, hs / r_race, z_mid - hz, z_mid + hz))
    meta = {"race_radius_mm": r_race, "bore_radius_mm": r_bore, "thickness_mm": t_i, "width_mm": width,
            "contact_half_sides_mm": (hz, hs), "contact_patch_area_mm2": 4 * hz * hs,
            "contact_ellipse_area_mm2": math.pi * a_c * b_c,
            "volume_closed_form_mm3": math.pi * (r_race ** 2 - r_bore ** 2) * width}
    slot = seam = None
    if crack_depth_mm is not None and crack_model == CrackModel.SEAM:
        seam = semi_elliptical_seam(r_race, crack_depth_mm, c, z_mid)
        meta.update(seam.meta, crack_depth_mm=crack_depth_mm, crack_model=CrackModel.SEAM.value)
    elif crack_depth_mm is not None:
        slot = semi_elliptical_slot(r_race, crack_depth_mm, c, z_mid, cg.slot_width_mm)
        solid = cut(solid, slot.tool)
        meta.update(slot.meta, crack_depth_mm=crack_depth_mm, slot_width_mm=cg.slot_width_mm,
                    slot_volume_mm3=slot.volume_mm3)
        meta["volume_closed_form_mm3"] -= slot.volume_mm3

    infos = F.face_infos(solid)
    race_all = F.select(infos, F.is_cylinder(r_race))
    contact = F.select(race_all, lambda fi: fi.center_mm[0] > 0 and abs(fi.center_mm[1]) < hs + 1e-9
                       and fi.bbox_min[2] > 1e-6 and fi.bbox_max[2] < width - 1e-6)
    named = {"bore": F.refs(F.select(infos, F.is_cylinder(r_bore))),
             "race": F.refs(F.select(race_all, F.without(lambda fi: True, contact))),
             "contact": F.refs(contact),
             "side_bottom": F.refs(F.select(infos, F.is_zplane(0.0))),
             "side_top": F.refs(F.select(infos, F.is_zplane(width)))}
    if slot is not None:
        inside = F.select(infos, F.in_box(slot.box_lo, slot.box_hi))
        named["crack_face"] = F.refs(F.select(inside, lambda fi: fi.kind == "plane"))
        named["crack_front"] = F.refs(F.select(inside, lambda fi: fi.kind != "plane"))
    if seam is not None:
        return Part(PartName.WG_BEARING_RING, solid, named, seam.front_mm, None, meta, seam.face,
                    (seam.point_mm, seam.normal))
    return Part(PartName.WG_BEARING_RING, solid, named, slot.front_mm if slot else (), None, meta)
