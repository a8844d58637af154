"""Catalogue drives: the design rules make each CHA size a drive without per-size tuning, and the models'
stiffness obeys the similitude a linear elastic model must (K ~ G d^3 for geometrically similar units)."""
import math
import warnings

import pytest

from strainwave.analytic import catalogue
from strainwave.analytic.variant import Variant
from strainwave.params import load_params


def _params(row):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return load_params(overrides=catalogue.overrides_for(row))


def test_table_reads_in_newton_metres_per_radian():
    rows = catalogue.read_catalogue()
    assert len(rows) == 21 and {r.size for r in rows} == {14, 17, 20, 25, 32, 40, 50, 58}
    big = next(r for r in rows if r.size == 58 and r.ratio_label == ">50")
    assert (big.K1_Nm_per_rad, big.K3_Nm_per_rad, big.T2_Nm) == (400e3, 710e3, 598.0)
    assert all(r.K1_Nm_per_rad <= r.K2_Nm_per_rad <= r.K3_Nm_per_rad for r in rows)   # the curve stiffens


def test_rules_not_sizes_set_the_geometry():
    rules = catalogue.DesignRules()
    for row in catalogue.read_catalogue():
        cup = _params(row).flexspline_cup
        assert cup.pitch_diameter_mm == pytest.approx(2.54 * row.size)
        assert cup.wall_thickness_mm / cup.pitch_diameter_mm == pytest.approx(rules.wall_over_d1)
        assert cup.teeth == 2 * row.gear_ratio and cup.module_mm * cup.teeth == pytest.approx(cup.pitch_diameter_mm)


def test_model_stiffness_scales_as_the_cube_of_size():
    rows = [r for r in catalogue.read_catalogue() if r.ratio_label == ">50"]
    K = [catalogue.unit_stiffness_Nm_per_rad(_params(r), Variant.CORRECTED) for r in rows]
    assert catalogue.log_slope([r.size for r in rows], K) == pytest.approx(3.0, abs=1e-9)


def test_model_does_not_see_the_ratio():
    """w0 = m = d1/(2 i) cancels i in lambda_H: the catalogue's ratio dependence is tooth engagement."""
    rows = [r for r in catalogue.read_catalogue() if r.size == 25]
    K = {r.ratio_label: catalogue.unit_stiffness_Nm_per_rad(_params(r), Variant.PUBLISHED) for r in rows}
    assert K["30"] == pytest.approx(K[">50"], rel=1e-12) and K["50"] == pytest.approx(K[">50"], rel=1e-12)


def test_fea_flexibility_enters_in_series():
    row = catalogue.read_catalogue()[0]
    params = _params(row)
    K_rigid_cup = catalogue.unit_stiffness_Nm_per_rad(params, Variant.CORRECTED, 1e-30)
    K = catalogue.unit_stiffness_Nm_per_rad(params, Variant.CORRECTED, 2e-8)
    assert 1e-3 / K == pytest.approx(1e-3 / K_rigid_cup + 2e-8, rel=1e-12)


def test_log_slope_recovers_a_power_law():
    sizes = [14.0, 20.0, 32.0, 58.0]
    assert catalogue.log_slope(sizes, [3.7 * s ** 2.4 for s in sizes]) == pytest.approx(2.4, abs=1e-12)
    assert math.isclose(catalogue.log_slope([1.0, 2.0], [5.0, 5.0]), 0.0, abs_tol=1e-15)


def test_report_table_has_every_size_and_the_rules_it_used():
    from strainwave.compare.validate.catalogue_table import catalogue_document, catalogue_rows, slope_line

    doc = catalogue_document()
    assert len(catalogue_rows(doc)) == 21 and doc["rules"]["pitch_diameter_per_size_mm"] == 2.54
    assert set(doc["slopes"]) == {"30", "50", ">50"} and "catalogue" in slope_line(doc)
    assert all(abs(s["corrected"] - 3.0) < 1e-9 for s in doc["slopes"].values())
