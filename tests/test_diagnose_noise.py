"""Noise from the data itself and load reversals from a noisy load channel."""
import numpy as np
import pytest

from strainwave.compare.diagnose.context import find_segments, reversal_threshold
from strainwave.compare.diagnose.noise import noise_std


def test_noise_estimate_ignores_trend_and_drift():
    rng = np.random.default_rng(0)
    x = np.linspace(-1, 1, 5000)
    y = 3 * x + 0.4 * np.tanh(x / 0.2) + 0.1 * np.linspace(0, 1, 5000) + 0.01 * rng.standard_normal(5000)
    # 5000 samples: the std of a variance estimate from trimmed second differences is ~3 %; allow 6 %
    assert noise_std(y) == pytest.approx(0.01, rel=0.06)


def test_noise_estimate_survives_quantization():
    rng = np.random.default_rng(1)
    y = np.round((np.linspace(0, 1, 4000) * 0.05 + 0.002 * rng.standard_normal(4000)) / 0.004) * 0.004
    # white 0.002 plus quantization 0.004/sqrt(12) = 0.00115: total 0.0023; a median-based estimate gives 0.
    # Quantization noise is not Gaussian, so the trimmed estimate is only good to ~20 %.
    assert noise_std(y) == pytest.approx(np.hypot(0.002, 0.004 / np.sqrt(12)), rel=0.2)


def test_reversals_found_once_despite_noise():
    rng = np.random.default_rng(2)
    knots = [0, 1, -1, 1, 0]
    u = np.interp(np.linspace(0, 4, 2000), np.arange(5), knots) + 0.003 * rng.standard_normal(2000)
    segs = find_segments(u, reversal_threshold(u))
    assert [d for _, _, d in segs] == [1, -1, 1, -1]
    starts = [a for a, _, _ in segs[1:]]
    # true turning points at samples 500, 1000, 1500; noise 0.3 % of full scale moves the extreme by a few samples
    assert np.allclose(starts, [500, 1000, 1500], atol=15)
