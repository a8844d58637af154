"""Seed 003's minimal flexspline tooth number (eq 14) with the FEA-confirmed tooth factors.

Eq 14 takes K_delta = 1.07 and K_sigma = 1.9 as constants. The toothed-ring FEA shows both depend on the
rim: with delta = ratio m Z_R and tooth height h = (h*_a + h*_f) m, the rim ratios h/delta = (h*_a +
h*_f)/(ratio Z_R) and m/delta = 1/(ratio Z_R) change with Z_R, so K_delta(Z_R) K_sigma(Z_R)
(``tooth_factors``) must be evaluated at the tooth number being tested. n_sigma(Z) rises with Z (more
teeth: thicker rim, smaller factors, and eq 14's (Z + c)^2/Z), so the smallest integer Z with
n_sigma(Z) >= [n] is found by a scan upward from the seed-constant root.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

from strainwave.analytic import fatigue, tooth_factors

# Toothed-ring FEA at the model's Z_R,min rims (quick meshes, fillet 0.25 m; fea/ring_compression.run):
# (Z_R, dZ) -> FEA K_delta, K_sigma and eq 14's n_sigma with them. The model is within its fitting residual
# (K_delta -2.9 % / +1.2 %, K_sigma +0.5 % / +0.6 %), but at Z_R = 110 the FEA factors give n_sigma = 1.368 < 1.4:
# with the FEA's factors the dZ = 2 minimum is 113 (factors held at their Z_R = 110 values), for dZ = 4 it is 204.
FEA_AT_MINIMUM = {(110, 2): {"tooth_influence": 1.5423, "stress_concentration": 2.0340, "n_sigma": 1.3681,
                             "Z_R_min_with_these_factors": 113},
                  (208, 4): {"tooth_influence": 1.1328, "stress_concentration": 2.4595, "n_sigma": 1.4280,
                             "Z_R_min_with_these_factors": 204}}

__all__ = ["FEA_AT_MINIMUM", "supported_minimum", "ToothNumberResult", "rim_ratios", "safety_with_model", "minimal_teeth_with_model"]


def supported_minimum(tooth_difference: int, model_Z_R_min: int, permissible_safety: float,
                      fea_applies: bool) -> tuple[int, str]:
    """The one Z_R,min a headline states, and the basis of the other number (issue 37).

    Where the toothed-ring FEA at the model's minimum (FEA_AT_MINIMUM, solved for the seed's design only:
    ``fea_applies``) gives n_sigma < [n], the model is unconservative there and the number is the FEA factors'
    (held at their values at that rim); where the FEA confirms n_sigma >= [n], the model's number stands."""
    fea = FEA_AT_MINIMUM.get((model_Z_R_min, tooth_difference)) if fea_applies else None
    if fea is None:
        return model_Z_R_min, "the fitted tooth-factor model; no toothed-ring FEA at this rim"
    n, fea_min = fea["n_sigma"], fea["Z_R_min_with_these_factors"]
    if n < permissible_safety:
        return fea_min, (f"toothed-ring FEA at Z_R = {model_Z_R_min}: n_sigma = {n:.3f} < [n] = {permissible_safety:g}, "
                         f"so the FEA factors (held at their Z_R = {model_Z_R_min} values) need Z_R = {fea_min}; "
                         f"the fitted model alone gives {model_Z_R_min}")
    return model_Z_R_min, (f"toothed-ring FEA at Z_R = {model_Z_R_min} confirms n_sigma = {n:.3f} >= [n] = "
                           f"{permissible_safety:g}; the FEA factors held at those values would allow {fea_min} "
                           "(not solved there)")


@dataclass(frozen=True)
class ToothNumberResult:
    """Z_R,min for one tooth difference, with the factors at that Z_R."""

    tooth_difference: int
    Z_R_min: int
    n_sigma: float                # at Z_R_min
    tooth_influence: float        # K_delta at Z_R_min
    stress_concentration: float   # K_sigma at Z_R_min
    h_over_delta: float
    delta_over_m: float
    seed_constant_Z_R_min: int    # eq 14 with the seed's constants (K_delta = 1.07, K_sigma = 1.9)


def rim_ratios(teeth: float, design: fatigue.ToothDesign, addendum_coefficient: float = 1.0) -> tuple[float, float]:
    """(h/delta, m/delta) of the rim delta = ratio m Z_R (seed 003, eq 14 text: delta = 0.012 d_R)."""
    delta_over_m = design.rim_thickness_ratio * teeth
    h_over_m = tooth_factors.tooth_height_mm(1.0, design.dedendum_coefficient, addendum_coefficient)
    return h_over_m / delta_over_m, 1.0 / delta_over_m


def safety_with_model(teeth: int, tooth_difference: int, permissible_safety: float, fatigue_limit_MPa: float,
                      E_MPa: float, design: fatigue.ToothDesign, model: tooth_factors.ToothFactorModel) -> tuple:
    """n_sigma of eq 14 with K_delta, K_sigma from ``model`` at this Z_R; returns (n_sigma, K_delta, K_sigma)."""
    hd, md = rim_ratios(teeth, design)
    kd = tooth_factors.tooth_influence(hd, md, model)
    ks = tooth_factors.stress_concentration(hd, md, model)
    d = replace(design, tooth_influence=kd, stress_concentration=ks)
    n = fatigue.safety_from_teeth(teeth, tooth_difference, fatigue_limit_MPa, E_MPa, fatigue.tooth_constant(d),
                                  fatigue.tooth_offset(d))
    return n, kd, ks


def minimal_teeth_with_model(tooth_difference: int, permissible_safety: float, fatigue_limit_MPa: float,
                             E_MPa: float, design: fatigue.ToothDesign,
                             model: tooth_factors.ToothFactorModel = tooth_factors.FITTED,
                             max_teeth: int = 5000) -> ToothNumberResult:
    """Smallest integer Z_R with n_sigma(Z_R) >= [n], factors evaluated self-consistently at Z_R."""
    seed_root = fatigue.minimal_teeth_root(tooth_difference, permissible_safety, fatigue_limit_MPa, E_MPa,
                                           fatigue.tooth_constant(design), fatigue.tooth_offset(design))
    seed_z = fatigue.minimal_teeth(seed_root)
    # eq 14's (Z + c)^2/Z falls up to Z = c: the practical (larger-root) branch starts above c
    z = max(2 * tooth_difference, math.floor(fatigue.tooth_offset(design)) + 1)
    while z <= max_teeth:
        n, kd, ks = safety_with_model(z, tooth_difference, permissible_safety, fatigue_limit_MPa, E_MPa, design, model)
        if n >= permissible_safety:
            hd, md = rim_ratios(z, design)
            return ToothNumberResult(tooth_difference, z, n, kd, ks, hd, 1.0 / md, seed_z)
        z += 1
    raise ValueError(f"no Z_R <= {max_teeth} satisfies n_sigma >= {permissible_safety} for dZ = {tooth_difference}")
