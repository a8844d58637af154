"""hysteresis: loading and unloading branches differ because of friction; two loop families.

Friction dissipates: the twist lags the torque, so while the torque rises the twist is BELOW the
elastic line and while it falls it is ABOVE it; after unloading from +T_max a positive twist remains
(the catalogue's hysteresis loss), and the closed integral of T dphi over a cycle is positive.

- ``dahl``: Dahl's rate-independent friction law for a state z driven by the load,
      dz/du = (sgn(du) - z) / w,      twist += -h z,
  integrated exactly on every monotonic stretch between load reversals:
      z = d + (z_r - d) exp(-|u - u_r| / w),   d = direction, (u_r, z_r) at the reversal.
  z -> +1 while loading, so the loading branch sits h below the elastic line: loop width 2 h at zero load.
- ``dahl-exponent``: Dahl's law with its exponent (Dahl 1968: dF/dx = sigma0 |1 - F/Fc sgn(dx)|^i sgn(dx)),
      dz/du = sgn(du) |1 - z sgn(du)|^n / w,   0 <= n <= 3,
  integrated exactly on every monotonic stretch (x = 1 - d z: x^(1-n) = x_r^(1-n) - (1 - n) travel / w).
  n = 1 is the form above; n = 0 is the elastic-perfectly-plastic bristle (a stuck range of travel 2 w, then
  slip: a Jenkins element, LuGre's rate-independent limit); n < 1 saturates within a finite travel, n > 1
  approaches it algebraically. Each is a rigid shape at 100x the noise: the one-exponent form left a bristle,
  Dahl laws of exponent 0.5 and 2 "unexplained" with their widths right to 2 % (heldout6).
- ``play``: a Prandtl-Ishlinskii sum of play (backlash) operators with fixed thresholds r_i and weights
  w_i >= 0 (Maxwell-slip elements in twist form): twist += sum_i w_i (P_ri[u] - u). Each element is an
  elastic-perfectly-plastic loop of width 2 w_i r_i; the sum approximates any Preisach-type loop
  with purely dissipative elements (w_i >= 0 is the physics constraint, not a fitting convenience).
- ``preisach``: a Preisach sum of relay hysterons (Mayergoyz): a relay of switching thresholds
  alpha > beta jumps to +1 once u >= alpha and to -1 once u <= beta; twist += sum mu(alpha, beta) relay.
  The density mu >= 0 is continuous, piecewise bilinear in |bias| = |alpha + beta|/2 and half-width
  (alpha - beta)/2 on a few nodes, zero at zero width (a zero-width relay is reversible: stiffness, not
  friction) and symmetric in the bias (the same friction for both torque signs). Unlike the play sum, whose
  tangent compliance can only grow with the travel since the reversal, relays whose thresholds the load has
  passed stop contributing, so the loop can SATURATE (branches that flatten at full load: friction sources
  that all slip before full torque, e.g. a bearing's balls and the tooth flanks at different loads).
  Every relay with mu >= 0 dissipates 2 mu (alpha - beta) per cycle that crosses it: the form is passive
  for any weights. Initial state: demagnetised (the relay staircase of a joint brought to zero load).
All are reported through shape-free quantities (loop width at zero torque, energy per cycle).
"""
from __future__ import annotations

import dataclasses

import numpy as np

from .base import Context, Effect, Param
from .loop import ARCMIN_PER_RAD, loop_quantities

# play thresholds (fraction of full-scale load): log-spaced, from a tight slip to a wide elastic-slip range
PLAY_THRESHOLDS = (0.005, 0.01, 0.02, 0.04, 0.08, 0.15, 0.3, 0.5)


def _dahl_state(ctx: Context, approach) -> np.ndarray:
    """State z of a Dahl-type law, exact on each monotonic stretch: x = 1 - d z, the distance to saturation
    in the stretch's direction d, falls with the travel tau since the stretch began, x = approach(x_r, tau).
    Starts relaxed at z = 0. A stretch starts AT the previous one's extreme, which the load reached moving
    the old way: the extreme sample is advanced by the old stretch (read with the new one's rule it lagged one
    sample at every reversal, a spike in the residual at 100x the noise)."""
    z = np.empty_like(ctx.u)
    z_r = 0.0
    for start, stop, d in ctx.segments:
        seg = ctx.u[start:stop + 1]                  # with the next stretch's first sample, its own extreme
        travel = np.maximum.accumulate(np.maximum(d * (seg - seg[0]), 0.0))
        x = approach(max(1.0 - d * z_r, 0.0), travel)
        zs = d * (1.0 - x)
        z[start:stop] = zs[:stop - start]
        z_r = zs[-1]
    return z


def dahl_unit(ctx: Context, w: float) -> np.ndarray:
    """Dahl state z for unit amplitude (the twist is linear in h); starts relaxed at z = 0."""
    return _dahl_state(ctx, lambda x_r, travel: x_r * np.exp(-travel / w))


def dahl_exponent_unit(ctx: Context, w: float, n: float) -> np.ndarray:
    """State z of Dahl's law with exponent n (unit amplitude), exact on each stretch; starts relaxed at z = 0."""
    def approach(x_r, travel):
        if abs(n - 1.0) < 1e-9:
            return x_r * np.exp(-travel / w)
        if n < 1.0:
            return np.maximum(x_r ** (1.0 - n) - (1.0 - n) * travel / w, 0.0) ** (1.0 / (1.0 - n))
        if x_r == 0.0:
            return np.zeros_like(travel)
        return (x_r ** (1.0 - n) + (n - 1.0) * travel / w) ** (-1.0 / (n - 1.0))
    return _dahl_state(ctx, approach)


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
        # a stretch starts AT the previous one's extreme, which the load reached moving the old way
        p_r = min(max(p_r, float(seg[0]) - r), float(seg[0]) + r)
        if d > 0:
            p[start:stop] = np.maximum(p_r, np.maximum.accumulate(seg) - r)
        else:
            p[start:stop] = np.minimum(p_r, np.minimum.accumulate(seg) + r)
        p_r = float(p[stop - 1])
    return p


# Preisach relays on a fine threshold grid (spacing 0.05 of full scale, beyond it so saturation is reachable);
# the density's nodes (fractions of full scale): |bias| and half-width, hats between them
RELAY_LEVELS = np.linspace(-1.25, 1.25, 51)
RELAY_SHIFTS = 4
PREISACH_BIAS_NODES = (0.0, 0.4, 0.8)
PREISACH_WIDTH_NODES = (0.05, 0.2, 0.45, 0.8)


def _hats(x: np.ndarray, nodes: tuple[float, ...], left_zero: float | None) -> np.ndarray:
    """Piecewise-linear hat functions on ``nodes`` evaluated at x (len(x) x len(nodes)); the first hat ramps
    up from ``left_zero`` (None: flat to the left), the last one down to zero one spacing beyond its node."""
    ext = [left_zero if left_zero is not None else nodes[0] - 1e9, *nodes, 2 * nodes[-1] - nodes[-2]]
    out = np.empty((len(x), len(nodes)))
    for k in range(len(nodes)):
        a, m, b = ext[k], ext[k + 1], ext[k + 2]
        up = np.clip((x - a) / (m - a), 0.0, 1.0) if m > a else np.ones_like(x)
        down = np.clip((b - x) / (b - m), 0.0, 1.0)
        out[:, k] = np.where(x <= m, up, down)
    if left_zero is None:
        out[x <= nodes[0], 0] = 1.0
    return out


def relay_states(u: np.ndarray, alpha: np.ndarray, beta: np.ndarray) -> np.ndarray:
    """States (len(u) x n relays) of relay hysterons (alpha > beta) driven by u, demagnetised start.

    A relay is +1 if the load last reached its upper threshold after it last reached its lower one: with
    the running index of the last sample at or beyond each threshold level, every state is one comparison."""
    idx = np.arange(len(u))
    levels = np.unique(np.concatenate([alpha, beta]))
    last_up = np.maximum.accumulate(np.where(u[:, None] >= levels[None, :], idx[:, None], -1), axis=0)
    last_dn = np.maximum.accumulate(np.where(u[:, None] <= levels[None, :], idx[:, None], -1), axis=0)
    ia, ib = np.searchsorted(levels, alpha), np.searchsorted(levels, beta)
    up, dn = last_up[:, ia], last_dn[:, ib]
    start = np.where(alpha + beta < 0.0, 1.0, -1.0)
    return np.where(up > dn, 1.0, np.where(dn > up, -1.0, start[None, :]))


def preisach_basis(ctx: Context) -> np.ndarray:
    """Twist per unit node weight (len(u) x nodes): relay states times the density's hat functions."""
    if "preisach" not in ctx.cache:
        a, b = np.meshgrid(RELAY_LEVELS, RELAY_LEVELS, indexing="ij")
        keep = a > b
        alpha, beta = a[keep], b[keep]
        bias, half = np.abs(0.5 * (alpha + beta)), 0.5 * (alpha - beta)
        wb = _hats(bias, PREISACH_BIAS_NODES, None)
        wh = _hats(half, PREISACH_WIDTH_NODES, 0.0)
        density = (wb[:, :, None] * wh[:, None, :]).reshape(len(alpha), -1)
        # unit node weight = one unit of compliance spread over the relay grid's cell area
        step = RELAY_LEVELS[1] - RELAY_LEVELS[0]
        # the same grid at RELAY_SHIFTS sub-grid offsets, averaged: a relay density on one grid switches in
        # steps, which a constant loading rate turns into a staircase periodic in time (read as a ripple at
        # high signal/noise); the shifted grids smooth it to a quarter of the step
        basis = 0.0
        for shift in np.arange(RELAY_SHIFTS) / RELAY_SHIFTS * step:
            states = relay_states(ctx.u, alpha + shift, beta + shift)
            basis = basis + states @ (density * step ** 2 / RELAY_SHIFTS)
        # the loop only: the constant belongs to the channel offset and the least-squares line in the load to
        # the stiffness scale, so a relay sum's mean compliance does not pull the stiffness off its prior
        # (the width at zero torque and the energy per cycle of a line are zero: the loop quantities stay)
        A = np.column_stack([np.ones_like(ctx.u), ctx.u])
        ctx.cache["preisach"] = basis - A @ np.linalg.lstsq(A, basis, rcond=None)[0]
    return ctx.cache["preisach"]


def _preisach(ctx: Context, theta):
    return preisach_basis(ctx) @ np.asarray(theta, dtype=float)


def _dahl(ctx: Context, theta):
    # minus: z -> +1 on loading and friction makes the loading twist LOWER (dissipative loop)
    return -theta[0] * dahl_unit(ctx, 10.0 ** theta[1])


def _dahl_exponent_h(theta) -> float:
    """The loop's amplitude h from its parameter f = h 2^n / w, the stiffness it adds when it sticks right
    after a reversal (a fraction of the baseline compliance): f <= 1 keeps the stuck joint's tangent
    compliance >= 0 for any exponent (a bristle sticks rigidly at f = 1), where a free h let the fit trade a
    negative stuck compliance for a sharper corner (heldout6: an elasto-plastic bristle fitted f = 1.06)."""
    f, lw, n = theta
    return f * 10.0 ** lw / 2.0 ** n


def _dahl_exponent(ctx: Context, theta):
    return -_dahl_exponent_h(theta) * dahl_exponent_unit(ctx, 10.0 ** theta[1], theta[2])


def _report_dahl_exponent(ctx: Context, theta, s: float) -> dict:
    out = _loop_report(ctx, lambda c: _dahl_exponent(c, theta))
    out["friction_saturation_load"] = (10.0 ** theta[1] * ctx.X, ctx.load_unit)
    out["dahl_exponent"] = (float(theta[2]), "1")
    out["stuck_stiffening_fraction"] = (float(theta[0]), "1")
    return out


def _plausible_dahl_exponent(ctx: Context, theta, s: float) -> list[str]:
    # right after a reversal from saturation (x = 2) the term changes the compliance by -h 2^n / w = -f
    return _passive(s, float(theta[0]))


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
    out["play_elements"] = (float(np.count_nonzero(np.asarray(theta) > 1e-9)), "count")
    return out


def _report_preisach(ctx: Context, theta, s: float) -> dict:
    out = _loop_report(ctx, lambda c: _preisach(c, theta))
    out["relay_density_nodes"] = (float(np.count_nonzero(np.asarray(theta) > 1e-9)), "count")
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


def _form(variant: str, params: tuple[Param, ...], contribution, report, plausible=None) -> Effect:
    """Another loop law of the same physics: same id, explanation and applicability."""
    return dataclasses.replace(EFFECT, params=params, contribution=contribution, report=report, variant=variant,
                               plausible=plausible)


DAHL_EXPONENT = _form("dahl-exponent", (Param("f", 0.0, 1.0, (0.5,)), Param("log10_w", -2.5, 0.0, (-1.5, -0.7)),
                                        Param("n", 0.0, 3.0, (0.3, 2.0))),   # n = 1 is the classic form itself
                      _dahl_exponent, _report_dahl_exponent, _plausible_dahl_exponent)

PLAY = _form("play", tuple(Param(f"w_{r:g}", 0.0, 5.0, (0.0,)) for r in PLAY_THRESHOLDS), _play, _report_play,
             _plausible_play)

PREISACH = _form("preisach", tuple(Param(f"mu_b{b:g}_h{h:g}", 0.0, 50.0, (0.0,)) for b in PREISACH_BIAS_NODES
                                   for h in PREISACH_WIDTH_NODES), _preisach, _report_preisach)

__all__ = ["DAHL_EXPONENT", "EFFECT", "PLAY", "PLAY_THRESHOLDS", "PREISACH", "dahl_exponent_unit", "dahl_unit", "play_operator", "preisach_basis",
           "relay_states"]
