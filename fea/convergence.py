"""Discretization error from three refinements: observed order, Richardson extrapolation, GCI by the book.

Roache's grid convergence index as adopted by ASME V&V 20: with h1 < h2 < h3 (fine to coarse),
refinement ratios r21 = h2/h1, r32 = h3/h2, the observed order p solves

    p = |ln|e32/e21| + q(p)| / ln r21,   q(p) = ln((r21^p - s)/(r32^p - s)),  s = sign(e32/e21)

and GCI_fine = Fs |e_a21| / (r21^p - 1). Which p and Fs (Roache 1998; Oberkampf & Roy 2010, sec. 8.7):

- the observed order is used, with Fs = 1.25, only where the three meshes are in the asymptotic range:
  monotone convergence and p within ``ASYMPTOTIC_BAND`` (10 %) of the formal order;
- otherwise Fs = 3 with the formal order of the quantity (``formal_order``), or the observed order where that
  is lower, never below 0.5 (Oberkampf & Roy: p = min(max(0.5, p_observed), p_formal)): a series converging
  slower than its element's formal order must not borrow the faster order's smaller band.

The observed order is never clipped: it is stored as found (NaN where the order equation has no root,
inf where the two finest values agree) so that a table shows it beside the order actually used.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

SAFETY_FACTOR_THREE_GRIDS = 1.25
SAFETY_FACTOR_FORMAL = 3.0
# |p_observed - p_formal| <= 0.1 p_formal: Oberkampf & Roy (2010), sec. 8.7.2, the band in which
# the observed order is taken as confirming the asymptotic range
ASYMPTOTIC_BAND = 0.1
# Lowest formal order of a smooth quantity on the project's curved P2 elements (stresses): the order
# assumed when a caller names none, so an unnamed quantity never gets a less conservative band.
DEFAULT_FORMAL_ORDER = 2.0
# Outside the asymptotic range an observed order below the formal one is used, but never below this
MIN_ORDER_OUTSIDE = 0.5


class GciUndefined(ValueError):
    """Three refinements that cannot carry a GCI (all three values identical)."""


def formal_order(quantity: str, unit: str, element_order: int = 2) -> tuple[float, str]:
    """(formal order, kind) of ``quantity`` computed with Lagrange elements of degree ``element_order``:
    energy-type global quantities 2k, displacements k + 1, stresses and stress ratios k, crack
    compliances 1 whatever k (r^1/2 tip field without quarter-point nodes)."""
    name = quantity.lower()
    if name.startswith(("delta_flexibility", "delta_radial_compliance")):
        return 1.0, "crack compliance"
    if unit == "MPa" or name in ("tooth_influence", "stress_concentration", "root_stress_factor"):
        return float(element_order), "stress"
    if "flexibility" in name or "compliance" in name or unit == "N":
        return 2.0 * element_order, "energy"
    return element_order + 1.0, "displacement"


@dataclass(frozen=True)
class Convergence:
    """A headline quantity on three meshes, fine first."""

    h_mm: tuple[float, float, float]
    values: tuple[float, float, float]
    observed_order: float    # as found: NaN = no root (oscillatory), inf = f1 == f2
    extrapolated: float
    gci_fine: float          # relative, e.g. 0.001 = 0.1 %
    monotone: bool
    formal_order: float = DEFAULT_FORMAL_ORDER
    order_used: float = math.nan
    safety_factor: float = SAFETY_FACTOR_THREE_GRIDS
    refused: str = ""        # why no GCI was formed (then gci_fine is NaN, never 0)

    @classmethod
    def refusal(cls, h_mm, values, why: str, formal: float = DEFAULT_FORMAL_ORDER) -> "Convergence":
        """The record of three meshes that carry no GCI (``GciUndefined``): values kept, band NaN."""
        pairs = sorted(zip(h_mm, values))
        return cls(tuple(h for h, _ in pairs), tuple(v for _, v in pairs), math.nan, pairs[0][1], math.nan, True,
                   formal, math.nan, math.nan, why)

    @property
    def asymptotic(self) -> bool:
        """The observed order confirmed the asymptotic range (and so was used, with Fs = 1.25)."""
        return self.safety_factor == SAFETY_FACTOR_THREE_GRIDS

    @property
    def basis(self) -> str:
        """Which order and safety factor the GCI rests on, in words (the GCI table's column)."""
        if self.refused:
            return "GCI refused: " + self.refused
        if self.asymptotic:
            return f"observed p = {self.order_used:.3g}, Fs = 1.25"
        if self.order_used < self.formal_order:
            return f"observed p = {self.order_used:.3g} (< formal {self.formal_order:g}), Fs = 3"
        return f"formal p = {self.order_used:g}, Fs = 3"

    @property
    def uncertainty(self) -> float:
        """Absolute uncertainty of the finest value (GCI times |value|)."""
        return self.gci_fine * abs(self.values[0])

    def to_dict(self) -> dict:
        return {"h_mm": list(self.h_mm), "values": list(self.values), "observed_order": self.observed_order,
                "extrapolated": self.extrapolated, "gci_fine": self.gci_fine, "monotone": self.monotone,
                "formal_order": self.formal_order, "order_used": self.order_used,
                "safety_factor": self.safety_factor, "basis": self.basis, "uncertainty": self.uncertainty,
                "refused": self.refused}

    @classmethod
    def from_dict(cls, c: dict) -> "Convergence":
        return cls(tuple(c["h_mm"]), tuple(c["values"]), c["observed_order"], c["extrapolated"], c["gci_fine"],
                   c["monotone"], c.get("formal_order", DEFAULT_FORMAL_ORDER), c.get("order_used", math.nan),
                   c.get("safety_factor", SAFETY_FACTOR_THREE_GRIDS), c.get("refused", ""))


def observed_order(r21: float, r32: float, e21: float, e32: float) -> float:
    """The root of the order equation for monotone steps (e32 / e21 > 0), unclipped and signed (p < 0: the
    steps grow on refinement); NaN for oscillatory steps or when the fixed-point iteration does not settle."""
    ratio = e32 / e21
    if ratio <= 0:
        return math.nan

    def q(p: float) -> float:
        # ln((r21^p - 1) / (r32^p - 1)), with its p -> 0 limit ln(ln r21 / ln r32)
        if abs(p) < 1e-12:
            return math.log(math.log(r21) / math.log(r32))
        return math.log((r21 ** p - 1.0) / (r32 ** p - 1.0))

    p = math.log(ratio) / math.log(r21)
    try:
        for _ in range(500):
            p_new = (math.log(ratio) + q(p)) / math.log(r21)
            if abs(p_new - p) < 1e-12 * max(1.0, abs(p)):
                return p_new
            p = p_new
    except (OverflowError, ValueError):      # r^p beyond float range: no usable root
        return math.nan
    return math.nan


def grid_convergence(h_mm, values, *, formal_order: float = DEFAULT_FORMAL_ORDER) -> Convergence:
    """Observed order, Richardson value and GCI from three (h, value) pairs in any order, by the rule in
    the module docstring. Raises GciUndefined for three identical values and ValueError for equal sizes."""
    pairs = sorted(zip(h_mm, values))
    if len(pairs) != 3:
        raise ValueError("grid_convergence needs exactly three refinements")
    (h1, f1), (h2, f2), (h3, f3) = pairs
    if not h1 < h2 < h3:
        raise ValueError(f"mesh sizes must differ: {h1}, {h2}, {h3}")
    if not formal_order > 0:
        raise ValueError(f"formal_order must be > 0, got {formal_order!r}")
    if f1 == f2 == f3:
        raise GciUndefined(f"three identical values ({f1!r}) on h = {h1:g}, {h2:g}, {h3:g} mm: the meshes do not "
                           "change the quantity, so no GCI can be formed; change the mesh family (sizes or "
                           "local refinement) or report the value without a GCI")
    r21, r32 = h2 / h1, h3 / h2
    e21, e32 = f2 - f1, f3 - f2
    scale = abs(f1) if f1 != 0 else 1.0
    pf = float(formal_order)
    if e21 == 0.0:
        # the two finest agree to round-off: the coarse pair's change, carried to the fine mesh at the formal order
        gci = SAFETY_FACTOR_FORMAL * abs(e32) / scale / (r32 ** pf - 1.0) / r21 ** pf
        return Convergence((h1, h2, h3), (f1, f2, f3), math.inf, f1, gci, True, pf, pf, SAFETY_FACTOR_FORMAL)
    monotone = e32 / e21 > 0
    p_obs = observed_order(r21, r32, e21, e32)
    e_a21 = abs(e21) / scale
    if monotone and math.isfinite(p_obs) and abs(p_obs - pf) <= ASYMPTOTIC_BAND * pf:
        extrapolated = (r21 ** p_obs * f1 - f2) / (r21 ** p_obs - 1.0)
        gci = SAFETY_FACTOR_THREE_GRIDS * e_a21 / (r21 ** p_obs - 1.0)
        return Convergence((h1, h2, h3), (f1, f2, f3), p_obs, extrapolated, gci, True, pf, p_obs,
                           SAFETY_FACTOR_THREE_GRIDS)
    p = min(max(MIN_ORDER_OUTSIDE, p_obs), pf) if monotone and math.isfinite(p_obs) else pf
    gci = SAFETY_FACTOR_FORMAL * e_a21 / (r21 ** p - 1.0)
    extrapolated = (r21 ** p * f1 - f2) / (r21 ** p - 1.0)
    if not monotone:
        # oscillatory: Richardson has no basis; the band also covers the spread of the three values
        spread = (max(f1, f2, f3) - min(f1, f2, f3)) / scale
        gci = max(gci, SAFETY_FACTOR_THREE_GRIDS * spread)
        extrapolated = f1
    return Convergence((h1, h2, h3), (f1, f2, f3), p_obs, extrapolated, gci, monotone, pf, p, SAFETY_FACTOR_FORMAL)
