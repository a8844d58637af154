"""Check records: one FEA number confronted with the published and corrected closed forms.

A check asserts agreement with ONE named variant (usually ``corrected``); the other variant is
reported with its relative error so the verdict can say which one the FEA supports. A check that
cannot be evaluated (study missing or failed, closed form missing) is reported as such and does not
pass: a number that was not computed is never replaced by a guess.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

VARIANTS = ("published", "corrected")


@dataclass(frozen=True)
class Tolerance:
    """Relative tolerance on |fea/analytic - 1| and the reason it has that size."""

    relative: float
    reason: str
    gci: float = math.nan          # the GCI's share of ``relative`` (the rest: named allowances); NaN: not split

    @property
    def allowances(self) -> float:
        return self.relative - (self.gci if math.isfinite(self.gci) else 0.0)

    def to_dict(self) -> dict:
        return {"relative": _finite_or_none(self.relative), "reason": self.reason, "gci": _finite_or_none(self.gci)}


def fea_tolerance(fea: float | None, fea_uncertainty: float | None, *, allowances: dict[str, float],
                  basis: str = "") -> Tolerance:
    """Tolerance = the FEA's GCI + named modelling allowances (docs/verification.md, "Check tolerances").

    The GCI is Roache's Fs |e_ext| (``fea.convergence``): it already holds its safety factor (1.25 where three
    meshes show the asymptotic range, 3 otherwise), so it is added once, never multiplied again. ``basis``: the
    GCI's order and Fs in words (``Convergence.basis``), quoted in the reason. Each allowance is a relative size
    with the reason as its key, e.g. ``{"mu = 8e4 vs E/2(1+nu) = 80769 (seed 000, audit 18)": 0.0096}``.
    """
    rel_u = 0.0
    if fea not in (None, 0.0) and fea_uncertainty is not None and math.isfinite(fea_uncertainty):
        rel_u = abs(fea_uncertainty / fea)
    total = rel_u + sum(allowances.values())
    parts = [f"GCI {100 * rel_u:.3g} % ({basis or 'Fs inside'})"]
    parts += [f"{100 * v:.3g} % {why}" for why, v in allowances.items()]
    return Tolerance(total, " + ".join(parts), rel_u)


def gci_basis(quantity) -> str:
    """The GCI's order and safety factor in words (``Convergence.basis``), "" when the quantity carries none."""
    conv = getattr(quantity, "convergence", None)
    return "" if conv is None else conv.basis


RELATIONS = ("equal", "at_most")


@dataclass(frozen=True)
class Check:
    id: str
    quantity: str
    unit: str
    fea: float | None
    fea_uncertainty: float | None
    analytic: dict[str, float]                   # variant -> value (published / corrected where both exist)
    asserts: str                                 # the variant the check requires agreement with
    tolerance: Tolerance
    rel_error: dict[str, float] = field(default_factory=dict)
    verdict: str = "not evaluated"               # published | corrected | both | neither | not evaluated
    passed: bool = False
    note: str = ""                               # what is FEA, what is analytic, caveats
    sources: dict[str, str] = field(default_factory=dict)   # ingredient -> "FEA ..." / "analytic ..."
    reason_not_evaluated: str = ""
    relation: str = "equal"                      # "equal": |rel error| <= tol; "at_most": rel error <= tol

    def __post_init__(self):
        if self.relation not in RELATIONS:
            raise ValueError(f"check {self.id}: relation {self.relation!r} must be one of {RELATIONS}")

    @property
    def component(self) -> str:
        return self.id.split(".", 1)[0]

    def to_dict(self) -> dict:
        return {"id": self.id, "component": self.component, "quantity": self.quantity, "unit": self.unit,
                "fea": _finite_or_none(self.fea), "fea_uncertainty": _finite_or_none(self.fea_uncertainty),
                "analytic": {k: _finite_or_none(v) for k, v in self.analytic.items()},
                "asserts": self.asserts,
                "rel_error": {k: _finite_or_none(v) for k, v in self.rel_error.items()},
                "tolerance": self.tolerance.to_dict(), "verdict": self.verdict, "passed": self.passed,
                "note": self.note, "sources": dict(self.sources),
                "reason_not_evaluated": self.reason_not_evaluated, "relation": self.relation}


def _finite_or_none(value):
    if value is None:
        return None
    value = float(value)
    return value if math.isfinite(value) else None


def relative_error(fea: float, reference: float) -> float:
    """(fea - reference) / |reference|; signed so the report shows which side FEA lies on."""
    if reference == 0.0:
        return math.inf if fea != 0.0 else 0.0
    return (fea - reference) / abs(reference)



def within(rel_error: float, tolerance: float, relation: str = "equal") -> bool:
    """``equal``: |e| <= tol. ``at_most`` (the closed form is an upper bound, e.g. the compliance of a whole
    assembly against one of its series members): e <= tol."""
    return (rel_error if relation == "at_most" else abs(rel_error)) <= tolerance


def verdict_of(rel_error: dict[str, float], tolerance: float, relation: str = "equal") -> str:
    """Which variant the FEA supports: the one(s) inside the tolerance, else ``neither``."""
    inside = [v for v in VARIANTS if v in rel_error and within(rel_error[v], tolerance, relation)]
    if len(inside) == 2:
        return "both"
    return inside[0] if inside else "neither"


# --quick: a check whose coarse-mesh GCI exceeds its named allowances by more than this is not resolved there. A
# resolved one has tolerance <= 2 x allowances + 1 %, and the full run's tolerance is never below its allowances,
# so --quick never allows more than twice the full run's tolerance plus one point.
QUICK_GCI_FLOOR = 0.01
NOT_RESOLVED_AT_QUICK = "not resolved at --quick"


def quick_resolution(check: Check) -> Check:
    """``check`` as --quick reports it: unchanged when its GCI is at most its named allowances + 1 %; otherwise
    not resolved at --quick (not evaluated, so not passed), with the numbers."""
    tol = check.tolerance
    if (check.verdict == "not evaluated" or not math.isfinite(tol.gci)
            or tol.gci <= tol.allowances + QUICK_GCI_FLOOR):
        return check
    why = (f"{NOT_RESOLVED_AT_QUICK}: GCI {100 * tol.gci:.3g} % on the coarse meshes exceeds the named allowances "
           f"({100 * tol.allowances:.3g} %) by more than {100 * QUICK_GCI_FLOOR:g} %: its tolerance "
           f"({100 * tol.relative:.3g} %) could be more than twice the full run's; run without --quick")
    return replace(check, verdict="not evaluated", passed=False, reason_not_evaluated=why)


def evaluate(check: Check) -> Check:
    """Fill ``rel_error``, ``verdict`` and ``passed`` of a check whose inputs are set."""
    if check.fea is None or not math.isfinite(check.fea):
        return replace(check, verdict="not evaluated", passed=False,
                       reason_not_evaluated=check.reason_not_evaluated or "no FEA value")
    analytic = {k: v for k, v in check.analytic.items() if v is not None and math.isfinite(v)}
    if check.asserts not in analytic:
        return replace(check, verdict="not evaluated", passed=False,
                       reason_not_evaluated=check.reason_not_evaluated or f"no {check.asserts} closed form")
    errors = {k: relative_error(check.fea, v) for k, v in analytic.items()}
    verdict = verdict_of(errors, check.tolerance.relative, check.relation)
    passed = within(errors[check.asserts], check.tolerance.relative, check.relation)
    return replace(check, rel_error=errors, verdict=verdict, passed=passed, reason_not_evaluated="")


def not_evaluated(check_id: str, quantity: str, unit: str, why: str, *, analytic: dict | None = None,
                  asserts: str = "corrected") -> Check:
    """A required check whose inputs do not exist; it is listed and counted as failed."""
    return Check(check_id, quantity, unit, None, None, dict(analytic or {}), asserts,
                 Tolerance(math.nan, "not evaluated"), verdict="not evaluated", passed=False,
                 reason_not_evaluated=why)


def __getattr__(name: str):
    """``REQUIRED_IDS``: the ids of ``check_list.CHECKS``, in the report's order (derived, never restated)."""
    if name == "REQUIRED_IDS":
        from strainwave.compare.validate.check_list import REQUIRED_IDS
        return REQUIRED_IDS
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
