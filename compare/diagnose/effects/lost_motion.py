"""lost_motion: a narrow dead band around zero torque (clearance / backlash), smooth backlash model.

Model: twist += b tanh((T - T0)/w): crossing zero torque takes up a clearance 2 b within a torque band w.
The band is narrow by definition (w <= 10 % of the largest torque); a wider smooth S-shape is stiffening.
T0 is the torque channel's zero offset (nuisance, reported for completeness).
"""
from __future__ import annotations

import math

import numpy as np

from .base import Context, Effect, Param

ARCMIN_PER_RAD = 60.0 * 180.0 / math.pi


def _contribution(ctx: Context, theta):
    b, lw, u0 = theta
    return b * np.tanh((ctx.u - u0) / 10.0 ** lw)


def _where(ctx: Context, theta):
    b, lw, u0 = theta
    w = 10.0 ** lw
    return ((float(u0 - 2.0 * w), float(u0 + 2.0 * w)),), "around zero load, both branches (the dead band)"


def _report(ctx: Context, theta, s: float) -> dict:
    b, lw, u0 = theta
    lost = 2.0 * b * ctx.Y
    out = {"lost_motion": (lost, ctx.response_unit), "band_width": (10.0 ** lw * ctx.X, ctx.load_unit),
           "load_zero_offset": (u0 * ctx.X, ctx.load_unit)}
    if ctx.response_unit == "rad":
        out["lost_motion_arcmin"] = (lost * ARCMIN_PER_RAD, "arcmin")
    return out


EFFECT = Effect(
    id="lost_motion",
    kinds=("torsion",),
    params=(Param("b", 0.0, 1.0, (0.02,)), Param("log10_w", -3.0, -1.0, (-2.0, -1.3)),
            Param("u0", -0.1, 0.1, (0.0,))),
    contribution=_contribution,
    report=_report,
    explanation=("a clearance (backlash) between teeth or in a coupling is taken up each time the torque "
                 "changes sign, so the twist jumps by the lost motion in a narrow band around zero torque"),
    applicable=lambda ctx: ctx.two_sided,
    where=_where,
)
