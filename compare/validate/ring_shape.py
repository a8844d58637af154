"""The deformed mid-layer of a thin ring under two diametral forces, as a Fourier series.

Seed 003 gives only the two diameter changes (eqs 3 and 4); the report draws the whole analytic
shape against the FEA mid-layer, so the series they both come from is evaluated here.
"""
from __future__ import annotations

import numpy as np


def thin_ring_shape(theta_rad, terms: int = 400) -> np.ndarray:
    """Radial displacement of an inextensible thin ring, normalised to -1 at the load points.

    Two opposite point loads at theta = 0 and pi expand as q(theta) = P/(pi R) (1 + 2 sum cos n theta),
    n even; each harmonic bends the ring by w_n = q_n R^4 / (E I (n^2 - 1)^2), so

        w(theta) = -(2 P R^3 / (pi E I)) sum_{n = 2, 4, ...} cos(n theta) / (n^2 - 1)^2.

    At theta = 0 the sum is (pi^2 - 8)/16, which gives seed 003's eq 3 (delta_CD = 2 |w(0)| =
    0.148778 P R^3/EI); at theta = pi/2 it gives eq 4 (delta_AB = 0.136620 P R^3/EI), i.e. a shape
    value of +0.918 there: the ring is not an ellipse (audit item 5).
    """
    theta = np.asarray(theta_rad, dtype=float)
    n = np.arange(2, 2 * terms + 1, 2, dtype=float)
    weights = 1.0 / (n ** 2 - 1.0) ** 2
    series = np.cos(np.multiply.outer(theta, n)) @ weights
    return -series / weights.sum()


def radial_displacement_mm(theta_rad, delta_cd_mm: float, load_angle_rad: float = 0.0) -> np.ndarray:
    """u_r(theta) of the thin ring whose loaded diameter shortens by ``delta_cd_mm``."""
    return 0.5 * delta_cd_mm * thin_ring_shape(np.asarray(theta_rad) - load_angle_rad)
