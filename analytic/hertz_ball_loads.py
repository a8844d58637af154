"""Ball-load distributions of a radially loaded ball bearing: Hertz (nonlinear), Hertz with a linear spring in
series, and linear springs, each with zero clearance and the load line through a ball.

Ball i at psi_i (|psi_i| < 90 deg) is pressed by the rings' approach delta_0 cos psi_i. Its load Q_i follows from
its contact law, and equilibrium sum Q_i cos psi_i = F_r fixes delta_0:

- Hertz, Q = K_n delta^(3/2) (rigid rings): Q_i = Q_max cos^(3/2) psi_i, Z Q_max / F_r = Z / sum cos^(5/2) psi_i
  (Stribeck; 4.37 as Z -> infinity);
- Hertz in series with a linear spring of compliance g (a ring that gives under each ball):
  Q_i = K_n (delta_0 cos psi_i - g Q_i)^(3/2), solved ball by ball;
- linear springs, Q = k delta: Q_i = Q_max cos psi_i, Z Q_max / F_r = Z / sum cos^2 psi_i (4 as Z -> infinity).

The linear law is 8.5 % below Hertz's for Z = 24: a check of the ball loads whose tolerance is below that can
tell a Hertz contact from a linear spring.
"""
from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

__all__ = ["loaded_ball_angles_rad", "hertz_load_ratio", "linear_spring_load_ratio", "series_spring_loads_N",
           "series_spring_load_ratio", "ring_compliance_shift"]


def loaded_ball_angles_rad(ball_count: int) -> np.ndarray:
    """Angles of the balls the load line (psi = 0, a ball on it) presses: |psi| < 90 deg."""
    if ball_count < 3:
        raise ValueError(f"a ball bearing needs at least 3 balls, got {ball_count}")
    psi = np.angle(np.exp(2j * np.pi * np.arange(ball_count) / ball_count))
    return np.sort(psi[np.cos(psi) > 1e-12])


def hertz_load_ratio(ball_count: int) -> float:
    """Z Q_max / F_r of Hertz balls between rigid rings (Stribeck's exact sum)."""
    c = np.cos(loaded_ball_angles_rad(ball_count))
    return ball_count / float(np.sum(c ** 2.5))


def linear_spring_load_ratio(ball_count: int) -> float:
    """Z Q_max / F_r of linear springs between rigid rings."""
    c = np.cos(loaded_ball_angles_rad(ball_count))
    return ball_count / float(np.sum(c ** 2))


def _ball_load(approach_mm: float, K_n: float, g_mm_per_N: float) -> float:
    """Q solving Q = K_n (approach - g Q)^(3/2), 0 for no approach."""
    if approach_mm <= 0.0:
        return 0.0
    top = K_n * approach_mm ** 1.5
    if g_mm_per_N == 0.0:
        return top
    return brentq(lambda q: q - K_n * max(approach_mm - g_mm_per_N * q, 0.0) ** 1.5, 0.0, top, xtol=1e-14 * top,
                  rtol=1e-14)


def series_spring_loads_N(force_N: float, ball_count: int, K_n: float, g_mm_per_N: float) -> np.ndarray:
    """Q_i of Hertz balls (Q = K_n delta^1.5) each in series with a linear spring of compliance g."""
    c = np.cos(loaded_ball_angles_rad(ball_count))

    def loads(d0: float) -> np.ndarray:
        return np.array([_ball_load(d0 * ci, K_n, g_mm_per_N) for ci in c])

    d_rigid = (force_N / (K_n * float(np.sum(c ** 2.5)))) ** (2.0 / 3.0)
    hi = d_rigid + g_mm_per_N * force_N + 1e-12
    d0 = brentq(lambda d: float(loads(d) @ c) - force_N, 0.0, hi, xtol=1e-15 * hi, rtol=1e-14)
    return loads(d0)


def series_spring_load_ratio(force_N: float, ball_count: int, K_n: float, g_mm_per_N: float) -> float:
    """Z Q_max / F_r of ``series_spring_loads_N``."""
    return ball_count * float(series_spring_loads_N(force_N, ball_count, K_n, g_mm_per_N).max()) / force_N


def ring_compliance_shift(force_N: float, ball_count: int, K_n: float, g_mm_per_N: float) -> float:
    """|Z Q_max / F_r with a ring compliance g under each ball - rigid rings| / rigid rings: how far a ring that
    gives under the balls can move the distribution off Stribeck's (towards the linear law)."""
    rigid = hertz_load_ratio(ball_count)
    return abs(series_spring_load_ratio(force_N, ball_count, K_n, g_mm_per_N) / rigid - 1.0)
