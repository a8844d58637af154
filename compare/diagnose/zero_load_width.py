"""Model-free hysteresis loss: the loop width at zero torque read from the recording itself.

The catalogue's hysteresis loss is the twist on the unloading branch minus the twist on the loading branch
at T = 0, on the steady +/- full-scale cycle. A fitted loop model (Dahl, play operators) reports it through
its own law, which is biased when the true law has another shape (Preisach saturating loops, Bouc-Wen).
Here it is measured directly:

1. the fitted model's NON-hysteretic part (offset, drift, stiffness, any other named effect) is removed
   from the data; whatever is single-valued in the torque cancels in the difference of the two branches
   anyway, so the model only has to be right about the drift in time;
2. only steady full-scale branches are used: a descending stretch that starts at a reversal near +max|T|
   and an ascending one that starts near -max|T| (the virgin first loading and partial cycles are left out:
   a return-point-memory law is on its major loop only after a full-scale reversal);
3. on each branch type the residual is regressed on a quadratic in T over a window |T| <= h around zero
   (pooled over cycles); the width is the difference of the two intercepts. A quadratic in a window
   centred on zero has no bias from the branch curvature and only O(h^3) from its third derivative.
   Where cubic and quartic terms are significant (0.1 %) the branches bend too sharply for the window
   (a backlash band, a tight friction knee near zero) and the window is halved once (0.25 -> 0.125 of
   full scale); still significant: no estimate;
4. the standard error is the regression's, with the noise's total variance (the model's residual, at
   least the white level) and its lag-1 autocorrelation inflating it by (1 + rho)/(1 - rho).

Used only when both branch types cover zero torque (at least 5 samples on each side of it inside the
window, pooled over the steady cycles; a test that ends unloaded at zero covers one side only, and a
one-sided quadratic extrapolates too noisily); otherwise the caller falls back to the model's width.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from strainwave.compare.diagnose.effects.base import Context

WINDOWS = (0.25, 0.125)   # half-widths of the window around T = 0 (fraction of full scale), widest first
LACK_OF_FIT_CHI2 = 18.47  # chi-square with 4 degrees of freedom, 0.1 % tail
FULL_SCALE = 0.95      # a branch is steady full-scale when it starts at a reversal beyond this fraction
MIN_SIDE = 5           # samples required on each side of zero, per branch type


@dataclass(frozen=True)
class ZeroLoadWidth:
    width: float        # normalised response units (unloading minus loading at u = 0)
    std_error: float
    n_down: int
    n_up: int
    window: float       # half-width of the window used, fraction of full-scale torque


def _branch_mask(ctx: Context, direction: int, h: float) -> np.ndarray:
    mask = np.zeros(len(ctx.u), dtype=bool)
    full = float(np.max(np.abs(ctx.u)))
    for k, (start, stop, d) in enumerate(ctx.segments):
        if k == 0 or d != direction:
            continue                      # the first stretch starts from the virgin (or unknown) state
        if -d * ctx.u[start] < FULL_SCALE * full:
            continue                      # not a reversal from the full-scale extreme of the other sign
        mask[start:stop] = True
    return mask & (np.abs(ctx.u) <= h * full)


def _fit(u, r, D, degree):
    U = 1.0 - D
    A = np.column_stack([b * u ** k for k in range(degree + 1) for b in (D, U)])
    coef, *_ = np.linalg.lstsq(A, r, rcond=None)
    e = r - A @ coef
    return coef, float(e @ e), A


def full_scale_cycles(ctx: Context) -> int:
    """Full-scale cycles in the recording: a descending stretch from near +max|T| to near -max|T| followed by
    an ascending one that reaches zero torque again, both to within the full-scale rule's 5 % of max|T| (a test
    that ends unloaded stops at zero give or take the load channel's noise)."""
    peak = float(np.max(np.abs(ctx.u)))
    full, zero = FULL_SCALE * peak, -(1.0 - FULL_SCALE) * peak
    segs = ctx.segments
    return sum(1 for (a, b, d), (c, e, d2) in zip(segs[:-1], segs[1:])
               if d < 0 < d2 and ctx.u[a] >= full and ctx.u[b - 1] <= -full and float(np.max(ctx.u[c:e])) >= zero)


def zero_load_width(ctx: Context, residual: np.ndarray, sigma: float, rho: float = 0.0,
                    noise_var: float | None = None, exclude: tuple[tuple[float, float], ...] = ()
                    ) -> ZeroLoadWidth | None:
    """Width at zero load of ``residual`` (data minus the model's non-hysteretic part), or None when the
    recording does not cover zero torque on both steady branches or no window around zero is described by
    a quadratic per branch. ``sigma``: white noise (normalised); ``noise_var``: the noise's total variance
    (default sigma^2); ``rho``: lag-1 autocorrelation of the noise; ``exclude``: load ranges (normalised)
    left out of the window, a clearance's band (its own friction is the band's, not the loop's): the
    quadratics are read across the gap."""
    full = float(np.max(np.abs(ctx.u)))
    outside = np.ones(len(ctx.u), dtype=bool)
    for lo, hi in exclude:
        outside &= (ctx.u < lo) | (ctx.u > hi)
    rho = min(max(rho, 0.0), 0.99)
    inflation = (1.0 + rho) / (1.0 - rho)
    var = sigma ** 2 if noise_var is None else max(noise_var, sigma ** 2)
    for h in WINDOWS:
        down, up = _branch_mask(ctx, -1, h) & outside, _branch_mask(ctx, 1, h) & outside
        # both branch types must cover zero torque: samples on both sides of it inside the window (a test that
        # ends unloaded at zero gives one side only; a one-sided quadratic extrapolates too noisily)
        if any(np.count_nonzero(m & (ctx.u > 0)) < MIN_SIDE or np.count_nonzero(m & (ctx.u < 0)) < MIN_SIDE
               for m in (down, up)):
            return None
        sel = down | up
        u, r, D = ctx.u[sel] / full, residual[sel], down[sel].astype(float)
        coef, rss2, A = _fit(u, r, D, 2)
        _, rss4, _ = _fit(u, r, D, 4)
        # lack of fit: cubic and quartic terms (4 parameters) significant at 0.1 % -> the branches bend too
        # sharply in this window (a backlash band, a tight friction knee): try a narrower window
        if rss2 - rss4 > LACK_OF_FIT_CHI2 * var * inflation:
            continue
        cov = np.linalg.pinv(A.T @ A)
        v = (cov[0, 0] + cov[1, 1] - 2.0 * cov[0, 1]) * var * inflation
        return ZeroLoadWidth(float(coef[0] - coef[1]), float(np.sqrt(max(v, 0.0))),
                             int(np.count_nonzero(down)), int(np.count_nonzero(up)), h)
    return None


__all__ = ["FULL_SCALE", "full_scale_cycles", "LACK_OF_FIT_CHI2", "MIN_SIDE", "WINDOWS", "ZeroLoadWidth", "zero_load_width"]
