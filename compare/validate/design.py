"""The design verdict: does this drive meet the permissible safety factor [n] at its rated load?

The validation verdict asks whether the closed forms hold (the FEA against the seeds); this one asks whether
the drive as designed is strong enough. Each component carries one ``ComponentFactor``: its safety factor,
the stress and limit it is the ratio of, and the factor's definition. Where its stresses carry a GCI, the factor
carries the band they span: a band that straddles [n] is UNDECIDED (the meshes cannot tell), counted as not
met. A component factor another study adds
(a fatigue factor of the wave generator's cup, say) is one more entry of ``factors``: the verdict and both
reports read the list, nothing else. The exit status of ``strainwave validate`` stays the validation's;
``--require-design`` makes a failing design exit 3.
"""
from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from typing import Callable

__all__ = ["ComponentFactor", "DesignVerdict", "design_verdict", "factor_band", "REQUIRED_SOURCE"]

REQUIRED_SOURCE = "ewg_drive.permissible_safety, seed 003 eq 12 (the seed's [n], 1.3..1.5)"


@dataclass(frozen=True)
class ComponentFactor:
    """One component's safety factor at the rated load (None: not evaluated, with ``reason``)."""
    component: str            # key, e.g. "ring"
    title: str                # e.g. "EWG flexspline ring"
    safety_factor: float | None
    definition: str           # what the factor is the ratio of, in words and symbols
    stress_MPa: float | None  # the stress the factor is taken on
    limit_MPa: float | None   # the limit it is compared with
    load: str                 # the load it is at
    reason: str = ""          # why it is not evaluated
    band: tuple[float, float] | None = None   # the factor's lowest and highest over its stresses' GCI bands
    static_n: float | None = None             # R_p0.2 over the cycle's peak (analytic/design_method.py)
    fatigue: dict | None = None               # the factor's inputs (design.csv's row, FatigueFactor.to_dict)

    @classmethod
    def of(cls, factor) -> "ComponentFactor":
        """The verdict's entry for an ``analytic.design_method.FatigueFactor``."""
        return cls(factor.component, factor.title, factor.n,
                   f"{factor.criterion}: sigma_a {factor.amplitude_MPa:.4g} MPa ({factor.amplitude_source}), sigma_m "
                   f"{factor.mean_MPa:.4g} MPa ({factor.mean_source}), K = {factor.notch:.3g} ({factor.notch_source}); "
                   f"{factor.strength.name}", factor.notch * factor.amplitude_MPa, factor.strength.fatigue_limit_MPa,
                   factor.load, band=factor.band, static_n=factor.static_n, fatigue=factor.to_dict())

    def verdict(self, required: float) -> str:
        """PASS or FAIL against [n] (and, where it is given, the static check n_static >= 1); UNDECIDED where its
        band straddles [n]; NOT EVALUATED without a factor."""
        n = self.safety_factor
        if n is None or math.isnan(n):   # inf: no demand (a compressive mean, no amplitude): passes
            return "NOT EVALUATED"
        if self.static_n is not None and self.static_n < 1.0:
            return "FAIL"
        low, high = self.band or (n, n)
        if min(low, n) >= required:
            return "PASS"
        return "FAIL" if max(high, n) < required else "UNDECIDED"

    def passed(self, required: float) -> bool:
        return self.verdict(required) == "PASS"

    def to_dict(self, required: float) -> dict:
        return {"component": self.component, "title": self.title, "safety_factor": self.safety_factor,
                "required": required, "passed": self.passed(required), "verdict": self.verdict(required),
                "band": None if self.band is None else list(self.band), "definition": self.definition,
                "stress_MPa": self.stress_MPa, "limit_MPa": self.limit_MPa, "load": self.load,
                "reason": self.reason, "static_n": self.static_n, "fatigue": self.fatigue}


@dataclass(frozen=True)
class DesignVerdict:
    required: float
    factors: tuple[ComponentFactor, ...]

    @property
    def passed(self) -> bool:
        return bool(self.factors) and all(f.passed(self.required) for f in self.factors)

    @property
    def failing(self) -> list[ComponentFactor]:
        return [f for f in self.factors if not f.passed(self.required)]

    def headline(self) -> str:
        n = len(self.factors)
        text = (f"{'PASS' if self.passed else 'FAIL'}: {n - len(self.failing)} of {n} components meet [n] = "
                f"{self.required:g} at the rated load")
        below = [f for f in self.failing if f.verdict(self.required) == "FAIL"]
        undecided = [f for f in self.failing if f.verdict(self.required) == "UNDECIDED"]
        unknown = [f for f in self.failing if f.safety_factor is None]
        if below:
            text += "; below [n]: " + ", ".join(f"{f.title} n = {f.safety_factor:.3g}" for f in below)
        if undecided:
            text += ("; undecided, [n] within the band the FEA's GCIs give (counted as failing): "
                     + ", ".join(f"{f.title} n = {f.safety_factor:.3g} ({f.band[0]:.3g}..{f.band[1]:.3g})"
                                 for f in undecided))
        if unknown:
            text += "; not evaluated (counted as failing): " + ", ".join(f.title for f in unknown)
        return text

    def to_dict(self) -> dict:
        return {"passed": self.passed, "headline": self.headline(), "required_safety_factor": self.required,
                "required_source": REQUIRED_SOURCE, "factors": [f.to_dict(self.required) for f in self.factors],
                "failing": [f.component for f in self.failing]}


def factor_band(factor: Callable[..., float], *stresses: tuple[float, float | None]) -> tuple[float, float] | None:
    """(lowest, highest) of ``factor(*values)`` over the corners of the stresses' bands, each stress given as
    (value, GCI); None when any stress has no GCI (a band it cannot give)."""
    if any(u is None or not math.isfinite(u) for _, u in stresses):
        return None
    corners = [factor(*(v + s * abs(u) for (v, u), s in zip(stresses, signs)))
               for signs in itertools.product((-1.0, 1.0), repeat=len(stresses))]
    return min(corners), max(corners)


def design_verdict(params, factors: list[ComponentFactor]) -> DesignVerdict:
    """The verdict of ``factors`` against the parameters' [n]."""
    return DesignVerdict(float(params.ewg_drive.permissible_safety), tuple(factors))
