"""Mains pick-up: a 50 or 60 Hz line in the response, reported as interference beside the specimen's verdict.

A line at the mains frequency (within MAINS_TOLERANCE; seen at its alias where the sampling rate folds it) is a
rig fault, not the specimen's: no load history draws it. Where it swings (peak to peak) by MIN_COMPONENT_SIGMAS
white-noise sigmas or more and is significant (its two terms improve BIC by more than BIC_THRESHOLD), it is
named as interference and taken out of the response before the diagnosis, so the verdict is the specimen's.

The line is sought in the residual of a load model that draws any smooth single- or double-valued curve
(a polynomial of LOAD_DEGREE in the load per loading direction, plus a line in time): a loop or a stiffening
puts its power at the load cycle's harmonics, not at the mains line's alias. The white noise is sized on the
residual WITHOUT the line (a line inflates a difference-based estimate).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from strainwave.compare.diagnose.judge import BIC_THRESHOLD
from strainwave.compare.diagnose.structure import MIN_COMPONENT_SIGMAS

MAINS_HZ = (50.0, 60.0)
MAINS_TOLERANCE = 0.01      # grids hold their frequency within 1 % (EN 50160: 50 Hz +/- 1 % for 99.5 % of a year)
LOAD_DEGREE = 7
LINE_OVER_FLOOR = 20.0      # periodogram power over the neighbouring spectrum's median (white: P(>20x) ~ 1e-6)
MIN_CYCLES = 4.0            # a line fewer cycles than this over the record is a drift, not a line


@dataclass(frozen=True)
class MainsLine:
    mains_hz: float
    seen_hz: float              # where the sampling rate shows it
    amplitude: float            # response units
    sigmas: float               # peak-to-peak swing in white-noise sigmas (the noise without the line)
    line: np.ndarray            # the fitted line, every row

    def sentence(self, response_name: str = "twist", unit: str = "rad") -> str:
        seen = "" if abs(self.seen_hz - self.mains_hz) < 0.02 * self.mains_hz else \
            f", seen at its alias {self.seen_hz:.4g} Hz at this sampling rate"
        return (f"mains interference: a {self.mains_hz:g} Hz line in the {response_name}{seen}, amplitude "
                f"{self.amplitude:.3g} {unit} ({self.sigmas:.2g} white-noise sigmas peak to peak); a rig fault "
                f"(screening, earthing), taken out before the diagnosis: the verdict is the specimen's")


def _alias(f: float, fs: float) -> float:
    return abs(f - fs * round(f / fs))


def load_basis(load: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Any smooth curve of the load per loading direction (a loop, a stiffening), plus a line in time."""
    x = load / (float(np.max(np.abs(load))) or 1.0)
    d = np.sign(np.gradient(x))
    up = (d >= 0).astype(float)
    cols = [x ** k for k in range(LOAD_DEGREE + 1)] + [up * x ** k for k in range(LOAD_DEGREE + 1)]
    return np.column_stack(cols + [(t - t[0]) / (t[-1] - t[0])])


def find_mains(load: np.ndarray, response: np.ndarray, time_s: np.ndarray | None) -> MainsLine | None:
    """The mains line of the response (see the module doc), or None."""
    if time_s is None or len(time_s) < 50 or not time_s[-1] > time_s[0]:
        return None
    n, span = len(time_s), float(time_s[-1] - time_s[0])
    fs = (n - 1) / span
    A = load_basis(load, time_s)
    q, _ = np.linalg.qr(A)
    r = response - q @ (q.T @ response)
    m = 4 * n                                   # zero-padded: the peak located to a quarter of a bin
    power = np.abs(np.fft.rfft(r, m))
    freqs = np.fft.rfftfreq(m, d=span / (n - 1))
    best = None
    for f0 in MAINS_HZ:
        lo, hi = (_alias(f0 * (1.0 + s * MAINS_TOLERANCE), fs) for s in (-1.0, 1.0))
        lo, hi = max(min(lo, hi), MIN_CYCLES / span), max(lo, hi)
        band = np.flatnonzero((freqs >= lo) & (freqs <= hi))
        if len(band) == 0:
            continue
        k = int(band[np.argmax(power[band])])
        if best is None or power[k] > best[2]:
            best = (f0, float(freqs[k]), float(power[k]))
    if best is None:
        return None
    f0, f, peak = best
    # a line is narrow: its power stands LINE_OVER_FLOOR above the median of the spectrum from f/2 to 2f (a
    # load-model misfit, a rate-dependent loop, coloured noise have smooth spectra; at the floor's 1.5 sigma
    # swing and 300 rows a sinusoid stands ~40x above white noise's median)
    near = (freqs >= 0.5 * f) & (freqs <= 2.0 * f) & (np.abs(freqs - f) > 4.0 / span)
    if np.any(near) and peak ** 2 < LINE_OVER_FLOOR * float(np.median(power[near] ** 2)):
        return None
    w = 2.0 * np.pi * f * (time_s - time_s[0])
    full = np.column_stack([A, np.cos(w), np.sin(w)])
    coef, *_ = np.linalg.lstsq(full, response, rcond=None)
    rest = response - full @ coef
    rss0, rss1 = float(r @ r), float(rest @ rest)
    if not rss1 > 0.0 or n * math.log(rss0 / rss1) - 2.0 * math.log(n) <= BIC_THRESHOLD:
        return None
    sigma = float(np.std(np.diff(rest))) / math.sqrt(2.0)
    amplitude = float(math.hypot(coef[-2], coef[-1]))
    if not sigma > 0.0 or 2.0 * amplitude < MIN_COMPONENT_SIGMAS * sigma:
        return None
    return MainsLine(f0, f, amplitude, 2.0 * amplitude / sigma, coef[-2] * np.cos(w) + coef[-1] * np.sin(w))


__all__ = ["MAINS_HZ", "MAINS_TOLERANCE", "MainsLine", "find_mains", "load_basis"]
