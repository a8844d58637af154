"""A stiffness ripple at twice the input angle read as a flexspline tooth-root crack breathing.

The wave generator's major axis passes every point of the flexspline twice per input turn. A crack at a tooth
root opens as the major axis passes it and closes between: the gear's torsional compliance ripples at twice the
input angle, and the twist it adds grows with the torque (unlike the kinematic error, a ripple at any load).
The catalogue names that ripple `stiffness_ripple` (a model linear in the torque); its 2x amplitude in % of the
gear's mean compliance is, to first order, the stiffness ripple in % of K_HD (K = 1/(c0 s (1 + r cos 2 theta))
swings by +/- r about the stiffness midway between its extremes).

Given the FEA's breathing-crack ripple against the crack depth (a crack_sizing.DeltaCurve in % of K_HD, the GCI
of each point as its uncertainty), the measured ripple is sized as any compliance change is
(crack_sizing.size_crack): the depth whose FEA ripple equals it, a k = 2 interval, or why the flexspline cannot
hold it (a ripple beyond the curve's deepest crack).
"""
from __future__ import annotations

from dataclasses import dataclass

from strainwave.compare.diagnose.crack_sizing import COVERAGE_K, CrackSize, DeltaCurve, size_crack

RIPPLE = "compliance_ripple_2x_percent"
SIGNIFICANT = 2.0          # standard errors: a ripple smaller than this is no evidence of a crack


@dataclass(frozen=True)
class RippleReading:
    ripple_percent: float            # the 2x stiffness ripple, % of K_HD
    std_error_percent: float
    resolved: bool                   # the ripple stands SIGNIFICANT standard errors above zero
    size: CrackSize | None           # the flexspline crack it implies (None without an FEA ripple curve)

    def line(self) -> str:
        head = (f"stiffness ripple at twice the input angle {self.ripple_percent:.3g} +/- "
                f"{self.std_error_percent:.2g} % of K_HD, growing with the torque: ")
        if not self.resolved:
            return head + f"not resolved (under {SIGNIFICANT:g} standard errors), no evidence of a breathing crack"
        fits = "what a flexspline tooth-root crack breathing as the major axis passes it draws (so does the mesh " \
               "stiffness variation)"
        return head + fits + ("" if self.size is None else f"; {self.size.line()}")

    def to_dict(self) -> dict:
        return {"ripple_percent_of_K": self.ripple_percent, "std_error_percent": self.std_error_percent,
                "resolved": self.resolved, "coverage_k": COVERAGE_K,
                "flexspline_crack": None if self.size is None else self.size.to_dict(), "line": self.line()}


def ripple_reading(diagnosis, curve: DeltaCurve | None = None) -> RippleReading | None:
    """The breathing-crack reading of a diagnosis whose named model holds the 2x stiffness ripple (None
    otherwise); ``curve``: the FEA's flexspline ripple (% of K_HD) against the tooth-root crack depth."""
    if not diagnosis.named or not diagnosis.effects:
        return None
    top = diagnosis.effects[0]
    key = next((k for k in top.parameters if k == RIPPLE or k.endswith("." + RIPPLE)), None)
    if key is None:
        return None
    ripple, se = float(top.parameters[key][0]), float(top.errors.get(key) or 0.0)
    resolved = ripple > SIGNIFICANT * se
    size = size_crack(ripple, se, [curve])[0] if curve is not None and resolved else None
    return RippleReading(ripple, se, resolved, size)


__all__ = ["RippleReading", "ripple_reading"]
