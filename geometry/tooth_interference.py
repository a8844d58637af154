"""Where the rigid teeth of the deformed cup overlap the circular spline's: an oracle independent of the CAD drawing.

The cup's teeth are placed by the first-order kinematics of an inextensible ring (the textbook strain wave gear
model, not the drawing's parallel curves and arc lengths): a point of the neutral line r_m at angle phi moves
w = w0 cos 2phi out and v = -(w0/2) sin 2phi along, its section turns by (v - dw/dphi)/r_m = (3/2)(w0/r_m) sin 2phi,
and the tooth, rigid, stays on that section. The spline is fixed, a tooth space on +x. Each tooth's overlap is the
area common to the two involute outlines in the plane (Sutherland-Hodgman: the cup's external tooth is convex).
``geometry/drive_assembly.py`` draws the same design with OCC; the tests hold the two to each other.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from strainwave.errors import RangeWarning
from strainwave.geometry.involute import ToothSpec, circular_spline_tooth_spec, cup_tooth_spec, half_angle_rad

__all__ = ["ToothOverlap", "ToothOverlapWarning", "tooth_overlaps", "overlap_summary", "overlap_threshold_mm2"]

FLANK_POINTS = 16          # per flank: the chord's sag on the involute is ~1e-4 mm
# A tooth overlaps above this share of m^2 (a tooth's area is ~1.7 m^2): the model's neglected w0^2/r_m terms
# leave slivers below it where OCC's drawing clears (1.6e-4 m^2 on the tests' 48 mm drive, w0/r_m = 0.035).
OVERLAP_PER_M2 = 1e-3


class ToothOverlapWarning(RangeWarning):
    """The design's rigid teeth overlap the circular spline's somewhere round the wave generator; the run goes on."""


@dataclass(frozen=True)
class ToothOverlap:
    phi_deg: float          # the cup tooth's undeformed angle from the major axis
    area_mm2: float         # plane area common to it and the spline's teeth


def _outline(spec: ToothSpec, centre_rad: float) -> np.ndarray:
    """Counter-clockwise outline of one tooth (involute flanks, tip arc, closed by the root chord)."""
    radii = np.linspace(spec.root_radius_mm, spec.tip_radius_mm, FLANK_POINTS)
    h = half_angle_rad(spec, radii)
    tip = np.linspace(centre_rad - h[-1], centre_rad + h[-1], 6)[1:-1]
    ang = np.concatenate([centre_rad - h, tip, (centre_rad + h)[::-1]])
    rad = np.concatenate([radii, np.full(tip.size, spec.tip_radius_mm), radii[::-1]])
    xy = np.column_stack([rad * np.cos(ang), rad * np.sin(ang)])
    return xy if _area(xy) > 0 else xy[::-1]


def _area(xy: np.ndarray) -> float:
    x, y = xy[:, 0], xy[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _clip(subject: np.ndarray, convex: np.ndarray) -> np.ndarray | None:
    """Sutherland-Hodgman: ``subject`` clipped to the convex counter-clockwise polygon ``convex``."""
    out = subject
    for a, b in zip(convex, np.roll(convex, -1, axis=0)):
        if len(out) == 0:
            return None
        side = (b[0] - a[0]) * (out[:, 1] - a[1]) - (b[1] - a[1]) * (out[:, 0] - a[0])
        kept = []
        for i in range(len(out)):
            j = (i + 1) % len(out)
            if side[j] >= 0:
                if side[i] < 0:
                    kept.append(out[i] + (out[j] - out[i]) * side[i] / (side[i] - side[j]))
                kept.append(out[j])
            elif side[i] >= 0:
                kept.append(out[i] + (out[j] - out[i]) * side[i] / (side[i] - side[j]))
        out = np.array(kept)
    return out if len(out) >= 3 else None


def _placed_cup_tooth(params, cup: ToothSpec, local: np.ndarray, phi: float) -> np.ndarray:
    fc, w0 = params.flexspline_cup, params.gear.radial_deformation_mm
    r_m = 0.5 * fc.pitch_diameter_mm - 0.5 * fc.wall_thickness_mm
    w, v = w0 * math.cos(2 * phi), -0.5 * w0 * math.sin(2 * phi)
    theta, psi = phi + v / r_m, phi + 1.5 * w0 / r_m * math.sin(2 * phi)
    foot = ((r_m + w) * np.array([math.cos(theta), math.sin(theta)])
            + (cup.root_radius_mm - r_m) * np.array([math.cos(psi), math.sin(psi)]))
    turn = np.array([[math.cos(psi), -math.sin(psi)], [math.sin(psi), math.cos(psi)]])
    return (local - [cup.root_radius_mm, 0.0]) @ turn.T + foot


def tooth_overlaps(params, quadrant: bool = True) -> list[ToothOverlap]:
    """Every cup tooth's overlap with the spline (the first quadrant's, 0..90 deg, when ``quadrant``: the pair is
    symmetric about both axes)."""
    cup, spline = cup_tooth_spec(params), circular_spline_tooth_spec(params)
    local = _outline(cup, 0.0)
    pitch_c = 2 * math.pi / spline.teeth
    last = cup.teeth // 4 if quadrant else cup.teeth - 1
    rows = []
    for j in range(last + 1):
        phi = 2 * math.pi * j / cup.teeth
        tooth = _placed_cup_tooth(params, cup, local, phi)
        k0 = round(phi / pitch_c)
        area = 0.0
        for k in range(k0 - 2, k0 + 3):   # the spline's teeth within two pitches of the cup tooth
            common = _clip(_outline(spline, (k + 0.5) * pitch_c), tooth)
            area += abs(_area(common)) if common is not None else 0.0
        rows.append(ToothOverlap(math.degrees(phi), area))
    return rows


def overlap_threshold_mm2(params) -> float:
    return OVERLAP_PER_M2 * params.flexspline_cup.module_mm ** 2


def overlap_summary(params) -> str | None:
    """One line naming where the teeth overlap (first quadrant, mirrored), or None when they clear everywhere."""
    hits = [r for r in tooth_overlaps(params) if r.area_mm2 > overlap_threshold_mm2(params)]
    if not hits:
        return None
    lo, hi = min(r.phi_deg for r in hits), max(r.phi_deg for r in hits)
    w0, m = params.gear.radial_deformation_mm, params.flexspline_cup.module_mm
    return (f"the rigid teeth overlap the circular spline's by up to {max(r.area_mm2 for r in hits):.3g} mm^2 a tooth "
            f"at {lo:.0f}-{hi:.0f} deg from the major axis (and its mirror images about both axes): the design's tooth pair (w0 = {w0 / m:.3g} m, "
            f"h_a,c = {params.circular_spline.addendum_coefficient:g}, backlash {params.circular_spline.backlash_mm:g} mm) "
            f"has no clearance there; the drawing shows the design as given")
