"""Seeded crack slots: checks that refuse impossible cracks, slot tool solids and crack-front samples.

A crack is a thin slot (width w = crack_geometry.slot_width_mm, at most a/5) so that an ordinary
mesher can resolve both faces; its bottom (the slot floor) carries the name ``crack_front``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from strainwave.errors import InputError


@dataclass(frozen=True)
class Slot:
    """A slot tool solid with what the tests and the mesher need to know about it."""
    tool: object                                         # build123d Solid to subtract
    volume_mm3: float                                    # material it removes (closed form)
    front_mm: tuple[tuple[float, float, float], ...]     # points along the crack front
    box_lo: tuple[float, float, float]                   # bounding box of the slot (for face selection)
    box_hi: tuple[float, float, float]
    meta: dict


def check_crack(depth_mm: float, wall_mm: float, wall_name: str, slot_width_mm: float) -> None:
    """Refuse a crack deeper than the wall or a slot wider than depth/5 (then it would be a notch)."""
    if not (isinstance(depth_mm, (int, float)) and math.isfinite(depth_mm) and depth_mm > 0):
        raise InputError("crack_depth_mm", depth_mm, "must be a finite number > 0")
    if depth_mm >= wall_mm:
        raise InputError("crack_depth_mm", depth_mm, f"must be < {wall_name} = {wall_mm:g} mm")
    if slot_width_mm > depth_mm / 5:
        raise InputError("crack_geometry.slot_width_mm", slot_width_mm,
                         f"must be <= crack depth/5 = {depth_mm / 5:g} mm (a slot, not a notch)")


def half_length_from_q(depth_mm: float, q: float) -> float:
    """Half surface length c of a semi-elliptical crack from Q = 1 + 1.464 (a/c)^1.65 (seed 000, K_I text)."""
    if not q > 1.0:
        raise InputError("cracks.surface_crack_shape_factor", q, "must be > 1 for a finite surface crack (Q = 1 means c = infinity)")
    return depth_mm / ((q - 1.0) / 1.464) ** (1.0 / 1.65)


def circumferential_slot(r_outer_mm: float, depth_mm: float, z_mm: float, width_mm: float, arc_deg: float) -> Slot:
    """Circumferential slot of depth a from the outer surface, centred on +x, over ``arc_deg``."""
    from build123d import Axis, Face, Polyline, Wire, revolve

    r_in = r_outer_mm - depth_mm
    margin = max(1.0, depth_mm)
    pts = [(r_in, 0, z_mm - width_mm / 2), (r_outer_mm + margin, 0, z_mm - width_mm / 2),
           (r_outer_mm + margin, 0, z_mm + width_mm / 2), (r_in, 0, z_mm + width_mm / 2)]
    prof = Face(Wire(Polyline(*pts, close=True).edges()))
    if arc_deg >= 360.0:
        tool = revolve(prof, Axis.Z, 360.0)
    else:
        tool = revolve(prof, Axis.Z, arc_deg).rotate(Axis.Z, -arc_deg / 2)
    frac = min(arc_deg, 360.0) / 360.0
    vol = frac * math.pi * (r_outer_mm ** 2 - r_in ** 2) * width_mm
    n = max(8, int(arc_deg / 5))
    angles = np.radians(np.linspace(-arc_deg / 2, arc_deg / 2, n, endpoint=arc_deg < 360.0))
    front = tuple((float(r_in * math.cos(t)), float(r_in * math.sin(t)), float(z_mm)) for t in angles)
    big = r_outer_mm + margin
    return Slot(tool.solids()[0], vol, front, (-big, -big, z_mm - width_mm), (big, big, z_mm + width_mm),
                {"crack_radius_mm": r_in, "crack_arc_deg": arc_deg, "crack_z_mm": z_mm})


def inclined_root_slot(r_root_mm: float, theta_rad: float, depth_mm: float, angle_deg: float,
                       z_mm: float, half_length_mm: float, width_mm: float, opening_mm: float) -> Slot:
    """Planar slot from the root circle inwards, its plane containing z and inclined at beta to the surface.

    The front lies ``depth_mm`` below the root circle (length ~ a/sin beta along the plane); the
    slot starts ``opening_mm`` outside the root so that it opens into the tooth space.
    """
    from build123d import Box, Location

    beta = math.radians(angle_deg)
    er = np.array([math.cos(theta_rad), math.sin(theta_rad), 0.0])
    et = np.array([-math.sin(theta_rad), math.cos(theta_rad), 0.0])
    u = -er * math.sin(beta) + et * math.cos(beta)          # into the wall
    n = np.cross(np.array([0.0, 0.0, 1.0]), u)
    # the front lies at depth a below the root circle: |P + L u| = r_f - a, so L is slightly more than
    # a / sin(beta) (the front also moves tangentially by L cos(beta))
    r = r_root_mm
    length = r * math.sin(beta) - math.sqrt((r * math.sin(beta)) ** 2 - (2 * r * depth_mm - depth_mm ** 2))
    p = r_root_mm * er + np.array([0.0, 0.0, z_mm])
    centre = p + u * (length - opening_mm) / 2
    box = Box(length + opening_mm, width_mm, 2 * half_length_mm)
    # local x -> u, y -> n, z -> z; rotation about z by the angle of u
    ang = math.degrees(math.atan2(u[1], u[0]))
    tool = box.solids()[0].moved(Location(tuple(centre), (0, 0, 1), ang))
    tip = p + u * length
    front = tuple((float(tip[0]), float(tip[1]), float(z)) for z in
                  np.linspace(z_mm - half_length_mm, z_mm + half_length_mm, 9))
    bb = tool.bounding_box()
    pad = 1e-6
    return Slot(tool, width_mm * 2 * half_length_mm * length, front,
                (bb.min.X - pad, bb.min.Y - pad, bb.min.Z - pad), (bb.max.X + pad, bb.max.Y + pad, bb.max.Z + pad),
                {"crack_root_point_mm": tuple(map(float, p)), "crack_direction": tuple(map(float, u)),
                 "crack_normal": tuple(map(float, n)), "crack_length_along_plane_mm": length,
                 "crack_half_length_mm": half_length_mm, "crack_angle_deg": angle_deg})


def semi_elliptical_slot(r_surface_mm: float, depth_mm: float, half_length_mm: float, z_mm: float,
                         width_mm: float) -> Slot:
    """Semi-elliptical surface crack on the cylinder r = r_surface at +x, in the plane y = 0.

    Depth a radially inwards, half length c along z; the slot has thickness w in y.
    """
    from build123d import Edge, Face, Plane, Wire, extrude

    plane = Plane(origin=(r_surface_mm, 0.0, z_mm), x_dir=(1, 0, 0), z_dir=(0, 1, 0))
    ell = Face(Wire([Edge.make_ellipse(depth_mm, half_length_mm, plane)]))
    tool = extrude(ell, amount=width_mm / 2, both=True).solids()[0]
    t = np.linspace(-math.pi / 2, math.pi / 2, 13)
    front = tuple((float(r_surface_mm - depth_mm * math.cos(s)), 0.0, float(z_mm + half_length_mm * math.sin(s)))
                  for s in t)
    pad = 1e-6
    lo = (r_surface_mm - depth_mm - pad, -width_mm / 2 - pad, z_mm - half_length_mm - pad)
    hi = (r_surface_mm + pad, width_mm / 2 + pad, z_mm + half_length_mm + pad)
    return Slot(tool, 0.5 * math.pi * depth_mm * half_length_mm * width_mm, front, lo, hi,
                {"crack_half_length_mm": half_length_mm, "crack_aspect_a_over_c": depth_mm / half_length_mm,
                 "crack_z_mm": z_mm})
