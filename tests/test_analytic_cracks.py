"""Every seed-000 crack closed form against the numerical eq-4 integral of its own K/P function.

Corrected variants must equal their integral (1e-6 relative: quadrature at epsrel 1e-11 of a
polynomial-in-sqrt integrand leaves only round-off); published ones differ by exactly the
factor the audit states.
"""
import math

import pytest

from strainwave.analytic import crack_series as cs, cracks
from strainwave.analytic.variant import Variant

P, C = Variant.PUBLISHED, Variant.CORRECTED
E, MU = 2.1e5, 8e4
REL = 1e-6   # closed form vs quadrature (see module docstring)


@pytest.mark.parametrize("a", [0.1, 0.5, 1.5])
def test_flexspline_closed_form_vs_integral(a):
    r_m, delta, Ku, Kd = 78.88, 2.24, 1.2, 1.1
    for angle in (45.0, 30.0, 10.0):   # corrected form holds for any angle (sin^2 + cos^2 = 1)
        integral = cracks.crack_compliance_integral(cracks.flexspline_k_per_load(r_m, delta, Ku, Kd, angle),
                                                    lambda _: delta, a, E, MU)
        assert cracks.flexspline_crack_flexibility(r_m, delta, Ku, Kd, a, E, C) == pytest.approx(integral, rel=REL)
        # Audit: K_uK_d not squared and 2 pi for 4 pi -> published / integral = 2/(K_uK_d).
        assert cracks.flexspline_crack_flexibility(r_m, delta, Ku, Kd, a, E, P) / integral == pytest.approx(
            2.0 / (Ku * Kd), rel=REL)


@pytest.mark.parametrize("a", [0.1, 1.0, 5.0])
def test_shaft_torsion_closed_forms_vs_integral(a):
    d_s = 70.0
    d_e = d_s - 2 * a
    for series in (P, C):
        k = cracks.shaft_k_per_torque(d_s, a, series)         # d_e, M_M frozen at the final depth
        penny = cracks.crack_compliance_integral(k, cracks.penny_area_element, a, E, MU)
        circ = cracks.crack_compliance_integral(k, cracks.circumferential_area_element(d_s, a), a, E, MU)
        # Published = the integral with its own (penny) area element: the derivation is right, the geometry not.
        assert cracks.shaft_crack_flexibility(d_s, a, MU, P, series=series) == pytest.approx(penny, rel=REL)
        assert cracks.shaft_crack_flexibility(d_s, a, MU, C, series=series) == pytest.approx(circ, rel=REL)
        # Audit: published / corrected = 4a/(3 d_e) (a^3 vs a^2 scaling).
        ratio = cracks.shaft_crack_flexibility(d_s, a, MU, P, series=series) / circ
        assert ratio == pytest.approx(4 * a / (3 * d_e), rel=REL)


def test_shaft_growing_crack_differs_little_for_shallow_crack():
    # Frozen d_e and M_M vs following the crack: < 0.2 % at a/d_s = 0.0014, ~ a few % at a/d_s = 0.07.
    g = cracks.shaft_crack_flexibility_growing(70.0, 0.1, MU)
    assert g / cracks.shaft_crack_flexibility(70.0, 0.1, MU) == pytest.approx(1.0, abs=2e-3)
    deep = cracks.shaft_crack_flexibility_growing(70.0, 5.0, MU) / cracks.shaft_crack_flexibility(70.0, 5.0, MU)
    assert 0.5 < deep < 0.99


def test_shaft_mixed_term_is_the_integral_with_dA_da():
    # The published K_I term equals eq 4 with dA = da (no crack-front length): units 1/N, not rad/(N mm).
    for a in (0.1, 2.0):
        integral = cracks.crack_compliance_integral(cracks.shaft_k_per_axial_force(70.0, a, P), lambda _: 1.0,
                                                    a, E, MU)
        assert cracks.shaft_mixed_axial_term(70.0, a, E) == pytest.approx(integral, rel=REL)
        # With the real front length pi d_e it becomes an axial compliance (mm/N), pi d_e times larger.
        axial = cracks.crack_compliance_integral(cracks.shaft_k_per_axial_force(70.0, a, P),
                                                 cracks.circumferential_area_element(70.0, a), a, E, MU)
        assert axial / integral == pytest.approx(math.pi * (70.0 - 2 * a), rel=REL)


@pytest.mark.parametrize("F_r", [2.515625, 100.0])
def test_bearing_displacement_vs_integral(F_r):
    t_i, beta, axes, a, Q = 10.0, 0.45, (5.0, 3.0), 0.1, 1.5
    k = cracks.bearing_k_per_load(beta, axes, Q)
    du_int = cracks.crack_displacement_integral(k, lambda _: t_i, a, F_r, E, MU)
    assert cracks.bearing_displacement_mm(F_r, t_i, beta, axes, a, E, Q, C) == pytest.approx(du_int, rel=REL)
    # Published: F_r^2 and the rounded 0.217 -> ratio F_r * 0.217/0.216717 (audit item 7).
    assert cracks.bearing_displacement_mm(F_r, t_i, beta, axes, a, E, Q, P) / du_int == pytest.approx(
        F_r * 0.217 / cs.hertz_mode_i_constant(), rel=REL)
    # Eq 3 as printed (int G/P dA = K^2/(E' P)) is half the expanded form (audit item 6).
    g_over_p = cracks.crack_compliance_integral(k, lambda _: t_i, a, E, MU) * F_r / 2
    assert du_int / g_over_p == pytest.approx(2.0, rel=1e-12)
    # Corrected dK_G is load independent, published scales with 1/F_r.
    dk = cracks.bearing_crack_stiffness(F_r, t_i, beta, axes, a, E, Q, C)
    assert dk == pytest.approx(E * Q / (cs.hertz_mode_i_constant() * t_i * (beta * a / 15.0) ** 2), rel=1e-12)


def test_hertz_constant_and_series_limits():
    # 0.217 printed in seed 000 = (3 * 1.95/(4 pi))^2 = 0.216717 (audit).
    assert cs.hertz_mode_i_constant() == pytest.approx(0.216717, abs=5e-7)
    F1, F3 = cs.edge_crack_limits()
    # Edge-crack limits (audit): F1 = 1.1215, F3 = 1.0009 at 4 decimals; published M_P(1) = 1.286 fails 1.12.
    assert F1 == pytest.approx(1.1215, abs=5e-5) and F3 == pytest.approx(1.0009, abs=5e-5)
    assert cs.m_p(1.0, P) == pytest.approx(1.286, abs=5e-4)
    # Corrected coefficients as listed in the audit.
    assert cs.m_p_corrected_coefficients() == pytest.approx((0.5, 0.25, 0.1875, -0.1815, 0.3655), abs=1e-12)
    mm = cs.m_m_corrected_coefficients()
    # The published M_M agrees with Tada's F3 to its printed 3 decimals except the leading 0.376.
    assert [round(c, 3) for c in mm[1:]] == pytest.approx(list(cs.M_M_PUBLISHED[1:]), abs=1.5e-3)
    assert mm[0] == 0.375 and cs.deep_crack_torsion_factor() == 0.375


def test_general_integral_handles_mixed_modes_and_lower_limit():
    # Constant K/P of all three modes over [a0, a] with unit front: exact value by hand.
    k = lambda a: (2.0, 3.0, 5.0)
    val = cracks.crack_compliance_integral(k, lambda a: 1.0, 2.0, 4.0, 10.0, a0_mm=0.5)
    assert val == pytest.approx(1.5 * (2 / 4.0 * (4 + 9) + 25 / 10.0), rel=1e-12)


def test_stress_intensity_factors_at_load():
    # K = load * (K/P): the solid-bar torsion edge-crack limit K_III -> tau_gross sqrt(pi a) for a tiny crack.
    T, d_s, a = 1.0e5, 70.0, 1e-4
    tau = 16 * T / (math.pi * d_s ** 3)
    assert cracks.shaft_K_III(T, d_s, a) == pytest.approx(tau * math.sqrt(math.pi * a) * cs.m_m(1.0), rel=1e-4)
    # Mode I of the bearing ring: 1.95 * (beta/2) * 3F/(2 pi a'b') * sqrt(a/Q), exact.
    K = cracks.bearing_K_I(100.0, 0.45, (5.0, 3.0), 0.1, 1.5)
    assert K == pytest.approx(1.95 * 0.225 * 300 / (2 * math.pi * 15) * math.sqrt(0.1 / 1.5), rel=1e-14)
    kI, kII = cracks.flexspline_K(1000.0, 78.88, 2.24, 1.2, 1.1, 45.0, 0.1)
    assert kII == pytest.approx(0.0, abs=1e-12 * kI)   # beta = 45 deg is pure mode I (seed 000 text)
    assert cracks.shaft_K_I(10.0, 70.0, 0.1, Variant.PUBLISHED) > cracks.shaft_K_I(10.0, 70.0, 0.1)


def test_through_crack_integrates_both_tips():
    # a through-wall crack of half-length a grows at both tips: dA = 2 delta da in eq 4 (issue 13)
    r_m, delta, E = 78.88, 2.24, 2.1e5
    for angle in (30.0, 45.0):
        k = cracks.flexspline_k_per_load(r_m, delta, 1.0, 1.0, angle)
        for a in (0.1, 1.12):
            integral = cracks.crack_compliance_integral(k, lambda s: 2.0 * delta, a, E, 8e4)
            assert cracks.flexspline_through_crack_flexibility(r_m, delta, a, E) == pytest.approx(integral, rel=REL)
            # one tip is the audit's corrected form; the seed's published 2 pi is the two-tip value (K_u K_d = 1)
            one = cracks.flexspline_through_crack_flexibility(r_m, delta, a, E, tips=1)
            assert one == pytest.approx(cracks.flexspline_crack_flexibility(r_m, delta, 1, 1, a, E, C), rel=REL)
            assert 2 * one == pytest.approx(cracks.flexspline_crack_flexibility(r_m, delta, 1, 1, a, E, P), rel=REL)
    with pytest.raises(ValueError):
        cracks.flexspline_through_crack_flexibility(r_m, delta, 1.0, E, tips=3)
