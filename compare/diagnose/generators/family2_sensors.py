"""Family-2 measurement chain: noise colours and sensor artefacts, applied to noise-free channels.

Noise (all scaled to a stationary standard deviation ``sigma``):
- white; AR(1) e_k = rho e_{k-1} + sqrt(1 - rho^2) sigma w_k (stationary start);
- low-pass: white noise through a 2nd-order Butterworth filter, cut-off ``fc`` of Nyquist, rescaled;
- random walk: white noise plus an integrated-white-noise wander (an encoder or bridge creeping), whose
  standard deviation about its own mean is ``wander`` sigma (white part sqrt(1 - wander^2) sigma).
Artefacts: quantisation, hard clipping at an ADC full scale, soft (tanh) saturation of a channel,
a channel delayed by whole samples.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.signal import butter, lfilter


def coloured_noise(rng: np.random.Generator, n: int, sigma: float, kind: str, *, rho: float = 0.9,
                   fc: float = 0.1, wander: float = 0.7) -> np.ndarray:
    w = rng.standard_normal(n)
    if kind == "white":
        return sigma * w
    if kind == "ar1":
        if not 0.0 <= rho < 1.0:
            raise ValueError("rho must be in [0, 1)")
        e = np.empty(n)
        e[0] = w[0]                                          # stationary start: unit variance
        e[1:] = lfilter([math.sqrt(1.0 - rho ** 2)], [1.0, -rho], w[1:], zi=[rho * w[0]])[0]
        return sigma * e
    if kind == "lowpass":
        b, a = butter(2, fc)
        burn = int(20 / fc)                                  # let the filter forget its start
        e = lfilter(b, a, rng.standard_normal(n + burn))[burn:]
        return sigma * e / float(np.std(e))
    if kind == "random_walk":
        if not 0.0 < wander < 1.0:
            raise ValueError("wander must be in (0, 1)")
        walk = np.cumsum(rng.standard_normal(n))
        walk -= walk.mean()
        return sigma * (math.sqrt(1.0 - wander ** 2) * w + wander * walk / float(np.std(walk)))
    raise ValueError(f"noise kind {kind!r}: must be white, ar1, lowpass or random_walk")


def quantise(y: np.ndarray, step: float) -> np.ndarray:
    return np.round(y / step) * step if step > 0 else y


def clip(y: np.ndarray, low: float, high: float) -> np.ndarray:
    """An ADC that reads its full scale for anything beyond it."""
    return np.clip(y, low, high)


def soft_saturate(x: np.ndarray, full_scale: float) -> np.ndarray:
    """An amplifier running into its rails: linear for small x, tending to +/- full_scale."""
    return full_scale * np.tanh(x / full_scale)


def delay(y: np.ndarray, samples: int) -> np.ndarray:
    """The channel as recorded ``samples`` later than the other one (first value held)."""
    if samples <= 0:
        return y.copy()
    return np.concatenate([np.full(samples, y[0]), y[:-samples]])


__all__ = ["clip", "coloured_noise", "delay", "quantise", "soft_saturate"]
