"""External wave generator (seed 003): two rollers on the minor axis, or an elliptical cam ring.

Placed in the ring's frame (axis z, z = 0..B) so that an assembly can be exported: the EWG surface
reaches radius r_o - W0 on the minor axis (+/- y), where r_o is the ring's outer radius and
W0 = 0.5 m dZ (seed 003, eq 7). The undeformed ring therefore overlaps the EWG by W0 there: the
assembly shows the interference that the EWG imposes.

- rollers: two cylinders of radius 0.3 r_o, length B, centres at y = +/-(r_o - W0 + R). Two solids.
- cam ring: one solid whose bore is an ellipse with semi-axes r_o + k W0 (x) and r_o - W0 (y), where
  k = delta_AB / delta_CD = (2/pi - 1/2) / ((pi^2 - 8)/(4 pi)) = 0.9183 (seed 003, eqs 3-4: the ring
  does not deform into an ellipse, its major semi-axis grows by 0.918 W0); outer radius r_o + W0 + 0.3 r_o.
"""
from __future__ import annotations

import math

from strainwave.params import EwgGenerator

from strainwave.geometry import faces as F
from strainwave.geometry.ewg_ring import radii_mm
from strainwave.geometry.part import Part, PartName

ROLLER_RATIO = 0.3
K_AB_OVER_CD = (2 / math.pi - 0.5) / ((math.pi ** 2 - 8) / (4 * math.pi))


def build(params, *, crack_depth_mm: float | None = None, teeth: bool = True) -> Part:
    from build123d import Compound, Edge, Face, Location, Plane, Solid, Wire, extrude

    e = params.ewg_drive
    r_o = radii_mm(params)["outer_radius_mm"]
    w0 = 0.5 * e.module_mm * e.tooth_difference
    width = e.face_width_mm
    meta = {"W0_mm": w0, "ring_outer_radius_mm": r_o, "face_width_mm": width, "generator": e.generator.value,
            "contact_radius_mm": r_o - w0}
    if e.generator == EwgGenerator.ROLLERS:
        rr = ROLLER_RATIO * r_o
        yc = r_o - w0 + rr
        rollers = [Solid.make_cylinder(rr, width).moved(Location((0, s * yc, 0))) for s in (1, -1)]
        solid = Compound(rollers)
        meta.update(roller_radius_mm=rr, roller_centre_y_mm=yc,
                    volume_closed_form_mm3=2 * math.pi * rr ** 2 * width)
        infos = F.face_infos(solid)
        named = {"contact": F.refs(F.select(infos, F.is_cylinder(rr)))}
    else:
        a, b = r_o + K_AB_OVER_CD * w0, r_o - w0
        r_out = r_o + w0 + ROLLER_RATIO * r_o
        hole = Wire([Edge.make_ellipse(a, b, Plane.XY)])
        face = Face(Wire([Edge.make_circle(r_out)]), [hole])
        solid = extrude(face, amount=width).solids()[0]
        meta.update(cam_semi_axes_mm=(a, b), cam_outer_radius_mm=r_out,
                    volume_closed_form_mm3=(math.pi * r_out ** 2 - math.pi * a * b) * width)
        infos = F.face_infos(solid)
        named = {"contact": F.refs(F.select(infos, lambda fi: fi.kind == "other")),
                 "outer": F.refs(F.select(infos, F.is_cylinder(r_out)))}
    return Part(PartName.EWG, solid, named, (), None, meta)
