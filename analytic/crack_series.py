"""Geometry factors of a circumferentially cracked round bar: seed 000's M_P and M_M.

x = d_e/d_s (net over gross diameter), K = sigma_net sqrt(pi a) F(x) with
sigma_net = 4P/(pi d_e^2) (tension) or 16T/(pi d_e^3) (torsion). Solid-bar solutions
(Tada, Paris & Irwin, The Stress Analysis of Cracks Handbook; coefficients as in the audit):

    F1 (tension) = 1/2 sqrt(x) (1 + x/2 + 3x^2/8 - 0.363 x^3 + 0.731 x^4)
    F3 (torsion) = 3/8 sqrt(x) (1 + x/2 + 3x^2/8 + 5x^3/16 + 35x^4/128 + 0.208 x^5)

Shallow-crack limit x -> 1 gives the edge-crack values F1 = 1.1215 and F3 = 1.0009.
"""
from __future__ import annotations

import math

from strainwave.analytic.variant import Variant

# Coefficients of x^(1/2), x^(3/2), ... as printed in seed 000.
M_P_PUBLISHED = (0.5, 0.25, 0.188, 0.182, 0.166)
M_M_PUBLISHED = (0.376, 0.188, 0.141, 0.117, 0.102, 0.078)


def m_p_corrected_coefficients() -> tuple[float, ...]:
    """(1/2)(1, 1/2, 3/8, -0.363, 0.731) = 0.5, 0.25, 0.1875, -0.1815, 0.3655 (Tada F1)."""
    return tuple(0.5 * c for c in (1.0, 0.5, 3.0 / 8.0, -0.363, 0.731))


def m_m_corrected_coefficients() -> tuple[float, ...]:
    """(3/8)(1, 1/2, 3/8, 5/16, 35/128, 0.208) (Tada F3); the seed's M_M matches except 0.376 -> 0.375."""
    return tuple(0.375 * c for c in (1.0, 0.5, 3.0 / 8.0, 5.0 / 16.0, 35.0 / 128.0, 0.208))


def _series(x: float, coefficients: tuple[float, ...]) -> float:
    return sum(c * x ** (0.5 + k) for k, c in enumerate(coefficients))


def m_p(x: float, variant: Variant = Variant.CORRECTED) -> float:
    """Tension factor M_P(d_e/d_s) (seed 000, K_I of the output shaft).

    PUBLISHED: 0.5 x^.5 + 0.25 x^1.5 + 0.188 x^2.5 + 0.182 x^3.5 + 0.166 x^4.5
    (M_P(1) = 1.286, fails the edge-crack limit 1.12). CORRECTED: Tada F1.
    """
    return _series(x, M_P_PUBLISHED if variant is Variant.PUBLISHED else m_p_corrected_coefficients())


def m_m(x: float, variant: Variant = Variant.CORRECTED) -> float:
    """Torsion factor M_M(d_e/d_s) (seed 000, K_III of the output shaft).

    PUBLISHED: 0.376, 0.188, 0.141, 0.117, 0.102, 0.078 on x^(1/2 .. 11/2). CORRECTED: Tada F3.
    """
    return _series(x, M_M_PUBLISHED if variant is Variant.PUBLISHED else m_m_corrected_coefficients())


def edge_crack_limits() -> tuple[float, float]:
    """(F1(1), F3(1)) of the corrected series: 1.1215 and 1.0009 (edge-crack values 1.12 and 1.0)."""
    return m_p(1.0), m_m(1.0)


def deep_crack_torsion_factor() -> float:
    """3/8: K_III -> (3/8) tau_net sqrt(pi b) as x -> 0 (leading term of F3; audit's deep-crack check)."""
    return m_m_corrected_coefficients()[0]


def hertz_mode_i_constant() -> float:
    """(3 * 1.95 / (4 pi))^2 = 0.216717, printed 0.217 in seed 000's delta u_H.

    From K_I = 1.95 sigma sqrt(a/Q), sigma = beta sigma_max/2, sigma_max = 3F_r/(2 pi a' b').
    """
    return (3.0 * 1.95 / (4.0 * math.pi)) ** 2
