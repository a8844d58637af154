"""The design verdict's factors come from design_fea on the FEA's cycles (issue 49): the cup's tooth root on the
wave generator, the bearing's rings; a case that did not run is NOT EVALUATED and fails the design."""
import warnings
from types import SimpleNamespace

import pytest

from strainwave.compare.validate.design import DesignVerdict
from strainwave.compare.validate.design_fea import design_factors_from_fea
from strainwave.params import load_params

RECORD = {"case": "wg", "fatigue": {"amplitude_MPa": 164.8, "mean_MPa": 59.1, "amplitude_gci_MPa": 2.0,
                                    "mean_gci_MPa": 1.0}}


@pytest.fixture(scope="module")
def params():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return load_params()


def _book(q: dict):
    from strainwave.compare.validate.fea_book import FeaBook
    quantities = {k: SimpleNamespace(value=v, uncertainty=1.0) for k, v in q.items()}
    return FeaBook({"B": SimpleNamespace(result=SimpleNamespace(quantities=quantities), error=None,
                                         case=SimpleNamespace(study="wg-bearing"))})


def test_cup_tooth_root_takes_the_feas_cycle_and_a_band(params):
    factors = design_factors_from_fea(params, _book({}), {}, {}, {}, (), RECORD)
    cup = next(f for f in factors if f.component == "cup_tooth_root")
    fat = cup.fatigue
    assert "FEA wg" in fat["amplitude_source"] and cup.band is not None and cup.band[0] <= cup.safety_factor <= cup.band[1]
    # the FEA's 164.8 MPa swing times K_delta plus half the mesh root stress is the amplitude the row states
    assert fat["amplitude_MPa"] > 164.8


def test_the_tooth_mesh_fes_flank_load_is_shown_beside_not_in_the_verdict(params):
    """issue 49 item 3: the tooth-mesh study's peak flank load gives the factor it would imply, recomputed here from
    its stated inputs (Goodman, K_sigma on the amplitude); the verdict keeps the closed-form mesh load."""
    import math
    from strainwave.analytic.design_method import flexspline_steel, goodman
    plain = next(f for f in design_factors_from_fea(params, _book({}), {}, {}, {}, (), RECORD)
                 if f.component == "cup_tooth_root")
    book = _book({"peak_tooth_load_N": 2467.0})
    cup = next(f for f in design_factors_from_fea(params, book, {"tooth-mesh": "B"}, {}, {}, (), RECORD)
               if f.component == "cup_tooth_root")
    assert cup.safety_factor == plain.safety_factor          # the verdict is unchanged
    fe = cup.fatigue["extra"]["fe_mesh_load"]
    c = cup.fatigue["extra"]["closed_form"]
    m, b = params.flexspline_cup.module_mm, params.circular_spline.face_width_mm
    root = 6.0 * 2467.0 * 1.35 * m / (b * (0.5 * math.pi * m) ** 2)
    amp = c["K_delta"] * 164.8 + 0.5 * root
    mean = math.hypot(c["K_delta"] * 59.1 + 0.5 * root, math.sqrt(3.0) * c["shear_MPa"])
    assert fe["n"] == pytest.approx(goodman(amp, mean, c["K_sigma"], flexspline_steel(params)), rel=1e-12)
    assert fe["peak_force_N"] > 10.0 * fe["closed_form_peak_force_N"] and fe["n"] < plain.safety_factor


def test_a_missing_case_is_not_evaluated_and_fails_the_design(params):
    factors = design_factors_from_fea(params, _book({}), {}, {}, {}, (), {})
    missing = {f.component for f in factors if f.safety_factor is None}
    assert {"ring", "cup_tooth_root", "cup_band_edge", "wg_inner_ring"} <= missing
    assert not DesignVerdict(1.4, tuple(factors)).passed
    # the outer ring is closed form: always there
    assert next(f for f in factors if f.component == "wg_outer_ring").safety_factor > 0


def test_the_bearing_ring_on_the_cam_fails_when_the_cam_bends_it_past_the_steel(params):
    labels = {"wg-bearing": "B"}
    hot = design_factors_from_fea(params, _book({"race_stress_major_MPa": 1900.0, "net_race_stress_major_MPa": 1800.0}),
                                  labels, {}, {}, (), {})
    ring = next(f for f in hot if f.component == "wg_inner_ring")
    assert ring.verdict(1.4) == "FAIL" and "bearing_inner_ring_thickness_mm <=" in ring.fatigue["advice"]
    cool = design_factors_from_fea(params, _book({"race_stress_major_MPa": 200.0, "net_race_stress_major_MPa": 150.0}),
                                   labels, {}, {}, (), {})
    assert next(f for f in cool if f.component == "wg_inner_ring").verdict(1.4) == "PASS"
