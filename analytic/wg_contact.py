"""The wave generator bearing as built: Hertz point contact of a ball in its grooves, the ISO 281 rating and
L10 life, the ISO 76 static contact check, and the bending of the flexible rings.

Hertz point contact (Harris & Kotzalas, Rolling Bearing Analysis, ch. 6; the elliptic integrals by Hamrock
& Brewe's approximations, J. Lubr. Technol. 105 (1983) 171, within 3 % of the exact ones for 1 <= Ry/Rx <= 100):
the ball (diameter D_w) in a groove of radius f D_w on a race of radius r_race has the effective radii
1/Rx = 2/D_w +- 1/r_race (rolling direction; + the inner race, convex, - the outer race, concave) and
1/Ry = 2/D_w - 1/(f D_w) (across the groove); with R = (1/Rx + 1/Ry)^-1, E' = E/(1 - nu^2) (two steels),
k = a/b = 1.0339 (Ry/Rx)^0.636, E_k = 1.0003 + 0.5968 Rx/Ry:

    a = (6 k^2 E_k Q R / (pi E'))^(1/3)  (across),   b = (6 E_k Q R / (pi k E'))^(1/3)  (rolling),
    p0 = 3 Q / (2 pi a b).

A sphere on a flat (Rx = Ry) gives k = 1.03, E_k = 1.60 against the exact 1 and pi/2: the approximation's
3 % on a; the deep groove (Ry/Rx ~ 10..30) is the range it was fitted on.

ISO 281:2007, radial deep-groove ball bearing: C_r = b_m f_c (i cos alpha)^0.7 Z^(2/3) D_w^1.8 (D_w <= 25.4 mm),
b_m = 1.3, f_c from table 2 by D_w cos alpha / D_pw; L10 = (C_r/P)^3 million revolutions of one ring against
the other; P = F_r (a radial load). Left out, and said so where it is reported: the flexible rings'
elliptical shape, which loads the balls unlike Stribeck's rigid rings (a life factor the standard does not
give), and the a_ISO life modification factor (lubrication, contamination): L10 is the basic rating life.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["HertzContact", "hertz_point_contact", "hertz_from_radii", "contact_spring_constant", "ball_spring_constant", "iso281_fc", "dynamic_load_rating_N", "l10_hours",
           "outer_ring_bending_MPa", "ISO281_FC_TABLE"]

# ISO 281:2007 table 2, single-row radial deep-groove ball bearings: (D_w cos alpha / D_pw, f_c), N and mm
ISO281_FC_TABLE = ((0.01, 29.1), (0.02, 35.8), (0.03, 40.3), (0.04, 43.8), (0.05, 46.7), (0.06, 49.1),
                   (0.07, 51.1), (0.08, 52.8), (0.09, 54.3), (0.10, 55.5), (0.12, 57.5), (0.14, 58.8),
                   (0.16, 59.6), (0.18, 59.9), (0.20, 59.9), (0.22, 59.6), (0.24, 59.0), (0.26, 58.2),
                   (0.28, 57.1), (0.30, 56.0), (0.32, 54.6), (0.34, 53.2), (0.36, 51.7), (0.38, 50.0),
                   (0.40, 48.4))
B_M_RADIAL_BALL = 1.3   # ISO 281:2007 table 1: radial ball bearings (deep groove)


@dataclass(frozen=True)
class HertzContact:
    load_N: float
    a_mm: float           # semi-axis across the groove (the major one)
    b_mm: float           # semi-axis in the rolling direction
    p0_MPa: float         # peak pressure
    Rx_mm: float
    Ry_mm: float

    def to_dict(self) -> dict:
        return dict(self.__dict__)


def hertz_point_contact(load_N: float, ball_diameter_mm: float, groove_radius_ratio: float, race_radius_mm: float,
                        E_MPa: float, nu: float, *, inner: bool = True) -> HertzContact:
    """Hertz contact of one ball on the inner (convex) or outer (concave) race (module docstring)."""
    if load_N < 0 or ball_diameter_mm <= 0 or race_radius_mm <= 0 or not 0.5 < groove_radius_ratio < 1.0:
        raise ValueError("load >= 0, ball and race > 0 and 0.5 < f < 1 needed")
    inv_rx = 2.0 / ball_diameter_mm + (1.0 if inner else -1.0) / race_radius_mm
    inv_ry = 2.0 / ball_diameter_mm - 1.0 / (groove_radius_ratio * ball_diameter_mm)
    return hertz_from_radii(load_N, 1.0 / inv_rx, 1.0 / inv_ry, E_MPa, nu)


def hertz_from_radii(load_N: float, Rx: float, Ry: float, E_MPa: float, nu: float) -> HertzContact:
    """Hertz point contact of two equal steels with effective radii Rx <= Ry (Hamrock & Brewe's k, E_k)."""
    R = 1.0 / (1.0 / Rx + 1.0 / Ry)
    E_eff = E_MPa / (1.0 - nu ** 2)
    k = 1.0339 * (Ry / Rx) ** 0.636
    e_k = 1.0003 + 0.5968 * Rx / Ry
    a = (6.0 * k * k * e_k * load_N * R / (math.pi * E_eff)) ** (1.0 / 3.0)
    b = (6.0 * e_k * load_N * R / (math.pi * k * E_eff)) ** (1.0 / 3.0)
    p0 = 0.0 if load_N == 0 else 3.0 * load_N / (2.0 * math.pi * a * b)
    return HertzContact(load_N, a, b, p0, Rx, Ry)


def contact_spring_constant(Rx: float, Ry: float, E_MPa: float, nu: float) -> float:
    """K of Q = K delta^(3/2) for one Hertz point contact (Hamrock & Brewe: delta = F_k [9/(2 E_k R) (Q/(pi k E'))^2]^(1/3),
    F_k = 1.5277 + 0.6023 ln(Ry/Rx)): K = pi k E' sqrt(2 E_k R / 9) / F_k^(3/2)."""
    R = 1.0 / (1.0 / Rx + 1.0 / Ry)
    k = 1.0339 * (Ry / Rx) ** 0.636
    e_k = 1.0003 + 0.5968 * Rx / Ry
    f_k = 1.5277 + 0.6023 * math.log(Ry / Rx)
    return math.pi * k * E_MPa / (1.0 - nu ** 2) * math.sqrt(2.0 * e_k * R / 9.0) / f_k ** 1.5


def ball_spring_constant(ball_diameter_mm: float, groove_radius_ratio: float, race_radius_mm: float, E_MPa: float,
                         nu: float) -> float:
    """K_n of one ball between the inner race (radius ``race_radius_mm``) and the outer race one ball further out,
    both contacts in series: K_n = (K_i^(-2/3) + K_o^(-2/3))^(-3/2) (Harris & Kotzalas, ch. 7)."""
    out = []
    for inner, r in ((True, race_radius_mm), (False, race_radius_mm + ball_diameter_mm)):
        h = hertz_point_contact(1.0, ball_diameter_mm, groove_radius_ratio, r, E_MPa, nu, inner=inner)
        out.append(contact_spring_constant(h.Rx_mm, h.Ry_mm, E_MPa, nu))
    return (out[0] ** (-2.0 / 3.0) + out[1] ** (-2.0 / 3.0)) ** -1.5


def iso281_fc(dw_over_dpw: float) -> float:
    """f_c of ISO 281 table 2 (deep-groove ball bearings), linear between the table's rows."""
    x, y = zip(*ISO281_FC_TABLE)
    if not x[0] <= dw_over_dpw <= x[-1]:
        raise ValueError(f"D_w/D_pw = {dw_over_dpw:.3g} is outside ISO 281 table 2 ({x[0]}..{x[-1]})")
    return float(np.interp(dw_over_dpw, x, y))


def dynamic_load_rating_N(ball_count: int, ball_diameter_mm: float, pitch_diameter_mm: float) -> float:
    """C_r = b_m f_c Z^(2/3) D_w^1.8 (ISO 281:2007 eq. 7, one row, alpha = 0, D_w <= 25.4 mm)."""
    if ball_diameter_mm > 25.4:
        raise ValueError("ISO 281's D_w^1.8 form holds for D_w <= 25.4 mm")
    fc = iso281_fc(ball_diameter_mm / pitch_diameter_mm)
    return B_M_RADIAL_BALL * fc * ball_count ** (2.0 / 3.0) * ball_diameter_mm ** 1.8


def l10_hours(rating_N: float, load_N: float, relative_speed_rpm: float) -> float:
    """L10h = 10^6 (C/P)^3 / (60 n): the basic rating life in hours (ISO 281:2007 eqs. 14, 16)."""
    if load_N <= 0:
        return math.inf
    return 1e6 * (rating_N / load_N) ** 3 / (60.0 * relative_speed_rpm)


def outer_ring_bending_MPa(E_MPa: float, thickness_mm: float, mean_radius_mm: float, w0_mm: float,
                           wave_number: int = 2) -> float:
    """(n^2 - 1) E t w0 / (2 r^2): the outer fibre of a thin ring forced into w0 cos n phi (3 E t w0 / 2 r^2 for
    the dual wave); the flexible outer ring follows the flexspline's bore, so it carries this, reversed as
    the wave passes (analytic/wg_bearing.py derives the same curvature change for the inner ring)."""
    return (wave_number ** 2 - 1) * E_MPa * thickness_mm * w0_mm / (2.0 * mean_radius_mm ** 2)
