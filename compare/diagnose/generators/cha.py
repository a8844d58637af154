"""Real data: Harmonic Drive's published CHA stiffness table turned into recordings.

The table (strainwave/data/cha_torsional_stiffness.csv; CHA manual 1018854) gives per size and ratio
T1, T2 (N*m) and K1, K2, K3 (1e3 N*m/rad). The catalogue's twist curve, odd in the torque:
    phi = T/K1 (T <= T1);  T1/K1 + (T - T1)/K2 (T1 < T <= T2);  T1/K1 + (T2 - T1)/K2 + (T - T2)/K3.
Hysteresis loss is specified < 1 arcmin for ratios >= 50 and < 3 arcmin at ratio 30.

A recording built here cycles the torque to +/- 1.5 T2 (so all three slopes are seen) with an
encoder-limited twist channel; the header carries the linear model the diagnosis compares against:
stiffness K1 (what a linear simulation of the gear gives) with baseline_uncertainty 0.3 (a whole gear),
so the stiffness prior does not pin K1 and the fitted K1, K2, K3 come from the data.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from strainwave.compare.diagnose.generators.hifi_torsion import maxwell_slip_twist
from strainwave.compare.diagnose.recording import RecordingKind, format_recording

ARCMIN = math.pi / (180.0 * 60.0)
ENCODER_STEP_RAD = 2.0 * math.pi / 2 ** 20     # a 20-bit output encoder


@dataclass(frozen=True)
class ChaRow:
    size: int
    ratio: str            # "30", "50" or ">50" (80/100/120/160)
    T1_Nmm: float
    T2_Nmm: float
    K1_Nmm_per_rad: float
    K2_Nmm_per_rad: float
    K3_Nmm_per_rad: float

    @property
    def hysteresis_limit_arcmin(self) -> float:
        """Catalogue hysteresis loss limit: 3 arcmin at ratio 30, 1 arcmin for ratios >= 50."""
        return 3.0 if self.ratio == "30" else 1.0

    def twist_rad(self, T_Nmm: np.ndarray) -> np.ndarray:
        """The catalogue's three-slope twist curve, odd in the torque."""
        m = np.abs(T_Nmm)
        phi = (np.minimum(m, self.T1_Nmm) / self.K1_Nmm_per_rad
               + np.clip(m - self.T1_Nmm, 0.0, self.T2_Nmm - self.T1_Nmm) / self.K2_Nmm_per_rad
               + np.maximum(m - self.T2_Nmm, 0.0) / self.K3_Nmm_per_rad)
        return np.sign(T_Nmm) * phi


def cha_rows() -> list[ChaRow]:
    """All rows of the shipped table (read once, by analytic.catalogue), in N*mm and N*mm/rad."""
    from strainwave.analytic.catalogue import read_catalogue

    return [ChaRow(r.size, r.ratio_label, r.T1_Nm * 1e3, r.T2_Nm * 1e3, r.K1_Nm_per_rad * 1e3,
                   r.K2_Nm_per_rad * 1e3, r.K3_Nm_per_rad * 1e3) for r in read_catalogue()]


# Slip thresholds up to half the peak torque: at 0.15 the loop was unphysical (docs/decisions/024-cha-slip-fraction.md).
CHA_SLIP_FRACTION = 0.5


def cha_recording(row: ChaRow, *, hysteresis: bool, n: int = 2000, seed: int = 0,
                  loss_fraction_of_limit: float = 0.8) -> str:
    """A recording of one CHA gear: two torque cycles to +/- 1.5 T2, with or without the friction loop.

    The loop (Maxwell-slip, 40 elements) is ``loss_fraction_of_limit`` of the catalogue limit.
    Noise: 20-bit encoder quantization plus white noise of half a step; torque noise 0.05 % of full scale.
    """
    rng = np.random.default_rng(seed)
    T_max = 1.5 * row.T2_Nmm
    knots = [0.0, 1.0, -1.0, 1.0, -1.0, 0.0]
    s = np.linspace(0.0, len(knots) - 1, n)
    T = np.interp(s, np.arange(len(knots)), knots) * T_max
    twist = row.twist_rad(T)
    if hysteresis:
        twist = twist + maxwell_slip_twist(T, loss_fraction_of_limit * row.hysteresis_limit_arcmin * ARCMIN,
                                           CHA_SLIP_FRACTION)
    twist = twist + 0.5 * ENCODER_STEP_RAD * rng.standard_normal(n) + 3.0 * ENCODER_STEP_RAD
    twist = np.round(twist / ENCODER_STEP_RAD) * ENCODER_STEP_RAD
    T_meas = T + 5e-4 * T_max * rng.standard_normal(n)
    return format_recording(RecordingKind.TORSION, "gear", T_meas, twist, baseline_uncertainty=0.3,
                            baseline_stiffness=row.K1_Nmm_per_rad,
                            description=f"CHA-{row.size} ratio {row.ratio}{' with hysteresis' if hysteresis else ''}")
