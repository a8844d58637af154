"""The fits' shortcut keeps its answer: an effect's contribution is not evaluated again at the parameters it was
last evaluated at (fit._Contribution)."""
import dataclasses

import numpy as np
import pytest

from strainwave.compare.diagnose import candidates, fit
from strainwave.compare.diagnose.baseline import analytic_baseline
from strainwave.compare.diagnose.context import build_context
from strainwave.compare.diagnose.effects import effects_for
from strainwave.compare.diagnose.generators.cha import cha_recording, cha_rows
from strainwave.compare.diagnose.recording import parse_text


@pytest.fixture(scope="module")
def gear(params):
    """A CHA gear with a friction loop (three slopes beside a loop: the pair whose forms are combined)."""
    rec = parse_text(cha_recording(cha_rows()[3], hysteresis=True, n=600))
    base = analytic_baseline(rec, params)
    ctx = build_context(rec, base)
    return candidates.read_noise(rec, rec, base, ctx, workers=1)


def _counted(effect, calls: list):
    def contribution(ctx, theta):
        calls.append(np.asarray(theta, dtype=float).tobytes())
        return effect.contribution(ctx, theta)
    return dataclasses.replace(effect, contribution=contribution)


def test_a_difference_step_in_one_effect_does_not_evaluate_the_other(gear):
    """In a pair's fit, each effect is evaluated only where its own parameters moved: never twice in a row at
    the same parameters, so the loop (its parameters held while the stiffening's are differenced) is evaluated
    fewer times than the residual."""
    j = gear.judge
    forms = {e.label: e for e in effects_for("torsion")}
    loop_calls, stiff_calls = [], []
    effects = (_counted(forms["hysteresis[dahl]"], loop_calls), _counted(forms["nonlinear_stiffness"], stiff_calls))
    residuals = []
    original = fit.least_squares

    def spy(fun, x0, **kw):
        def counted(x):
            residuals.append(1)
            return fun(x)
        return original(counted, x0, **kw)

    fit.least_squares = spy
    try:
        fit.fit_effects(j.ctx, effects, j.sigma, j.uncertainty, noise=j.noise)
    finally:
        fit.least_squares = original
    for calls in (loop_calls, stiff_calls):
        assert all(a != b for a, b in zip(calls, calls[1:]))
    assert len(loop_calls) < 0.6 * len(residuals), (len(loop_calls), len(residuals))
