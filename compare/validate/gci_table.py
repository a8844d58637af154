"""The grid-convergence table in the ASME V&V 20 (Roache) form, one row per FEA quantity of every case.

Columns: h1 < h2 < h3 (fine to coarse), f1, f2, f3, refinement ratios r21 = h2/h1 and r32 = h3/h2, the
observed order p, the Richardson value f_ext and GCI_fine, all read from the study's own convergence record
(``fea/convergence.grid_convergence``: no second computation here), the formal order the element reaches on
the quantity, and flags where the three meshes are not in the asymptotic range, so that a GCI band is never
shown without saying how far it can be trusted:

- "non-monotone": f2 - f1 and f3 - f2 change sign; p has no root, the band is the spread of the three values.
- "p < 1": slower than first order: the meshes are far from asymptotic (or the field is singular there).
- "p above formal": faster than the element can converge: error cancellation between the meshes.
- "p fixed at k": the study set the order (equal bounds, e.g. crack compliances at 1), not the data.
- "p clipped": p sat on a bound of the study's range, not on a root of the order equation.
- "f_ext = f1": no extrapolation was made although f1 != f2 (non-monotone series).

Formal orders for Lagrange elements of degree k on smooth solutions: energy-type global quantities
(flexibility, compliance, the force for a prescribed displacement) 2k; displacements k + 1; stresses and stress
ratios k. Crack compliances: 1 whatever k (r^1/2 tip field without quarter-point nodes, fea/refinement.py).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ...fea.convergence import Convergence

__all__ = ["GciRow", "formal_order", "asymptotic_flags", "gci_rows", "GCI_COLUMNS", "gci_cells"]

GCI_COLUMNS = ("case", "quantity", "h1 / h2 / h3 (mm)", "f1 (fine)", "f2", "f3", "r21", "r32", "p (formal)",
               "f_ext", "GCI fine", "asymptotic range")


def formal_order(quantity: str, unit: str, element_order: int) -> tuple[float, str]:
    """(formal order, kind) of ``quantity`` computed with Lagrange elements of degree ``element_order``."""
    name = quantity.lower()
    if name.startswith(("delta_flexibility", "delta_radial_compliance")):
        return 1.0, "crack compliance"
    if unit == "MPa" or name in ("tooth_influence", "stress_concentration", "root_stress_factor"):
        return float(element_order), "stress"
    if "flexibility" in name or "compliance" in name or unit == "N":
        return 2.0 * element_order, "energy"
    return element_order + 1.0, "displacement"


def asymptotic_flags(c: Convergence, formal: float) -> tuple[str, ...]:
    """Why the three meshes of ``c`` are not (or cannot be shown to be) in the asymptotic range; () if they are."""
    f1, f2, _ = c.values
    p = c.observed_order
    flags = []
    if not c.monotone:
        flags.append("non-monotone")
    if c.order_fixed:
        flags.append(f"p fixed at {c.order_bounds[0]:g}")
    elif math.isfinite(p):
        if p < 1.0:
            flags.append("p < 1")
        if p > formal + 1e-9:
            flags.append(f"p above formal {formal:g}")
        if c.order_clipped:
            flags.append("p clipped")
    if c.extrapolated == f1 and f1 != f2:
        flags.append("f_ext = f1")
    return tuple(flags)


@dataclass(frozen=True)
class GciRow:
    case: str
    quantity: str
    unit: str
    h_mm: tuple[float, float, float]
    values: tuple[float, float, float]
    r21: float
    r32: float
    observed_order: float
    extrapolated: float
    gci_fine: float
    formal_order: float
    kind: str
    flags: tuple[str, ...]

    @property
    def asymptotic(self) -> bool:
        return not self.flags

    def to_dict(self) -> dict:
        return {"case": self.case, "quantity": self.quantity, "unit": self.unit, "h_mm": list(self.h_mm),
                "values": list(self.values), "r21": self.r21, "r32": self.r32,
                "observed_order": self.observed_order if math.isfinite(self.observed_order) else None,
                "extrapolated": self.extrapolated, "gci_fine": self.gci_fine, "formal_order": self.formal_order,
                "kind": self.kind, "flags": list(self.flags), "asymptotic": self.asymptotic}


def gci_rows(book, order: int) -> list[GciRow]:
    """Every quantity with three-mesh data, of every solved case of ``book`` (a FeaBook), in its order."""
    rows = []
    for label, outcome in book.outcomes.items():
        if outcome.result is None:
            continue
        for q in outcome.result.quantities.values():
            c = q.convergence
            if c is None:
                continue
            formal, kind = formal_order(q.name, q.unit, order)
            h = c.h_mm
            rows.append(GciRow(label, q.name, q.unit, h, c.values, h[1] / h[0], h[2] / h[1], c.observed_order,
                               c.extrapolated, c.gci_fine, formal, kind, asymptotic_flags(c, formal)))
    return rows


def gci_cells(row: dict) -> tuple[str, ...]:
    """One table row of the reports from a results.json ``gci_table`` entry."""
    p = row["observed_order"]
    p_text = ("inf (f1 = f2)" if p is None else f"{p:.3g}") + f" ({row['formal_order']:g})"
    flags = "yes" if row["asymptotic"] else "NO: " + ", ".join(row["flags"])
    return (row["case"], f"{row['quantity']} [{row['unit']}]", " / ".join(f"{h:.3g}" for h in row["h_mm"]),
            *(f"{v:.6g}" for v in row["values"]), f"{row['r21']:.3g}", f"{row['r32']:.3g}", p_text,
            f"{row['extrapolated']:.6g}", f"{100 * row['gci_fine']:.3g} %", flags)
