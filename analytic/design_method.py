"""One fatigue method for every component of the drive (issue 49).

Every design factor is one ``FatigueFactor``: the stress cycle a point runs through (amplitude sigma_a and
mean sigma_m, each with where it comes from), ONE notch factor K on the amplitude (the tooth factors
K_delta K_sigma on a smooth-ring stress, or 1 where the stress is already the FEA's own notched peak: never
both), the criterion and the material. The criterion is Goodman's line, the same everywhere:

    n = 1 / (K sigma_a / sigma_-1 + max(sigma_m, 0) / R_m)

(Goodman 1899; Shigley's Mechanical Engineering Design, 10th ed., eq. 6-41; the notch on the amplitude only,
as seed 003's eq 13 takes it: ductile steel, the mean relaxes at a notch; a compressive mean is not credited).
Seed 003's eq 13 is the same line with psi_sigma = sigma_-1/R_m replaced by the seed's 0.12: it is shown, not
used. Beside it, the static check against the first yield: n_static = R_p0.2 / (|sigma_m| + K sigma_a) (the
largest stress of the cycle at the notch).

``solve_for`` turns a failing factor into advice: the one value of one parameter at which the factor equals
[n], found by bracketing and bisection (Brent) on the factor as a function of that parameter.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

__all__ = ["Strength", "FatigueFactor", "goodman", "static_factor", "flexspline_steel", "bearing_steel",
           "solve_for", "Advice", "CRITERION", "CRITERION_SOURCE"]

CRITERION = "Goodman"
CRITERION_SOURCE = ("Goodman line, notch factor on the amplitude, compressive mean not credited (Shigley, Mechanical "
                    "Engineering Design, 10th ed., eq. 6-41; seed 003 eq 13's form with psi = sigma_-1/R_m)")


@dataclass(frozen=True)
class Strength:
    """One material of the materials table."""
    name: str
    fatigue_limit_MPa: float
    yield_strength_MPa: float
    ultimate_strength_MPa: float
    source: str

    def to_dict(self) -> dict:
        return dict(self.__dict__)


def flexspline_steel(params) -> Strength:
    m = params.material
    return Strength(m.name, m.fatigue_limit_MPa, m.yield_strength_MPa, m.ultimate_strength_MPa, m.source)


def bearing_steel(params) -> Strength:
    b = params.bearing_material
    return Strength(b.name, b.fatigue_limit_MPa, b.yield_strength_MPa, b.ultimate_strength_MPa, b.source)


def goodman(amplitude_MPa: float, mean_MPa: float, notch: float, strength: Strength) -> float:
    """n = 1 / (K sigma_a / sigma_-1 + max(sigma_m, 0) / R_m) (module docstring); inf without a demand."""
    demand = notch * abs(amplitude_MPa) / strength.fatigue_limit_MPa + max(mean_MPa, 0.0) / strength.ultimate_strength_MPa
    return math.inf if demand <= 0.0 else 1.0 / demand


def static_factor(amplitude_MPa: float, mean_MPa: float, notch: float, strength: Strength) -> float:
    """n_static = R_p0.2 / (|sigma_m| + K sigma_a): the cycle's largest stress at the notch against first yield."""
    peak = abs(mean_MPa) + notch * abs(amplitude_MPa)
    return math.inf if peak <= 0.0 else strength.yield_strength_MPa / peak


@dataclass(frozen=True)
class Advice:
    """The one value of ``key`` that brings the factor to [n] (None: no value in the searched range does)."""
    key: str
    value: float | None
    relation: str          # ">=" or "<=": which side of ``value`` meets [n]
    searched: tuple[float, float]
    note: str = ""

    def text(self) -> str:
        if self.value is None:
            return (f"no value of {self.key} in {self.searched[0]:g}..{self.searched[1]:g} brings it to [n]"
                    + (f" ({self.note})" if self.note else ""))
        return f"{self.key} {self.relation} {self.value:.4g}" + (f" ({self.note})" if self.note else "")


@dataclass(frozen=True)
class FatigueFactor:
    """One component's design factor at the rated load, with every input it is computed from."""
    component: str
    title: str
    amplitude_MPa: float
    mean_MPa: float
    amplitude_source: str
    mean_source: str
    notch: float                  # K on the amplitude (1: the stress is the FEA's own notched peak)
    notch_source: str
    strength: Strength
    required: float               # [n]
    load: str
    band: tuple[float, float] | None = None
    advice: Advice | None = None
    admissible: Advice | None = None    # the value of a sizing parameter up to which the factor holds [n], pass or fail
    criterion: str = CRITERION
    criterion_source: str = CRITERION_SOURCE
    extra: dict = field(default_factory=dict)

    @property
    def n(self) -> float:
        return goodman(self.amplitude_MPa, self.mean_MPa, self.notch, self.strength)

    @property
    def static_n(self) -> float:
        return static_factor(self.amplitude_MPa, self.mean_MPa, self.notch, self.strength)

    def verdict(self) -> str:
        low, high = self.band or (self.n, self.n)
        if min(low, self.n) >= self.required and self.static_n >= 1.0:
            return "PASS"
        return "FAIL" if max(high, self.n) < self.required or self.static_n < 1.0 else "UNDECIDED"

    def row(self) -> dict:
        """design.csv's row: every input of the factor, and the factor."""
        return {"component": self.component, "title": self.title, "criterion": self.criterion,
                "amplitude_MPa": self.amplitude_MPa, "mean_MPa": self.mean_MPa, "notch_K": self.notch,
                "fatigue_limit_MPa": self.strength.fatigue_limit_MPa,
                "ultimate_strength_MPa": self.strength.ultimate_strength_MPa,
                "yield_strength_MPa": self.strength.yield_strength_MPa, "n": self.n, "required_n": self.required,
                "static_n": self.static_n, "verdict": self.verdict(), "material": self.strength.name,
                "band_low": None if self.band is None else self.band[0],
                "band_high": None if self.band is None else self.band[1],
                "amplitude_source": self.amplitude_source, "mean_source": self.mean_source,
                "notch_source": self.notch_source, "load": self.load,
                "advice": "" if self.advice is None else self.advice.text(),
                "admissible": "" if self.admissible is None else self.admissible.text()}

    def to_dict(self) -> dict:
        return {**self.row(), "criterion_source": self.criterion_source, "material_source": self.strength.source,
                **({"extra": self.extra} if self.extra else {})}


def solve_for(key: str, factor_of: Callable[[float], float], target: float, current: float, lo: float, hi: float,
              note: str = "") -> Advice:
    """The value of ``key`` in [lo, hi] where ``factor_of(value) = target``, on the side of ``current``'s
    root that meets it (Brent's method between the two nearest samples that bracket the root)."""
    import warnings

    from scipy.optimize import brentq

    with warnings.catch_warnings():     # the search passes values outside the recommended ranges on purpose
        warnings.simplefilter("ignore")
        return _solve(key, factor_of, target, current, lo, hi, note, brentq)


def _solve(key, factor_of, target, current, lo, hi, note, brentq) -> Advice:
    grid = [lo + (hi - lo) * i / 40 for i in range(41)]
    values = []
    for x in grid:
        try:
            values.append(factor_of(x) - target)
        except (ValueError, ArithmeticError):
            values.append(math.nan)
    brackets = [(grid[i], grid[i + 1]) for i in range(40)
                if math.isfinite(values[i]) and math.isfinite(values[i + 1]) and values[i] * values[i + 1] <= 0]
    if not brackets:
        return Advice(key, None, "", (lo, hi), note)
    x0, x1 = min(brackets, key=lambda b: abs(0.5 * (b[0] + b[1]) - current))
    root = brentq(lambda x: factor_of(x) - target, x0, x1, xtol=1e-6 * max(1.0, abs(x1)))
    # which side meets [n]: a step from the root toward the side of larger factor
    step = 1e-3 * max(abs(root), 1e-3)
    relation = ">=" if factor_of(min(root + step, hi)) >= factor_of(max(root - step, lo)) else "<="
    return Advice(key, root, relation, (lo, hi), note)
