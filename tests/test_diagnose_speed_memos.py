"""The diagnosis's speed shortcuts keep its answer bit for bit (issue 51, item 8): the last loop state kept per
law, the Bouc-Wen travel table's fixed nodes, the memoised noise variograms and the parallel fits' claim order."""
import dataclasses

import numpy as np
import pytest

from strainwave.compare.diagnose import structure
from strainwave.compare.diagnose.baseline import analytic_baseline
from strainwave.compare.diagnose.context import build_context
from strainwave.compare.diagnose.effects import effects_for, hysteresis
from strainwave.compare.diagnose.generators.cha import cha_recording, cha_rows
from strainwave.compare.diagnose.parallel import FitTask, _cost
from strainwave.compare.diagnose.recording import parse_text


@pytest.fixture(scope="module")
def ctx(params):
    rec = parse_text(cha_recording(cha_rows()[3], hysteresis=True, n=400))
    return build_context(rec, analytic_baseline(rec, params))


def _fresh(ctx):
    """The same context with an empty memo (dataclasses.replace starts a new cache)."""
    return dataclasses.replace(ctx, u=ctx.u.copy())


@pytest.mark.parametrize("label, theta, moved", [
    ("hysteresis[dahl]", [0.02, -1.2], [0.02, -1.1]),
    ("hysteresis[dahl-exponent]", [0.5, -1.2, 0.7], [0.5, -1.2, 1.4]),
    ("hysteresis[bouc-wen]", [0.5, -1.2, 1.5, 0.8], [0.5, -1.2, 1.5, 0.3]),
])
def test_a_kept_loop_state_is_the_state_computed_afresh(ctx, label, theta, moved):
    """An amplitude step reuses the state, any other parameter recomputes it: each contribution equals, bit for
    bit, the one computed on a context with an empty memo (a stale state would differ by the moved parameter)."""
    form = {e.label: e for e in effects_for("torsion")}[label]
    for th in (theta, [theta[0] * 1.3, *theta[1:]], moved, theta):
        got = form.contribution(ctx, np.array(th))
        want = form.contribution(_fresh(ctx), np.array(th))
        np.testing.assert_array_equal(got, want)
    assert not np.array_equal(form.contribution(ctx, np.array(moved)), form.contribution(ctx, np.array(theta)))


@pytest.mark.parametrize("n, q", [(1.0, 1.0), (2.0, 0.5), (0.7, 2.5)])
def test_the_travel_table_is_the_quadrature_written_out(n, q):
    """bouc_wen_travel on its precomputed nodes: the trapezoids in x up to 0 and in g beyond, written out here."""
    x_neg = np.linspace(-1.0, 0.0, 801)
    g_pos = np.linspace(0.0, 12.0 * np.log(10.0), 4001)
    x_pos = -np.expm1(-g_pos)
    rate_neg = 1.0 + q * np.abs(x_neg) ** n
    f_pos = (1.0 - x_pos) / (1.0 - x_pos ** n)
    tau_neg = np.concatenate([[0.0], np.cumsum(0.5 * (1.0 / rate_neg[1:] + 1.0 / rate_neg[:-1]) * np.diff(x_neg))])
    tau_pos = tau_neg[-1] + np.concatenate([[0.0], np.cumsum(0.5 * (f_pos[1:] + f_pos[:-1]) * np.diff(g_pos))])
    tau, g = hysteresis.bouc_wen_travel.__wrapped__(n, q)
    np.testing.assert_array_equal(tau, np.concatenate([tau_neg[:-1], tau_pos]))
    np.testing.assert_array_equal(g, np.concatenate([-np.log1p(-x_neg[:-1]), g_pos]))
    # Dahl's law is Bouc-Wen's n = 1, q = 1: the travel to x is w ln((1 + 1)/(1 - x)) from x = -1
    if n == 1.0 and q == 1.0:
        x = -np.expm1(-g)
        np.testing.assert_allclose(tau, np.log(2.0 / (1.0 - x)), rtol=1e-5, atol=1e-8)


def test_a_memoised_variogram_is_the_impulse_response_and_cannot_be_changed():
    """The variogram of a random walk plus white (ARMA(1,1), phi = 1) is linear in the lag: v(k) = (1 - theta)^2
    k / 2 + theta (white part theta, a unit innovation's walk (1 - theta)^2 per step); the memo hands out copies."""
    b, a, lags = np.array([1.0, -1.0]), np.array([1.0, -0.5]), np.arange(1, 17)
    v = structure._variogram(b, a, lags)
    np.testing.assert_allclose(v, 0.25 * lags / 2.0 + 0.5, rtol=1e-9)
    v[:] = -1.0
    np.testing.assert_allclose(structure._variogram(b, a, lags), 0.25 * lags / 2.0 + 0.5, rtol=1e-9)


def test_the_costliest_fits_are_claimed_first():
    """Bouc-Wen (8 starts of 4 searched parameters) is costlier than a Preisach density (its weights solved
    inside the residual: one start, nothing searched)."""
    forms = {e.label: e for e in effects_for("torsion")}
    assert _cost(FitTask((forms["hysteresis[bouc-wen]"],))) == 8 * 5
    assert _cost(FitTask((forms["hysteresis[preisach]"],))) == 1
    assert _cost(FitTask((forms["hysteresis[bouc-wen]"],), starts=(np.zeros(4),))) == 5


def test_forms_with_a_basis_are_fitted_by_the_parent_and_the_answer_is_one_process_s(params, tmp_path):
    """Two workers: the Preisach and play densities are fitted here (their bases built once, after the fork), the
    other forms shared; every fit equals the one-process fit bit for bit."""
    import os

    from strainwave.compare.diagnose.parallel import fit_all
    rec = parse_text(cha_recording(cha_rows()[3], hysteresis=True, n=400))
    forms = [e for e in effects_for(rec.kind.value) if e.label in (
        "hysteresis[preisach]", "hysteresis[play]", "hysteresis[preisach-fine]", "hysteresis[play-fine]",
        "hysteresis[dahl]")]
    parent = os.getpid()

    def traced(e):
        def contribution(c, theta):
            if os.getpid() != parent:                  # the copy leaves a mark the parent can see
                (tmp_path / e.label).touch()
            return e.contribution(c, theta)
        return dataclasses.replace(e, contribution=contribution)

    tasks = [FitTask((traced(e),)) for e in forms]
    serial = fit_all(build_context(rec, analytic_baseline(rec, params)), tasks, 1e-3, 0.3, workers=1)
    shared = fit_all(build_context(rec, analytic_baseline(rec, params)), tasks, 1e-3, 0.3, workers=2)
    in_copy = {p.name for p in tmp_path.iterdir()}
    assert in_copy <= {"hysteresis[dahl]"}, in_copy
    for a, b in zip(serial, shared):
        assert a.bic == b.bic and a.nuisance == b.nuisance
        np.testing.assert_array_equal(a.theta, b.theta)
        np.testing.assert_array_equal(a.model, b.model)


def test_the_step_after_each_fit_is_applied_whichever_process_made_it(params):
    """``then`` (the loop's stiffness prior in the diagnosis) is applied to every fit, the copy's too, once."""
    from strainwave.compare.diagnose.parallel import fit_all
    rec = parse_text(cha_recording(cha_rows()[3], hysteresis=True, n=400))
    ctx = build_context(rec, analytic_baseline(rec, params))
    tasks = [FitTask((e,)) for e in effects_for(rec.kind.value)
             if e.label in ("hysteresis[dahl]", "lost_motion", "nonlinear_stiffness", "crack_closure")]

    def then(c, f):
        return dataclasses.replace(f, bic=f.bic + 1000.0)
    plain = fit_all(ctx, tasks, 1e-3, 0.3, workers=1)
    for workers in (1, 2):
        for a, b in zip(plain, fit_all(ctx, tasks, 1e-3, 0.3, workers=workers, then=then)):
            assert b.bic == a.bic + 1000.0 and [e.label for e in b.effects] == [e.label for e in a.effects]
