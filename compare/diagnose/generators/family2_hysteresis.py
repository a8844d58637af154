"""Family-2 friction laws (independent of the catalogue and of family 1): twist of a joint under a
prescribed torque history T (N*mm, acquisition order). Each returns the joint's whole twist (rad),
starting from the virgin state; the generator removes the secant compliance and scales.

- ``bouc_wen_twist``: the displacement-driven Bouc-Wen joint  T = k_e phi + T_f z (z dimensionless),
  phi_y dz/dphi = A - |z|^n (beta sgn(dphi z) + gamma), inverted for a torque-controlled test: the
  tangent stiffness k_e + (T_f/phi_y) phi_y dz/dphi > 0 when beta >= |gamma|, so dphi has the sign of dT.
- ``play_sum_twist``: a Prandtl-Ishlinskii sum of play operators, i.e. a series chain of Jenkins
  elements (a spring in parallel with a Coulomb slider of threshold r_i): the element moves only once
  the torque has come back more than r_i from it.
- ``preisach_twist``: classical Preisach model, relay hysterons (alpha >= beta) on a grid with a
  factorised density (Gaussian in the bias, log-normal in the coercive half-width), demagnetised start.
"""
from __future__ import annotations

import math

import numpy as np


def _bw_slope(z: float, direction: float, A: float, beta: float, gamma: float, n: float) -> float:
    """phi_y dz/dphi for a motion of sign ``direction``."""
    return A - abs(z) ** n * (beta * math.copysign(1.0, direction * z) + gamma) if z != 0.0 else A


def bouc_wen_twist(T: np.ndarray, k_e: float, friction_Nmm: float, yield_twist_rad: float, *, A: float = 1.0,
                   beta: float = 0.6, gamma: float = 0.2, n: float = 1.0, max_step: float | None = None) -> np.ndarray:
    """Twist (rad) of a Bouc-Wen joint under the torque history T; midpoint integration in torque.

    The hysteretic torque saturates at friction_Nmm (A/(beta + gamma))^(1/n) while sliding; right after a
    reversal the joint is stiffer by friction_Nmm A / yield_twist_rad (pre-slip).
    """
    if not (k_e > 0 and friction_Nmm > 0 and yield_twist_rad > 0 and A > 0 and beta >= abs(gamma)
            and beta + gamma > 0 and n >= 1.0):
        raise ValueError("Bouc-Wen needs k_e, friction, yield twist, A > 0, beta >= |gamma|, beta + gamma > 0, n >= 1")
    k_h = friction_Nmm / yield_twist_rad
    T = np.asarray(T, dtype=float)
    z_sat = (A / (beta + gamma)) ** (1.0 / n)
    h = max_step if max_step is not None else max(float(np.ptp(T)), 1e-300) / 2000.0
    phi, z = 0.0, 0.0
    out = np.empty(len(T))
    out[0] = 0.0
    for k in range(1, len(T)):
        dT_total = T[k] - T[k - 1]
        m = max(1, int(math.ceil(abs(dT_total) / h)))
        dT = dT_total / m
        for _ in range(m):
            s1 = _bw_slope(z, dT, A, beta, gamma, n)
            dphi1 = dT / (k_e + k_h * s1)
            z_mid = z + 0.5 * s1 * dphi1 / yield_twist_rad
            s2 = _bw_slope(z_mid, dT, A, beta, gamma, n)
            dphi = dT / (k_e + k_h * s2)
            phi += dphi
            z = min(max(z + s2 * dphi / yield_twist_rad, -z_sat), z_sat)    # the exact solution never passes saturation
        out[k] = phi
    return out


def play_sum_twist(T: np.ndarray, thresholds_Nmm: np.ndarray, compliances: np.ndarray) -> np.ndarray:
    """Twist (rad) of a series chain of Jenkins elements: sum_i c_i play_{r_i}(T), virgin elements at 0."""
    r = np.asarray(thresholds_Nmm, dtype=float)
    c = np.asarray(compliances, dtype=float)
    if r.shape != c.shape or np.any(r < 0) or np.any(c < 0):
        raise ValueError("thresholds and compliances must be non-negative arrays of one shape")
    p = np.zeros_like(r)
    out = np.empty(len(T))
    for k, x in enumerate(np.asarray(T, dtype=float)):
        p = np.maximum(x - r, np.minimum(x + r, p))
        out[k] = c @ p
    return out


def preisach_twist(T: np.ndarray, scale_Nmm: float, *, coercive: float = 0.3, coercive_spread: float = 0.5,
                   bias_spread: float = 0.3, levels: int = 120) -> np.ndarray:
    """Sum of relay hysterons (+1 once T >= alpha, -1 once T <= beta), in units of the total weight.

    Thresholds on a grid over +/- 1.3 ``scale_Nmm`` (120 levels: the law is a smooth density; on a grid the
    twist climbs in steps, which a constant loading rate turns into a line in time at the grid's period. On
    40 levels that staircase was 1.1 % of the loop's range, and diagnose rightly read a clean 10 sigma loop as
    "periodic in time with period 6.03 samples"; at 120 levels it is a third of that);
    density exp(-b^2 / 2 s_b^2) * lognormal(h) with
    bias b = (alpha + beta)/2, half-width h = (alpha - beta)/2 (both relative to the scale).
    """
    g = np.linspace(-1.3, 1.3, levels)
    a, b = np.meshgrid(g, g, indexing="ij")
    keep = a > b
    alpha, beta = a[keep] * scale_Nmm, b[keep] * scale_Nmm
    bias, half = 0.5 * (a[keep] + b[keep]), 0.5 * (a[keep] - b[keep])
    mu = np.exp(-0.5 * (bias / bias_spread) ** 2) * np.exp(-0.5 * (np.log(half / coercive) / coercive_spread) ** 2) / half
    mu /= mu.sum()
    state = np.where(alpha + beta < 0.0, 1.0, -1.0)     # demagnetised: staircase along alpha = -beta
    out = np.empty(len(T))
    for k, x in enumerate(np.asarray(T, dtype=float)):
        state = np.where(x >= alpha, 1.0, np.where(x <= beta, -1.0, state))
        out[k] = mu @ state
    return out


__all__ = ["bouc_wen_twist", "play_sum_twist", "preisach_twist"]
