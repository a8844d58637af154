"""Thin ring under two diametral forces: seed 003, eqs 1-9 (bending energy only).

The flexspline rim of a harmonic gear drive with external wave generator (EWG) is
modelled as a thin circular ring of mid-layer radius r_m, squeezed by two equal and
opposite forces F at C and D. The angle phi is measured from the unloaded section B
(phi = 0) towards the load point D (phi = pi/2), as in the seed.

All coefficients are derived from pi here; the seed's printed decimals
(0.148778, 0.136620, 8.5580, 4.8849) are only used in tests as targets.
"""
from __future__ import annotations

import math

import numpy as np


def mid_layer_radius_mm(module_mm: float, teeth: int, rim_thickness_mm: float,
                        dedendum_coefficient: float = 1.35) -> float:
    """Radius of the undeformed mid-layer (seed 003, eq 1).

    r_m = 0.5 d_R + h_fR + 0.5 delta, with d_R = m Z_R and h_fR = h*_fR m.
    """
    return 0.5 * module_mm * teeth + dedendum_coefficient * module_mm + 0.5 * rim_thickness_mm


def second_moment_mm4(face_width_mm: float, rim_thickness_mm: float) -> float:
    """I = B delta^3 / 12 of the rim cross-section (seed 003, text under eq 3)."""
    return face_width_mm * rim_thickness_mm ** 3 / 12.0


def bending_moment_Nmm(phi_rad: float, force_N: float, r_m_mm: float) -> float:
    """Bending moment M(phi) = F r_m (cos(phi)/2 - 1/pi), phi from B (seed 003, eq 2).

    Valid for 0 <= phi <= pi/2 and extended by the ring's two symmetry axes.
    """
    phi = _fold(phi_rad)
    return force_N * r_m_mm * (0.5 * math.cos(phi) - 1.0 / math.pi)


def delta_cd_coefficient() -> float:
    """(pi^2 - 8)/(4 pi) = 0.148778: shortening of the loaded diameter CD (seed 003, eq 3)."""
    return (math.pi ** 2 - 8.0) / (4.0 * math.pi)


def delta_ab_coefficient() -> float:
    """2/pi - 1/2 = 0.136620: lengthening of the free diameter AB (seed 003, eq 4)."""
    return 2.0 / math.pi - 0.5


def delta_cd_mm(force_N: float, r_m_mm: float, E_MPa: float, I_mm4: float) -> float:
    """delta_CD = (pi^2 - 8) F r_m^3 / (4 pi E I) (seed 003, eq 3)."""
    return delta_cd_coefficient() * force_N * r_m_mm ** 3 / (E_MPa * I_mm4)


def delta_ab_mm(force_N: float, r_m_mm: float, E_MPa: float, I_mm4: float) -> float:
    """delta_AB = (2/pi - 1/2) F r_m^3 / (E I) (seed 003, eq 4)."""
    return delta_ab_coefficient() * force_N * r_m_mm ** 3 / (E_MPa * I_mm4)


def radial_deformation_from_force_mm(force_N: float, r_m_mm: float, E_MPa: float, I_mm4: float) -> float:
    """W0 = delta_CD / 2 (seed 003, eq 5)."""
    return 0.5 * delta_cd_mm(force_N, r_m_mm, E_MPa, I_mm4)


def radial_deformation_from_teeth_mm(module_mm: float, tooth_difference: int) -> float:
    """W0 = 0.5 m dZ, the deformation the mesh demands (seed 003, eq 7)."""
    return 0.5 * module_mm * tooth_difference


def short_semi_axis_mm(module_mm: float, circular_spline_teeth: int, rim_thickness_mm: float,
                       dedendum_coefficient: float = 1.35) -> float:
    """b = 0.5 d_G + h_fR + 0.5 delta with d_G = m Z_G (seed 003, eq 6)."""
    return 0.5 * module_mm * circular_spline_teeth + dedendum_coefficient * module_mm + 0.5 * rim_thickness_mm


def force_for_deformation_N(W0_mm: float, r_m_mm: float, E_MPa: float, I_mm4: float) -> float:
    """Squeezing force that produces W0: F = 2 W0 E I / (0.148778 r_m^3) (seed 003, eqs 3 and 5 inverted)."""
    return 2.0 * W0_mm * E_MPa * I_mm4 / (delta_cd_coefficient() * r_m_mm ** 3)


def sigma_max_coefficient() -> float:
    """-16/(pi^2 - 8) = -8.557960, outer fibre at the load point D (seed 003, eq 8).

    sigma_max = coefficient * W0 E delta / d_m^2 (compressive).
    """
    return -16.0 / (math.pi ** 2 - 8.0)


def sigma_min_coefficient() -> float:
    """8(pi - 2)/(pi^2 - 8) = 4.884852, outer fibre at the free point B (seed 003, eq 9)."""
    return 8.0 * (math.pi - 2.0) / (math.pi ** 2 - 8.0)


def sigma_max_MPa(W0_mm: float, E_MPa: float, rim_thickness_mm: float, d_m_mm: float) -> float:
    """sigma_max = -8.5580 W0 E delta / d_m^2, outer fibre at D (seed 003, eq 8)."""
    return sigma_max_coefficient() * W0_mm * E_MPa * rim_thickness_mm / d_m_mm ** 2


def sigma_min_MPa(W0_mm: float, E_MPa: float, rim_thickness_mm: float, d_m_mm: float) -> float:
    """sigma_min = 4.8849 W0 E delta / d_m^2, outer fibre at B (seed 003, eq 9)."""
    return sigma_min_coefficient() * W0_mm * E_MPa * rim_thickness_mm / d_m_mm ** 2


def radial_displacement_mm(phi_rad, force_N: float, r_m_mm: float, E_MPa: float, I_mm4: float):
    """Radial displacement w(phi) of the mid-layer, outward positive (closed form behind seed 003, eqs 3-4).

    From the inextensible thin-ring equation w'' + w = -M r^2/(E I) with M of eq 2,
    symmetry w'(0) = w'(pi/2) = 0 and zero mean (inextensibility):

        w(phi) = (F r^3 / E I) [1/pi - (phi sin phi)/4 - (cos phi)/4],   phi from B.

    w(pi/2) = -delta_CD/2 and w(0) = +delta_AB/2. Works on scalars or arrays.
    """
    phi = _fold(phi_rad)
    scale = force_N * r_m_mm ** 3 / (E_MPa * I_mm4)
    return scale * (1.0 / np.pi - 0.25 * phi * np.sin(phi) - 0.25 * np.cos(phi))


def tangential_displacement_mm(phi_rad, force_N: float, r_m_mm: float, E_MPa: float, I_mm4: float):
    """Tangential displacement v(phi) (towards increasing phi), from inextensibility v' = -w.

    v(phi) = -(F r^3/EI) [phi/pi + (phi cos phi)/4 - (sin phi)/2] on 0 <= phi <= pi/2,
    odd about B and about D. Zero at B and D.
    """
    phi_arr = np.asarray(phi_rad, dtype=float)
    folded = _fold(phi_arr)
    sign = _fold_sign(phi_arr)
    scale = force_N * r_m_mm ** 3 / (E_MPa * I_mm4)
    v = -scale * (folded / np.pi + 0.25 * folded * np.cos(folded) - 0.5 * np.sin(folded))
    return sign * v


def deformed_mid_layer_mm(W0_mm: float, r_m_mm: float, n_points: int = 361):
    """Points (x, y) of the deformed mid-layer for a prescribed W0 (seed 003, Fig. 2, drawn exactly).

    The loads act along the x axis (C and D at phi = 90 and 270 deg from B, which lies
    on +y). Uses w and v of the thin-ring solution, scaled so that w(D) = -W0.
    Returns (x_mm, y_mm) arrays; the ring is NOT an ellipse (AB grows by 0.918 W0).
    """
    unit_E_I = 1.0
    force = force_for_deformation_N(W0_mm, r_m_mm, 1.0, unit_E_I)
    phi = np.linspace(0.0, 2.0 * np.pi, n_points)
    w = radial_displacement_mm(phi, force, r_m_mm, 1.0, unit_E_I)
    v = tangential_displacement_mm(phi, force, r_m_mm, 1.0, unit_E_I)
    # Polar angle theta measured from +x (load point D) with B at +y: theta = pi/2 - phi.
    theta = np.pi / 2.0 - phi
    e_r = np.stack([np.cos(theta), np.sin(theta)])
    e_phi = np.stack([np.sin(theta), -np.cos(theta)])   # d(position)/d(phi) direction
    pos = (r_m_mm + w) * e_r + v * e_phi
    return pos[0], pos[1]


def _fold(phi):
    """Map any angle onto [0, pi/2] using the ring's two symmetry axes (through B and through D)."""
    p = np.mod(np.asarray(phi, dtype=float), np.pi)
    p = np.where(p > np.pi / 2, np.pi - p, p)
    return float(p) if np.ndim(p) == 0 else p


def _fold_sign(phi):
    """+1 where the folded angle increases with phi, -1 where it decreases (for odd fields like v)."""
    p = np.mod(np.asarray(phi, dtype=float), np.pi)
    return np.where(p > np.pi / 2, -1.0, 1.0)
