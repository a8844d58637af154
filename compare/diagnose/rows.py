"""Model selection on a strided subsample of a long recording, and the chosen model back on every row."""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from strainwave.compare.diagnose import periodic
from strainwave.compare.diagnose.baseline import Baseline
from strainwave.compare.diagnose.context import build_context
from strainwave.compare.diagnose.fit import Fit
from strainwave.compare.diagnose.recording import Recording

MAX_FIT_ROWS = 2500        # model selection on a strided subsample beyond this (docs/decisions/019-diagnose-speed.md)


def stride(n: int) -> int:
    """The step between fitted rows of a recording of ``n`` rows."""
    return 1 if n <= MAX_FIT_ROWS else math.ceil(n / MAX_FIT_ROWS)


def subsample(rec: Recording) -> Recording:
    """Every k-th row (acquisition order kept) so at most MAX_FIT_ROWS are fitted; white noise stays white."""
    if rec.n <= MAX_FIT_ROWS:
        return rec
    k = stride(rec.n)
    return dataclasses.replace(rec, load=rec.load[::k], response=rec.response[::k],
                               time_s=None if rec.time_s is None else rec.time_s[::k],
                               extra={c: v[::k] for c, v in rec.extra.items()})


def full_residual(rec: Recording, base: Baseline, ctx, fit: Fit) -> np.ndarray:
    """Data minus ``fit`` on EVERY row of ``rec`` (the fit ran on every k-th, ``ctx``), in the fit's
    normalisation: the same scales and the same map of time onto [0, 1]."""
    k = stride(rec.n)
    fitted = rec.time_s[::k] if rec.time_s is not None else np.arange(0, rec.n, k, dtype=float)
    full = build_context(rec, base, X=ctx.X, time_map=(float(fitted[0]), float(fitted[-1] - fitted[0])))
    # a line searched on the fitted rows is the fitted model's (the same normalisation), not searched again
    if periodic.CACHE_KEY in ctx.cache:
        full.cache[periodic.CACHE_KEY] = ctx.cache[periodic.CACHE_KEY]
    b0, b1, s = fit.nuisance
    model = b0 + b1 * full.t + s * full.u
    for e, th in zip(fit.effects, fit.split_theta()):
        model = model + e.contribution(full, th)
    return full.y - model


def explained_rows(rec: Recording, base: Baseline, ctx, fit: Fit) -> np.ndarray:
    """``fit``'s response on every row of ``rec`` (physical units)."""
    if stride(rec.n) == 1:
        return fit.model * ctx.Y
    return rec.response - full_residual(rec, base, ctx, fit) * ctx.Y


__all__ = ["MAX_FIT_ROWS", "explained_rows", "full_residual", "stride", "subsample"]
