"""Tooth-factor model (analytic/tooth_factors.py) and eq 14 with it (analytic/tooth_number.py)."""
import math

import pytest

from strainwave.analytic import fatigue, tooth_factors as tf, tooth_number as tn


def test_refit_reproduces_the_stored_constants():
    fitted = tf.fit_tooth_factors(tf.FITTING_SET)
    for name in ("c", "k", "p0", "a"):
        assert getattr(fitted, name) == pytest.approx(getattr(tf.FITTED, name), rel=1e-4)


def test_residuals_on_the_fitting_set_are_small_and_reported():
    res = tf.fit_residuals(tf.FITTING_SET, tf.FITTED)
    assert 0.0 < res["tooth_influence"] < 0.05 and 0.0 < res["stress_concentration"] < 0.05
    assert res["root_product"] < 0.02


def test_limits_of_the_model():
    m = tf.FITTED
    # no teeth: every factor is 1 (K_sigma -> P0, the notch alone)
    assert tf.tooth_influence(0.0, 1.0, m) == pytest.approx(1.0)
    assert tf.root_product(0.0, 1.0, m) == pytest.approx(m.p0)
    # long segments (m/delta large): the outer fibre carries the stiffness ratio (segmented beam)
    assert tf.tooth_influence(2.0, 50.0, m) == pytest.approx(tf.stiffness_ratio(2.0, m), rel=1e-9)
    # the equivalent rim: R = ((delta + c h)/delta)^3
    assert tf.stiffness_ratio(2.0, m) == pytest.approx((1 + 2.0 * m.c) ** 3)


def test_fitting_needs_a_residual():
    with pytest.raises(ValueError):
        tf.fit_tooth_factors(tf.FITTING_SET[:2])


def test_minimal_teeth_is_the_smallest_integer_that_satisfies_eq14():
    design = fatigue.ToothDesign()
    for dz in (2, 4):
        r = tn.minimal_teeth_with_model(dz, 1.4, 625.0, 2.1e5, design)
        n_at, _, _ = tn.safety_with_model(r.Z_R_min, dz, 1.4, 625.0, 2.1e5, design, tf.FITTED)
        n_below, _, _ = tn.safety_with_model(r.Z_R_min - 1, dz, 1.4, 625.0, 2.1e5, design, tf.FITTED)
        assert n_at >= 1.4 > n_below
        # self-consistent: the factors are those of the rim at Z_R,min
        hd, md = tn.rim_ratios(r.Z_R_min, design)
        assert r.tooth_influence == pytest.approx(tf.tooth_influence(hd, md, tf.FITTED))
        assert r.seed_constant_Z_R_min == math.ceil(fatigue.minimal_teeth_root(
            dz, 1.4, 625.0, 2.1e5, fatigue.tooth_constant(design), fatigue.tooth_offset(design)))
        # thicker factors than the seed's 1.07 x 1.9 need more teeth
        assert r.Z_R_min > r.seed_constant_Z_R_min


def test_stored_fea_at_the_minimum_is_consistent_with_eq14():
    from dataclasses import replace
    for (z, dz), v in tn.FEA_AT_MINIMUM.items():
        d = replace(fatigue.ToothDesign(), tooth_influence=v["tooth_influence"],
                    stress_concentration=v["stress_concentration"])
        n = fatigue.safety_from_teeth(z, dz, 625.0, 2.1e5, fatigue.tooth_constant(d), fatigue.tooth_offset(d))
        assert n == pytest.approx(v["n_sigma"], rel=1e-3)
        root = fatigue.minimal_teeth_root(dz, 1.4, 625.0, 2.1e5, fatigue.tooth_constant(d), fatigue.tooth_offset(d))
        assert fatigue.minimal_teeth(root) == v["Z_R_min_with_these_factors"]
        # the model's factors at that rim lie within its fitting residual of the FEA
        hd, md = tn.rim_ratios(z, fatigue.ToothDesign())
        res = tf.fit_residuals(tf.FITTING_SET, tf.FITTED)
        assert abs(tf.tooth_influence(hd, md, tf.FITTED) / v["tooth_influence"] - 1) <= res["tooth_influence"]
        assert abs(tf.stress_concentration(hd, md, tf.FITTED) / v["stress_concentration"] - 1) <= \
            res["stress_concentration"]


def test_the_headline_states_one_z_r_min_the_one_the_fea_supports_with_the_others_basis():
    from strainwave.analytic import tooth_number as tn
    # dZ = 2: the FEA at the model's 110 gives n_sigma 1.368 < 1.4, so the headline number is the FEA's 113
    z, basis = tn.supported_minimum(2, 110, 1.4, fea_applies=True)
    assert z == 113 and "n_sigma = 1.368 < [n] = 1.4" in basis and "the fitted model alone gives 110" in basis
    # dZ = 4: the FEA at 208 confirms n_sigma 1.428 >= 1.4, so the model's 208 stands and 204 is named as unsolved
    z, basis = tn.supported_minimum(4, 208, 1.4, fea_applies=True)
    assert z == 208 and "confirms" in basis and "204 (not solved there)" in basis
    # a stricter [n] than the FEA's n_sigma at 208 turns it over, and a design the FEA was not solved for keeps the model
    assert tn.supported_minimum(4, 208, 1.43, fea_applies=True)[0] == 204
    z, basis = tn.supported_minimum(2, 110, 1.4, fea_applies=False)
    assert z == 110 and "no toothed-ring FEA" in basis


def test_designer_headline_prints_113_for_the_seed_design():
    import warnings

    from strainwave.analytic.summary import analytic_summary, designer_headline
    from strainwave.params import load_params
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        lines = designer_headline(analytic_summary(load_params())["seed003"])
    assert lines[1].startswith("  dZ = 2: Z_R,min = 113 (basis: toothed-ring FEA at Z_R = 110")
    assert lines[2].startswith("  dZ = 4: Z_R,min = 208 (basis: toothed-ring FEA at Z_R = 208 confirms")


def test_the_model_outside_its_fitted_rim_range_carries_the_error_the_fea_measured_there():
    from strainwave.analytic import tooth_factors as tf
    lo, hi = tf.FITTED_DELTA_OVER_M
    assert (lo, hi) == (min(r.delta_over_m for r in tf.FITTING_SET), max(r.delta_over_m for r in tf.FITTING_SET))
    assert all(not lo <= d <= hi for d in tf.EXTRAPOLATION)            # both measured rims lie outside
    thin, thick = tf.extrapolation_errors(0.6), tf.extrapolation_errors(3.6)
    # thin rim: K_delta is over-predicted by 10 %, beyond 3 x the FEA's GCI (3 %) and the fit's own residuals
    kd_fea, kd_gci = tf.EXTRAPOLATION[0.6]["tooth_influence"]
    assert thin["tooth_influence"] == pytest.approx(0.1003, abs=5e-4) and thin["tooth_influence"] > 3 * kd_gci
    assert abs(thin["tooth_influence"]) > tf.fit_residuals(tf.FITTING_SET, tf.FITTED)["tooth_influence"]
    # thick rim: the saturating forms extrapolate within 1 %
    assert abs(thick["tooth_influence"]) < 0.01 and abs(thick["stress_concentration"]) < 0.01
    note = tf.range_note(0.5)
    assert "OUTSIDE the fitted range 0.75-3" in note and "+10.0 % (K_delta" in note
    assert "inside the fitted range" in tf.range_note(1.32)
