"""Hertz line contact at the flank (issue 48 item 3): the closed form by hand, the real involutes' gap, the contact
solve on a problem with a known answer, and the checks mesh.flank_hertz / mesh.flank_hertz_width failing on a
perturbed reference and a perturbed FE value (compare/validate/flank_hertz_checks.py, fea/flank_hertz.py)."""
from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from strainwave.analytic.hertz_line import (contact_modulus_MPa, line_contact, load_for_half_width,
                                            relative_radius_mm)
from strainwave.compare.validate import flank_hertz_checks as fhc
from strainwave.compare.validate.checks import evaluate, quick_resolution
from strainwave.compare.validate.mutation_checks import mutation_rows
from strainwave.fea import flank_hertz as fh
from strainwave.params import load_params

SECOND = "strainwave/data/second_gear.toml"


def test_hertz_line_contact_by_hand():
    # steel on steel, E* = E / (2 (1 - nu^2)) = 2.1e5 / 1.82 = 115 384.6 MPa; R* = 10 mm, P = 100 N/mm:
    # b = sqrt(4 100 10 / (pi 115384.6)) = 0.105046 mm, p0 = 2 100 / (pi b) = 606.03 MPa
    e = contact_modulus_MPa(2.1e5, 0.3)
    assert e == pytest.approx(2.1e5 / 1.82, rel=1e-12)
    h = line_contact(100.0, 10.0, e)
    assert h.half_width_mm == pytest.approx(0.105046, rel=1e-5)
    assert h.peak_pressure_MPa == pytest.approx(606.03, rel=1e-4)
    assert h.peak_pressure_MPa == pytest.approx(math.sqrt(100.0 * e / (math.pi * 10.0)), rel=1e-12)
    assert load_for_half_width(h.half_width_mm, 10.0, e) == pytest.approx(100.0, rel=1e-12)
    # an internal pair: the concave radius counts negative, R* = 30 x 31 / 1 = 930 mm
    assert relative_radius_mm(30.0, -31.0) == pytest.approx(930.0)
    with pytest.raises(ValueError):
        relative_radius_mm(30.0, -30.0)                      # conforming: no Hertz contact


def test_the_real_involutes_gap_is_hertz_s_parabola():
    pair = fh.flank_pair(load_params(None))
    rb_f, rb_c = pair.fs.base_radius_mm, pair.cs.base_radius_mm
    # the involute's radius of curvature is its roll length: rho = sqrt(r^2 - r_b^2)
    assert pair.rho_fs_mm == pytest.approx(math.sqrt(pair.r_fs_mm ** 2 - rb_f ** 2))
    assert 30.0 < pair.rho_fs_mm < pair.rho_cs_mm < 31.0           # near-conformal, as decision 064 found
    x = np.linspace(-0.1, 0.1, 21)
    # each exact flank (points from geometry/involute.py) bends as its own radius: y = -x^2 / (2 rho)
    assert fh.surface_y(pair, 0, x) == pytest.approx(-x ** 2 / (2 * pair.rho_fs_mm), rel=2e-2, abs=1e-12)
    assert fh.surface_y(pair, 1, x) == pytest.approx(-x ** 2 / (2 * pair.rho_cs_mm), rel=2e-2, abs=1e-12)
    gap = fh.initial_gap_mm(pair, x)
    assert gap.min() >= 0.0 and gap[10] == 0.0
    assert gap == pytest.approx(x ** 2 / (2 * pair.relative_radius_mm), rel=1e-2, abs=1e-14)


def test_contact_lcp_on_a_winkler_bed():
    # a diagonal flexibility (each hat its own spring, A_kk = w_k c) on a parabolic gap has the closed answer
    # p_k = (delta - g_k) / c where positive; the load fixes delta
    x = np.linspace(-1.0, 1.0, 41)
    w = fh.hat_weights(x)
    c, g = 1e-3, 0.5 * x ** 2
    delta_true = 0.2
    p_true = np.maximum(delta_true - g, 0.0) / c
    load = float(w @ p_true)
    p, delta = fh.contact_lcp(np.diag(w * c), w, g, load)
    assert delta == pytest.approx(delta_true, rel=1e-10)
    assert p == pytest.approx(p_true, rel=1e-9, abs=1e-9)
    assert w @ p == pytest.approx(load)


@pytest.fixture(scope="module")
def default_checks():
    params = load_params(None)
    return params, fhc.fe_quantities(params)


def test_flank_hertz_checks_pass_and_fail_on_a_perturbed_side(default_checks):
    params, solved = default_checks
    checks = fhc.hertz_checks(params, solved)
    assert [c.id for c in checks] == [fhc.CHECK_P0, fhc.CHECK_B]
    for c in checks:
        assert c.passed, (c.id, c.rel_error, c.tolerance.reason)
        assert c.tolerance.relative < 0.09                       # so a 10 % error fails too
        assert quick_resolution(c) == c                          # resolved at --quick too (the same meshes)
        # the reference perturbed by +-20 % (and the FE value): each fails
        for k in (0.8, 1.2):
            assert not evaluate(dataclasses.replace(c, analytic={"corrected": k * c.analytic["corrected"]})).passed
            assert not evaluate(dataclasses.replace(c, fea=k * c.fea)).passed
    # given the study's rated peak flank load, the notes say Hertz's assumption fails there
    rated = fhc.hertz_checks(params, solved, rated_load_N_per_mm=82.0)
    assert all("Hertz's assumptions fail there" in c.note for c in rated)
    assert [c.fea for c in rated] == [c.fea for c in checks]
    rows = mutation_rows([c.to_dict() for c in checks])
    assert all(r.catches_20 and r.catches_10 for r in rows)
    # the validated load keeps Hertz's half-width at 5 % of the shorter of the working flank and tooth thickness
    pair, h, flank, _ = fhc.closed_form(params)
    assert h.half_width_mm == pytest.approx(fhc.B_OVER_FLANK * min(flank, fhc.tooth_thickness_mm(pair)))


def test_a_wrong_curvature_fails_the_check(default_checks):
    # the closed form taken with the cup flank's radius alone (as if the spline's were flat: an external pair's
    # slip, R* = rho_f) is 10x off: the check must not pass
    params, solved = default_checks
    pair, h, _, _ = fhc.closed_form(params)
    wrong = line_contact(h.load_N_per_mm, pair.rho_fs_mm, h.contact_modulus_MPa)
    c = fhc.hertz_checks(params, solved)[0]
    assert not evaluate(dataclasses.replace(c, analytic={"corrected": wrong.peak_pressure_MPa})).passed


def test_rated_record_says_hertz_fails_there(monkeypatch):
    monkeypatch.setattr(fhc, "RATED_MESHES", (16, 11))          # coarse: the record's statement, not its numbers
    params = load_params(None)
    rec = fhc.rated_record(params, 82.0)["rated"]                # ~ the study's rated peak flank load, 2467 N / 30 mm
    assert rec["b_over_flank"] > 0.9 and not rec["hertz_holds"]
    assert "fail" in rec["statement"]
    # the FE's contact reaches the working flank's end and its peak is far above Hertz's (edge contact)
    assert all(f["zone_ends_loaded"] for f in rec["fe"])
    assert min(f["peak_pressure_MPa"] for f in rec["fe"]) > 3 * rec["hertz_peak_pressure_MPa"]
    assert fhc.rated_record(params, None, "no tooth-mesh case") == {"rated": None, "why": "no tooth-mesh case"}


@pytest.mark.heavy
def test_second_gear_passes_and_fails_at_20_percent():
    params = load_params(SECOND)
    for c in fhc.hertz_checks(params):
        assert c.passed, (c.id, c.rel_error, c.tolerance.reason)
        assert all(r.catches_20 for r in mutation_rows([c.to_dict()]))


def test_a_pair_without_hertz_contact_is_reported_not_raised(monkeypatch):
    # flanks of equal curvature conform: no Hertz contact exists; the checks say so and are not evaluated
    params = load_params(None)
    real = fh.flank_pair(params)
    monkeypatch.setattr(fh, "flank_pair", lambda p: dataclasses.replace(real, rho_cs_mm=real.rho_fs_mm))
    checks = fhc.hertz_checks(params)
    assert [c.verdict for c in checks] == ["not evaluated"] * 2 and not any(c.passed for c in checks)
    assert "conform" in checks[0].reason_not_evaluated
    assert fhc.rated_record(params, 82.0)["rated"] is None
