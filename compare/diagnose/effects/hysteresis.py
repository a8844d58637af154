"""hysteresis: loading and unloading branches differ because of friction; two loop families.

Friction dissipates: the twist lags the torque, so while the torque rises the twist is BELOW the
elastic line and while it falls it is ABOVE it; after unloading from +T_max a positive twist remains
(the catalogue's hysteresis loss), and the closed integral of T dphi over a cycle is positive.

- ``dahl``: Dahl's rate-independent friction law for a state z driven by the load,
      dz/du = (sgn(du) - z) / w,      twist += -h z,
  integrated exactly on every monotonic stretch between load reversals:
      z = d + (z_r - d) exp(-|u - u_r| / w),   d = direction, (u_r, z_r) at the reversal.
  z -> +1 while loading, so the loading branch sits h below the elastic line: loop width 2 h at zero load.
- ``play``: a Prandtl-Ishlinskii sum of play (backlash) operators with fixed thresholds r_i and weights
  w_i >= 0 (Maxwell-slip elements in twist form): twist += sum_i w_i (P_ri[u] - u). Each element is an
  elastic-perfectly-plastic loop of width 2 w_i r_i; the sum approximates any Preisach-type loop
  with purely dissipative elements (w_i >= 0 is the physics constraint, not a fitting convenience).
Both are reported through shape-free quantities (loop width at zero torque, energy per cycle).
"""
from __future__ import annotations

import numpy as np

from .base import Context, Effect, Param
from .loop import ARCMIN_PER_RAD, loop_quantities

# play thresholds (fraction of full-scale load): log-spaced, from a tight slip to a wide elastic-slip range
PLAY_THRESHOLDS = (0.005, 0.01, 0.02, 0.04, 0.08, 0.15, 0.3, 0.5)


def dahl_unit(ctx: Context, w: float) -> np.ndarray:
    """Dahl state z for unit amplitude (the twist is linear in h); starts relaxed at z = 0."""
    z = np.empty_like(ctx.u)
    z_r = 0.0
    for start, stop, d in ctx.segments:
        seg = ctx.u[start:stop]
        travel = np.maximum.accumulate(np.maximum(d * (seg - seg[0]), 0.0))
        z[start:stop] = d + (z_r - d) * np.exp(-travel / w)
        z_r = z[stop - 1]
    return z


def play_operator(ctx: Context, r: float) -> np.ndarray:
    """Output p of a play operator of half-width r: p follows u at distance r behind it.

    On a monotonic stretch the exact recursion p_k = clip(p_{k-1}, u_k - r, u_k + r) reduces to a running
    extreme of the load (loading: p = max(p_r, max u - r); unloading: p = min(p_r, min u + r)), so it is
    vectorised per stretch. Starts at p = u_0 (relaxed).
    """
    p = np.empty_like(ctx.u)
    p_r = float(ctx.u[0])
    for start, stop, d in ctx.segments:
        seg = ctx.u[start:stop]
        if d > 0:
            p[start:stop] = np.maximum(p_r, np.maximum.accumulate(seg) - r)
        else:
            p[start:stop] = np.minimum(p_r, np.minimum.accumulate(seg) + r)
        p_r = float(p[stop - 1])
    return p


def _dahl(ctx: Context, theta):
    # minus: z -> +1 on loading and friction makes the loading twist LOWER (dissipative loop)
    return -theta[0] * dahl_unit(ctx, 10.0 ** theta[1])


def _play(ctx: Context, theta):
    out = np.zeros_like(ctx.u)
    for w, r in zip(theta, PLAY_THRESHOLDS):
        if w != 0.0:
            out += w * (play_operator(ctx, r) - ctx.u)
    return out


def _report_dahl(ctx: Context, theta, s: float) -> dict:
    out = _loop_report(ctx, lambda c: _dahl(c, theta))
    out["friction_saturation_load"] = (10.0 ** theta[1] * ctx.X, ctx.load_unit)
    return out


def _report_play(ctx: Context, theta, s: float) -> dict:
    out = _loop_report(ctx, lambda c: _play(c, theta))
    out["play_elements"] = (float(np.count_nonzero(np.asarray(theta) > 1e-9)), "1")
    return out


def _loop_report(ctx: Context, model) -> dict:
    width, energy = loop_quantities(ctx, model)
    out = {"hysteresis_loss": (width, ctx.response_unit),
           "hysteresis_energy_per_cycle": (energy, f"{ctx.load_unit}*{ctx.response_unit}")}
    if ctx.response_unit == "rad":
        out["hysteresis_loss_arcmin"] = (width * ARCMIN_PER_RAD, "arcmin")
    return out


def _plausible_dahl(ctx: Context, theta, s: float) -> list[str]:
    # right after a reversal from z_r = +/-1 the Dahl term changes the compliance by -2 h / w
    return _passive(s, 2.0 * theta[0] / 10.0 ** theta[1])


def _plausible_play(ctx: Context, theta, s: float) -> list[str]:
    # right after a reversal every play element is stuck: the compliance drops by the sum of the weights
    return _passive(s, float(np.sum(theta)))


def _passive(s: float, drop: float) -> list[str]:
    """A friction joint is passive: right after a load reversal its sliders stick and the twist follows the
    torque with a positive (stiffer) compliance s - drop > 0. A loop that needs the twist to keep moving the
    old way after the torque has turned (negative tangent compliance) is a channel lagging in time or a rate
    effect, not friction."""
    if s - drop <= 0.0:
        return [f"the loop needs a negative tangent compliance ({s - drop:.3g} of the baseline's) right after a "
                f"load reversal: the twist keeps moving after the torque has turned (a lagging channel or a "
                f"rate effect), which friction cannot do"]
    return []


EXPLANATION = ("friction in the tooth mesh and the wave-generator bearing makes the twist lag the torque: the "
               "unloading branch lies above the loading branch, leaving a twist (hysteresis loss) at zero torque "
               "and dissipating energy every cycle")


def _applicable(ctx: Context) -> bool:
    return ctx.reversals >= 1


EFFECT = Effect(
    id="hysteresis",
    kinds=("torsion",),
    params=(Param("h", 0.0, 1.0, (0.02,)), Param("log10_w", -2.5, 0.0, (-1.5, -0.7))),
    contribution=_dahl,
    report=_report_dahl,
    explanation=EXPLANATION,
    applicable=_applicable,
    variant="dahl",
    plausible=_plausible_dahl,
)

PLAY = Effect(
    id="hysteresis",
    kinds=("torsion",),
    params=tuple(Param(f"w_{r:g}", 0.0, 5.0, (0.0,)) for r in PLAY_THRESHOLDS),
    contribution=_play,
    report=_report_play,
    explanation=EXPLANATION,
    applicable=_applicable,
    variant="play",
    plausible=_plausible_play,
)

__all__ = ["EFFECT", "PLAY", "PLAY_THRESHOLDS", "dahl_unit", "play_operator"]
