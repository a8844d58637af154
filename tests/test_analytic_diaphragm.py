"""The diaphragm's annular plate (analytic/diaphragm.py) against a clamped beam: a narrow ring far from the axis is a
strip whose outer end is moved by delta and turned by theta (the n = 2 terms 4 w/r^2 vanish as r grows)."""
import math

import pytest

from strainwave.analytic.diaphragm import diaphragm_stresses

E, NU, T = 2.1e5, 0.3, 2.0


def _beam_root_stress(l, delta, theta):
    """w = c2 x^2 + c3 x^3 with w(0) = w'(0) = 0, w(l) = delta, w'(l) = theta; 6 M(0)/t^2, M = -D w''."""
    c2 = (3.0 * delta - theta * l) / l ** 2
    D = E * T ** 3 / (12.0 * (1.0 - NU ** 2))
    return 6.0 * (-D * 2.0 * c2) / T ** 2


def test_narrow_ring_far_out_is_a_clamped_strip():
    a, b, lever, w0 = 5000.0, 5010.0, 100.0, 0.5
    s = diaphragm_stresses(a, b, T, lever, w0, 0.0, E, NU)
    delta, theta = -b * w0 / (4 * lever), -w0 / lever
    assert s.hub_bending_MPa == pytest.approx(_beam_root_stress(b - a, delta, theta), rel=2e-3)


def test_stress_scales_with_the_insertion_and_the_shear_with_the_torque():
    one = diaphragm_stresses(40.0, 79.0, 2.2, 136.0, 0.8, 1.0e6, E, NU)
    two = diaphragm_stresses(40.0, 79.0, 2.2, 136.0, 1.6, 2.0e6, E, NU)
    assert two.bending_MPa == pytest.approx(2 * one.bending_MPa, rel=1e-12)
    assert one.hub_shear_MPa == pytest.approx(1.0e6 / (2 * math.pi * 40.0 ** 2 * 2.2))
    assert two.hub_shear_MPa == pytest.approx(2 * one.hub_shear_MPa)
