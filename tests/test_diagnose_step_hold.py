"""A step-and-hold staircase (the load raised in equal steps, each held while the rig settles) reads the response at
a few load levels: samples held at one level see one phase of any line pitch, so a friction loop's level-to-level
misfit must not be read as an encoder's interpolation error (periodic.load_levels). The loop is written here from
first principles: a Prandtl-Ishlinskii sum of play operators on the torque (dissipative, rate independent)."""
import warnings

import numpy as np
import pytest

from strainwave.compare.diagnose.baseline import analytic_baseline
from strainwave.compare.diagnose.periodic import load_levels
from strainwave.compare.diagnose.pipeline import Verdict, diagnose
from strainwave.compare.diagnose.recording import RecordingKind, format_recording, parse_text

K = RecordingKind.TORSION
X = 1e6          # N*mm full scale


def staircase(cycles: int = 2, steps: int = 10, hold: int = 24, ramp: int = 1) -> np.ndarray:
    """0 -> +1 -> -1 -> ... -> 0 in steps of 1/steps of full scale, each level held ``hold`` samples and reached
    by a ``ramp``-sample ramp (a servo's step: one sample)."""
    knots = np.concatenate([[0.0]] + [np.linspace(0, 1, steps + 1)[1:], np.linspace(1, -1, 2 * steps + 1)[1:],
                                      np.linspace(-1, 0, steps + 1)[1:]] * cycles)
    out = [np.full(hold, knots[0])]
    for a, b in zip(knots[:-1], knots[1:]):
        out += [np.linspace(a, b, ramp + 1)[1:], np.full(hold, b)]
    return np.concatenate(out)


def play_loop(u: np.ndarray, radii: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """Sum of play operators p_r(u): p_k = clip(p_(k-1), u_k - r, u_k + r), starting relaxed (p_0 = u_0)."""
    p = np.full(len(radii), float(u[0]))
    out = np.empty(len(u))
    for k, x in enumerate(u.tolist()):
        p = np.clip(p, x - radii, x + radii)
        out[k] = float(weights @ p)
    return out


def test_staircase_levels_are_counted_once():
    assert load_levels(staircase()) == 1 + 2 * 40                          # one per step, not per held sample
    assert load_levels(staircase(ramp=4)) == 1 + 2 * 40 * 4                # a ramp's samples each read a new level
    # a sweep moves at (nearly) every sample; only at its reversals it lingers within its own noise
    assert load_levels(np.sin(np.linspace(0, 6, 500))) >= 490


def test_friction_loop_on_a_staircase_is_not_an_encoder_error(params):
    u = staircase()
    radii = np.linspace(0.02, 0.6, 20)
    loop = play_loop(u, radii, np.full(20, 0.15 / 20)) - 0.15 * u          # secant kept on the baseline's line
    probe = parse_text(format_recording(K, "output_shaft", u * X, u))
    c = analytic_baseline(probe, params).compliance
    # main named "hysteresis + encoder_error" here: the line pitch fitted to the loop's level-to-level misfit
    y = u + loop + 0.004 * np.random.default_rng(0).standard_normal(len(u))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        diag = diagnose(parse_text(format_recording(K, "output_shaft", u * X, y * X * c)), params, workers=1)[0]
    assert diag.verdict is Verdict.EXPLAINED and "encoder_error" not in diag.named and "hysteresis" in diag.named
