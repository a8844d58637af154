"""The closed form one check compares the FEA with, as a typed record handed from analytic to compare.

``published`` is the seed's form as printed, ``corrected`` the form the check asserts; ``beside`` holds further
forms shown next to them (never asserted). A missing form is None, never a default: a check whose asserted
form is None is reported as not evaluated. ``variants()`` is the JSON boundary (results.json, the sweep table).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = ["Reference"]


@dataclass(frozen=True)
class Reference:
    published: float | None
    corrected: float | None
    unit: str
    source: str                                   # which formula, from where
    beside: tuple[tuple[str, float], ...] = ()    # (name, value) of forms shown beside, not asserted

    def __post_init__(self):
        if not self.unit or not self.source:
            raise ValueError(f"Reference {self}: unit and source are required")

    def variants(self) -> dict[str, float]:
        """{variant: value} of the finite forms: published, corrected, then those beside."""
        pairs = (("published", self.published), ("corrected", self.corrected)) + self.beside
        return {k: float(v) for k, v in pairs if v is not None and math.isfinite(v)}

    def scaled(self, factor: float) -> "Reference":
        """The same forms at ``factor`` x the load (linear elasticity)."""
        return Reference(None if self.published is None else self.published * factor,
                         None if self.corrected is None else self.corrected * factor, self.unit, self.source,
                         tuple((k, v * factor) for k, v in self.beside))
