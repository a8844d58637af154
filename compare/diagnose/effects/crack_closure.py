"""crack_closure: a breathing crack, open (compliant) for one torque sign and closed for the other.

Bilinear model: the closed crack transmits torque like intact material (baseline compliance s c0);
the open crack adds a compliance c_x on one side of the load zero T0 only:
    y += d max(sgn(d) (u - u0), 0)
(d > 0: open under positive torque, extra twist d u for u > u0; d < 0: open under negative torque,
extra twist |d| u for u < u0). K_open = 1/((s + |d|) c0), K_closed = 1/(s c0).
Variant ``gradual``: the faces close over a load width w (the ramp's corner rounded by a softplus), for
cracks whose faces touch progressively (rough faces, crack-tip plasticity).
Variant ``progressive``: no closure law assumed. On the closing side the crack's remaining compliance
|d| (1 - F(x)) falls monotonically with the load x past the zero, F a non-decreasing staircase of closed
fractions f_k >= 0 at fixed loads (capped at fully closed): asperity contact stiffens with its contact load
by whatever law the faces' roughness sets (a power-law tail, an exponential, a sharp stop).
Variant ``opening``: the mirror image, no opening law assumed. On the OPEN side the crack's compliance
|d| G(x) rises monotonically with the load x past the zero, G a non-decreasing staircase of open fractions
g_k >= 0 at fixed loads up to full scale (capped at fully open): a crack held shut by residual compressive
stress or crack-tip plasticity (plasticity-induced closure) separates from its mouth towards its tip as the
load grows, and may still be opening at full load (a crack whose compliance rose linearly with the load up to
full scale was left unexplained by the three closure laws, which all open fully within 60 % of it).
It is offered alone, never in a pair: a free one-sided compliance beside a free odd stiffening spans every even
curve, and the pair named a sensor's even nonlinearity (twist + k T^2) crack_closure + nonlinear_stiffness.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from strainwave.compare.diagnose.effects.base import Context, Effect, Param


def _contribution(ctx: Context, theta):
    d, u0 = theta
    side = 1.0 if d >= 0 else -1.0
    return d * np.maximum(side * (ctx.u - u0), 0.0)


def _contribution_gradual(ctx: Context, theta):
    d, u0, lw = theta
    w = 10.0 ** lw
    side = 1.0 if d >= 0 else -1.0
    return d * w * (np.logaddexp(0.0, side * (ctx.u - u0) / w) - np.logaddexp(0.0, -side * u0 / w))


# loads (fraction of full scale) past the zero where part of the crack face closes; 0 = the sharp closure
CLOSURE_KNOTS = (0.0, 0.03, 0.08, 0.15, 0.25, 0.4, 0.6)


def _contribution_progressive(ctx: Context, theta):
    d, u0 = theta[0], theta[1]
    side = 1.0 if d >= 0 else -1.0
    v = side * (ctx.u - u0)
    x = np.maximum(-v, 0.0)                           # load past the zero on the closing side
    closed = np.minimum(np.cumsum(theta[2:]), 1.0)    # closed fraction from each knot on
    edges = (*CLOSURE_KNOTS[1:], np.inf)
    # the integral of the remaining compliance fraction 1 - F over [0, x]
    open_area = sum((1.0 - c) * np.clip(x - a, 0.0, b - a) for c, a, b in zip(closed, CLOSURE_KNOTS, edges))
    return d * np.maximum(v, 0.0) - d * open_area


# loads (fraction of full scale) past the zero where a further part of the crack opens
OPENING_KNOTS = (0.0, 0.1, 0.2, 0.35, 0.5, 0.7, 0.85)


def _contribution_opening(ctx: Context, theta):
    d, u0 = theta[0], theta[1]
    side = 1.0 if d >= 0 else -1.0
    x = np.maximum(side * (ctx.u - u0), 0.0)          # load past the zero on the opening side
    opened = np.minimum(np.cumsum(theta[2:]), 1.0)     # open fraction from each knot on
    edges = (*OPENING_KNOTS[1:], np.inf)
    # the integral of the open fraction G over [0, x]
    return d * sum(g * np.clip(x - a, 0.0, b - a) for g, a, b in zip(opened, OPENING_KNOTS, edges))


def _where(ctx: Context, theta):
    d, u0 = theta[0], theta[1]
    if d >= 0:
        return ((float(u0), float(ctx.u.max())),), "positive load only (the crack opens under positive load)"
    return ((float(ctx.u.min()), float(u0)),), "negative load only (the crack opens under negative load)"


def _report(ctx: Context, theta, s: float) -> dict:
    d, u0 = theta[0], theta[1]
    inv = "N*mm/rad" if ctx.response_unit == "rad" else "N/mm"
    k_open, k_closed = 1.0 / ((s + abs(d)) * ctx.c0), 1.0 / (s * ctx.c0)
    return {"stiffness_crack_open": (k_open, inv), "stiffness_crack_closed": (k_closed, inv),
            "open_under_load_sign": (1.0 if d >= 0 else -1.0, "1"),
            "stiffness_ratio_open_to_closed": (k_open / k_closed, "1"),
            "load_zero_offset": (u0 * ctx.X, ctx.load_unit)}


def _exchange_rival(*args):
    """exchange.rival (imported here: it reads the catalogue's base, which imports this module)."""
    from strainwave.compare.diagnose.exchange import rival
    return rival(*args)


# the largest load (normalised) at which the crack faces meet: residual stress shifts a crack's closure from
# zero, by less than a tenth of the largest torque
U0_MAX = 0.1


def _plausible_zero(ctx: Context, theta, s: float) -> list[str]:
    """A crack's faces meet near zero load and its closed side is linear from there: a closure point fitted at
    its bound says the curve bends on both sides of zero (an even curvature: a sensor's non-linearity), which
    a crack does not draw."""
    if abs(theta[1]) >= U0_MAX / 1.05:
        return [f"closure point {theta[1] * ctx.X:.4g} {ctx.load_unit} at its bound ({U0_MAX:g} of the largest "
                f"torque): the curve bends on both sides of zero, not on one side as a crack's does"]
    return []


EFFECT = Effect(
    id="crack_closure",
    kinds=("torsion",),
    params=(Param("d", -0.8, 0.8, (0.05, -0.05)), Param("u0", -U0_MAX, U0_MAX, (0.0,))),
    contribution=_contribution,
    report=_report,
    explanation=("a fatigue crack opens under one torque direction and its faces press shut under the "
                 "other, so the part is softer for one sign of torque than for the other"),
    applicable=lambda ctx: ctx.two_sided,
    where=_where,
    rival=_exchange_rival,
    plausible=_plausible_zero,
)

# the gradual closure's widest load width in log10 of the normalised torque: 20 % of the largest torque, so
# the faces are shut (99 %) within 5 w of the zero and the closed side is linear beyond
LOG10_W_MAX = -0.7
# a fit within this of the bound (a factor 1.05 in width) wants a wider closure than a crack's faces make
AT_BOUND = math.log10(1.05)


def _plausible_gradual(ctx: Context, theta, s: float) -> list[str]:
    """A crack is softer on one side and LINEAR on its closed side once the faces are shut. Without the
    bound, the gradual form tends to a parabola (w ln 2 + v/2 + v^2/(8 w) as w grows): a closure as wide as
    the bound allows is an even curvature over the whole range, a sensor's non-linearity (heldout5: a torque
    sensor reading T + k T^2 was named crack_closure[gradual] at 300x the noise, its width at the bound, its
    stiffness ratio 0.995) or a stiffening, not a crack. As lost_motion's band at its bound is a stiffening."""
    if theta[2] >= LOG10_W_MAX - AT_BOUND:
        return _plausible_zero(ctx, theta, s) + [f"closure width {10.0 ** theta[2] * ctx.X:.4g} {ctx.load_unit} at its bound (20 % of the largest "
                f"torque): a closure this wide is an even curvature over the whole range (a sensor's "
                f"non-linearity or a stiffening), not crack faces closing"]
    return _plausible_zero(ctx, theta, s)


# the other forms are the sharp form with another closure law: same id, side, report and location
GRADUAL = dataclasses.replace(EFFECT, params=(*EFFECT.params, Param("log10_w", -2.5, LOG10_W_MAX, (-1.5,))),
                              contribution=_contribution_gradual, variant="gradual", plausible=_plausible_gradual)
PROGRESSIVE = dataclasses.replace(
    EFFECT, params=(*EFFECT.params, *(Param(f"f_{k:g}", 0.0, 1.0, (1.0 if k == 0.0 else 0.0,)) for k in CLOSURE_KNOTS)),
    contribution=_contribution_progressive, variant="progressive")
# one start: a crack opening evenly up to full scale (the sharp crack is the form above)
OPENING = dataclasses.replace(
    EFFECT, params=(*EFFECT.params, *(Param(f"g_{k:g}", 0.0, 1.0, (1.0 / len(OPENING_KNOTS),))
                                      for k in OPENING_KNOTS)),
    contribution=_contribution_opening, variant="opening", pairs=False)
