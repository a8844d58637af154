"""The cup-type gear as a drive that goes together: the cup on the wave generator, in mesh with the circular spline.

Placed as the design puts each part (z up the cup's axis, the cup's hub at z = 0):
- the wave generator (``wg_bearing``'s layout): cam, inner ring, balls, outer ring, centred on the toothed band;
  the cam's major axis on +x;
- the cup deformed by the cam: its toothed band and bore follow the bearing (the parallel curves of the cam's
  ellipse, so the bore lies on the outer ring: w0 out at the major axis, w0 in at the minor one), its wall cones
  (ruled) from round just above the diaphragm to that shape where the band begins. Each tooth moves rigidly: it
  stays normal to the deformed root curve, tooth j on the normal through j/Z of the neutral (mid-wall) line's
  arc length from the major axis (an inextensible rim), so the cup's tooth 0 stands on the major axis;
- the circular spline, concentric, centred on the band, a tooth space on +x where the cup's tooth 0 engages;
- the output shaft below the hub.
Drawn as the design's geometry, not a solved deformation: the shape is the cam's, the teeth rigid on it.
"""
from __future__ import annotations

import math

import numpy as np

from strainwave.errors import InputError

from strainwave.geometry import faces as F
from strainwave.geometry import tooth_profiles
from strainwave.geometry.involute import cup_tooth_spec
from strainwave.geometry.occ import fuse, single_solid
from strainwave.geometry.part import Part, PartName
from strainwave.geometry.step_xcaf import Placed
from strainwave.geometry.wg_bearing import BearingLayout, bearing_layout, contour_edge, contour_points

# The cam stands out of the bearing by this many ball diameters towards the diaphragm (its hub, for the input's
# coupling; chosen): a cam exactly as wide as the ring would give its contact face the ring bore's centre and area,
# which the STEP face names (matched by centre and area, step_xcaf) cannot tell apart.
CAM_HUB_OVER_D = 0.5
GROOVE_TOL_MM = 1e-7        # the swept groove's approximation (OCC's default, 1e-4, puts a ball 2e-5 mm off its race)

__all__ = ["bearing_parts", "build_balls", "build_outer_ring", "deformed_cup", "cup_gear_assembly"]


def _annulus_face(layout: BearingLayout, r_in_mm: float, r_out_mm: float, z_mm: float = 0.0):
    """The plane region between the contours of two round radii (deformed by the layout's cam)."""
    from build123d import Face, Wire

    a, b = layout.cam_semi_axes_mm
    outer = Wire([contour_edge(a, b, layout.offset_mm(r_out_mm), z_mm)])
    inner = Wire([contour_edge(a, b, layout.offset_mm(r_in_mm), z_mm)])
    return Face(outer, [inner])


def _ring(layout: BearingLayout, r_in_mm: float, r_out_mm: float):
    from build123d import extrude

    return extrude(_annulus_face(layout, r_in_mm, r_out_mm), amount=layout.width_mm, dir=(0, 0, 1)).solids()[0]


def _ring_faces(solid, layout: BearingLayout, inner: str, outer: str) -> dict:
    """Names of a grooved ring's faces: its z planes, the groove (``race``: the only curved face clear of both
    planes), the lands beside it (``land``) and the plain contour surface on the other side (``inner``/``outer``,
    whichever the groove is not on; told apart from the lands by reach)."""
    infos = F.face_infos(solid)
    tol = 1e-6 * layout.outer_radius_mm
    w = layout.width_mm
    curved = [fi for fi in infos if fi.kind != "plane"]
    race = [fi for fi in curved if fi.bbox_min[2] > tol and fi.bbox_max[2] < w - tol]
    sides = [fi for fi in curved if fi not in race]
    reach = max(fi.bbox_max[0] for fi in sides)
    far = [fi for fi in sides if fi.bbox_max[0] >= reach - tol]
    near = [fi for fi in sides if fi.bbox_max[0] < reach - tol]
    plain, lands = (near, far) if outer == "race" else (far, near)     # the groove is on the lands' side
    return {inner if outer == "race" else outer: F.refs(plain), "race": F.refs(race), "land": F.refs(lands),
            "side_bottom": F.refs(F.select(infos, F.is_zplane(0.0, tol))),
            "side_top": F.refs(F.select(infos, F.is_zplane(w, tol)))}


def _perimeter_mm(layout: BearingLayout, radius_mm: float) -> float:
    """Perimeter of the contour a round circle of ``radius_mm`` becomes."""
    q, _ = contour_points(*layout.cam_semi_axes_mm, layout.offset_mm(radius_mm), np.linspace(0.0, 1.0, 20001))
    return float(np.hypot(*np.diff(q, axis=0).T).sum())


def _area_between_mm2(layout: BearingLayout, r_in_mm: float, r_out_mm: float) -> float:
    """Area between two parallel curves of a convex curve: P_in w + pi w^2 (Steiner), P_in the inner perimeter."""
    w = r_out_mm - r_in_mm
    return _perimeter_mm(layout, r_in_mm) * w + math.pi * w * w


def _groove(layout: BearingLayout, centre_radius_mm: float):
    """The ball groove's cutter: a circle of the groove radius swept along the contour of its centre (mid-width)."""
    from build123d import Edge, Plane, Solid, Wire
    from OCP.BRepOffsetAPI import BRepOffsetAPI_MakePipeShell
    from OCP.gp import gp_Dir

    path = Wire([contour_edge(*layout.cam_semi_axes_mm, layout.offset_mm(centre_radius_mm), 0.5 * layout.width_mm)])
    circle = Edge.make_circle(layout.groove_radius_mm, Plane(origin=path.position_at(0), z_dir=path.tangent_at(0)))
    pipe = BRepOffsetAPI_MakePipeShell(path.wrapped)
    pipe.SetMode(gp_Dir(0.0, 0.0, 1.0))                  # the section stays upright: a parallel-curve tube
    pipe.SetTolerance(GROOVE_TOL_MM, GROOVE_TOL_MM, 1e-6)
    pipe.Add(Wire([circle]).wrapped)
    pipe.Build()
    if not pipe.IsDone() or not pipe.MakeSolid():
        raise RuntimeError("the bearing's groove could not be swept")
    return Solid(pipe.Shape())


def _groove_volume_mm3(layout: BearingLayout, centre_radius_mm: float, inward: bool) -> float:
    """What the groove takes from a ring: the circle's segment of height = groove depth (Pappus along the parallel
    curve through the segment's centroid), the segment towards the axis (``inward``, inner ring) or away."""
    r, h = layout.groove_radius_mm, layout.groove_depth_mm
    theta = 2 * math.acos((r - h) / r)
    area = 0.5 * r * r * (theta - math.sin(theta))
    centroid = 4 * r * math.sin(0.5 * theta) ** 3 / (3 * (theta - math.sin(theta)))
    return area * _perimeter_mm(layout, centre_radius_mm + (-centroid if inward else centroid))


def _layout(params, deformed: bool) -> BearingLayout:
    layout = bearing_layout(params)
    return layout if deformed else BearingLayout(**{**layout.__dict__, "w0_mm": 0.0})


def _meta(r: BearingLayout) -> dict:
    return {"layout": dict(r.__dict__), "width_mm": r.width_mm, "w0_mm": r.w0_mm}


def _cam(r: BearingLayout) -> Part:
    from build123d import Face, Wire, extrude

    a, b = r.cam_semi_axes_mm
    hub = r.hub_bore_radius_mm
    hub_mm = CAM_HUB_OVER_D * r.ball_diameter_mm
    face = Face(Wire([contour_edge(a, b, 0.0, -hub_mm)]), [Wire([contour_edge(hub, hub, 0.0, -hub_mm)])])
    cam = extrude(face, amount=r.width_mm + hub_mm, dir=(0, 0, 1)).solids()[0]
    infos = F.face_infos(cam)
    curved = [fi for fi in infos if fi.kind != "plane"]
    named = {"contact": F.refs(fi for fi in curved if fi.bbox_max[0] > hub + 1e-6),
             "bore": F.refs(fi for fi in curved if fi.bbox_max[0] <= hub + 1e-6),
             "sides": F.refs(fi for fi in infos if fi.kind == "plane")}
    return Part(PartName.WG_CAM, cam, named, (), None, {**_meta(r), "cam_semi_axes_mm": (a, b),
                                                       "volume_closed_form_mm3": (math.pi * a * b - math.pi * hub ** 2) * (r.width_mm + hub_mm)})


def _groove_centres_mm(r: BearingLayout) -> tuple[float, float]:
    """Round radii of the inner and outer grooves' centres: r_g - D_w/2 beyond the balls' pitch circle, so each
    groove's bottom is the race and the ball touches it there only."""
    e = r.groove_radius_mm - 0.5 * r.ball_diameter_mm
    return r.pitch_radius_mm + e, r.pitch_radius_mm - e


def _inner_ring(r: BearingLayout) -> Part:
    centre = _groove_centres_mm(r)[0]
    land = r.inner_race_radius_mm + r.groove_depth_mm
    solid = single_solid(_ring(r, r.bore_radius_mm, land).cut(_groove(r, centre)))
    volume = (_area_between_mm2(r, r.bore_radius_mm, land) * r.width_mm
              - _groove_volume_mm3(r, centre, inward=True))
    return Part(PartName.WG_BEARING_RING, solid, _ring_faces(solid, r, "bore", "race"), (), None,
                {**_meta(r), "volume_closed_form_mm3": volume})


def _balls(r: BearingLayout) -> Part:
    from build123d import Compound, Plane, Solid

    a, b = r.cam_semi_axes_mm
    centres, _ = contour_points(a, b, r.offset_mm(r.pitch_radius_mm), np.arange(r.ball_count) / r.ball_count)
    # one sphere made per ball, not moved copies of one: STEP names faces by their own shapes (step_xcaf)
    balls = Compound([Solid.make_sphere(0.5 * r.ball_diameter_mm, plane=Plane((float(x), float(y), 0.5 * r.width_mm)))
                      for x, y in centres])
    return Part(PartName.WG_BEARING_BALLS, balls, {"ball": F.refs(F.face_infos(balls))}, (), None,
                {**_meta(r), "centres_mm": [(float(x), float(y), 0.5 * r.width_mm) for x, y in centres],
                 "volume_closed_form_mm3": r.ball_count * math.pi * r.ball_diameter_mm ** 3 / 6})


def _outer_ring(r: BearingLayout) -> Part:
    centre = _groove_centres_mm(r)[1]
    land = r.outer_race_radius_mm - r.groove_depth_mm
    solid = single_solid(_ring(r, land, r.outer_radius_mm).cut(_groove(r, centre)))
    volume = (_area_between_mm2(r, land, r.outer_radius_mm) * r.width_mm
              - _groove_volume_mm3(r, centre, inward=False))
    return Part(PartName.WG_BEARING_OUTER_RING, solid, _ring_faces(solid, r, "race", "outer"), (), None,
                {**_meta(r), "volume_closed_form_mm3": volume})


def bearing_parts(params, *, deformed: bool = True) -> list[Part]:
    """Cam, inner ring, balls (one compound), outer ring in the bearing's frame (z = 0..width), on the cam's
    ellipse (``deformed``) or round (w0 = 0: each part as made, before assembly)."""
    r = _layout(params, deformed)
    return [_cam(r), _inner_ring(r), _balls(r), _outer_ring(r)]


def build_balls(params, *, crack_depth_mm: float | None = None, teeth: bool = True) -> Part:
    """``wg-bearing-balls``: the bearing's balls on the round pitch circle (as made), z = 0..width."""
    return _balls(_layout(params, False))


def build_outer_ring(params, *, crack_depth_mm: float | None = None, teeth: bool = True) -> Part:
    """``wg-bearing-outer-ring``: the bearing's flexible outer ring, round (as made), z = 0..width."""
    return _outer_ring(_layout(params, False))


def _deformed_teeth_wire(params, layout: BearingLayout):
    """The cup's toothed outline on the deformed root curve: each round tooth moved rigidly to stand normal to
    the curve at j/Z of its arc length, joined by root arcs through the curve."""
    from build123d import Edge, Location, Wire

    spec = cup_tooth_spec(params)
    a, b = layout.cam_semi_axes_mm
    d_root = layout.offset_mm(spec.root_radius_mm)
    # the rim is inextensible along its neutral line (mid-wall), not along the root curve the teeth stand on
    d_mid = layout.offset_mm(0.5 * params.flexspline_cup.pitch_diameter_mm - 0.5 * params.flexspline_cup.wall_thickness_mm)
    z = spec.teeth
    feet, normals = contour_points(a, b, d_mid, np.arange(z) / z, at_d=d_root)
    mids, _ = contour_points(a, b, d_mid, (np.arange(z) + 0.5) / z, at_d=d_root)
    moved = []
    for j, (tooth, _) in enumerate(tooth_profiles.edges(params.circular_spline.profile, spec)):
        beta = math.atan2(normals[j, 1], normals[j, 0])
        shift = feet[j] - spec.root_radius_mm * np.array([math.cos(beta), math.sin(beta)])
        at = Location((float(shift[0]), float(shift[1]), 0.0)) * Location((0, 0, 0), (0, 0, 1),
                                                                            math.degrees(beta - 2 * math.pi * j / z))
        moved.append([e.moved(at) for e in tooth])
    edges = []
    for j, tooth in enumerate(moved):
        nxt = moved[(j + 1) % z][0]
        edges += [*tooth, Edge.make_three_point_arc(tooth[-1].end_point(), (float(mids[j, 0]), float(mids[j, 1]), 0.0),
                                                     nxt.start_point())]
    return Wire(edges)


def _cone_start_mm(fc) -> float:
    """Where the cup's wall begins to cone: one wall thickness above the diaphragm region (round below)."""
    from strainwave.geometry.flexspline_cup import BAND_RATIO, BOSS_HEIGHT_WALLS, HUB_RATIO
    from strainwave.params import CupShape

    if not fc.cup:
        return 0.0
    t, r_i = fc.wall_thickness_mm, fc.pitch_diameter_mm / 2 - fc.wall_thickness_mm
    bottom = BOSS_HEIGHT_WALLS * t + (0.3 * (r_i - HUB_RATIO * fc.pitch_diameter_mm) + t
                                      if fc.shape == CupShape.BELL else t)
    z_b = fc.length_mm - BAND_RATIO * fc.pitch_diameter_mm
    if z_b <= bottom:
        raise InputError("flexspline_cup.length_mm", fc.length_mm,
                         f"must exceed the tooth band 0.2 d1 plus the diaphragm region = {fc.length_mm - z_b + bottom:g} mm")
    return bottom + min(t, 0.5 * (z_b - bottom))


def deformed_cup(params, *, teeth: bool = True) -> Part:
    """The cup as the wave generator holds it (see the module docstring), uncracked. With teeth two solids, the round
    hub and diaphragm with the coned wall, and the toothed band on it, touching at the band's start z_b; without,
    one."""
    from build123d import Axis, Compound, Edge, Face, Solid, Wire, extrude, revolve

    from strainwave.geometry.flexspline_cup import BAND_RATIO, _profile

    fc = params.flexspline_cup
    layout = bearing_layout(params)
    a, b = layout.cam_semi_axes_mm
    r_o, r_i, length = fc.pitch_diameter_mm / 2, fc.pitch_diameter_mm / 2 - fc.wall_thickness_mm, fc.length_mm
    z_b, z_c = length - BAND_RATIO * fc.pitch_diameter_mm, _cone_start_mm(fc)
    z_top = z_b if teeth else length      # without teeth the band is the wall's prismatic top: one ruled loft

    def loft(radius_mm: float):
        low = Wire([Edge.make_circle(radius_mm).moved(_at_z(z_c))])
        d = layout.offset_mm(radius_mm)
        tops = [Wire([contour_edge(a, b, d, z)]) for z in ((z_b, length) if z_top > z_b else (z_b,))]
        return Solid.make_loft([low, *tops], ruled=True)
    solid = loft(r_o).cut(loft(r_i)).solids()[0]
    if fc.cup:
        solid = fuse(revolve(_profile(fc, z_c, None), Axis.Z).solids()[0], solid, touching=True)
    if teeth:
        bore = Wire([contour_edge(a, b, layout.offset_mm(r_i), z_b)])
        outline = _deformed_teeth_wire(params, layout).moved(_at_z(z_b))
        band = extrude(Face(outline, [bore]), amount=length - z_b, dir=(0, 0, 1)).solids()[0]
        # two solids touching at z_b: OCC's glue fuse drops a 200-tooth band whose root arcs only approximate the
        # cone's top contour (measured: the default cup lost its band after 83 s), and a full fuse takes minutes
        solid = Compound([solid, band])
    meta = {"outer_radius_mm": r_o, "bore_radius_mm": r_i, "length_mm": length, "band_z_mm": (z_b, length),
            "cone_z_mm": (z_c, z_b), "w0_mm": layout.w0_mm, "teeth": fc.teeth if teeth else 0,
            "tip_radius_mm": cup_tooth_spec(params).tip_radius_mm, "root_radius_mm": cup_tooth_spec(params).root_radius_mm}
    return Part(PartName.FLEXSPLINE_CUP, solid, _deformed_cup_faces(solid, meta, fc.wall_thickness_mm), (), None, meta)


def _at_z(z_mm: float):
    from build123d import Location

    return Location((0.0, 0.0, z_mm))


def _deformed_cup_faces(solid, meta: dict, wall_mm: float) -> dict:
    """fixed (hub's bottom), rim, loaded (the band's teeth or smooth outside), bore (the deformed inside), outer (the
    coned outside), tooth_end (the teeth's ends where the band begins), closed_end (hub and diaphragm)."""
    infos = F.face_infos(solid)
    length, (z_c, z_b), w0 = meta["length_mm"], meta["cone_z_mm"], meta["w0_mm"]
    tol = 1e-6 * length
    inside = meta["bore_radius_mm"] + w0 + 0.5 * wall_mm      # a face reaching beyond this is on the outside
    fixed, rim = F.select(infos, F.is_zplane(0.0, tol)), F.select(infos, F.is_zplane(length, tol))
    tooth_end = F.select(infos, F.is_zplane(z_b, tol))
    # the wall's faces from the cone's start up: every face there but the z planes
    above_c = F.select(infos, lambda fi: fi.bbox_min[2] >= z_c - tol and (fi.kind != "plane" or abs(fi.normal[2]) < 1e-9))
    bore = tuple(fi for fi in above_c if fi.bbox_max[0] < inside)
    loaded = tuple(fi for fi in above_c if fi.bbox_max[0] >= inside and fi.bbox_min[2] >= z_b - tol)
    outer = tuple(fi for fi in above_c if fi.bbox_max[0] >= inside and fi.bbox_min[2] < z_b - tol)
    rest = F.select(infos, F.without(lambda fi: True, fixed, rim, tooth_end, bore, loaded, outer))
    named = {"fixed": fixed, "rim": rim, "loaded": loaded, "bore": bore, "outer": outer, "tooth_end": tooth_end,
             "closed_end": rest}
    return {k: F.refs(v) for k, v in named.items() if v}


def cup_gear_assembly(params, *, crack_depth_mm: float | None = None, teeth: bool = True) -> list[Placed]:
    """Cup (deformed), circular spline, cam, inner ring, balls, outer ring and output shaft, each placed where the
    design puts it. ``crack_depth_mm`` cracks the output shaft (the cup and bearing are drawn as assembled,
    uncracked: a seeded crack lives on the round parts ``export-step --part`` builds)."""
    from build123d import Location

    from strainwave.geometry.parts import build_part

    if teeth:
        _check_minor_axis(params)
        _warn_tooth_overlap(params)
    cup = deformed_cup(params, teeth=teeth)
    spline = build_part(PartName.CIRCULAR_SPLINE, params, teeth=teeth)
    shaft = build_part(PartName.OUTPUT_SHAFT, params, crack_depth_mm=crack_depth_mm)
    z_mid = 0.5 * sum(cup.meta["band_z_mm"])
    wg = bearing_parts(params)
    at_wg = Location((0, 0, z_mid - 0.5 * wg[0].meta["width_mm"]))
    return [Placed(cup), Placed(spline, Location((0, 0, z_mid - 0.5 * spline.meta["face_width_mm"]))),
            *(Placed(p, at_wg) for p in wg), Placed(shaft, Location((0, 0, -shaft.meta["length_mm"])))]


def _check_minor_axis(params) -> None:
    """Refuse a design whose tooth tips overlap at the minor axis (2 w0 < (h_a,f + h_a,c) m): no drive goes together."""
    from strainwave.geometry.involute import CUP_ADDENDUM_COEF, mesh_clearances_mm

    clear, m = mesh_clearances_mm(params), params.flexspline_cup.module_mm
    if clear.tip_minor_mm < -1e-9 * m:
        w0 = params.gear.radial_deformation_mm
        raise InputError("circular_spline.addendum_coefficient", params.circular_spline.addendum_coefficient,
                         f"the teeth's tips overlap by {-clear.tip_minor_mm:.3g} mm at the minor axis: with w0 = {w0:g} mm "
                         f"and the cup's addendum {CUP_ADDENDUM_COEF:g} m it must be <= 2 w0/m - {CUP_ADDENDUM_COEF:g} = "
                         f"{2 * w0 / m - CUP_ADDENDUM_COEF:.4g}")


def _warn_tooth_overlap(params) -> None:
    """Say where the design's rigid teeth overlap (the default's w0 = m pair does at 56-88 deg: decision 067)."""
    import warnings

    from strainwave.geometry.tooth_interference import ToothOverlapWarning, overlap_summary

    summary = overlap_summary(params)
    if summary:
        warnings.warn(ToothOverlapWarning(f"circular_spline: {summary}"), stacklevel=3)
