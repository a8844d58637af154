"""Discretization error from three refinements: observed order, Richardson extrapolation, GCI.

Roache's grid convergence index as adopted by ASME V&V 20: with h1 < h2 < h3 (fine to coarse),
refinement ratios r21 = h2/h1, r32 = h3/h2, the observed order p solves

    p = |ln|e32/e21| + q(p)| / ln r21,   q(p) = ln((r21^p - s)/(r32^p - s)),  s = sign(e32/e21)

and GCI_fine = Fs |e_a21| / (r21^p - 1) with the safety factor Fs = 1.25 for three grids.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

SAFETY_FACTOR_THREE_GRIDS = 1.25


@dataclass(frozen=True)
class Convergence:
    """A headline quantity on three meshes, fine first."""

    h_mm: tuple[float, float, float]
    values: tuple[float, float, float]
    observed_order: float
    extrapolated: float
    gci_fine: float          # relative, e.g. 0.001 = 0.1 %
    monotone: bool
    # the bounds p was clipped to: equal bounds = a fixed (formal) order, e.g. crack compliances (1, 1)
    order_bounds: tuple[float, float] = (0.05, 8.0)

    @property
    def order_fixed(self) -> bool:
        return self.order_bounds[0] == self.order_bounds[1]

    @property
    def order_clipped(self) -> bool:
        """p sits on a bound (and the bounds leave it free): the data did not set it."""
        return not self.order_fixed and math.isfinite(self.observed_order) and self.observed_order in self.order_bounds

    @property
    def uncertainty(self) -> float:
        """Absolute uncertainty of the finest value (GCI times |value|)."""
        return self.gci_fine * abs(self.values[0])

    def to_dict(self) -> dict:
        return {"h_mm": list(self.h_mm), "values": list(self.values), "observed_order": self.observed_order,
                "extrapolated": self.extrapolated, "gci_fine": self.gci_fine, "monotone": self.monotone,
                "order_bounds": list(self.order_bounds), "uncertainty": self.uncertainty}


def grid_convergence(h_mm, values, *, max_order: float = 8.0, min_order: float = 0.05) -> Convergence:
    """Observed order, Richardson value and GCI from three (h, value) pairs in any order.

    The observed order is clipped to [``min_order``, ``max_order``]: a quantity with a known formal order
    (e.g. a crack compliance, O(h) near the tip) passes bounds around it so that an accidental p from
    irregular steps neither inflates nor shrinks its GCI beyond what the theory allows."""
    pairs = sorted(zip(h_mm, values))
    if len(pairs) != 3:
        raise ValueError("grid_convergence needs exactly three refinements")
    (h1, f1), (h2, f2), (h3, f3) = pairs
    if not h1 < h2 < h3:
        raise ValueError(f"mesh sizes must differ: {h1}, {h2}, {h3}")
    r21, r32 = h2 / h1, h3 / h2
    e21, e32 = f2 - f1, f3 - f2
    if e21 == 0.0:
        # The two finest meshes agree to round-off: the discretization error is below resolution.
        return Convergence((h1, h2, h3), (f1, f2, f3), math.inf, f1, 0.0, True, (min_order, max_order))
    ratio = e32 / e21
    monotone = ratio > 0
    s = 1.0 if monotone else -1.0
    p = abs(math.log(abs(ratio))) / math.log(r21) if ratio != 0 else max_order
    for _ in range(100):  # fixed-point iteration of the implicit equation for unequal ratios
        q = math.log(max((r21 ** p - s) / (r32 ** p - s), 1e-300))
        p_new = abs(math.log(abs(ratio)) + q) / math.log(r21) if ratio != 0 else max_order
        p_new = min(max(p_new, min_order), max_order)
        if abs(p_new - p) < 1e-10:
            break
        p = p_new
    p = min(max(p, min_order), max_order)
    extrapolated = (r21 ** p * f1 - f2) / (r21 ** p - 1.0)
    e_a21 = abs((f1 - f2) / f1) if f1 != 0 else abs(f1 - f2)
    gci = SAFETY_FACTOR_THREE_GRIDS * e_a21 / (r21 ** p - 1.0)
    if not monotone:
        # Oscillatory convergence: the order equation has no meaningful root (p is clipped), so a
        # Richardson-based GCI would be arbitrary. The error band is the spread of the three values,
        # with the three-grid safety factor, and the finest value is kept as the estimate.
        spread = (max(f1, f2, f3) - min(f1, f2, f3)) / abs(f1) if f1 != 0 else 0.0
        gci = SAFETY_FACTOR_THREE_GRIDS * spread
        extrapolated = f1
    return Convergence((h1, h2, h3), (f1, f2, f3), p, extrapolated, gci, monotone, (min_order, max_order))
