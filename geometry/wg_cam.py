"""The cup-type gear's wave generator cam (seed 000's drive): the elliptical plug the bearing's inner ring sits on.

The bearing ring's bore is forced onto this outline (fea/wg_bearing.py: u_r = w0 cos 2 phi), and through the
bearing the cup's bore onto the same w0 (fea/wg_band.py's rigid cam). Its outline is the ellipse of semi-axes r_b + w0 (x, the major axis) and r_b - w0 (y), where r_b is the
bearing inner ring's bore radius (geometry/bearing_ring.py) and w0 = ``gear.radial_deformation_mm``. It is as
wide as the ring (z = 0..B) and has a round bore for the input shaft of radius ``HUB_BORE_OVER_MINOR`` x the
minor semi-axis (chosen: the seeds give no input shaft). Named faces: ``contact`` (the elliptical outline, under
the ring's bore) and ``bore`` (the input shaft's seat).
"""
from __future__ import annotations

import math

from strainwave.errors import InputError

from strainwave.geometry import faces as F
from strainwave.geometry.part import Part, PartName

__all__ = ["HUB_BORE_OVER_MINOR", "cam_semi_axes_mm", "build"]

HUB_BORE_OVER_MINOR = 0.4     # input-shaft bore over the minor semi-axis (chosen; the seeds give none)


def cam_semi_axes_mm(params) -> tuple[float, float]:
    """(major, minor) semi-axes: the bearing ring's bore radius +- w0."""
    from strainwave.geometry.bearing_ring import check_ring_fits

    _, r_bore = check_ring_fits(params)
    w0 = params.gear.radial_deformation_mm
    if r_bore - w0 <= 0:
        raise InputError("gear.radial_deformation_mm", w0, f"must be < the bearing ring's bore radius {r_bore:g} mm")
    return r_bore + w0, r_bore - w0


def build(params, *, crack_depth_mm: float | None = None, teeth: bool = True) -> Part:
    from build123d import Edge, Face, Plane, Wire, extrude


    a, b = cam_semi_axes_mm(params)
    r_hub = HUB_BORE_OVER_MINOR * b
    width = params.wave_generator.bearing_width_mm     # the ring's width
    outline = Wire([Edge.make_ellipse(a, b, Plane.XY)])
    face = Face(outline, [Wire([Edge.make_circle(r_hub)])])
    solid = extrude(face, amount=width).solids()[0]
    infos = F.face_infos(solid)
    named = {"contact": F.refs(F.select(infos, lambda fi: fi.kind == "other")),
             "bore": F.refs(F.select(infos, F.is_cylinder(r_hub)))}
    meta = {"cam_semi_axes_mm": (a, b), "w0_mm": params.gear.radial_deformation_mm, "hub_bore_radius_mm": r_hub,
            "width_mm": width, "volume_closed_form_mm3": (math.pi * a * b - math.pi * r_hub ** 2) * width}
    return Part(PartName.WG_CAM, solid, named, (), None, meta)
