"""ISO 6336-1's single stiffness c' of one spur tooth pair (method B), the closed form the tooth-mesh FE's
solid-body tooth pair stands beside (check ``mesh.pair_stiffness``).

    q' = C1 + C2/zn1 + C3/zn2 + C4 x1 + C5 x1/zn1 + C6 x2 + C7 x2/zn2 + C8 x1^2 + C9 x2^2   (mm um / N)
    c'_th = 1/q'  (N/(mm um)),   c' = c'_th C_M C_R C_B cos(beta) (E / E_steel)

C1..C9 = 0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182 (ISO 6336-1
eq. for q', solid spur gears, Schmidt's/Weber-Banaschek's theory fitted); C_B = [1 + 0.5(1.2 - h_fP/m)]
[1 - 0.02(20 deg - alpha_P)] (basic-rack factor); C_R = 1 (solid bodies); C_M = 0.8 is ISO's correction of
the theoretical to the measured value: the FE is the theoretical problem, so it is left out here. An internal
gear is taken with zn2 = infinity and its profile shift x2 with the sign that keeps x1 + x2 in ISO's range
-0.5 <= x1 + x2 <= 2 (the strain-wave pair's x2 = -x1: the CS's space is the cup's tooth, shifted alike).
"""
from __future__ import annotations

import math

__all__ = ["single_stiffness_N_per_mm_um", "E_STEEL_MPA", "C"]

C = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)
E_STEEL_MPA = 2.06e5          # ISO's reference steel


def single_stiffness_N_per_mm_um(z1: float, x1: float, z2: float | None, x2: float, *, dedendum_coef: float = 1.25,
                                 pressure_angle_deg: float = 20.0, youngs_modulus_MPa: float = E_STEEL_MPA) -> float:
    """c'_th C_B (E/E_steel) of the pair; ``z2`` None: an internal gear (zn2 = infinity)."""
    c1, c2, c3, c4, c5, c6, c7, c8, c9 = C
    inv2 = 0.0 if z2 is None else 1.0 / z2
    q = (c1 + c2 / z1 + c3 * inv2 + c4 * x1 + c5 * x1 / z1 + c6 * x2 + c7 * x2 * inv2 + c8 * x1 ** 2
         + c9 * x2 ** 2)
    cb = (1.0 + 0.5 * (1.2 - dedendum_coef)) * (1.0 - 0.02 * (20.0 - pressure_angle_deg))
    return cb / q * youngs_modulus_MPa / E_STEEL_MPA


def in_range(x1: float, x2: float) -> bool:
    return -0.5 <= x1 + x2 <= 2.0 and x1 >= x2 and not math.isnan(x1 + x2)
