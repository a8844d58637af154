"""How crack compliance grows with depth: the exponent p of delta_lambda ~ a^p from a depth sweep.

Seed 000 publishes delta_lambda_so ~ a^3 (penny-shaped area element) where the circumferential crack
of the shaft gives ~ a^2 (audit item 10). A straight-line fit of log delta_lambda against log a over
the sweep (np.polyfit) settles it, with the standard error of the slope from the fit's covariance.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class PowerFit:
    exponent: float
    stderr: float | None       # None with only two points
    coefficient: float         # delta_lambda = coefficient * a^exponent
    points: int

    def to_dict(self) -> dict:
        return {"exponent": self.exponent, "stderr": self.stderr, "coefficient": self.coefficient,
                "points": self.points}


def fit_power_law(depths_mm, values) -> PowerFit | None:
    """Least-squares slope of log(value) vs log(a) over the points with value > 0; None if < 2 points."""
    a = np.asarray(depths_mm, dtype=float)
    v = np.asarray(values, dtype=float)
    keep = np.isfinite(a) & np.isfinite(v) & (a > 0) & (v > 0)
    a, v = a[keep], v[keep]
    if len(a) < 2 or np.ptp(np.log(a)) == 0.0:
        return None
    x, y = np.log(a), np.log(v)
    slope, intercept = np.polyfit(x, y, 1)
    stderr = None
    if len(a) >= 3:  # residual variance with n - 2 degrees of freedom over the spread of log a
        residual = y - (slope * x + intercept)
        stderr = float(math.sqrt(np.sum(residual ** 2) / (len(a) - 2) / np.sum((x - x.mean()) ** 2)))
    return PowerFit(float(slope), stderr, float(math.exp(intercept)), int(len(a)))


def closer_exponent(fitted: float, candidates: dict[str, float]) -> str:
    """Name of the candidate exponent nearest the fitted one (e.g. {'published': 3, 'corrected': 2})."""
    return min(candidates, key=lambda name: abs(candidates[name] - fitted))
