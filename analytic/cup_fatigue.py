"""The flexspline's fatigue as it really cycles: safety factors from the stress amplitude and mean a point of
the tooth band runs through per input revolution (it passes the major and minor axes twice).

Two forms of the same question, each from the FEA's amplitude sigma_a and mean sigma_m:
- seed 003, eq 13: n = sigma_-1 / (K_sigma sigma_a + psi_sigma sigma_m);
- Goodman (notch factor on the amplitude): n = 1 / (K_sigma sigma_a / sigma_-1 + sigma_m / R_m), with a
  compressive mean taken as zero (Goodman's line is for tensile means; a compressive mean does not help
  here by assumption).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from strainwave.analytic.fatigue import normal_safety_factor


@dataclass(frozen=True)
class CupFatigueSafety:
    amplitude_MPa: float
    mean_MPa: float
    fatigue_limit_MPa: float
    ultimate_strength_MPa: float
    stress_concentration: float
    mean_stress_influence: float
    n_eq13: float
    n_goodman: float

    def to_dict(self) -> dict:
        return dict(self.__dict__)


def goodman_safety_factor(fatigue_limit_MPa: float, ultimate_strength_MPa: float, stress_concentration: float,
                          amplitude_MPa: float, mean_MPa: float) -> float:
    """n = 1 / (K_sigma sigma_a / sigma_-1 + max(sigma_m, 0) / R_m) (Goodman, notch factor on the amplitude)."""
    demand = stress_concentration * amplitude_MPa / fatigue_limit_MPa + max(mean_MPa, 0.0) / ultimate_strength_MPa
    return math.inf if demand <= 0.0 else 1.0 / demand


def cup_fatigue_safety(amplitude_MPa: float, mean_MPa: float, *, fatigue_limit_MPa: float,
                       ultimate_strength_MPa: float, stress_concentration: float,
                       mean_stress_influence: float) -> CupFatigueSafety:
    """Both safety factors of the cycle (sigma_a, sigma_m); eq 13 with the signed mean (seed 003, eq 13)."""
    if not (math.isfinite(amplitude_MPa) and amplitude_MPa >= 0.0 and math.isfinite(mean_MPa)):
        raise ValueError(f"amplitude must be finite and >= 0, mean finite; got {amplitude_MPa!r}, {mean_MPa!r}")
    n13 = normal_safety_factor(fatigue_limit_MPa, stress_concentration, amplitude_MPa, mean_stress_influence,
                               mean_MPa)
    n_g = goodman_safety_factor(fatigue_limit_MPa, ultimate_strength_MPa, stress_concentration, amplitude_MPa,
                                mean_MPa)
    return CupFatigueSafety(amplitude_MPa, mean_MPa, fatigue_limit_MPa, ultimate_strength_MPa, stress_concentration,
                            mean_stress_influence, n13, n_g)


def cup_fatigue_of(params, amplitude_MPa: float, mean_MPa: float) -> CupFatigueSafety:
    """``cup_fatigue_safety`` with the material's sigma_-1, R_m and seed 003's K_sigma, psi_sigma from ``params``."""
    m, e = params.material, params.ewg_drive
    return cup_fatigue_safety(amplitude_MPa, mean_MPa, fatigue_limit_MPa=m.fatigue_limit_MPa,
                              ultimate_strength_MPa=m.ultimate_strength_MPa, stress_concentration=e.stress_concentration,
                              mean_stress_influence=e.mean_stress_influence)
