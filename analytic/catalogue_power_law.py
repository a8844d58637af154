"""The CHA table's own power law in size, read at one gear's size: the catalogue unit a gear of this pitch
diameter and ratio column would be (Harmonic Drive's size = pitch diameter in tenths of an inch).

Least squares of log(value) on log(size) over every row of the gear's ratio column (T1, T2: every row, they do
not depend on the ratio); returns the value, the rms log residual (the table's scatter about its law) and
whether the size lies outside the table's 14..58 (an extrapolation the caller must say)."""
from __future__ import annotations

import math

import numpy as np

from strainwave.analytic.catalogue import read_catalogue

__all__ = ["ratio_column", "power_law_at", "catalogue_curve_Nm"]


def ratio_column(gear_ratio: float) -> str:
    return "30" if gear_ratio <= 40 else ("50" if gear_ratio <= 65 else ">50")


def power_law_at(params, name: str) -> tuple[float, float, str, bool]:
    """(value in the table's unit x 1 (K in N m/rad, T in N m), rms log residual, column, extrapolated)."""
    label = ratio_column(params.gear.gear_ratio)
    rows = [r for r in read_catalogue() if (name.startswith("T") or r.ratio_label == label)
            and getattr(r, name) is not None]
    x = np.log([r.size for r in rows])
    y = np.log([getattr(r, name) for r in rows])
    A = np.column_stack([np.ones_like(x), x])
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    resid = y - A @ coef
    size = params.flexspline_cup.pitch_diameter_mm / 2.54
    outside = not (min(r.size for r in rows) <= size <= max(r.size for r in rows))
    return math.exp(coef[0] + coef[1] * math.log(size)), float(np.sqrt(np.mean(resid ** 2))), label, outside


def catalogue_curve_Nm(params) -> tuple[float, float, float, float, float]:
    """(K1, K2, K3 in N m/rad, T1, T2 in N m) at this gear's size and ratio column."""
    return tuple(power_law_at(params, n)[0] for n in ("K1_Nm_per_rad", "K2_Nm_per_rad", "K3_Nm_per_rad",
                                                         "T1_Nm", "T2_Nm"))
