"""Tooth influence K_delta and root stress concentration K_sigma of the EWG flexspline rim (seed 003, eqs 10-14).

Seed 003 assumes K_delta = 1.07 (1.05..1.10) and K_sigma = 1.9 (1.8..2.0) for every rim. The toothed-ring
FEA (``fea/ring_compression.py``, both factors at the same prescribed W0) says otherwise, and the factors
depend on the rim: this module is the model that replaces the seed's constants.

Definitions (the FEA's, in the seed's terms; every stress at the same mid-layer deformation W0):
- K_delta = outer-fibre stress amplitude of the toothed ring / that of the smooth ring (eqs 10-11 multiply
  the smooth-shell stresses by K_delta).
- P = K_delta K_sigma = tooth-root-fillet peak amplitude / the smooth ring's inner-fibre amplitude (eq 13
  applies K_sigma to sigma_a, which already contains K_delta), so K_sigma = P / K_delta.

Model (one small mechanical argument per constant):
1. Equivalent rim. For bending stiffness the toothed rim acts as a smooth rim of thickness
   delta_eq = delta + c h (h the whole tooth height): the toothed/smooth stiffness ratio at equal W0 is
   R = (delta_eq/delta)^3.
2. Where the stress is read. Under a prescribed average curvature (W0) a rim of alternating thin (under a
   tooth space) and thick (under a tooth) segments bends mostly in the thin ones; if a segment is long
   compared with the rim thickness, the outer fibre behind a space carries R times the smooth stress (the
   curvature ratio of a segmented beam equals its stiffness ratio). If it is short, the periodic part has
   decayed (Saint-Venant) before reaching the outer fibre, and the rim reads ~1. The segments repeat every
   pitch pi m, so the attenuation is a function of m/delta:  K_delta = 1 + (R - 1) tanh(k m/delta).
3. Root factor. The fillet peak over the smooth inner fibre: P = P0 + a (K_delta - 1): a notch factor P0
   of the tooth-root fillet in a rim the teeth do not stiffen, plus a share of the tooth-induced increase.

c, k, P0, a are fitted (``fit_tooth_factors``) to toothed-ring FEA on the FITTING_SET below (Z_R = 100,
m = 1 mm, fillet 0.25 m), and checked against the FEA of geometries they were not fitted on (the default
Z_R = 72 ring of validate, and the second parameter file). They hold for root_fillet_coefficient = 0.25;
``FILLET_SENSITIVITY`` gives what the FEA measured at 0.35 m.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["FITTED_DELTA_OVER_M", "EXTRAPOLATION", "range_note", "ToothFactorModel", "FitRow", "FITTING_SET", "FITTED", "FILLET_SENSITIVITY", "MODEL_ROOT_FILLET_COEFFICIENT", "tooth_height_mm",
           "fit_tooth_factors", "stiffness_ratio", "tooth_influence", "root_product", "stress_concentration",
           "fit_residuals"]


@dataclass(frozen=True)
class FitRow:
    """One toothed-ring FEA result (quick meshes, finest h = 0.4 m) used to fit the model."""

    teeth: int
    module_mm: float
    delta_over_m: float
    tooth_height_over_m: float
    stiffness_ratio: float      # F_toothed / F_smooth at equal W0 (meta tooth_stiffness_ratio)
    tooth_influence: float      # K_delta
    root_product: float         # K_delta K_sigma

    def __post_init__(self):
        for name in ("module_mm", "delta_over_m", "tooth_height_over_m", "stiffness_ratio", "tooth_influence",
                     "root_product"):
            if not getattr(self, name) > 0:
                raise ValueError(f"FitRow.{name} must be > 0, got {getattr(self, name)!r}")


@dataclass(frozen=True)
class ToothFactorModel:
    """Fitted constants: equivalent-rim c, attenuation k, notch factor P0 and share a."""

    c: float
    k: float
    p0: float
    a: float

    def __post_init__(self):
        if not (self.c > 0 and self.k > 0 and self.p0 >= 1.0):
            raise ValueError(f"unphysical tooth-factor model {self!r}")


def tooth_height_mm(module_mm: float, dedendum_coefficient: float = 1.35, addendum_coefficient: float = 1.0) -> float:
    """Whole depth h = (h*_a + h*_f) m of the flexspline's internal teeth (seed 003: h*_fR = 1.35, h*_a = 1)."""
    return (addendum_coefficient + dedendum_coefficient) * module_mm


def stiffness_ratio(h_over_delta: float, model: ToothFactorModel) -> float:
    """R = (1 + c h/delta)^3: bending stiffness of the equivalent rim delta + c h over the bare rim."""
    return (1.0 + model.c * h_over_delta) ** 3


def tooth_influence(h_over_delta: float, m_over_delta: float, model: ToothFactorModel) -> float:
    """K_delta = 1 + (R - 1) tanh(k m/delta) (module docstring, point 2)."""
    return 1.0 + (stiffness_ratio(h_over_delta, model) - 1.0) * math.tanh(model.k * m_over_delta)


def root_product(h_over_delta: float, m_over_delta: float, model: ToothFactorModel) -> float:
    """P = K_delta K_sigma = P0 + a (K_delta - 1) (module docstring, point 3)."""
    return model.p0 + model.a * (tooth_influence(h_over_delta, m_over_delta, model) - 1.0)


def stress_concentration(h_over_delta: float, m_over_delta: float, model: ToothFactorModel) -> float:
    """K_sigma = P / K_delta in seed 003's terms (eq 13 applies it to sigma_a, which contains K_delta)."""
    return root_product(h_over_delta, m_over_delta, model) / tooth_influence(h_over_delta, m_over_delta, model)


def fit_tooth_factors(rows) -> ToothFactorModel:
    """Least-squares constants from FEA rows: c from the stiffness ratios (closed form per row, averaged in
    the cube root), k from K_delta given c (1D bounded search), (P0, a) linear in K_delta - 1."""
    from scipy.optimize import minimize_scalar

    rows = list(rows)
    if len(rows) < 3:
        raise ValueError("need at least 3 FEA rows to fit 4 constants with a residual (2 + 2 per relation)")
    hd = np.array([r.tooth_height_over_m / r.delta_over_m for r in rows])
    md = np.array([1.0 / r.delta_over_m for r in rows])
    R = np.array([r.stiffness_ratio for r in rows])
    Kd = np.array([r.tooth_influence for r in rows])
    P = np.array([r.root_product for r in rows])
    # c: least squares of R^(1/3) - 1 = c h/delta through the origin
    y = np.cbrt(R) - 1.0
    c = float(np.dot(y, hd) / np.dot(hd, hd))
    Rm = (1.0 + c * hd) ** 3

    def cost(k):
        return float(np.sum(((1.0 + (Rm - 1.0) * np.tanh(k * md)) / Kd - 1.0) ** 2))

    k = float(minimize_scalar(cost, bounds=(0.05, 20.0), method="bounded").x)
    Kmod = 1.0 + (Rm - 1.0) * np.tanh(k * md)
    A = np.column_stack([np.ones_like(Kmod), Kmod - 1.0])
    p0, a = np.linalg.lstsq(A, P, rcond=None)[0]
    return ToothFactorModel(c, k, float(p0), float(a))


def fit_residuals(rows, model: ToothFactorModel) -> dict[str, float]:
    """Largest relative residual of each relation over ``rows`` (the model's own error on its fitting set)."""
    out = {"stiffness_ratio": 0.0, "tooth_influence": 0.0, "root_product": 0.0, "stress_concentration": 0.0}
    for r in rows:
        hd, md = r.tooth_height_over_m / r.delta_over_m, 1.0 / r.delta_over_m
        pairs = {"stiffness_ratio": (stiffness_ratio(hd, model), r.stiffness_ratio),
                 "tooth_influence": (tooth_influence(hd, md, model), r.tooth_influence),
                 "root_product": (root_product(hd, md, model), r.root_product),
                 "stress_concentration": (stress_concentration(hd, md, model), r.root_product / r.tooth_influence)}
        for key, (mod, fea) in pairs.items():
            out[key] = max(out[key], abs(mod / fea - 1.0))
    return out


# Toothed-ring FEA (fea/ring_compression.run, quick, finest h = 0.4 m, fillet 0.25 m, pressure angle 20 deg,
# h*_f = 1.35) on Z_R = 100, m = 1 mm: the rims the constants are fitted on. Regenerate with
# benchmarks/fit_tooth_factors.py; none of these is the validate geometry (Z_R = 72).
FITTING_SET: tuple[FitRow, ...] = (
    FitRow(100, 1.0, 0.75, 2.35, stiffness_ratio=2.434820, tooth_influence=2.257891, root_product=3.586008),
    FitRow(100, 1.0, 1.10, 2.35, stiffness_ratio=1.935634, tooth_influence=1.746321, root_product=3.178408),
    FitRow(100, 1.0, 1.50, 2.35, stiffness_ratio=1.636490, tooth_influence=1.401582, root_product=3.026295),
    FitRow(100, 1.0, 2.00, 2.35, stiffness_ratio=1.445575, tooth_influence=1.220295, root_product=2.890617),
    FitRow(100, 1.0, 3.00, 2.35, stiffness_ratio=1.267726, tooth_influence=1.073849, root_product=2.789501),
)
# fit_tooth_factors(FITTING_SET), rounded (tests/test_analytic_tooth_factors.py refits and compares)
FITTED = ToothFactorModel(c=0.11182, k=1.11448, p0=2.74420, a=0.64025)
# The fillet radius / module of every FITTING_SET ring (the model holds for this fillet).
MODEL_ROOT_FILLET_COEFFICIENT = 0.25
# Fillet sensitivity at the default ring (Z_R = 72, delta/m = 0.864), toothed FEA at h = delta/4 (the full
# run's meshes): K_sigma falls 3.6 % from fillet 0.25 m to 0.35 m (the 0.35 m root factor's GCI is 16 %, its
# medium mesh does not resolve the larger fillet's curvature change; the 0.25 m value's GCI is 0.5 %).
FILLET_SENSITIVITY: dict[float, dict[str, float]] = {
    0.25: {"tooth_influence": 2.0462, "root_product": 3.4528, "stress_concentration": 1.6874},
    0.35: {"tooth_influence": 2.0662, "root_product": 3.3590, "stress_concentration": 1.6257},
}
# The delta/m range of FITTING_SET: the model interpolates inside it.
FITTED_DELTA_OVER_M = (0.75, 3.0)
# Toothed-ring FEA (quick, Z_R = 100, m = 1 mm, fillet 0.25 m) at rims OUTSIDE that range, against the model
# (benchmarks/fit_tooth_factors.py --extrapolate): delta/m -> FEA value and its GCI per factor. The model's
# error there is what an extrapolated use carries.
EXTRAPOLATION: dict[float, dict[str, tuple[float, float]]] = {
    0.6: {"tooth_influence": (2.6169, 0.030), "stress_concentration": (1.4942, 0.078)},
    3.6: {"tooth_influence": (1.0608, 0.033), "stress_concentration": (2.6232, 0.0052)},
}


def extrapolation_errors(delta_over_m: float, model: ToothFactorModel = FITTED) -> dict[str, float]:
    """model / FEA - 1 of each factor at a measured rim of EXTRAPOLATION (Z_R = 100, h*_f = 1.35)."""
    fea = EXTRAPOLATION[delta_over_m]
    hd, md = tooth_height_mm(1.0) / delta_over_m, 1.0 / delta_over_m
    return {"tooth_influence": tooth_influence(hd, md, model) / fea["tooth_influence"][0] - 1.0,
            "stress_concentration": stress_concentration(hd, md, model) / fea["stress_concentration"][0] - 1.0}


def range_note(delta_over_m: float) -> str:
    """The range the fitted form holds on, and where ``delta_over_m`` lies: inside, or outside with the error the
    FEA measured at the nearest extrapolated rim."""
    lo, hi = FITTED_DELTA_OVER_M
    if lo <= delta_over_m <= hi:
        return f"delta/m = {delta_over_m:.3g} inside the fitted range {lo:g}-{hi:g} (interpolation)"
    nearest = min(EXTRAPOLATION, key=lambda d: abs(d - delta_over_m))
    err = extrapolation_errors(nearest)
    return (f"delta/m = {delta_over_m:.3g} OUTSIDE the fitted range {lo:g}-{hi:g} (extrapolation): at delta/m = "
            f"{nearest:g} the model is off the FEA by {100 * err['tooth_influence']:+.1f} % (K_delta, FEA GCI "
            f"{100 * EXTRAPOLATION[nearest]['tooth_influence'][1]:.2g} %) and {100 * err['stress_concentration']:+.1f} % "
            f"(K_sigma, GCI {100 * EXTRAPOLATION[nearest]['stress_concentration'][1]:.2g} %)")
