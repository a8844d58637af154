"""plasticity: yield at the load points, an elastic-plastic hinge: a knee and a permanent set on unloading.

Model: the plastic deflection follows the largest load reached so far, F_max(t):
    delta_p = a Y ((F_max - F_y)/X)+^n,
so loading beyond F_y bends the curve down (softening) and unloading is elastic, leaving delta_p.
Variant ``limit-load`` (four parameters): the plastic TANGENT compliance of a structure whose plastic zones spread
from first yield towards collapse at the limit load L = X/lambda beyond the recorded peak (an elastic-perfectly-
plastic ring: four hinges at 6/pi of the first-yield load for a rectangle), smoothly from F_y:
    d delta_p / dF ~ ((F - F_y)/X)+^m / (1 - lambda F/X),   delta_p(F_max) = a I(F_max)/I(X),
I the integral of the tangent from zero. lambda = 0 is a power law: the form above (n = m + 1 up to 20) and, with
F_y -> 0, a Ramberg-Osgood skeleton a (F/X)^n; lambda > 0 draws the fast growth near collapse that no power with
n <= 3 follows, then the hardening's finite slope where lambda stays short of the peak's 1/X. A stable material
(Drucker) never lowers the tangent compliance under monotone loading: every member rises with the load.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from strainwave.compare.diagnose.effects.base import Context, Effect, Param


def _contribution(ctx: Context, theta):
    a, f, n = theta
    peak = np.maximum.accumulate(ctx.u)
    return a * np.maximum(peak - f, 0.0) ** n


LIMIT_GRID = 513          # integration points from the yield load to full scale


def _limit_curve(theta) -> tuple[np.ndarray, np.ndarray]:
    """(loads from F_y to full scale, I(load)/I(full scale)) of the limit-load form, by the trapezoid rule."""
    _, f, m, lam = theta
    g = f + (1.0 - f) * np.linspace(0.0, 1.0, LIMIT_GRID)
    tangent = (g - f) ** m / (1.0 - lam * g)
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (tangent[1:] + tangent[:-1]) * np.diff(g))])
    return g, cum / cum[-1] if cum[-1] > 0 else cum


def _contribution_limit(ctx: Context, theta):
    g, share = _limit_curve(theta)
    return theta[0] * np.interp(np.maximum.accumulate(ctx.u), g, share, left=0.0)


# a smooth law has no sharp first yield (a Ramberg-Osgood one none at all): its yield load is read where the plastic
# deflection reaches this share of the elastic one at that load, the ring's analogue of an offset yield
OFFSET_SHARE = 0.02


def _offset_yield(theta, s: float) -> float:
    """The load (normalised) of the limit-load form's offset yield; its onset F_y where the set stays below it."""
    g, share = _limit_curve(theta)
    above = theta[0] * share >= OFFSET_SHARE * s * g
    return float(g[np.argmax(above)]) if above[1:].any() else float(theta[1])


def _report_limit(ctx: Context, theta, s: float) -> dict:
    a, f, m, lam = theta
    g, share = _limit_curve(theta)
    return {"yield_load": (_offset_yield(theta, s) * ctx.X, ctx.load_unit),
            "plastic_onset_load": (f * ctx.X, ctx.load_unit),
            "permanent_set": (a * float(np.interp(float(np.max(ctx.u)), g, share, left=0.0)) * ctx.Y,
                              ctx.response_unit),
            "hardening_exponent": (m + 1.0, "1"),
            "limit_load": (ctx.X / lam if lam > 0 else float("inf"), ctx.load_unit)}


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
    fy = (_offset_yield(theta, s) if len(theta) == 4 else theta[1]) * ctx.X
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

# lambda <= 0.95: the collapse load at least 5 % beyond the recorded peak, where the hardening governs the slope
LIMIT_LOAD = dataclasses.replace(
    EFFECT, variant="limit-load", contribution=_contribution_limit, report=_report_limit,
    params=(Param("a", 0.0, 5.0, (0.1,)), Param("f", 0.05, 0.98, (0.4, 0.7)), Param("m", 0.0, 19.0, (2.0, 8.0)),
            Param("lambda", 0.0, 0.95, (0.3,))))
