"""The tooth mesh's closed forms against first principles (the references meshfe's FE checks compare with)."""
import math

import numpy as np
import pytest

from strainwave.analytic import mesh_compliance as mc
from strainwave.analytic.catalogue_rules import MeshRules, RimRule
from strainwave.analytic.mesh_kinematics import MeshGeometry, flank_clearances, teeth_on_neutral_line


def test_iso_c_prime_of_a_rack_pair():
    # q' = C1 alone for z1, z2 -> infinity, x = 0: c'_th = 1/0.04723; C_B = 0.975 for h_fP = 1.25 m, alpha 20
    c = mc.iso6336_single_pair_stiffness_N_per_mm_um(1e12, None)
    assert c == pytest.approx(0.8 * 0.975 / 0.04723, rel=1e-6)
    # fewer teeth: a more compliant pair (q' grows with 1/z)
    assert mc.iso6336_single_pair_stiffness_N_per_mm_um(20, 40) < c


def test_rim_on_foundation_carries_the_load_and_the_moment():
    """Equilibrium of Hetenyi's beam: the foundation's reaction k w integrates to the load P."""
    E, I, k = 2.1e5, 50.0, 300.0
    x = np.linspace(-400.0, 400.0, 400001)
    w = mc.rim_on_foundation_green_mm_per_N(x, E, I, k)
    assert np.trapezoid(k * w, x) == pytest.approx(1.0, rel=1e-4)
    beta = (k / (4 * E * I)) ** 0.25
    assert w[len(x) // 2] == pytest.approx(beta / (2 * k))
    # a unit moment: the rotation under it is beta^3/k (Hetenyi), and the kernel is symmetric positive definite
    assert mc.rim_moment_green_rad_per_Nmm(np.array([0.0]), E, I, k)[0] == pytest.approx(beta ** 3 / k)
    pts = np.linspace(0.0, 30.0, 12)
    K = mc.rim_moment_green_rad_per_Nmm(pts[:, None] - pts[None, :], E, I, k)
    assert np.all(np.linalg.eigvalsh(K) > 0.0)


def test_inextensible_neutral_line_keeps_the_teeth_conjugate_near_the_major_axis():
    """Near the major axis the FS tooth's offset from its CS space is the tooth difference's drift
    r_p phi 2/Z_c less the inextensible line's tangential flexure (w0/2) sin 2 phi (at the pitch radius), plus
    the rim's tilt gamma h: first order in phi cancels to (m Z_f/Z_c - w0 r_p/r_n) phi, and what is left is O(phi^3)."""
    g = MeshGeometry(200, 0.8, 0.8, 20.0, 1.0, 0.0, 1.0, 30.0)
    t = teeth_on_neutral_line(g, 0.0)
    j = np.arange(1, 6)
    phi = 2 * np.pi * j / 200
    r_p, r_n = g.pitch_radius_mm, g.neutral_radius_mm
    gamma_h = 1.5 * g.w0_mm / r_n * np.sin(2 * phi) * (r_p - r_n)
    first_order = (g.module_mm * 200 / 202 - g.w0_mm * r_p / r_n + 3.0 * g.w0_mm * (r_p - r_n) / r_n) * phi
    rest = t.offset_mm[1:6] - first_order
    assert np.all(np.abs(rest) < 2.0 * g.w0_mm * phi ** 3)
    assert np.all(np.abs(t.offset_mm[1:6]) > 0.5 * np.abs(gamma_h))   # the tilt is not negligible: kept
    assert t.depth_loss_mm[0] == pytest.approx(0.0, abs=1e-12)


def test_clearances_grow_away_from_the_major_axis_and_with_the_backlash():
    # decision 065's drive (the blank rim): the fatigue rim (069-cat48d) is 2.2x thicker at i = 100 and its rim
    # rotation closes tooth 3's gap as well (clipped at zero like teeth 1-2 here)
    d = MeshRules(rim_rule=RimRule.BLANK).design(25, 100)
    g = d.geometry
    gap, sign, tooth = flank_clearances(g, teeth_on_neutral_line(g, 0.0))
    first = gap[(sign > 0) & (tooth == 0)][0]
    assert first == pytest.approx(math.cos(math.radians(20.0)) * g.backlash_mm, rel=1e-9)
    near = gap[(sign > 0) & (tooth == 3)][0]
    far = gap[(sign > 0) & (tooth == 12)][0]
    assert first < near < far
    assert np.all(gap >= 0.0)
