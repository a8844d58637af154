"""The diametral load on a ring (seed 003, Fig. 3) as a pressure over a small arc.

Seed 003 loads the mid-layer ring by two opposite point forces F. A point force on an elastic body has
an infinite local displacement, so the FEA spreads each force over a small arc of the outer surface
with an elliptical (2D Hertz) profile. The thin-ring answer for exactly that distribution is a closed
form and lives in ``analytic/ring_arc_load.py`` (validate grants its gap to the point force as an allowance).
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
