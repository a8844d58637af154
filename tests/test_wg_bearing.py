"""The wave generator bearing's inner ring on the elliptical cam (issue 34 item 3): closed forms, the 2D FEA
on coarse meshes (cheap), and checks that fail on a perturbed reference."""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from strainwave.analytic import michell_ring as michell
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
        # the 10 mm ring these checks' perturbations were sized on (thin-ring and curved-beam errors of -10 and
        # +2.4 %); the default is 3 mm since issue 49, where those errors shrink with t/r_m
        params = load_params().with_value("wave_generator.bearing_inner_ring_thickness_mm", 10.0)
    return params, setup_from(params, **wg_bearing_load(params))


def test_cam_bends_the_race_into_tension_at_the_major_axis(ring):
    from strainwave.fea.wg_bearing import solve_plain
    params, s = ring
    d = solve_plain(s, 5.0, 1.96, 1.0)
    ref = michell.cam_ring_hoop_stress_MPa(s.E_MPa, s.nu, s.r_bore_mm, s.r_race_mm, s.w0_mm)
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
    # the uncracked stress the check's closed form takes is the exact ring's (Michell's series), not the FEA's:
    # on this coarse mesh the FEA's profile lies within 1 % of it (the full meshes: 0.3 %)
    from strainwave.compare.validate.wg_bearing_checks import exact_hoop_profile
    xe, exact = exact_hoop_profile(params, 1.0)
    assert np.interp(x, xe, exact) == pytest.approx(sig, rel=0.01, abs=0.01 * abs(sig).max())


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
    a = 0.1 * s.thickness_mm      # the sweep's deepest crack, a_max = 0.1 t (fea/wg_bearing.SWEEP_OVER_T; 3 mm ring)
    x = np.linspace(0.0, a, 65)
    sig = -0.003 + 0.001 * x / a
    meta = {"crack_depths_mm": [a], "cracks": {f"{a:g}": {"profile_x_mm": x.tolist(), "hoop_stress_per_N_MPa": sig.tolist()}}}
    delta = wc.crack_curve(params)(a)["corrected"]      # the exact ring's stress, whatever the FEA's profile
    stress = michell.cam_ring_hoop_stress_MPa(s.E_MPa, s.nu, s.r_bore_mm, s.r_race_mm, s.w0_mm)
    book = _book({delta_name(a): delta, "race_stress_major_MPa": stress, "net_race_stress_major_MPa": stress}, meta)
    assert wc.bearing_crack_check(book, "wg-bearing", params).passed
    assert wc.race_stress_check(book, "wg-bearing", params, "major").passed
    bad = lambda a: {"corrected": 1.3 * delta}      # noqa: E731
    assert not wc.bearing_crack_check(book, "wg-bearing", params, curve=bad).passed
    # the exact solution is asserted: the thin ring (-10 %), the curved beam (+2.4 %), plane strain (+10 %) and a
    # +-20 % stress all fail
    r_m = 0.5 * (s.r_bore_mm + s.r_race_mm)
    for wrong in (wgb.thin_ring_race_stress_MPa(s.E_MPa, s.thickness_mm, r_m, s.w0_mm),
                  wgb.curved_beam_race_stress_MPa(s.E_MPa, s.r_bore_mm, s.r_race_mm, s.w0_mm),
                  michell.cam_ring_hoop_stress_MPa(s.E_MPa, s.nu, s.r_bore_mm, s.r_race_mm, s.w0_mm,
                                                   plane=michell.Plane.STRAIN), 0.8 * stress, 1.2 * stress):
        assert not wc.race_stress_check(_book({"race_stress_major_MPa": wrong}, meta), "wg-bearing", params,
                                        "major").passed


def test_ball_load_check_tells_hertz_from_linear_springs(ring):
    """Stribeck's Hertz distribution passes; linear springs (Q ~ delta, Z Q_max/F_r = 4.00 against 4.37) fail,
    as do +-20 % and +-10 % errors."""
    from strainwave.analytic import hertz_ball_loads as hb
    from strainwave.compare.validate import wg_bearing_checks as wc
    params, _ = ring
    Z = params.wave_generator.ball_count
    hertz = hb.hertz_load_ratio(Z)
    check = wc.ball_load_check(_book({"ball_load_ratio": hertz}, {}), "wg-bearing", params)
    assert check.passed and check.tolerance.relative < 0.02
    for wrong in (hb.linear_spring_load_ratio(Z), 0.8 * hertz, 0.9 * hertz, 1.1 * hertz, 1.2 * hertz):
        assert not wc.ball_load_check(_book({"ball_load_ratio": wrong}, {}), "wg-bearing", params).passed


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
    """wg-bearing's VTU (the finest uncracked ring on the cam under the ball loads) reads back with pyvista and
    as a meshio mesh (through pyvista: meshio's own reader refuses VTK String arrays): its P2 triangles, a finite hoop stress that is the study's own race stress at the major axis, and a
    bore that follows the cam, u_r = w0 cos 2 phi."""
    import meshio
    import pyvista as pv

    from strainwave.fea.wg_bearing import solve_plain, write_fields
    params, s = ring
    d = solve_plain(s, 5.0, 1.96, 1.0)
    path = write_fields(tmp_path / "wg.vtu", s, d, params.material)
    back = pv.to_meshio(pv.read(path))
    assert isinstance(back, meshio.Mesh)
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
