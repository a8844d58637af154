"""The wave generator's balls as a Hertz spring: first principles and the way they enter the drive's curve."""
import math

import numpy as np
import pytest

from strainwave.analytic import wg_bearing as wb


def test_palmgren_point_contact_law_and_its_tangent():
    """delta ~ Q^(2/3): doubling Q multiplies delta by 2^(2/3); the tangent is 1.5 Q / delta (a finite difference),
    and the constant is Palmgren's 0.002 mm kgf^(-2/3) mm^(1/3) in SI (0.002 / 9.80665^(2/3) = 4.36e-4)."""
    D = 9.525
    d1, d2 = wb.ball_contact_deflection_mm(np.array([100.0, 200.0]), D)
    assert d2 / d1 == pytest.approx(2.0 ** (2.0 / 3.0), rel=1e-12)
    assert 0.002 / 9.80665 ** (2.0 / 3.0) == pytest.approx(4.36e-4, rel=2e-3)
    assert d1 == pytest.approx(4.36e-4 * 100.0 ** (2 / 3) / D ** (1 / 3), rel=1e-12)
    h = 1e-4
    fd = 2 * h / (wb.ball_contact_deflection_mm(100.0 + h, D) - wb.ball_contact_deflection_mm(100.0 - h, D))
    assert wb.ball_contact_stiffness_N_per_mm(100.0, D) == pytest.approx(fd, rel=1e-6)
    # the spring stiffens with load (one source of K1 < K3) and has no stiffness at zero load (no preload)
    assert wb.ball_contact_stiffness_N_per_mm(800.0, D) == pytest.approx(2.0 * wb.ball_contact_stiffness_N_per_mm(100.0, D))
    assert wb.ball_contact_stiffness_N_per_mm(0.0, D) == 0.0


def test_foundation_is_self_consistent_and_series_with_a_lumped_one():
    """The fixed point: the foundation's beta puts Q on the peak ball and the balls' tangent at Q gives back the
    foundation; a lumped foundation in series makes it softer than either."""
    b = wb.BallBearing(9.525, 24, 140.0)
    EI = 2.1e5 * 30.0 * (2.24 ** 3 + 2.5 ** 3) / 12.0
    k, Q = wb.linearised_foundation(b, 3000.0, EI)
    beta = (k / (4.0 * EI)) ** 0.25
    assert Q == pytest.approx(wb.peak_ball_load_N(3000.0, beta, b.ball_pitch_mm), rel=1e-6)
    assert k == pytest.approx(wb.ball_contact_stiffness_N_per_mm(Q, 9.525) / b.ball_pitch_mm, rel=1e-6)
    k2, _ = wb.linearised_foundation(b, 3000.0, EI, lumped_N_per_mm2=k)
    assert k2 < 0.5 * k * 1.01 and k2 > 0.4 * k


def test_hertz_remainder_is_odd_and_tangent_at_the_reference():
    """The series remainder delta(Q) - Q / k_t(Q_ref): odd in T, zero slope at the reference torque, and the
    whole ball approach at the reference is the remainder plus the tangent line (delta/3 + 2 delta/3)."""
    b = wb.BallBearing(9.525, 24, 140.0)
    kw = dict(bearing=b, Q_at_reference_N=500.0, reference_torque_Nmm=1e6, pitch_radius_mm=80.0, alpha_deg=20.0)
    T = np.array([-1e6, -2e5, 0.0, 2e5, 1e6])
    th = wb.hertz_remainder_twist_rad(T, **kw)
    assert th == pytest.approx(-th[::-1]) and th[2] == 0.0
    h = 1e2
    slope = (wb.hertz_remainder_twist_rad(1e6 + h, **kw) - wb.hertz_remainder_twist_rad(1e6 - h, **kw)) / (2 * h)
    assert abs(slope) < 1e-6 * th[-1] / 1e6
    delta = wb.ball_contact_deflection_mm(500.0, 9.525)
    assert th[-1] == pytest.approx(delta / 3.0 * math.tan(math.radians(20.0)) / 80.0, rel=1e-9)


def test_the_support_bounds_a_free_ring_and_the_ball_bed():
    """The physical range of a lumped rim support (decision 065): the rim's own n = 2 ring stiffness
    (9 E I / R^4, checked here by hand) below the Hertz ball bed, which is the rules' own support (balls alone)."""
    from strainwave.analytic.catalogue_rules import MeshRules
    rules = MeshRules()
    assert rules.foundation_coefficient is None
    for size, ratio in ((14, 30), (58, 100)):
        lo, hi = rules.foundation_bounds(size, ratio)
        design = rules.design(size, ratio)
        g = design.geometry
        d = rules.pitch_diameter_mm(size)
        ring = 9.0 * rules.E_MPa * g.face_width_mm * g.rim_thickness_mm ** 3 / 12.0 / g.neutral_radius_mm ** 4
        assert lo == pytest.approx(ring * d / (rules.E_MPa * g.face_width_mm), rel=1e-12)
        assert hi == pytest.approx(design.foundation_N_per_mm2 * d / (rules.E_MPa * g.face_width_mm), rel=1e-12)
        assert 100.0 * lo < hi


def test_the_balls_twist_rides_on_the_drive_loop():
    """The drive's loop is the linear mesh model's plus the balls' series remainder, exactly."""
    from dataclasses import replace
    from strainwave.analytic.catalogue_rules import MeshRules
    from strainwave.analytic.drive_curve import _loop
    from strainwave.analytic.mesh_drive import bearing_twist_rad
    design = MeshRules().design(14, 30)
    T, tw, _ = _loop(design, 0.0, 10.0, 0.0)
    T0, tw0, _ = _loop(replace(design, bearing=None), 0.0, 10.0, 0.0)
    assert tw - tw0 == pytest.approx(bearing_twist_rad(design, 1e3 * T), abs=1e-15)
    assert np.max(np.abs(bearing_twist_rad(design, 1e3 * T))) > 0.0


@pytest.mark.parametrize("ratio", [30, 100])
def test_the_readers_k3_is_the_curves_own_slope(ratio):
    """Under the rules the reader's K3 is the first loading's secant from its T2 to the rated torque, not the
    friction stick band at the loop's tip (the artefact that made a fitted support look right, decision 065)."""
    from strainwave.analytic.catalogue_rules import MeshRules
    from strainwave.analytic.drive_curve import predict_curve
    rules = MeshRules()
    c = predict_curve(rules.design(14, ratio), rules.cup_flexibility_rad_per_Nmm(14), rules.rated_torque_Nm(14),
                      with_te=False)
    T, tw = c.loop_torque_Nm, c.loop_twist_rad
    k0 = int(np.argmax(T))
    sel = T[:k0 + 1] >= min(c.T2_Nm, 0.7 * T[k0])
    secant = np.polyfit(tw[:k0 + 1][sel], T[:k0 + 1][sel], 1)[0]
    assert c.K3_Nm_per_rad == pytest.approx(secant, rel=0.1)
