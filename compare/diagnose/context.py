"""Turn a recording and its baseline into the normalised ``Context`` the effect models work in.

Also finds the load reversals (loading/unloading segments) robustly against noise on the load channel.
"""
from __future__ import annotations

import numpy as np

from strainwave.compare.diagnose.baseline import Baseline
from strainwave.compare.diagnose.effects.base import Context
from strainwave.compare.diagnose.recording import Recording


def build_context(rec: Recording, baseline: Baseline, *, X: float | None = None,
                  time_map: tuple[float, float] | None = None) -> Context:
    """Normalise: u = load / max|load|, y = response / (c0 max|load|), t in [0, 1].

    ``X`` and ``time_map`` = (t0, span), in the recording's time (or row index) units, put the recording in
    another context's normalisation (the full recording in that of its fitted subsample)."""
    X = float(np.max(np.abs(rec.load))) if X is None else X
    Y = baseline.compliance * X
    u = rec.load / X
    t_raw = rec.time_s if rec.time_s is not None else np.arange(rec.n, dtype=float)
    t0, span = (float(t_raw[0]), float(t_raw[-1] - t_raw[0])) if time_map is None else time_map
    t = (t_raw - t0) / span if span > 0 else np.linspace(0.0, 1.0, rec.n)
    segments = find_segments(u, reversal_threshold(u))
    direction = np.empty(rec.n)
    for start, stop, d in segments:
        direction[start:stop] = d
    return Context(u=u, y=rec.response / Y, t=t, X=X, Y=Y, c0=baseline.compliance,
                   load_unit=rec.load_unit, response_unit=rec.response_unit, direction=direction,
                   segments=tuple(segments), geometry=dict(baseline.geometry),
                   uncertainty=baseline.uncertainty, angle=rec.extra.get("input_angle_rad"))


def reversal_threshold(u: np.ndarray) -> float:
    """A load reversal must exceed both 2 % of full scale and 6 sigma of the load channel's own noise."""
    d2 = np.diff(u, 2)
    sigma = 1.4826 * np.median(np.abs(d2 - np.median(d2))) / np.sqrt(6.0) if len(d2) else 0.0
    return max(0.02, 6.0 * sigma)


def find_segments(u: np.ndarray, threshold: float) -> list[tuple[int, int, int]]:
    """Monotonic stretches (start, stop, direction) between reversals, by a zig-zag filter.

    A turn is accepted only once the load has come back more than ``threshold`` from the
    running extreme, so noise on a plateau or a slow ramp does not create spurious reversals.
    """
    n = len(u)
    hi = lo = 0
    d = 0
    ext = 0
    starts, dirs = [0], []
    for i in range(1, n):
        x = u[i]
        if d == 0:
            if x > u[hi]:
                hi = i
            if x < u[lo]:
                lo = i
            if u[hi] - u[lo] > threshold:
                d = 1 if hi > lo else -1
                ext = hi if d > 0 else lo
                dirs.append(d)
        elif d > 0:
            if x >= u[ext]:
                ext = i
            elif u[ext] - x > threshold:
                starts.append(ext)
                d, ext = -1, i
                dirs.append(d)
        else:
            if x <= u[ext]:
                ext = i
            elif x - u[ext] > threshold:
                starts.append(ext)
                d, ext = 1, i
                dirs.append(d)
    if not dirs:
        dirs = [1 if u[-1] >= u[0] else -1]
    stops = starts[1:] + [n]
    return [(a, b, dd) for a, b, dd in zip(starts, stops, dirs) if b > a]
