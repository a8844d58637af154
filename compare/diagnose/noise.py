"""Noise level of the response channel, estimated from the recording itself.

Second differences in acquisition order cancel offsets, drift and any smooth load dependence;
for white noise of std sigma they have variance 6 sigma^2. The largest 10 % are trimmed (load
reversals, kinks of a dead band) and the trimmed mean square is corrected back to a Gaussian variance.
Unlike a median (MAD) this does not collapse to zero when encoder quantization makes most differences 0.
"""
from __future__ import annotations

import math

import numpy as np
from scipy import stats

KEEP = 0.9
# E[z^2 | |z| < q] for a standard normal, q the two-sided KEEP quantile
_Q = stats.norm.ppf(0.5 + KEEP / 2.0)
_TRIM_FACTOR = 1.0 - 2.0 * _Q * stats.norm.pdf(_Q) / KEEP


def noise_std(residual: np.ndarray) -> float:
    """Std of the white part of ``residual`` (any smooth trend is ignored)."""
    d2 = np.diff(residual, 2)
    if len(d2) < 3:
        return float(np.std(residual))
    a = np.abs(d2)
    cut = np.quantile(a, KEEP)
    kept = d2[a <= cut]
    var = float(np.mean(kept ** 2)) / _TRIM_FACTOR / 6.0
    return math.sqrt(var) if var > 0 else float(np.std(np.diff(residual))) / math.sqrt(2.0) + 1e-300
