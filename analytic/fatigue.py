"""Fatigue of the EWG flexspline rim and its minimal tooth number: seed 003, eqs 10-15.

Stress coefficients multiply K_delta W0 E delta / d_m^2. The seed prints eq 10 as
"sigma_m = sigma_max + sigma_min" and eq 11 with the same label and the word
"difference"; its numbers (1.8366 and 6.7214) are the HALF sum (in magnitude) and the
HALF difference. PUBLISHED returns what the printed expressions say; CORRECTED
returns the half sum (signed) and the half difference.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from strainwave.analytic.ring import sigma_max_coefficient, sigma_min_coefficient
from strainwave.analytic.variant import Variant

# The paper's printed roots of eq 14 (seed 003, worked example, [n] = 1.4,
# sigma_-1 = 625 MPa, E = 2.1e5 MPa). Kept as data: they are not reproduced exactly.
PAPER_ROOTS = {2: 71.2765, 4: 148.0406}
PAPER_EXAMPLE = {"permissible_safety": 1.4, "fatigue_limit_MPa": 625.0, "youngs_modulus_MPa": 2.1e5}


def mean_stress_coefficient(variant: Variant = Variant.CORRECTED) -> float:
    """Coefficient of sigma_m (seed 003, eq 10).

    CORRECTED: (sigma_max + sigma_min)/2 = -4(4 - pi)/(pi^2 - 8) = -1.836554 (compressive).
    PUBLISHED: sigma_max + sigma_min as the equation is printed (no /2) = -3.673108;
    the seed's printed number is |CORRECTED| = 1.8366 (see ``printed_mean_stress_coefficient``).
    """
    total = sigma_max_coefficient() + sigma_min_coefficient()
    return total if variant is Variant.PUBLISHED else 0.5 * total


def amplitude_coefficient(variant: Variant = Variant.CORRECTED) -> float:
    """Coefficient of sigma_a (seed 003, eq 11, printed with the label sigma_m).

    CORRECTED: (sigma_min - sigma_max)/2 = 4 pi/(pi^2 - 8) = 6.721406.
    PUBLISHED: the "difference" sigma_min - sigma_max without /2 = 13.442812.
    """
    diff = sigma_min_coefficient() - sigma_max_coefficient()
    return diff if variant is Variant.PUBLISHED else 0.5 * diff


def printed_mean_stress_coefficient() -> float:
    """The number the seed prints in eq 10 and uses in eq 14: |(sigma_max + sigma_min)/2| = 1.8366."""
    return abs(mean_stress_coefficient(Variant.CORRECTED))


def stress_MPa(coefficient: float, tooth_influence: float, W0_mm: float, E_MPa: float,
               rim_thickness_mm: float, d_m_mm: float) -> float:
    """sigma = coefficient K_delta W0 E delta / d_m^2 (seed 003, eqs 10, 11)."""
    return coefficient * tooth_influence * W0_mm * E_MPa * rim_thickness_mm / d_m_mm ** 2


def normal_safety_factor(fatigue_limit_MPa: float, stress_concentration: float, sigma_a_MPa: float,
                         mean_stress_influence: float, sigma_m_MPa: float) -> float:
    """n_sigma = sigma_-1 / (K_sigma sigma_a + psi_sigma sigma_m) (seed 003, eq 13)."""
    return fatigue_limit_MPa / (stress_concentration * sigma_a_MPa + mean_stress_influence * sigma_m_MPa)


def combined_safety_factor(n_sigma: float, n_tau: float = math.inf) -> float:
    """n = n_sigma n_tau / sqrt(n_sigma^2 + n_tau^2) (seed 003, eq 12); n_tau = inf gives n_sigma."""
    if math.isinf(n_tau):
        return n_sigma
    return n_sigma * n_tau / math.hypot(n_sigma, n_tau)


@dataclass(frozen=True)
class ToothDesign:
    """The seed-003 design assumptions behind eq 14 (seed defaults in brackets)."""

    tooth_influence: float = 1.07        # K_delta
    stress_concentration: float = 1.9    # K_sigma
    mean_stress_influence: float = 0.12  # psi_sigma
    rim_thickness_ratio: float = 0.012   # delta / d_R
    dedendum_coefficient: float = 1.35   # h*_fR


def tooth_offset(design: ToothDesign = ToothDesign()) -> float:
    """Offset c in d_m = 2 r_m = (1 + ratio) m (Z_R + c), c = 2 h*_fR/(1 + ratio) (seed 003, eqs 1 and 14).

    With the seed's values c = 2.7/1.012 = 2.667984 (printed 2.668).
    """
    return 2.0 * design.dedendum_coefficient / (1.0 + design.rim_thickness_ratio)


def tooth_constant(design: ToothDesign = ToothDesign(), signed_mean_stress: bool = False) -> float:
    """C in n_sigma = C sigma_-1 (Z_R + c)^2 / (dZ E Z_R) (seed 003, eq 14).

    From eqs 1, 7, 10, 11, 13 with W0 = m dZ/2, delta = ratio m Z_R, d_m = (1 + ratio) m (Z_R + c):
        C = (1 + ratio)^2 / [K_delta (K_sigma |c_a| + psi_sigma c_m) ratio/2].
    With |sigma_m| (the seed's choice) C = 12.279522; keeping sigma_m compressive C = 12.710786.
    """
    c_m = mean_stress_coefficient(Variant.CORRECTED)
    c_m = c_m if signed_mean_stress else abs(c_m)
    denom = design.tooth_influence * (design.stress_concentration * amplitude_coefficient()
                                      + design.mean_stress_influence * c_m)
    return (1.0 + design.rim_thickness_ratio) ** 2 / (denom * 0.5 * design.rim_thickness_ratio)


def safety_from_teeth(teeth: float, tooth_difference: int, fatigue_limit_MPa: float, E_MPa: float,
                      constant: float, offset: float) -> float:
    """n_sigma = C sigma_-1 (Z_R + c)^2 / (dZ E Z_R) (seed 003, eq 14)."""
    return constant * fatigue_limit_MPa * (teeth + offset) ** 2 / (tooth_difference * E_MPa * teeth)


def minimal_teeth_root(tooth_difference: int, permissible_safety: float, fatigue_limit_MPa: float,
                       E_MPa: float, constant: float, offset: float) -> float:
    """Real root of eq 14 at n_sigma = [n] (seed 003, eq 14): the larger root of (Z + c)^2 = k Z.

    k = [n] dZ E / (C sigma_-1). n_sigma(Z) falls then rises around Z = c; the
    practical branch (thin rim, many teeth) is the larger root. Raises ValueError when
    no real root exists (n_sigma >= [n] for every Z).
    """
    k = permissible_safety * tooth_difference * E_MPa / (constant * fatigue_limit_MPa)
    p = k - 2.0 * offset
    disc = p * p - 4.0 * offset * offset
    if disc < 0.0:
        raise ValueError("eq 14 has no real root: every tooth number satisfies n_sigma >= [n]")
    return 0.5 * (p + math.sqrt(disc))


def minimal_teeth(root: float) -> int:
    """Smallest integer Z_R with n_sigma >= [n]: ceil of the root (seed 003, example text)."""
    return math.ceil(root - 1e-9)


def constant_implied_by_root(root: float, tooth_difference: int, permissible_safety: float,
                             fatigue_limit_MPa: float, E_MPa: float, offset: float) -> float:
    """The C for which ``root`` solves eq 14 exactly: C = [n] dZ E Z / (sigma_-1 (Z + c)^2).

    The paper's 71.2765 and 148.0406 both give C = 12.2640 (not 12.2795).
    """
    return permissible_safety * tooth_difference * E_MPa * root / (fatigue_limit_MPa * (root + offset) ** 2)


def circular_spline_teeth(flexspline_teeth: int, tooth_difference: int) -> int:
    """Z_G = Z_R - dZ (seed 003, eq 15)."""
    return flexspline_teeth - tooth_difference
