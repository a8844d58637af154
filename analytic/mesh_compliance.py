"""Closed-form flexibility of the teeth in mesh along their lines of action (mm/N).

Three springs, each a named pure function so the FE study can replace one and compare with it:

1. the tooth pair itself, ISO 6336-1:2019 Method B single-pair stiffness
       c'_th = 1 / q',  q' = C1 + C2/z_n1 + C3/z_n2 + C4 x1 + C5 x1/z_n1 + C6 x2 + C7 x2/z_n2 + C8 x1^2 + C9 x2^2
       c' = c'_th C_M C_R C_B cos(beta)          (N/(mm um)); per pair along the line of action 1/(c' b);
   internal gear: z_n2 -> infinity (ISO's rule for internal teeth), C_M = 0.8, C_R = 1 (solid blank: the
   thin rim is spring 2), C_B from the basic rack;
2. the flexspline rim with the wave-generator bearing's outer ring, a beam on an elastic foundation
   (Hetenyi): a radial load P at s deflects the rim at s' by P beta/(2 k) e^{-beta|x|} (cos beta x + sin beta|x|),
   x = s' - s, beta = (k / (4 E I))^(1/4), k the bearing's radial foundation modulus per unit length;
   the flank's tangential component F cos(alpha), applied h above the neutral line, is a moment F cos(alpha) h
   that turns the rim by beta^3/k e^{-beta|x|} (cos beta|x| - sin beta|x|) per unit moment (Hetenyi's C function;
   decision 077-hetenyi48) and tilts the teeth it carries
   (the radial-moment cross terms, odd in x, are left out: they cancel over a zone symmetric about a tooth);
3. the wave generator as one radial spring per lobe (its cam and inner ring), K_G.

A flank's normal force F has a radial component F sin(alpha) that pushes the flexspline tooth inward, which
opens the flank along its line of action by sin(alpha) per unit radial travel; hence springs 2 and 3 enter
as sin(alpha_i) sin(alpha_j) G_r(i, j).
"""
from __future__ import annotations

import math

import numpy as np

__all__ = ["iso6336_single_pair_stiffness_N_per_mm_um", "tooth_pair_compliance_mm_per_N",
           "rim_on_foundation_green_mm_per_N", "rim_moment_green_rad_per_Nmm", "thin_rim_tilt_compliance_mm_per_N", "wave_generator_lobe_compliance_mm_per_N", "mesh_compliance_matrix"]

_ISO_C = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)
ISO_SOURCE = "ISO 6336-1:2019, 9.3 (Method B): q', c'_th, C_M = 0.8, C_B"


def iso6336_single_pair_stiffness_N_per_mm_um(z1: float, z2: float | None, x1: float = 0.0, x2: float = 0.0,
                                              alpha_deg: float = 20.0, dedendum_coef: float = 1.25,
                                              C_R: float = 1.0) -> float:
    """c' (N per mm face width per um) of one spur tooth pair; ``z2=None`` for internal teeth (z_n2 -> inf)."""
    C1, C2, C3, C4, C5, C6, C7, C8, C9 = _ISO_C
    inv2 = 0.0 if z2 is None else 1.0 / z2
    q = C1 + C2 / z1 + C3 * inv2 + C4 * x1 + C5 * x1 / z1 + C6 * x2 + C7 * x2 * inv2 + C8 * x1 ** 2 + C9 * x2 ** 2
    C_B = (1.0 + 0.5 * (1.2 - dedendum_coef)) * (1.0 - 0.02 * (20.0 - alpha_deg))
    return 0.8 * C_R * C_B / q


def tooth_pair_compliance_mm_per_N(c_prime_N_per_mm_um: float, face_width_mm: float) -> float:
    """1/(c' b) along the line of action, in mm/N (c' b is N/um)."""
    return 1.0 / (1e3 * c_prime_N_per_mm_um * face_width_mm)


def rim_on_foundation_green_mm_per_N(arc_mm: np.ndarray, E_MPa: float, I_mm4: float,
                                     k_N_per_mm2: float) -> np.ndarray:
    """Radial deflection at arc distance ``arc_mm`` from a unit radial load on an infinite beam on an elastic
    foundation (Hetenyi 1946): beta/(2k) e^{-beta|x|} (cos beta x + sin beta|x|)."""
    beta = (k_N_per_mm2 / (4.0 * E_MPa * I_mm4)) ** 0.25
    x = np.abs(arc_mm)
    return beta / (2.0 * k_N_per_mm2) * np.exp(-beta * x) * (np.cos(beta * x) + np.sin(beta * x))


def rim_moment_green_rad_per_Nmm(arc_mm: np.ndarray, E_MPa: float, I_mm4: float,
                                 k_N_per_mm2: float) -> np.ndarray:
    """Rotation of the rim at arc distance ``arc_mm`` from a unit moment on the same beam on an elastic
    foundation (Hetenyi 1946, C function): beta^3/k e^{-beta|x|} (cos beta|x| - sin beta|x|), the slope of the
    couple's deflection beta^2/k e^{-beta|x|} sin(beta x) and minus the second derivative of the force's Green's
    function (decision 077-hetenyi48); it integrates to zero (a couple on an infinite beam turns no rigid body)."""
    beta = (k_N_per_mm2 / (4.0 * E_MPa * I_mm4)) ** 0.25
    x = np.abs(arc_mm)
    return beta ** 3 / k_N_per_mm2 * np.exp(-beta * x) * (np.cos(beta * x) - np.sin(beta * x))


def thin_rim_tilt_compliance_mm_per_N(height_mm: float, pitch_mm: float, rim_mm: float, face_width_mm: float,
                                      E_MPa: float, alpha_deg: float) -> float:
    """A tooth standing on a thin rim: its tangential load F cos(alpha) at height h bends the rim under its root
    (one pitch p long, thickness t) by the moment F cos(alpha) h; the root turns by M p / (E I), I = b t^3/12,
    and the load point moves h times that: 12 h^2 p cos^2(alpha) / (E b t^3) along the line of action.
    Small against ISO's c' when t >> m; it grows as (m/t)^3 when the module approaches the rim (low ratios)."""
    ca = math.cos(math.radians(alpha_deg))
    return 12.0 * height_mm ** 2 * pitch_mm * ca * ca / (E_MPa * face_width_mm * rim_mm ** 3)


def wave_generator_lobe_compliance_mm_per_N(K_G_N_per_mm: float) -> float:
    """One lobe of the wave generator (cam and inner ring) as a radial spring: 1/K_G."""
    return 1.0 / K_G_N_per_mm


def _lobe(angle_rad: np.ndarray, psi_rad: float, wave_number: int) -> np.ndarray:
    """Index of the wave-generator lobe (major axis) each angle is nearest to."""
    lobe_pitch = 2.0 * math.pi / wave_number
    return np.mod(np.round((angle_rad - psi_rad) / lobe_pitch), wave_number).astype(int)


def mesh_compliance_matrix(angle_rad: np.ndarray, tooth_index: np.ndarray, *, psi_rad: float, wave_number: int,
                           radius_mm: float, alpha_deg: float, pair_compliance_mm_per_N: float,
                           E_MPa: float, rim_I_mm4: float, foundation_N_per_mm2: float,
                           K_G_N_per_mm: float, tooth_height_mm: float, flank_sign: np.ndarray) -> np.ndarray:
    """(n, n) flexibility along the lines of action of the n flank pairs (teeth at ``angle_rad[tooth_index]``)."""
    ang = angle_rad[tooth_index]
    sa = math.sin(math.radians(alpha_deg))
    d = np.abs(ang[:, None] - ang[None, :])
    arc = radius_mm * np.minimum(d, 2.0 * math.pi - d)
    G = rim_on_foundation_green_mm_per_N(arc, E_MPa, rim_I_mm4, foundation_N_per_mm2)
    lobes = _lobe(ang, psi_rad, wave_number)
    G = G + wave_generator_lobe_compliance_mm_per_N(K_G_N_per_mm) * (lobes[:, None] == lobes[None, :])
    C = sa * sa * G
    # the tangential component F cos(alpha) acts at the pitch point, ``tooth_height_mm`` above the neutral line:
    # a moment on the rim whose rotation tilts every loaded tooth (driving flanks +, reverse flanks -)
    hc = tooth_height_mm * math.cos(math.radians(alpha_deg))
    M = rim_moment_green_rad_per_Nmm(arc, E_MPa, rim_I_mm4, foundation_N_per_mm2)
    C = C + hc * hc * (flank_sign[:, None] * flank_sign[None, :]) * M
    # a slice's own tooth bending acts on that slice and flank only (both flanks never carry load at once)
    return C + pair_compliance_mm_per_N * np.eye(len(ang))
