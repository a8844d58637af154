"""Seed 003 thin ring (eqs 1-9): coefficients from pi, the w(phi) closed form, the mid-layer shape."""
import math

import numpy as np
import pytest

from strainwave.analytic import ring


def test_coefficients_derived_from_pi_match_seed_decimals():
    # The seed prints 6 significant digits (eqs 3, 4) and 5 (eqs 8, 9): compare at that resolution.
    assert ring.delta_cd_coefficient() == pytest.approx(0.148778, abs=5e-7)
    assert ring.delta_ab_coefficient() == pytest.approx(0.136620, abs=5e-7)
    assert ring.sigma_max_coefficient() == pytest.approx(-8.5580, abs=5e-5)
    assert ring.sigma_min_coefficient() == pytest.approx(4.8849, abs=5e-5)


def test_sigma_max_follows_from_moment_and_eqs_3_5():
    # sigma_max = 0.5 M_max delta / I with M_max = -F r/pi and F from W0 (seed text above eq 8); exact algebra.
    E, B, delta, r, W0 = 2.1e5, 12.0, 0.864, 37.782, 1.0
    I = ring.second_moment_mm4(B, delta)
    F = ring.force_for_deformation_N(W0, r, E, I)
    direct = 0.5 * ring.bending_moment_Nmm(math.pi / 2, F, r) * delta / I
    assert direct == pytest.approx(ring.sigma_max_MPa(W0, E, delta, 2 * r), rel=1e-12)
    direct_min = 0.5 * ring.bending_moment_Nmm(0.0, F, r) * delta / I
    assert direct_min == pytest.approx(ring.sigma_min_MPa(W0, E, delta, 2 * r), rel=1e-12)
    assert ring.radial_deformation_from_force_mm(F, r, E, I) == pytest.approx(W0, rel=1e-12)


def test_eq1_eq6_eq7_consistent():
    # W0 = r_m - b must equal 0.5 m dZ (seed 003, eq 7): exact identity up to rounding.
    m, Z_R, dZ = 1.25, 90, 2
    delta = 0.012 * m * Z_R
    r_m = ring.mid_layer_radius_mm(m, Z_R, delta)
    b = ring.short_semi_axis_mm(m, Z_R - dZ, delta)
    assert r_m - b == pytest.approx(ring.radial_deformation_from_teeth_mm(m, dZ), rel=1e-12)


def test_bending_moment_has_zero_mean_over_quarter():
    # The seed's check of eq 2: int_0^{pi/2} M dphi = 0 (zero rotation between B and D); quadrature error only.
    phi = np.linspace(0, math.pi / 2, 20001)
    M = np.array([ring.bending_moment_Nmm(p, 1.0, 1.0) for p in phi])
    assert abs(np.trapezoid(M, phi)) < 1e-8


def test_radial_displacement_solves_ring_equation_and_ends_at_eq3_eq4():
    F, r, E, I = 10.0, 40.0, 2.1e5, 0.5
    scale = F * r ** 3 / (E * I)
    # End values are exact: w(D) = -delta_CD/2, w(B) = +delta_AB/2.
    assert ring.radial_displacement_mm(math.pi / 2, F, r, E, I) == pytest.approx(-0.5 * ring.delta_cd_mm(F, r, E, I), rel=1e-12)
    assert ring.radial_displacement_mm(0.0, F, r, E, I) == pytest.approx(0.5 * ring.delta_ab_mm(F, r, E, I), rel=1e-12)
    # w'' + w = -M r^2/(E I) by central differences, h = 1e-4: truncation ~h^2 * w'''' ~ 1e-8 of scale.
    h = 1e-4
    for p in np.linspace(0.1, 1.4, 7):
        w = lambda x: ring.radial_displacement_mm(x, F, r, E, I)
        lhs = (w(p + h) - 2 * w(p) + w(p - h)) / h ** 2 + w(p)
        assert lhs == pytest.approx(-ring.bending_moment_Nmm(p, F, r) * r ** 2 / (E * I), abs=1e-6 * scale)
    # Inextensible: zero mean radial displacement over the ring (trapezoid on a periodic function: spectral).
    phi = np.linspace(0, 2 * math.pi, 4001)[:-1]
    assert abs(np.mean(ring.radial_displacement_mm(phi, F, r, E, I))) < 1e-12 * scale


def test_deformed_mid_layer_is_not_an_ellipse():
    W0, r = 1.0, 37.782
    x, y = ring.deformed_mid_layer_mm(W0, r, n_points=721)
    # Load points on x: r - W0 exactly; free points on y: r + 0.918 W0 (audit item 5). Exact closed forms.
    assert x.max() == pytest.approx(r - W0, rel=1e-12)
    assert y.max() == pytest.approx(r + W0 * ring.delta_ab_coefficient() / ring.delta_cd_coefficient(), rel=1e-12)
    assert ring.delta_ab_coefficient() / ring.delta_cd_coefficient() == pytest.approx(0.918, abs=5e-4)
    # Arc length is preserved to first order (inextensible): relative change O((W0/r)^2) ~ 1e-3.
    length = np.sum(np.hypot(np.diff(x), np.diff(y)))
    assert length == pytest.approx(2 * math.pi * r, rel=2e-3)
    # An ellipse with the same semi-axes deviates from it by a visible amount somewhere (> 1 % of W0).
    a_ax, b_ax = r + W0 * 0.9183, r - W0
    theta = np.arctan2(y, x)
    ell = a_ax * b_ax / np.sqrt((b_ax * np.sin(theta)) ** 2 + (a_ax * np.cos(theta)) ** 2)
    assert np.max(np.abs(np.hypot(x, y) - ell)) > 0.01 * W0
