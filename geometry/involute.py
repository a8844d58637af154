"""Involute tooth profiles as one closed 2D wire (xy plane), external or internal.

Building the whole toothed outline as a single wire and extruding it once is what keeps the
200-tooth flexspline fast: one face and one prism instead of fusing hundreds of tooth solids.

Conventions (standard basic rack, no profile shift; seed 003 text gives h_f = 1.35 m):
- pitch radius r_p = m Z / 2, base radius r_b = r_p cos(alpha);
- external gear: tip r_p + h_a m, root r_p - h_f m; internal gear: tip r_p - h_a m, root r_p + h_f m;
- tooth thickness on the pitch circle pi m / 2 (+ 2 x m tan(alpha) with a profile shift x); tooth 0 on +x;
- a root fillet of radius ``root_fillet_mm`` joins flank and root circle (a sharp root would make the
  FEA root stress singular and K_sigma meaningless); below the base circle the flank is radial.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from strainwave.errors import InputError


@dataclass(frozen=True)
class ToothSpec:
    teeth: int
    module_mm: float
    pressure_angle_deg: float = 20.0
    addendum_coef: float = 1.0
    dedendum_coef: float = 1.35
    internal: bool = False
    root_fillet_coef: float = 0.25      # fillet radius / module; 0.25 fits the 1.35 m dedendum space
    shift_coef: float = 0.0             # profile shift x: root and tip move radially outward by x m
    thinning_mm: float = 0.0            # tooth thickness taken off at the pitch circle (backlash), arc length

    @property
    def pitch_radius_mm(self) -> float:
        return 0.5 * self.module_mm * self.teeth

    @property
    def base_radius_mm(self) -> float:
        return self.pitch_radius_mm * math.cos(math.radians(self.pressure_angle_deg))

    @property
    def tip_radius_mm(self) -> float:
        if self.internal:
            # An internal tooth tip inside the base circle has no involute; clamp it to the base circle.
            return max(self.pitch_radius_mm + (self.shift_coef - self.addendum_coef) * self.module_mm,
                       self.base_radius_mm * 1.0005)
        return self.pitch_radius_mm + (self.addendum_coef + self.shift_coef) * self.module_mm

    @property
    def root_radius_mm(self) -> float:
        if self.internal:
            return self.pitch_radius_mm + (self.dedendum_coef + self.shift_coef) * self.module_mm
        return self.pitch_radius_mm - (self.dedendum_coef - self.shift_coef) * self.module_mm

    @property
    def root_fillet_mm(self) -> float:
        return self.root_fillet_coef * self.module_mm


def tip_thickness_mm(spec: ToothSpec) -> float:
    """Chordal-ish tooth thickness on the tip circle (arc length); <= 0 means a pointed tooth."""
    return 2 * float(half_angle_rad(spec, spec.tip_radius_mm)) * spec.tip_radius_mm


def _inv(alpha: np.ndarray | float):
    return np.tan(alpha) - alpha


def half_angle_rad(spec: ToothSpec, r_mm: np.ndarray | float):
    """Half angular thickness of a tooth at radius r (involute above the base circle, radial below)."""
    r = np.maximum(np.asarray(r_mm, dtype=float), spec.base_radius_mm)
    alpha_p = math.radians(spec.pressure_angle_deg)
    alpha_r = np.arccos(spec.base_radius_mm / r)
    # an outward profile shift x thickens an external tooth on the pitch circle by 2 x m tan(alpha) and thins an
    # internal one as much (the internal tooth is the space of an external one: the rack moves towards its tip)
    sign = -1.0 if spec.internal else 1.0
    psi_p = ((math.pi / 2 + sign * 2 * spec.shift_coef * math.tan(alpha_p)) * spec.module_mm
             - spec.thinning_mm) / (2 * spec.pitch_radius_mm)
    if spec.internal:  # an internal tooth widens outwards
        return psi_p - _inv(alpha_p) + _inv(alpha_r)
    return psi_p + _inv(alpha_p) - _inv(alpha_r)


def tooth_polyline_mm(spec: ToothSpec, n_flank: int = 12, n_arc: int = 6) -> np.ndarray:
    """Dense closed outline (N x 2) of the whole toothed circle, for area checks and previews."""
    pts = []
    r_f, r_a = spec.root_radius_mm, spec.tip_radius_mm
    radii = np.linspace(r_f, r_a, n_flank)
    pitch = 2 * math.pi / spec.teeth
    for j in range(spec.teeth):
        th = j * pitch
        right = th - half_angle_rad(spec, radii)
        left = th + half_angle_rad(spec, radii[::-1])
        tip = np.linspace(right[-1], left[0], n_arc)[1:-1]
        root = np.linspace(left[-1], th + pitch - half_angle_rad(spec, r_f), n_arc)[1:-1]
        for ang, rr in ((right, radii), (tip, np.full(tip.size, r_a)), (left, radii[::-1]),
                        (root, np.full(root.size, r_f))):
            pts.append(np.column_stack([rr * np.cos(ang), rr * np.sin(ang)]))
    return np.vstack(pts)


def polygon_area_mm2(xy: np.ndarray) -> float:
    """Shoelace area of a closed polyline."""
    x, y = xy[:, 0], xy[:, 1]
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def _fillet_offset(spec: ToothSpec, rho_mm: float) -> tuple[float, float, float]:
    """Root fillet tangent to the root circle and to the flank, found numerically.

    Returns (dphi, r_t, psi_t): the fillet centre and its root-circle tangent point lie at angle
    th + dphi from tooth centre th (left flank side), the flank tangent point at radius r_t and
    flank half angle psi_t.
    """
    s = -1.0 if spec.internal else 1.0          # the tooth space lies outside r_f (external), inside (internal)
    r_f = spec.root_radius_mm
    r_c = r_f + s * rho_mm
    span = abs(spec.tip_radius_mm - r_f)
    radii = r_f + s * np.linspace(-0.5 * rho_mm, min(3.0 * rho_mm, 0.9 * span), 4001)
    flank = np.column_stack([radii * np.cos(half_angle_rad(spec, radii)),
                             radii * np.sin(half_angle_rad(spec, radii))])

    def gap(phi):
        c = np.array([r_c * math.cos(phi), r_c * math.sin(phi)])
        d = np.hypot(*(flank - c).T)
        k = int(np.argmin(d))
        return d[k] - rho_mm, k

    lo, hi = float(half_angle_rad(spec, r_f)) - rho_mm / r_c, math.pi / spec.teeth
    if gap(hi)[0] < 0:
        raise ValueError("root fillet does not fit the tooth space")
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if gap(mid)[0] < 0 else (lo, mid)
    k = gap(hi)[1]
    r_t = float(radii[k])
    return hi, r_t, float(half_angle_rad(spec, r_t))


def gear_wire(spec: ToothSpec, n_flank: int = 9):
    """The closed toothed outline as a build123d Wire: ``gear_edges`` in order."""
    from build123d import Wire

    return Wire([e for tooth, root in gear_edges(spec, n_flank) for e in (*tooth, root)])


def _fitted_fillet(spec: ToothSpec) -> tuple:
    """(rho, dphi, r_t, psi_t) of the root fillet, shrunk until it fits the tooth space (no fillet: dphi and
    psi_t None, r_t the root radius)."""
    rho = spec.root_fillet_mm
    for _ in range(20):
        try:
            return (rho, *_fillet_offset(spec, rho)) if rho > 0 else (rho, None, spec.root_radius_mm, None)
        except ValueError:
            rho *= 0.7
    return rho, None, spec.root_radius_mm, None


def gear_edges(spec: ToothSpec, n_flank: int = 9) -> list:
    """The toothed outline's edges tooth by tooth: (the tooth's edges from root circle to root circle, the
    root arc to the next tooth).

    Per tooth: two spline flanks (exact involute points), a tip arc, two root-fillet arcs and a root
    arc. Fillets are computed here analytically-numerically because OCC's 2D fillet is far too slow on
    hundreds of root corners (docs/decisions/015-cad-build-speed.md).
    """
    from build123d import Edge

    r_f, r_a = spec.root_radius_mm, spec.tip_radius_mm
    pitch = 2 * math.pi / spec.teeth
    rho, dphi, r_t, psi_t = _fitted_fillet(spec)
    r_b = spec.base_radius_mm
    # below the base circle the flank is a radial line: a separate straight edge, because one spline
    # through the kink at r_b would smear it (5e-5 area error for Z = 30)
    radial = (not spec.internal) and r_t < r_b
    # flank points uniform in the involute roll angle t (r = r_b sqrt(1 + t^2)): uniform radii crowd the
    # spline's error near the base circle, where the involute turns fastest
    t0, t1 = (math.sqrt(max((r / r_b) ** 2 - 1.0, 0.0)) for r in (r_b if radial else r_t, r_a))
    radii = r_b * np.sqrt(1.0 + np.linspace(t0, t1, n_flank) ** 2)
    radii[0], radii[-1] = (r_b if radial else r_t), r_a
    psi = half_angle_rad(spec, radii)
    if dphi is None:
        dphi = float(psi[0])
    if dphi >= pitch / 2:
        # too few teeth for the profile (e.g. Z = 8 on the EWG ring): the user's parameters, not a CAD fault
        raise InputError(f"teeth ({'internal' if spec.internal else 'external'} toothing)", spec.teeth,
                         "teeth overlap at the root circle: too few teeth for this module and profile; use more teeth")
    s = -1.0 if spec.internal else 1.0
    r_c = r_f + s * rho

    def pt(r, a):
        return (float(r * math.cos(a)), float(r * math.sin(a)), 0.0)

    def arc(p0, pm, p1):
        return Edge.make_three_point_arc(p0, pm, p1)

    def fillet(th, side):
        """Fillet arc from the root tangent point to the flank tangent point (side +1 left, -1 right)."""
        ang_c = th + side * dphi
        centre = np.array([r_c * math.cos(ang_c), r_c * math.sin(ang_c)])
        p_root = np.array(pt(r_f, ang_c)[:2])
        p_flank = np.array(pt(r_t, th + side * float(psi[0]))[:2])  # psi is constant below r_b
        u0, u1 = p_root - centre, p_flank - centre
        um = u0 / np.linalg.norm(u0) + u1 / np.linalg.norm(u1)
        pm = centre + rho * um / np.linalg.norm(um)
        return (*p_root, 0.0), (float(pm[0]), float(pm[1]), 0.0), (*p_flank, 0.0)

    filleted = psi_t is not None
    teeth = []
    for j in range(spec.teeth):
        th = j * pitch
        right = [pt(r, th - p) for r, p in zip(radii, psi)]
        left = [pt(r, th + p) for r, p in zip(radii[::-1], psi[::-1])]
        foot_r, foot_l = pt(r_t, th - float(psi[0])), pt(r_t, th + float(psi[0]))
        edges = []
        if filleted:
            a, m, b = fillet(th, -1)
            edges.append(arc(a, m, foot_r))
        if radial:
            edges.append(Edge.make_line(foot_r, right[0]))
        edges.append(Edge.make_spline(right))
        edges.append(arc(pt(r_a, th - float(psi[-1])), pt(r_a, th), pt(r_a, th + float(psi[-1]))))
        edges.append(Edge.make_spline(left))
        if radial:
            edges.append(Edge.make_line(left[-1], foot_l))
        if filleted:
            a, m, b = fillet(th, +1)
            edges.append(arc(foot_l, m, a))
        a0, a1 = th + dphi, th + pitch - dphi
        teeth.append((edges, arc(pt(r_f, a0), pt(r_f, 0.5 * (a0 + a1)), pt(r_f, a1))))
    return teeth


def tooth_end_faces(teeth: list, root_radius_mm: float) -> list:
    """Planar faces (z = 0) each bounded by one tooth's edges of ``gear_edges`` and the root-circle arc
    under the tooth: the external toothed outline minus its root disc, tooth by tooth."""
    from build123d import Edge, Face
    from OCP.BRepBuilderAPI import BRepBuilderAPI_MakeFace, BRepBuilderAPI_MakeWire

    faces = []
    for edges, _ in teeth:
        p0, p1 = edges[0].start_point(), edges[-1].end_point()
        mid = math.atan2(p0.Y + p1.Y, p0.X + p1.X)     # the ends lie symmetric about the tooth's axis
        foot = Edge.make_three_point_arc(p1, (root_radius_mm * math.cos(mid), root_radius_mm * math.sin(mid), 0.0), p0)
        wire = BRepBuilderAPI_MakeWire()
        for edge in (*edges, foot):        # OCC's own makers: build123d's Face() re-fixes every wire (slower)
            wire.Add(edge.wrapped)
        faces.append(Face(BRepBuilderAPI_MakeFace(wire.Wire(), True).Face()))
    return faces


def gear_face(spec: ToothSpec, inner_radius_mm: float | None = None, outer_radius_mm: float | None = None):
    """Planar toothed annulus at z = 0.

    External teeth: outline outside, circular hole ``inner_radius_mm`` (the bore).
    Internal teeth: circle ``outer_radius_mm`` outside, toothed outline as the hole.
    """
    from build123d import Edge, Face, Wire

    toothed = gear_wire(spec)
    if spec.internal:
        return Face(Wire([Edge.make_circle(outer_radius_mm)]), [toothed])
    return Face(toothed, [Wire([Edge.make_circle(inner_radius_mm)])])


def root_space_mm(spec: ToothSpec) -> float:
    """Arc length of the tooth space on the root circle; <= 0 means neighbouring teeth overlap there."""
    r = spec.root_radius_mm
    return r * (2 * math.pi / spec.teeth - 2 * float(half_angle_rad(spec, r)))


def check_teeth(spec: ToothSpec, key: str, value: object, part: str) -> None:
    """The one tooth-shape check every command shares (params, analytic, solve, export-step): a tip of at
    least 0.2 m (not pointed) and a tooth space left on the root circle (teeth do not overlap). Either
    failure is a drawing no gear can have: its closed forms mean nothing and its CAD cannot be meshed."""
    tip = tip_thickness_mm(spec)
    if tip < 0.2 * spec.module_mm:
        raise InputError(key, value, f"pointed {part} teeth: Z = {spec.teeth}, m = {spec.module_mm:g} mm, "
                                     f"pressure angle {spec.pressure_angle_deg:g} deg, profile shift "
                                     f"{spec.shift_coef:.3f} leave a tip of {tip:.3g} mm (< 0.2 m)")
    space = root_space_mm(spec)
    if space <= 0:
        raise InputError(key, value, f"{part} teeth overlap on the root circle: Z = {spec.teeth}, m = "
                                     f"{spec.module_mm:g} mm, pressure angle {spec.pressure_angle_deg:g} deg, "
                                     f"dedendum {spec.dedendum_coef:g} m leave a tooth space of {space:.3g} mm")


CUP_ADDENDUM_COEF = 1.0        # h_a / m of the flexspline's teeth (the basic rack's)
DEDENDUM_COEF = 1.35           # h_f / m of both toothed parts (seed 003's basic rack)


def cup_tooth_spec(params) -> ToothSpec:
    """The flexspline cup's external teeth: the design's basic rack (circular_spline.pressure_angle_deg, 20 deg by
    default), h_a = 1.0 m, h_f = 1.35 m, shifted so the root circle is d1/2."""
    fc = params.flexspline_cup
    r_p = 0.5 * fc.module_mm * fc.teeth
    shift = (0.5 * fc.pitch_diameter_mm - r_p) / fc.module_mm + DEDENDUM_COEF
    return ToothSpec(fc.teeth, fc.module_mm, params.circular_spline.pressure_angle_deg, CUP_ADDENDUM_COEF,
                     DEDENDUM_COEF, internal=False, shift_coef=shift)


def circular_spline_tooth_spec(params) -> ToothSpec:
    """The circular spline's internal teeth: Z_c = Z_f + U, the cup's module and basic rack, the addendum the
    design gives, thinned by twice ``circular_spline.backlash_mm`` (each flank pair's gap at the pitch circle).

    Its profile shift puts its rack where the cup's rack is at the major axis (the cup's tooth moved out by w0):
    x_c = x_f + (w0 - m U / 2) / m, so the pair meets there as a gear and its rack would, with radial
    clearance (h_f - h_a) m at both tips (``mesh_clearances_mm``)."""
    fc, cs, U = params.flexspline_cup, params.circular_spline, params.gear.wave_number
    cup = cup_tooth_spec(params)
    shift = cup.shift_coef + (params.gear.radial_deformation_mm - 0.5 * fc.module_mm * U) / fc.module_mm
    return ToothSpec(fc.teeth + U, fc.module_mm, cs.pressure_angle_deg, cs.addendum_coefficient, DEDENDUM_COEF,
                     internal=True, shift_coef=shift, thinning_mm=2.0 * cs.backlash_mm)


@dataclass(frozen=True)
class MeshClearances:
    """The design's clearances between the deformed cup's teeth and the circular spline's (mm, radial unless said)."""
    root_major_mm: float     # each part's tip to the other's root circle at the major axis, (h_f - h_a) m
    tip_minor_mm: float      # cup tip circle to spline tip circle at the minor axis: 2 w0 - (h_a,f + h_a,c) m
    flank_mm: float          # circumferential gap per flank pair at the pitch circle (the backlash)
    working_depth_mm: float  # radial overlap of the two tooth rings at the major axis


def mesh_clearances_mm(params) -> MeshClearances:
    """Closed-form clearances of the pair as ``circular_spline_tooth_spec`` draws it on a cup deformed by w0
    (tooth tips and roots are circles; the cup's tooth moves radially by +-w0 at the axes)."""
    cup, cs = cup_tooth_spec(params), circular_spline_tooth_spec(params)
    w0 = params.gear.radial_deformation_mm
    return MeshClearances(root_major_mm=min(cs.tip_radius_mm - (cup.root_radius_mm + w0),
                                            cs.root_radius_mm - (cup.tip_radius_mm + w0)),
                          tip_minor_mm=cs.tip_radius_mm - (cup.tip_radius_mm - w0),
                          flank_mm=params.circular_spline.backlash_mm,
                          working_depth_mm=cup.tip_radius_mm + w0 - cs.tip_radius_mm)


def ewg_tooth_spec(params) -> ToothSpec:
    """The EWG flexspline ring's internal teeth (seed 003)."""
    e = params.ewg_drive
    return ToothSpec(e.flexspline_teeth, e.module_mm, e.pressure_angle_deg, 1.0, e.dedendum_coefficient,
                     internal=True, root_fillet_coef=e.root_fillet_coefficient)
