"""The report's outputs on their own (no FEA): the design verdict and its exit status, plot legends that show
what they name, the CSV tables, and `strainwave compare` of two runs."""
from __future__ import annotations

import csv
import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

from conftest import STRAINWAVE
from strainwave.compare.validate.design import ComponentFactor, design_verdict
from strainwave.compare.validate.plots import crack_sweep_figure, legend_of_shown
from strainwave.compare.validate.run_diff import diff_runs
from strainwave.compare.validate.tables_csv import write_tables


def _factor(component: str, n: float | None) -> ComponentFactor:
    return ComponentFactor(component, component.title(), n, "sigma_-1 / sigma_vM,peak", None if n is None else 625 / n,
                           625.0, "T = 1e6 N*mm")


def test_design_fails_below_n_and_an_extra_component_is_one_entry(params):
    required = params.ewg_drive.permissible_safety
    ok = design_verdict(params, [_factor("shaft", 19.9), _factor("ring", 1.01 * required)])
    assert ok.passed and ok.headline().startswith("PASS: 2 of 2")
    # just below [n] fails: the check can fail, and says which component and by how much
    low = design_verdict(params, [_factor("shaft", 19.9), _factor("ring", 0.99 * required)])
    assert not low.passed and "below [n]: Ring n = 1.39" in low.headline()
    # a factor another study adds (the wave generator cup's fatigue, say) is one more entry of the list
    extra = design_verdict(params, [_factor("shaft", 19.9), _factor("wg_cup_fatigue", 1.2)])
    assert extra.failing == [extra.factors[1]] and extra.to_dict()["failing"] == ["wg_cup_fatigue"]
    missing = design_verdict(params, [_factor("shaft", 19.9), _factor("cup", None)])
    assert not missing.passed and "not evaluated (counted as failing): Cup" in missing.headline()


def test_a_factor_whose_gci_band_straddles_n_is_undecided_and_not_met(params):
    """The band is the factor's range over the corners of its stresses' GCI bands: Goodman on (amplitude, mean)
    +- their GCIs. A band wholly above [n] passes, wholly below fails; one that straddles [n] is UNDECIDED,
    counted as failing and named with its band; moving the GCI shrinks it back to a PASS."""
    from strainwave.analytic.design_method import Strength, goodman as goodman_line
    from strainwave.compare.validate.design import factor_band
    required = params.ewg_drive.permissible_safety

    def goodman(a, m):
        return goodman_line(a, m, 1.0, Strength("steel", 625.0, 800.0, 1000.0, "test"))
    band = factor_band(goodman, (370.0, 30.0), (100.0, 20.0))
    assert band == pytest.approx((goodman(400.0, 120.0), goodman(340.0, 80.0)))
    assert factor_band(goodman, (370.0, 30.0), (100.0, None)) is None       # no GCI, no band
    n = goodman(370.0, 100.0)
    assert band[0] < required < n          # n alone would pass; its band reaches below [n]

    def factor(b):
        return ComponentFactor("cup_wg", "Cup on the WG", n, "Goodman", 370.0, None, "T", band=b)
    straddles = design_verdict(params, [_factor("shaft", 19.9), factor(band)])
    assert straddles.factors[1].verdict(required) == "UNDECIDED" and not straddles.passed
    assert f"undecided, [n] within the band the FEA's GCIs give (counted as failing): Cup on the WG n = {n:.3g}" \
        in straddles.headline()
    assert straddles.to_dict()["factors"][1]["band"] == list(band)
    tight = factor_band(goodman, (370.0, 3.0), (100.0, 2.0))
    assert design_verdict(params, [factor(tight)]).passed
    assert ComponentFactor("x", "X", 1.0, "d", 1.0, None, "T", band=(0.9, 1.2)).verdict(required) == "FAIL"


class _Outcome:
    def __init__(self, passed: bool, design_passed: bool):
        self.passed, self.design_passed, self.design = passed, design_passed, None
        self.out_dir, self.timings_s, self.checks = Path("."), {}, ()

    def summary(self) -> str:
        return "fake run"


@pytest.mark.parametrize("passed, design, require, status", [
    (True, False, False, 0), (True, False, True, 3), (True, True, True, 0), (False, False, True, 1)])
def test_exit_status_is_the_validation_unless_the_design_is_required(monkeypatch, tmp_path, passed, design, require,
                                                                     status):
    import strainwave.compare.validate.pipeline as pipeline
    from strainwave.cli import main

    monkeypatch.setattr(pipeline, "run_validate", lambda *a, **k: _Outcome(passed, design))
    argv = ["-q", "validate", "--quick", "--out", str(tmp_path / "out")] + (["--require-design"] if require else [])
    assert main(argv) == status


@pytest.mark.parametrize("flags, step", [(["--quick"], None), (["--quick", "--step"], True), ([], None)])
def test_validate_passes_the_step_choice_on(monkeypatch, tmp_path, flags, step):
    import strainwave.compare.validate.pipeline as pipeline
    from strainwave.cli import main

    seen = {}
    monkeypatch.setattr(pipeline, "run_validate", lambda *a, **k: seen.update(k) or _Outcome(True, True))
    assert main(["-q", "validate", "--out", str(tmp_path / "out")] + flags) == 0
    assert seen["step"] is step and seen["quick"] == ("--quick" in flags)


def test_a_run_without_step_starts_no_export_and_says_why(tmp_path):
    from strainwave.cache import ResultCache
    from strainwave.compare.validate.report_text import no_step_line, run_line
    from strainwave.compare.validate.step_export import StepJob
    from strainwave.params import load_params

    job = StepJob(load_params(), tmp_path / "step", ResultCache(tmp_path / "cache"), lambda m: None,
                  preview_dir=tmp_path / "images", parts=())
    assert job.process is None and job.result() == ([], 0.0) and not (tmp_path / "step").exists()
    meta = {"settings": {"quick": True, "order": 2, "step": False}, "cases": [], "total_s": 1.0,
            "created_utc": "now", "versions": {"strainwave": "x", "code_version": "y"}}
    assert "no STEP export" in run_line({"metadata": meta}) and "--step" in no_step_line({"metadata": meta})
    meta["settings"]["step"] = True   # the export ran and every part failed: another reason, not "skipped"
    assert "no STEP" not in run_line({"metadata": meta}) and "could be built" in no_step_line({"metadata": meta})


def test_sweep_legend_lists_only_what_is_drawn():
    curves = {"published": (np.array([1.0]), np.array([2e-8])), "corrected": (np.array([1.0]), np.array([1e-9]))}
    # one depth (a --quick sweep) whose FEA value is <= 0: nothing of the FEA can be drawn on a log axis
    fig = crack_sweep_figure(title="t", unit="mm/N", depths_mm=[1.0], fea=[-1e-17], fea_uncertainty=[1e-16],
                             curves=curves)
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert labels == ["published closed form", "corrected closed form"]
    assert any("FEA <= 0" in t.get_text() for t in fig.axes[0].texts)
    fig = crack_sweep_figure(title="t", unit="mm/N", depths_mm=[1.0, 2.0], fea=[1e-9, 3e-9],
                             fea_uncertainty=[1e-10, 1e-10], curves=curves)
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    assert len(labels) == 3 and any(label.startswith("FEA (GCI bars)") for label in labels)


def _inside_the_picture(fig) -> bool:
    """Whether every drawn label, title, tick label and legend of ``fig`` lies inside the figure (none clipped)."""
    renderer = fig.canvas.get_renderer()
    box = fig.bbox
    parts = [ax.get_tightbbox(renderer) for ax in fig.axes]
    parts += [fig._suptitle.get_window_extent(renderer)] if fig._suptitle is not None else []
    return all(b.x0 >= box.x0 - 0.5 and b.y0 >= box.y0 - 0.5 and b.x1 <= box.x1 + 0.5 and b.y1 <= box.y1 + 0.5
               for b in parts)


def test_plots_keep_every_label_and_the_legend_inside_the_picture(tmp_path):
    """The plots are drawn once at a fixed size (constrained layout): long closed-form names, a two-line title, a
    legend of six entries below the axes all fit; the same sweep figure without its layout engine would clip the
    legend, so the check sees a clipped label."""
    from strainwave.compare.validate.plots import _save, convergence_figure

    conv = convergence_figure(title="ring.delta_cd: delta_CD, a long quantity name", unit="mm", h_mm=[1.6, 0.8, 0.4],
                              values=[1.051e-3, 1.012e-3, 1.003e-3], extrapolated=1.0e-3, gci_fine=0.004,
                              observed_order=2.0, flags=("non-monotone", "p far from formal"),
                              analytic={"published": 1.1e-3, "corrected": 1.0e-3, "hollow_tube_strip": 0.9e-3})
    curves = {name: (np.array([0.5, 1.0, 2.0]), np.array([1e-9, 3e-9, 9e-9]) * (k + 1))
              for k, name in enumerate(("published", "corrected", "hollow_tube_strip", "solid_bar_a2", "fifth"))}
    sweep = crack_sweep_figure(title="output shaft: crack compliance vs depth", unit="rad/(N*mm)",
                               depths_mm=[0.5, 1.0, 2.0], fea=[1.1e-9, 3.2e-9, 9.5e-9],
                               fea_uncertainty=[1e-10, 2e-10, 4e-10], curves=curves)
    for name, fig in (("conv", conv), ("sweep", sweep)):
        png = _save(fig, tmp_path / f"{name}.png")
        assert png.stat().st_size > 0 and _inside_the_picture(fig), name
    assert len(sweep.axes[0].get_legend().get_texts()) == 6
    sweep.set_layout_engine("none")
    sweep.axes[0].set_position([0.125, 0.11, 0.775, 0.77])   # matplotlib's default margins: the legend runs off
    _save(sweep, tmp_path / "clipped.png")
    assert not _inside_the_picture(sweep)


def test_legend_drops_a_line_that_has_no_finite_point():
    from matplotlib.figure import Figure

    ax = Figure().add_subplot(1, 1, 1)
    ax.plot([1, 2], [1, 2], "-", label="drawn")
    ax.plot([1, 2], [np.nan, np.nan], "x", label="never drawn")
    ax.plot([1], [3], "-", label="one point, no marker")
    assert legend_of_shown(ax) == ["drawn"]


def _doc() -> dict:
    check = {"id": "shaft.flexibility", "component": "shaft", "quantity": "lambda, with, commas", "unit": "rad/(N*mm)",
             "fea": 1.2667837066886318e-09, "fea_uncertainty": 1.8e-14,
             "analytic": {"published": 1.04e-09, "corrected": 1.279e-09},
             "rel_error": {"published": 0.2166, "corrected": -0.0096}, "asserts": "corrected", "relation": "equal",
             "tolerance": {"relative": 0.0097, "reason": "3 x GCI + 0.962 %"}, "verdict": "corrected", "passed": True,
             "reason_not_evaluated": ""}
    gci = {"case": "shaft", "quantity": "flexibility_rad_per_Nmm", "unit": "rad/(N*mm)", "h_mm": [1.0, 1.4, 1.96],
           "values": [1.0, 1.1, 1.3], "r21": 1.4, "r32": 1.4, "observed_order": 2.0, "formal_order": 4.0,
           "extrapolated": 0.9, "gci_fine": 0.01, "asymptotic": False, "flags": ["p < 1", "non-monotone"]}
    stress = {"load": {"name": "output torque T", "rated": 1e6, "unit": "N*mm", "solved": 1e3, "scale": 1e3},
              "peak_von_mises_MPa": 31.3, "peak_location_mm": [35.0, 0.0, 0.0], "peak_on": ["fixed"],
              "peak_displacement_mm": 0.044, "fatigue_limit_MPa": 625.0, "safety_factor": 625 / 31.3,
              "field_file": "shaft.vtu", "note": "material-only", "tip_radius_mm": None, "tip_peak_von_mises_MPa": None}
    design = {"factors": [{"component": "shaft", "required": 1.4, "passed": True, "safety_factor": 625 / 31.3}]}
    return {"checks": [check], "gci_table": [gci], "stress_at_rated": {"shaft": stress}, "design": design}


def test_csv_tables_carry_the_document_numbers_at_full_precision(tmp_path):
    doc = _doc()
    write_tables(tmp_path, doc)
    (check,) = list(csv.DictReader((tmp_path / "checks.csv").open()))
    assert float(check["fea"]) == doc["checks"][0]["fea"] and check["quantity"] == "lambda, with, commas"
    assert check["passed"] == "True" and float(check["tolerance_relative"]) == 0.0097
    (gci,) = list(csv.DictReader((tmp_path / "gci.csv").open()))
    assert [float(gci[f"h{k}_mm"]) for k in (1, 2, 3)] == [1.0, 1.4, 1.96] and gci["flags"] == "p < 1; non-monotone"
    (stress,) = list(csv.DictReader((tmp_path / "stress.csv").open()))
    assert float(stress["safety_factor"]) == 625 / 31.3 and stress["design_passed"] == "True"
    assert stress["tip_peak_von_mises_MPa"] == ""


def test_compare_lists_changed_checks_side_by_side(tmp_path):
    a = _doc()
    b = json.loads(json.dumps(a))
    assert diff_runs(a, b).changes == ()
    b["checks"][0]["fea"] *= 1 + 1e-6
    b["checks"][0]["verdict"], b["checks"][0]["passed"] = "neither", False
    b["checks"].append({**a["checks"][0], "id": "cup.flexibility"})
    diff = diff_runs(a, b)
    assert [(c.check_id, c.status, c.fields) for c in diff.changes] == [
        ("shaft.flexibility", "changed", ("fea", "verdict", "passed")),
        ("cup.flexibility", "added", ("fea", "fea_uncertainty", "tolerance", "verdict", "passed"))]
    for name, doc in (("a", a), ("b", b)):
        (tmp_path / name).mkdir()
        (tmp_path / name / "results.json").write_text(json.dumps(doc))
    proc = subprocess.run([STRAINWAVE, "compare", str(tmp_path / "a"), str(tmp_path / "b")], capture_output=True,
                          text=True, timeout=60)
    assert proc.returncode == 0
    row = next(line for line in proc.stdout.splitlines() if line.startswith("shaft.flexibility"))
    assert row.split()[1:] == ["fea", "1.26678e-09", "1.26678e-09", "+0.0001", "%"]
    assert "corrected" in proc.stdout and "neither" in proc.stdout and "added: fea" in proc.stdout
    bad = subprocess.run([STRAINWAVE, "compare", str(tmp_path / "a"), str(tmp_path / "nowhere")], capture_output=True,
                         text=True, timeout=60)
    assert bad.returncode == 2 and bad.stderr.startswith("error: RUN_B = ") and "Traceback" not in bad.stderr
