"""Read access to the solved cases: one quantity of one case, or why it is not there.

Also gathers a component's crack-depth sweep (depth, delta, uncertainty) from the headline case and the
sweep cases, so checks, the audit and the plots all read the same numbers.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from strainwave.fea.result import Quantity, StudyResult
from strainwave.compare.validate.runner import CaseOutcome


@dataclass(frozen=True)
class Sweep:
    component: str
    quantity: str
    unit: str
    depths_mm: tuple[float, ...]
    values: tuple[float, ...]
    uncertainties: tuple[float, ...]     # absolute, from each case's GCI (0 if the study gave none)

    def resolved(self, factor: float = 1.0) -> np.ndarray:
        """Mask of depths where the crack effect exceeds ``factor`` x its own uncertainty and is positive."""
        v, u = np.asarray(self.values), np.asarray(self.uncertainties)
        return (v > 0) & (v > factor * u)

    def to_dict(self) -> dict:
        return {"component": self.component, "quantity": self.quantity, "unit": self.unit,
                "depths_mm": list(self.depths_mm), "fea": list(self.values),
                "fea_uncertainty": list(self.uncertainties), "resolved": self.resolved().tolist()}


@dataclass(frozen=True)
class FeaBook:
    outcomes: dict[str, CaseOutcome]

    def quantity(self, label: str, name: str) -> tuple[Quantity | None, str]:
        """The quantity, or None and the reason (case failed, not run, or quantity not produced)."""
        outcome = self.outcomes.get(label)
        if outcome is None:
            return None, f"case {label} was not run"
        if outcome.result is None:
            return None, f"case {label} failed: {outcome.error}"
        if name not in outcome.result.quantities:
            have = ", ".join(sorted(outcome.result.quantities))
            return None, f"{outcome.case.study} produced no {name} (it has: {have})"
        return outcome.result.quantities[name], ""

    def result(self, label: str) -> StudyResult | None:
        """The solved case's typed result (its load, supports, crack, solver facts), or None if it failed."""
        outcome = self.outcomes.get(label)
        return None if outcome is None else outcome.result

    def applied_force_N(self, label: str) -> float | None:
        """The force the case's study applied (its typed ``Load``), or None (failed, or a torque load)."""
        result = self.result(label)
        return None if result is None else result.load.force_N

    def sweep(self, component: str, labels: list[str], name: str) -> Sweep | None:
        """The crack sweep of ``component`` over the cases ``labels`` that produced ``name``."""
        rows = []
        unit = ""
        for label in labels:
            q, _ = self.quantity(label, name)
            if q is None:
                continue
            depth = self.outcomes[label].case.crack_depth_mm
            rows.append((depth, q.value, q.uncertainty or 0.0))
            unit = q.unit
        if not rows:
            return None
        rows.sort()
        depths, values, unc = zip(*rows)
        return Sweep(component, name, unit, tuple(depths), tuple(values), tuple(unc))
