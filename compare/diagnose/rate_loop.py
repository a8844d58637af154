"""The rate-dependent rival of a friction loop: linear viscoelastic creep (a Zener / standard linear solid).

Not a catalogue effect (it is never named): it is what a loop could be instead of friction. Creep compliance
J(t) = J0 + J1 (1 - exp(-t/tau)) gives, for any torque history, twist = J0 u + J1 x with x the torque passed
through a first-order lag of time constant tau (dx/dt = (u - x)/tau). With the stiffness scale s = J0 + J1
fitted as always, the effect is J1 (x - u), J1 >= 0: the twist lags the torque IN TIME, and the loop dissipates.

Why it is needed: under a constant loading rate, time since a reversal is proportional to the travel since
it, so this law draws exactly the loop of Dahl's rate-independent friction law (h = J1 tau rate, w = tau rate).
One loading rate cannot tell friction from creep (or from a channel recorded a few samples late, a lag x - u
= -L du/dt); only a loop that keeps its width at another rate, or a branch shape creep cannot draw (sharp
slip corners, saturation), can. The diagnosis fits this rival beside every named friction loop and says so.
"""
from __future__ import annotations

import numpy as np
from scipy.signal import lfilter, savgol_filter

from strainwave.compare.diagnose.effects.base import Context, Effect, Param, RivalReading

LABEL = "a rate-dependent loop (viscoelastic creep, or a channel lagging in time)"


def lagged(u: np.ndarray, t: np.ndarray, tau: float) -> np.ndarray:
    """u through a first-order lag of time constant tau (units of t), exact for u linear between samples,
    starting relaxed (x = u at the first sample)."""
    dt = np.diff(t)
    x0 = float(u[0])
    if len(dt) and np.allclose(dt, dt[0], rtol=1e-6, atol=0.0):
        a = float(np.exp(-dt[0] / tau))
        g = 1.0 - tau / dt[0] * (1.0 - a)          # the weight of the current sample for a linear ramp
        # x_k = a x_(k-1) + (1 - a - g) u_(k-1) + g u_k
        x = lfilter([g, 1.0 - a - g], [1.0, -a], u - x0)
        return x + x0
    x = np.empty_like(u)
    x[0] = x0
    for k in range(1, len(u)):
        a = float(np.exp(-dt[k - 1] / tau)) if dt[k - 1] > 0 else 1.0
        g = 1.0 - tau / dt[k - 1] * (1.0 - a) if dt[k - 1] > 0 else 0.0
        x[k] = a * x[k - 1] + (1.0 - a - g) * u[k - 1] + g * u[k]
    return x


# loading rates within this factor are one rate (a rig's speed control holds a few per cent; a second test
# speed is normally a factor of 2 or more)
ONE_RATE_SPREAD = 1.3


def several_rates(ctx: Context) -> bool:
    """Does the recording load at more than one rate? The median |du/dt| of every monotonic stretch that
    travels most of the load range, slowest against fastest (short stretches are dwell, noise, or the ramp
    from zero that a rig often runs at its own speed)."""
    span = float(np.ptp(ctx.u)) or 1.0
    rates = []
    for start, stop, _ in ctx.segments:
        if stop - start >= 5 and abs(ctx.u[stop - 1] - ctx.u[start]) >= 0.6 * span:
            du, dt = np.diff(ctx.u[start:stop]), np.diff(ctx.t[start:stop])
            ok = dt > 0
            if np.any(ok):
                rates.append(float(np.median(np.abs(du[ok] / dt[ok]))))
    return len(rates) >= 2 and max(rates) > ONE_RATE_SPREAD * min(rates)


# the rival lags the torque, not its noise: a quadratic smoother over this many samples (a ramp passes exactly)
SMOOTH_SAMPLES = 11


def smooth_load(ctx: Context) -> np.ndarray:
    """The torque with its white noise smoothed away (Savitzky-Golay, quadratic, SMOOTH_SAMPLES). A lag of the
    RAW torque also low-passes the torque channel's noise, which every friction law passes on to the twist in
    full; on a stiff gear behind a fine encoder that noise alone made the lag win (errors in variables: family-2
    CHA-14/30 and CHA-20/50 with their rate-independent Bouc-Wen loops, rival better by 89 and 91 BIC units
    on the raw torque, worse by 263 and 12 on the smoothed one; docs/decisions/067-diag51b-events-and-speed.md)."""
    if "smooth_load" not in ctx.cache:
        ctx.cache["smooth_load"] = savgol_filter(ctx.u, SMOOTH_SAMPLES, 2) if len(ctx.u) > SMOOTH_SAMPLES \
            else ctx.u
    return ctx.cache["smooth_load"]


def _contribution(ctx: Context, theta) -> np.ndarray:
    u = smooth_load(ctx)
    return theta[0] * (lagged(u, ctx.t, 10.0 ** theta[1]) - u)


def _report(ctx: Context, theta, s: float) -> dict:
    return {"delayed_compliance_fraction": (float(theta[0]), "1"),
            "time_constant_fraction_of_record": (float(10.0 ** theta[1]), "1")}


RATE_LOOP = Effect(
    id="rate_dependence",
    kinds=("torsion",),
    params=(Param("J1", 0.0, 5.0, (0.05,)), Param("log10_tau", -4.0, 0.0, (-2.5, -1.5))),
    contribution=_contribution,
    report=_report,
    explanation=LABEL,
    variant="zener",
)



def rival(ctx: Context, kept: tuple[Effect, ...], heads: list, best_bic: float, sigma: float, uncertainty: float,
          noise, stride: int) -> RivalReading:
    """The named friction loop replaced by linear viscoelastic creep, the other named effects ``kept``. The loop
    keeps time, not travel, across loading rates: out of the catalogue (friction is rate-independent); at one
    loading rate a better-fitting rival is only a better SHAPE (creep may keep twisting after the torque has
    turned, a passive friction law may not): no evidence of rate dependence."""
    from strainwave.compare.diagnose.fit import fit_effects       # fit imports the catalogue, which names this
    starts = [np.concatenate([*heads, np.array(x0)]) for x0 in ((0.05, -2.5), (0.05, -1.5))]
    fitted = fit_effects(ctx, kept + (RATE_LOOP,), sigma, uncertainty, starts=starts, noise=noise)
    margin = float(fitted.bic - best_bic)
    several = several_rates(ctx)
    return RivalReading(
        margin, several,
        f"the loop is rate-dependent: {LABEL} draws it better than any friction law at the recording's several "
        f"loading rates (by {-margin:.0f} BIC units), and friction does not depend on the loading rate",
        LABEL + ("" if several else ", at the recording's one loading rate") +
        "; a test at a second loading rate tells them apart")


__all__ = ["LABEL", "ONE_RATE_SPREAD", "RATE_LOOP", "SMOOTH_SAMPLES", "lagged", "rival", "several_rates", "smooth_load"]
