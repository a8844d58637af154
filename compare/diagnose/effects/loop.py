"""Shape-free quantities of a loop model: width at zero load and dissipated energy per cycle.

Any hysteresis law (Dahl, play operators, ...) is run on one reference cycle spanning the recording's
own load range, after a first loading that erases the initial state:
    0 -> u_max -> u_min -> u_max.
The closed loop is the stretch u_max -> u_min -> u_max. Quantities (physical units):
- width at zero load = twist on the unloading branch minus twist on the loading branch at u = 0
  (positive for a dissipative loop: the twist lags the torque); a test that never crosses zero load
  (unipolar, or cycling about a preload) has no width there: the loop is read at the middle of its
  recorded load range instead (``width_load``), rather than at an end where its branches meet;
- energy per cycle = closed integral of T dphi = -closed integral of phi dT (positive when dissipative).
"""
from __future__ import annotations

import dataclasses
import math
from typing import Callable

import numpy as np

from strainwave.compare.diagnose.effects.base import Context

ARCMIN_PER_RAD = 60.0 * 180.0 / math.pi
N_LEG = 400


def reference_cycle(ctx: Context) -> tuple[Context, int]:
    """A noise-free context on the reference cycle and the index where the closed loop starts (one per
    recording: its own memo then keeps the history bases, e.g. the relay states, across loop readings)."""
    if "reference_cycle" not in ctx.cache:
        ctx.cache["reference_cycle"] = _reference_cycle(ctx)
    return ctx.cache["reference_cycle"]


def _reference_cycle(ctx: Context) -> tuple[Context, int]:
    # a loop about a preload spans only its recorded range (the model is not run where the data never were)
    lo = float(ctx.u.min()) if ctx.u.min() > 0.0 else float(min(ctx.u.min(), 0.0))
    hi = float(max(ctx.u.max(), 0.0))
    up = np.linspace(0.0, hi, N_LEG)
    down = np.linspace(hi, lo, 2 * N_LEG)[1:]
    back = np.linspace(lo, hi, 2 * N_LEG)[1:]
    u = np.concatenate([up, down, back])
    n1, n2 = len(up), len(up) + len(down)
    segments = ((0, n1 - 1, 1), (n1 - 1, n2 - 1, -1), (n2 - 1, len(u), 1))
    direction = np.empty(len(u))
    for a, b, d in segments:
        direction[a:b] = d
    ref = dataclasses.replace(ctx, u=u, y=np.zeros_like(u), t=np.linspace(0.0, 1.0, len(u)),
                              direction=direction, segments=segments, angle=None)
    return ref, n1 - 1


def width_load(ctx: Context) -> float:
    """Normalised load at which the loop width is read: zero where the recording crosses zero load, else the
    middle of its recorded range."""
    lo, hi = float(ctx.u.min()), float(ctx.u.max())
    return 0.0 if lo < 0.0 < hi else 0.5 * (lo + hi)


def load_path_model(ctx: Context, fit) -> np.ndarray:
    """The contributions of ``fit``'s effects that the load history draws (Effect.load_path) on ``ctx``."""
    out = np.zeros_like(ctx.u)
    for e, th in zip(fit.effects, fit.split_theta()):
        if e.load_path:
            out = out + e.contribution(ctx, th)
    return out


def loop_quantities(ctx: Context, model: Callable[[Context], np.ndarray]) -> tuple[float, float]:
    """(width at zero load -- or at ``width_load`` -- in the response unit, energy per cycle in load unit x
    response unit)."""
    ref, start = reference_cycle(ctx)
    at = width_load(ctx)
    y = model(ref)
    u, y = ref.u[start:], y[start:]
    k = int(np.argmin(u))                        # the turning point at u_min
    down_u, down_y = u[:k + 1][::-1], y[:k + 1][::-1]     # ascending u for interp
    up_u, up_y = u[k:], y[k:]
    width = float(np.interp(at, down_u, down_y) - np.interp(at, up_u, up_y)) * ctx.Y
    # -closed integral of phi dT (trapezoid); the elastic part integrates to zero on a closed path
    energy = -float(np.sum(0.5 * (y[1:] + y[:-1]) * np.diff(u))) * ctx.X * ctx.Y
    return width, energy


__all__ = ["ARCMIN_PER_RAD", "load_path_model", "loop_quantities", "reference_cycle", "width_load"]
