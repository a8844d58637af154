"""nonlinear_stiffness: stiffness that rises with load as tooth contact spreads (catalogue K1 < K2 < K3).

Model (Harmonic Drive's three-slope stiffness curve, odd in the load):
    twist = sgn(T) [ |T|/K1 - (1/K1 - 1/K2) (|T| - T1)+ - (1/K2 - 1/K3) (|T| - T2)+ ]
In normalised units with s/K1 = s c0: y += -sgn(u) [a1 (|u| - p1)+ + a2 (|u| - p2)+], p2 = p1 + g,
a1, a2 >= 0 so K1 <= K2 <= K3.
Variant ``two-slope`` (K1 <= K2 above T1, two parameters) for weak or single-knee stiffening: with half the
parameters it wins on BIC when the third slope is not resolved.
"""
from __future__ import annotations

import numpy as np

from .base import Context, Effect, Param


def _breaks(theta):
    a1, a2, p1, g = theta
    return a1, a2, p1, p1 + g


def _contribution(ctx: Context, theta):
    a1, a2, p1, p2 = _breaks(theta)
    m = np.abs(ctx.u)
    return -np.sign(ctx.u) * (a1 * np.maximum(m - p1, 0.0) + a2 * np.maximum(m - p2, 0.0))


def _report(ctx: Context, theta, s: float) -> dict:
    a1, a2, p1, p2 = _breaks(theta)
    inv = "N*mm/rad" if ctx.response_unit == "rad" else "N/mm"

    def stiff(comp):
        return 1.0 / (comp * ctx.c0) if comp > 0 else float("inf")
    return {"K1": (stiff(s), inv), "K2": (stiff(s - a1), inv), "K3": (stiff(s - a1 - a2), inv),
            "T1": (p1 * ctx.X, ctx.load_unit), "T2": (p2 * ctx.X, ctx.load_unit)}


def _contribution_two(ctx: Context, theta):
    a1, p1 = theta
    return -np.sign(ctx.u) * a1 * np.maximum(np.abs(ctx.u) - p1, 0.0)


def _report_two(ctx: Context, theta, s: float) -> dict:
    a1, p1 = theta
    inv = "N*mm/rad" if ctx.response_unit == "rad" else "N/mm"
    return {"K1": (1.0 / (s * ctx.c0), inv), "K2": (1.0 / ((s - a1) * ctx.c0) if s > a1 else float("inf"), inv),
            "T1": (p1 * ctx.X, ctx.load_unit)}


EXPLANATION = ("the stiffness rises with torque as more teeth come into contact and the contact zones "
               "spread, so the torque-twist curve bends towards the torque axis (K1 < K2 < K3)")

EFFECT = Effect(
    id="nonlinear_stiffness",
    kinds=("torsion",),
    params=(Param("a1", 0.0, 0.95, (0.1,)), Param("a2", 0.0, 0.95, (0.1,)),
            Param("p1", 0.02, 0.9, (0.1, 0.3)), Param("g", 0.03, 0.9, (0.15, 0.4))),
    contribution=_contribution,
    report=_report,
    explanation=EXPLANATION,
)

TWO_SLOPE = Effect(
    id="nonlinear_stiffness",
    kinds=("torsion",),
    params=(Param("a1", 0.0, 0.95, (0.1,)), Param("p1", 0.02, 0.9, (0.1, 0.4))),
    contribution=_contribution_two,
    report=_report_two,
    explanation=EXPLANATION,
    variant="two-slope",
)
