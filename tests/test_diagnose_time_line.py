"""A line in time that the load does not share (mains pick-up, a pump): reported as a rig fault where a user can
see it (a swing of structure.MIN_COMPONENT_SIGMAS white-noise sigmas), not where thousands of samples merely make
a sub-noise line statistically evident. The recordings are a shaft on its baseline compliance under a sine torque,
white noise and a sinusoid in time at 0.1371 cycles per sample (no harmonic of the load's 2.5 cycles)."""
import numpy as np
import pytest

from strainwave.compare.diagnose.baseline import analytic_baseline
from strainwave.compare.diagnose.pipeline import Verdict, diagnose
from strainwave.compare.diagnose.recording import RecordingKind, format_recording, parse_text
from strainwave.compare.diagnose.structure import MIN_COMPONENT_SIGMAS

K = RecordingKind.TORSION
X = 1e6          # N*mm full scale
SIGMA = 0.004    # white noise over the full-scale twist


def _diagnose(params, amplitude_sigmas: float, n: int = 1500):
    k = np.arange(n)
    u = np.sin(2.0 * np.pi * 2.5 * k / n)
    probe = parse_text(format_recording(K, "output_shaft", u * X, u))
    c = analytic_baseline(probe, params).compliance
    line = amplitude_sigmas * SIGMA * np.sin(2.0 * np.pi * 0.1371 * k + 0.4)
    y = (u + SIGMA * np.random.default_rng(0).standard_normal(n) + line) * X * c
    return diagnose(parse_text(format_recording(K, "output_shaft", u * X, y)), params, workers=1)[0]


def test_sub_visible_hum_is_noise(params):
    # amplitude 0.5 sigma (swing 1 sigma < 1.5): on 1,500 rows its delta BIC is far beyond 10 (the line is real)
    assert 2 * 0.5 < MIN_COMPONENT_SIGMAS
    diag = _diagnose(params, 0.5)
    assert diag.verdict is Verdict.AGREES
    line = next(s for s in diag.gof_baseline.structures if s.name == "periodic_time")
    assert line.delta_bic > 10.0 and not line.visible


@pytest.mark.parametrize("amplitude", [1.0])
def test_visible_hum_is_a_rig_fault(params, amplitude):
    # swing 2 sigma: the line is reported, periodic in time
    diag = _diagnose(params, amplitude)
    assert diag.verdict is Verdict.UNEXPLAINED and "periodic in time" in diag.structure
