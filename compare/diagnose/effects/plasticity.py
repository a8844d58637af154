"""plasticity: yield at the load points, an elastic-plastic hinge: a knee and a permanent set on unloading.

Model: the plastic deflection follows the largest load reached so far, F_max(t):
    delta_p = a Y ((F_max - F_y)/X)+^n,
so loading beyond F_y bends the curve down (softening) and unloading is elastic, leaving delta_p.
"""
from __future__ import annotations

import math

import numpy as np

from strainwave.compare.diagnose.effects.base import Context, Effect, Param


def _contribution(ctx: Context, theta):
    a, f, n = theta
    peak = np.maximum.accumulate(ctx.u)
    return a * np.maximum(peak - f, 0.0) ** n


# yield stress range of flexspline and ring steels (annealed structural steel to through-hardened 40CrNiMo)
YIELD_STRESS_RANGE_MPa = (200.0, 1800.0)


def first_yield_force_N(geometry: dict, yield_stress_MPa: float) -> float:
    """Load at first yield of the thin ring under diametral compression: M_max = F R / pi at the load
    points (seed 003 moment distribution), sigma = 6 M/(b h^2)."""
    return math.pi * yield_stress_MPa * geometry["face_width_mm"] * geometry["rim_thickness_mm"] ** 2 / (
        6.0 * geometry["r_m_mm"])


def _plausible(ctx: Context, theta, s: float) -> list[str]:
    if "r_m_mm" not in ctx.geometry:
        return []
    f_lo, f_hi = (first_yield_force_N(ctx.geometry, sy) for sy in YIELD_STRESS_RANGE_MPa)
    fy = theta[1] * ctx.X
    if not f_lo / 1.5 <= fy <= f_hi * 1.5:
        return [f"yield load {fy:.3g} N is outside {f_lo:.3g}-{f_hi:.3g} N, the first-yield range of this "
                f"section for yield stresses {YIELD_STRESS_RANGE_MPa[0]:g}-{YIELD_STRESS_RANGE_MPa[1]:g} MPa"]
    return []


def _where(ctx: Context, theta):
    return ((float(theta[1]), float(ctx.u.max())),), "beyond the yield load while loading, a set on unloading"


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
    plausible=_plausible,
    where=_where,
)
