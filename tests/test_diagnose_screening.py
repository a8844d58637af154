"""The diagnosis's shortcuts keep its answer: an effect's contribution is not evaluated again at the parameters it
was last evaluated at (fit._Contribution), and the best pair's other form combinations are screened, the best
unfinished ones refitted in full from the same start (candidates._screened)."""
import dataclasses
import itertools

import numpy as np
import pytest

from strainwave.compare.diagnose import candidates, fit
from strainwave.compare.diagnose.baseline import analytic_baseline
from strainwave.compare.diagnose.context import build_context
from strainwave.compare.diagnose.effects import effects_for
from strainwave.compare.diagnose.generators.cha import cha_recording, cha_rows
from strainwave.compare.diagnose.parallel import FitTask
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


def test_screened_combinations_keep_the_best_pair_and_the_full_fits(gear):
    """Every form of the loop beside every form of the stiffening: the screened set holds the combination the
    full fits rank first, each kept combination is bit for bit its full fit (converged within the screen, or
    refitted from the same start), and only unfinished ones outside the POLISHED best are left out."""
    j = gear.judge
    by_id: dict[str, list] = {}
    for f in gear.singles:
        by_id.setdefault(f.id, []).append(f)
    tasks = [FitTask(x.effects + y.effects, (np.concatenate([x.theta, y.theta]),), j.noise, candidates.SCREEN_NFEV)
             for x, y in itertools.product(by_id["hysteresis"], by_id["nonlinear_stiffness"])]
    full = [fit.fit_effects(j.ctx, t.effects, j.sigma, j.uncertainty, starts=list(t.starts), noise=j.noise)
            for t in tasks]
    kept = candidates._screened(j, tasks)
    labels = {f.label: f for f in kept}
    assert len(kept) < len(tasks)                     # the screen does leave some out on this recording
    assert min(full, key=lambda f: f.bic).label in labels
    for f in full:
        if f.label in labels:
            assert labels[f.label].bic == f.bic
            np.testing.assert_array_equal(labels[f.label].theta, f.theta)
    screened = [fit.fit_effects(j.ctx, t.effects, j.sigma, j.uncertainty, starts=list(t.starts),
                                max_nfev=candidates.SCREEN_NFEV, noise=j.noise) for t in tasks]
    unfinished = sorted((f for f in screened if not f.converged), key=lambda f: f.bic)
    assert {f.label for f in screened if f.label not in labels} == \
        {f.label for f in unfinished[candidates.POLISHED:]}
