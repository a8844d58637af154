"""The noise model's slow power (structure.slow_power_inflation): a steep low-pass sensor is drawn at the fine
scales by a filter whose power at the slow structures' frequencies falls short of the sensor's; white and
correctly modelled noise are left as they are."""
import math

import numpy as np
import pytest
from scipy import signal

from strainwave.compare.diagnose.structure import NoiseModel, fine_scale_noise, slow_power_inflation


def test_noise_model_psd_is_the_filters_closed_form():
    # AR(1) r_k = 0.9 r_(k-1) + e_k: whitening filter b = [1, -0.9]; S(w) = var / |1 - 0.9 e^-iw|^2
    m = NoiseModel(np.array([1.0, -0.9]), np.array([1.0]), 2.0)
    w = np.array([0.0, 0.3, math.pi])
    assert m.psd(w) == pytest.approx(2.0 / np.abs(1.0 - 0.9 * np.exp(-1j * w)) ** 2, rel=1e-12)


@pytest.mark.parametrize("kind", ["white", "ar1"])
def test_noise_the_fine_scale_filter_draws_right_is_not_inflated(kind):
    # 20 records each: the bound is one-sided at 1 % over its bands, so nearly all read exactly 1
    out = []
    for seed in range(20):
        e = np.random.default_rng(seed).standard_normal(3000)
        x = e if kind == "white" else signal.lfilter([1.0], [1.0, -0.9], e)
        out.append(slow_power_inflation(x, fine_scale_noise(x)))
    assert sum(v > 1.0 for v in out) <= 2 and max(out) < 1.3


def test_steep_low_pass_sensor_is_inflated_to_its_passband_level():
    # Butterworth order 5 at 0.16 Nyquist: flat passband down to zero frequency, which the fine-scale filter
    # (an AR(2)) draws 3 to 7 times too low there; the bound recovers at least half of the shortfall and never
    # more than all of it (it is a lower bound)
    b, a = signal.butter(5, 0.16)
    for seed in range(3):
        x = signal.lfilter(b, a, np.random.default_rng(seed).standard_normal(9000))[5000:]
        model = fine_scale_noise(x)
        slow = 2.0 * np.pi * np.arange(1, 9) / len(x)
        _, h = signal.freqz(b, a, slow)
        shortfall = float(np.min(np.abs(h) ** 2 / model.psd(slow)))
        assert shortfall > 2.0
        assert 0.5 * shortfall < slow_power_inflation(x, model) <= shortfall * 1.05
