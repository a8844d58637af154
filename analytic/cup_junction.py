"""The cup's junction compliance: what the series shell model (tube + diaphragm + hub) leaves out.

The series model (``seed000.cup_series_model``) adds the tube, the diaphragm and the hub as if each carried
its shear undisturbed up to the next. The corners where they meet (diaphragm to tube, hub to diaphragm) add
a compliance of their own. The exact (r, z) section FEA of smooth cups (``fea/cup_axisym.py``) shows it is
independent of the cup's length and, in units of 1 / (G d1^3), a smooth function of the wall ratio
delta/d1 alone (every other proportion is a fixed ratio of d1 in ``geometry/flexspline_cup``). It is
fitted here as a straight line in delta/d1 on FIT_CUPS and confirmed on other cups
(``benchmarks/cup_calibration.py``; docs/decisions/031-cup-section-flexibility.md).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["FIT_CUPS", "JunctionFit", "junction_fit", "junction_compliance", "in_calibrated_range"]

# The FEA's G (E = 210 GPa, nu = 0.3) of the runs below: E / 2(1 + nu).
FIT_G_MPa = 210000.0 / 2.6
# (d1, delta, L) mm -> (section FEA lambda_f, series model) rad/(N mm); `python benchmarks/cup_calibration.py`
FIT_CUPS = {(120.0, 1.2, 96.0): (1.391146e-09, 1.315335e-09), (120.0, 1.2, 156.0): (1.861192e-09, 1.785382e-09),
            (120.0, 1.8, 120.0): (1.096908e-09, 1.032385e-09), (120.0, 2.4, 96.0): (7.648860e-10, 7.103268e-10),
            (120.0, 2.4, 156.0): (1.007101e-09, 9.525420e-10)}


@dataclass(frozen=True)
class JunctionFit:
    intercept: float            # G d1^3 Delta lambda at delta/d1 = 0
    slope: float                # its change per unit delta/d1
    scatter: float              # largest |residual| of a fit cup, as a fraction of its lambda_f
    wall_ratio_range: tuple[float, float]

    def dimensionless(self, wall_ratio: float) -> float:
        return self.intercept + self.slope * wall_ratio


def junction_fit(cups: dict | None = None) -> JunctionFit:
    """Least squares of G d1^3 (FEA - series model) against delta/d1 over ``cups`` (default FIT_CUPS)."""
    cups = FIT_CUPS if cups is None else cups
    x = np.array([delta / d1 for d1, delta, _ in cups])
    y = np.array([(fea - model) * FIT_G_MPa * d1 ** 3 for (d1, _, _), (fea, model) in cups.items()])
    slope, intercept = np.polyfit(x, y, 1)
    fea = np.array([v[0] for v in cups.values()])
    d1 = np.array([k[0] for k in cups])
    residual = (y - (intercept + slope * x)) / (FIT_G_MPa * d1 ** 3) / fea
    return JunctionFit(float(intercept), float(slope), float(np.abs(residual).max()), (float(x.min()), float(x.max())))


JUNCTION = junction_fit()


def junction_compliance(params, G_MPa: float) -> float:
    """Delta lambda_f of the junctions, rad/(N mm), for the cup of ``params`` and shear modulus ``G_MPa``."""
    c = params.flexspline_cup
    return JUNCTION.dimensionless(c.wall_thickness_mm / c.pitch_diameter_mm) / (G_MPa * c.pitch_diameter_mm ** 3)


def in_calibrated_range(params) -> tuple[bool, str]:
    """(inside, why not): the fit holds for cylindrical cups with delta/d1 inside the fit cups' range."""
    c = params.flexspline_cup
    lo, hi = JUNCTION.wall_ratio_range
    ratio = c.wall_thickness_mm / c.pitch_diameter_mm
    if not c.cup:
        return False, "an open tube has no junctions: the calibration is for cups"
    if getattr(c.shape, "value", c.shape) != "cylindrical":
        return False, f"shape {getattr(c.shape, 'value', c.shape)!r}: the calibration is for cylindrical cups"
    if not lo - 1e-12 <= ratio <= hi + 1e-12:
        return False, f"delta/d1 = {ratio:.4g} lies outside the calibrated {lo:.3g}..{hi:.3g}: extrapolated"
    return True, ""
