"""The prescribed-shape ring (analytic/ring_prescribed.py) against a numerical deformed ring: the mid-line
x(phi) = (r + w) e_r + v e_theta with the inextensional v, its curvature and its fibres' stretch computed
by finite differences (no formula of the module is used)."""
import math

import numpy as np
import pytest

from strainwave.analytic import ring_prescribed as rp

R, W0, T = 78.88, 0.8, 2.24


def _deformed(phi, w0, r, n, y=0.0):
    """Points of the fibre at distance y (outward, along the deformed normal) of the deformed mid-line."""
    w, v = w0 * np.cos(n * phi), -(w0 / n) * np.sin(n * phi)
    er = np.stack([np.cos(phi), np.sin(phi)])
    et = np.stack([-np.sin(phi), np.cos(phi)])
    p = (r + w) * er + v * et
    dp = np.gradient(p, phi, axis=1)
    normal = np.stack([dp[1], -dp[0]]) / np.hypot(dp[0], dp[1])     # outward for a counter-clockwise curve
    return p + y * normal


def _curvature(p, phi):
    d1 = np.gradient(p, phi, axis=1)
    d2 = np.gradient(d1, phi, axis=1)
    return (d1[0] * d2[1] - d1[1] * d2[0]) / np.hypot(d1[0], d1[1]) ** 3


@pytest.mark.parametrize("n", [2, 3])
def test_curvature_change_matches_the_deformed_mid_line(n):
    phi = np.linspace(0.0, 2 * np.pi, 20001)
    w0 = 1e-3 * R          # small: the closed form is first order in w0/r
    kappa = _curvature(_deformed(phi, w0, R, n), phi) - 1.0 / R
    inner = slice(100, -100)
    expected = rp.curvature_change_per_mm(phi, w0, R, n)
    assert np.max(np.abs(kappa[inner] - expected[inner])) < 2e-3 * np.max(np.abs(expected))


def test_fibre_stress_at_the_axes_from_the_fibre_stretch():
    """sigma = E' eps of the outer fibre, eps = stretch of the fibre against its undeformed length (r + y) dphi."""
    phi = np.linspace(-0.05, math.pi / 2 + 0.05, 40001)
    w0, y = 1e-3 * R, 0.5 * T
    fibre = _deformed(phi, w0, R, 2, y)
    stretch = np.hypot(*np.gradient(fibre, phi, axis=1)) / (R + y) - 1.0
    mid = np.hypot(*np.gradient(_deformed(phi, w0, R, 2), phi, axis=1)) / R - 1.0   # second order in w0
    E, nu = 2.1e5, 0.3
    for angle in (0.0, math.pi / 2):
        k = int(np.argmin(np.abs(phi - angle)))
        numeric = E / (1 - nu ** 2) * (stretch[k] - mid[k])
        closed = rp.hoop_bending_stress_MPa(angle, w0, T, R, E, nu)
        # the thin ring leaves out the curved beam's y/r: the numeric fibre is within t/2r of the closed form
        assert numeric == pytest.approx(closed, rel=1.2 * rp.curved_beam_allowance(T, R))
        assert np.sign(numeric) == np.sign(closed)


def test_axis_stresses_signs_and_the_default_magnitude():
    s = rp.axis_stresses_MPa(W0, T, R, 2.1e5, 0.3, plane_strain=False)
    # the "about 91 MPa nominal" on the default cup: E t/2 3 w0 / r_m^2
    assert s["major_outer"] == pytest.approx(2.1e5 * 1.12 * 3 * 0.8 / R ** 2, rel=1e-12)
    assert 85.0 < s["major_outer"] < 95.0
    assert s["minor_outer"] == pytest.approx(-s["major_outer"])
    assert s["major_inner"] == pytest.approx(-s["major_outer"])
    strain = rp.axis_stresses_MPa(W0, T, R, 2.1e5, 0.3, plane_strain=True)
    assert strain["major_outer"] / s["major_outer"] == pytest.approx(1 / (1 - 0.09))


def test_fibre_outside_the_wall_is_refused():
    with pytest.raises(ValueError):
        rp.hoop_bending_stress_MPa(0.0, W0, T, R, 2.1e5, 0.3, fibre=1.5)
