"""Samples the noise cannot have made (glitches.py): a spike, a frozen reading, a jump, found on the innovations
of the final residual; clean noise of every colour the noise model describes raises none."""
import math

import numpy as np
import pytest

from strainwave.compare.diagnose.generators import family2_sensors as fs
from strainwave.compare.diagnose.baseline import analytic_baseline
from strainwave.compare.diagnose import glitches
from strainwave.compare.diagnose.glitches import ALPHA, GROSS_SIGMAS, GlitchKind, find_glitch
from strainwave.compare.diagnose.pipeline import Verdict, diagnose
from strainwave.compare.diagnose.recording import RecordingKind, format_recording, parse_text
from strainwave.compare.diagnose.structure import NoiseModel, fine_scale_noise

X = 1e6
WHITE = NoiseModel(np.array([1.0]), np.array([1.0]), 1.0)


def _clean(params, n=1500, noise=None, seed=0):
    """A linear shaft recording, two full cycles, white noise of 0.2 % of full scale (or ``noise``)."""
    T = X * np.interp(np.linspace(0, 4, n), np.arange(5), [0, 1, -1, 1, 0])
    probe = parse_text(format_recording(RecordingKind.TORSION, "output_shaft", T, T * 0 + 1.0))
    c0 = analytic_baseline(probe, params).compliance
    sigma = 2e-3 * c0 * X
    e = sigma * np.random.default_rng(seed).standard_normal(n) if noise is None else noise(sigma, n)
    return T, c0 * T + e, sigma


def _diagnose(params, T, y):
    return diagnose(parse_text(format_recording(RecordingKind.TORSION, "output_shaft", T, y)), params)[0]


def test_white_noise_raises_no_glitch_at_the_stated_rate(monkeypatch):
    # the Bonferroni point alone (no gross floor): 400 records of 2,000 standard-normal samples, ALPHA = 1e-3
    # per record expects 0.4 alarms; 3 or more would happen by chance with probability 0.8 % (Poisson(0.4))
    monkeypatch.setattr(glitches, "GROSS_SIGMAS", 0.0)
    rng = np.random.default_rng(7)
    rows = np.arange(2000)
    alarms = sum(find_glitch(rng.standard_normal(2000), WHITE, rows, rng.standard_normal(2000), rows * 1.0)
                 is not None for _ in range(400))
    assert 400 * ALPHA == pytest.approx(0.4)
    assert alarms <= 2


def test_spike_is_found_where_it_is_and_named(params):
    T, y, sigma = _clean(params)
    y = y.copy()
    y[700] += 30.0 * sigma
    d = _diagnose(params, T, y)
    assert d.verdict is Verdict.UNEXPLAINED and d.named == () and d.suggestion is None
    assert "sample 701 " in d.structure and "spike" in d.structure
    assert "apart from it, the residual is consistent with the noise" in d.structure


def test_frozen_reading_is_named_with_its_run(params):
    T, y, _ = _clean(params)
    y = y.copy()
    y[400:420] = y[400]                        # 20 samples frozen mid-ramp, then the channel catches up
    d = _diagnose(params, T, y)
    assert d.verdict is Verdict.UNEXPLAINED
    assert "frozen reading" in d.structure and "(401-420)" in d.structure


def test_jump_that_stays_is_named_a_jump():
    rng = np.random.default_rng(3)
    r = rng.standard_normal(1000)
    r[600:] += 2.0 * GROSS_SIGMAS              # a slip: the level changes and stays
    rows = np.arange(1000)
    g = find_glitch(r, WHITE, rows, r, rows * 1.0)
    assert g is not None and g.kind is GlitchKind.JUMP and g.sample == 601


def _sensor(kind: str, seed: int):
    """noise(sigma, n) of one sensor: AR(1) 0.95, 2nd-order low-pass at 5 % of Nyquist, white + random walk
    (wander 0.7), or white quantised at 1.5 sigma."""
    def noise(sigma, n):
        rng = np.random.default_rng(seed)
        if kind == "quantised":
            return fs.quantise(sigma * rng.standard_normal(n), 1.5 * sigma)
        return fs.coloured_noise(rng, n, sigma, kind, rho=0.95, fc=0.05, wander=0.7)
    return noise


@pytest.mark.parametrize("kind", ["ar1", "lowpass", "random_walk", "quantised"])
def test_clean_coloured_or_quantised_noise_still_agrees(params, kind):
    T, y, _ = _clean(params, noise=_sensor(kind, 11))
    d = _diagnose(params, T, y)
    assert d.verdict is Verdict.AGREES, d.structure


def test_a_hold_at_constant_load_repeating_a_quantised_reading_is_no_frozen_channel():
    # a hold: the load stays, the quantised twist repeats; the load did not move, so nothing froze
    rows = np.arange(200)
    load = np.concatenate([np.linspace(0, 1, 100), np.ones(100)])
    response = np.round(np.concatenate([np.linspace(0, 50, 100), np.full(100, 50.0)]))
    r = np.random.default_rng(0).standard_normal(200)
    r[150] = 4.0 * GROSS_SIGMAS
    g = find_glitch(r, WHITE, rows, response, load)
    assert g is not None and g.kind is not GlitchKind.FROZEN and math.isfinite(g.sigmas)


def test_a_departure_below_the_gross_floor_is_left_to_the_structure_test():
    # 8 sigma on white noise is far beyond the Bonferroni point (4.9 at 1,000) but within what a right model of
    # another form leaves at a sharp feature at high signal-to-noise: no glitch
    r = np.random.default_rng(5).standard_normal(1000)
    r[300] += 8.0
    rows = np.arange(1000)
    assert find_glitch(r, WHITE, rows, r, rows * 1.0) is None
    r[300] += 8.0
    assert find_glitch(r, WHITE, rows, r, rows * 1.0).kind is GlitchKind.SPIKE


def test_spike_on_a_row_the_fit_skipped_is_found(params):
    # 10,000 rows are fitted on every 4th (MAX_FIT_ROWS 2,500): row 4,001 is not among them
    T, y, sigma = _clean(params, n=10_000)
    y = y.copy()
    y[4001] += 30.0 * sigma
    d = _diagnose(params, T, y)
    assert d.verdict is Verdict.UNEXPLAINED and "sample 4002 " in d.structure and "spike" in d.structure


@pytest.mark.heavy
@pytest.mark.parametrize("kind", ["white", "ar1", "random_walk", "quantised"])
def test_clean_long_recording_raises_no_glitch(params, kind):
    # every row is checked (the fit sees every 4th): the full-rate residual's own noise model keeps the
    # innovations standard-normal for each noise colour. (The goodness-of-fit test itself is not under test
    # here: on this random-walk draw it reads the wander as rate dependence, with or without the glitch check.)
    noise = _sensor(kind, 13)
    T, y, sigma = _clean(params, n=10_000, noise=noise)
    d = _diagnose(params, T, y)
    assert "departs from the model" not in d.structure
    assert d.verdict is Verdict.AGREES or kind == "random_walk"
    # the same full-rate path on the noise itself, whatever the verdict
    e = noise(sigma, 10_000) / sigma
    rows = np.arange(10_000)
    assert find_glitch(e, fine_scale_noise(e), rows, e, rows * 1.0) is None


def test_a_departure_at_a_load_reversal_is_not_judged():
    """At a load reversal the load's true extreme may lie between two samples, so the model misses the travel
    nobody recorded: a departure at the reversal or beside it is no glitch; the same departure away from it is."""
    rng = np.random.default_rng(5)
    r = rng.standard_normal(1000)
    r[500] += 3.0 * GROSS_SIGMAS
    rows = np.arange(1000)
    assert find_glitch(r, WHITE, rows, r, rows * 1.0, reversals=np.array([250, 499, 750])) is None
    g = find_glitch(r, WHITE, rows, r, rows * 1.0, reversals=np.array([250, 750]))
    assert g is not None and g.kind is GlitchKind.SPIKE and g.sample == 501


def test_step_noise_std_is_the_line_extrapolation_error_on_white_noise():
    # two independent 10-sample least-squares lines extrapolated one step past their ends: each has variance
    # 1/10 + 5.5^2/82.5 (x from the line's mean, over the sum of squared deviations), the difference twice that
    one_side = 1.0 / 10 + 5.5 ** 2 / 82.5
    assert glitches.step_noise_std(WHITE) == pytest.approx(math.sqrt(2.0 * one_side), rel=1e-9)
    # a sampled resonant sensor: the std of the step over many positions of a long record matches the model's
    ar = NoiseModel(np.array([1.0, -1.65, 0.759]), np.array([1.0]), 1.0)
    from scipy.signal import lfilter
    r = lfilter([1.0], ar.b, np.random.default_rng(2).standard_normal(200_000))
    w = glitches._step_weights()
    steps = np.convolve(r, w[::-1], mode="valid")
    assert np.std(steps) == pytest.approx(glitches.step_noise_std(ar), rel=0.03)


def test_a_corner_in_resonant_noise_is_no_jump_but_a_real_jump_is():
    # AR(2) 1.65, -0.76 (a resonant sensor; heldout6's Bouc-Wen loop at 50x read "a jump" behind it): one
    # innovation of 12 sigma (a corner the model draws with another form, whitened into one large innovation)
    # moves the two sides' lines by about what the sensor's own swing does; a slip of 6 step stds (41
    # innovation sigmas) still reads a jump
    ar = NoiseModel(np.array([1.0, -1.65, 0.759]), np.array([1.0]), 1.0)
    from scipy.signal import lfilter
    e = np.random.default_rng(4).standard_normal(1000)
    e[500] += 12.0
    r = lfilter([1.0], ar.b, e)
    rows = np.arange(1000)
    assert find_glitch(r, ar, rows, r, rows * 1.0) is None
    e2 = np.random.default_rng(4).standard_normal(1000)
    jumped = lfilter([1.0], ar.b, e2)
    jumped[600:] += 6.0 * glitches.step_noise_std(ar)
    g = find_glitch(jumped, ar, rows, jumped, rows * 1.0)
    assert g is not None and g.kind is GlitchKind.JUMP and abs(g.sample - 601) <= 2
