"""Zero-width crack surfaces for the FEA (the ``CrackModel.SEAM`` representation).

A seam is a planar build123d Face in the crack plane that covers the crack and reaches a little beyond
the free surface (so the mesher's fragment puts its mouth exactly on that surface; the piece outside the
solid is dropped there). The solid stays uncracked: the mesher embeds the face as a conforming internal
surface and ``fea.crack_seam.open_crack`` later separates its two faces on the same mesh. The same crack
positions, depths and planes as the CAD slots of ``cracks.py`` (which STEP export and previews keep).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

Vec = tuple[float, float, float]


@dataclass(frozen=True)
class CrackSurface:
    """A planar crack surface: the face, its plane (point, unit normal) and points along its front."""
    face: object                         # build123d Face, extending beyond the free surface
    point_mm: Vec                        # a point of the crack plane
    normal: Vec                          # unit normal of the crack plane
    front_mm: tuple[Vec, ...]            # samples of the crack front (for size fields)
    meta: dict


def _vec(v) -> Vec:
    return tuple(float(x) for x in v)


def circumferential_seam(r_outer_mm: float, depth_mm: float, z_mm: float, arc_deg: float) -> CrackSurface:
    """Annulus (or annular sector centred on +x over ``arc_deg``) in z = z_c from r_o - a to beyond r_o."""
    from build123d import Axis, Edge, Face, Plane, Wire
    from OCP.BRepPrimAPI import BRepPrimAPI_MakeRevol
    from OCP.gp import gp_Ax1, gp_Dir, gp_Pnt

    r_in = r_outer_mm - depth_mm
    r_out = r_outer_mm + min(depth_mm, 1.0)          # overshoot: the mouth is cut by the outer cylinder
    if arc_deg >= 360.0:
        plane = Plane.XY.offset(z_mm)
        face = Face(Wire([Edge.make_circle(r_out, plane)]), [Wire([Edge.make_circle(r_in, plane)])])
    else:
        ray = Edge.make_line((r_in, 0.0, z_mm), (r_out, 0.0, z_mm))
        rev = BRepPrimAPI_MakeRevol(ray.wrapped, gp_Ax1(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1)), math.radians(arc_deg))
        face = Face(rev.Shape()).rotate(Axis.Z, -arc_deg / 2)
    n = max(8, int(arc_deg / 5))
    angles = np.radians(np.linspace(-arc_deg / 2, arc_deg / 2, n, endpoint=arc_deg < 360.0))
    front = tuple((float(r_in * math.cos(t)), float(r_in * math.sin(t)), float(z_mm)) for t in angles)
    return CrackSurface(face, (0.0, 0.0, float(z_mm)), (0.0, 0.0, 1.0), front,
                        {"crack_radius_mm": r_in, "crack_arc_deg": arc_deg, "crack_z_mm": z_mm})


def semi_elliptical_seam(r_surface_mm: float, depth_mm: float, half_length_mm: float, z_mm: float) -> CrackSurface:
    """Half ellipse (a radial, c axial) in the plane y = 0 at the cylinder r = r_surface, +x.

    The face is the full ellipse centred on the surface: its outer half lies outside the ring and is
    dropped by the mesher, which leaves the mouth exactly on the race."""
    from build123d import Edge, Face, Plane, Wire

    plane = Plane(origin=(r_surface_mm, 0.0, z_mm), x_dir=(1, 0, 0), z_dir=(0, 1, 0))
    face = Face(Wire([Edge.make_ellipse(depth_mm, half_length_mm, plane)]))
    t = np.linspace(-math.pi / 2, math.pi / 2, 13)
    front = tuple((float(r_surface_mm - depth_mm * math.cos(s)), 0.0, float(z_mm + half_length_mm * math.sin(s)))
                  for s in t)
    return CrackSurface(face, (float(r_surface_mm), 0.0, float(z_mm)), (0.0, 1.0, 0.0), front,
                        {"crack_half_length_mm": half_length_mm, "crack_aspect_a_over_c": depth_mm / half_length_mm,
                         "crack_z_mm": z_mm})


def helical_through_seam(r_inner_mm: float, r_outer_mm: float, half_length_mm: float, angle_deg: float,
                         theta_rad: float, z_mm: float) -> CrackSurface:
    """Through-wall crack of half-length a in a tube wall, at ``angle_deg`` to the axis in the wall's tangent
    plane (45 deg: normal to the principal tension of torsion, seed 000's flexspline crack), centred at
    (theta, z). A flat rectangle: radial through the wall (overshooting both surfaces, which trim it) times
    +-a along the inclined direction; the wall's curvature over a moves its surface by a^2/(2r), covered
    by the overshoot. Its front is the two radial lines at +-a."""
    from build123d import Face, Polyline, Wire

    beta = math.radians(angle_deg)
    er = np.array([math.cos(theta_rad), math.sin(theta_rad), 0.0])
    et = np.array([-math.sin(theta_rad), math.cos(theta_rad), 0.0])
    d = math.sin(beta) * et + math.cos(beta) * np.array([0.0, 0.0, 1.0])   # in the tangent plane
    n = np.cross(er, d)
    r_m = 0.5 * (r_inner_mm + r_outer_mm)
    c = r_m * er + np.array([0.0, 0.0, z_mm])
    t = r_outer_mm - r_inner_mm
    lo, hi = c + er * (r_inner_mm - r_m - 0.5 * t), c + er * (r_outer_mm - r_m + 0.5 * t + half_length_mm ** 2 / r_m)
    pts = [lo - half_length_mm * d, hi - half_length_mm * d, hi + half_length_mm * d, lo + half_length_mm * d]
    face = Face(Wire(Polyline(*[_vec(q) for q in pts], close=True).edges()))
    s = np.linspace(r_inner_mm - r_m, r_outer_mm - r_m, 5)
    front = tuple(_vec(c + er * x + sgn * half_length_mm * d) for sgn in (-1.0, 1.0) for x in s)
    return CrackSurface(face, _vec(c), _vec(n), front,
                        {"crack_kind": "through-wall", "crack_half_length_mm": half_length_mm,
                         "crack_angle_deg": angle_deg, "crack_normal": _vec(n), "crack_direction": _vec(d),
                         "crack_z_mm": z_mm, "crack_centre_mm": _vec(c)})
