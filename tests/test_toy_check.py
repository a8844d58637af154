"""One check list: a toy check, declared in this one file plus one line added to ``check_list.CHECKS`` (the
``toy_check`` fixture), is built, ordered, reported, written to the JSON and stood beside its FEA quantity in a
sweep; and the sweep's closed form for the shaft crack is validate's, at the point's own bore.

The toy check compares the toy strip of tests/test_toy_study.py (its one registry line is that file's fixture)
with Timoshenko's beam at the force the FEA applied.
"""
from __future__ import annotations

import json
import math
from dataclasses import replace

import jsonschema
import pytest

from strainwave.analytic.reference import Reference
from strainwave.compare.validate import check_list
from strainwave.compare.validate.check_list import At, CheckSpec
from strainwave.compare.validate.checks import Check, evaluate, fea_tolerance, not_evaluated
from test_toy_study import FORCE_N, TIP, TOY, strip, timoshenko_tip_mm, toy_study  # noqa: F401 - the fixture

TOY_CHECK = "toy.tip_deflection"


def toy_reference(params, at: At) -> Reference | None:
    if at.force_N is None:
        return None
    tip = timoshenko_tip_mm(params, at.force_N)
    return Reference(tip["published"], tip["corrected"], "mm", "Timoshenko beam, kappa = 5/6")


def toy_tip_check(ctx) -> Check:
    """The strip's tip deflection against Timoshenko's beam, within 3 x GCI plus the clamped root's restraint of
    the section's warping, which the beam leaves out: an O(t/L) allowance, fixed before any solve."""
    quantity, label = "toy strip tip deflection under P", ctx.label(TOY)
    q, why = ctx.book.quantity(label, TIP) if label else (None, "no toy case in the plan")
    if q is None:
        return not_evaluated(TOY_CHECK, quantity, "mm", why)
    L, t = strip(ctx.params)
    tol = fea_tolerance(q.value, q.uncertainty, allowances={f"clamped root, O(t/L) = {t / L:.3g}": t / L})
    reference = toy_reference(ctx.params, At(force_N=ctx.book.applied_force_N(label)))
    return evaluate(Check(TOY_CHECK, quantity, "mm", q.value, q.uncertainty, reference.variants(), "corrected", tol,
                          note="published: Euler-Bernoulli; corrected: + the shear term", sources={"fea": f"FEA {label}"}))


SPEC = CheckSpec(TOY_CHECK, "toy", toy_tip_check, toy_reference, "3 x GCI + the clamped root (t/L)", ((TOY, TIP),))


@pytest.fixture
def toy_check(monkeypatch, toy_study):
    """The one line of the check list."""
    monkeypatch.setattr(check_list, "CHECKS", check_list.CHECKS + (SPEC,))
    return SPEC


@pytest.fixture(scope="module")
def params():
    from strainwave.params import load_params
    return load_params()


def _toy_book(params):
    from strainwave.compare.validate.fea_book import FeaBook
    from strainwave.compare.validate.plan import make_plan
    from strainwave.compare.validate.runner import CaseOutcome
    from strainwave.fea.studies import run_study

    plan = make_plan(params, quick=True)
    case = plan.case_of(TOY)
    return plan, FeaBook({case.label: CaseOutcome(case, run_study(TOY, params, quick=True), 0.0, False)})


def test_a_toy_check_is_built_reported_and_written(toy_check, params):
    from strainwave.analytic.summary import analytic_summary
    from strainwave.compare.validate import report_text as rt
    from strainwave.compare.validate.check_set import build_checks
    from strainwave.compare.validate.results import plain, validate_results

    plan, book = _toy_book(params)
    checks = build_checks(book, plan, analytic_summary(params), params).checks
    assert [c.id for c in checks] == [s.id for s in check_list.CHECKS]          # the list's order
    toy = checks[-1]
    assert toy.id == TOY_CHECK and toy.passed, toy.rel_error
    fea = book.quantity(plan.label_of(TOY), TIP)[0].value
    assert toy.fea == fea and toy.analytic == timoshenko_tip_mm(params, FORCE_N)
    assert ("toy", "toy") in rt.components()                                      # its report section
    row = rt.check_row(toy.to_dict())
    assert row[0] == TOY_CHECK and rt.num(fea) in row[2] and row[-1] == "PASS"
    # the JSON: its component is one the schema accepts because the check list has it
    doc = {"schema_version": 1, "passed": False,
           "summary": {"checks": len(checks), "passed": 0, "failed": [], "not_evaluated": []},
           "metadata": {"created_utc": "x", "params": {}, "versions": {"strainwave": "0", "code_version": "0",
                                                                        "python": "3"},
                        "settings": {"quick": True, "order": 2}, "cases": [], "timings_s": {}, "total_s": 0.0},
           "checks": [c.to_dict() for c in checks], "audit": [], "crack_sweeps": {}, "images": [],
           "files": {"step": [], "fields": [], "report_html": "report.html", "report_md": "report.md"}}
    validate_results(plain(doc))
    written = json.loads(json.dumps(plain(doc)))["checks"][-1]
    assert written["id"] == TOY_CHECK and written["fea"] == fea and written["component"] == "toy"
    # a perturbed reference fails the same check
    off = evaluate(replace(toy, analytic={k: 1.1 * v for k, v in toy.analytic.items()}))
    assert not off.passed and toy.tolerance.relative < 0.1


def test_the_schema_refuses_a_component_the_check_list_lacks(toy_study, params):
    from strainwave.compare.validate.results import load_schema, plain
    one_check = {"$defs": load_schema()["$defs"], "$ref": "#/$defs/check"}
    jsonschema.validate(plain(not_evaluated("shaft.flexibility", "q", "mm", "missing").to_dict()), one_check)
    with pytest.raises(jsonschema.ValidationError, match="toy"):
        jsonschema.validate(plain(not_evaluated(TOY_CHECK, "q", "mm", "missing").to_dict()), one_check)


def test_a_toy_sweep_point_stands_the_check_reference_beside_its_fea(toy_check, params, tmp_path):
    from strainwave.compare.sweep.task import PointSpec, point_key, run_point

    spec = PointSpec(TOY, (("output_shaft.inner_diameter_mm", 50.0),), params.to_dict(), quick=True)   # wall 10 mm
    record = run_point(spec, point_key(spec, None), str(tmp_path))
    assert record["status"] == "ok", record.get("error")
    beside = record["analytic"][TIP]
    thinner = params.with_value("output_shaft.inner_diameter_mm", 50.0)
    assert beside["key"] == f"checks.{TOY_CHECK}"
    assert beside["corrected"] == pytest.approx(timoshenko_tip_mm(thinner, FORCE_N)["corrected"], rel=1e-12)
    assert abs(record["fea"][TIP]["value"] / beside["corrected"] - 1.0) < 0.02


@pytest.mark.parametrize("bore_mm", [40.0, 48.0])
def test_the_sweep_shaft_crack_reference_is_validates(params, bore_mm):
    """At each bore the sweep's corrected closed form for the shaft crack is the one validate asserts (the
    thick-tube form of analytic/tube_crack.py, G = E/2(1+nu)), not the solid-bar K_III that ignores the bore."""
    from strainwave.analytic import tube_crack
    from strainwave.analytic.summary import analytic_summary
    from strainwave.compare.sweep.task import analytic_beside
    from strainwave.compare.validate.check_list import check_spec

    a, name = 3.0, "delta_flexibility_rad_per_Nmm"
    point = params.with_value("output_shaft.inner_diameter_mm", bore_mm).with_value("output_shaft.crack_depth_mm", a)
    sweep = analytic_beside("shaft-torsion", point, [name], crack_depth_mm=a)[name]
    validate = check_spec("shaft.crack_compliance").reference(point, At(crack_depth_mm=a))
    assert sweep["key"] == "checks.shaft.crack_compliance" and sweep["unit"] == validate.unit
    assert sweep["corrected"] == validate.corrected and sweep["published"] == validate.published
    s, m = point.output_shaft, point.material
    assert validate.corrected == pytest.approx(tube_crack.thick_tube_flexibility(
        s.outer_diameter_mm / 2, bore_mm / 2, a, m.youngs_modulus_MPa / (2 * (1 + m.poisson_ratio))), rel=1e-12)
    solid = analytic_summary(point)["checks"]["shaft.crack_compliance"]["corrected"]
    assert not math.isclose(sweep["corrected"], solid, rel_tol=0.05)     # the entry the sweep no longer uses
