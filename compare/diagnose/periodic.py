"""Patterns that repeat with the load or with an angle cycle after cycle, which the noise model must not absorb
(a stiffness rippling at twice the input angle read "agrees" at a residual 5.9x the white noise, an
encoder's interpolation error periodic in the measured angle at 4.7x).

- ``angle_load_columns``: harmonics of the wave generator's input angle times the load, u cos(k theta),
  u sin(k theta): a torsional stiffness that ripples with the input angle (mesh stiffness variation, a breathing
  crack passing the major axis twice per input turn), its twist ripple growing with the torque;
- ``response_line``: the strongest frequency of a residual against the measured response itself (the encoder's
  reading): an interpolation error repeats every line pitch of the scale, whatever the load or the time.
"""
from __future__ import annotations

import math

import numpy as np

from strainwave.compare.diagnose.effects.base import Context
from strainwave.compare.diagnose.noise import KEEP, noise_std

ANGLE_LOAD_HARMONICS = (1, 2, 3, 4)
# an interpolation error is read only at 5 or more periods over the recorded range (slower, it is a smooth function
# of the response, i.e. of the load, which the load structures draw) and at 4 or more samples per period on each
# pass over the range (the path passes it once per monotonic stretch)
MIN_CYCLES = 5.0
SAMPLES_PER_PERIOD = 4.0
GRID_PER_BIN = 4           # frequency grid: a quarter of the range's Fourier bin
LINE_CONTRAST = 30.0       # a line's power over its neighbours' median (as structure.LINE_CONTRAST in time)
# a line pitch is read only where the reading's own noise leaves its phase: at twice the line frequency the noise
# sigma jitters the phase by 4 pi sigma / pitch radians, so pitches under 4 pi sigma scramble it, and there the
# noise correlates with functions of its own reading (a curve in the load was fitted by a "pitch" of 1.6 sigma)
PITCH_NOISE_SIGMAS = 4.0 * math.pi


def angle_load_columns(ctx: Context, harmonics=ANGLE_LOAD_HARMONICS) -> np.ndarray:
    """u cos(k theta), u sin(k theta) for k in ``harmonics`` (theta the input angle)."""
    return np.column_stack([ctx.u * f(k * ctx.angle) for k in harmonics for f in (np.cos, np.sin)])


# the load has moved to a new level when it is this many of its own sample-to-sample noise sigmas from the last one
LEVEL_SIGMAS = 3.0


def load_levels(u: np.ndarray) -> int:
    """How many distinct load levels the path visits in turn: a sample counts where the load has moved by more than
    LEVEL_SIGMAS of its own noise from the last counted one (any move for a noise-free channel). A load held for
    many samples (a step-and-hold staircase) reads the response at one level, one phase of a line pitch."""
    noisy = len(u) > 3 and float(np.quantile(np.abs(np.diff(u, 2)), KEEP)) > 0.0
    tol = LEVEL_SIGMAS * noise_std(u) if noisy else 0.0
    count, last = 1, float(u[0]) if len(u) else 0.0
    for x in u[1:].tolist():
        if abs(x - last) > tol:
            count, last = count + 1, x
    return count


def response_grid(ctx: Context) -> np.ndarray:
    """Candidate frequencies in cycles per normalised response unit (see MIN_CYCLES, SAMPLES_PER_PERIOD), counting
    the load levels visited (``load_levels``), not the samples: samples held at one level sample one phase; pitches
    of at least PITCH_NOISE_SIGMAS white-noise sigmas of the response."""
    span = float(np.ptp(ctx.y))
    if not span > 0.0:
        return np.zeros(0)
    passes = max(len(ctx.segments), 1)
    if "load_levels" not in ctx.cache:
        ctx.cache["load_levels"] = load_levels(ctx.u)
    if "response_noise" not in ctx.cache:
        ctx.cache["response_noise"] = noise_std(ctx.y)
    top = ctx.cache["load_levels"] / (SAMPLES_PER_PERIOD * passes)
    if ctx.cache["response_noise"] > 0.0:
        top = min(top, span / (PITCH_NOISE_SIGMAS * ctx.cache["response_noise"]))
    if top <= MIN_CYCLES:
        return np.zeros(0)
    return np.arange(MIN_CYCLES, top, 1.0 / GRID_PER_BIN) / span


def response_line(ctx: Context, r: np.ndarray) -> float:
    """The frequency (cycles per normalised response unit) at which ``r`` has most power against the measured
    response (a Schuster periodogram of the two harmonics over ``response_grid``), 0 unless it is a LINE:
    LINE_CONTRAST times the median power 3 to 12 Fourier bins away. A local event (a reading frozen for a few
    samples, a jump) spreads its power over every frequency; the encoder's error repeats and stands out."""
    grid = response_grid(ctx)
    if not len(grid):
        return 0.0
    x = r - r.mean()
    power = np.empty(len(grid))
    for idx in np.array_split(np.arange(len(grid)), max(1, len(grid) * len(x) // 2_000_000 + 1)):
        phase = np.exp(-2j * np.pi * np.outer(grid[idx], ctx.y))
        power[idx] = np.abs(phase @ x) ** 2 + np.abs((phase ** 2) @ x) ** 2
    k = int(np.argmax(power))
    near, far = 3 * GRID_PER_BIN, 12 * GRID_PER_BIN
    around = np.concatenate([power[max(k - far, 0):max(k - near, 0)], power[k + near:k + far]])
    if len(around) < 4 or power[k] < LINE_CONTRAST * float(np.median(around)):
        return 0.0
    return float(grid[k])


CACHE_KEY = "response_line"


def recorded_line(ctx: Context) -> tuple[float, float]:
    """(the recording's strongest line against its measured response, in cycles per normalised response unit, or
    0; the recorded span of the response), searched once on the residual of a straight line in the load and
    memoised on the context (a context of the same recording on more rows takes it over)."""
    if CACHE_KEY not in ctx.cache:
        A = np.column_stack([np.ones_like(ctx.u), ctx.t, ctx.u])
        coef, *_ = np.linalg.lstsq(A, ctx.y, rcond=None)
        ctx.cache[CACHE_KEY] = (response_line(ctx, ctx.y - A @ coef), float(np.ptp(ctx.y)))
    return ctx.cache[CACHE_KEY]


def response_columns(ctx: Context, f: float, harmonics=(1, 2)) -> np.ndarray:
    """cos, sin of 2 pi k f y for k in ``harmonics`` (y the measured response, normalised)."""
    return np.column_stack([g(2.0 * math.pi * k * f * ctx.y) for k in harmonics for g in (np.cos, np.sin)])


__all__ = ["ANGLE_LOAD_HARMONICS", "CACHE_KEY", "PITCH_NOISE_SIGMAS", "angle_load_columns", "load_levels", "recorded_line", "response_columns", "response_grid", "response_line"]
