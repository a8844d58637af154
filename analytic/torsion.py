"""Uncracked torsional flexibilities and the drive stiffness: seed 000.

Flexibilities in rad/(N*mm), stiffnesses in N*mm/rad, lengths in mm, moduli in MPa.
Seed 000 uses the shear modulus mu directly (8e4 MPa), not E/(2(1+nu)).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from strainwave.analytic.variant import Variant

# Seed 000's printed numerical example (units 1e-10 rad/(N*mm) and N*mm/rad), kept as data.
SEED000_TABLE = {
    "lambda_H0": 3.4071e-10, "delta_lambda_H": 0.1514e-10,
    "lambda_f0": 2.3588e-10, "delta_lambda_f": 0.0000023e-10,
    "lambda_so0": 6.9063e-10, "delta_lambda_so": 0.000039e-10,
    "lambda_sum": 12.8236e-10, "lambda_sum0": 12.6722e-10,
    "K_HD_printed": 7.7981e5, "K_HD0_printed": 7.8913e5,
    "reduction_percent": 1.2, "shares_percent": (28.0, 19.0, 53.0),
}


def polar_factor(variant: Variant) -> float:
    """J = factor * (D^4 - d^4): 0.1 as printed in seed 000, pi/32 = 0.098175 exactly."""
    return 0.1 if variant is Variant.PUBLISHED else math.pi / 32.0


def shape_coefficient(bell: bool) -> float:
    """k_f: 0.83 for a bell-shaped flexspline, 1.0 for cylindrical (seed 000, lambda_f0)."""
    return 0.83 if bell else 1.0


def structure_coefficient(cup: bool) -> float:
    """k_G: 0.83 for a cup-shaped flexspline, 1.0 otherwise (seed 000, lambda_f0)."""
    return 0.83 if cup else 1.0


def flexspline_flexibility(d1_mm: float, wall_mm: float, length_mm: float, mu_MPa: float,
                           k_f: float, k_G: float, variant: Variant = Variant.PUBLISHED) -> float:
    """lambda_f0 = k_f k_G c_L / (0.1 mu [1 - (1 - 2 c_delta)^4] d1^3) (seed 000, lambda_f0).

    c_L = L/d1, c_delta = delta/d1: a tube of outer diameter d1 and wall delta.
    PUBLISHED uses 0.1 (compliance 1.83 % low); CORRECTED uses pi/32.
    Default seed-000 example: 2.3588e-10 rad/(N*mm) with k_f = 1, k_G = 0.83.
    """
    c_L = length_mm / d1_mm
    c_d = wall_mm / d1_mm
    return k_f * k_G * c_L / (polar_factor(variant) * mu_MPa * (1.0 - (1.0 - 2.0 * c_d) ** 4) * d1_mm ** 3)


def shaft_flexibility(length_mm: float, outer_mm: float, inner_mm: float, mu_MPa: float,
                      variant: Variant = Variant.PUBLISHED) -> float:
    """Output-shaft flexibility (seed 000, lambda_so0).

    PUBLISHED: L_s/(0.1 mu d_s^4), the bore ignored (10.4123e-10 for the example).
    CORRECTED: 32 L_s/(pi mu (d_s^4 - d_s2^4)), the hollow shaft (12.790e-10).
    """
    if variant is Variant.PUBLISHED:
        return length_mm / (0.1 * mu_MPa * outer_mm ** 4)
    return 32.0 * length_mm / (math.pi * mu_MPa * (outer_mm ** 4 - inner_mm ** 4))


def shaft_flexibility_table_reconstruction(length_mm: float, outer_mm: float, inner_mm: float,
                                           mu_MPa: float) -> float:
    """L_s/(0.1 mu (d_s^4 - d_s2^4)): the only reading that gives seed 000's table value.

    Reproduces 6.9063e-10 only with L_s = 110 mm (the seed states 200 mm).
    """
    return length_mm / (0.1 * mu_MPa * (outer_mm ** 4 - inner_mm ** 4))


def shaft_length_implied_mm(flexibility: float, outer_mm: float, inner_mm: float, mu_MPa: float) -> float:
    """L_s that makes ``shaft_flexibility_table_reconstruction`` equal to ``flexibility`` (audit item 13)."""
    return flexibility * 0.1 * mu_MPa * (outer_mm ** 4 - inner_mm ** 4)


def radial_force_N(force_coefficient: float, torque_Nmm: float, d1_mm: float) -> float:
    """F_r = 1.15 k_r T / d1 (seed 000, wave generator section)."""
    return 1.15 * force_coefficient * torque_Nmm / d1_mm


def wave_generator_kinematic_factor(d1_mm: float, wave_number: int, w0_mm: float, gear_ratio: float) -> float:
    """pi / (2 d1 U w0 i_h), the radial-to-torsional conversion in lambda_H (seed 000)."""
    return math.pi / (2.0 * d1_mm * wave_number * w0_mm * gear_ratio)


def wave_generator_flexibility(force_coefficient: float, K_G_N_per_mm: float, d1_mm: float, wave_number: int,
                               w0_mm: float, gear_ratio: float) -> float:
    """lambda_H = (k_r / K_G) * pi / (2 d1 U w0 i_h) (seed 000).

    Units check but the relation is not derived in the seed; K_G0 is never given
    (6.303e4 N/mm reproduces the table's 3.4071e-10).
    """
    return force_coefficient / K_G_N_per_mm * wave_generator_kinematic_factor(d1_mm, wave_number, w0_mm, gear_ratio)


def radial_stiffness_implied_N_per_mm(lambda_H: float, force_coefficient: float, d1_mm: float,
                                      wave_number: int, w0_mm: float, gear_ratio: float) -> float:
    """K_G0 implied by a lambda_H (inverse of ``wave_generator_flexibility``)."""
    return force_coefficient * wave_generator_kinematic_factor(d1_mm, wave_number, w0_mm, gear_ratio) / lambda_H


def cracked_radial_stiffness_N_per_mm(K_G0_N_per_mm: float, delta_K_G: float,
                                      variant: Variant = Variant.CORRECTED) -> float:
    """Radial stiffness of the cracked wave generator (seed 000, K_G = K_G0 - dK_G).

    PUBLISHED: K_G0 - dK_G (subtracts stiffnesses; negative for the example).
    CORRECTED: springs in series, 1/K_G = 1/K_G0 + 1/dK_G.
    """
    if variant is Variant.PUBLISHED:
        return K_G0_N_per_mm - delta_K_G
    return 1.0 / (1.0 / K_G0_N_per_mm + 1.0 / delta_K_G)


def radial_stiffness_with_crack_N_per_mm(K_G0_N_per_mm: float, delta_u_H_mm: float, radial_force_N: float,
                                         variant: Variant = Variant.CORRECTED) -> float:
    """K_G from K_G0 and the crack's extra radial displacement du_H at F_r (seed 000).

    PUBLISHED: K_G0 - F_r/du_H (stiffnesses subtracted). CORRECTED: compliances added,
    1/K_G = 1/K_G0 + du_H/F_r.
    """
    return cracked_radial_stiffness_N_per_mm(K_G0_N_per_mm, radial_force_N / delta_u_H_mm, variant)


def total_flexibility(lambda_H: float, lambda_f: float, lambda_so: float) -> float:
    """lambda_sum = lambda_H + lambda_f + lambda_so (seed 000, first equation)."""
    return lambda_H + lambda_f + lambda_so


def drive_stiffness_Nmm_per_rad(lambda_sum: float) -> float:
    """K_HD = 1/lambda_sum in N*mm/rad (seed 000). The seed prints 1e3 too small."""
    return 1.0 / lambda_sum


def printed_stiffness_slip(lambda_sum: float, printed_K_HD: float) -> float:
    """Ratio of 1/lambda_sum to the seed's printed K_HD: 1e3 for both table rows (audit item 14)."""
    return drive_stiffness_Nmm_per_rad(lambda_sum) / printed_K_HD


def shares(lambda_H: float, lambda_f: float, lambda_so: float) -> tuple[float, float, float]:
    """Fractions of lambda_sum carried by wave generator, flexspline and output shaft."""
    total = total_flexibility(lambda_H, lambda_f, lambda_so)
    return lambda_H / total, lambda_f / total, lambda_so / total


@dataclass(frozen=True)
class CupSeriesFlexibility:
    """The parts of ``cup_series_flexibility`` in rad/(N*mm): tube, diaphragm and hub in series."""

    tube: float
    diaphragm: float
    hub: float

    @property
    def total(self) -> float:
        return self.tube + self.diaphragm + self.hub

    def to_dict(self) -> dict:
        return {"tube": self.tube, "diaphragm": self.diaphragm, "hub": self.hub, "total": self.total}


def tube_effective_length_mm(length_mm: float, band_length_mm: float, diaphragm_z_mm: float) -> float:
    """Twisted length of the tube between the diaphragm mid-plane and the band's mean rotation.

    The torque T enters the band (the last b of the tube, up to z = L) uniformly per unit length, so the
    internal torque falls linearly from T at the band start to 0 at the rim. With x measured from the
    band start, the twist in the band is phi(x) = phi_b + T/(G J) (x - x^2/(2b)); its mean over the band
    is phi_b + T/(G J) (b/2 - b/6), hence L_eff = (L - b - z_d) + b/3.
    """
    return length_mm - band_length_mm - diaphragm_z_mm + band_length_mm / 3.0


def cup_series_flexibility(d1_mm: float, wall_mm: float, length_mm: float, G_MPa: float, *,
                           hub_radius_mm: float, hub_bore_radius_mm: float, hub_height_mm: float,
                           diaphragm_thickness_mm: float, band_length_mm: float,
                           diaphragm_z_mm: float) -> CupSeriesFlexibility:
    """Torsional flexibility of a cup: tube + annular diaphragm + hub in series (strainwave's own model).

    Not a seed formula: seed 000's lambda_f0 is a bare tube of length L (scaled by k_f k_G) and has no
    diaphragm term, yet the diaphragm is about as compliant as the tube. Parameters
    (lengths in mm, G in MPa; the cup's z runs from the clamped hub face z = 0 to the rim z = L):

    Parameters
    ----------
    d1_mm, wall_mm, length_mm : float
        Outer diameter of the wall, wall thickness delta, cup length L (clamped face to open rim).
    G_MPa : float
        Shear modulus.
    hub_radius_mm, hub_bore_radius_mm, hub_height_mm : float
        Hub (boss) outer radius, bore radius and height; the diaphragm must lie on it.
    diaphragm_thickness_mm, diaphragm_z_mm : float
        Diaphragm thickness t and the z of its mid-plane.
    band_length_mm : float
        Axial length b of the loaded band at the rim (uniform torque per length; twist averaged over it).

    Returns
    -------
    CupSeriesFlexibility
        - tube: L_eff/(G J), J = pi/32 (d1^4 - (d1 - 2 delta)^4), L_eff from ``tube_effective_length_mm``;
        - diaphragm: an annular plate in pure shear tau = T/(2 pi r^2 t), so dphi/dr = T/(2 pi G t r^3),
          integrated from the hub radius to the wall mid-surface r_m = (d1 - delta)/2:
          (1/(4 pi G t)) (1/r_hub^2 - 1/r_m^2);
        - hub: a solid annulus r_bore..r_hub twisted from the clamped face to the diaphragm mid-plane,
          z_d/(G pi/2 (r_hub^4 - r_bore^4)).
        Ignored: the wall-diaphragm and hub-diaphragm junctions (fillet, local warping of the corners).
    """
    if not 0.0 < diaphragm_z_mm <= hub_height_mm or not 0.0 <= hub_bore_radius_mm < hub_radius_mm:
        raise ValueError("the diaphragm must lie on a hub with a bore smaller than it")
    J_tube = math.pi / 32.0 * (d1_mm ** 4 - (d1_mm - 2.0 * wall_mm) ** 4)
    tube = tube_effective_length_mm(length_mm, band_length_mm, diaphragm_z_mm) / (G_MPa * J_tube)
    r_m = 0.5 * (d1_mm - wall_mm)
    diaphragm = (1.0 / hub_radius_mm ** 2 - 1.0 / r_m ** 2) / (4.0 * math.pi * G_MPa * diaphragm_thickness_mm)
    J_hub = 0.5 * math.pi * (hub_radius_mm ** 4 - hub_bore_radius_mm ** 4)
    hub = diaphragm_z_mm / (G_MPa * J_hub)
    return CupSeriesFlexibility(tube, diaphragm, hub)
