"""A torque-proportional stiffness ripple at twice the input angle is read as a flexspline crack breathing, with
its amplitude, and sized on an FEA-style ripple curve (here a power law whose inverse is known in closed form)."""
import numpy as np
import pytest

from strainwave.compare.diagnose.baseline import analytic_baseline
from strainwave.compare.diagnose.breathing_crack import ripple_reading
from strainwave.compare.diagnose.context import build_context
from strainwave.compare.diagnose.crack_sizing import DeltaCurve
from strainwave.compare.diagnose.pipeline import diagnose
from strainwave.compare.diagnose.recording import RecordingKind, format_recording, parse_text

RIPPLE = 1.2          # % of the compliance, at twice the input angle
DEPTHS = (0.1, 0.2, 0.4, 0.8, 1.2, 1.6)
CURVE_A, CURVE_P = 0.9, 1.5        # the curve's ripple = A a^P (% of K_HD, a in mm): a = (r / A)^(1/P)


def _curve(scale: float = 1.0) -> DeltaCurve:
    ripple = tuple(scale * CURVE_A * a ** CURVE_P for a in DEPTHS)
    return DeltaCurve("cup", "% of K_HD", DEPTHS, ripple, tuple(0.01 * r for r in ripple), 1.6, "power law")


def _diagnosis(params, ripple_of_torque: bool):
    n = 600
    u = np.interp(np.linspace(0, 5, n), np.arange(6), [0, 1, -1, 1, -1, 0])
    angle = 2 * np.pi * 7 * np.linspace(0, 1, n)
    probe = parse_text(format_recording(RecordingKind.TORSION, "output_shaft", u * 1e5, u))
    ctx = build_context(probe, analytic_baseline(probe, params))
    wave = 0.01 * RIPPLE * np.cos(2 * angle + 0.4)
    y = u * (1.0 + wave) if ripple_of_torque else u + 0.7 * wave
    y = y + 1e-3 * np.random.default_rng(4).standard_normal(n)
    rec = parse_text(format_recording(RecordingKind.TORSION, "output_shaft", u * ctx.X, y * ctx.Y,
                                      input_angle_rad=angle))
    return diagnose(rec, params, workers=1)[0]


@pytest.mark.heavy
def test_a_torque_proportional_2x_ripple_is_read_as_a_breathing_crack_and_sized(params):
    diag = _diagnosis(params, True)
    reading = ripple_reading(diag, _curve())
    assert reading is not None and reading.resolved
    assert abs(reading.ripple_percent - RIPPLE) < 3 * reading.std_error_percent
    assert reading.ripple_percent == pytest.approx(RIPPLE, rel=0.1)
    assert "flexspline tooth-root crack breathing" in reading.line()
    truth = (RIPPLE / CURVE_A) ** (1 / CURVE_P)                  # the closed-form inverse of the curve
    size = reading.size
    assert size.possible and size.low_mm <= truth <= size.high_mm
    assert size.depth_mm == pytest.approx((reading.ripple_percent / CURVE_A) ** (1 / CURVE_P), rel=0.01)
    # the check can fail: on a curve twice as steep the same ripple is a shallower crack, outside that interval
    steep = ripple_reading(diag, _curve(2.0)).size
    assert not steep.low_mm <= truth <= steep.high_mm
    # a flexspline whose deepest crack ripples less cannot hold it
    shallow = ripple_reading(diag, _curve(0.05)).size
    assert not shallow.possible and "exceeds" in shallow.reason


def test_a_ripple_at_every_load_is_no_breathing_crack(params):
    diag = _diagnosis(params, False)
    assert diag.named == ("kinematic_error",)
    assert ripple_reading(diag, _curve()) is None
