"""The wave generator bearing's inner ring on the elliptical cam (issue 34 item 3): closed forms, the 2D FEA
on coarse meshes (cheap), and checks that fail on a perturbed reference."""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from strainwave.analytic import wg_bearing as wgb


def test_edge_crack_weight_function_gives_the_uniform_edge_crack():
    K = wgb.edge_crack_K(lambda x: np.ones_like(x), 2.0)
    assert K / math.sqrt(math.pi * 2.0) == pytest.approx(1.1215, rel=2e-3)


def test_curved_beam_tends_to_the_thin_ring_and_is_tensile_at_the_major_axis_race():
    thin = wgb.thin_ring_race_stress_MPa(2.1e5, 0.1, 100.0, 0.5)
    thick = wgb.curved_beam_race_stress_MPa(2.1e5, 99.95, 100.05, 0.5)
    assert thick == pytest.approx(thin, rel=1e-3) and thick > 0
    assert wgb.curved_beam_race_stress_MPa(2.1e5, 52.76, 62.76, 0.8, 0.5 * math.pi) < 0


def test_stribeck_sum_is_equilibrium_and_tends_to_4_37():
    psi, q = wgb.stribeck_ball_loads(1000.0, 24)
    assert float(q @ np.cos(psi)) == pytest.approx(1000.0)
    assert 400 * wgb.stribeck_ball_loads(1.0, 400)[1].max() == pytest.approx(4.37, rel=2e-3)


def test_back_face_allowance_grows_with_depth():
    a = [wgb.back_face_allowance(d, 10.0) for d in (0.1, 0.5, 1.0)]
    assert 0 < a[0] < a[1] < a[2] < 0.1


@pytest.fixture(scope="module")
def ring():
    from strainwave.analytic.study_loads import wg_bearing_load
    from strainwave.fea.wg_bearing import setup_from
    from strainwave.params import load_params
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        params = load_params()
    return params, setup_from(params, **wg_bearing_load(params))


def test_cam_bends_the_race_into_tension_at_the_major_axis(ring):
    from strainwave.fea.wg_bearing import solve_plain
    params, s = ring
    d = solve_plain(s, 5.0, 1.96, 1.0)
    ref = wgb.curved_beam_race_stress_MPa(s.E_MPa, s.r_bore_mm, s.r_race_mm, s.w0_mm)
    assert d["race_major_MPa"] == pytest.approx(ref, rel=0.05)
    assert d["race_minor_MPa"] == pytest.approx(-ref, rel=0.05)
    assert d["ball_ratio"] == pytest.approx(24 * max(s.ball_loads_N) / s.force_N, rel=0.05)


def test_race_crack_opens_under_the_cam_and_shuts_when_the_cam_is_reversed(ring):
    from strainwave.fea.wg_bearing import solve_crack
    params, s = ring
    opened = solve_crack(s, 5.0, 1.96, 1.0, compressed=True)
    shut = opened.pop("compressed")
    assert opened["closed_pairs"] == 0 and opened["mouth_opening_mm"] > 0 and opened["delta"] > 0
    assert shut["closed_pairs"] == shut["pairs"] and abs(shut["delta"]) < 1e-6 * opened["delta"]
    x, sig = opened["profile"]
    ref = wgb.edge_crack_compliance_mm_per_N(lambda xx: np.interp(xx, x, sig), 1.0, s.E_MPa, s.width_mm)
    assert opened["delta"] == pytest.approx(ref, rel=0.1)


def _outcome(label: str, values: dict, meta: dict):
    from strainwave.compare.validate.runner import Case, CaseOutcome
    from strainwave.fea.convergence import Convergence
    from strainwave.fea.result import Load, MeshQuality, Quantity, StudyResult, Support

    q = {n: Quantity(n, v, "u", Convergence((1.0, 1.4, 1.96), (v, v, v), 1.0, v, 1e-3, True)) for n, v in values.items()}
    mesh = MeshQuality(1, 1, 2, 2, 1.0, 1.0)
    res = StudyResult(label, q, mesh, Load("F", 1.0, "N", ("race",), "x"), (Support(("bore",), "cam"),), meta=meta)
    return CaseOutcome(Case(label, label), res, 1.0, False)


def _book(values: dict, meta: dict, **more):
    from strainwave.compare.validate.fea_book import FeaBook
    return FeaBook({"wg-bearing": _outcome("wg-bearing", values, meta),
                    **{label: _outcome(label, v, {}) for label, v in more.items()}})


def test_checks_pass_on_their_closed_forms_and_fail_on_perturbed_ones(ring):
    from strainwave.compare.validate import wg_bearing_checks as wc
    from strainwave.fea.wg_bearing import delta_name
    params, s = ring
    a = 0.1 * s.thickness_mm      # the sweep's deepest crack, a_max = 0.1 t (fea/wg_bearing.SWEEP_OVER_T)
    x = np.linspace(0.0, a, 65)
    sig = -0.003 + 0.001 * x / a
    meta = {"crack_depths_mm": [a], "cracks": {f"{a:g}": {"depth_mm": a, "profile_x_mm": x.tolist(),
                                                         "hoop_stress_per_N_MPa": sig.tolist()}}}
    delta = wgb.edge_crack_compliance_mm_per_N(lambda xx: np.interp(xx, x, sig), a, s.E_MPa, s.width_mm)
    stress = wgb.curved_beam_race_stress_MPa(s.E_MPa, s.r_bore_mm, s.r_race_mm, s.w0_mm)
    book = _book({delta_name(a): delta, "race_stress_major_MPa": stress, "net_race_stress_major_MPa": stress}, meta)
    assert wc.bearing_crack_check(book, "wg-bearing", params).passed
    assert wc.race_stress_check(book, "wg-bearing", params, "major").passed
    bad = lambda a: {"corrected": 1.3 * delta}      # noqa: E731
    assert not wc.bearing_crack_check(book, "wg-bearing", params, curve=bad).passed
    thin = _book({"race_stress_major_MPa": wgb.thin_ring_race_stress_MPa(
        s.E_MPa, s.thickness_mm, 0.5 * (s.r_bore_mm + s.r_race_mm), s.w0_mm)}, meta)
    assert not wc.race_stress_check(thin, "wg-bearing", params, "major").passed


def test_drive_stiffness_takes_the_wave_generator_from_the_fea_and_fails_on_the_seeds_K_G0(ring):
    from strainwave.analytic import torsion
    from strainwave.analytic.seed000 import cup_series_model, seed000_summary
    from strainwave.analytic.variant import Variant
    from strainwave.compare.validate import wg_bearing_checks as wc
    params, s = ring
    G, sh = params.material.implied_shear_modulus_MPa, params.output_shaft
    from strainwave.analytic.cup_junction import junction_compliance
    # the stand-in FEA cup is the series model with the junction compliance it omits (the calibrated correction)
    cup = {"flexibility_rad_per_Nmm": cup_series_model(params, G).total + junction_compliance(params, G)}
    shaft = {"flexibility_rad_per_Nmm": torsion.shaft_flexibility(sh.length_mm, sh.outer_diameter_mm,
                                                                  sh.inner_diameter_mm, G, Variant.CORRECTED)}
    labels, s000 = {"cup": "cup", "shaft": "shaft"}, seed000_summary(params)
    K_G = wc.stribeck_radial_stiffness_N_per_mm(params)
    good = _book({"radial_stiffness_N_per_mm": K_G}, {}, cup=cup, shaft=shaft)
    check = wc.gear_stiffness(good, labels, "wg-bearing", s000, params)
    assert check.passed and check.analytic["today_seed_k_g0"] < check.fea
    seed = _book({"radial_stiffness_N_per_mm": params.wave_generator.uncracked_radial_stiffness_N_per_mm}, {},
                 cup=cup, shaft=shaft)
    assert not wc.gear_stiffness(seed, labels, "wg-bearing", s000, params).passed


def test_the_ring_on_the_cam_writes_a_readable_field(ring, tmp_path):
    """wg-bearing's VTU (the finest uncracked ring on the cam under the ball loads) reads back with meshio and
    pyvista: its P2 triangles, a finite hoop stress that is the study's own race stress at the major axis, and a
    bore that follows the cam, u_r = w0 cos 2 phi."""
    import meshio
    import pyvista as pv

    from strainwave.fea.wg_bearing import solve_plain, write_fields
    params, s = ring
    d = solve_plain(s, 5.0, 1.96, 1.0)
    path = write_fields(tmp_path / "wg.vtu", s, d, params.material)
    back = meshio.read(path)
    assert len(back.points) == d["_nodes"] and back.cells_dict["triangle6"].shape == (d["_elements"], 6)
    grid = pv.read(path)
    hoop = np.asarray(grid.point_data["hoop_stress_MPa"])
    assert np.isfinite(hoop).all() and np.isfinite(grid.point_data["von_mises_MPa"]).all()
    p = np.asarray(grid.points)
    r, phi = np.hypot(p[:, 0], p[:, 1]), np.arctan2(p[:, 1], p[:, 0])
    race = np.flatnonzero(np.abs(r - s.r_race_mm) < 1e-6 * s.r_race_mm)
    major = race[np.argmin(np.abs(phi[race]))]
    assert hoop[major] == pytest.approx(d["net_race_major_MPa"], rel=1e-3)
    bore = np.flatnonzero(np.abs(r - s.r_bore_mm) < 1e-6 * s.r_bore_mm)
    u = np.asarray(grid.point_data["displacement_mm"])
    u_r = u[bore, 0] * np.cos(phi[bore]) + u[bore, 1] * np.sin(phi[bore])
    assert u_r == pytest.approx(s.w0_mm * np.cos(2 * phi[bore]), abs=1e-6 * s.w0_mm)
    assert set(pv.read(tmp_path / "wg.boundary.vtu").field_data.keys()) >= {"physical_group_names"}


# ---- the balls as a Hertz spring (Palmgren): first principles and the way they enter the drive's curve ----

from strainwave.analytic import wg_bearing as wb  # noqa: E402


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
