"""An encoder's interpolation error is periodic in the measured angle, at a line pitch the reading resolves and with
an amplitude that decodable quadrature signals can make (effects/encoder_error.py, periodic.PITCH_NOISE_SIGMAS).
A quantised reading is constant or alternating at pitches of one or two quantisation steps, so a "line" there is
collinear with the offset and fitted any size: a power-law stiffening was named encoder_error + compliance_offset.
The stiffening is written here from its own law: tangent stiffness K1 (1 + (|T|/T_s)^q), integrated numerically."""
import math
import warnings

import numpy as np

from strainwave.compare.diagnose.baseline import analytic_baseline
from strainwave.compare.diagnose.effects import CATALOGUE
from strainwave.compare.diagnose.effects.base import Context
from strainwave.compare.diagnose.pipeline import Verdict, diagnose
from strainwave.compare.diagnose.recording import RecordingKind, format_recording, parse_text

K = RecordingKind.TORSION
X = 1e6          # N*mm full scale


def power_stiffening_twist(u: np.ndarray, ratio: float, q: float, n: int = 20001) -> np.ndarray:
    """Twist in units of c1 X for tangent stiffness K1 (1 + (|u|/u_s)^q), K(1)/K1 = ratio, by the trapezoid rule."""
    us = (ratio - 1.0) ** (-1.0 / q)
    g = np.linspace(0.0, 1.0, n)
    f = 1.0 / (1.0 + (g / us) ** q)
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(g))])
    return np.sign(u) * np.interp(np.abs(u), g, cum)


def test_power_stiffening_read_through_a_quantised_encoder_is_not_an_encoder_error(params):
    n = 1768
    u = np.sin(2 * math.pi * 3 * np.linspace(0.0, 1.0, n))
    c = analytic_baseline(parse_text(format_recording(K, "output_shaft", u * X, u)), params).compliance
    step = 0.016       # the reading's count, twice the white noise
    y = power_stiffening_twist(u, 2.0, 1.1) + 0.008 * np.random.default_rng(4).standard_normal(n)
    y = np.round(y / step) * step
    # main: "encoder_error + compliance_offset", a line pitch of two counts with a 2x amplitude at its bound
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        diag = diagnose(parse_text(format_recording(K, "output_shaft", u * X, y * X * c)), params, workers=1)[0]
    assert diag.verdict is Verdict.EXPLAINED and diag.named == ("nonlinear_stiffness",)


def _ctx(y: np.ndarray) -> Context:
    u = np.linspace(-1.0, 1.0, len(y))
    return Context(u=u, y=y, t=np.linspace(0.0, 1.0, len(y)), X=1.0, Y=1.0, c0=1.0, load_unit="N*mm",
                   response_unit="rad", direction=np.ones_like(u), segments=((0, len(u), 1),))


def test_interpolation_error_beyond_a_decodable_fraction_of_the_pitch_is_implausible():
    """Bounds P/(2 pi) at the line frequency (an offset as large as the signal), P/8 at twice it (a phase error of
    90 degrees): just inside is plausible, just outside is not."""
    enc = CATALOGUE["encoder_error"]
    ctx = _ctx(np.linspace(-1.0, 1.0, 4001))
    ctx.cache["response_line"] = (40.0, 2.0)       # a line of pitch 1/40 over the recorded span
    pitch = 1.0 / 40.0
    inside = np.array([0.0, 0.99 * pitch / (2 * math.pi), 0.0, 0.0, 0.99 * pitch / 8])
    assert enc.plausible(ctx, inside, 1.0) == []
    assert len(enc.plausible(ctx, inside * np.array([1, 1.03, 1, 1, 1]), 1.0)) == 1
    assert len(enc.plausible(ctx, inside * np.array([1, 1, 1, 1, 1.03]), 1.0)) == 1
