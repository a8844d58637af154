"""The grid-convergence table in the ASME V&V 20 (Roache) form, one row per FEA quantity of every case.

Columns: h1 < h2 < h3 (fine to coarse), f1, f2, f3, refinement ratios r21 = h2/h1 and r32 = h3/h2, the
observed order p (as found, never clipped) beside the formal order, the Richardson value f_ext, GCI_fine and
the basis of that GCI, all read from the study's own convergence record (``fea/convergence.grid_convergence``:
no second computation here). By the book (Roache; Oberkampf & Roy sec. 8.7) the GCI uses the observed order
with Fs = 1.25 only where the three meshes are in the asymptotic range (monotone, p within 10 % of the formal
order); otherwise Fs = 3 with the formal order, or the observed one where lower (never below 0.5). The flags
say why a row is not in the asymptotic range:

- "non-monotone": f2 - f1 and f3 - f2 change sign; p has no root, the band also covers the spread of the values.
- "diverging": p < 0, the steps grow on refinement.
- "p outside formal +-10 %": the observed order does not confirm the formal one (too slow, or error cancellation).
- "f1 = f2": the two finest agree; the coarse pair's change, carried down at the formal order, sets the band.
- "f_ext = f1": no extrapolation was made although f1 != f2 (non-monotone series).

Formal orders (``fea/convergence.formal_order``) for Lagrange elements of degree k on smooth solutions:
energy-type global quantities 2k; displacements k + 1; stresses and stress ratios k; crack compliances 1.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from strainwave.fea.convergence import ASYMPTOTIC_BAND, Convergence, formal_order

__all__ = ["GciRow", "formal_order", "asymptotic_flags", "gci_rows", "GCI_COLUMNS", "gci_cells"]

GCI_COLUMNS = ("case", "quantity", "h1 / h2 / h3 (mm)", "f1 (fine)", "f2", "f3", "r21", "r32",
               "p observed (formal)", "f_ext", "GCI fine", "GCI basis", "asymptotic range")


def asymptotic_flags(c: Convergence) -> tuple[str, ...]:
    """Why the three meshes of ``c`` are not in the asymptotic range; () if they are (the GCI then rests on
    the observed order with Fs = 1.25)."""
    f1, f2, _ = c.values
    p = c.observed_order
    flags = []
    if c.refused:
        return ("identical values: GCI refused",) if c.refused.startswith("three identical") else \
            (f"GCI refused: {c.refused}",)
    if not c.monotone:
        flags.append("non-monotone")
    elif math.isinf(p):
        flags.append("f1 = f2")
    elif math.isfinite(p) and p < 0:
        flags.append("diverging")
    elif not c.asymptotic:
        flags.append(f"p outside formal {c.formal_order:g} +-{100 * ASYMPTOTIC_BAND:g} %")
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
    basis: str
    flags: tuple[str, ...]

    @property
    def asymptotic(self) -> bool:
        return not self.flags

    def to_dict(self) -> dict:
        return {"case": self.case, "quantity": self.quantity, "unit": self.unit, "h_mm": list(self.h_mm),
                "values": list(self.values), "r21": self.r21, "r32": self.r32,
                "observed_order": self.observed_order if math.isfinite(self.observed_order) else None,
                "extrapolated": self.extrapolated,
                "gci_fine": self.gci_fine if math.isfinite(self.gci_fine) else None, "formal_order": self.formal_order,
                "kind": self.kind, "basis": self.basis, "flags": list(self.flags), "asymptotic": self.asymptotic}


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
            kind = formal_order(q.name, q.unit, order)[1]
            h = c.h_mm
            rows.append(GciRow(label, q.name, q.unit, h, c.values, h[1] / h[0], h[2] / h[1], c.observed_order,
                               c.extrapolated, c.gci_fine, c.formal_order, kind, c.basis, asymptotic_flags(c)))
    return rows


def gci_cells(row: dict) -> tuple[str, ...]:
    """One table row of the reports from a results.json ``gci_table`` entry."""
    p = row["observed_order"]
    p_text = ("- (no root)" if p is None else f"{p:.3g}") + f" ({row['formal_order']:g})"
    gci = row["gci_fine"]
    gci_text = f"{100 * gci:.3g} %" if gci is not None and math.isfinite(gci) else "refused"
    flags = "yes" if row["asymptotic"] else "NO: " + ", ".join(row["flags"])
    return (row["case"], f"{row['quantity']} [{row['unit']}]", " / ".join(f"{h:.3g}" for h in row["h_mm"]),
            *(f"{v:.6g}" for v in row["values"]), f"{row['r21']:.3g}", f"{row['r32']:.3g}", p_text,
            f"{row['extrapolated']:.6g}", gci_text, row.get("basis", "-"), flags)
