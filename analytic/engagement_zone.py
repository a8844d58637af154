"""The edge of the strain-wave engagement zone from the kinematic theory, by hand (check ``mesh.engagement_zone``).

The flexspline's neutral line (radius r_n) takes the wave generator's shape and does not stretch:

    w = w0 cos 2 phi,    v = -(w0/2) sin 2 phi,    chi = (v - dw/dphi) / r_n = (3 w0 / (2 r_n)) sin 2 phi

(phi from the major axis; chi the section's rotation). A tooth is rigid on its section, so its tip (radius r_a in
the undeformed cup) travels on the path

    R(phi) = r_a + w,      angle(phi) = phi + (v + (r_a - r_n) chi) / r_a.

With the output held against the wave generator (Z_c - Z_f = 2) the circular spline's space that faces the tooth
at phi is centred on phi Z_f / Z_c, so the tip stands e = R (angle - phi Z_f / Z_c) ahead of the space's middle.
The driving flank of the tooth (the one a positive output torque closes) clears the space's flank at the tip by

    gap(phi) = R s(R) + j_t R / r_pc - r_a t(r_a) - e

(s: the space's half angle at R, t: the cup tooth's half angle at r_a, both the design's involutes; j_t the backlash
per flank at the CS pitch circle r_pc). Near the major axis the tooth sits centred with its backlash; the gap
narrows as the tooth climbs out, and the tip reaches the circular spline's flank where gap = 0: the edge of the
engagement zone, beyond which rigid teeth would cut into each other. Nothing here calls the study's engagement
(analytic/mesh_engagement.py): the path is written out again from the theory.
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["tip_path", "driving_flank_gap_mm", "zone_edge_rad"]


def tip_path(phi_rad, w0_mm: float, r_neutral_mm: float, rho_mm: float) -> tuple[np.ndarray, np.ndarray]:
    """(R, angle) of the point at radius ``rho_mm`` of the rigid tooth standing at ``phi_rad`` on the neutral line."""
    phi = np.asarray(phi_rad, float)
    w = w0_mm * np.cos(2 * phi)
    v = -0.5 * w0_mm * np.sin(2 * phi)
    chi = 1.5 * w0_mm * np.sin(2 * phi) / r_neutral_mm
    return rho_mm + w, phi + (v + (rho_mm - r_neutral_mm) * chi) / rho_mm


def driving_flank_gap_mm(phi_rad, geo, rho_mm: float | None = None) -> np.ndarray:
    """Arc gap (mm, at the deformed radius) between the driving flank of the tooth at ``phi_rad`` and the circular
    spline's flank, at the tooth's radius ``rho_mm`` (default: its tip). ``geo``: geometry.mesh_geometry's record."""
    from strainwave.geometry.involute import half_angle_rad
    rho = geo.fs.tip_radius_mm if rho_mm is None else rho_mm
    phi = np.asarray(phi_rad, float)
    R, ang = tip_path(phi, geo.w0_mm, geo.r_neutral_mm, rho)
    pitch_c = 2 * math.pi / geo.z_c
    rel = ang - phi * geo.z_f / geo.z_c
    e = R * (rel - np.round(rel / pitch_c) * pitch_c)
    space = R * half_angle_rad(geo.cs_space, R) + geo.backlash_mm * R / geo.cs_space.pitch_radius_mm
    return space - rho * half_angle_rad(geo.fs, rho) - e


def zone_edge_rad(geo, rho_mm: float | None = None, *, samples: int = 9001) -> float:
    """The first phi (0 < phi < pi/2) where the driving flank's gap at radius ``rho_mm`` (default: the tip) closes,
    refined by bisection between the grid points that bracket it; nan if it never closes."""
    phi = np.linspace(0.0, 0.5 * math.pi, samples)[1:-1]
    g = driving_flank_gap_mm(phi, geo, rho_mm)
    shut = np.flatnonzero(g <= 0.0)
    if shut.size == 0 or shut[0] == 0:
        return math.nan
    lo, hi = float(phi[shut[0] - 1]), float(phi[shut[0]])
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if driving_flank_gap_mm(mid, geo, rho_mm) > 0.0 else (lo, mid)
    return 0.5 * (lo + hi)
