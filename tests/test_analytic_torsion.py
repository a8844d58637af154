"""Seed 000 uncracked flexibilities and drive stiffness against the seed's own table."""
import math

import pytest

from strainwave.analytic import torsion
from strainwave.analytic.variant import Variant
from strainwave.errors import RangeWarning
from strainwave.params import load_params

MU = 8e4


def test_lambda_f0_from_defaults():
    with pytest.warns(RangeWarning, match="0.96"):   # the seed's E, nu, mu disagree (audit 18)
        p = load_params()
    cup = p.flexspline_cup
    lam = torsion.flexspline_flexibility(cup.pitch_diameter_mm, cup.wall_thickness_mm, cup.length_mm,
                                         p.material.shear_modulus_MPa, torsion.shape_coefficient(False),
                                         torsion.structure_coefficient(cup.cup))
    # Table value printed to 5 significant digits.
    assert lam == pytest.approx(2.3588e-10, abs=5e-15)
    # pi/32 instead of 0.1: exactly 3.2/pi more compliant (1.86 % more = published 1.83 % low).
    corr = torsion.flexspline_flexibility(cup.pitch_diameter_mm, cup.wall_thickness_mm, cup.length_mm, MU, 1.0,
                                          0.83, Variant.CORRECTED)
    assert corr / lam == pytest.approx(3.2 / math.pi, rel=1e-14)
    assert 1 - lam / corr == pytest.approx(0.0183, abs=5e-5)


def test_lambda_so0_reproduces_table_only_with_bore_and_110mm():
    table = 6.9063e-10
    # 5 significant digits in the table -> abs 5e-15.
    assert torsion.shaft_flexibility_table_reconstruction(110.0, 70.0, 45.0, MU) == pytest.approx(table, abs=5e-15)
    assert torsion.shaft_length_implied_mm(table, 70.0, 45.0, MU) == pytest.approx(110.0, abs=0.01)
    # Printed formula with the stated 200 mm: 10.4123; with the bore: 12.5569 (audit, 5 digits).
    assert torsion.shaft_flexibility(200.0, 70.0, 45.0, MU) == pytest.approx(10.4123e-10, abs=5e-15)
    assert torsion.shaft_flexibility_table_reconstruction(200.0, 70.0, 45.0, MU) == pytest.approx(12.5569e-10, abs=5e-15)
    for L in (110.0, 200.0):   # neither the printed formula nor the exact hollow one hits the table
        assert abs(torsion.shaft_flexibility(L, 70.0, 45.0, MU) / table - 1) > 0.01
        assert abs(torsion.shaft_flexibility(L, 70.0, 45.0, MU, Variant.CORRECTED) / table - 1) > 0.01
    # Corrected = exact hollow-shaft torsion 32 L/(pi mu (D^4 - d^4)).
    assert torsion.shaft_flexibility(200.0, 70.0, 45.0, MU, Variant.CORRECTED) == pytest.approx(
        200.0 / (MU * math.pi * (70 ** 4 - 45 ** 4) / 32), rel=1e-14)


def test_lambda_H0_and_implied_K_G0():
    lam = torsion.wave_generator_flexibility(0.35, 6.303e4, 160.0, 2, 0.8, 100.0)
    # K_G0 = 6.303e4 is itself rounded to 4 digits: 3.4071 reproduced to 1e-4 relative.
    assert lam == pytest.approx(3.4071e-10, rel=1e-4)
    assert torsion.radial_stiffness_implied_N_per_mm(3.4071e-10, 0.35, 160.0, 2, 0.8, 100.0) == pytest.approx(6.303e4, rel=1e-4)
    assert torsion.radial_force_N(0.35, 1000.0, 160.0) == pytest.approx(1.15 * 0.35 * 1000 / 160, rel=1e-15)


def test_K_HD_printed_with_1e3_slip_and_shares():
    t = torsion.SEED000_TABLE
    # Table rows sum correctly (to the 4 decimals printed).
    assert t["lambda_H0"] + t["lambda_f0"] + t["lambda_so0"] == pytest.approx(t["lambda_sum0"], abs=1e-14)
    for lam, printed in ((t["lambda_sum0"], t["K_HD0_printed"]), (t["lambda_sum"], t["K_HD_printed"])):
        # The printed stiffness is 1/lambda_sum divided by 1000 (5-digit rounding of both numbers).
        assert torsion.printed_stiffness_slip(lam, printed) == pytest.approx(1000.0, rel=1e-4)
    sh = torsion.shares(t["lambda_H0"] + t["delta_lambda_H"], t["lambda_f0"], t["lambda_so0"])
    assert [round(100 * s, 2) for s in sh] == [27.75, 18.39, 53.86]
    assert [round(100 * s) for s in sh] != list(t["shares_percent"])   # the paper's 28/19/53 do not follow


def test_series_vs_subtractive_radial_stiffness():
    # Series springs are softer than either; the published subtraction goes negative for a stiff crack term.
    assert torsion.cracked_radial_stiffness_N_per_mm(100.0, 300.0) == pytest.approx(75.0, rel=1e-14)
    assert torsion.cracked_radial_stiffness_N_per_mm(6.303e4, 6.4e9, Variant.PUBLISHED) < 0


def test_K_G_from_crack_displacement():
    # Series: the crack's displacement adds to the ring's own (exact algebra).
    K0, du, F = 6.303e4, 1.557e-10, 2.515625
    K = torsion.radial_stiffness_with_crack_N_per_mm(K0, du, F)
    assert F / K == pytest.approx(F / K0 + du, rel=1e-12)
    assert torsion.radial_stiffness_with_crack_N_per_mm(K0, du, F, Variant.PUBLISHED) == pytest.approx(K0 - F / du, rel=1e-12)


def _cup(**kw):
    d1, t = 160.0, 2.24
    args = dict(hub_radius_mm=0.25 * d1, hub_bore_radius_mm=0.1 * d1, hub_height_mm=4 * t,
                diaphragm_thickness_mm=t, band_length_mm=0.2 * d1, diaphragm_z_mm=3.5 * t)
    args.update(kw)
    return torsion.cup_series_flexibility(d1, t, 160.0, 80769.0, **args)


def test_cup_series_tube_reduces_to_L_over_GJ():
    # band -> 0 and no diaphragm (the tube from z = 0, no hub length): L/(G J) of the hollow tube exactly
    d1, t, L, G = 160.0, 2.24, 160.0, 80769.0
    parts = torsion.cup_series_flexibility(d1, t, L, G, hub_radius_mm=40.0, hub_bore_radius_mm=16.0,
                                           hub_height_mm=1e-12, diaphragm_thickness_mm=t, band_length_mm=0.0,
                                           diaphragm_z_mm=1e-12)
    J = math.pi / 32 * (d1 ** 4 - (d1 - 2 * t) ** 4)
    assert parts.tube == pytest.approx(L / (G * J), rel=1e-12)   # z_d = 1e-12 mm of 160 mm
    assert parts.hub < 1e-22                                       # 1e-12 mm of hub
    # the pi/32 tube equals seed 000's corrected lambda_f0 without k_f k_G
    tube = torsion.flexspline_flexibility(d1, t, L, G, 1.0, 1.0, Variant.CORRECTED)
    assert parts.tube == pytest.approx(tube, rel=1e-12)


def test_cup_series_terms_against_numerical_integration():
    from scipy.integrate import quad

    d1, t, L, G = 160.0, 2.24, 160.0, 80769.0
    b, z_d, r_hub, r_bore = 0.2 * d1, 3.5 * t, 40.0, 16.0
    parts = _cup()
    r_m = (d1 - t) / 2
    # diaphragm: dphi/dr = T / (G 2 pi r^3 t) (pure shear tau = T/(2 pi r^2 t), gamma = r dphi/dr), T = 1
    diaphragm, _ = quad(lambda r: 1.0 / (G * 2 * math.pi * r ** 3 * t), r_hub, r_m, epsabs=0, epsrel=1e-13)
    # hub and tube: J = int 2 pi r^3 dr over the section
    J_hub, _ = quad(lambda r: 2 * math.pi * r ** 3, r_bore, r_hub, epsabs=0, epsrel=1e-13)
    J_tube, _ = quad(lambda r: 2 * math.pi * r ** 3, d1 / 2 - t, d1 / 2, epsabs=0, epsrel=1e-13)
    # tube: internal torque 1 up to the band, falling linearly to 0 at the rim; twist = its z integral
    # from the diaphragm mid-plane, averaged over the band (a double integral, no L_eff assumed)
    z_b = L - b
    torque = lambda s: 1.0 if s < z_b else (L - s) / b
    twist = lambda z: quad(lambda s: torque(s) / (G * J_tube), z_d, z, points=[z_b] if z > z_b else None,
                           epsabs=0, epsrel=1e-13)[0]
    tube = quad(twist, z_b, L, epsabs=0, epsrel=1e-12)[0] / b
    # 1e-9: quad's requested relative accuracy is 1e-12..1e-13, far below
    assert parts.diaphragm == pytest.approx(diaphragm, rel=1e-9)
    assert parts.hub == pytest.approx(z_d / (G * J_hub), rel=1e-9)
    assert parts.tube == pytest.approx(tube, rel=1e-9)
    assert parts.total == pytest.approx(tube + diaphragm + z_d / (G * J_hub), rel=1e-9)
    # the default cup: the diaphragm is as compliant as the tube (2.04 vs 2.34e-10), the hub ~5 %
    assert parts.diaphragm / parts.tube == pytest.approx(0.8711, abs=1e-3)
    assert parts.total == pytest.approx(4.6342e-10, rel=1e-4)
    assert set(parts.to_dict()) == {"tube", "diaphragm", "hub", "total"}


def test_cup_series_rejects_a_diaphragm_off_the_hub():
    with pytest.raises(ValueError, match="hub"):
        _cup(diaphragm_z_mm=10.0)


def test_hertz_contact_stiffness_limits_and_derivative():
    import math
    from strainwave.analytic import bearing_stiffness as bs
    E, nu = 2.1e5, 0.3
    Es = E / (2 * (1 - nu ** 2))
    # circle: k = 2 a E* (Johnson)
    assert bs.hertz_contact_stiffness_N_per_mm(2.0, 2.0, E, nu) == pytest.approx(4.0 * Es, rel=1e-12)
    # ellipse: k = dP/d(delta) of the Hertz law delta = 3 P K(e)/(2 pi a E*) with a, b ~ P^(1/3)
    from scipy.special import ellipk
    a0, b0, P0 = 5.0, 3.0, 100.0

    def approach(P):
        s = (P / P0) ** (1 / 3)
        return 3 * P * ellipk(1 - (b0 / a0) ** 2) / (2 * math.pi * a0 * s * Es)

    dP = 1e-3 * P0
    k_num = 2 * dP / (approach(P0 + dP) - approach(P0 - dP))
    assert bs.hertz_contact_stiffness_N_per_mm(a0, b0, E, nu) == pytest.approx(k_num, rel=1e-6)
    assert bs.ball_pair_stiffness_N_per_mm(a0, b0, E, nu) == pytest.approx(0.5 * k_num, rel=1e-6)
