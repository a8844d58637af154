"""Crack sizing from a compliance change and Paris-law life: inverse and integral checked against closed forms."""
import math

import numpy as np
import pytest

from strainwave.analytic import tube_crack
from strainwave.compare.diagnose.crack_sizing import DeltaCurve, size_crack
from strainwave.compare.diagnose.remaining_life import (BS7910_STEEL, LoadSpectrum, ParisLaw, remaining_life,
                                                        spectrum_from_history)

R_O, R_I, G = 35.0, 22.5, 80769.0
WALL = R_O - R_I


def tube_curve(fractions=(0.03, 0.1, 0.25, 0.45, 0.7, 0.9), rel_gci=0.01):
    a = tuple(f * WALL for f in fractions)
    d = tuple(tube_crack.thick_tube_flexibility(R_O, R_I, x, G) for x in a)
    return DeltaCurve("shaft", "rad/(N*mm)", a, d, tuple(rel_gci * v for v in d), WALL, "closed form",
                      front_length_mm=lambda x: 2.0 * math.pi * R_O)


def power_curve(c=2e-14, p=3.0, L=50.0):
    a = (0.5, 1.0, 2.0, 4.0, 8.0)
    return DeltaCurve("x", "rad/(N*mm)", a, tuple(c * x ** p for x in a), (0.0,) * 5, 10.0, "power law",
                      front_length_mm=lambda x: L)


def test_sizing_inverts_the_curve_between_and_below_its_points():
    curve = power_curve()
    for a in (0.2, 0.7, 3.3, 8.0):
        (s,) = size_crack(curve.delta_at(a), 0.0, [curve])
        assert s.possible and s.depth_mm == pytest.approx(a, rel=1e-9) and s.low_mm == s.high_mm == s.depth_mm


def test_a_change_no_crack_in_the_component_can_reach_is_refused_by_name():
    curve = tube_curve()
    (s,) = size_crack(10 * curve.delta[-1], 0.01 * curve.delta[-1], [curve])
    assert not s.possible and "exceeds" in s.reason and "cannot hold" in s.line()


def test_change_within_noise_of_zero_says_so():
    curve = tube_curve()
    (s,) = size_crack(0.5 * curve.delta[0], curve.delta[0], [curve])
    assert s.possible and s.low_mm == 0.0 and "no crack" in s.reason


def test_interpolated_curve_sizes_an_independent_truth_within_its_interval():
    """Recordings drawn around the tube form at depths between the curve's points (not on them): the k = 2
    interval holds the true depth in >= 90 % of draws and is no wider than 2x the draws' spread."""
    curve, rng = tube_curve(), np.random.default_rng(7)
    for a_true in (2.0, 4.7, 8.1):
        truth = tube_crack.thick_tube_flexibility(R_O, R_I, a_true, G)
        sigma = 0.03 * truth
        sizes = [size_crack(truth + rng.normal(0, sigma), sigma, [curve])[0] for _ in range(300)]
        hits = np.mean([s.low_mm <= a_true <= s.high_mm for s in sizes])
        spread = np.std([s.depth_mm for s in sizes])
        half = np.median([(s.high_mm - s.low_mm) / 2 for s in sizes])
        assert hits >= 0.90 and half <= 2.0 * 2.0 * spread, (a_true, hits, half, spread)


def test_stress_intensity_from_the_curve_equals_the_one_that_built_it():
    """The curve is the eq-4 integral of K_III^2: its slope must give that K_III back (mode III, E' = 2 mu)."""
    from strainwave.compare.diagnose.remaining_life import _k_per_torque

    a = 3.0
    fine = DeltaCurve("shaft", "rad/(N*mm)", (a * 0.999, a * 1.001),
                      tuple(tube_crack.thick_tube_flexibility(R_O, R_I, x, G) for x in (a * 0.999, a * 1.001)),
                      (0.0, 0.0), WALL, "closed form", front_length_mm=lambda x: 2.0 * math.pi * R_O)
    k_built = (tube_crack.tube_outer_stress_per_torque(R_O, R_I) * tube_crack.strip_factor(a / WALL)
               * math.sqrt(math.pi * a) * tube_crack.thick_tube_amplification(R_O, R_I, a)
               ** (tube_crack.THICK_TUBE_EXPONENT / 2))
    assert _k_per_torque(fine, a, 2.0 * G) == pytest.approx(k_built, rel=2e-3)


def test_paris_integral_matches_its_closed_form_for_a_power_law_curve():
    c, p, L, Ep, dT = 2e-14, 3.0, 50.0, 2.1e5, 2e5
    curve = power_curve(c, p, L)
    (s,) = size_crack(curve.delta_at(1.0), 0.0, [curve])
    lam0 = curve.delta_at(4.0) * 9.0                 # 10 % stiffness loss exactly at a = 4 mm
    life = remaining_life(s, curve, lam0, LoadSpectrum.constant(dT), modulus_MPa=Ep, stiffness_loss=0.1)
    B = (Ep * 0.5 * c * p / L) ** (BS7910_STEEL.m / 2)
    q = (p - 1) * BS7910_STEEL.m / 2
    exact = (4.0 ** (1 - q) - 1.0 ** (1 - q)) / (1 - q) / (BS7910_STEEL.C * B * dT ** BS7910_STEEL.m)
    assert life.stop_depth_mm == pytest.approx(4.0, rel=1e-9) and life.cycles == pytest.approx(exact, rel=1e-6)
    assert life.curve[0][1] > life.curve[-1][1] == pytest.approx(0.9, rel=1e-6)   # stiffness falls to the limit


def test_life_scales_as_the_load_range_to_the_minus_m_and_rainflow_agrees_with_constant_amplitude():
    curve = power_curve()
    (s,) = size_crack(curve.delta_at(1.0), 0.0, [curve])
    kw = dict(modulus_MPa=2.1e5, stiffness_loss=0.1)
    lam0 = curve.delta_at(4.0) * 9.0
    n1 = remaining_life(s, curve, lam0, LoadSpectrum.constant(1e5), **kw).cycles
    n2 = remaining_life(s, curve, lam0, LoadSpectrum.constant(2e5), **kw).cycles
    assert n1 / n2 == pytest.approx(2.0 ** 3, rel=1e-9)
    history = np.tile([0.0, 2e5], 50)
    n_rf = remaining_life(s, curve, lam0, spectrum_from_history(history), **kw).cycles
    assert n_rf == pytest.approx(n2, rel=1e-9)


def test_steeper_paris_exponent_or_deeper_start_shortens_life():
    curve = power_curve()
    lam0 = curve.delta_at(8.0) * 9.0
    kw = dict(modulus_MPa=2.1e5, stiffness_loss=0.1)
    shallow, deep = (size_crack(curve.delta_at(a), 0.0, [curve])[0] for a in (1.0, 3.0))
    assert (remaining_life(deep, curve, lam0, LoadSpectrum.constant(1e5), **kw).cycles
            < remaining_life(shallow, curve, lam0, LoadSpectrum.constant(1e5), **kw).cycles)
    with pytest.raises(ValueError):
        ParisLaw(1e-12, 0.5, "bad")


def test_life_record_lines_and_plot_for_a_sized_crack(tmp_path):
    import warnings

    from strainwave.compare.diagnose.remaining_life import life_lines, life_of_sizing, plot_life
    from strainwave.params import load_params

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        params = load_params()
    curve = power_curve()
    sizes = size_crack(curve.delta_at(1.0), 0.05 * curve.delta_at(1.0), [curve])
    lives = life_of_sizing({"_sizes": sizes, "_curves": [curve]}, curve.delta_at(4.0) * 9.0, params,
                           cycles_per_hour=3600.0)
    (life,) = lives
    assert life["cycles_low"] < life["cycles"] < life["cycles_high"]
    assert life["hours"] == pytest.approx(life["cycles"] / 3600.0)
    assert "remaining life" in life_lines(lives)[0] and "BS 7910" in life_lines(lives)[0]
    png = plot_life(tmp_path / "life.png", lives)
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def _cup_recording(path, delta_rad_per_Nmm, rng):
    import warnings

    from strainwave.analytic import torsion
    from strainwave.params import load_params

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cup = load_params().flexspline_cup
    c0 = torsion.flexspline_flexibility(cup.pitch_diameter_mm, cup.wall_thickness_mm, cup.length_mm, 80769.23, 1.0,
                                        0.83)
    torque = 1e6 * np.sin(np.linspace(0, 6 * np.pi, 300))
    twist = (c0 + delta_rad_per_Nmm) * torque + rng.normal(0, 2e-7, torque.size)
    head = ["# [test]", '# kind = "torsion"', '# specimen = "flexspline_cup"', "# baseline_uncertainty = 0.001",
            f"# baseline_stiffness_Nmm_per_rad = {1 / c0:.9e}", "torque_Nmm,twist_rad"]
    path.write_text("\n".join(head + [f"{t:.4f},{p:.9e}" for t, p in zip(torque, twist)]) + "\n")
    return c0


def test_size_crack_command_sizes_a_cup_crack_on_a_validate_curve(tmp_path, strainwave_cmd):
    """A cup 1.5 % softer than its model, read against a validate run's cup crack sweep (a^2 law)."""
    import json
    import subprocess

    rng = np.random.default_rng(3)
    depths = [0.1, 0.3, 0.7, 1.4]
    c0 = _cup_recording(tmp_path / "cup.csv", 0.0, rng)
    curve = [0.02 * c0 * (a / 0.7) ** 2 for a in depths]            # delta = 1.5 % of c0 at a = 0.606 mm
    _cup_recording(tmp_path / "cup.csv", 0.015 * c0, rng)
    (tmp_path / "results.json").write_text(json.dumps({"crack_sweeps": {"cup": {
        "unit": "rad/(N*mm)", "depths_mm": depths, "fea": curve, "fea_uncertainty": [0.01 * v for v in curve],
        "resolved": [True] * 4}}}))
    run = subprocess.run([*strainwave_cmd, "size-crack", str(tmp_path / "cup.csv"), "--curves",
                          str(tmp_path / "results.json"), "--json", "-"], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    out = json.loads(run.stdout)
    (size,) = out["sizing"]["sizes"]
    assert size["component"] == "cup" and size["low_mm"] <= 0.7 * (0.015 / 0.02) ** 0.5 <= size["high_mm"]
    assert out["remaining_life"] == []          # the cup's curve carries no crack-front length: no life claimed
    bad = subprocess.run([*strainwave_cmd, "size-crack", str(tmp_path / "cup.csv"), "--curves",
                          str(tmp_path / "cup.csv")], capture_output=True, text=True, timeout=60)
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "--curves" in bad.stderr


def test_midline_of_a_friction_loop_is_the_elastic_compliance_not_the_secant():
    """Coulomb friction f in parallel with a spring of compliance c: twist = c (T - f sgn(dT/dt)). The
    branches sit c f either side of c T; their mean curve is c T exactly."""
    from strainwave.compare.diagnose.crack_sizing import midline_compliance

    c, f, T_max = 1.3e-9, 3e4, 1e6
    T = T_max * np.sin(np.linspace(0, 6 * np.pi, 1800))
    twist = c * (T - f * np.sign(np.gradient(T)))
    slope, err = midline_compliance(T, twist)
    assert slope == pytest.approx(c, rel=1e-6) and err < 1e-6 * c
    straight, _ = midline_compliance(np.linspace(0, T_max, 50), c * np.linspace(0, T_max, 50))
    assert straight == pytest.approx(c, rel=1e-12)             # no loop: the plain slope


def _fake_point(params, depth_mm):
    """A stand-in for the section solves: the thick tube's closed form at the depth, 1 % GCI."""
    value = tube_crack.thick_tube_flexibility(R_O, R_I, depth_mm, G)
    return {"value": value, "uncertainty": 0.01 * value}


def _failing_point(params, depth_mm):
    raise RuntimeError("solved again")


def test_shaft_curve_points_come_back_in_depth_order_and_from_the_cache(params, tmp_path, monkeypatch):
    """The curve's points are solved on both cores where forking is safe and come back in depth order; the next
    call reads every point from the cache and solves none; a point that fails is an error, not a gap."""
    from strainwave.compare.diagnose import crack_sizing
    from strainwave.compare.diagnose.parallel import usable_workers
    monkeypatch.setattr(crack_sizing, "_curve_point", _fake_point)
    said = []
    curve = crack_sizing.shaft_curve_fea(params, tmp_path, progress=said.append)
    wall = params.output_shaft.wall_mm
    expected = [_fake_point(params, round(f * wall, 6))["value"] for f in crack_sizing.SHAFT_DEPTH_FRACTIONS]
    assert curve.delta == tuple(expected)
    assert curve.depths_mm == tuple(round(f * wall, 6) for f in crack_sizing.SHAFT_DEPTH_FRACTIONS)
    assert ("on 2 processes" in said[0]) == (usable_workers() > 1)
    monkeypatch.setattr(crack_sizing, "_curve_point", _failing_point)
    assert crack_sizing.shaft_curve_fea(params, tmp_path).delta == curve.delta
    with pytest.raises(RuntimeError, match="solved again"):
        crack_sizing.shaft_curve_fea(params, tmp_path / "empty")
