"""Hertz line contact of two long elastic cylinders (plane strain): Johnson, Contact Mechanics (1985), sec. 4.2,
eqs. (4.43)-(4.45). The closed form of ``fea/flank_hertz``'s problem, written from the book, not from the FE.

    1/R* = 1/R1 + 1/R2   (a concave surface counts negative: an internal gear's flank)
    1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2
    b = sqrt(4 P R* / (pi E*)),  p0 = 2 P / (pi b) = sqrt(P E* / (pi R*)),  p(x) = p0 sqrt(1 - x^2 / b^2)

P is the load per unit length (N/mm). Valid where b is small against R1, |R2| and the bodies' extent (the
half-space), the surfaces are smooth and the relative curvature is constant across the contact.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["LineContact", "line_contact", "load_for_half_width", "relative_radius_mm", "contact_modulus_MPa"]


@dataclass(frozen=True)
class LineContact:
    load_N_per_mm: float
    relative_radius_mm: float
    contact_modulus_MPa: float
    half_width_mm: float
    peak_pressure_MPa: float


def relative_radius_mm(r1_mm: float, r2_mm: float) -> float:
    """R* of two signed radii (concave negative); raises when the pair is conformal or not convex overall."""
    k = 1.0 / r1_mm + 1.0 / r2_mm
    if not k > 0.0:
        raise ValueError(f"radii {r1_mm:g} and {r2_mm:g} mm: the surfaces conform or separate (1/R* = {k:g})")
    return 1.0 / k


def contact_modulus_MPa(E1_MPa: float, nu1: float, E2_MPa: float | None = None, nu2: float | None = None) -> float:
    """E* of the pair (the second body defaults to the first's material)."""
    E2_MPa, nu2 = (E1_MPa if E2_MPa is None else E2_MPa), (nu1 if nu2 is None else nu2)
    return 1.0 / ((1.0 - nu1 ** 2) / E1_MPa + (1.0 - nu2 ** 2) / E2_MPa)


def line_contact(load_N_per_mm: float, r_star_mm: float, e_star_MPa: float) -> LineContact:
    b = math.sqrt(4.0 * load_N_per_mm * r_star_mm / (math.pi * e_star_MPa))
    return LineContact(load_N_per_mm, r_star_mm, e_star_MPa, b, 2.0 * load_N_per_mm / (math.pi * b))


def load_for_half_width(b_mm: float, r_star_mm: float, e_star_MPa: float) -> float:
    """The line load whose Hertz half-width is ``b_mm`` (the inverse of b(P))."""
    return math.pi * e_star_MPa * b_mm ** 2 / (4.0 * r_star_mm)
