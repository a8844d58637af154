"""plasticity: yield at the load points, an elastic-plastic hinge: a knee and a permanent set on unloading.

Model: the plastic deflection follows the largest load reached so far, F_max(t):
    delta_p = a Y ((F_max - F_y)/X)+^n,
so loading beyond F_y bends the curve down (softening) and unloading is elastic, leaving delta_p.
"""
from __future__ import annotations

import numpy as np

from .base import Context, Effect, Param


def _contribution(ctx: Context, theta):
    a, f, n = theta
    peak = np.maximum.accumulate(ctx.u)
    return a * np.maximum(peak - f, 0.0) ** n


def _report(ctx: Context, theta, s: float) -> dict:
    a, f, n = theta
    peak = float(np.max(ctx.u))
    return {"yield_load": (f * ctx.X, ctx.load_unit),
            "permanent_set": (a * max(peak - f, 0.0) ** n * ctx.Y, ctx.response_unit),
            "hardening_exponent": (n, "1")}


EFFECT = Effect(
    id="plasticity",
    kinds=("ring_compression",),
    params=(Param("a", 0.0, 5.0, (0.1,)), Param("f", 0.05, 0.98, (0.4, 0.7)), Param("n", 1.0, 3.0, (1.5,))),
    contribution=_contribution,
    report=_report,
    explanation=("the rim yields at the load points: past the yield load plastic hinges turn, the curve "
                 "shows a knee, and a permanent set remains after unloading"),
)
