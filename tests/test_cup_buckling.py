"""The flexspline's torsional buckling (issue 49 item 4): the closed form against its own limits, the FE tube
against the closed form, and the check failing on a +-20 % reference."""
import math
from dataclasses import replace

import pytest
from hypothesis import given, settings, strategies as st

from strainwave.analytic.cylinder_buckling import asymptote_k, batdorf_k, torsional_buckling


def _least_k(Z: float) -> float:
    """Batdorf's k_s at the least continuous beta (a long cylinder's wave number is free)."""
    from scipy.optimize import minimize_scalar
    res = minimize_scalar(lambda lb: batdorf_k(Z, math.exp(lb)), bounds=(-4.0, 6.0), method="bounded")
    return res.fun


def test_galerkin_reaches_the_flat_strip_and_the_moderate_length_asymptote():
    # Z -> 0: the long simply supported strip in shear, k_s = 5.35 (Southwell and Skan)
    assert _least_k(0.01) == pytest.approx(5.35, rel=0.01)
    # large Z: Batdorf's moderate-length line 0.85 Z^(3/4)
    assert _least_k(1.0e4) == pytest.approx(asymptote_k(1.0e4), rel=0.005)


def test_asymptote_is_timoshenko_geres_donnell_formula():
    """tau_cr = 0.747 E (t/R)^(5/4) (R/L)^(1/2) at nu = 0.3 (Timoshenko & Gere sec. 11.12)."""
    R, t, L, E = 78.9, 2.24, 144.3, 2.1e5
    cb = torsional_buckling(R, t, L, E, 0.3)
    donnell = 0.747 * E * (t / R) ** 1.25 * (R / L) ** 0.5
    assert cb.tau_cr_asymptote_MPa == pytest.approx(donnell, rel=0.01)
    assert cb.torque_Nmm == pytest.approx(cb.tau_cr_MPa * 2 * math.pi * R * R * t)


def test_fe_tube_on_a_coarse_mesh_lies_above_the_closed_form():
    """One coarse FE solve (28 elements around): an eigenvalue converges from above, within 15 % here."""
    from strainwave.analytic.cylinder_buckling import torsional_buckling
    from strainwave.fea.assembly import Lame
    from strainwave.fea.cup_buckling import buckling_torque
    from strainwave.fea.wg_band import tube_geometry
    from strainwave.params import load_params

    p = load_params()
    geo = tube_geometry(p)
    m = p.material
    fe = buckling_torque(geo, Lame.from_young(m.youngs_modulus_MPa, m.poisson_ratio), 28)
    ref = torsional_buckling(geo.r_m_mm, geo.wall_mm, geo.length_mm - geo.z_end_mm, m.youngs_modulus_MPa,
                             m.poisson_ratio)
    assert 1.0 < fe.torque_Nmm / ref.torque_Nmm < 1.15
    assert fe.n_waves == ref.n_waves


@pytest.mark.heavy
def test_buckling_check_passes_and_fails_on_a_perturbed_reference(monkeypatch):
    from strainwave.compare.validate import buckling_checks as bc
    from strainwave.params import load_params

    p = load_params()
    solved = bc.fe_quantity(p)
    check = bc.buckling_check(p, solved)
    assert check.passed and check.tolerance.relative < 0.15
    true = bc.closed_form
    for scale in (0.8, 1.2):
        monkeypatch.setattr(bc, "closed_form", lambda params, s=scale: replace(
            true(params), torque_Nmm=s * true(params).torque_Nmm))
        assert not bc.buckling_check(p, solved).passed, scale
    record = bc.buckling_record(p, check)
    assert record["fe_over_rated"] == pytest.approx(check.fea / p.gear.rated_output_torque_Nmm)


def test_a_tube_the_fe_cannot_take_is_not_evaluated_not_raised(monkeypatch):
    from strainwave.compare.validate import buckling_checks as bc
    from strainwave.errors import StageError
    from strainwave.params import load_params

    def fail(params):
        raise StageError("solve", "cup-buckling", "the buckling eigenvalues did not converge")
    monkeypatch.setattr(bc, "fe_quantity", fail)
    check = bc.buckling_check(load_params())
    assert check.verdict == "not evaluated" and not check.passed and "did not converge" in check.reason_not_evaluated
    assert check.analytic["corrected"] == pytest.approx(bc.closed_form(load_params()).torque_Nmm)
    assert bc.buckling_record(load_params(), check)["fe_over_rated"] is None


@settings(max_examples=25, deadline=None)
@given(r_over_t=st.floats(20.0, 500.0), l_over_r=st.floats(0.3, 5.0))
def test_closed_form_lies_between_the_flat_strip_and_the_moderate_length_line(r_over_t, l_over_r):
    """Curvature only stiffens a strip in shear (k_s >= 5.35); past Z = 100 the least integer-n solution is Batdorf's
    line 0.85 Z^(3/4) within 10 % (the integer n and the dropped plate term)."""
    R = 50.0
    cb = torsional_buckling(R, R / r_over_t, l_over_r * R, 2.1e5, 0.3)
    assert cb.n_waves >= 2 and math.isfinite(cb.torque_Nmm) and cb.torque_Nmm > 0
    assert cb.k_s >= 5.35 * 0.995
    if cb.Z >= 100:
        assert cb.k_s == pytest.approx(cb.k_s_asymptote, rel=0.10)


@pytest.mark.parametrize("path", [None, "strainwave/data/second_gear.toml"])
def test_the_closed_forms_tube_is_the_fes(path):
    import warnings
    from strainwave.analytic.cylinder_buckling import cup_tube
    from strainwave.fea.wg_band import tube_geometry
    from strainwave.params import load_params
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        p = load_params(path)
    geo = tube_geometry(p)
    assert cup_tube(p) == pytest.approx((geo.r_m_mm, geo.wall_mm, geo.length_mm - geo.z_end_mm), rel=1e-12)
