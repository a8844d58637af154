"""Issue 52: a report says what it ran (gear, parameter file, command line, the parameters that differ from the
embedded default), its designer headline is a table, and `compare` warns when two runs measure different things."""
from __future__ import annotations

import json
import subprocess

import pytest

from conftest import STRAINWAVE
from strainwave.compare.validate.designer_table import designer_table
from strainwave.compare.validate.report_html import render_html
from strainwave.compare.validate.report_md import render_markdown
from strainwave.compare.validate.run_diff import diff_runs
from strainwave.compare.validate.run_record import DEFAULT_GEAR, params_diff, run_record
from strainwave.params import load_params


def _minimal_doc(params, params_file=None) -> dict:
    """The smallest results document both report writers accept."""
    meta = {"settings": {"quick": True, "order": 2, "step": False}, "cases": [], "total_s": 1.0, "timings_s": {},
            "created_utc": "2026-12-07T00:00:00Z", "versions": {"strainwave": "x", "code_version": "y"},
            "params": params.to_dict(), "run": run_record(params, params_file, ["strainwave", "validate", "--quick"])}
    return {"passed": True, "summary": {"checks": 0, "passed": 0, "failed": [], "not_evaluated": []},
            "metadata": meta, "checks": [], "audit": [], "crack_sweeps": {}, "images": [], "gci_table": [],
            "files": {"step": [], "fields": [], "tables": []}}


def test_params_diff_lists_exactly_the_keys_that_differ():
    default = load_params().to_dict()
    mine = load_params(overrides={"output_shaft": {"length_mm": 60.0}}).to_dict()
    assert params_diff(mine, default) == [{"key": "output_shaft.length_mm", "value": 60.0,
                                           "default": default["output_shaft"]["length_mm"]}]
    assert params_diff(default, default) == []


def test_the_report_names_the_gear_its_file_and_the_parameters_changed(tmp_path):
    second = "strainwave/data/second_gear.toml"
    params = load_params(second)
    doc = _minimal_doc(params, second)
    md, html = render_markdown(doc), render_html(doc)
    assert md.splitlines()[0] == "# strainwave validation report: second_gear"
    assert "<title>strainwave validation report: second_gear</title>" in html
    assert "second_gear" in md and second in md and "strainwave validate --quick" in md
    # the parameter echo: every key the file sets differently, with the default beside it
    changed = {d["key"] for d in doc["metadata"]["run"]["changed_from_default"]}
    assert {"flexspline_cup.teeth", "output_shaft.inner_diameter_mm"} <= changed
    assert "| flexspline_cup.teeth | 160 |" in md and 'id="params-diff"' in html
    # the embedded default names itself and has no parameter table
    plain = _minimal_doc(load_params())
    assert render_markdown(plain).splitlines()[0] == f"# strainwave validation report: {DEFAULT_GEAR}"
    assert "differ from the embedded default" not in render_markdown(plain).split("Gear:")[0]


def test_designer_headline_is_a_short_table_with_catalogue_units():
    from strainwave.analytic.summary import analytic_summary
    table = designer_table(analytic_summary(load_params()))
    assert table["columns"] == ["question", "answer", "basis"]
    assert 4 <= len(table["rows"]) <= 8 and all(len(r) == 3 for r in table["rows"])
    stiffness = next(r for r in table["rows"] if r[0].startswith("torsional stiffness"))
    k_nmm, k_nm = (float(stiffness[1].split()[0]), float(stiffness[1].split("(")[1].split()[0]))
    assert k_nm == pytest.approx(k_nmm / 1e3, rel=1e-3) and "N m/rad" in stiffness[1]
    doc = _minimal_doc(load_params())
    doc["designer_table"] = table
    assert 'id="designer-table"' in render_html(doc) and "| question | answer | basis |" in render_markdown(doc)


def _run(quick: bool, **params_over) -> dict:
    params = load_params(overrides=params_over or None)
    doc = _minimal_doc(params)
    doc["metadata"]["settings"]["quick"] = quick
    doc["metadata"]["settings"]["sweep_depths_mm"] = {"shaft": [0.5] if quick else [0.5, 1.0, 2.0]}
    doc["design"] = {"passed": quick, "headline": "PASS: 5 of 5" if quick else "FAIL: 4 of 5"}
    doc["checks"] = [{"id": "shaft.crack_compliance", "fea": 6.36e-11 if quick else 1.37e-14, "fea_uncertainty": None,
                      "tolerance": {"relative": 0.1}, "verdict": "corrected", "passed": True}]
    return doc


def test_compare_warns_when_the_modes_differ_and_shows_percent_and_verdicts():
    diff = diff_runs(_run(False), _run(True))
    assert len(diff.warnings) == 1 and "--quick" in diff.warnings[0] and "full" in diff.warnings[0]
    assert diff.designs == ("FAIL: 4 of 5", "PASS: 5 of 5")
    text = diff.summary()
    assert text.splitlines()[0].startswith("warning: A is a full run and B a --quick run")
    row = next(line for line in text.splitlines() if line.startswith("shaft.crack_compliance"))
    assert row.split()[-2:] == [f"{100 * (6.36e-11 - 1.37e-14) / 1.37e-14:+.3g}", "%"]
    # same mode, same parameters: nothing to warn about
    assert diff_runs(_run(True), _run(True)).warnings == ()


def test_compare_shows_the_parameter_diff_and_warns_of_another_gear(tmp_path):
    a, b = _run(True), _run(True, output_shaft={"crack_depth_mm": 1.0})
    diff = diff_runs(a, b)
    assert [p["key"] for p in diff.params] == ["output_shaft.crack_depth_mm"] and diff.params[0]["b"] == 1.0
    assert any("differ in 1 parameter(s) (output_shaft.crack_depth_mm)" in w for w in diff.warnings)
    for name, doc in (("a", a), ("b", _run(False))):
        (tmp_path / name).mkdir()
        (tmp_path / name / "results.json").write_text(json.dumps(doc))
    proc = subprocess.run([STRAINWAVE, "compare", str(tmp_path / "a"), str(tmp_path / "b"), "--json", "-"],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout)
    assert out["warnings"] and out["design"] == {"a": "PASS: 5 of 5", "b": "FAIL: 4 of 5"}
    assert out["changes"][0]["percent_change"]["fea"] == pytest.approx(100 * (1.37e-14 - 6.36e-11) / 6.36e-11)
