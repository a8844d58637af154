"""The wave generator's flexible ball bearing as built: cam, inner ring, balls, outer ring, filling the cup's bore.

Layout (every radius from the keys, so it follows the parameters; round, before the cam deforms it):
- the outer ring's outside is the cup's bore r_cb = d1/2 - delta; its race (groove bottom) r_cb - t_o;
- the balls (D_w, ``ball_count`` of them, equally spaced) on the pitch circle r_cb - t_o - D_w/2;
- the inner ring's race (groove bottom) r_cb - t_o - D_w, its bore that minus t_i: the cam's mean radius;
- grooves of radius f D_w (``groove_radius_ratio``), centred (f - 1/2) D_w beyond the pitch circle, their bottoms the
  races; the lands stand GROOVE_DEPTH_OVER_D D_w above them (``drive_assembly`` cuts them);
- width (all three and the cam) 4 a', as ``geometry.bearing_ring``'s ring.
Deformed (the assembly): the cam is the ellipse of semi-axes r_bore +- w0; every other circle of radius R is drawn
as the parallel curve of that ellipse at distance R - r_bore (``contour``), the shape of a ring of constant
thickness forced onto the cam. So the cup's bore lies r_cb + w0 out at the major axis and r_cb - w0 in at the
minor one, and each ball touches both races exactly (the races are the parallel curves at D_w/2 either side of
its centre's).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from strainwave.errors import InputError

__all__ = ["GROOVE_DEPTH_OVER_D", "BearingLayout", "bearing_layout", "contour_edge", "contour_points"]

GROOVE_DEPTH_OVER_D = 0.18     # land height over the groove bottom / D_w (chosen: deep-groove rings 0.15..0.22)
HUB_BORE_OVER_MINOR = 0.4      # the cam's input-shaft bore over its minor semi-axis (as geometry.wg_cam)
APPROX_TOL_MM = 1e-7          # B-spline of a parallel curve: within OCC's own precision (1e-7)
_SAMPLES = 20001               # points along a contour for arc length (error ~ (2 pi R / N)^2 / R: far below 1e-6 mm)


@dataclass(frozen=True)
class BearingLayout:
    """Round radii (mm) of the bearing from the cam outwards, and the cam's ellipse (w0 out, w0 in)."""
    bore_radius_mm: float          # the inner ring's bore: the cam's mean radius
    inner_race_radius_mm: float    # groove bottom of the inner ring
    pitch_radius_mm: float         # ball centres
    outer_race_radius_mm: float    # groove bottom of the outer ring
    outer_radius_mm: float         # the outer ring's outside = the cup's bore
    ball_diameter_mm: float
    ball_count: int
    groove_radius_mm: float
    groove_depth_mm: float
    width_mm: float
    w0_mm: float

    @property
    def cam_semi_axes_mm(self) -> tuple[float, float]:
        return self.bore_radius_mm + self.w0_mm, self.bore_radius_mm - self.w0_mm

    @property
    def hub_bore_radius_mm(self) -> float:
        return HUB_BORE_OVER_MINOR * self.cam_semi_axes_mm[1]

    def offset_mm(self, radius_mm: float) -> float:
        """Distance from the cam's ellipse of the contour that a round circle of ``radius_mm`` becomes."""
        return radius_mm - self.bore_radius_mm


def bearing_layout(params) -> BearingLayout:
    """The layout from the parameters; InputError (the key that does not fit) when the bearing cannot fill the bore."""
    fc, wg = params.flexspline_cup, params.wave_generator
    d_w, t_o, t_i = wg.ball_diameter_mm, wg.outer_ring_thickness_mm, wg.bearing_inner_ring_thickness_mm
    r_cb = 0.5 * fc.pitch_diameter_mm - fc.wall_thickness_mm
    r_pitch = r_cb - t_o - 0.5 * d_w
    r_bore = r_cb - t_o - d_w - t_i
    w0 = params.gear.radial_deformation_mm
    width = wg.bearing_width_mm      # the rings' axial width (geometry/bearing_ring.py builds the inner ring so)
    if r_bore - w0 <= 0:
        raise InputError("wave_generator.bearing_inner_ring_thickness_mm", t_i,
                         f"the cup's bore {r_cb:g} mm leaves no cam inside outer ring ({t_o:g} mm), balls ({d_w:g} mm), "
                         f"inner ring and w0 = {w0:g} mm: need t_o + D_w + t_i + w0 < {r_cb:g} mm")
    if wg.ball_count * d_w >= 2 * math.pi * r_pitch * 0.98:
        raise InputError("wave_generator.ball_count", wg.ball_count,
                         f"{wg.ball_count} balls of {d_w:g} mm do not fit on the pitch circle of radius {r_pitch:.4g} mm "
                         f"(at most {int(0.98 * 2 * math.pi * r_pitch / d_w)})")
    depth = GROOVE_DEPTH_OVER_D * d_w
    r_g = wg.groove_radius_ratio * d_w
    half = math.sqrt(r_g ** 2 - (r_g - depth) ** 2)          # the groove's half width at the land
    if 2 * half >= width:
        raise InputError("wave_generator.bearing_width_mm", width,
                         f"the bearing's width {width:g} mm is narrower than its ball groove ({2 * half:.3g} mm)")
    return BearingLayout(r_bore, r_bore + t_i, r_pitch, r_cb - t_o, r_cb, d_w, wg.ball_count, r_g, depth, width, w0)


def _ellipse(a: float, b: float, t: np.ndarray):
    """Points and outward unit normals of the ellipse (a cos t, b sin t)."""
    p = np.column_stack([a * np.cos(t), b * np.sin(t)])
    n = np.column_stack([b * np.cos(t), a * np.sin(t)])
    return p, n / np.hypot(n[:, 0], n[:, 1])[:, None]


def contour_points(a: float, b: float, d: float, s_fraction: np.ndarray, at_d: float | None = None):
    """Points (N x 2) and outward normals of the parallel curve at ``d`` of the ellipse (a, b), at the given
    fractions of its arc length from the major axis (+x), counter-clockwise. ``at_d``: the points on the parallel
    curve at ``at_d`` instead, on the same normals (a ring's outer surface over the stations of its neutral line)."""
    t = np.linspace(0.0, 2 * math.pi, _SAMPLES)
    p, n = _ellipse(a, b, t)
    q = p + d * n
    s = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(q, axis=0).T))])
    tt = np.interp(np.asarray(s_fraction, dtype=float) % 1.0 * s[-1], s, t)
    p, n = _ellipse(a, b, tt)
    return p + (d if at_d is None else at_d) * n, n


def contour_edge(a: float, b: float, d: float, z_mm: float = 0.0):
    """The parallel curve at ``d`` of the ellipse (a, b) in the plane z (a circle of radius a + d when a == b), as a
    build123d Edge: OCC's offset curve approximated by a B-spline within ``APPROX_TOL_MM`` (STEP writes B-splines
    exactly, an offset curve it re-approximates, and booleans on B-splines are faster)."""
    from build123d import Edge
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeEdge
    from OCP.Geom import Geom_Circle, Geom_Ellipse, Geom_OffsetCurve
    from OCP.GeomAbs import GeomAbs_C2
    from OCP.GeomConvert import GeomConvert_ApproxCurve
    from OCP.gp import gp_Ax2, gp_Dir, gp_Pnt

    axes = gp_Ax2(gp_Pnt(0.0, 0.0, z_mm), gp_Dir(0.0, 0.0, 1.0), gp_Dir(1.0, 0.0, 0.0))
    if a - b < 1e-12 * a:
        return Edge(BRepBuilderAPI_MakeEdge(Geom_Circle(axes, a + d)).Edge())
    base = Geom_Ellipse(axes, a, b)
    if d == 0.0:
        return Edge(BRepBuilderAPI_MakeEdge(base).Edge())
    approx = GeomConvert_ApproxCurve(Geom_OffsetCurve(base, d, gp_Dir(0.0, 0.0, 1.0)), APPROX_TOL_MM, GeomAbs_C2, 64, 8)
    if not approx.IsDone():
        raise RuntimeError(f"B-spline of the parallel curve at {d:g} mm of the ellipse ({a:g}, {b:g}) failed")
    return Edge(BRepBuilderAPI_MakeEdge(approx.Curve()).Edge())
