"""crack_closure: a breathing crack, open (compliant) for one torque sign and closed for the other.

Bilinear model: twist = c+ T for T > T0 and c- T for T < T0; with the scale s this is
y += d |u - u0|, so c+ = (s + d) c0 and c- = (s - d) c0 (up to the offsets).
"""
from __future__ import annotations

import numpy as np

from .base import Context, Effect, Param


def _contribution(ctx: Context, theta):
    d, u0 = theta
    return d * np.abs(ctx.u - u0)


def _report(ctx: Context, theta, s: float) -> dict:
    d, u0 = theta
    inv = "N*mm/rad" if ctx.response_unit == "rad" else "N/mm"
    kp, kn = 1.0 / ((s + d) * ctx.c0), 1.0 / ((s - d) * ctx.c0)
    return {"stiffness_positive_load": (kp, inv), "stiffness_negative_load": (kn, inv),
            "stiffness_ratio_open_to_closed": (min(kp, kn) / max(kp, kn), "1"),
            "load_zero_offset": (u0 * ctx.X, ctx.load_unit)}


EFFECT = Effect(
    id="crack_closure",
    kinds=("torsion",),
    params=(Param("d", -0.8, 0.8, (0.05, -0.05)), Param("u0", -0.1, 0.1, (0.0,))),
    contribution=_contribution,
    report=_report,
    explanation=("a fatigue crack opens under one torque direction and its faces press shut under the "
                 "other, so the part is softer for one sign of torque than for the other"),
    applicable=lambda ctx: ctx.two_sided,
)
