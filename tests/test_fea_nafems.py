"""NAFEMS LE1 and LE10 (TNSB Rev. 3) on coarse meshes through the solver core and its nodal-averaging recovery.

Tolerance, fixed before the run (``fea/nafems.coarse_tolerance``): min(5 %, 3 GCI + the target's rounding).
5 % is the benchmark's coarse-mesh practice: the 6-node triangle on the NAFEMS coarse LE1 mesh lands 4 % below
the target (Abaqus Benchmarks Manual 4.2.1). The fine meshes (1 % with their GCI) run in ``make bench``.
"""
from __future__ import annotations

import dataclasses

import pytest

from strainwave.fea import nafems
from strainwave.fea.convergence import grid_convergence


@pytest.fixture(scope="module")
def coarse():
    return {b: nafems.run(nafems.BENCHMARKS[b], nafems.COARSE_SIZES_MM[b], "coarse") for b in ("LE1", "LE10")}


@pytest.mark.parametrize("bench", ["LE1", "LE10"])
def test_coarse_nafems_case_meets_its_target(coarse, bench):
    r = coarse[bench]
    assert r.tolerance_rel == pytest.approx(min(0.05, 3 * r.convergence.gci_fine + r.bench.rounding_rel))
    assert abs(r.error_rel) <= r.tolerance_rel, r.to_dict()
    assert r.passed
    # the point is a mesh node (the recovery reads nodal averages there, no interpolation)
    assert all(p.node_offset_mm == 0.0 for p in r.points)
    assert r.points[0].dofs > r.points[2].dofs


@pytest.mark.parametrize("bench,shift", [("LE1", 1.08), ("LE10", 1.08), ("LE1", 0.93)])
def test_the_check_fails_on_a_perturbed_target(coarse, bench, shift):
    r = coarse[bench]
    moved = dataclasses.replace(r, bench=dataclasses.replace(r.bench, target_MPa=r.bench.target_MPa * shift))
    assert not moved.passed


def test_the_tolerance_is_recomputed_from_its_rule():
    conv = grid_convergence((1.0, 1.4, 1.96), (92.0, 91.9, 91.7), formal_order=2.0)
    # 3 GCI + rounding of 92.7 (half a unit of its last digit, 0.05 / 92.7) below the 5 % ceiling
    assert nafems.coarse_tolerance(nafems.LE1, conv) == pytest.approx(3 * conv.gci_fine + 0.05 / 92.7)
    wide = grid_convergence((1.0, 1.4, 1.96), (92.0, 88.0, 80.0), formal_order=2.0)
    assert nafems.coarse_tolerance(nafems.LE1, wide) == 0.05
    assert nafems.LE10.rounding_rel == pytest.approx(0.005 / 5.38)


def test_fine_acceptance_is_the_whole_gci_band_within_one_percent():
    assert nafems.fine_passes(-0.004, 0.005)
    assert not nafems.fine_passes(-0.004, 0.007)
    assert not nafems.fine_passes(0.011, 0.0)


def test_the_result_names_its_recovery_and_its_numbers(coarse):
    d = coarse["LE1"].to_dict()
    assert d["recovery"].startswith("nodal averaging") and d["target_MPa"] == 92.7
    assert len(d["meshes"]) == 3 and d["dofs"] == d["meshes"][0]["dofs"]


def test_the_report_appendix_lists_the_coarse_runs_and_quotes_the_bench_record(coarse, tmp_path, monkeypatch):
    import json

    from strainwave.compare.validate import report_text as rt
    from strainwave.compare.validate.nafems_appendix import nafems_appendix

    monkeypatch.setattr(nafems, "run_all", lambda level, progress=None: list(coarse.values()))
    out = tmp_path / "reports" / "validate"
    first = nafems_appendix(out)
    assert [c["id"] for c in first["cases"]] == ["LE1", "LE10"]
    assert any("LE11" in n and "thermal strain" in n for n in first["notes"])
    assert any("make bench" in n and "not run here" in n for n in first["notes"])
    record = tmp_path / "reports" / "bench" / "nafems.json"
    fine = dataclasses.replace(coarse["LE1"], level="fine", tolerance_rel=0.01)
    record.parent.mkdir(parents=True)
    record.write_text(json.dumps(nafems.results_document([fine])))
    second = nafems_appendix(out)
    assert [c["level"] for c in second["cases"]] == ["coarse", "coarse", "fine"]
    row = rt.nafems_row(second["cases"][2])
    assert row[0].startswith("LE1") and row[3] == "92.7" and row[-1] in ("PASS", "MISS")
    assert row[-2] == "|error| + GCI <= 1 %"
