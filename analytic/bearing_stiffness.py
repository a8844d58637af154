"""What the seed's own contact ellipse says about the wave generator's radial stiffness K_G0 (seed 000).

Seed 000 never gives K_G0; its table implies 6.303e4 N/mm (audit 13). A ball bearing's radial compliance is
its rings' bending plus the ball-race Hertz contacts (Palmgren; Harris & Kotzalas, Rolling Bearing
Analysis, ch. 7: deflection of each ball from Hertz theory, summed over the loaded balls). The seed gives no
ball count, ball diameter or race conformity, so a full bearing model cannot be built from it; it does give
the contact ellipse (a', b') at the race, which fixes the Hertz contact stiffness of one ball:

    approach  delta = 3 P K(e) / (2 pi a E*)       (Hertz; Johnson, Contact Mechanics, 1985, ch. 3-4, the
                                                    elliptical contact: delta = p0 b K(e)/E*, p0 = 3P/(2 pi a b))
    a, b ~ P^(1/3)  =>  tangent stiffness  k = dP/d(delta) = 3P/(2 delta) = pi a E* / K(e)

with a the semi-major axis, e^2 = 1 - (b/a)^2, K the complete elliptic integral of the first kind and
E* = E / (2 (1 - nu^2)) for two steel bodies. Circle: k = 2 a E* (Johnson). One ball presses on both races
(two contacts in series); more loaded balls only stiffen the bearing. So the bearing (rings rigid) cannot be
more compliant than one ball's two contacts: K_G0 >= pi a E*/(2 K(e)) unless the supports add compliance.
"""
from __future__ import annotations

import math

__all__ = ["effective_modulus_MPa", "hertz_contact_stiffness_N_per_mm", "ball_pair_stiffness_N_per_mm",
           "implied_ball_pairs"]


def effective_modulus_MPa(E_MPa: float, poisson_ratio: float) -> float:
    """E* = E / (2 (1 - nu^2)): two bodies of the same steel in contact (Hertz)."""
    return E_MPa / (2.0 * (1.0 - poisson_ratio ** 2))


def hertz_contact_stiffness_N_per_mm(a_mm: float, b_mm: float, E_MPa: float, poisson_ratio: float) -> float:
    """Tangent stiffness pi a E*/K(e) of an elliptical Hertz contact with semi-axes a >= b (module docstring)."""
    from scipy.special import ellipk

    a, b = max(a_mm, b_mm), min(a_mm, b_mm)
    if not (a > 0 and b > 0):
        raise ValueError(f"contact semi-axes must be > 0, got {a_mm!r}, {b_mm!r}")
    return math.pi * a * effective_modulus_MPa(E_MPa, poisson_ratio) / float(ellipk(1.0 - (b / a) ** 2))


def ball_pair_stiffness_N_per_mm(a_mm: float, b_mm: float, E_MPa: float, poisson_ratio: float) -> float:
    """One ball between inner and outer race, both contacts of the same ellipse, in series."""
    return 0.5 * hertz_contact_stiffness_N_per_mm(a_mm, b_mm, E_MPa, poisson_ratio)


def implied_ball_pairs(K_G0_N_per_mm: float, a_mm: float, b_mm: float, E_MPa: float, poisson_ratio: float) -> float:
    """How many such balls in parallel K_G0 would amount to (rings and supports rigid): K_G0 / k_pair.

    Below 1 means K_G0 is softer than a single loaded ball's contacts: the seed's K_G0 then needs a
    compliance the seed names nowhere (cam, supports or rings several times softer than the contacts)."""
    return K_G0_N_per_mm / ball_pair_stiffness_N_per_mm(a_mm, b_mm, E_MPa, poisson_ratio)
