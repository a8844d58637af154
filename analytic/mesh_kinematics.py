"""Where the teeth stand unloaded: the kinematic theory of strain-wave tooth engagement.

The flexspline's neutral line (radius r_n, mid-surface of the rim under the teeth) is forced into
w(phi) = w0 cos 2(phi - psi) by the wave generator at angle psi and does not stretch (v' = -w), so

    v = -(w0/2) sin 2(phi - psi),       gamma = (v - w')/r_n = (3 w0 / (2 r_n)) sin 2(phi - psi)
(for U waves: w0 cos U(phi - psi), v = -(w0/U) sin U(phi - psi), gamma = w0 (U - 1/U)/r_n sin U(phi - psi))

(tangential displacement and the rotation of the rim's cross-section; J. Mech. Des. 112(1):131, 1990:
the teeth are rigid bodies riding on that line). The circular spline's teeth are fixed. With the wave
generator at psi the flexspline has turned by -2 psi / Z_f (Z_c - Z_f = 2, circular spline held), so
flexspline tooth j sits, at its pitch point, a circumferential distance

    e_j = r_p (phi_j - phi_space) + v_j + gamma_j (r_p - r_n)

from the middle of the circular-spline tooth space it is in, and Delta_j = w0 - w_j below full depth.
On a rack of pressure angle alpha a tooth lowered by Delta clears each flank by Delta tan(alpha) more
(circumferentially), so the gap of the driving (+) and reverse (-) flank along the line of action is

    g_j(+/-) = cos(alpha) * (j_t + Delta_j tan(alpha) -/+ e_j)        (j_t: backlash per flank)

clipped at zero (a design with kappa > 1 may interfere: those pairs start touching). A pair exists only
while the tips overlap by more than ``min_overlap_mm`` (working depth 2 h_a m minus Delta).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["MeshGeometry", "TeethOnNeutralLine", "coning_factors", "teeth_on_neutral_line", "flank_clearances",
           "sliced_clearances"]


@dataclass(frozen=True)
class MeshGeometry:
    """The drive's tooth-mesh geometry (lengths mm, angles deg)."""

    teeth_flexspline: int          # Z_f
    module_mm: float               # m
    w0_mm: float                   # radial deformation at the major axis
    pressure_angle_deg: float
    addendum_coefficient: float    # h_a / m of each part (working depth 2 h_a m)
    backlash_mm: float             # circumferential clearance per flank at the pitch circle
    rim_thickness_mm: float        # rim under the teeth (its mid-surface is the neutral line)
    face_width_mm: float
    wave_number: int = 2
    cup_length_mm: float = 0.0     # diaphragm to rim; > 0 cones the flexure along the face (w ~ z), 0: a ring
    face_slices: int = 1           # the face width cut into this many slices, each with its own clearance
    # manufacturing deviations (analytic/tooth_deviations, decision 070-engage48): ISO 1328-1 class, None: ideal teeth;
    # the seed picks one unit
    accuracy_grade: float | None = None
    deviation_seed: int = 0

    @property
    def teeth_circular(self) -> int:
        return self.teeth_flexspline + self.wave_number

    @property
    def pitch_radius_mm(self) -> float:
        return 0.5 * self.module_mm * self.teeth_flexspline

    @property
    def neutral_radius_mm(self) -> float:
        # the root sits 1.25 m below the pitch circle, the neutral line half the rim below the root
        return self.pitch_radius_mm - 1.25 * self.module_mm - 0.5 * self.rim_thickness_mm

    @property
    def min_overlap_mm(self) -> float:
        # the rack model's flank contact needs the pitch point inside the space: overlap >= one addendum
        return self.addendum_coefficient * self.module_mm


@dataclass(frozen=True)
class TeethOnNeutralLine:
    """Flexspline teeth at one wave-generator angle (arrays over the Z_f teeth)."""

    angle_rad: np.ndarray        # deformed angular position of each tooth's pitch point
    offset_mm: np.ndarray        # e_j: circumferential offset from the middle of its tooth space
    depth_loss_mm: np.ndarray    # Delta_j = w0 - w_j
    overlap_mm: np.ndarray       # tip overlap: working depth - Delta_j
    radial_mm: np.ndarray        # w_j
    space: np.ndarray | None = None   # the circular-spline tooth space each tooth's pitch point is in (0..Z_c-1)


def coning_factors(g: MeshGeometry) -> np.ndarray:
    """w0(z)/w0 at the middle of each face slice: the cup flexes in proportion to the distance z from its
    diaphragm (references section 2, coning), w0 being the design value at the open end, where the teeth
    meet at full depth (a slice nearer the diaphragm sits shallower, never in interference)."""
    n = g.face_slices
    if g.cup_length_mm <= 0.0 or n == 1:
        return np.ones(n)
    z = g.cup_length_mm - g.face_width_mm * (np.arange(n) + 0.5) / n
    return z / g.cup_length_mm


def teeth_on_neutral_line(g: MeshGeometry, psi_rad: float, scale: float = 1.0) -> TeethOnNeutralLine:
    """Every flexspline tooth's place against the circular spline at wave-generator angle ``psi_rad``
    (``scale``: the flexure there over the design w0, a face slice of a coned cup)."""
    zf, zc = g.teeth_flexspline, g.teeth_circular
    r_p, r_n = g.pitch_radius_mm, g.neutral_radius_mm
    phi = 2.0 * np.pi * np.arange(zf) / zf - g.wave_number * psi_rad / zf
    u = g.wave_number
    x = u * (phi - psi_rad)
    w0 = scale * g.w0_mm
    w = w0 * np.cos(x)
    v = -w0 / u * np.sin(x)                      # inextensible: v' = -w
    gamma = w0 * (u - 1.0 / u) / r_n * np.sin(x)   # (v - w') / r_n
    ang = phi + v / r_n + gamma * (r_p - r_n) / r_p
    pitch_c = 2.0 * np.pi / zc
    # the tooth space of the circular spline each tooth's pitch point falls in (spaces centred on k pitch_c)
    k = np.round(ang / pitch_c)
    offset = r_p * (ang - k * pitch_c)
    delta = g.w0_mm - w                          # depth lost against the full depth of the design section
    overlap = 2.0 * g.addendum_coefficient * g.module_mm - delta
    return TeethOnNeutralLine(ang, offset, delta, overlap, w, np.mod(k, zc).astype(int))


def flank_clearances(g: MeshGeometry, teeth: TeethOnNeutralLine) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(gap along the line of action mm, sign +1 driving / -1 reverse flank, tooth index) of every flank
    pair whose tips overlap: the unloaded clearances of the mesh at this wave-generator angle."""
    alpha = np.radians(g.pressure_angle_deg)
    live = np.flatnonzero(teeth.overlap_mm > g.min_overlap_mm)
    dev = _deviations(g)
    gaps, signs, index = [], [], []
    for sgn in (1.0, -1.0):
        circ = g.backlash_mm + teeth.depth_loss_mm[live] * np.tan(alpha) - sgn * teeth.offset_mm[live]
        gap = np.maximum(np.cos(alpha) * circ, 0.0)
        if dev is not None and len(live):
            gap = _with_deviations(gap, dev.flank_offset_mm(live, teeth.space[live], sgn) * np.cos(alpha))
        gaps.append(gap)
        signs.append(np.full(len(live), sgn))
        index.append(live)
    return np.concatenate(gaps), np.concatenate(signs), np.concatenate(index)


def _deviations(g: MeshGeometry):
    if g.accuracy_grade is None:
        return None
    from strainwave.analytic.tooth_deviations import draw_deviations
    return draw_deviations(g.teeth_flexspline, g.teeth_circular, g.module_mm, g.accuracy_grade, g.deviation_seed)


def _with_deviations(gap: np.ndarray, offset: np.ndarray) -> np.ndarray:
    """The ideal gaps plus each pair's deviation, shifted so the tightest pair of this flank keeps the ideal mesh's
    smallest gap (a zero-backlash unit is assembled to zero backlash whatever its deviations). The shift is taken at
    the wave-generator angle asked for (the catalogue's one angle), not fixed per unit over a revolution."""
    raw = gap + offset
    return np.maximum(raw - raw.min() + gap.min(), 0.0)


def sliced_clearances(g: MeshGeometry, psi_rad: float):
    """``flank_clearances`` of every face slice: (gap, sign, tooth, slice, tooth angles of the design section)."""
    out = [], [], [], []
    angles = teeth_on_neutral_line(g, psi_rad).angle_rad
    for k, f in enumerate(coning_factors(g)):
        gap, sign, tooth = flank_clearances(g, teeth_on_neutral_line(g, psi_rad, f))
        for lst, arr in zip(out, (gap, sign, tooth, np.full(len(gap), k))):
            lst.append(arr)
    gap, sign, tooth, sl = (np.concatenate(a) for a in out)
    return gap, sign, tooth, sl, angles
