"""The circular spline: the rigid ring gear with Z_c = Z_f + U internal teeth around the flexspline's band.

Frame: axis z, the teeth from z = 0 (``side_bottom``) to z = b = ``circular_spline.face_width_mm``
(``side_top``), a tooth SPACE centred on +x (the cup's tooth 0 engages there at the major axis), the rim the
cylinder of ``circular_spline.outer_diameter_mm`` (``rim``). Teeth: ``involute.circular_spline_tooth_spec``
(the cup's module and basic rack, the design's addendum, shifted so its rack meets the cup's at the major
axis, thinned by the backlash), drawn in ``circular_spline.profile``'s form (``tooth_profiles``).
Named faces: ``tooth_flank``, ``tooth_tip`` (tip cylinder), ``tooth_root`` (root cylinder), ``root_fillet``,
``rim``, ``side_bottom``, ``side_top``.
"""
from __future__ import annotations

from strainwave.errors import InputError

from strainwave.geometry import faces as F
from strainwave.geometry import tooth_profiles
from strainwave.geometry.involute import check_teeth, circular_spline_tooth_spec, mesh_clearances_mm
from strainwave.geometry.part import Part, PartName

__all__ = ["build", "section"]

MIN_RIM_OVER_M = 1.0     # the rim under the tooth roots: at least one module (else it is no ring gear)


def _checked_spec(params):
    cs = params.circular_spline
    spec = circular_spline_tooth_spec(params)
    check_teeth(spec, "circular_spline.addendum_coefficient", cs.addendum_coefficient, "circular spline")
    r_out = 0.5 * cs.outer_diameter_mm
    if r_out < spec.root_radius_mm + MIN_RIM_OVER_M * spec.module_mm:
        raise InputError("circular_spline.outer_diameter_mm", cs.outer_diameter_mm,
                         f"must be >= 2 (root radius {spec.root_radius_mm:.4g} mm + one module) = "
                         f"{2 * (spec.root_radius_mm + MIN_RIM_OVER_M * spec.module_mm):.4g} mm")
    return spec


def section(params, *, teeth: bool = True):
    """The 2D xy section (build123d Face): rim circle outside, the toothed outline (or, without teeth, the tip
    circle) as the hole, a tooth space on +x."""
    from build123d import Axis, Edge, Face, Wire

    spec = _checked_spec(params)
    rim = Wire([Edge.make_circle(0.5 * params.circular_spline.outer_diameter_mm)])
    if not teeth:
        return Face(rim, [Wire([Edge.make_circle(spec.tip_radius_mm)])])
    hole = tooth_profiles.outline_wire(params.circular_spline.profile, spec)
    return Face(rim, [hole]).rotate(Axis.Z, 180.0 / spec.teeth)   # half a pitch: a space on +x


def build(params, *, crack_depth_mm: float | None = None, teeth: bool = True) -> Part:
    from build123d import extrude

    cs = params.circular_spline
    spec = _checked_spec(params)
    face = section(params, teeth=teeth)
    solid = extrude(face, amount=cs.face_width_mm, clean=False).solids()[0]
    r_out = 0.5 * cs.outer_diameter_mm
    clear = mesh_clearances_mm(params)
    meta = {"teeth": spec.teeth if teeth else 0, "module_mm": spec.module_mm, "pitch_radius_mm": spec.pitch_radius_mm,
            "tip_radius_mm": spec.tip_radius_mm, "root_radius_mm": spec.root_radius_mm,
            "root_fillet_mm": spec.root_fillet_mm, "shift_coef": spec.shift_coef, "thinning_mm": spec.thinning_mm,
            "outer_radius_mm": r_out, "face_width_mm": cs.face_width_mm, "profile": cs.profile.value,
            "profile_source": cs.profile_source, "pressure_angle_deg": spec.pressure_angle_deg,
            "rim_under_roots_mm": r_out - spec.root_radius_mm,
            "clearance_root_major_mm": clear.root_major_mm, "clearance_tip_minor_mm": clear.tip_minor_mm,
            "backlash_per_flank_mm": clear.flank_mm, "working_depth_mm": clear.working_depth_mm,
            "area_closed_form_mm2": float(face.area)}
    return Part(PartName.CIRCULAR_SPLINE, solid, _named(solid, meta, teeth), (), face, meta)


def _named(solid, meta: dict, teeth: bool) -> dict:
    infos = F.face_infos(solid)
    b = meta["face_width_mm"]
    tol = 1e-6 * max(1.0, meta["outer_radius_mm"])
    named = {"rim": F.refs(F.select(infos, F.is_cylinder(meta["outer_radius_mm"], tol))),
             "side_bottom": F.refs(F.select(infos, F.is_zplane(0.0, tol))),
             "side_top": F.refs(F.select(infos, F.is_zplane(b, tol)))}
    tip = F.select(infos, F.is_cylinder(meta["tip_radius_mm"], tol))
    if not teeth:
        return {**named, "bore": F.refs(tip)}
    root = F.select(infos, F.is_cylinder(meta["root_radius_mm"], tol))
    fillet = F.select(infos, lambda fi: fi.kind == "cylinder" and abs(fi.radius_mm - meta["outer_radius_mm"]) > tol
                      and abs(fi.radius_mm - meta["root_radius_mm"]) > tol and abs(fi.radius_mm - meta["tip_radius_mm"]) > tol)
    taken = (*tip, *root, *fillet)
    flank = F.select(infos, F.without(lambda fi: fi.kind == "other", taken))
    return {**named, "tooth_flank": F.refs(flank), "tooth_tip": F.refs(tip), "tooth_root": F.refs(root),
            "root_fillet": F.refs(fillet)}
