"""Flexspline cup (seed 000): thin cylindrical or bell-shaped cup, diaphragm and hub, teeth on the rim.

Geometry choices (the seed gives d1, delta, L only):
- wall: outer radius d1/2, bore d1/2 - delta, so the mid-surface r_m = (d1 - delta)/2 is the one of
  seed 000's lambda_f0 = k_f k_G c_L / (0.1 mu [1 - (1 - 2 c_delta)^4] d1^3) (tube d1 x (d1 - 2 delta));
- the hub (boss) lies at z = 0: outer radius 0.25 d1, bore 0.1 d1, height 4 delta; its bottom face is
  ``fixed``; the diaphragm (thickness delta) joins it at z = 3 delta .. 4 delta;
- cylindrical cup: fillet of radius delta at the inner wall/diaphragm corner; bell cup: the wall turns
  into the diaphragm through concentric arcs (inner radius 0.3 (r_bore - r_hub)), keeping thickness delta;
- the toothed band (``loaded``, the torque zone) spans the last b = 0.2 d1 of the length up to the open rim
  at z = L; with teeth it carries Z external involute teeth of module m (20 deg, addendum 1.0 m,
  dedendum 1.35 m) standing ON the wall: a profile shift x = (d1/2 - m Z/2)/m + 1.35 puts the root circle
  on the wall's outer radius d1/2 (x = 1.35 for the default m Z = d1). So the toothed rim is the smooth
  shell of thickness delta (same mid-surface) plus teeth, as in seed 003's r_m = d/2 + h_f + delta/2;
  without teeth the band is the smooth wall;
- ``cup = false`` gives an open tube (no diaphragm, no hub); then the face z = 0 is ``fixed``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from strainwave.errors import InputError
from strainwave.params import CupShape

from strainwave.geometry import faces as F
from strainwave.geometry.crack_seams import helical_through_seam
from strainwave.geometry.cracks import check_crack, inclined_root_slot
from strainwave.geometry.involute import ToothSpec, cup_tooth_spec, gear_edges, tip_thickness_mm, tooth_end_faces
from strainwave.geometry.occ import cut, fuse, sew_solid
from strainwave.geometry.part import CrackModel, Part, PartName

BAND_RATIO = 0.2          # tooth face width / d1
HUB_RATIO, HUB_BORE_RATIO = 0.25, 0.10
BOSS_HEIGHT_WALLS = 4.0   # boss height in wall thicknesses (diaphragm is the top one)
CRACK_ASPECT = 0.5        # a / c of the root crack: axial half length c = 2 a (seed gives depth only)


def _profile(fc, z_top: float, split_at: float | None):
    """Half section (x = radius, z) of the revolved body from z = 0 to ``z_top``."""
    from build123d import Edge, Face, Wire

    d1, t = fc.pitch_diameter_mm, fc.wall_thickness_mm
    r_o, r_i = d1 / 2, d1 / 2 - t
    E = Edge.make_line
    pts_outer = [(r_o, 0, z) for z in ([split_at] if split_at else [])] + [(r_o, 0, z_top)]
    if not fc.cup:
        chain = [(r_i, 0, 0.0), (r_o, 0, 0.0), *pts_outer, (r_i, 0, z_top)]
        edges = [E(a, b) for a, b in zip(chain, chain[1:] + chain[:1])]
        return Face(Wire(edges))
    r_hub, r_hb = HUB_RATIO * d1, HUB_BORE_RATIO * d1
    z0, z1 = (BOSS_HEIGHT_WALLS - 1) * t, BOSS_HEIGHT_WALLS * t
    arc = Edge.make_three_point_arc
    edges = [E((r_hb, 0, 0), (r_hub, 0, 0)), E((r_hub, 0, 0), (r_hub, 0, z0))]
    if fc.shape == CupShape.BELL:
        rb = 0.3 * (r_i - r_hub)
        cx, cz = r_i - rb, z1 + rb          # common centre of both arcs: wall stays delta thick
        ro = rb + t
        s = math.sqrt(0.5)
        edges += [E((r_hub, 0, z0), (cx, 0, z0)),
                  arc((cx, 0, z0), (cx + ro * s, 0, cz - ro * s), (r_o, 0, cz))]
        start_out = (r_o, 0, cz)
        inner = [arc((r_i, 0, cz), (cx + rb * s, 0, cz - rb * s), (cx, 0, z1)), E((cx, 0, z1), (r_hb, 0, z1))]
        inner_top = (r_i, 0, cz)
    else:
        rf = t
        s = math.sqrt(0.5)
        edges += [E((r_hub, 0, z0), (r_o, 0, z0))]
        start_out = (r_o, 0, z0)
        inner = [arc((r_i, 0, z1 + rf), (r_i - rf + rf * s, 0, z1 + rf - rf * s), (r_i - rf, 0, z1)),
                 E((r_i - rf, 0, z1), (r_hb, 0, z1))]
        inner_top = (r_i, 0, z1 + rf)
    chain = [start_out, *pts_outer]
    edges += [E(a, b) for a, b in zip(chain, chain[1:])]
    edges += [E((r_o, 0, z_top), (r_i, 0, z_top)), E((r_i, 0, z_top), inner_top), *inner,
              E((r_hb, 0, z1), (r_hb, 0, 0))]
    return Face(Wire(edges))


@dataclass(frozen=True)
class SmoothSection:
    """The smooth cup's (r, z) half section as revolved (``face``: x = r, z in the xz plane), the band's start
    z_b on its outer edge, and the re-entrant corners where the torsion field is singular."""

    face: object
    outer_radius_mm: float
    band_z_mm: float
    length_mm: float
    corners_mm: tuple[tuple[float, float], ...]


def reentrant_corners_mm(params) -> tuple[tuple[float, float], ...]:
    """(r, z) of the cup's sharp re-entrant edges, circles about its axis: the hub's outer edge meets the
    diaphragm's underside at a 270 deg corner (none in an open tube), where the torsion field is singular."""
    fc = params.flexspline_cup
    return ((HUB_RATIO * fc.pitch_diameter_mm, (BOSS_HEIGHT_WALLS - 1) * fc.wall_thickness_mm),) if fc.cup else ()


def smooth_section(params) -> SmoothSection:
    """The half section of the smooth (toothless) cup that ``build(teeth=False)`` revolves."""
    fc = params.flexspline_cup
    d1, length = fc.pitch_diameter_mm, fc.length_mm
    z_b = length - BAND_RATIO * d1
    return SmoothSection(_profile(fc, length, z_b), d1 / 2, z_b, length, reentrant_corners_mm(params))


def tooth_spec(params) -> ToothSpec:
    return cup_tooth_spec(params)


def build(params, *, crack_depth_mm: float | None = None, teeth: bool = True,
          crack_model: CrackModel = CrackModel.SLOT) -> Part:
    """The cup; a crack as the CAD slot or (``CrackModel.SEAM``) as the root-crack rectangle
    ``Part.crack_surface`` on the uncracked cup."""
    fc, cg = params.flexspline_cup, params.crack_geometry
    d1, t, length = fc.pitch_diameter_mm, fc.wall_thickness_mm, fc.length_mm
    r_o, r_i = d1 / 2, d1 / 2 - t
    band = BAND_RATIO * d1
    z_b = length - band
    bottom_needed = BOSS_HEIGHT_WALLS * t + (0.3 * (r_i - HUB_RATIO * d1) + t if fc.shape == CupShape.BELL else t)
    if fc.cup and z_b <= bottom_needed:
        raise InputError("flexspline_cup.length_mm", length,
                         f"must exceed the tooth band 0.2 d1 plus the diaphragm region = {band + bottom_needed:g} mm")
    spec = tooth_spec(params)
    if teeth and tip_thickness_mm(spec) < 0.2 * fc.module_mm:
        raise InputError("flexspline_cup.module_mm", fc.module_mm,
                         f"pointed teeth: with m Z = {2 * spec.pitch_radius_mm:g} mm on d1 = {d1:g} mm the profile "
                         f"shift {spec.shift_coef:.3f} leaves a tip of {tip_thickness_mm(spec):.3f} mm (< 0.2 m)")
    if crack_depth_mm is not None:  # refuse bad cracks before any CAD work
        # teeth stand on the wall (root circle = d1/2), so the wall under the root is delta either way
        check_crack(crack_depth_mm, t, "flexspline_cup.wall_thickness_mm (wall under the tooth root)",
                    0.0 if crack_model == CrackModel.SEAM else cg.slot_width_mm)
        c = crack_depth_mm / CRACK_ASPECT
        z_c = cg.flexspline_axial_position_ratio * length
        if crack_model == CrackModel.SEAM:
            # the FEA solves the seed's crack: through the wall, 45 deg, in the fully loaded tube between the
            # diaphragm region and the band (where the torque enters as surface shear the section carries
            # less than T; the FEA showed the outer-fibre shear halved at z = 0.9 L)
            z_c = 0.5 * ((bottom_needed if fc.cup else 0.0) + z_b)
        elif not (z_b + c < z_c < length - c):
            raise InputError("crack_geometry.flexspline_axial_position_ratio", cg.flexspline_axial_position_ratio,
                             f"the crack (half length {c:g} mm) must lie inside the tooth band "
                             f"z = {z_b:g}..{length:g} mm, i.e. ratio in ({(z_b + c) / length:.4f}, {(length - c) / length:.4f})")
    from build123d import Axis, revolve

    if teeth:
        solid = toothed_solid(fc, spec, sew=True)
        r_surface = spec.root_radius_mm
    else:
        solid = revolve(_profile(fc, length, z_b), Axis.Z, clean=False).solids()[0]
        r_surface = r_o
    meta = {"outer_radius_mm": r_o, "bore_radius_mm": r_i, "mid_radius_mm": r_o - t / 2, "wall_mm": t,
            "length_mm": length, "band_z_mm": (z_b, length), "band_width_mm": band, "teeth": fc.teeth if teeth else 0,
            "module_mm": fc.module_mm, "pitch_radius_mm": spec.pitch_radius_mm,
            "root_radius_mm": spec.root_radius_mm, "tip_radius_mm": spec.tip_radius_mm,
            "root_fillet_mm": spec.root_fillet_mm, "hub_radius_mm": HUB_RATIO * d1,
            "hub_bore_radius_mm": HUB_BORE_RATIO * d1, "shape": fc.shape.value, "cup": fc.cup,
            "shift_coef": spec.shift_coef, "rim_under_teeth_mm": t}
    slot = None
    if crack_depth_mm is not None:
        theta = (cg.flexspline_tooth_index + 0.5) * 2 * math.pi / fc.teeth
        opening = 0.5 * spec.root_fillet_mm if teeth else crack_depth_mm
    if crack_depth_mm is not None and crack_model == CrackModel.SEAM:
        seam = helical_through_seam(r_i, r_o, crack_depth_mm, params.cracks.flexspline_crack_angle_deg, theta, z_c)
        meta.update(seam.meta, crack_depth_mm=crack_depth_mm, crack_z_mm=z_c, crack_model=CrackModel.SEAM.value)
        return Part(PartName.FLEXSPLINE_CUP, solid, _named(solid, meta, None, teeth, fc.cup), seam.front_mm, None,
                    meta, seam.face, (seam.point_mm, seam.normal))
    if crack_depth_mm is not None:
        slot = inclined_root_slot(r_surface, theta, crack_depth_mm, params.cracks.flexspline_crack_angle_deg,
                                  z_c, c, cg.slot_width_mm, opening)
        solid = cut(solid, slot.tool)
        meta.update(slot.meta, crack_depth_mm=crack_depth_mm, slot_width_mm=cg.slot_width_mm,
                    slot_volume_mm3=slot.volume_mm3, crack_z_mm=z_c)
    return Part(PartName.FLEXSPLINE_CUP, solid, _named(solid, meta, slot, teeth, fc.cup),
                slot.front_mm if slot else (), None, meta)


def toothed_solid(fc, spec: ToothSpec, *, sew: bool = True):
    """The revolved cup up to the band joined to the toothed band (``fc``: the cup's parameters).

    ``sew``: the faces of both but the annulus they share at the band's start, plus each tooth's end there,
    sewn into one solid, without a boolean over all the band's faces; if sewing does not close one shell
    of those faces, or with ``sew=False``, the two solids' glued fuse, which gives the same solid."""
    from build123d import Axis, Edge, Face, GeomType, Location, Wire, extrude, revolve

    t, band = fc.wall_thickness_mm, BAND_RATIO * fc.pitch_diameter_mm
    r_i, z_b = fc.pitch_diameter_mm / 2 - t, fc.length_mm - band
    teeth, at_band = gear_edges(spec), Location((0, 0, z_b))
    outline = Face(Wire([e for edges, root in teeth for e in (*edges, root)]), [Wire([Edge.make_circle(r_i)])])
    ring = extrude(outline, amount=band, clean=False).solids()[0].moved(at_band)
    body = revolve(_profile(fc, z_b, None), Axis.Z).solids()[0]
    if not sew:
        return fuse(body, ring, touching=True)

    def shared(face) -> bool:   # the body's top annulus and the band's bottom face, both at z_b
        if face.geom_type != GeomType.PLANE:
            return False
        bb = face.bounding_box()
        return abs(bb.min.Z - z_b) < 1e-9 * fc.length_mm and abs(bb.max.Z - z_b) < 1e-9 * fc.length_mm
    faces = [f for f in (*body.faces(), *ring.faces()) if not shared(f)]
    faces += [Face(f.wrapped.Moved(at_band.wrapped)) for f in tooth_end_faces(teeth, spec.root_radius_mm)]
    solid = sew_solid(faces, len(faces))
    return solid if solid is not None else fuse(body, ring, touching=True)


def _named(solid, meta, slot, teeth: bool, is_cup: bool) -> dict:
    infos = F.face_infos(solid)
    r_o, r_i, length = meta["outer_radius_mm"], meta["bore_radius_mm"], meta["length_mm"]
    z_b = meta["band_z_mm"][0]
    tol = 1e-6 * length
    crack_face, crack_front = (), ()
    if slot is not None:
        inside = F.select(infos, F.in_box(slot.box_lo, slot.box_hi))
        nrm = meta["crack_normal"]
        is_wall = lambda fi: fi.kind == "plane" and abs(sum(a * b for a, b in zip(fi.normal, nrm))) > 1 - 1e-9  # noqa: E731
        crack_face = F.select(inside, is_wall)
        crack_front = F.select(inside, lambda fi: not is_wall(fi))
    cracked = crack_face + crack_front
    fixed = F.select(infos, F.is_zplane(0.0))
    rim = F.select(infos, F.is_zplane(length))
    bore = F.select(infos, F.is_cylinder(r_i))
    in_band = lambda fi: fi.bbox_min[2] >= z_b - tol and fi.kind != "plane" or (  # noqa: E731
        fi.kind == "plane" and fi.bbox_min[2] >= z_b - tol and abs(fi.normal[2]) < 1e-9)
    loaded = F.select(infos, F.without(in_band, bore, rim, cracked))
    named = {"fixed": F.refs(fixed), "loaded": F.refs(loaded), "bore": F.refs(bore), "rim": F.refs(rim),
             "outer": F.refs(F.select(infos, F.without(F.is_cylinder(r_o, z_range=(0.0, z_b)), loaded)))}
    if teeth:
        named["tooth_flank"] = F.refs(F.select(loaded, lambda fi: fi.kind == "other"))
    if slot is not None:
        named["crack_face"] = F.refs(crack_face)
        named["crack_front"] = F.refs(crack_front)
    # every other face has a name too, so a STEP reader shows none blank: the teeth's ends where the band
    # begins, and the closed end (diaphragm, hub and their fillets)
    rest = F.without(lambda fi: True, fixed, rim, bore, loaded, cracked,
                     F.select(infos, F.is_cylinder(r_o, z_range=(0.0, z_b))))
    more = {"tooth_end": F.select(infos, F.both(rest, F.is_zplane(z_b))),
            "closed_end": F.select(infos, F.both(rest, lambda fi: fi.bbox_max[2] < z_b - tol))}
    return {**named, **{name: F.refs(faces) for name, faces in more.items() if faces}}


def check_crack_patch(part: Part, half_size_mm: float) -> None:
    """ValueError unless ``part`` is a SEAM cup whose crack's patch (+-``half_size_mm`` axially and in arc)
    lies in the smooth tube between the diaphragm region and the band."""
    m = part.meta
    if part.crack_surface is None or "crack_centre_mm" not in m:
        raise ValueError("crack_patch: the part carries no seam crack")
    z_c = m["crack_z_mm"]
    bottom = BOSS_HEIGHT_WALLS * m["wall_mm"] + m["wall_mm"] if m["cup"] else 0.0
    if not (bottom < z_c - half_size_mm and z_c + half_size_mm < m["band_z_mm"][0] and half_size_mm < m["mid_radius_mm"]):
        raise ValueError(f"crack_patch: +-{half_size_mm:g} mm around z = {z_c:g} mm leaves the smooth tube "
                         f"(z = {bottom:g}..{m['band_z_mm'][0]:g} mm)")


def crack_patch(part: Part, half_size_mm: float) -> Part:
    """The global-local crack model's local part: the tube wall within +-``half_size_mm`` axially and the
    same arc length either way of a SEAM cup's crack centre, with the same seam. Its four cut faces form
    the group ``cut`` (held at the global displacement); the bore and outer cylinders stay free."""
    from build123d import Axis, Face, Polyline, Wire, revolve

    check_crack_patch(part, half_size_mm)
    m = part.meta
    r_i, r_o, r_m, z_c = m["bore_radius_mm"], m["outer_radius_mm"], m["mid_radius_mm"], m["crack_z_mm"]
    theta = math.atan2(m["crack_centre_mm"][1], m["crack_centre_mm"][0])
    arc = half_size_mm / r_m
    lo, hi = z_c - half_size_mm, z_c + half_size_mm
    profile = Face(Wire(Polyline((r_i, 0, lo), (r_o, 0, lo), (r_o, 0, hi), (r_i, 0, hi), close=True).edges()))
    solid = revolve(profile, Axis.Z, revolution_arc=math.degrees(2 * arc)).solids()[0].rotate(
        Axis.Z, math.degrees(theta - arc))
    infos = F.face_infos(solid)
    named = {"cut": F.refs(F.select(infos, lambda fi: fi.kind == "plane")),
             "bore": F.refs(F.select(infos, F.is_cylinder(r_i))), "outer": F.refs(F.select(infos, F.is_cylinder(r_o)))}
    meta = dict(m, patch_half_size_mm=half_size_mm)
    return Part(PartName.FLEXSPLINE_CUP, solid, named, part.crack_front_mm, None, meta, part.crack_surface,
                part.crack_plane)
