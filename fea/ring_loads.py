"""The diametral load on a ring (seed 003, Fig. 3) as a pressure over a small arc, and its thin-ring answer.

Seed 003 loads the mid-layer ring by two opposite point forces F. A point force on an elastic body has
an infinite local displacement, so the FEA spreads each force over a small arc of the outer surface
with an elliptical (2D Hertz) profile. The thin-ring answer for exactly that distribution is computed
here too, so that the FEA can be checked against the beam theory of the load it really carries, and
the difference between the arc and the seed's point force is a stated number, not an error.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.special import j1


@dataclass(frozen=True)
class ArcLoad:
    """Two opposite resultant forces ``force_N`` along y, each spread over +/- half_angle_rad.

    The pressure acts normal to the outer surface of radius ``radius_mm`` and width ``width_mm``, centred
    on the minor axis (angles +/- pi/2 from +x): p(psi) = p0 sqrt(1 - ((psi - psi_c)/half_angle)^2).
    """

    force_N: float
    half_angle_rad: float
    radius_mm: float
    width_mm: float

    @property
    def peak_pressure_MPa(self) -> float:
        """p0 such that the y-resultant of each arc is F: F = p0 B R pi J1(theta0) (exact for the profile)."""
        return self.force_N / (np.pi * self.width_mm * self.radius_mm * j1(self.half_angle_rad))

    def pressure_MPa(self, x_mm: np.ndarray, y_mm: np.ndarray) -> np.ndarray:
        """Pressure at surface points (any shape); zero outside both arcs."""
        psi = np.arctan2(y_mm, x_mm)
        p = np.zeros(np.shape(psi))
        for centre in (0.5 * np.pi, -0.5 * np.pi):
            t = (psi - centre) / self.half_angle_rad
            inside = np.abs(t) < 1.0
            p = np.where(inside, self.peak_pressure_MPa * np.sqrt(np.clip(1.0 - t * t, 0.0, None)), p)
        return p

    def scaled(self, factor: float) -> "ArcLoad":
        """The same distribution with the force multiplied (linear problems scale)."""
        return ArcLoad(self.force_N * factor, self.half_angle_rad, self.radius_mm, self.width_mm)


def _arc_density(load: ArcLoad, n: int = 801) -> tuple[np.ndarray, np.ndarray]:
    """Radial force per radian q(psi) on the arc centred at pi/2 (quadrature nodes, values)."""
    t = np.linspace(-1.0, 1.0, n)
    psi = 0.5 * np.pi + load.half_angle_rad * t
    q = load.peak_pressure_MPa * np.sqrt(np.clip(1.0 - t * t, 0.0, None)) * load.width_mm * load.radius_mm
    return psi, q


def thin_ring_moment_Nmm(phi_rad: np.ndarray, load: ArcLoad, r_mm: float) -> np.ndarray:
    """Thin-ring bending moment M(phi), phi from section B (+x axis), positive when it raises the curvature.

    Seed 003, eq 2 for a point force: M = F r (cos(phi)/2 - 1/pi). For the arc, the statics of the quarter
    ring cut at B (hoop force F/2, moment M_B) plus the radial loads between B and phi give
    M(phi) = M_B - (F/2) r (1 - cos phi) + int_{psi<phi} q(psi) r sin(phi - psi) dpsi,
    and M_B follows from zero rotation between B and D (double symmetry): int_0^{pi/2} M dphi = 0.
    Radial forces act along lines through the centre, so where on the thickness they act does not matter.
    """
    phi = np.atleast_1d(np.asarray(phi_rad, dtype=float))
    psi, q = _arc_density(load)
    f = load.force_N

    def m_without_mb(ph):
        arm = np.where(psi[None, :] < ph[:, None], np.sin(ph[:, None] - psi[None, :]), 0.0)
        return -0.5 * f * r_mm * (1.0 - np.cos(ph)) + r_mm * np.trapezoid(q[None, :] * arm, psi, axis=1)

    grid = np.linspace(0.0, 0.5 * np.pi, 2001)
    m_b = -np.trapezoid(m_without_mb(grid), grid) / (0.5 * np.pi)
    return m_b + m_without_mb(phi)


def thin_ring_deflections_mm(load: ArcLoad, r_mm: float, ei_Nmm2: float) -> tuple[float, float]:
    """(delta_CD, delta_AB) of the thin ring under the arc load by the unit-load method (Maxwell-Mohr).

    Seed 003, eqs 3 and 4 are the point-load limits: 0.148778 and 0.136620 F r^3/(E I). The virtual unit
    loads act at the mid-layer points C, D (pair along y) and A, B (pair along x, pulling apart).
    """
    phi = np.linspace(0.0, 0.5 * np.pi, 4001)
    m = thin_ring_moment_Nmm(phi, load, r_mm)
    m_cd = r_mm * (0.5 * np.cos(phi) - 1.0 / np.pi)          # unit compressive pair at C, D
    m_ab = r_mm * (0.5 * np.sin(phi) - 1.0 / np.pi)          # unit compressive pair at A, B (phi from B)
    scale = 4.0 * r_mm / ei_Nmm2
    return scale * np.trapezoid(m * m_cd, phi), -scale * np.trapezoid(m * m_ab, phi)


def point_load_factors() -> dict[str, float]:
    """Seed 003 constants for the point-force ring: eq 3, eq 4 and M at B and D over F r."""
    return {"delta_cd": (np.pi ** 2 - 8.0) / (4.0 * np.pi), "delta_ab": 2.0 / np.pi - 0.5,
            "moment_B": 0.5 - 1.0 / np.pi, "moment_D": -1.0 / np.pi}
