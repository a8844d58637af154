"""Diagnosis of real test rigs: each recording is written here from first principles, never with a
catalogue effect's own model.

- friction: a twist-driven Maxwell-slip joint (parallel Jenkins elements: a spring and a Coulomb slider each,
  Iwan 1966), a loop that need not slip fully, beside a linear spring;
- kinematic error: the wave generator's elliptical deflection, a ripple at twice the input angle;
- a torque held at its extremes while the wave generator keeps turning.
"""
import math
import warnings

import numpy as np
import pytest

from strainwave.compare.diagnose.baseline import analytic_baseline
from strainwave.compare.diagnose.context import build_context
from strainwave.compare.diagnose.pipeline import Verdict, diagnose
from strainwave.compare.diagnose.recording import RecordingKind, format_recording, parse_text

K = RecordingKind.TORSION
X = 1e6          # N*mm full scale


def maxwell_slip(phi: np.ndarray, k_linear: float, k: np.ndarray, slip: np.ndarray) -> np.ndarray:
    """Torque of a twist-driven joint: a linear spring beside Jenkins elements (spring k_i in series with a
    slider that slips at torque slip_i), each slider moving only when its spring's torque would exceed slip_i."""
    s = np.zeros(len(k))
    torque = np.empty_like(phi)
    for j, p in enumerate(phi):
        tau = k * (p - s)
        s = np.where(np.abs(tau) > slip, p - np.sign(tau) * slip / k, s)
        torque[j] = k_linear * p + float(np.sum(np.clip(tau, -slip, slip)))
    return torque


def _path(n, knots=(0, 1, -1, 1, -1, 0)):
    return np.interp(np.linspace(0, len(knots) - 1, n), np.arange(len(knots)), knots)


def partial_slip_loop(n: int, share: float = 0.3, stuck: float = 0.5, secant: float = 1.0):
    """(torque u, twist y) normalised, of a Maxwell-slip joint whose elements carry ``share`` of the stuck
    stiffness, their slip twists spread so that at the stroke's end only a fraction ``stuck`` of the range
    has slipped; scaled so that the twist between the two load extremes over the torque between them (the
    secant compliance) is ``secant`` times the baseline's."""
    phi = _path(n)
    m = 20
    k = np.full(m, share / m)
    torque = maxwell_slip(phi, 1.0 - share, k, k * np.linspace(0.05, 1.0 / stuck, m))
    measured = np.ptp(phi) / np.ptp(torque)
    peak = float(np.max(np.abs(torque)))
    return torque / peak, phi / (measured * peak) * secant


def _ctx(params, u):
    probe = parse_text(format_recording(K, "output_shaft", u * X, u))
    return build_context(probe, analytic_baseline(probe, params))


def _diagnose(params, u, y, *, sigma=1e-3, seed=0, angle=None):
    rng = np.random.default_rng(seed)
    ctx = _ctx(params, u)
    y = y + 0.01 + 0.002 * np.linspace(0, 1, len(u)) + sigma * rng.standard_normal(len(u))
    rec = parse_text(format_recording(K, "output_shaft", u * X, y * ctx.Y, input_angle_rad=angle))
    return diagnose(rec, params, workers=1)[0], ctx


def test_the_joint_dissipates_and_sticks_after_a_reversal():
    """First principles of the generator: a positive closed integral of T dphi, and right after a reversal every
    slider sticks (the tangent is the stuck stiffness 1)."""
    phi = _path(1501, (0, 1, -1, 1))          # reversals at samples 500 and 1000
    k = np.full(20, 0.3 / 20)
    T = maxwell_slip(phi, 0.7, k, k * np.linspace(0.05, 2.0, 20))
    loop = slice(500, 1501)
    assert np.sum(0.5 * (T[loop][1:] + T[loop][:-1]) * np.diff(phi[loop])) > 0
    assert (T[502] - T[501]) / (phi[502] - phi[501]) == pytest.approx(1.0, rel=1e-9)


def test_kinematic_error_beside_a_friction_loop_is_named_with_its_loss(params):
    """The loop width was read by running the whole model on a reference cycle without an input angle: a
    TypeError, exit 1. The ripple in the input angle is no part of the loop."""
    n = 900
    u, y = partial_slip_loop(n, share=0.5, stuck=0.6)
    angle = 2 * np.pi * 6 * np.linspace(0, 1, n)
    ripple = 0.004 * np.cos(2 * angle + 0.3)
    diag, ctx = _diagnose(params, u, y + ripple, angle=angle)
    assert diag.verdict is Verdict.EXPLAINED and set(diag.named) == {"hysteresis", "kinematic_error"}
    width = np.interp(0.0, *_branch(u, y, -1)) - np.interp(0.0, *_branch(u, y, +1))
    assert diag.quantity("hysteresis_loss") == pytest.approx(width * ctx.Y, rel=0.05)


def _branch(u, y, direction):
    """(u, y) of the last full loading (+1) or unloading (-1) stroke, ascending in u, for interpolation."""
    d = np.sign(np.diff(u))
    idx = np.flatnonzero(d == direction)
    stop = idx[-1] + 1
    start = stop
    while start > 0 and d[start - 1] == direction:
        start -= 1
    uu, yy = u[start:stop + 1], y[start:stop + 1]
    return (uu, yy) if direction > 0 else (uu[::-1], yy[::-1])


@pytest.mark.parametrize("stuck", [0.5, 0.7])
def test_a_loop_not_fully_slipped_is_no_softer_specimen(params, stuck):
    """Secant compliance on its nominal: only the loop is named, and the secant it reports is the recording's
    (the slip tangent at a reversal read as a +9.6 % and +13.4 % compliance change)."""
    u, y = partial_slip_loop(700, stuck=stuck)
    diag, _ = _diagnose(params, u, y)
    assert diag.verdict is Verdict.EXPLAINED and diag.named == ("hysteresis",)
    assert abs(diag.quantity("secant_compliance_change_percent")) < 1.0


def test_the_same_loop_on_a_softer_specimen_names_the_secant_change(params):
    """The check can fail: the same joint 25 % softer over its secant (its stuck, elastic stiffness then 13 % off:
    both readings beyond the 2 % prior) is a series compliance beside the loop, reported as the secant's change."""
    u, y = partial_slip_loop(700, stuck=0.5, secant=1.25)
    diag, _ = _diagnose(params, u, y)
    assert diag.verdict is Verdict.EXPLAINED and set(diag.named) == {"hysteresis", "compliance_offset"}
    assert diag.quantity("compliance_offset.compliance_change_percent") == pytest.approx(25.0, abs=1.5)


def _held_extremes(n):
    """Torque ramps held at +/- full scale for a tenth of the record each, the wave generator turning steadily:
    under the holds the twist moves by the kinematic error alone."""
    u = _path(n, (0, 1, 1, -1, -1, 1, 1, -1, -1, 0))
    angle = 2 * np.pi * 8 * np.linspace(0, 1, n)
    return u, u + 0.003 * np.cos(2 * angle), angle


def test_a_held_torque_under_a_turning_wave_generator_is_its_kinematic_error(params):
    """The hold check read the twist the kinematic error draws as a load channel stuck at its extreme
    (unexplained at chi2/n 0.95); it is judged on what the fitted model leaves."""
    u, y, angle = _held_extremes(800)
    diag, _ = _diagnose(params, u, y, angle=angle)
    assert diag.verdict is Verdict.EXPLAINED and diag.named == ("kinematic_error",)


def test_the_same_hold_without_the_input_angle_is_unexplained(params):
    """The check can fail: without the input angle no model draws the ripple, under the holds or elsewhere."""
    u, y, _ = _held_extremes(800)
    diag, _ = _diagnose(params, u, y)
    assert diag.verdict is Verdict.UNEXPLAINED and "periodic in time" in diag.structure


def test_a_stiffness_rippling_at_twice_the_input_angle_is_named(params):
    """The twist of a compliance 1 + 1.2 % cos(2 theta) grows with the torque (residual ~4x the white noise):
    it read "agrees", the noise model absorbing it."""
    n = 800
    u, angle = _path(n), 2 * np.pi * 7 * np.linspace(0, 1, n)
    diag, _ = _diagnose(params, u, u * (1.0 + 0.012 * np.cos(2 * angle + 0.4)), angle=angle)
    assert diag.verdict is Verdict.EXPLAINED and diag.named == ("stiffness_ripple",)
    assert diag.quantity("compliance_ripple_2x_percent") == pytest.approx(1.2, rel=0.1)


def test_a_ripple_that_does_not_grow_with_the_torque_is_the_kinematic_error(params):
    """The check can fail: the same ripple at every load is no stiffness change."""
    n = 800
    u, angle = _path(n), 2 * np.pi * 7 * np.linspace(0, 1, n)
    diag, _ = _diagnose(params, u, u + 0.008 * np.cos(2 * angle + 0.4), angle=angle)
    assert diag.verdict is Verdict.EXPLAINED and diag.named == ("kinematic_error",)


def _encoder_reading(twist: np.ndarray, pitch: float) -> np.ndarray:
    """An interpolating encoder's reading: quadrature signals sin, cos of the line phase with an offset, unequal
    gains and a phase error, the phase read back by atan2 and unwrapped over the lines (Heidenhain's error
    sources of interpolation), so the error repeats every line pitch of the true twist."""
    phase = 2 * np.pi * twist / pitch
    a = 1.0 * np.sin(phase) + 0.08
    b = 1.15 * np.cos(phase + 0.08)
    read = np.unwrap(np.arctan2(a, b))
    return read * pitch / (2 * np.pi)


def test_an_encoder_interpolation_error_is_named_with_its_pitch(params):
    """The error repeats every line pitch of the measured angle at any load, ~4x the white noise (it read
    "agrees")."""
    u = _path(900)
    pitch = 2.0 / 9.0                        # 9 lines over the recorded twist range (normalised)
    diag, ctx = _diagnose(params, u, _encoder_reading(u, pitch))
    assert diag.verdict is Verdict.EXPLAINED and diag.named == ("encoder_error",)
    assert diag.quantity("period") == pytest.approx(pitch * ctx.Y, rel=0.02)


def _cha_curve_text(given_stiffness: str = "") -> str:
    """A CHA-25 (ratio 100) catalogue curve, phi odd in T with three slopes (the table's own definition:
    K1 = 31e3, K2 = 50e3, K3 = 57e3 N*m/rad, T1 = 29, T2 = 108 N*m), cycled to +/- 1.5 T2, on a gear specimen."""
    T = 1.5 * 108e3 * _path(400)
    a = np.abs(T)
    K1, K2, K3, T1, T2 = 31e6, 50e6, 57e6, 29e3, 108e3
    phi = np.sign(T) * np.where(a <= T1, a / K1, np.where(a <= T2, T1 / K1 + (a - T1) / K2,
                                                          T1 / K1 + (T2 - T1) / K2 + (a - T2) / K3))
    phi = phi + 2e-6 * np.random.default_rng(0).standard_normal(len(T))
    rows = "\n".join(f"{t:.6g},{p:.8g}" for t, p in zip(T, phi))
    return (f'# [test]\n# kind = "torsion"\n# specimen = "gear"\n# baseline_uncertainty = 0.3\n{given_stiffness}'
            f"torque_Nmm,twist_rad\n{rows}\n")


def test_a_gear_curve_against_another_gears_baseline_names_the_key_to_set(strainwave_cmd, tmp_path):
    """A CHA curve without its baseline stiffness read "compliance change 6378 %, unexplained": the
    default gear is another gear. Exit 2, one line naming the header key, nothing written."""
    import subprocess
    rec = tmp_path / "cha.csv"
    rec.write_text(_cha_curve_text())
    out = subprocess.run([*strainwave_cmd, "diagnose", str(rec), "--json", str(tmp_path / "o.json")],
                         capture_output=True, text=True, timeout=300)
    assert out.returncode == 2 and "Traceback" not in out.stderr and out.stderr.count("\n") == 1
    assert "baseline_stiffness_Nmm_per_rad" in out.stderr and "cha.csv" in out.stderr
    assert "--stiffness" in out.stderr                     # the flag that sets it, for a recording without a header
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cha.csv"]


def test_the_same_curve_with_its_stiffness_given_is_diagnosed(params):
    """The check can fail: given the table's K1, the curve is within 10x and reads as its stiffening."""
    rec = parse_text(_cha_curve_text("# baseline_stiffness_Nmm_per_rad = 31e6\n"))
    diag = diagnose(rec, params, workers=1)[0]
    assert diag.verdict is Verdict.EXPLAINED and diag.primary == "nonlinear_stiffness"


def _unit_rows(n=30):
    """Rows of torque in N m and twist in arcmin, written by a German-locale spreadsheet (';', decimal comma)."""
    return "\n".join(f"{12.5 * i:.4f};{0.02 * i:.5f}".replace(".", ",") for i in range(n))


def test_a_column_row_in_the_engineers_units_is_converted():
    """`Torque [Nm];Angle [arcmin]`: 1 N m = 1000 N mm, 1 arcmin = pi / 10800 rad (definitions)."""
    head = '# [test]\n# kind = "torsion"\n# specimen = "gear"\n'
    rec = parse_text(head + "Torque [Nm];Angle [arcmin]\n" + _unit_rows() + "\n")
    i = np.arange(30)
    assert rec.load_name == "torque_Nmm" and rec.response_name == "twist_rad"
    assert np.allclose(rec.load, 12.5e3 * i) and np.allclose(rec.response, 0.02 * i * math.pi / 10800, rtol=1e-12)
    ring = parse_text('# [test]\n# kind = "ring_compression"\n# specimen = "ewg_ring"\n'
                      "Force [kN];Deflection [um]\n" + _unit_rows() + "\n")
    assert np.allclose(ring.load, 12.5e3 * i) and np.allclose(ring.response, 0.02e-3 * i, rtol=1e-12)


@pytest.mark.parametrize("row, bad", [("Torque [lbf ft];Angle [arcmin]", "lbf ft"),
                                      ("Torque [Nm];Angle [grad]", "grad"),
                                      ("Torque [Nm];Strain [1]", "Strain [1]")])
def test_an_unknown_unit_is_named_with_the_allowed_ones(row, bad):
    from strainwave.errors import InputError
    head = '# [test]\n# kind = "torsion"\n# specimen = "gear"\n'
    with pytest.raises(InputError) as err:
        parse_text(head + row + "\n" + _unit_rows() + "\n", "rec.csv")
    text = str(err.value)
    assert text.startswith("rec.csv:4") and bad in text and ("allowed: " in text or "one of: " in text)
