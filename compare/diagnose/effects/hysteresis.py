"""hysteresis: loading and unloading branches differ because of friction (Dahl model).

Dahl's rate-independent friction law for an additive twist z driven by the load,
    dz/du = (sgn(du) h - z) / w,
is integrated exactly on every monotonic stretch between load reversals:
    z = d h + (z_r - d h) exp(-|u - u_r| / w),   d = direction, (u_r, z_r) at the reversal.
h is half the loop width at zero load (the hysteresis loss is 2 h), w the load over which friction saturates.
"""
from __future__ import annotations

import math

import numpy as np

from .base import Context, Effect, Param

ARCMIN_PER_RAD = 60.0 * 180.0 / math.pi


def dahl_unit(ctx: Context, w: float) -> np.ndarray:
    """Dahl state for h = 1 (the state is linear in h); starts relaxed at z = 0."""
    z = np.empty_like(ctx.u)
    z_r = 0.0
    for start, stop, d in ctx.segments:
        seg = ctx.u[start:stop]
        travel = np.maximum.accumulate(np.maximum(d * (seg - seg[0]), 0.0))
        z[start:stop] = d + (z_r - d) * np.exp(-travel / w)
        z_r = z[stop - 1]
    return z


def _contribution(ctx: Context, theta):
    return theta[0] * dahl_unit(ctx, 10.0 ** theta[1])


def _report(ctx: Context, theta, s: float) -> dict:
    loss = 2.0 * theta[0] * ctx.Y
    out = {"hysteresis_loss": (loss, ctx.response_unit),
           "friction_saturation_load": (10.0 ** theta[1] * ctx.X, ctx.load_unit)}
    if ctx.response_unit == "rad":
        out["hysteresis_loss_arcmin"] = (loss * ARCMIN_PER_RAD, "arcmin")
    return out


EFFECT = Effect(
    id="hysteresis",
    kinds=("torsion",),
    params=(Param("h", 0.0, 1.0, (0.02,)), Param("log10_w", -2.5, 0.0, (-1.5, -0.7))),
    contribution=_contribution,
    report=_report,
    explanation=("friction in the tooth mesh and the wave-generator bearing makes the unloading branch lag "
                 "the loading branch, leaving a twist (hysteresis loss) at zero torque"),
    applicable=lambda ctx: ctx.reversals >= 1,
)
