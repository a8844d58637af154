"""The wave generator's flexible ball bearing as a radial spring from its own geometry (Hertz, Palmgren).

A ball pressed between its two raceways by the load Q approaches them by (Palmgren 1959, "Ball and Roller
Bearing Engineering", 3rd ed., eq. for point contact of steel balls; Harris & Kotzalas, "Rolling Bearing
Analysis", 5th ed., 2006, the ball bearing's load-deflection constant)

    delta = 4.36e-4 Q^(2/3) / D_w^(1/3)          (mm, N, mm; both raceways, steel on steel)

so its tangent stiffness dQ/d(delta) = 1.5 Q / delta grows as Q^(1/3): the bearing stiffens with the load, one
source of K1 < K3. Under the flexspline's rim, balls a pitch s apart are a foundation of modulus k_ball / s per
unit rim length; the rim and the outer ring bend over it as a beam on an elastic foundation (Hetenyi), so a radial
load R on the rim presses the nearest ball with Q = R beta s / 2 (the foundation's peak pressure R beta / 2 times
the pitch; one ball at most carries R). A flank's radial push F sin(alpha) moves the tooth inward and opens the
flank circumferentially by tan(alpha) per unit travel: the output turns by delta tan(alpha) / r_p.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["PALMGREN_SOURCE", "ball_contact_deflection_mm", "ball_contact_stiffness_N_per_mm", "BallBearing",
           "peak_ball_load_N", "linearised_foundation", "hertz_remainder_twist_rad"]

PALMGREN_SOURCE = ("Palmgren 1959 / Harris & Kotzalas 2006: delta = 4.36e-4 Q^(2/3) D_w^(-1/3) mm "
                   "(ball between both raceways, steel)")
_PALMGREN = 4.36e-4      # mm N^(-2/3) mm^(1/3)


def ball_contact_deflection_mm(Q_N, ball_diameter_mm: float):
    """Approach of both raceways over one ball under the load Q (Palmgren)."""
    return _PALMGREN * np.power(np.maximum(Q_N, 0.0), 2.0 / 3.0) / ball_diameter_mm ** (1.0 / 3.0)


def ball_contact_stiffness_N_per_mm(Q_N, ball_diameter_mm: float):
    """Tangent stiffness dQ/d(delta) = 1.5 Q^(1/3) D_w^(1/3) / 4.36e-4 (zero at zero load: no preload)."""
    return 1.5 * np.power(np.maximum(Q_N, 0.0), 1.0 / 3.0) * ball_diameter_mm ** (1.0 / 3.0) / _PALMGREN


@dataclass(frozen=True)
class BallBearing:
    """The WG bearing's balls under the rim (mm)."""

    ball_diameter_mm: float
    ball_count: int
    pitch_diameter_mm: float       # of the ball set

    @property
    def ball_pitch_mm(self) -> float:
        return math.pi * self.pitch_diameter_mm / self.ball_count


def peak_ball_load_N(radial_load_N: float, beta_per_mm: float, ball_pitch_mm: float) -> float:
    """The most loaded ball under a radial load R on a rim bending over the balls (Hetenyi's peak pressure)."""
    return radial_load_N * min(1.0, 0.5 * beta_per_mm * ball_pitch_mm)


def linearised_foundation(bearing: BallBearing, radial_load_N: float, EI_Nmm2: float,
                          lumped_N_per_mm2: float | None = None, iterations: int = 30) -> tuple[float, float]:
    """(foundation modulus N/mm per mm of rim, the peak ball load N) with the balls' tangent stiffness at the
    ball load that ``radial_load_N`` makes, in series with an optional lumped foundation (fixed point in beta)."""
    s = bearing.ball_pitch_mm
    Q = radial_load_N
    k = 0.0
    for _ in range(iterations):
        k_ball = ball_contact_stiffness_N_per_mm(max(Q, 1e-9), bearing.ball_diameter_mm) / s
        k = k_ball if lumped_N_per_mm2 is None else 1.0 / (1.0 / k_ball + 1.0 / lumped_N_per_mm2)
        beta = (k / (4.0 * EI_Nmm2)) ** 0.25
        Q_new = peak_ball_load_N(radial_load_N, beta, s)
        if abs(Q_new - Q) <= 1e-9 * max(Q, 1e-12):
            break
        Q = Q_new
    return float(k), float(Q)


def hertz_remainder_twist_rad(torque_Nmm, *, bearing: BallBearing, Q_at_reference_N: float,
                              reference_torque_Nmm: float, pitch_radius_mm: float, alpha_deg: float):
    """The balls' twist beyond their tangent line at the reference torque (which the linear mesh model holds):
    sign(T) tan(alpha)/r_p [delta(Q(|T|)) - Q(|T|) / k_t(Q_ref)], Q proportional to |T| (the zone's radial load
    per lobe is T tan(alpha) / (2 r_p)). Odd in T, zero slope at the reference torque, steep near zero."""
    T = np.asarray(torque_Nmm, float)
    Q = Q_at_reference_N * np.abs(T) / reference_torque_Nmm
    D = bearing.ball_diameter_mm
    extra = ball_contact_deflection_mm(Q, D) - Q / ball_contact_stiffness_N_per_mm(Q_at_reference_N, D)
    return np.sign(T) * math.tan(math.radians(alpha_deg)) / pitch_radius_mm * extra
