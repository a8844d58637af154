"""large_deflection: geometric nonlinearity of the ring when the deflection is not small against r_m.

Model (first correction of the elastica): delta = c F (1 + gamma delta_lin / r_m), delta_lin = c0 F;
in normalised units y += g u|u| with g = gamma Y / r_m. gamma < 0: the ring stiffens as it flattens,
gamma > 0: it softens.
"""
from __future__ import annotations

import numpy as np

from .base import Context, Effect, Param


def _contribution(ctx: Context, theta):
    return theta[0] * ctx.u * np.abs(ctx.u)


GAMMA_PLAUSIBLE = 3.0   # the first elastica correction of a ring has gamma of order one (0.2-0.5 for a ring)


def _plausible(ctx: Context, theta, s: float) -> list[str]:
    r_m = ctx.geometry.get("r_m_mm", float("nan"))
    gamma = theta[0] * r_m / ctx.Y
    if not abs(gamma) <= GAMMA_PLAUSIBLE:
        return [f"gamma = {gamma:.3g} is not of order one (|gamma| <= {GAMMA_PLAUSIBLE:g} for a ring): "
                f"the curvature is too large to be the elastica's"]
    return []


def _report(ctx: Context, theta, s: float) -> dict:
    r_m = ctx.geometry.get("r_m_mm", float("nan"))
    return {"gamma": (theta[0] * r_m / ctx.Y, "1"),
            "stiffness_change_at_max_load_percent": (-100.0 * theta[0] / (s + theta[0]), "%"),
            "max_deflection_to_radius": (ctx.Y / r_m, "1")}


EFFECT = Effect(
    id="large_deflection",
    kinds=("ring_compression",),
    params=(Param("g", -1.0, 1.0, (0.02, -0.02)),),
    contribution=_contribution,
    report=_report,
    explanation=("the deflection is no longer small against the ring radius, so the changing shape "
                 "changes the lever arms of the load and the force-deflection curve bends"),
    plausible=_plausible,
)
