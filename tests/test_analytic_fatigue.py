"""Seed 003 eqs 10-15: constants recomputed from their assumptions, tooth-number roots, paper's slip."""
import math

import pytest

from strainwave.analytic import fatigue, ring
from strainwave.analytic.variant import Variant

N_ALLOW, S_1, E = 1.4, 625.0, 2.1e5   # seed 003 example


def test_stress_coefficients_recomputed():
    # Printed to 4 decimals in seed 003; compared at half a unit of the last digit.
    assert abs(fatigue.mean_stress_coefficient()) == pytest.approx(1.8366, abs=5e-5)
    assert fatigue.mean_stress_coefficient() < 0          # compressive (eqs 8, 9)
    assert fatigue.amplitude_coefficient() == pytest.approx(6.7214, abs=5e-5)
    assert fatigue.printed_mean_stress_coefficient() == pytest.approx(1.8366, abs=5e-5)
    # Closed forms -4(4 - pi)/(pi^2 - 8) and 4 pi/(pi^2 - 8): exact identities.
    assert fatigue.mean_stress_coefficient() == pytest.approx(-4 * (4 - math.pi) / (math.pi ** 2 - 8), rel=1e-14)
    assert fatigue.amplitude_coefficient() == pytest.approx(4 * math.pi / (math.pi ** 2 - 8), rel=1e-14)


def test_published_literal_coefficients_lack_the_half():
    # Eq 10/11 as printed (sum and difference, no /2) are exactly twice the corrected ones.
    assert fatigue.mean_stress_coefficient(Variant.PUBLISHED) == pytest.approx(2 * fatigue.mean_stress_coefficient(), rel=1e-14)
    assert fatigue.amplitude_coefficient(Variant.PUBLISHED) == pytest.approx(2 * fatigue.amplitude_coefficient(), rel=1e-14)


def test_eq14_constants_recomputed_from_assumptions():
    # 12.2795 and 2.668 are printed in eq 14; the audit's full-precision values to 1e-6.
    assert fatigue.tooth_constant() == pytest.approx(12.2795, abs=5e-5)
    assert fatigue.tooth_constant() == pytest.approx(12.279522, abs=1e-6)
    assert fatigue.tooth_offset() == pytest.approx(2.668, abs=5e-4)
    assert fatigue.tooth_offset() == pytest.approx(2.7 / 1.012, rel=1e-14)
    assert fatigue.tooth_constant(signed_mean_stress=True) == pytest.approx(12.710786, abs=1e-6)


def test_eq14_equals_direct_stress_route():
    # Eq 14 is eqs 1, 7, 10, 11, 13 combined: the two routes agree to round-off for any Z_R, m.
    d = fatigue.ToothDesign()
    for m, Z, dZ in ((1.0, 72, 2), (0.5, 150, 4), (2.0, 40, 2)):
        delta = d.rim_thickness_ratio * m * Z
        d_m = 2 * ring.mid_layer_radius_mm(m, Z, delta)
        W0 = ring.radial_deformation_from_teeth_mm(m, dZ)
        s_a = fatigue.stress_MPa(fatigue.amplitude_coefficient(), d.tooth_influence, W0, E, delta, d_m)
        s_m = fatigue.stress_MPa(abs(fatigue.mean_stress_coefficient()), d.tooth_influence, W0, E, delta, d_m)
        n = fatigue.normal_safety_factor(S_1, d.stress_concentration, s_a, d.mean_stress_influence, s_m)
        assert n == pytest.approx(fatigue.safety_from_teeth(Z, dZ, S_1, E, fatigue.tooth_constant(d),
                                                            fatigue.tooth_offset(d)), rel=1e-12)


@pytest.mark.parametrize("dZ, root_abs, root_signed", [(2, 71.18, 68.58), (4, 147.85, 142.65)])
def test_minimal_tooth_number_roots(dZ, root_abs, root_signed):
    c = fatigue.tooth_offset()
    r = fatigue.minimal_teeth_root(dZ, N_ALLOW, S_1, E, fatigue.tooth_constant(), c)
    rs = fatigue.minimal_teeth_root(dZ, N_ALLOW, S_1, E, fatigue.tooth_constant(signed_mean_stress=True), c)
    # Issue 2 quotes 2 decimals: half a unit of the last digit.
    assert r == pytest.approx(root_abs, abs=5e-3)
    assert rs == pytest.approx(root_signed, abs=5e-3)
    # The root is where n_sigma = [n] exactly (round-off only).
    assert fatigue.safety_from_teeth(r, dZ, S_1, E, fatigue.tooth_constant(), c) == pytest.approx(N_ALLOW, rel=1e-12)


def test_paper_roots_fit_12_2640_not_12_2795():
    c = fatigue.tooth_offset()
    for dZ, root in fatigue.PAPER_ROOTS.items():
        C = fatigue.constant_implied_by_root(root, dZ, N_ALLOW, S_1, E, c)
        # Both printed roots imply the same constant to the 4 decimals the audit gives.
        assert C == pytest.approx(12.2640, abs=5e-5)
        assert abs(C / fatigue.tooth_constant() - 1) == pytest.approx(0.00126, abs=5e-5)
    # Integer consequences: dZ = 2 -> 72 either way; dZ = 4 -> exact 148 suffices, paper says more than 148.
    r4 = fatigue.minimal_teeth_root(4, N_ALLOW, S_1, E, fatigue.tooth_constant(), c)
    assert fatigue.minimal_teeth(r4) == 148 and fatigue.PAPER_ROOTS[4] > 148
    assert fatigue.safety_from_teeth(148, 4, S_1, E, fatigue.tooth_constant(), c) == pytest.approx(1.4014, abs=5e-5)


def test_no_real_root_raises_and_helpers():
    with pytest.raises(ValueError):
        fatigue.minimal_teeth_root(2, 1e-6, S_1, E, fatigue.tooth_constant(), fatigue.tooth_offset())
    assert fatigue.circular_spline_teeth(72, 2) == 70
    assert fatigue.combined_safety_factor(3.0, 4.0) == pytest.approx(2.4, rel=1e-14)
    assert fatigue.combined_safety_factor(1.5) == 1.5
