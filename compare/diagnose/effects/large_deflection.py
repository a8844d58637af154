"""large_deflection: geometric nonlinearity of the ring when the deflection is not small against r_m.

Model (first correction of the elastica): delta = c F (1 + gamma delta_lin / r_m), delta_lin = c0 F;
in normalised units y += g u|u| with g = gamma Y / r_m. gamma > 0: the ring softens, gamma < 0: it stiffens.

The sign and size are not free. The inextensible elastica of a thin ring under diametral point loads (the
same as between flat platens while the ring touches each in a line) softens: its first correction is
gamma = GAMMA_ELASTICA = 0.774 (small-load limit of the exact elastica, solved by shooting on the redundant
moment; tests/test_diagnose_effects.py checks the constant against that solution). A fitted gamma outside
[GAMMA_ELASTICA / GAMMA_FACTOR, GAMMA_FACTOR * GAMMA_ELASTICA] is some other nonlinearity drawn by the same
u|u| shape: a ring that STIFFENS under compression does so through its contacts (a Hertzian line contact
flattening on the platens, delta ~ F^(2/3)), not through its geometry (a platen-contact recording was named
large_deflection with gamma = -0.35 and, with a compliance offset, -2.0).
"""
from __future__ import annotations

import numpy as np

from .base import Context, Effect, Param


def _contribution(ctx: Context, theta):
    return theta[0] * ctx.u * np.abs(ctx.u)


GAMMA_ELASTICA = 0.774
# a factor of 2 either way: gamma scales with the baseline's deflection scale Y and with r_m (the ring's
# stiffness and geometry within their stated uncertainties, a thick ring's shear), and the elastica's next
# terms raise the effective coefficient of a one-term fit by ~10 % at delta/r_m = 0.3 (measured: 0.80-0.91)
GAMMA_FACTOR = 2.0


def _plausible(ctx: Context, theta, s: float) -> list[str]:
    r_m = ctx.geometry.get("r_m_mm", float("nan"))
    gamma = theta[0] * r_m / ctx.Y
    lo, hi = GAMMA_ELASTICA / GAMMA_FACTOR, GAMMA_FACTOR * GAMMA_ELASTICA
    if not lo <= gamma <= hi:
        what = "the ring stiffens, which its geometry does not do (contact with the platens does)" if gamma < 0 \
            else "the curvature is not the elastica's"
        return [f"gamma = {gamma:.3g} is outside the elastica's range [{lo:.2g}, {hi:.2g}] (first correction "
                f"{GAMMA_ELASTICA:g}): {what}"]
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
