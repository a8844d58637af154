"""Newman-Raju's surface crack against independently known limits, its compliance integral against a closed
form, and the crack-face contact rule (a shut crack adds nothing)."""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy import integrate
from scipy.special import ellipe

from strainwave.analytic import surface_crack as sc
from strainwave.fea.surface_crack import ASPECT


@pytest.fixture(scope="module")
def params():
    from strainwave.params import load_params
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return load_params()


def test_long_shallow_crack_is_the_edge_crack():
    # a/c -> 0, a/t -> 0, deepest point: the edge crack 1.1215 sigma sqrt(pi a) (Tada, Paris, Irwin)
    K = sc.stress_intensity(1e-3, 0.1, 100.0, 0.5 * math.pi, 1.0, 0.0)
    assert K / math.sqrt(math.pi * 1e-3) == pytest.approx(1.1215, rel=0.01)
    # and under bending, which a shallow crack sees as tension (H -> 1)
    assert sc.stress_intensity(1e-3, 0.1, 100.0, 0.5 * math.pi, 0.0, 1.0) == pytest.approx(K, rel=1e-4)


@pytest.mark.parametrize("a_over_c", [0.2, 0.5, 1.0])
def test_shape_factor_is_the_elliptic_integral_squared(a_over_c):
    # Q = E(k)^2, k^2 = 1 - (a/c)^2 (Irwin's embedded ellipse); Newman-Raju's fit holds it within 0.2 %
    assert sc.shape_factor_Q(a_over_c) == pytest.approx(ellipe(1.0 - a_over_c ** 2) ** 2, rel=2e-3)


def test_semicircular_crack_in_a_half_space_lies_just_above_the_penny_crack():
    # a/c = 1, a/t -> 0: the embedded penny crack gives 2/pi (Sneddon, exact); the free front face raises
    # the deepest point by a few per cent and the surface point by more (Smith, Emery, Kobayashi 1967)
    deep = sc.stress_intensity(1.0, 1.0, 1e4, 0.5 * math.pi, 1.0, 0.0) / math.sqrt(math.pi)
    surface = sc.stress_intensity(1.0, 1.0, 1e4, 0.0, 1.0, 0.0) / math.sqrt(math.pi)
    assert 1.02 < deep / (2.0 / math.pi) < 1.06
    assert surface > deep


def test_bending_lowers_the_deepest_point_of_a_deep_crack():
    phi = np.array([0.0, 0.5 * math.pi])
    H = sc.newman_raju_H(0.5, 0.5, phi)
    assert H[1] < H[0] < 1.0 and H[1] < 0.7


def test_shut_crack_gives_zero_and_an_open_one_does_not():
    phi = np.linspace(0.0, math.pi, 7)
    assert np.all(sc.stress_intensity(0.5, 1.0, 2.0, phi, -10.0, 0.0) == 0.0)
    assert np.all(sc.stress_intensity(0.5, 1.0, 2.0, phi, -10.0, 0.0, contact=False) < 0.0)
    shut = sc.CrackFaceLoads(-50.0, 0.0, 1e-5, 1e6)
    opened = sc.CrackFaceLoads(+50.0, 0.0, 1e-5, 1e6)
    assert sc.delta_flexibility(0.5, 0.5, 2.0, shut, 2.3e5) == 0.0
    assert sc.delta_flexibility(0.5, 0.5, 2.0, opened, 2.3e5) > 0.0


def test_compliance_integral_matches_its_closed_form_for_a_shallow_crack():
    # a << t: K/T = s sqrt(pi a'/Q) M1 g f_phi with constant M1, so delta = 2/E' s^2 pi M1^2 I a^3 / (3 Q alpha),
    # I = int_0^pi g^2 f_phi^2 dphi (g = 1 + 0.1 (1 - sin phi)^2)
    alpha, a, t, s, E = 0.5, 1e-2, 1e3, 2e-5, 2.3e5
    loads = sc.CrackFaceLoads(0.0, 0.0, s, 1.0)
    M1 = 1.13 - 0.09 * alpha
    I, _ = integrate.quad(lambda p: (1 + 0.1 * (1 - math.sin(p)) ** 2) ** 2
                          * math.sqrt(alpha ** 2 * math.cos(p) ** 2 + math.sin(p) ** 2), 0.0, math.pi)
    closed = 2.0 / E * s * s * math.pi * M1 ** 2 * I * a ** 3 / (3.0 * sc.shape_factor_Q(alpha) * alpha)
    assert sc.delta_flexibility(a, alpha, t, loads, E) == pytest.approx(closed, rel=1e-4)


def test_out_of_range_crack_is_refused():
    with pytest.raises(ValueError, match="a/t"):
        sc.newman_raju_F(0.5, 0.9, 0.0)
    with pytest.raises(ValueError, match="a/c"):
        sc.newman_raju_F(2.5, 0.2, 0.0)


def test_tooth_root_crack_breathes_open_at_the_major_axis_and_shut_at_the_minor(params):
    t = params.flexspline_cup.wall_thickness_mm
    E = params.material.youngs_modulus_MPa / (1.0 - params.material.poisson_ratio ** 2)
    major, minor = (sc.tooth_root_loads(params, phi) for phi in (0.0, 0.5 * math.pi))
    # the torque's map is the seed's tau = T/(2 pi r_m^2 t) at beta = 45 deg
    r_m = 0.5 * (params.flexspline_cup.pitch_diameter_mm - t)
    assert major.per_torque_MPa_per_Nmm == pytest.approx(1.0 / (2.0 * math.pi * r_m ** 2 * t))
    assert major.bending_MPa > 0 > minor.bending_MPa
    open_ = sc.delta_flexibility(0.2 * t, ASPECT, t, major, E)
    assert open_ > 0.0 and sc.delta_flexibility(0.2 * t, ASPECT, t, minor, E) == 0.0
    assert sc.ripple_percent(open_, 0.0, 1e-9) == pytest.approx(100.0 * open_ / 1e-9, rel=1e-5)
