"""Hollow-tube crack forms (analytic.tube_crack): closed form against seed 000's eq 4, limits, review number."""
import math

import pytest

from strainwave.analytic import cracks, tube_crack as tc

G_MPa = 2.1e5 / 2.6


def test_strip_closed_form_equals_the_eq4_integral():
    r_o, r_i = 35.0, 22.5
    t, k = r_o - r_i, tc.tube_outer_stress_per_torque(r_o, r_i)
    for a in (0.1, 0.781, 6.25, 10.0):
        integral = cracks.crack_compliance_integral(
            lambda s: (0.0, 0.0, k * math.sqrt(math.pi * s) * tc.strip_factor(s / t)),
            lambda s: 2.0 * math.pi * r_o, a, 1.0, G_MPa)
        assert tc.hollow_tube_strip_flexibility(r_o, r_i, a, G_MPa) == pytest.approx(integral, rel=1e-8)


def test_strip_form_limits_and_the_review_number():
    r_o, r_i = 35.0, 22.5
    J = math.pi / 2 * (r_o ** 4 - r_i ** 4)
    # shallow: K = tau_o sqrt(pi a), dlambda = pi^2 r_o^3 a^2 / (G J^2)
    a = 1e-3
    assert tc.hollow_tube_strip_flexibility(r_o, r_i, a, G_MPa) == pytest.approx(
        math.pi ** 2 * r_o ** 3 * a ** 2 / (G_MPa * J ** 2), rel=1e-5)
    assert tc.strip_factor(0.0) == 1.0 and tc.strip_factor(0.5) == pytest.approx(math.sqrt(4 / math.pi))
    # issue 13's independent review: 8.378e-13 at a = 0.781 mm
    assert tc.hollow_tube_strip_flexibility(r_o, r_i, 0.781, G_MPa) == pytest.approx(8.378e-13, rel=2e-4)
    with pytest.raises(ValueError):
        tc.hollow_tube_strip_flexibility(r_o, r_i, 12.5, G_MPa)


def test_thick_tube_amplification_vanishes_where_the_strip_is_exact():
    # a -> 0 and a thin wall: A -> 1, so the thick-tube form falls back on the strip form
    assert tc.thick_tube_amplification(35.0, 22.5, 0.0) == pytest.approx(1.0)
    assert tc.thick_tube_amplification(35.0, 34.9, 0.05) == pytest.approx(1.0, abs=3e-3)
    # a thick tube's net section carries the torque over a smaller polar moment than the flat strip: A > 1
    assert tc.thick_tube_amplification(35.0, 17.5, 10.0) > 1.1
    assert tc.thick_tube_flexibility(35.0, 34.9, 0.05, G_MPa) == pytest.approx(
        tc.hollow_tube_strip_flexibility(35.0, 34.9, 0.05, G_MPa), rel=3e-3)
