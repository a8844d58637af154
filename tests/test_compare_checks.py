"""Unit tests of the comparison machinery: verdicts, tolerances, exponent fits, the ring shape, the schema."""
from __future__ import annotations

import copy
import math
from pathlib import Path

import jsonschema
import numpy as np
import pytest

from strainwave.compare.validate.audit_evidence import exponent_evidence
from strainwave.compare.validate.checks import Check, Tolerance, evaluate, fea_tolerance, not_evaluated, verdict_of
from strainwave.compare.validate.crack_scaling import fit_power_law
from strainwave.compare.validate.plan import make_plan, sweep_depths_mm
from strainwave.fea.bearing_ring import patch_depth_limit_mm as bearing_depth_limit_mm
from strainwave.compare.validate.results import plain, validate_results
from strainwave.compare.validate.ring_shape import thin_ring_shape
from strainwave.params import load_params
import strainwave


def _check(fea, published, corrected, tol):
    return evaluate(Check("shaft.flexibility", "q", "rad/(N*mm)", fea, 0.0,
                          {"published": published, "corrected": corrected}, "corrected", Tolerance(tol, "test")))


def test_check_passes_on_corrected_and_reports_published_error():
    # Seed 000 example: solid-shaft 1.0412e-9 vs hollow 1.2790e-9; FEA 0.5 % below the hollow value.
    c = _check(1.2726e-9, 1.0412e-9, 1.2790e-9, 0.0105)
    assert c.passed
    assert c.verdict == "corrected"
    assert c.rel_error["corrected"] == pytest.approx(1.2726 / 1.2790 - 1, rel=1e-12)
    assert c.rel_error["published"] == pytest.approx(1.2726 / 1.0412 - 1, rel=1e-12)


def test_check_fails_honestly_when_fea_contradicts_the_asserted_form():
    c = _check(1.0412e-9, 1.0412e-9, 1.2790e-9, 0.0105)
    assert not c.passed
    assert c.verdict == "published"


def test_verdict_both_and_neither():
    # 0.1 vs pi/32 differ by 1.83 %: a 3 % tolerance cannot tell them apart, a 0.5 % one can.
    assert verdict_of({"published": -0.018, "corrected": 0.0003}, 0.03) == "both"
    assert verdict_of({"published": -0.018, "corrected": 0.0003}, 0.005) == "corrected"
    assert verdict_of({"published": 0.4, "corrected": -0.3}, 0.05) == "neither"


def test_tolerance_states_its_reason_and_adds_up():
    tol = fea_tolerance(2.0, 0.002, allowances={"mu vs E/2(1+nu)": 0.0096})
    # the GCI (0.002/2, its Fs inside it) once + 0.0096: never 3 x a GCI that already holds Fs
    assert tol.relative == pytest.approx(1e-3 + 0.0096, rel=1e-12)
    assert "GCI 0.1 %" in tol.reason and "mu vs E/2(1+nu)" in tol.reason and "3 x" not in tol.reason


def test_not_evaluated_check_does_not_pass_and_serialises_without_nan():
    c = not_evaluated("ring.delta_cd", "q", "mm", "case ring failed")
    d = c.to_dict()
    assert d["passed"] is False and d["verdict"] == "not evaluated"
    assert d["tolerance"]["relative"] is None  # NaN never reaches JSON


def test_power_law_fit_recovers_exponents():
    a = np.array([0.8, 1.6, 3.1, 6.25])
    fit2 = fit_power_law(a, 7e-16 * a ** 2)
    fit3 = fit_power_law(a, 7e-16 * a ** 3 * (1 + 0.01 * np.array([1, -1, 1, -1])))
    assert fit2.exponent == pytest.approx(2.0, abs=1e-10)
    # 1 % alternating noise moves the slope by well under 0.02 over a factor-8 depth range
    assert fit3.exponent == pytest.approx(3.0, abs=0.02)
    assert fit3.stderr is not None and fit3.stderr < 0.02
    assert fit_power_law([1.0], [2.0]) is None


def test_exponent_evidence_picks_the_closer_closed_form():
    fit = fit_power_law(np.array([1.0, 2.0, 4.0, 8.0]), np.array([1.0, 4.3, 18.1, 80.0]))
    ev = exponent_evidence(fit, {"published": 3.04, "corrected": 2.02})
    assert ev["settles"] == "corrected"
    assert "a^2.1" in ev["finding"] or "a^2.2" in ev["finding"]


def test_thin_ring_shape_reproduces_seed_003_eqs_3_and_4():
    # delta_AB/delta_CD = (2/pi - 1/2) / ((pi^2 - 8)/(4 pi)) = 0.918277 (audit item 5: not an ellipse)
    ratio = (2 / math.pi - 0.5) / ((math.pi ** 2 - 8) / (4 * math.pi))
    assert thin_ring_shape(0.0) == pytest.approx(-1.0, abs=1e-12)
    # 400 even harmonics: the series tail is below 1e-9
    assert thin_ring_shape(math.pi / 2) == pytest.approx(ratio, rel=1e-8)
    assert thin_ring_shape(math.pi) == pytest.approx(-1.0, abs=1e-12)


def test_plan_sweeps_reach_half_the_wall_and_stay_inside_it():
    params = load_params()
    plan = make_plan(params, quick=False)
    wall = params.output_shaft.wall_mm
    depths = [c.crack_depth_mm for c in plan.sweeps["shaft"]]
    assert plan.headline["shaft"].crack_depth_mm == params.output_shaft.crack_depth_mm  # the full run keeps the seed's depth
    quick = make_plan(params, quick=True)
    # --quick: one case per component, at the deepest crack, which must be the full sweep's deepest one
    assert [c.crack_depth_mm for c in quick.headline.values()] == [max(c.crack_depth_mm for c in plan.sweeps[k])
                                                                   for k in quick.headline]
    assert all(not s for s in quick.sweeps.values())
    assert max(depths) == pytest.approx(wall / 2, rel=1e-2)  # 3-digit rounding of the depths
    assert all(d < wall for d in depths)
    assert len(sweep_depths_mm(wall, 4)) == 4
    # the bearing crack's surface length must fit the contact patch: Q = 1.5 gives c = 1.918 a and the
    # patch half-length is 0.5 sqrt(pi) 5 = 4.431 mm, so a < 2.310 mm
    assert bearing_depth_limit_mm(params) == pytest.approx(4.431134627 / 1.917656, rel=1e-5)
    assert max(c.crack_depth_mm for c in plan.sweeps["bearing"]) < bearing_depth_limit_mm(params)
    labels = [c.label for c in plan.all_cases()]
    assert len(labels) == len(set(labels))  # every case writes its own fields/<label>.vtu


def test_plan_asks_only_the_close_up_case_for_its_crack_field_alone_where_its_study_can():
    from strainwave.compare.validate.runner import Case
    from strainwave.registry import STUDIES

    params = load_params()
    plan = make_plan(params, quick=False)
    for cases in plan.sweeps.values():
        can = STUDIES[cases[-1].study].facts().crack_field_alone
        assert [(c.fields, c.crack_field_only) for c in cases] == [(False, False)] * (len(cases) - 1) + [(True, can)]
    assert plan.sweeps["cup"][-1].crack_field_only and not plan.sweeps["shaft"][-1].crack_field_only
    assert not any(c.crack_field_only for c in plan.headline.values())       # the stress pictures need the part
    assert not any(c.crack_field_only for c in make_plan(params, quick=True).all_cases())
    # a crack-only result is never reused for a case that needs the whole part's field
    deep = plan.sweeps["cup"][-1]
    whole = Case(deep.label, deep.study, deep.crack_depth_mm, deep.mesh_size_mm)
    assert deep.payload(params, False, 2) != whole.payload(params, False, 2)
    assert "crack_field_only" not in whole.payload(params, False, 2)       # the other cases keep their keys


def test_schema_rejects_a_check_without_a_tolerance_reason():
    check = not_evaluated("shaft.flexibility", "q", "rad/(N*mm)", "missing").to_dict()
    doc = {"schema_version": 1, "passed": False,
           "summary": {"checks": 13, "passed": 0, "failed": [], "not_evaluated": []},
           "metadata": {"created_utc": "x", "params": {}, "versions": {"strainwave": "0", "code_version": "0",
                                                                        "python": "3"},
                        "settings": {"quick": True, "order": 2}, "cases": [], "timings_s": {}, "total_s": 0.0},
           "checks": [check] * 13, "audit": [], "crack_sweeps": {}, "images": [],
           "files": {"step": [], "fields": [], "report_html": "report.html", "report_md": "report.md"}}
    validate_results(plain(doc))
    broken = copy.deepcopy(doc)
    broken["checks"][0]["tolerance"]["reason"] = ""
    with pytest.raises(jsonschema.ValidationError):
        validate_results(broken)


@pytest.mark.heavy
def test_isolated_case_reports_errors_and_time_limits_instead_of_dying():
    from strainwave.compare.validate.isolated import run_isolated

    params = load_params()
    bad = run_isolated("no-such-study", params, {}, timeout_s=60, progress=lambda m: None)
    assert bad.result is None and "InputError" in bad.error and "no-such-study" in bad.error
    # the ring study takes seconds; a 0.3 s limit must stop it and say so (not hang, not raise)
    slow = run_isolated("ring-compression", params, {"quick": True}, timeout_s=0.3, progress=lambda m: None)
    assert slow.result is None and "timed out after 0.3 s" in slow.error
    assert slow.seconds < 10.0  # terminated promptly; 10 s covers a loaded 2-core machine


def _cup_check(fea_value, gci_abs):
    from types import SimpleNamespace

    from strainwave.analytic.seed000 import seed000_summary
    from strainwave.compare.validate.fea_book import FeaBook
    from strainwave.compare.validate.torsion_checks import cup_flexibility

    params = load_params()
    q = SimpleNamespace(value=fea_value, uncertainty=gci_abs)
    outcome = SimpleNamespace(result=SimpleNamespace(quantities={"flexibility_rad_per_Nmm": q}, meta={}),
                              case=SimpleNamespace(study="cup-torsion"), error=None)
    return cup_flexibility(FeaBook({"cup": outcome}), "cup", seed000_summary(params), params)


def test_cup_check_asserts_the_series_shell_model_plus_the_junctions_not_the_tube():
    from strainwave.analytic.cup_junction import JUNCTION
    # the default cup's section FEA: 4.91555e-10 rad/(N*mm), GCI 1e-14 (benchmarks/cup_calibration.py)
    c = _cup_check(4.91555e-10, 1.0e-14)
    # series model = tube 2.3444 + diaphragm 2.0421 + hub 0.2477 (e-10), G = E/2(1+nu)
    assert c.analytic["series_model"] == pytest.approx(4.6342e-10, rel=1e-4)
    # + the junctions: (13.528 - 296.60 x 0.014) / (G d1^3) = 2.834e-11
    assert c.analytic["corrected"] - c.analytic["series_model"] == pytest.approx(2.834e-11, rel=2e-3)
    assert c.analytic["published"] == pytest.approx(2.3588e-10, rel=1e-4)   # seed 000 table value
    # GCI + the calibration's scatter, no after-the-fact allowance
    assert c.tolerance.relative == pytest.approx(1.0e-14 / 4.91555e-10 + JUNCTION.scatter, rel=1e-9)
    assert c.passed and c.verdict == "corrected"
    assert "diaphragm" in c.note and "calibration" in c.tolerance.reason and "FLAGGED" not in c.note


def test_cup_junction_is_fitted_on_other_cups_and_holds_on_held_out_ones():
    from strainwave.analytic import cup_junction as cj
    fit = cj.junction_fit()
    # the fit cups exclude both shipped gears' cups (d1 160 / 2.24 and d1 100 / 1.4)
    assert not any(c[:2] in ((160.0, 2.24), (100.0, 1.4)) for c in cj.FIT_CUPS)
    # the junction compliance does not depend on the length: equal at L/d1 = 0.8 and 1.3 for one wall ratio
    by_wall = {}
    for (d1, delta, _), (fea, model) in cj.FIT_CUPS.items():
        by_wall.setdefault(delta, []).append((fea - model) * cj.FIT_G_MPa * d1 ** 3)
    assert all(max(v) - min(v) < 1e-3 * max(v) for v in by_wall.values() if len(v) > 1)
    # it falls with the wall ratio, and the straight line leaves less than 0.1 % of lambda_f
    assert fit.slope < 0 and fit.scatter < 1e-3
    # held out (benchmarks/cup_calibration.py): the shipped gears' section FEA within the scatter + 3 GCI
    for toml, fea in ((None, 4.915549e-10), ("second_gear.toml", 2.013408e-09)):
        params = load_params(None if toml is None else Path(strainwave.__file__).parent / "data" / toml)
        from strainwave.compare.validate.torsion_checks import cup_model_flexibility
        model = cup_model_flexibility(params, params.material.implied_shear_modulus_MPa)[0]
        assert abs(fea / model - 1) <= fit.scatter + 3e-4
    # outside the fitted wall ratios the use is flagged
    thick = load_params(None, {"flexspline_cup": {"wall_thickness_mm": 4.0}})
    assert not cj.in_calibrated_range(thick)[0] and "outside" in cj.in_calibrated_range(thick)[1]


def test_cup_section_fea_reproduces_a_fit_cup_of_the_calibration():
    # the calibration table is the section FEA's, not typed in: one fit cup recomputed on quick meshes
    from strainwave.analytic.cup_junction import FIT_CUPS
    from strainwave.fea.cup_axisym import section_flexibility
    d1, delta, length = 120.0, 2.4, 96.0
    params = load_params(None, {"flexspline_cup": {"pitch_diameter_mm": d1, "wall_thickness_mm": delta,
                                                   "length_mm": length, "teeth": 200, "module_mm": d1 / 200}})
    q = section_flexibility(params, quick=True)
    assert q.value == pytest.approx(FIT_CUPS[(d1, delta, length)][0], rel=max(3 * q.uncertainty / q.value, 2e-4))


def test_cup_check_fails_when_the_fea_matches_only_the_bare_tube():
    # an FEA cup as stiff as seed 000's tube (no diaphragm compliance) must fail the series model
    c = _cup_check(2.40e-10, 2.759e-12)
    assert not c.passed
    # the uncalibrated series model itself (the old check's reference with its 6 % allowance) now fails too
    assert not _cup_check(4.6342e-10, 2.759e-12).passed
    # and 1 % above the calibrated model is outside GCI + scatter
    assert not _cup_check(1.01 * 4.9176e-10, 1.0e-14).passed


def test_bearing_radial_compliance_is_information_not_a_check():
    from strainwave.analytic.summary import analytic_summary
    from strainwave.compare.validate.checks import REQUIRED_IDS
    assert "bearing.radial_compliance" not in REQUIRED_IDS
    info = analytic_summary(load_params())["checks"]["bearing.radial_compliance"]
    # the seed's K_G0 = 6.303e4 N/mm is softer than one ball's two Hertz contacts at its own ellipse
    assert info["implied_ball_pairs"] < 1.0 and info["ball_pair_stiffness_N_per_mm"] > 6.303e4


def _shaft_check(fea_value, gci_abs):
    from types import SimpleNamespace

    from strainwave.analytic.seed000 import seed000_summary
    from strainwave.compare.validate.fea_book import FeaBook
    from strainwave.compare.validate.torsion_checks import shaft_flexibility

    params = load_params()
    q = SimpleNamespace(value=fea_value, uncertainty=gci_abs)
    outcome = SimpleNamespace(result=SimpleNamespace(quantities={"flexibility_rad_per_Nmm": q}, meta={}),
                              case=SimpleNamespace(study="shaft-torsion"), error=None)
    return shaft_flexibility(FeaBook({"shaft": outcome}), "shaft", seed000_summary(params), params), params


def test_shaft_check_tests_the_fea_against_the_same_problem_and_reports_the_material_gap_apart():
    import math
    # quick shaft-torsion FEA: 1.26678e-9 rad/(N*mm), GCI 0.0164 % (formal p = 4, Fs = 3; observed p 8.05)
    c, params = _shaft_check(1.2667837e-09, 0.000164 * 1.2667837e-09)
    sh, m = params.output_shaft, params.material
    J = math.pi / 32 * (sh.outer_diameter_mm ** 4 - sh.inner_diameter_mm ** 4)
    assert c.analytic["corrected"] == pytest.approx(sh.length_mm / (m.implied_shear_modulus_MPa * J), rel=1e-12)
    assert c.analytic["corrected_mu"] == pytest.approx(sh.length_mm / (m.shear_modulus_MPa * J), rel=1e-12)
    assert c.tolerance.relative == pytest.approx(0.000164, rel=1e-9)      # the GCI once, no allowance
    assert c.passed and "material gap apart" in c.note and "80000" in c.note
    # the mu form lies the whole material gap (0.96 %) away: outside this tolerance, as a separate line
    assert abs(c.rel_error["corrected_mu"]) > 0.009


def test_shaft_check_fails_on_a_reference_perturbed_by_the_material_gap():
    # an FEA that matched the mu = 80000 form (the old check's 0.96 % allowance absorbed this) now fails
    c, params = _shaft_check(1.2790352e-09, 0.000164 * 1.2790352e-09)
    assert not c.passed


def test_quick_reports_a_check_its_coarse_meshes_do_not_resolve():
    """--quick: a GCI above the named allowances + 1 % is not resolved, never a pass on a ballooned tolerance."""
    from strainwave.compare.validate.checks import quick_resolution

    def check(gci, allowance):
        tol = fea_tolerance(1.0, gci, allowances={"plane stress vs plane strain": allowance} if allowance else {})
        return evaluate(Check("ring.sigma_max", "q", "MPa", 1.0, gci, {"corrected": 1.0}, "corrected", tol))

    resolved = check(0.04, 0.05)
    assert resolved.tolerance.gci == pytest.approx(0.04) and resolved.tolerance.allowances == pytest.approx(0.05)
    assert quick_resolution(resolved) is resolved and resolved.passed
    assert quick_resolution(check(0.005, 0.0)).passed            # below the 1 % floor: resolved
    assert quick_resolution(check(0.105, 0.1024)).passed         # the surface crack: quick meshes are the full's
    coarse = quick_resolution(check(0.276, 0.035))                 # ring.stress_concentration's quick series
    assert not coarse.passed and coarse.verdict == "not evaluated"
    assert coarse.reason_not_evaluated.startswith("not resolved at --quick") and "27.6 %" in coarse.reason_not_evaluated
