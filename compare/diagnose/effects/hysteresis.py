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
- ``bouc-wen``: the Bouc-Wen law (Wen 1976) in its torque-driven, normalised form,
      dz/du = [1 - (beta sgn(du z) + gamma) |z|^n] / w,   beta + gamma = 1,   q = beta - gamma >= 0,
  twist += -h z. Unlike Dahl's law its rate depends on whether the load moves with the state or against it
  (q): after a reversal from saturation the state leaves at (1 + q) / w and saturates again at
  (1 - |z|^n) / w. n = 1, q = 1 is the classic Dahl form. Integrated exactly on every monotonic stretch through
  the travel the law needs to reach each state (one quadrature per parameter set, inverted by interpolation).
  The Bouc-Wen loop of exponent 2 was "unexplained" at 130x the noise with every other form (heldout6).
- ``play``: a Prandtl-Ishlinskii sum of play (backlash) operators (Maxwell-slip elements in twist form) with a
  density of thresholds: twist += integral w(r) (P_r[u] - u) dr, w >= 0 piecewise linear between a few
  nodes of r. Each element is an elastic-perfectly-plastic loop of width 2 w r; the sum approximates any
  Preisach-type loop that does not saturate, with purely dissipative elements (w >= 0 is the physics
  constraint, not a fitting convenience). A density, not a few fixed thresholds: a sum of a few elements has
  kinks at ITS thresholds, which repeat every cycle and read as structure periodic in time at 100x the noise
  where the joint's own sliders are many (heldout6: an Iwan chain and a smooth play density "unexplained").
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
import functools
from dataclasses import dataclass
from typing import Callable

import numpy as np

from strainwave.compare.diagnose.effects.base import Context, Effect, Param
from strainwave.compare.diagnose.effects.loop import ARCMIN_PER_RAD, loop_quantities

# play half-widths (fraction of full-scale load): a fine grid carrying the density, from a slip within one
# sample step to beyond full scale; the density's nodes, hats between them (finest where a tight slip
# makes the loop's corner)
PLAY_GRID = np.arange(1, 211) * 0.005
PLAY_DENSITY_NODES = (0.0, 0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 1.0)
# a finer density, its own form (BIC picks the resolution, as for the Preisach bias): eight nodes draw an Iwan
# chain's or a Prandtl-Ishlinskii sum's threshold density only to ~1 % of the loop, whose rest reads as a structure
# odd in load (docs/decisions/060)
PLAY_FINE_DENSITY_NODES = (0.0, 0.02, 0.05, 0.1, 0.15, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.85, 1.0)

# the two law classes: one internal state (Dahl, Bouc-Wen) draws a loop only; a density of elements (play
# operators, Preisach relays) can also draw part of an elastic curvature (relays of narrow width at a bias)
STATE_LAW, ELEMENT_LAW = "state", "elements"


def _dahl_state(ctx: Context, approach) -> np.ndarray:
    """State z of a Dahl-type law, exact on each monotonic stretch: x = 1 - d z, the distance to saturation
    in the stretch's direction d, falls with the travel tau since the stretch began, x = approach(x_r, tau).
    Starts relaxed at z = 0. A stretch starts AT the previous one's extreme, which the load reached moving
    the old way: the extreme sample is advanced by the old stretch (read with the new one's rule it lagged one
    sample at every reversal, a spike in the residual at 100x the noise)."""
    z = np.empty_like(ctx.u)
    z_r = 0.0
    for (start, stop, d), travel in zip(ctx.segments, _travels(ctx)):
        x = approach(max(1.0 - d * z_r, 0.0), travel)
        zs = d * (1.0 - x)
        z[start:stop] = zs[:stop - start]
        z_r = zs[-1]
    return z


def _travels(ctx: Context) -> list[np.ndarray]:
    """The load's travel since each stretch began (its running extreme), with the next stretch's first sample,
    the stretch's own extreme; the same for every law and parameter, so kept on the context."""
    if "travels" not in ctx.cache:
        out = []
        for start, stop, d in ctx.segments:
            seg = ctx.u[start:stop + 1]
            travel = np.maximum.accumulate(np.maximum(d * (seg - seg[0]), 0.0))
            travel.flags.writeable = False
            out.append(travel)
        ctx.cache["travels"] = out
    return ctx.cache["travels"]


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


@functools.lru_cache(maxsize=64)
def bouc_wen_travel(n: float, q: float) -> tuple[np.ndarray, np.ndarray]:
    """(tau, g): the travel tau (in units of w) the Bouc-Wen law needs to bring x = d z from -1 (saturated the
    other way) to x, tabulated against g = -ln(1 - x), the log of the distance to saturation. Trapezoids in x up
    to 0, then in g, where the integrand (1 - x) / rate stays smooth while tau grows without bound towards
    saturation (x = 1 - 1e-12); g against tau is then near linear, so interpolating it is accurate."""
    abs_x, dx, x_pos, one_minus_x, dg, g = _TRAVEL_GRID
    rate_neg = 1.0 + q * abs_x ** n
    f_pos = one_minus_x / (1.0 - x_pos ** n)
    tau_neg = np.concatenate([[0.0], np.cumsum(0.5 * (1.0 / rate_neg[1:] + 1.0 / rate_neg[:-1]) * dx)])
    tau_pos = tau_neg[-1] + np.concatenate([[0.0], np.cumsum(0.5 * (f_pos[1:] + f_pos[:-1]) * dg)])
    return np.concatenate([tau_neg[:-1], tau_pos]), g


def _travel_grid() -> tuple[np.ndarray, ...]:
    """bouc_wen_travel's quadrature nodes, the same for every (n, q): |x| and its steps up to 0; x, 1 - x and the
    steps of g beyond; g at every node."""
    x_neg = np.linspace(-1.0, 0.0, 801)
    g_pos = np.linspace(0.0, 12.0 * np.log(10.0), 4001)
    x_pos = -np.expm1(-g_pos)
    out = (np.abs(x_neg), np.diff(x_neg), x_pos, 1.0 - x_pos, np.diff(g_pos),
           np.concatenate([-np.log1p(-x_neg[:-1]), g_pos]))
    for a in out:
        a.flags.writeable = False           # shared by every table (g is returned with each)
    return out


_TRAVEL_GRID = _travel_grid()


def bouc_wen_unit(ctx: Context, w: float, n: float, q: float) -> np.ndarray:
    """State z of the Bouc-Wen law (unit amplitude), exact on each stretch up to the travel table's
    quadrature; starts relaxed at z = 0."""
    tau, g = bouc_wen_travel(n, q)

    def approach(x_r, travel):
        start = np.interp(-np.log(max(x_r, 1e-300)), g, tau)
        return np.exp(-np.interp(start + travel / w, tau, g, right=np.inf))
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
# a finer density in the bias, its own form: BIC picks the resolution. The fine one draws a narrow bias
# distribution to the noise at 100-260x (heldout6: relay densities Gaussian in the bias, "unexplained" with the
# coarse one); its 8 more parameters cost a short, noisy loop its evidence (332 rows at 8x: "agrees")
PREISACH_FINE_BIAS_NODES = (0.0, 0.15, 0.35, 0.6, 0.9)
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
    # 32-bit sample indices: the (samples x relays) gathers below move half the memory (2.8x faster at 2,500
    # rows, which a Preisach fit and its loop reading pay 8 times)
    idx = np.arange(len(u), dtype=np.int32)
    levels = np.unique(np.concatenate([alpha, beta]))
    # levels x samples: each relay's gather is then one contiguous row (a third faster than gathering columns);
    # the states are handed out transposed, the samples x relays array in the memory order it always had
    last_up = np.maximum.accumulate(np.where(u[None, :] >= levels[:, None], idx[None, :], np.int32(-1)), axis=1)
    last_dn = np.maximum.accumulate(np.where(u[None, :] <= levels[:, None], idx[None, :], np.int32(-1)), axis=1)
    ia, ib = np.searchsorted(levels, alpha), np.searchsorted(levels, beta)
    up, dn = last_up[ia], last_dn[ib]
    start = np.where(alpha + beta < 0.0, 1.0, -1.0)
    return np.where(up > dn, 1.0, np.where(dn > up, -1.0, start[:, None])).T


def preisach_basis(ctx: Context, bias_nodes: tuple[float, ...] = PREISACH_BIAS_NODES,
                   secant: bool = True) -> np.ndarray:
    """Twist per unit node weight (len(u) x nodes): relay states times the density's hat functions, for the
    density on ``bias_nodes`` (both resolutions come from one pass over the relays). ``secant``: the relays'
    least-squares line in the load is left to the stiffness scale (the simulation's stiffness is the loop's
    secant); else the relays keep it (the simulation's stiffness is the elastic one, and the sliding relays add
    their own compliance)."""
    if "preisach" not in ctx.cache:
        ctx.cache["preisach"] = _preisach_bases(ctx, (PREISACH_BIAS_NODES, PREISACH_FINE_BIAS_NODES))
    return ctx.cache["preisach"][bias_nodes, secant]


def _preisach_bases(ctx: Context, resolutions) -> dict:
    a, b = np.meshgrid(RELAY_LEVELS, RELAY_LEVELS, indexing="ij")
    keep = a > b
    alpha, beta = a[keep], b[keep]
    bias, half = np.abs(0.5 * (alpha + beta)), 0.5 * (alpha - beta)
    wh = _hats(half, PREISACH_WIDTH_NODES, 0.0)
    # unit node weight = one unit of compliance spread over the relay grid's cell area
    step = RELAY_LEVELS[1] - RELAY_LEVELS[0]
    densities = [(_hats(bias, nodes, None)[:, :, None] * wh[:, None, :]).reshape(len(alpha), -1) * step ** 2
                 / RELAY_SHIFTS for nodes in resolutions]
    density = np.hstack(densities)
    # the same grid at RELAY_SHIFTS sub-grid offsets, averaged: a relay density on one grid switches in
    # steps, which a constant loading rate turns into a staircase periodic in time (read as a ripple at
    # high signal/noise); the shifted grids smooth it to a quarter of the step
    basis = 0.0
    for shift in np.arange(RELAY_SHIFTS) / RELAY_SHIFTS * step:
        basis = basis + relay_states(ctx.u, alpha + shift, beta + shift) @ density
    # the loop only: the constant belongs to the channel offset and the least-squares line in the load to
    # the stiffness scale, so a relay sum's mean compliance does not pull the stiffness off its prior
    # (the width at zero torque and the energy per cycle of a line are zero: the loop quantities stay)
    A = np.column_stack([np.ones_like(ctx.u), ctx.u])
    coef = np.linalg.lstsq(A, basis, rcond=None)[0]
    bases = {True: basis - A @ coef, False: basis - A[:, :1] @ coef[:1]}
    edges = np.cumsum([0] + [d.shape[1] for d in densities])
    return {(nodes, secant): b[:, lo:hi] for nodes, lo, hi in zip(resolutions, edges[:-1], edges[1:])
            for secant, b in bases.items()}


def _last_state(ctx: Context, law: str, args: tuple, state: Callable[..., np.ndarray]) -> np.ndarray:
    """``state(ctx, *args)``, the last one per law kept on the context: a step in the loop's amplitude alone (a
    column of the optimiser's difference Jacobian) scales the same state (the answer bit for bit the same)."""
    key = ("last_state", law)
    hit = ctx.cache.get(key)
    if hit is not None and hit[0] == args:
        return hit[1]
    z = state(ctx, *args)
    ctx.cache[key] = (args, z)
    return z


def _dahl(ctx: Context, theta):
    # minus: z -> +1 on loading and friction makes the loading twist LOWER (dissipative loop)
    return -theta[0] * _last_state(ctx, "dahl", (float(10.0 ** theta[1]),), dahl_unit)


def _dahl_exponent_h(theta) -> float:
    """The loop's amplitude h from its parameter f = h 2^n / w, the stiffness it adds when it sticks right
    after a reversal (a fraction of the baseline compliance): f <= 1 keeps the stuck joint's tangent
    compliance >= 0 for any exponent (a bristle sticks rigidly at f = 1), where a free h let the fit trade a
    negative stuck compliance for a sharper corner (heldout6: an elasto-plastic bristle fitted f = 1.06)."""
    f, lw, n = theta
    return f * 10.0 ** lw / 2.0 ** n


def _dahl_exponent(ctx: Context, theta):
    return -_dahl_exponent_h(theta) * _last_state(ctx, "dahl-exponent", (float(10.0 ** theta[1]), float(theta[2])),
                                                  dahl_exponent_unit)


def _report_dahl_exponent(ctx: Context, theta, s: float) -> dict:
    out = _loop_report(ctx, lambda c: _dahl_exponent(c, theta))
    out["friction_saturation_load"] = (10.0 ** theta[1] * ctx.X, ctx.load_unit)
    out["dahl_exponent"] = (float(theta[2]), "1")
    out["stuck_stiffening_fraction"] = (float(theta[0]), "1")
    return out


def _plausible_dahl_exponent(ctx: Context, theta, s: float) -> list[str]:
    return _passive(ctx, _dahl_exponent(ctx, theta), s)


def play_basis(ctx: Context, nodes: tuple[float, ...] = PLAY_DENSITY_NODES) -> np.ndarray:
    """Twist per unit node weight (len(u) x nodes): the play operators on the fine grid times the density's
    hat functions on ``nodes``, integrated over the half-width (every resolution from one pass of the plays)."""
    if "play" not in ctx.cache:
        ctx.cache["play"] = np.column_stack([play_operator(ctx, r) - ctx.u for r in PLAY_GRID])
    key = ("play", nodes)
    if key not in ctx.cache:
        step = PLAY_GRID[1] - PLAY_GRID[0]
        ctx.cache[key] = ctx.cache["play"] @ (_hats(PLAY_GRID, nodes, None) * step)
    return ctx.cache[key]


def _bouc_wen_h(theta) -> float:
    """The loop's amplitude h from f = h (1 + q) / w, the stiffness it adds right after a reversal from
    saturation (as for Dahl's exponent: f <= 1 keeps the stuck joint's compliance >= 0)."""
    f, lw, _, q = theta
    return f * 10.0 ** lw / (1.0 + q)


def _bouc_wen(ctx: Context, theta):
    return -_bouc_wen_h(theta) * _last_state(ctx, "bouc-wen", (float(10.0 ** theta[1]), float(theta[2]),
                                                               float(theta[3])), bouc_wen_unit)


def _report_bouc_wen(ctx: Context, theta, s: float) -> dict:
    out = _loop_report(ctx, lambda c: _bouc_wen(c, theta))
    out["friction_saturation_load"] = (10.0 ** theta[1] * ctx.X, ctx.load_unit)
    out["bouc_wen_exponent"] = (float(theta[2]), "1")
    out["bouc_wen_q"] = (float(theta[3]), "1")
    return out


def _plausible_bouc_wen(ctx: Context, theta, s: float) -> list[str]:
    return _passive(ctx, _bouc_wen(ctx, theta), s)


def _report_dahl(ctx: Context, theta, s: float) -> dict:
    out = _loop_report(ctx, lambda c: _dahl(c, theta))
    out["friction_saturation_load"] = (10.0 ** theta[1] * ctx.X, ctx.load_unit)
    return out


def _loop_report(ctx: Context, model) -> dict:
    width, energy = loop_quantities(ctx, model)
    out = {"hysteresis_loss": (width, ctx.response_unit),
           "hysteresis_energy_per_cycle": (energy, f"{ctx.load_unit}*{ctx.response_unit}")}
    if ctx.response_unit == "rad":
        out["hysteresis_loss_arcmin"] = (width * ARCMIN_PER_RAD, "arcmin")
    return out


def _plausible_dahl(ctx: Context, theta, s: float) -> list[str]:
    return _passive(ctx, _dahl(ctx, theta), s)


@dataclass(frozen=True)
class _Density:
    """A loop law that is a density of elements (play operators, Preisach relays): linear in its node weights
    over a basis of element outputs; its contribution, report and passivity check, one for every such form."""
    basis: Callable[[Context], np.ndarray]
    count_name: str                  # the report's count of nodes that carry weight

    def contribution(self, ctx: Context, theta) -> np.ndarray:
        return self.basis(ctx) @ np.asarray(theta, dtype=float)

    def report(self, ctx: Context, theta, s: float) -> dict:
        out = _loop_report(ctx, lambda c: self.contribution(c, theta))
        out[self.count_name] = (float(np.count_nonzero(np.asarray(theta) > 1e-9)), "count")
        return out

    def plausible(self, ctx: Context, theta, s: float) -> list[str]:
        return _passive(ctx, self.contribution(ctx, theta), s)


def sampled_tangent(ctx: Context, loop: np.ndarray, s: float) -> float:
    """The smallest tangent compliance of the model twist s u + loop along the recorded load path, as a
    fraction of s: each sample's change of twist over its change of load, on every monotonic stretch.

    The step out of the reversal sample is not judged: the load's true extreme may lie between the reversal
    sample and the next one, and the twist recorded after it follows that unrecorded excursion (a twist-driven
    rig: the twist peaks between two samples while the torque drops along the stuck branch, so the samples
    show the torque falling and the twist still rising). heldout6: Dahl loops of exponent 2 fitted to the noise
    were refused with tangents of -1.1 and -0.8 on that one step. A lag of two samples or more still moves the
    sampled twist backwards on the next step. Nor is the record's first step: the history before it is unknown
    too."""
    worst = np.inf
    for start, stop, d in ctx.segments:
        first = start + 1        # ``start``: the reversal sample (or the record's first)
        du = d * np.diff(ctx.u[first:stop])
        dy = d * np.diff(s * ctx.u[first:stop] + loop[first:stop])
        moving = du > 0.0
        if moving.any():
            worst = min(worst, float(np.min(dy[moving] / du[moving])))
    return worst / s if np.isfinite(worst) and s > 0.0 else np.inf


def _passive(ctx: Context, loop: np.ndarray, s: float) -> list[str]:
    """A friction joint is passive: right after a load reversal its sliders stick and the twist follows the
    torque with a positive (stiffer) compliance. A loop that needs the twist to keep moving the old way after
    the torque has turned (negative tangent compliance) is a channel lagging in time or a rate effect, not
    friction.

    Judged where the data was sampled, on the model's twist from sample to sample: a slider that sticks for
    less travel than one sample step leaves no trace the recording could test (a friction law stiff at the
    reversal, Dahl's exponent 2 or an Iwan chain, is drawn by a catalogue form whose stuck range is shorter than
    a step: heldout6 read those "unexplained" at a residual on the noise), while a lag of two samples or more
    moves the sampled twist backwards and is refused as before (see ``sampled_tangent`` for the one step not
    judged)."""
    tangent = sampled_tangent(ctx, loop, s)
    if s <= 0.0 or tangent < 0.0:
        return [f"the loop needs a negative tangent compliance ({tangent:.3g} of the baseline's) right after a "
                f"load reversal: the twist keeps moving after the torque has turned (a lagging channel or a "
                f"rate effect), which friction cannot do"]
    return []


EXPLANATION = ("friction in the tooth mesh and the wave-generator bearing makes the twist lag the torque: the "
               "unloading branch lies above the loading branch, leaving a twist (hysteresis loss) at zero torque "
               "and dissipating energy every cycle")


def _applicable(ctx: Context) -> bool:
    return ctx.reversals >= 1


def _rate_rival(*args):
    """rate_loop.rival (imported here: it reads the catalogue's base, which imports this module)."""
    from strainwave.compare.diagnose.rate_loop import rival
    return rival(*args)


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
    law_class=STATE_LAW,
    loop=True,
    # a real drive's recording always shows its stiffening and its loop together: for a gear that pair is the
    # normal model, not a second effect that must earn its place by more than 10 BIC units and by a structure
    normal_with=(("gear", "nonlinear_stiffness"),),
    # ... and at small torque its lost motion as well (Harmonic Drive's loop: the curve, the loss and the lost
    # motion are one measurement)
    normal_model=(("gear", ("nonlinear_stiffness", "lost_motion", "hysteresis")),),
    rival=_rate_rival,
)


def _form(variant: str, params: tuple[Param, ...], contribution, report, plausible=None,
          law_class: str = STATE_LAW, basis=None) -> Effect:
    """Another loop law of the same physics: same id, explanation and applicability."""
    return dataclasses.replace(EFFECT, params=params, contribution=contribution, report=report, variant=variant,
                               plausible=plausible, law_class=law_class, basis=basis)


DAHL_EXPONENT = _form("dahl-exponent", (Param("f", 0.0, 1.0, (0.5,)), Param("log10_w", -2.5, 0.0, (-1.5, -0.7)),
                                        Param("n", 0.0, 3.0, (0.3, 2.0))),   # n = 1 is the classic form itself
                      _dahl_exponent, _report_dahl_exponent, _plausible_dahl_exponent)

BOUC_WEN = _form("bouc-wen", (Param("f", 0.0, 1.0, (0.5,)), Param("log10_w", -2.5, 0.0, (-1.5, -0.7)),
                              Param("n", 0.5, 4.0, (1.0, 2.0)), Param("q", 0.0, 3.0, (0.5, 1.5))),
                 _bouc_wen, _report_bouc_wen, _plausible_bouc_wen)

def _density_form(variant: str, names, basis: Callable[[Context], np.ndarray], count_name: str,
                  rereads: str | None = None) -> Effect:
    law = _Density(basis, count_name)
    form = _form(variant, tuple(Param(name, 0.0, 50.0, (0.0,)) for name in names), law.contribution, law.report,
                 law.plausible, ELEMENT_LAW, basis)
    return dataclasses.replace(form, rereads=rereads)


_PLAY_NAMES = tuple(f"w_r{r:g}" for r in PLAY_DENSITY_NODES)
_RELAY_NAMES = tuple(f"mu_b{b:g}_h{h:g}" for b in PREISACH_BIAS_NODES for h in PREISACH_WIDTH_NODES)

PLAY = _density_form("play", _PLAY_NAMES, play_basis, "play_density_nodes")
PLAY_FINE = _density_form("play-fine", tuple(f"w_r{r:g}" for r in PLAY_FINE_DENSITY_NODES),
                          functools.partial(play_basis, nodes=PLAY_FINE_DENSITY_NODES), "play_density_nodes")
PREISACH = _density_form("preisach", _RELAY_NAMES, preisach_basis, "relay_density_nodes")
# the same relays keeping their mean compliance: where the simulation's stiffness is the ELASTIC one, a relay
# density spread over the load range makes the loop's secant softer than it (heldout6's Preisach loops: secant
# 2 to 9 prior sigmas softer, so the secant form read "the stiffness differs from the baseline"); BIC and the
# stiffness prior choose between the two readings of the stated stiffness
PREISACH_ELASTIC = _density_form("preisach-elastic", _RELAY_NAMES, functools.partial(preisach_basis, secant=False),
                                 "relay_density_nodes", rereads="preisach")
PREISACH_FINE = _density_form("preisach-fine", tuple(f"mu_b{b:g}_h{h:g}" for b in PREISACH_FINE_BIAS_NODES
                                                     for h in PREISACH_WIDTH_NODES),
                              functools.partial(preisach_basis, bias_nodes=PREISACH_FINE_BIAS_NODES),
                              "relay_density_nodes")

__all__ = ["BOUC_WEN", "DAHL_EXPONENT", "EFFECT", "ELEMENT_LAW", "PLAY", "PLAY_DENSITY_NODES", "PLAY_FINE",
           "PLAY_FINE_DENSITY_NODES", "PLAY_GRID", "PREISACH", "PREISACH_ELASTIC",
           "PREISACH_FINE", "STATE_LAW", "bouc_wen_travel", "bouc_wen_unit", "dahl_exponent_unit", "dahl_unit",
           "play_basis", "play_operator", "preisach_basis", "relay_states", "sampled_tangent"]
