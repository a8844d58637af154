"""Family 1's higher-fidelity generators against first principles, the scorer on hand-made outcomes,
a small smoke run of both families, and the CLI's bad-flag exits. The model's accuracy is NOT asserted
here (it is measured by `benchmark-diagnose` / `make bench`, which print PASS/MISS)."""
import json
import math

import numpy as np
import pytest

from strainwave.cli import main
from strainwave.compare.diagnose.generators import hifi_ring as hr
from strainwave.compare.diagnose.generators import hifi_torsion as ht
from strainwave.compare.diagnose.generators.benchmark import Outcome, family_targets, run_benchmark
from strainwave.compare.diagnose.generators.loop_metrics import measure_loop, set_after_unloading

A = 1e5
CYCLE = A * np.interp(np.linspace(0, 4, 4001), [0, 1, 2, 3, 4], [0, 1, -1, 1, 0])


@pytest.mark.parametrize("fraction", [0.05, 0.2, 0.4])
def test_maxwell_slip_dissipates_and_has_its_loss(fraction):
    law = lambda T: ht.maxwell_slip_twist(T, 1e-4, fraction)
    loop = measure_loop(law, A)
    # friction: work is done on the specimen every cycle and unloading from +T leaves a positive twist
    assert loop.energy_Nmm_rad > 0 and set_after_unloading(law, A) > 0
    assert loop.loss_rad == pytest.approx(1e-4, rel=1e-9)          # every element slips: width 2 sum w r
    # a dissipative loop's energy is at most loss x (2 x full torque) (rectangle bound), at least a fraction
    assert 0.2 * 1e-4 * 2 * A < loop.energy_Nmm_rad < 1e-4 * 2 * A


@pytest.mark.parametrize("loss_over_cT", [0.005, 0.08])
def test_family1_friction_on_the_stiffest_gear_is_passive(loss_over_cT):
    """The widest loop family 1 draws, with its narrowest slip range, on its stiffest contact spread: the
    twist still moves with the torque along every monotonic stretch (a spring-and-slider chain is passive)."""
    from strainwave.compare.diagnose.generators.generate_recordings import STIFFEST, passive_slip_fraction
    c = 1e-8
    loss = loss_over_cT * c * A
    frac = passive_slip_fraction(0.05, loss, A, c)
    assert frac <= 0.5
    twist = c * CYCLE + ht.contact_spread_twist(CYCLE, 1 / c, STIFFEST / c, 0.15 * A, 2.5) + \
        ht.maxwell_slip_twist(CYCLE, loss, frac)
    steps = np.diff(CYCLE) != 0
    assert np.all(np.diff(twist)[steps] * np.sign(np.diff(CYCLE)[steps]) > 0)


def test_backlash_with_friction_dissipates_and_without_is_odd_and_centred():
    law = lambda T: ht.backlash_twist(T, 1e-4, 0.05 * A, 0.01 * A)
    assert measure_loop(law, A).energy_Nmm_rad > 0 and set_after_unloading(law, A) > 0
    T = np.linspace(-A, A, 2001)
    frictionless = ht.backlash_twist(T, 1e-4, 0.05 * A, 0.0)
    np.testing.assert_allclose(frictionless, -frictionless[::-1], atol=1e-18)   # dead zone centred on T = 0
    assert frictionless[-1] - frictionless[0] == pytest.approx(1e-4)            # the lost motion it was given


def test_contact_spread_stiffening_is_monotone_with_its_end_slopes():
    K1, K3 = 1e9, 1.5e9
    tw = ht.contact_spread_twist(CYCLE, K1, K3, 2e4) + CYCLE / K1
    T = np.linspace(1.0, A, 2000)
    stiffness = np.diff(T) / np.diff(ht.contact_spread_twist(T, K1, K3, 2e4) + T / K1)
    assert np.all(np.diff(stiffness) > -1e-6 * K1)                  # stiffening never reverses
    assert stiffness[0] == pytest.approx(K1, rel=1e-3) and stiffness[-1] == pytest.approx(K3, rel=1e-3)
    assert np.ptp(tw[np.abs(CYCLE - A / 2) < 1]) < 1e-15            # elastic: same twist on every pass


@pytest.mark.parametrize("sign", [1, -1])
def test_breathing_crack_closes_under_the_other_sign(sign):
    cx, Tc = 2e-10, 2e3
    T = np.linspace(-A, A, 4001)
    compliance = np.gradient(ht.breathing_crack_twist(T, cx, Tc, sign), T)
    closed, opened = sign * T < -10 * Tc, sign * T > 10 * Tc
    assert np.all(compliance[closed] < 1e-6 * cx) and np.allclose(compliance[opened], cx, rtol=1e-6)


def test_elastica_ring_small_load_is_seed_003_eq_3_and_softens():
    # P = F R^2/EI; the thin-ring limit delta/R = 0.148778 P (seed 003 eq 3) to 1e-3 at P = 1e-3
    assert hr.elastica_point(1e-3) / (hr.THIN_DV * 1e-3) == pytest.approx(1.0, abs=1e-3)
    r1, r2 = (hr.elastica_point(p) / (hr.THIN_DV * p) for p in (0.5, 1.0))
    assert 1.0 < r1 < r2


def test_fibre_ring_is_elastic_below_yield_and_keeps_a_positive_set_above():
    R, h, b, E, sy = 38.9, 2.88, 12.0, 2.1e5, 800.0
    I = b * h ** 3 / 12.0
    Fy = math.pi * sy * b * h ** 2 / 6.0 / R          # first yield under the load (M = F R/pi)
    d = hr.fibre_ring_deflection(np.array([0.5 * Fy]), R, h, b, E, sy)
    assert d[0] == pytest.approx(hr.THIN_DV * 0.5 * Fy * R ** 3 / (E * I), rel=1e-3)
    path = np.concatenate([np.linspace(0, 1.4 * Fy, 15), np.linspace(1.4 * Fy, 0, 15)])
    d = hr.fibre_ring_deflection(path, R, h, b, E, sy)
    assert d[-1] > 0.02 * d.max()                     # plasticity leaves a positive permanent set


def test_curved_beam_factor_tends_to_thin_ring():
    assert hr.curved_beam_factor(40.0, 0.4, 12.0, 0.3) == pytest.approx(1.0, abs=1e-3)
    assert hr.curved_beam_factor(44.55, 14.4, 12.0, 0.3) > 1.1


def _outcome(**kw):
    base = dict(family=2, name="x", cls="c", truth=(), out_of_catalogue="", noise="white", snr=5.0, n_samples=100,
                verdict="agrees", named=(), ambiguous=False, loss_true_arcmin=None, loss_arcmin=None,
                stiffness_true=None, stiffness=None, rms_before=1.0, rms_after=1.0, noise_std=1.0, seconds=0.1)
    base.update(kw)
    return Outcome(**base)


def test_scorer_counts_each_target_from_hand_made_outcomes():
    outs = [
        _outcome(truth=("hysteresis",), verdict="explained", named=("hysteresis",), loss_true_arcmin=1.0,
                 loss_arcmin=1.05),                                                  # right, loss within 10 %
        _outcome(truth=("hysteresis",), verdict="explained", named=("hysteresis", "lost_motion"),
                 loss_true_arcmin=1.0, loss_arcmin=1.2),                             # primary ok, set and loss not
        _outcome(truth=("lost_motion",), verdict="explained", named=("nonlinear_stiffness",)),
        _outcome(truth=("lost_motion",), snr=2.0, verdict="agrees"),                 # below 3x noise: not scored
        _outcome(noise="ar1", verdict="unexplained"),                                # coloured false alarm
        _outcome(noise="white", verdict="agrees"),
        _outcome(out_of_catalogue="ripple_time", verdict="unexplained"),
        _outcome(out_of_catalogue="spliced", verdict="explained", named=("compliance_offset",), ambiguous=True),
        _outcome(out_of_catalogue="clipping", verdict="explained", named=("crack_closure",)),
        _outcome(truth=("nonlinear_stiffness",), verdict="explained", named=("nonlinear_stiffness",),
                 stiffness_true=(1.0, 2.0, 3.0), stiffness=(1.01, 2.0, 3.1)),        # K3 off by 3.3 %
    ]
    t = {x.name: x for x in family_targets(outs)}
    assert t["primary effect, signal >= 3x noise"].value == pytest.approx(2 / 3)
    assert t["exactly the right set, signal >= 3x noise"].value == pytest.approx(1 / 3)
    assert t["false alarms, clean, coloured noise"].value == 1.0
    assert t["false alarms, clean, white noise"].status == "PASS"
    assert t["hysteresis named, loss within 10 %"].value == 0.5
    assert t["out of catalogue: unexplained or ambiguous"].value == pytest.approx(2 / 3)
    assert t["out of catalogue: confidently wrong effect"].value == pytest.approx(1 / 3)
    assert t["CHA: exactly nonlinear_stiffness, K within 2 %"].status == "MISS"
    assert t["CHA + loop: exactly nonlinear_stiffness + hysteresis"].status == "n/a"


@pytest.mark.heavy
def test_smoke_run_of_both_families_writes_tables(tmp_path):
    classes = {1: ("clean_torsion_coloured", "hysteresis", "plasticity"),
               2: ("clean_coloured", "bouc_wen", "ramberg_osgood", "ripple_time", "spliced")}
    report = run_benchmark(1, seed=3, out_dir=tmp_path, rows=(200, 300), classes=classes, cha=1)
    assert len(report.outcomes) == 3 + 5 + 2 * 2          # one CHA row with and without a loop per family
    assert not [o.error for o in report.outcomes if o.verdict == "error"]
    doc = json.loads((tmp_path / "benchmark_diagnose.json").read_text())
    assert set(doc["family"]) == {"1", "2"}
    assert set(doc["family"]["2"]["out_of_catalogue"]) == {"ripple_time", "spliced"}
    assert set(doc["family"]["1"]["confusion"]) == set(classes[1])
    text = (tmp_path / "benchmark_diagnose.txt").read_text()
    assert "out of catalogue, family 2" in text and "CHA table, family 1" in text
    assert text.count("PASS") + text.count("MISS") >= 8


@pytest.mark.parametrize("argv", [["--n", "0"], ["--n", "-3"], ["--family", "3"], ["--n", "many"]])
def test_bad_benchmark_flags_exit_2_with_one_line(argv, capsys):
    assert main(["benchmark-diagnose", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error:") and len(err.splitlines()) == 1


def test_loss_error_bar_scoring_from_hand_made_outcomes():
    loop = dict(truth=("hysteresis",), verdict="explained", named=("hysteresis",), loss_true_arcmin=1.0)
    covered = _outcome(**loop, loss_arcmin=1.25, loss_std_error_arcmin=0.15)     # a 25 % miss, 1.7 SE, said so
    overconfident = _outcome(**loop, loss_arcmin=1.25, loss_std_error_arcmin=0.05)   # 5 SE: the bar lied
    no_bar = _outcome(**loop, loss_arcmin=1.0)
    assert covered.loss_within_3se and covered.loss_flagged_imprecise and not covered.loss_ok
    assert overconfident.loss_within_3se is False and not overconfident.loss_flagged_imprecise
    assert no_bar.loss_within_3se is None and not no_bar.loss_flagged_imprecise
