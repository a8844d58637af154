"""Which of a drive's slopes a given "linear stiffness" is: K1 (the first, softest) or K3 (the catalogue's headline).

A harmonic drive has no one linear stiffness: its curve stiffens from K1 to K3 (often 1.8x). The diagnosis's
baseline is the line of the FIRST slope (every stiffening is drawn from it: K1 = 1/(s c0)). A user who gives K3,
the figure a catalogue prints first, would otherwise see the whole curve read as a specimen 1.8x softer than
stated ("unexplained", a crack suggested). So for a gear the given stiffness is compared with the recording's own
tangents: below 20 % and above 60 % of its largest torque (each from a line plus a branch offset, so the loop's
width does not tilt it). Nearer the high-load tangent it is K3, and the baseline's first slope is it times the
recording's low/high tangent ratio; the report says which slope it was taken as.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

LOW_BAND = (0.05, 0.20)      # fraction of the largest torque: above a lost motion's take-up, below most knees
HIGH_BAND = (0.60, 1.00)     # above T2 for a +/-1.5 T2 catalogue cycle
MIN_ROWS = 10
# a curve whose low-load tangent is within this factor of its high-load one is a line: the given value is its slope
STIFFENING_RATIO = 1.15


@dataclass(frozen=True)
class SlopeReading:
    """How the given stiffness was read."""

    slope: str                    # "K1" or "K3"
    given: float                  # the stiffness given, N*mm/rad
    first_slope: float            # the baseline's first slope, N*mm/rad
    low_tangent: float            # the recording's tangent stiffness below 20 % of its largest torque
    high_tangent: float           # ... above 60 %

    def sentence(self, unit: str = "N*mm/rad") -> str:
        if self.slope == "K1":
            return (f"the given stiffness {self.given:.4g} {unit} was taken as K1, the first slope (nearer the "
                    f"recording's tangent below 20 % of its largest torque, {self.low_tangent:.4g}, than the one "
                    f"above 60 %, {self.high_tangent:.4g})")
        return (f"the given stiffness {self.given:.4g} {unit} was taken as K3, the slope at high torque (nearer the "
                f"recording's tangent above 60 % of its largest torque, {self.high_tangent:.4g}, than the one below "
                f"20 %, {self.low_tangent:.4g}); the baseline's first slope K1 = {self.first_slope:.4g} is it times "
                f"their ratio")


def _tangent(load: np.ndarray, response: np.ndarray, direction: np.ndarray, band: tuple[float, float]) -> float:
    """Compliance of the line plus branch offset through the rows whose |load| lies in ``band`` of the largest
    (each load sign its own intercept); nan where too few rows."""
    m = float(np.max(np.abs(load)))
    a = np.abs(load) / m
    keep = (a >= band[0]) & (a <= band[1])
    if int(keep.sum()) < MIN_ROWS:
        return math.nan
    T, y, d = load[keep], response[keep], direction[keep]
    A = np.column_stack([T, (T > 0).astype(float), (T <= 0).astype(float), d])
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    return float(coef[0])


def read_slope(load: np.ndarray, response: np.ndarray, direction: np.ndarray, given: float) -> SlopeReading | None:
    """The slope a given stiffness (N*mm/rad) stands for on this recording; None where the curve is a line (or
    the bands hold too few rows), so the given value is its one slope."""
    c_low = _tangent(load, response, direction, LOW_BAND)
    c_high = _tangent(load, response, direction, HIGH_BAND)
    if not (c_low > 0.0 and c_high > 0.0) or c_low < STIFFENING_RATIO * c_high:
        return None
    k_low, k_high = 1.0 / c_low, 1.0 / c_high
    if abs(math.log(given / k_high)) < abs(math.log(given / k_low)):
        return SlopeReading("K3", given, given * k_low / k_high, k_low, k_high)
    return SlopeReading("K1", given, given, k_low, k_high)


__all__ = ["SlopeReading", "read_slope"]
