"""The three-outcome verdict from first principles (issue 12): friction dissipates; coloured noise is no
mismatch; physics outside the catalogue is *unexplained* with its structure described; a second effect
must earn its place; every model form of hysteresis is reported through its loop width and energy."""
import math
import warnings

import numpy as np
import pytest

from strainwave.compare.diagnose.baseline import analytic_baseline
from strainwave.compare.diagnose.context import build_context
from strainwave.compare.diagnose import rate_loop
from strainwave.compare.diagnose.effects import hysteresis
from strainwave.compare.diagnose.effects.loop import loop_quantities
from strainwave.compare.diagnose.pipeline import Verdict, diagnose
from strainwave.compare.diagnose.recording import RecordingKind, format_recording, parse_text
from strainwave.params import load_params

K = RecordingKind.TORSION
X = 1e6          # N*mm full scale


def _path(n, knots=(0, 1, -1, 1, -1, 0)):
    return np.interp(np.linspace(0, len(knots) - 1, n), np.arange(len(knots)), knots)


def _ctx(params, u):
    probe = parse_text(format_recording(K, "output_shaft", u * X, u))
    return build_context(probe, analytic_baseline(probe, params))


def _noise(kind, n, rng):
    e = rng.standard_normal(n)
    if kind == "ar1":                      # AR(1), rho = 0.95
        x = np.zeros(n)
        for i in range(1, n):
            x[i] = 0.95 * x[i - 1] + e[i]
        e = x
    elif kind == "random_walk":
        e = np.cumsum(e)
    elif kind == "low_pass":               # 15-sample moving average (a sensor's anti-alias filter)
        e = np.convolve(e, np.ones(15) / 15, mode="same")
    return e / np.std(e)


def _diagnose(params, extra, *, n=800, noise="white", sigma=2e-3, seed=0, time_s=None, angle=None):
    """Baseline + extra(u, t, ctx) + offset + linear drift + noise (normalised units), diagnosed blind."""
    rng = np.random.default_rng(seed)
    u = _path(n)
    ctx = _ctx(params, u)
    t = np.linspace(0, 1, n)
    y = u + 0.01 + 0.003 * t + extra(u, t, ctx) + sigma * _noise(noise, n, rng)
    rec = parse_text(format_recording(K, "output_shaft", u * X, y * ctx.Y, time_s=time_s, input_angle_rad=angle))
    return diagnose(rec, params)[0], ctx


def _bouc_wen(u, z_max=0.05, beta=0.5, gamma=0.5):
    """Bouc-Wen state driven by the torque (explicit Euler on the sampled path, n = 1):
    dz = du - (beta |du| z + gamma du |z|)/z_max. Twist = -A z / z_max: below the elastic line while loading."""
    z = np.zeros_like(u)
    for i in range(1, len(u)):
        du = u[i] - u[i - 1]
        z[i] = z[i - 1] + du - (beta * abs(du) * z[i - 1] + gamma * du * abs(z[i - 1])) / z_max
    return z / z_max


@pytest.mark.parametrize("model", ["dahl", "dahl_n0", "dahl_n05", "dahl_n2", "play", "play_fine", "preisach",
                                   "preisach_elastic", "preisach_fine",
                                   "bouc_wen", "bouc_wen_form", "bouc_wen_form_soft"])
def test_every_loop_law_dissipates(params, model):
    """First principles: closed integral of T dphi > 0, and a positive twist remains after unloading."""
    u = _path(2001, (0, 1, -1, 1, 0))
    ctx = _ctx(params, u)
    laws = {"dahl": lambda c: hysteresis.EFFECT.contribution(c, np.array([0.02, -1.3])),
            "play": lambda c: hysteresis.PLAY.contribution(c, np.array([0.0, 0.0, 0.1, 0.0, 0.2, 0.05, 0.0, 0.0])),
            # the fine density (nodes 0, 0.02, 0.05, 0.1, 0.15, 0.2, 0.3, ..., 1): tight slips near the corner
            "play_fine": lambda c: hysteresis.PLAY_FINE.contribution(c, np.array(
                [0.0, 0.3, 0.2, 0.1, 0.0, 0.05, 0.1, 0.0, 0.0, 0.02, 0.0, 0.0, 0.0])),
            # a saturating relay density: most weight at bias 0.4, half-width 0.2 (all slip before full torque)
            # (bias nodes 0, 0.4, 0.8 x half-width nodes 0.05, 0.2, 0.45, 0.8)
            "preisach": lambda c: hysteresis.PREISACH.contribution(c, 0.02 * np.array([0.2, 0.5, 0.1, 0.0, 0.3, 1.0,
                                                                                       0.2, 0.0, 0.0, 0.2, 0.0, 0.0])),
            # the same relays keeping their mean compliance (the stated stiffness is the elastic one)
            "preisach_elastic": lambda c: hysteresis.PREISACH_ELASTIC.contribution(c, 0.02 * np.array(
                [0.2, 0.5, 0.1, 0.0, 0.3, 1.0, 0.2, 0.0, 0.0, 0.2, 0.0, 0.0])),
            # the fine density (bias nodes 0, 0.15, 0.35, 0.6, 0.9): a narrow band of bias about 0.35
            "preisach_fine": lambda c: hysteresis.PREISACH_FINE.contribution(c, 0.02 * np.outer(
                [0.0, 0.3, 1.0, 0.2, 0.0], [0.3, 1.0, 0.2, 0.0]).ravel()),
            "bouc_wen": lambda c: -0.02 * _bouc_wen(c.u),
            # the catalogue's Bouc-Wen form: exponent 2, q = 0.5 (beta 0.75, gamma 0.25), and a softening q = 1.67
            "bouc_wen_form": lambda c: hysteresis.BOUC_WEN.contribution(c, np.array([0.5, -1.3, 2.0, 0.5])),
            "bouc_wen_form_soft": lambda c: hysteresis.BOUC_WEN.contribution(c, np.array([0.5, -1.0, 1.0, 1.67])),
            **{f"dahl_n{str(n).replace('.', '')}": (lambda n: lambda c: hysteresis.DAHL_EXPONENT.contribution(
                c, np.array([0.02 * 2 ** n / 10 ** -1.3, -1.3, n])))(n) for n in (0, 0.5, 2)}}
    twist = laws[model](ctx)
    width, energy = loop_quantities(ctx, laws[model])
    assert width > 0 and energy > 0
    # residual twist after the first unloading from +T_max (sample 750 is u = 0 on the way down; sample 1000,
    # read here before, is u = -1, where a loop's own mean compliance decides the sign)
    assert ctx.u[750] == pytest.approx(0.0, abs=1e-12) and ctx.u[500] == pytest.approx(1.0)
    assert twist[750] - twist[0] > 0
    # energy of a loop of width w spanning +/- T_max: between a parallelogram (2 w T_max) and half of it
    assert width * 1.0 * X <= energy * 1.0001 <= 2.0 * width * X * 1.0001


def test_passivity_is_judged_where_the_data_was_sampled(params):
    """A friction joint's stuck compliance must be positive; a slider that sticks for less travel than one
    sample step cannot be tested by the recording, a lag of a few samples can.

    The same Jenkins element (Dahl's exponent 0: one play operator of half-width w and weight f) beside a
    baseline compliance s = 0.5 with f = 0.9 > s, stuck for 2 w of load travel after each reversal. The step
    out of the reversal sample is not judged (the true extreme may lie between two samples). Sampled in steps
    of 1.5625 w, the element is stuck for that step and 0.28 of the next, where the twist still moves with the
    torque (0.5 - 0.9 x 0.28 > 0): plausible; sampled in steps of w / 4 the twist moves against the torque for
    7 judged samples after each reversal, which friction cannot do. A channel lagging the torque by 3 samples
    is refused however coarse the sampling."""
    w = 0.004
    theta = np.array([0.9, math.log10(w), 0.0])
    for step, passive in ((1.5625 * w, True), (0.25 * w, False)):
        ctx = _ctx(params, _path(int(round(6.0 / step)) + 1, (-1, 1, -1, 1)))
        assert abs(np.median(np.abs(np.diff(ctx.u))) - step) < 1e-3 * step
        assert (not hysteresis.DAHL_EXPONENT.plausible(ctx, theta, 0.5)) is passive
        tangent = hysteresis.sampled_tangent(ctx, hysteresis.DAHL_EXPONENT.contribution(ctx, theta), 0.5)
        expected = 1.0 - 0.9 * (2 * w - step) / step / 0.5 if passive else 1.0 - 0.9 / 0.5
        assert tangent == pytest.approx(expected, rel=1e-6)
    ctx = _ctx(params, _path(121, (0, 1, -1, 1, 0)))
    lagged = np.concatenate([np.full(3, ctx.u[0]), ctx.u[:-3]])
    assert hysteresis.sampled_tangent(ctx, lagged - ctx.u, 1.0) < 0.0


def test_dahl_exponent_spans_the_bristle_and_the_classic_dahl(params):
    """Dahl's exponent n: n = 1 is the classic exponential form; n = 0 is the elastic-perfectly-plastic bristle,
    i.e. one play operator of half-width w and weight h/w (a Jenkins element); each exact, sample by sample."""
    u = _path(2001, (0, 1, -0.6, 0.8, -1, 0.3))
    ctx = _ctx(params, u)
    w = 10 ** -1.2
    classic = hysteresis.EFFECT.contribution(ctx, np.array([0.02, -1.2]))
    # f = h 2^n / w: h = 0.02 at n = 1 is f = 0.04 / w
    assert np.allclose(hysteresis.DAHL_EXPONENT.contribution(ctx, np.array([0.04 / w, -1.2, 1.0])), classic,
                       atol=1e-15)
    play = np.empty(len(u))
    p = ctx.u[0]
    for k, x in enumerate(ctx.u):                  # the play operator's own recursion, sample by sample
        p = min(max(p, x - w), x + w)
        play[k] = p
    assert np.allclose(hysteresis.play_operator(ctx, w), play, atol=1e-15)
    bristle = 0.02 / w * (play - ctx.u)
    assert np.allclose(hysteresis.DAHL_EXPONENT.contribution(ctx, np.array([0.02 / w, -1.2, 0.0])), bristle,
                       atol=1e-12)


def test_bouc_wen_state_is_the_law_integrated_in_small_steps(params):
    """The Bouc-Wen form's state (a travel table inverted by interpolation) against the law itself,
    dz/du = [1 - (beta sgn(du z) + gamma) |z|^n] / w, integrated by RK4 in 200 sub-steps per sample, on a path
    with minor loops (reversals before saturation); and n = 1, q = 1 (beta 1, gamma 0) is Dahl's classic law."""
    u = _path(601, (0, 0.6, -0.2, 0.4, -1, 0.3))
    ctx = _ctx(params, u)
    w, n, q = 0.15, 2.0, 0.5
    beta, gamma = (1 + q) / 2, (1 - q) / 2

    def rate(z, d):
        return (1.0 - (beta * np.sign(d * z) + gamma) * abs(z) ** n) / w * d

    z = np.zeros(len(u))
    for k in range(1, len(u)):
        du = ctx.u[k] - ctx.u[k - 1]
        h, zk = du / 200, z[k - 1]
        d = np.sign(du)
        for _ in range(200):
            a1 = rate(zk, d)
            a2 = rate(zk + 0.5 * abs(h) * a1, d)
            a3 = rate(zk + 0.5 * abs(h) * a2, d)
            a4 = rate(zk + abs(h) * a3, d)
            zk += abs(h) * (a1 + 2 * a2 + 2 * a3 + a4) / 6
        z[k] = zk
    assert np.max(np.abs(hysteresis.bouc_wen_unit(ctx, w, n, q) - z)) < 1e-5
    assert np.max(np.abs(hysteresis.bouc_wen_unit(ctx, 0.2, 1.0, 1.0) - hysteresis.dahl_unit(ctx, 0.2))) < 1e-6


def test_dahl_state_is_the_law_integrated_sample_by_sample(params):
    """dz/du = (sgn(du) - z)/w integrated exactly over each load step, z_k = s + (z_(k-1) - s) exp(-|du|/w),
    on a path whose reversals come before the state saturates (minor loops): the per-stretch closed form is the
    same at every sample, the reversal samples included."""
    u = _path(1201, (0, 0.3, -0.1, 0.2, -0.3, 0.05))
    ctx = _ctx(params, u)
    w = 0.2
    z = np.zeros(len(u))
    for k in range(1, len(u)):
        du = ctx.u[k] - ctx.u[k - 1]
        s = np.sign(du)
        z[k] = s + (z[k - 1] - s) * np.exp(-abs(du) / w) if s else z[k - 1]
    assert np.allclose(hysteresis.dahl_unit(ctx, w), z, atol=1e-12)


def test_relay_states_follow_the_relay_definition():
    """Each relay against its own definition, sample by sample: +1 once u >= alpha, -1 once u <= beta, else it
    keeps its state; demagnetised start (+1 below the alpha = -beta line)."""
    rng = np.random.default_rng(3)
    u = np.cumsum(rng.normal(0.0, 0.1, 400))
    alpha = np.array([0.5, 0.2, -0.1, 1.0, 0.05])
    beta = np.array([-0.5, 0.0, -0.6, 0.4, -0.05])
    got = hysteresis.relay_states(u, alpha, beta)
    state = np.where(alpha + beta < 0, 1.0, -1.0)
    for k, x in enumerate(u):
        state = np.where(x >= alpha, 1.0, np.where(x <= beta, -1.0, state))
        assert np.array_equal(got[k], state)


def test_mirrored_loop_is_not_named_hysteresis(params):
    """A loop that generates energy (twist above the elastic line while loading) is not friction."""
    diag, _ = _diagnose(params, lambda u, t, c: 0.02 * _bouc_wen(u))
    assert diag.verdict is not Verdict.AGREES
    assert "hysteresis" not in diag.named


def test_bouc_wen_loop_named_with_its_loss(params):
    diag, ctx = _diagnose(params, lambda u, t, c: -0.03 * _bouc_wen(u))
    # issue 12: physical hysteresis is NAMED (primary) with its loss; at signal/noise 15 the Bouc-Wen branch
    # shape (gamma = beta) may also earn a weak stiffening term, which the loop quantities do not depend on
    assert diag.verdict is Verdict.EXPLAINED and diag.primary == "hysteresis"
    true_width, true_energy = loop_quantities(ctx, lambda c: -0.03 * _bouc_wen(c.u))
    arcmin = true_width * 60 * 180 / math.pi
    # issue 12 target: the loss within 10 %
    assert diag.quantity("hysteresis_loss_arcmin") == pytest.approx(arcmin, rel=0.10)
    assert diag.quantity("hysteresis_energy_per_cycle_Nmm_rad") == pytest.approx(true_energy, rel=0.15)


@pytest.mark.parametrize("noise", ["ar1", "random_walk", "low_pass"])
@pytest.mark.parametrize("seed", range(3))
def test_coloured_noise_raises_no_alarm(params, noise, seed):
    diag, _ = _diagnose(params, lambda u, t, c: 0.0, noise=noise, seed=seed)
    assert diag.verdict is Verdict.AGREES and diag.named == () and not diag.mismatch


def test_ripple_periodic_in_time_is_unexplained_with_its_period(params):
    n, period_s = 1000, 0.137
    time_s = np.arange(n) * 1e-3
    diag, _ = _diagnose(params, lambda u, t, c: 0.01 * np.sin(2 * np.pi * time_s / period_s), n=n, time_s=time_s)
    assert diag.verdict is Verdict.UNEXPLAINED and diag.named == ()
    assert "periodic in time" in diag.structure
    found = float(diag.structure.split("samples = ")[1].split(" s")[0])
    # a 1000-sample record holds 7.3 periods: the periodogram line is refined to ~1 % of the period
    assert found == pytest.approx(period_s, rel=0.03)
    assert diag.suggestion is not None and "MISMATCH NOT EXPLAINED" in diag.explanation


def test_spliced_specimens_are_unexplained(params):
    diag, _ = _diagnose(params, lambda u, t, c: 0.1 * u * (t > 0.5))
    assert diag.verdict is Verdict.UNEXPLAINED
    assert "compliance changes during the test" in diag.structure


def test_kinematic_error_needs_the_input_angle(params):
    n = 1000
    angle = 2 * np.pi * 3.0 * np.linspace(0, 1, n) ** 1.2
    ripple = lambda u, t, c: 0.008 * np.cos(2 * (2 * np.pi * 3.0 * t ** 1.2)) if True else 0
    diag, ctx = _diagnose(params, ripple, n=n, angle=angle)
    assert diag.verdict is Verdict.EXPLAINED and diag.named == ("kinematic_error",)
    arcsec = 0.008 * ctx.Y * 3600 * 180 / math.pi
    assert diag.quantity("amplitude_2x_arcsec") == pytest.approx(arcsec, rel=0.05)
    without, _ = _diagnose(params, ripple, n=n)
    assert without.verdict is Verdict.UNEXPLAINED


def test_smooth_stiffening_is_one_effect_not_two(params):
    """tanh stiffening at signal/noise ~ 100: nonlinear_stiffness alone (no lost motion mops up the knee)."""
    diag, _ = _diagnose(params, lambda u, t, c: -0.1 * (u - 0.4 * np.tanh(u / 0.4)), sigma=3e-4)
    assert diag.verdict is Verdict.EXPLAINED and diag.named == ("nonlinear_stiffness",)


def test_stiffness_beyond_its_prior_is_named_within_it_agrees(params):
    out, _ = _diagnose(params, lambda u, t, c: 0.06 * u)        # 3 sigma of the 2 % prior
    assert out.verdict is Verdict.EXPLAINED and out.named == ("compliance_offset",)
    inside, _ = _diagnose(params, lambda u, t, c: 0.02 * u)     # 1 sigma
    assert inside.verdict is Verdict.AGREES


@pytest.mark.parametrize("seed", [0, 1])
def test_stiffening_with_a_stiffness_beyond_its_prior_is_both(params, seed):
    """tanh stiffening on a specimen 8 % more compliant than simulated (4 sigmas of the 2 % prior): the stiffening
    alone leaves noise but for its stiffness, so the series compliance joins it (it read "unexplained"), with the
    compliance change recovered."""
    diag, _ = _diagnose(params, lambda u, t, c: -0.1 * (u - 0.4 * np.tanh(u / 0.4)) + 0.08 * u, sigma=1e-3,
                        seed=seed)
    assert diag.verdict is Verdict.EXPLAINED and diag.named == ("nonlinear_stiffness", "compliance_offset")
    best = diag.effects[0]
    change, se = best.parameters["compliance_offset.compliance_change_percent"][0], \
        best.errors["compliance_offset.compliance_change_percent"]
    assert abs(change - 8.0) < 3 * se + 1.0, (change, se)


def _one_sided(params, knots, extra, seed, n=800, sigma=2e-3):
    rng = np.random.default_rng(seed)
    u = _path(n, knots)
    ctx = _ctx(params, u)
    t = np.linspace(0, 1, n)
    y = u + 0.01 + 0.003 * t + extra(u, t) + sigma * rng.standard_normal(n)
    return diagnose(parse_text(format_recording(K, "output_shaft", u * X, y * ctx.Y)), params)[0]


@pytest.mark.parametrize("seed", [0, 1])
def test_a_crack_seen_in_one_cycle_is_also_an_exchanged_specimen(params, seed):
    """One cycle (up to +T, then down to -T) visits each load sign in one half of the record only: a crack
    open under negative torque is then the same curve as a specimen exchanged at the zero crossing, and the
    answer names the crack as ambiguous with that rival. Two cycles tell them apart."""
    crack = lambda u, t: 0.15 * np.minimum(u, 0.0)          # noqa: E731 (extra compliance when u < 0)
    one = _one_sided(params, (0, 1, 0, -1, 0), crack, seed)
    assert one.verdict is Verdict.EXPLAINED and one.named == ("crack_closure",) and one.ambiguous
    assert "exchanged" in one.runner_up
    two = _one_sided(params, (0, 1, -1, 1, -1, 0), crack, seed)
    assert two.verdict is Verdict.EXPLAINED and two.named == ("crack_closure",)
    assert "exchanged" not in (two.runner_up or "")


@pytest.mark.parametrize("seed", [0, 1])
def test_a_specimen_exchanged_with_its_zero_moved_is_not_a_crack(params, seed):
    """Half way, unloaded, the specimen is exchanged for one 15 % more compliant whose zero sits 10 noise sigmas
    higher: within one cycle a crack draws the compliance change but not the jump (it read crack_closure)."""
    one = _one_sided(params, (0, 1, 0, -1, 0), lambda u, t: (t >= 0.5) * (0.15 * u + 0.02), seed)
    assert one.verdict is Verdict.UNEXPLAINED and "exchanged" in one.structure


def test_exchange_candidates_are_unloaded_rows_near_interior_zero_crossings(params):
    from strainwave.compare.diagnose import exchange
    u = _path(800, (0, 1, 0, -1, 0))
    ctx = _ctx(params, u)
    rows = exchange.candidate_splits(ctx)
    assert rows and all(80 <= k <= 720 for k in rows)
    assert all(min(abs(u[k]), abs(u[k - 1])) <= exchange.UNLOADED for k in rows)
    assert any(np.sign(u[k]) != np.sign(u[k - 1]) for k in rows)


def test_clipped_response_is_not_stiffening(params):
    diag, _ = _diagnose(params, lambda u, t, c: np.clip(u, -0.85, 0.85) - u)
    assert diag.verdict is Verdict.UNEXPLAINED
    assert any("clipping" in w for w in diag.suggestion.warnings)


def test_parameters_carry_standard_errors(params):
    diag, _ = _diagnose(params, lambda u, t, c: 0.1 * np.maximum(u, 0.0))
    assert diag.named == ("crack_closure",)
    top = diag.effects[0]
    se = top.errors["stiffness_crack_open"]
    # Fisher information: a 10 % compliance step seen at 2e-3 noise over 400 samples is known to < 1 %
    assert 0 < se < 0.01 * top.parameters["stiffness_crack_open"][0]
    assert 0.0 < top.weight <= 1.0


@pytest.mark.parametrize("seed", range(2))
def test_a_channel_lagging_by_four_samples_is_unexplained_and_rate_dependent(params, seed):
    """A twist channel recorded 4 samples late draws a loop that looks like friction on a triangle path, but
    its twist keeps moving for 4 samples after each reversal (no passive joint does that) and its offset
    follows the loading rate: unexplained, described as rate-dependent, never named hysteresis."""
    def lagged(u, t, c, lag=4):
        return np.concatenate([np.full(lag, u[0]), u[:-lag]]) - u
    diag, _ = _diagnose(params, lagged, seed=seed)
    assert diag.verdict is Verdict.UNEXPLAINED and "hysteresis" not in diag.named
    assert "loading rate" in diag.structure


def test_first_order_lag_is_exact_for_a_ramp():
    # dx/dt = (u - x)/tau with u = r t and x(0) = 0: x = r (t - tau (1 - exp(-t/tau)))
    t = np.linspace(0.0, 2.0, 41)
    tau = 0.3
    x = rate_loop.lagged(0.7 * t, t, tau)
    assert x == pytest.approx(0.7 * (t - tau * (1.0 - np.exp(-t / tau))), abs=1e-12)
    # and on a non-uniform time grid (the sample-by-sample path)
    t2 = np.sort(np.concatenate([[0.0, 2.0], np.random.default_rng(1).uniform(0.0, 2.0, 60)]))
    assert rate_loop.lagged(0.7 * t2, t2, tau) == pytest.approx(0.7 * (t2 - tau * (1.0 - np.exp(-t2 / tau))), abs=1e-12)


def test_creep_loop_at_one_rate_is_not_confidently_friction(params):
    """Under one constant loading rate, creep (twist lagging in TIME) draws exactly Dahl's friction loop: the
    diagnosis may name hysteresis only as ambiguous with the rate-dependent rival, never with confidence."""
    diag, _ = _diagnose(params, lambda u, t, c: 0.05 * (rate_loop.lagged(u, t, 0.01) - u))
    assert diag.verdict is not Verdict.AGREES
    if diag.verdict is Verdict.EXPLAINED:
        assert diag.named == ("hysteresis",) and diag.ambiguous and "rate" in diag.runner_up


def test_creep_loop_at_two_rates_is_unexplained(params):
    """At two loading rates creep's loop width changes with the rate, which no friction law does."""
    n = 800
    # the second half of the record is sampled 4x slower: the same load path at a quarter of the rate
    time_s = np.concatenate([np.arange(n // 2) * 1e-3, (n // 2) * 1e-3 + np.arange(n - n // 2) * 4e-3])
    t = (time_s - time_s[0]) / (time_s[-1] - time_s[0])
    diag, _ = _diagnose(params, lambda u, _t, c: 0.05 * (rate_loop.lagged(u, t, 0.005) - u), time_s=time_s)
    assert diag.verdict is Verdict.UNEXPLAINED
    assert "rate" in diag.structure


@pytest.mark.parametrize("d", [0.2, -0.2])
def test_progressive_crack_closes_under_its_closing_load(params, d):
    """First principles: the crack adds its full compliance |d| where it is open; where its faces are pressed
    shut the added compliance falls monotonically from |d| towards zero (a crack under compression closes)."""
    from strainwave.compare.diagnose.effects import crack_closure
    u = np.linspace(-1.0, 1.0, 2001)
    ctx = _ctx(params, u)
    theta = np.array([d, 0.0, 0.1, 0.2, 0.3, 0.2, 0.1, 0.05, 0.05])
    y = crack_closure.PROGRESSIVE.contribution(ctx, theta)
    slope = np.gradient(y, u)
    open_side, closing = (u > 0.01, u < -0.01) if d > 0 else (u < -0.01, u > 0.01)
    assert slope[open_side] == pytest.approx(abs(d), rel=1e-9)
    added = slope[closing]
    assert np.all(added >= -1e-12) and np.all(added <= abs(d) + 1e-12)
    # non-increasing with the closing load (ordered away from the zero)
    away = added[::-1] if d > 0 else added
    assert np.all(np.diff(away) <= 1e-9)
    assert away[-1] == pytest.approx(0.0, abs=1e-9)          # the staircase sums to fully closed


def test_gradual_crack_as_wide_as_its_bound_is_an_even_curvature_not_a_crack(params):
    """First principles: as its width grows the gradual closure tends to a parabola (w ln 2 + v/2 + v^2/(8 w)),
    an even curvature over the whole range with no linear closed side; at the width's bound it is reported
    implausible, well inside it is not."""
    from strainwave.compare.diagnose.effects import crack_closure
    u = np.linspace(-1.0, 1.0, 2001)
    ctx = _ctx(params, u)
    wide = crack_closure.GRADUAL.contribution(ctx, np.array([0.1, 0.0, 1.5]))
    parabola = np.polyval(np.polyfit(u, wide, 2), u)
    assert np.max(np.abs(wide - parabola)) < 2e-3 * np.ptp(wide)
    at_bound = np.array([0.1, 0.0, crack_closure.LOG10_W_MAX])
    assert crack_closure.GRADUAL.plausible(ctx, at_bound, 1.0)
    assert not crack_closure.GRADUAL.plausible(ctx, np.array([0.1, 0.0, -1.3]), 1.0)


@pytest.mark.parametrize("seed", [0, 1])
def test_torque_sensor_quadratic_is_not_confidently_a_crack(params, seed):
    """A linear specimen read through a torque sensor with a quadratic error (twist - k T^2, k = 0.5 % of full
    scale, 25x the noise) under AR(1) noise: an even curvature over the whole range, which a crack (softer on
    one side, linear on its closed side) is not. Before the gradual form's width bound was a plausibility
    bound, it was named crack_closure[gradual] with its width at the bound, without doubt."""
    diag, _ = _diagnose(params, lambda u, t, c: -0.005 * u ** 2, sigma=2e-4, seed=seed, n=1500, noise="ar1")
    assert diag.verdict is not Verdict.AGREES
    assert not (diag.verdict is Verdict.EXPLAINED and not diag.ambiguous and "crack_closure" in diag.named), \
        (diag.verdict, diag.named, diag.ambiguous)


def test_friction_loop_at_two_rates_stays_friction(params):
    """The converse: a rate-independent loop (Dahl, a function of the load path only) recorded at two loading
    rates is named hysteresis, and its rate-dependent rival does not take it."""
    n = 800
    time_s = np.concatenate([np.arange(n // 2) * 1e-3, (n // 2) * 1e-3 + np.arange(n - n // 2) * 4e-3])
    diag, _ = _diagnose(params, lambda u, t, c: hysteresis.EFFECT.contribution(c, np.array([0.03, -1.0])),
                        time_s=time_s)
    assert diag.verdict is Verdict.EXPLAINED and diag.named == ("hysteresis",)
    assert diag.runner_up is None or "rate" not in diag.runner_up


def test_several_rates_reads_the_loading_rate_of_each_stretch(params):
    u = _path(800)
    one = _ctx(params, u)
    assert not rate_loop.several_rates(one)
    time_s = np.concatenate([np.arange(400) * 1e-3, 0.4 + np.arange(400) * 4e-3])
    probe = parse_text(format_recording(K, "output_shaft", u * X, u, time_s=time_s))
    two = build_context(probe, analytic_baseline(probe, params))
    assert rate_loop.several_rates(two)


def test_backlash_flanks_stiffen_about_the_clearance_wherever_it_sits(params):
    """A clearance centred off zero carries its flank contact with it: the twist is odd about the clearance's
    centre u0 (not about zero torque), and past the band the contact stiffens monotonically with its load."""
    from strainwave.compare.diagnose.effects import lost_motion
    u = np.linspace(-1.0, 1.0, 4001)
    ctx = _ctx(params, u)
    u0 = 0.07
    theta = np.array([0.02, -2.0, u0, 0.3, -1.2])
    y = lost_motion.FLANK.contribution(ctx, theta)
    i0 = int(np.argmin(np.abs(u - u0)))          # u0 is a grid point (step 5e-4)
    k = np.arange(1, len(u) - i0)
    k = k[i0 - k >= 0]
    assert y[i0 + k] == pytest.approx(-y[i0 - k], abs=1e-12)
    slope = np.gradient(y, u)
    past = u > u0 + 0.1
    assert np.all(slope[past] > 0) and np.all(np.diff(slope[past]) < 0)


def test_a_saturated_torque_channel_is_unexplained_and_said(params):
    """The torque reading clipped at 90 % of its full scale while the twist follows the true torque: whatever
    fits the rest, the load there is not the load recorded."""
    n = 800
    u_true = _path(n)
    rng = np.random.default_rng(5)
    y = u_true + 2e-3 * rng.standard_normal(n)
    ctx = _ctx(params, u_true)
    recorded = np.clip(u_true, -0.9, 0.9)
    rec = parse_text(format_recording(K, "output_shaft", recorded * X, y * ctx.Y))
    diag = diagnose(rec, params)[0]
    assert diag.verdict is Verdict.UNEXPLAINED
    assert "saturated load channel" in diag.structure and "saturated load channel" in diag.explanation


def test_a_sampled_triangle_peak_is_no_plateau():
    from strainwave.compare.diagnose.channels import stuck_channel
    rng = np.random.default_rng(2)
    u = _path(2000) + 2e-4 * rng.standard_normal(2000)
    y = u + 1e-3 * rng.standard_normal(2000)
    assert stuck_channel(u, y, 1e-3, "torque", "twist") == ""



@pytest.mark.parametrize("seed", range(3))
def test_a_sine_peak_under_low_pass_noise_is_no_stuck_channel(seed):
    """A sine test lingers at its peaks (5-10 samples within 3 load-noise sigmas); a second-order low-pass
    sensor's twist drifts there by 10-40 times its sample-to-sample noise, as it does everywhere else: no stuck
    channel. A twist that moves as much across each peak while the rest of its residual is white still is one."""
    from strainwave.compare.diagnose.channels import _plateaus, stuck_channel
    from strainwave.compare.diagnose.noise import noise_std
    rng = np.random.default_rng(seed)
    n = 1400
    u = np.sin(2 * np.pi * 3 * np.arange(n) / n) + 1e-3 * rng.standard_normal(n)
    e, smooth = rng.standard_normal(n), np.zeros(n)
    for i in range(2, n):                     # double pole at 0.9: a second-order low-pass sensor
        smooth[i] = 1.8 * smooth[i - 1] - 0.81 * smooth[i - 2] + e[i]
    smooth *= 1e-2 / np.std(smooth)
    sigma = noise_std(smooth)
    assert stuck_channel(u, u + smooth, sigma, "torque", "twist") != ""     # judged as white noise it would be
    assert stuck_channel(u, u + smooth, sigma, "torque", "twist", residual=smooth) == ""
    white = sigma * rng.standard_normal(n)
    creep = np.zeros(n)
    for a, b in _plateaus(u):                 # the twist keeps moving while the torque reading sits
        creep[a:b] = np.linspace(0.0, 40 * sigma, b - a)
    assert stuck_channel(u, u + white + creep, sigma, "torque", "twist", residual=white + creep) != ""


@pytest.mark.parametrize("seed", range(6))
def test_second_order_low_pass_sensor_raises_no_alarm(params, seed):
    """A sensor behind a second-order Butterworth anti-alias filter at 5 % of the Nyquist frequency: smooth
    sample to sample, its variogram rises quadratically, then saturates. Read as a random walk (a linear
    variogram), its correlated steps made a drift in time out of clean data (seed 1 before the double-pole
    noise model). Slower still (3 % of Nyquist) 2 of 6 clean recordings alarm: the record holds too few of
    the filter's correlation times to tell its swell from a drift."""
    from scipy.signal import butter, lfilter

    rng = np.random.default_rng(100 + seed)
    n = 1500
    b, a = butter(2, 0.05)
    smooth = lfilter(b, a, rng.standard_normal(n + 1000))[1000:]
    smooth /= np.std(smooth)
    diag, _ = _diagnose(params, lambda u, t, c: 2e-3 * smooth, n=n, sigma=0.0)
    assert diag.verdict is Verdict.AGREES and not diag.mismatch, diag.structure


@pytest.mark.parametrize("seed", range(2))
def test_a_loop_under_a_high_order_low_pass_sensor_is_still_named(params, seed):
    """A friction loop 15 times the std of a 5th-order Butterworth sensor at 7 % of the Nyquist frequency (a flat
    pass band and a ringing impulse response, which no two-parameter noise shape draws), behind it a white floor
    of a tenth of its std (an ADC's), is found and named, with its loss. With no white floor at all the loop
    reads "unexplained": the two-parameter noise shape that judges the named model sees the filter's smooth
    wander as structure (see docs/recordings.md, noise)."""
    from scipy.signal import butter, sosfilt

    rng = np.random.default_rng(300 + seed)
    n = 1800
    smooth = sosfilt(butter(5, 0.07, output="sos"), rng.standard_normal(n + 2000))[2000:]
    smooth /= np.std(smooth)
    diag, ctx = _diagnose(params, lambda u, t, c: -0.03 * _bouc_wen(u) + 2e-3 * smooth, n=n, sigma=2e-4)
    assert diag.verdict is Verdict.EXPLAINED and diag.primary == "hysteresis", diag.structure
    true_width, _ = loop_quantities(ctx, lambda c: -0.03 * _bouc_wen(c.u))
    # issue 12 target: the loss within 10 %
    assert diag.quantity("hysteresis_loss_arcmin") == pytest.approx(true_width * 60 * 180 / math.pi, rel=0.10)


def test_a_second_effect_of_eight_noise_sigmas_is_still_named(params):
    """A friction loop (15 sigma) and a crack adding compliance under positive torque: at 8 noise sigmas at full
    load the crack is a second finding (pipeline.MIN_COMPONENT_SIGMAS must not hide it)."""
    sigma = 2e-3
    diag, _ = _diagnose(params, lambda u, t, c: -0.03 * _bouc_wen(u) + 8.0 * sigma * np.maximum(u, 0.0),
                        n=1600, sigma=sigma)
    assert diag.verdict is Verdict.EXPLAINED
    assert set(diag.named) == {"hysteresis", "crack_closure"}


def test_contact_stiffening_is_not_a_backlash_without_a_clearance(params):
    """Stiffening by a spreading contact, twist += B sgn(u) ((1 + |u|/u_c)^(2/3) - 1) (no clearance at all),
    is drawn equally well by the flank-contact backlash form with a clearance far below the noise: a backlash
    is its clearance (Effect.signature), so the stiffening is named."""
    diag, _ = _diagnose(params, lambda u, t, c: 0.01 * np.sign(u) * ((1 + np.abs(u) / 0.2) ** (2 / 3) - 1),
                        n=1600, sigma=1e-3)
    assert diag.verdict is Verdict.EXPLAINED
    assert diag.named == ("nonlinear_stiffness",)


def test_a_loop_that_never_crosses_zero_torque_is_read_mid_range(params):
    """A unipolar test (0 -> full scale -> 0) holds no width at zero torque, where its branches meet: the loop
    is read at the middle of the recorded range, where a dissipative loop is open, and said to be so."""
    rng = np.random.default_rng(3)
    n = 1200
    u = _path(n, knots=(0, 1, 0, 1, 0, 1, 0))
    ctx = _ctx(params, u)
    loop = -0.03 * _bouc_wen(u)
    y = u + 0.01 + loop + 1e-3 * rng.standard_normal(n)
    rec = parse_text(format_recording(K, "output_shaft", u * X, y * ctx.Y))
    diag = diagnose(rec, params)[0]
    assert diag.verdict is Verdict.EXPLAINED and "hysteresis" in diag.named
    assert diag.quantity("hysteresis_loss_read_at_load") == pytest.approx(0.5 * X, rel=1e-3)
    # the steady loop of the last full cycle: unloading over rows 600-800, reloading over rows 800-1000
    true_width = float(np.interp(0.5, u[600:800][::-1], loop[600:800][::-1]) -
                       np.interp(0.5, u[800:1000], loop[800:1000])) * ctx.Y * 60 * 180 / math.pi
    assert true_width > 0.0
    assert diag.quantity("hysteresis_loss_arcmin") == pytest.approx(true_width, rel=0.10)
    assert "never crosses zero torque" in diag.explanation


def test_hertz_contact_stiffening_at_high_signal_is_stiffening_alone(params):
    """A Hertzian point contact (compliance falling as (1 + |u|/u_c)^(-1/3)) at ~300x the noise: stiffening
    without a knee. The contact form draws it, so no clearance or ambiguity is invented from the three-slope
    forms' misfit (before the contact form: named stiffening but ambiguous with lost_motion), and K1 and K3,
    the law's tangent stiffnesses at zero and full load, lie within 3 of their reported standard errors (which
    include the stiffness scale's own error: K1 = 1/(s c0))."""
    B, uc = 0.01, 0.2
    diag, ctx = _diagnose(params, lambda u, t, c: B * np.sign(u) * ((1 + np.abs(u) / uc) ** (2 / 3) - 1),
                          n=1600, sigma=1e-4)
    assert diag.verdict is Verdict.EXPLAINED
    assert diag.named == ("nonlinear_stiffness",) and not diag.ambiguous
    # d(twist)/d(torque) of the generated curve: y (units of ctx.Y) against u (units of X, not ctx.X: the
    # sampled path's peak falls between samples)
    for name, c in (("K1", 1.0 + 2.0 * B / (3.0 * uc)), ("K3", 1.0 + 2.0 * B / (3.0 * uc) * (1.0 + 1.0 / uc) ** (-1 / 3))):
        true = X / (c * ctx.Y)
        se = diag.effects[0].errors[name]
        assert 0.0 < se < 1e-3 * true
        assert abs(diag.quantity(name) - true) <= 3.0 * se, (name, diag.quantity(name) / true - 1.0, se / true)
    # the scale itself is reported with its error, and K1 = 1/(s c0) carries exactly that relative error
    s, s_se = diag.quantity("stiffness_scale_within_prior"), diag.effects[0].errors["stiffness_scale_within_prior"]
    assert diag.effects[0].errors["K1"] / diag.quantity("K1") == pytest.approx(s_se / s, rel=1e-3)


def test_a_pair_tries_the_best_form_of_each_loop_law_class():
    """Beside another effect, a pair tries the best form of each law class first (Effect.law_class), then the
    next best of any class; forms without a class are each their own."""
    from types import SimpleNamespace
    from strainwave.compare.diagnose.candidates import pair_forms as _pair_forms

    def fit(effect):
        return SimpleNamespace(effects=(effect,))
    fine, coarse, dahl, play = (fit(e) for e in (hysteresis.PREISACH_FINE, hysteresis.PREISACH,
                                                  hysteresis.DAHL_EXPONENT, hysteresis.PLAY))
    ranked = [fine, coarse, play, dahl]           # best BIC first: the two relay densities lead
    assert _pair_forms(ranked, 2) == [fine, dahl]
    assert _pair_forms(ranked, 1) == [fine]
    assert _pair_forms(ranked, 4) == [fine, dahl, coarse, play]
    assert {hysteresis.EFFECT.law_class, hysteresis.DAHL_EXPONENT.law_class, hysteresis.BOUC_WEN.law_class} == \
        {hysteresis.STATE_LAW}
    assert {hysteresis.PLAY.law_class, hysteresis.PREISACH.law_class, hysteresis.PREISACH_FINE.law_class} == \
        {hysteresis.ELEMENT_LAW}


def test_a_catalogue_curve_with_a_bouc_wen_loop_names_both(params):
    """Family 2's CHA-40 ratio-50 curve (Harmonic Drive's table) with a Bouc-Wen loop (benchmark-diagnose seed 0):
    alone, the two Preisach densities fit it best (by drawing part of the stiffening with relays at a bias), and
    neither fits beside the stiffening; the pair with a one-state loop law does, to the noise. With the pair's
    forms taken as the two best of any class it read "unexplained"."""
    from pathlib import Path
    path = Path(__file__).parent / "data" / "family2_cha40_50_bouc_wen.csv"
    diag, _ = diagnose(parse_text(path.read_text(), path.name), params)
    assert diag.verdict is Verdict.EXPLAINED and set(diag.named) == {"nonlinear_stiffness", "hysteresis"}
    k1, k2, k3 = (diag.quantity(f"nonlinear_stiffness.{k}") for k in ("K1", "K2", "K3"))
    assert k1 < k2 < k3
    assert diag.quantity("hysteresis.hysteresis_loss_arcmin") > 0


def test_relays_that_add_compliance_to_an_elastic_stiffness_are_friction_not_a_softer_specimen(params):
    """A relay density spread over the load range adds its sliding compliance to the elastic one: with the
    ELASTIC stiffness stated, the loop's secant is softer than the baseline by many prior sigmas. The secant
    reading of the stated stiffness (its line left to the stiffness scale) must call that a stiffness outside
    its prior; the elastic reading names the loop alone, its stiffness within the prior. Every loop form's
    stiffness is judged on its secant or its elastic reading (loop_stiffness.py), so whichever form
    wins, the loop is named alone with its elastic stiffness on the stated one."""
    theta = 0.2 * np.array([0.2, 0.5, 0.1, 0.0, 0.3, 1.0, 0.2, 0.0, 0.0, 0.2, 0.0, 0.0])

    def relays(u, t, ctx):
        return hysteresis.PREISACH_ELASTIC.contribution(ctx, theta)
    ctx = _ctx(params, _path(800))
    added = np.polyfit(ctx.u, relays(ctx.u, ctx.t, ctx), 1)[0]
    assert added > 5 * 0.02                  # the secant: more than 5 prior sigmas (2 %) softer
    d, _ = _diagnose(params, relays, sigma=1e-3)
    assert d.verdict is Verdict.EXPLAINED and d.named == ("hysteresis",), d.structure
    assert abs(d.effects[0].parameters["elastic_compliance_change_percent"][0]) < 2.58 * 2.0
    assert d.effects[0].parameters["secant_compliance_change_percent"][0] > 5 * 2.0
    assert "stiffness differs" not in d.structure


@pytest.mark.parametrize("name", ["family2_warmup_drift_ar1.csv", "family2_reclamped.csv"])
def test_a_smooth_departure_is_not_taken_for_the_sensors_wander(name, monkeypatch):
    """benchmark-diagnose family 2: a warm-up drift 7.7 noise sigmas RMS behind an AR(1) sensor (seed 0) and a
    re-clamped specimen 2.5 sigma RMS (seed 1). Seen over 16 lags each looks like a random walk, but once the
    generic smooth structures are fitted away the sensor's own noise is left (its white part dominant), where a
    random walk's steps would remain: the departure is unexplained. Judged on the raw residual alone both
    read "agrees"."""
    from pathlib import Path
    from strainwave.compare.diagnose import structure
    path = Path(__file__).parent / "data" / name
    rec = parse_text(path.read_text(), path.name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        p = load_params(overrides=rec.param_overrides) if rec.param_overrides else load_params()
        assert diagnose(rec, p)[0].verdict is Verdict.UNEXPLAINED
        monkeypatch.setattr(structure, "_still_wandering", lambda m: True)
        # the counterfactual isolates the noise rule: the thermal drift read on an agreeing recording
        # (decision 069) is kept out of it
        from strainwave.compare.diagnose import pipeline
        monkeypatch.setattr(pipeline, "_drift", lambda rec: None)
        assert diagnose(rec, p)[0].verdict is Verdict.AGREES
