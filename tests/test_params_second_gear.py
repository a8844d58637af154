"""The second shipped parameter file: another gear size, every model coefficient unchanged.

`make validate` runs the full validation on it; here only what is cheap: it loads, it differs from the
default where it says, and the fitted tooth-factor model meets it as a held-out rim.
"""
import math
import warnings
from importlib import resources

import pytest

from strainwave.analytic import tooth_factors
from strainwave.analytic.summary import analytic_summary
from strainwave.params import load_params


@pytest.fixture(scope="module")
def second():
    path = resources.files("strainwave").joinpath("data/second_gear.toml")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return load_params(path), load_params()


def test_second_gear_is_another_size(second):
    p, d = second
    assert p.ewg_drive.module_mm != d.ewg_drive.module_mm
    assert p.ewg_drive.flexspline_teeth != d.ewg_drive.flexspline_teeth
    assert p.ewg_drive.rim_thickness_ratio != d.ewg_drive.rim_thickness_ratio
    assert p.output_shaft.inner_diameter_mm / p.output_shaft.outer_diameter_mm != pytest.approx(
        d.output_shaft.inner_diameter_mm / d.output_shaft.outer_diameter_mm)
    # its rated torque follows its size (torque capacity ~ d1^3 at equal shear), not the 160 mm gear's
    ratio = (p.flexspline_cup.pitch_diameter_mm / d.flexspline_cup.pitch_diameter_mm) ** 3
    assert p.gear.rated_output_torque_Nmm == pytest.approx(ratio * d.gear.rated_output_torque_Nmm, rel=0.05)
    # no coefficient of a model is a parameter: the fitted ones live in analytic/ and are the same objects
    assert p.ewg_drive.root_fillet_coefficient == tooth_factors.MODEL_ROOT_FILLET_COEFFICIENT


def test_second_gear_ring_is_held_out_and_every_reference_is_finite(second):
    p, _ = second
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        s = analytic_summary(p)
    tf = s["seed003"]["tooth_factors"]
    assert tf["held_out"] and tf["h_over_delta"] == pytest.approx(2.35 / 1.2)
    for cid, entry in s["checks"].items():
        assert math.isfinite(entry["corrected"]), cid
    zm = s["seed003"]["tooth_number_min_with_fea_factors"]
    assert zm["dZ2"]["Z_R_min"] > zm["dZ2"]["seed_constant_Z_R_min"]
